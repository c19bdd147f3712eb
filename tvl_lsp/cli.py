"""Command line entry point.

    tvl-lsp                      serve LSP on stdio (``--tcp [HOST:]PORT`` for TCP)
    tvl-lsp --check [PATH ...]   check models and launch files (CI); see ``--check --help``
    tvl-lsp --explain CODE       print the documentation of a diagnostic code
    tvl-lsp count MODEL ...      exact number of products
    tvl-lsp launch FILE a:=b ... what roslaunch would load under these args

Each sub-command lives in its own module under ``tvl_lsp.commands`` and exposes
``main(argv) -> int``; the exit code is 0 (no error), 1 (errors found), 2 (usage or
internal failure).
"""

from __future__ import annotations

import importlib
import sys

SUBCOMMANDS = {
    "count": "tvl_lsp.commands.count",
    "launch": "tvl_lsp.commands.launch",
    "generate": "tvl_lsp.commands.generate",
    "check": "tvl_lsp.commands.check",
}


def _run(module: str, argv: list[str]) -> int:
    mod = importlib.import_module(module)
    return int(mod.main(argv) or 0)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        if argv and argv[0] in SUBCOMMANDS:
            return _run(SUBCOMMANDS[argv[0]], argv[1:])
        if "--check" in argv:
            argv.remove("--check")
            return _run("tvl_lsp.commands.check", argv)
        if argv and argv[0] == "--explain":
            return _run("tvl_lsp.commands.explain", argv[1:])
        if argv and argv[0] in ("--version", "-V"):
            from . import __version__
            print(f"tvl-lsp {__version__}")
            return 0
        if argv and argv[0] in ("-h", "--help"):
            print(__doc__)
            return 0
        return _run("tvl_lsp.server", argv)
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
