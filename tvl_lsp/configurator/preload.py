"""Import the whole analysis core in the calling thread, before a host starts its threads.

The core imports some modules lazily (inside functions) to keep one-shot CLI commands quick.
In a host with threads (the language server's check threads, the configurator UI's request
threads and warm-up) two threads can then import the same packages at the same moment, and
Python's import locks do not make that safe for packages whose ``__init__`` imports their own
submodules: one thread may see a partially initialised module (``cannot import name ...``,
``KeyError: 'tvl_lsp.launch'``).  Hosts therefore call :func:`import_core` once, on their main
thread, before any other thread exists; every later lazy import is then a dictionary look-up.
"""

from __future__ import annotations

import importlib
import logging
import pkgutil

#: the core's packages, lowest layer first (the order of the layers contract in pyproject.toml)
CORE_PACKAGES = ("base", "tvl", "launch", "uvl", "analysis", "graph", "project", "configurator")

log = logging.getLogger(__name__)


def import_core() -> list[str]:
    """Import every module of the core packages; return the names of those that could not be
    imported (an optional dependency missing), which are logged and otherwise ignored."""
    failed: list[str] = []
    for sub in CORE_PACKAGES:
        pkg = importlib.import_module(f"tvl_lsp.{sub}")
        for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".", onerror=failed.append):
            try:
                importlib.import_module(info.name)
            except Exception as exc:  # an optional dependency; its users report it when called
                log.info("preload: %s not imported: %s", info.name, exc)
                failed.append(info.name)
    return failed


def warm_parsers() -> None:
    """Build the TVL and UVL parse tables now (0.1 s of CPU, once per process): the first model
    a host parses -- a launch file's quick check reads its model -- then does not pay for it."""
    from ..tvl import parser as tvl_parser
    from ..uvl import parser as uvl_parser
    tvl_parser._tables()
    uvl_parser._tables()
