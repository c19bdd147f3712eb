"""tvl-lsp: language server and checker for TVL feature models and ROS launch files.

usage:
  tvl-lsp                           serve LSP on stdio (--tcp [HOST:]PORT for TCP)
  tvl-lsp --check [PATH ...]        check models, launch files and HAROS project files
                                    (tvl-lsp --check --help for formats and options)
  tvl-lsp --explain [CODE]          what a diagnostic code means and how to fix it
  tvl-lsp count MODEL [--include F]... [--exclude F]... [--per-feature] [--json]
                                    exact number of products (MODEL: .tvl, .uvl or .dimacs)
  tvl-lsp sample MODEL (--t 2 | --uniform N) [--seed S] [--include F]... [--json]
                                    products to test: a pairwise cover, or uniform at random
  tvl-lsp convert IN OUT [--verify]  convert a model between TVL, UVL and DIMACS (by extension)
  tvl-lsp launch FILE [name:=value ...] [--json]
                                    what roslaunch would load from FILE under these args
  tvl-lsp generate LAUNCH [--mode one|completions|all|sample] ...
                                    configuration launch files for products of the model
  tvl-lsp graph LAUNCH [--include F]... [--exclude F]... [--format json|dot|mermaid]
                                    the computation graph of every product at once (docs/graph.md)
  tvl-lsp extract PATH... [--json]  each program's topics, services, actions and parameters,
                                    read from the C++ and Python sources of its package
  tvl-lsp ui [PATH] [--port N] [--no-browser]
                                    the configurator (feature diagram, computation graph,
                                    problems) in the browser, on 127.0.0.1
  tvl-lsp --version

Exit status: 0 no error, 1 errors found, 2 usage or internal failure.
"""

from __future__ import annotations

import importlib
import os
import sys

SUBCOMMANDS = {
    "count": "tvl_lsp.cli.commands.count",
    "sample": "tvl_lsp.cli.commands.sample",
    "launch": "tvl_lsp.cli.commands.launch",
    "generate": "tvl_lsp.cli.commands.generate",
    "check": "tvl_lsp.cli.commands.check",
    "graph": "tvl_lsp.cli.commands.graph",
    "ui": "tvl_lsp.ui.command",
    "convert": "tvl_lsp.cli.commands.convert",
    "extract": "tvl_lsp.cli.commands.extract",
}


def _run(module: str, argv: list[str]) -> int:
    mod = importlib.import_module(module)
    return int(mod.main(argv) or 0)


# commands whose process ends when they return: from the console, they end without the
# interpreter's teardown (freeing millions of objects one by one doubled the CPU time of a
# check of a 200,000-feature model); their output is flushed first and they hold no
# resources that need atexit handlers
_ONE_SHOT = ("count", "sample", "launch", "generate", "check", "graph", "convert", "extract")


def main(argv: list[str] | None = None) -> int:
    from_console = argv is None
    argv = list(sys.argv[1:] if argv is None else argv)
    one_shot = bool(argv) and (argv[0] in _ONE_SHOT or argv[0] == "--explain" or "--check" in argv)
    if from_console and one_shot and ("--check" in argv or argv[0] == "check"):
        from .project import check
        check.KEEP_LAST = True  # the last file's models are left for os._exit to drop
    if from_console and one_shot:
        from .base.children import terminate_on_sigterm
        terminate_on_sigterm()  # SIGTERM ends it like Ctrl-C: temporary files removed, children killed
    code = _main(argv)
    if from_console and one_shot:
        _exit_now(code)
    return code


def _exit_now(code: int) -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def _main(argv: list[str]) -> int:
    try:
        if argv and argv[0] in SUBCOMMANDS:
            return _run(SUBCOMMANDS[argv[0]], argv[1:])
        if "--check" in argv:
            argv.remove("--check")
            return _run("tvl_lsp.cli.commands.check", argv)
        if argv and argv[0] == "--explain":
            return _run("tvl_lsp.cli.commands.explain", argv[1:])
        if argv and argv[0] in ("--version", "-V"):
            from . import __version__
            print(f"tvl-lsp {__version__}")
            return 0
        if argv and argv[0] in ("-h", "--help"):
            print(__doc__)
            return 0
        return _run("tvl_lsp.server", argv)
    except KeyboardInterrupt:
        from .base.children import kill_all
        kill_all()
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
