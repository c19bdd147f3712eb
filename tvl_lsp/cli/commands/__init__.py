"""One module per ``tvl-lsp`` subcommand, each with ``main(argv) -> exit status``; register a
new one in ``tvl_lsp.main.SUBCOMMANDS``."""
