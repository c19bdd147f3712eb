"""The tvl-lsp language server: its public entry point.

    from tvl_lsp.server import create_server, serve

    serve()                      # LSP on stdio until the client exits (what `tvl-lsp` runs)
    serve(tcp="127.0.0.1:2087")  # LSP on TCP
    server = create_server()     # the pygls server object, every feature registered, not started

The server itself lives in the :mod:`tvl_lsp.lsp` package, one module per concern (the server
object and start-up in ``lsp/server.py``, one module per LSP feature in ``lsp/features``;
``docs/architecture.md`` has the map).  This module is the stable name to import and the one
the console command starts; its settings and commands are documented in ``lsp/server.py``.
"""

from __future__ import annotations

import sys
from typing import Optional

from .lsp.server import TvlLanguageServer, create_server
from .lsp.server import main as _main

__all__ = ["TvlLanguageServer", "create_server", "serve", "main"]


def serve(tcp: Optional[str] = None) -> int:
    """Serve LSP on stdio, or on TCP at ``tcp`` (``"[HOST:]PORT"``), until the client exits.
    Returns the exit status LSP prescribes (0 after ``shutdown`` then ``exit``, else 1)."""
    return _main(["--tcp", tcp] if tcp else [])


def main(argv: Optional[list[str]] = None) -> int:
    """``tvl-lsp [--stdio | --tcp [HOST:]PORT]``: the console command without a subcommand."""
    return _main(list(sys.argv[1:] if argv is None else argv))


if __name__ == "__main__":
    sys.exit(main())
