"""The command-line host: ``commands/`` has one module per subcommand (``check``, ``count``,
``launch``, ``generate``, ``explain``), each with a ``main(argv) -> exit status``; ``output``
renders diagnostics (text, JSON, SARIF, GitHub).  The dispatch from ``tvl-lsp ARGS`` is
``tvl_lsp.main``."""
