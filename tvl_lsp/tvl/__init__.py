"""TVL front end: grammar, parser, resolver and checks.  Pure: no LSP here."""
