"""Logic, SAT, counting, cross-file checks and configurations.  Pure: no LSP here."""
