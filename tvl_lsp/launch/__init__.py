"""roslaunch 1 XML front end: secure parsing, load-time rules, arg scopes, presence conditions.  Pure: no LSP here."""
