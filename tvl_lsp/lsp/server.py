"""The language server: thin glue between LSP (pygls 2) and the pure core.

    tvl-lsp                    serve LSP on stdio
    tvl-lsp --tcp [HOST:]PORT  serve LSP on TCP

Settings (``initializationOptions`` or ``workspace/configuration`` section ``tvl-lsp``)::

    {"diagnostics": {"<code>": "off" | "error" | "warning" | "information" | "hint"},
     "count": {"timeBudget": 10},          # seconds per count (CPU) / solver-backed check
     "generate": {"folder": "configs",     # relative to the launch file's package, or absolute
                  "limit": 100},           # files per "generate" action
     "debounce": 0.15}                     # seconds of quiet before the solver-backed pass

Commands (``workspace/executeCommand``, see ``tvl_lsp.lsp.features.commands``): ``tvl-lsp.include``,
``tvl-lsp.exclude``, ``tvl-lsp.reset``, ``tvl-lsp.count``, ``tvl-lsp.listProducts``,
``tvl-lsp.generateConfigurations``; ``tvl-lsp.graph`` (``tvl_lsp.lsp.features.graph``).

The server keeps its own copy of every open document (unsaved editor text wins over disk:
:meth:`TvlLanguageServer.read_file` consults open documents first), runs the same pure check
pipeline as ``tvl-lsp --check`` off the event loop, and converts results to the client's
position encoding (``tvl_lsp.lsp.convert``).  Each LSP feature lives in its own module under
``tvl_lsp.lsp.features``; they are registered in one place (``tvl_lsp.lsp.features.register_all``).

This module is the server object, its start-up and the publication of diagnostics; the rest
of the LSP layer has its own rooms: ``settings`` (the settings above), ``documents`` (the
document store), ``scheduler`` (checks, re-checks, counts in the background), ``workers``
(thread and process pools, progress), ``checks`` (the entry into the pure check pipeline),
``convert`` (positions, ranges, diagnostics, edits), ``features/`` (one module per feature).
"""

from __future__ import annotations

import logging
import os
import sys
from pathlib import Path
from typing import Any, Optional

from lsprotocol import types
from pygls.lsp.server import LanguageServer

from .. import __version__
from ..base.text import LineIndex
from .convert import encoding_name, to_lsp_diagnostic
from .documents import DocumentStore
from .known import KnownDiagnostics
from .protocol import TvlProtocol
from .scheduler import Scheduler
from .settings import Settings
from .procinit import bound_heap
from .workers import Workers, start_watchdog

log = logging.getLogger("tvl_lsp.server")

MAX_DIAGNOSTICS = 1000  # per document: beyond this an editor is no help anyway


class TvlLanguageServer(DocumentStore, Scheduler, KnownDiagnostics, Workers, LanguageServer):
    def __init__(self):
        super().__init__("tvl-lsp", __version__, protocol_cls=TvlProtocol,
                         text_document_sync_kind=types.TextDocumentSyncKind.Incremental)
        self.settings = Settings()
        self.published: dict[str, list[types.Diagnostic]] = {}
        self._init_documents()
        self._init_workers()
        self._init_scheduler()
        self._init_known()

    # ------------------------------------------------------------ client capabilities
    @property
    def caps(self) -> types.ClientCapabilities:
        try:
            return self.client_capabilities
        except Exception:
            return types.ClientCapabilities()

    @property
    def encoding(self) -> str:
        try:
            return encoding_name(self.protocol.server_capabilities.position_encoding)
        except Exception:
            return "utf-16"

    def cap(self, path: str, default=None):
        obj: Any = self.caps
        for part in path.split("."):
            obj = getattr(obj, part, None)
            if obj is None:
                return default
        return obj

    @property
    def pull_diagnostics(self) -> bool:
        """Diagnostics are pulled: offered only to clients that accept refreshes (see
        ``TvlProtocol.lsp_initialize``); the others get them pushed."""
        try:
            return self.protocol.server_capabilities.diagnostic_provider is not None
        except AttributeError:  # (before initialize)
            return False

    @property
    def supports_progress(self) -> bool:
        return bool(self.cap("window.work_done_progress", False))

    # ------------------------------------------------------------ publishing
    def lsp_diagnostics(self, uri: str) -> list[types.Diagnostic]:
        """The document's diagnostics as far as they are known now (``known.py``: the quick
        pass of its text, the solver's findings of its last full check moved with the edits)."""
        doc = self.docs.get(uri)
        if doc is None or self.results.get(uri) is None:
            return []
        out = []
        enc = self.encoding
        memo: dict[str, Optional[LineIndex]] = {doc.path: doc.index}

        def index_of(p: str) -> Optional[LineIndex]:
            if p not in memo:
                memo[p] = self.index_of(p)
            return memo[p]
        for d in self.known_diagnostics(uri):
            if d.path and d.path != doc.path and Path(d.path) != Path(doc.path):
                continue
            sev = self.settings.severity(d)
            if sev is None:
                continue
            out.append(to_lsp_diagnostic(d, doc.index, enc, index_of, sev))
            if len(out) >= MAX_DIAGNOSTICS:
                break
        return out

    def publish(self, uri: str) -> None:
        if self.pull_diagnostics:
            if self.cap("workspace.diagnostics.refresh_support", False):
                try:
                    self.workspace_diagnostic_refresh(None)
                except Exception:
                    pass
            return
        doc = self.docs.get(uri)
        if doc is None:
            return
        diags = self.lsp_diagnostics(uri)
        self.published[uri] = diags
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=uri, diagnostics=diags, version=doc.version))

    def clear(self, uri: str) -> None:
        self.results.pop(uri, None)
        self.last_full.pop(uri, None)
        self._quick_keys.pop(uri, None)
        self.forget_known(uri)
        if not self.pull_diagnostics:
            self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))

    # ------------------------------------------------------------ messages
    def info(self, msg: str) -> None:
        try:
            self.window_show_message(types.ShowMessageParams(type=types.MessageType.Info, message=msg))
        except Exception:
            pass

    def warn(self, msg: str) -> None:
        try:
            self.window_show_message(types.ShowMessageParams(type=types.MessageType.Warning, message=msg))
        except Exception:
            pass


def create_server() -> TvlLanguageServer:
    from ..configurator.preload import import_core, warm_parsers
    from .features import register_all
    import_core()  # before any check thread exists: concurrent first imports are not safe
    warm_parsers()  # (the first document opened is parsed at once)
    server = TvlLanguageServer()
    register_all(server)
    return server


def _stop_on_sigterm(server) -> None:
    """SIGTERM (an editor or a session manager stopping the server): its worker processes and
    counting processes are killed with it, at once (they would otherwise notice within a
    second, or finish a compilation first)."""
    import signal
    from ..base.children import kill_all
    from ..base.pools import kill_processes

    def on_term(signum, frame):
        for pool in (getattr(server, "_proc_pool", None), getattr(server, "_check_pool", None)):
            kill_processes(pool)
        kill_all()
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except Exception:  # (a reentrant write interrupted by the signal)
                pass
        os._exit(128 + signal.SIGTERM)
    try:
        signal.signal(signal.SIGTERM, on_term)
    except (ValueError, OSError):  # not the main thread (tests)
        pass


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0
    if argv and argv[0] == "--stdio":
        argv = argv[1:]
    tcp = None
    if argv and argv[0] == "--tcp":
        target = argv[1] if len(argv) > 1 else "127.0.0.1:2087"
        host, _, port = target.rpartition(":")
        if not port.isdigit() or not 0 <= int(port) <= 65535:
            print(f"tvl-lsp: bad port {port!r} (use --tcp [HOST:]PORT)", file=sys.stderr)
            return 2
        tcp = (host or "127.0.0.1", int(port))
    elif argv:
        print(f"tvl-lsp: unknown arguments {' '.join(argv)} (see tvl-lsp --help)", file=sys.stderr)
        return 2
    from ..base.envvars import log_level
    level = log_level()  # (an unknown TVL_LSP_LOG is explained on stderr, not fatal)
    logfile = os.environ.get("TVL_LSP_LOGFILE")
    stream = None
    if logfile:
        from ..base.safewrite import open_append
        try:  # (a regular file: a FIFO would block the start)
            stream = open_append(logfile)
        except OSError as ex:
            print(f"tvl-lsp: TVL_LSP_LOGFILE: {ex}; logging on stderr", file=sys.stderr)
    if stream is not None:
        logging.basicConfig(level=level, stream=stream, format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    else:
        logging.basicConfig(level=level, stream=sys.stderr)
    server = create_server()
    # parsed models are large, long-lived object graphs: collect the young generation less
    # often and keep start-up objects out of full collections (fewer, shorter GC pauses)
    import gc
    gc.collect()
    gc.freeze()
    gc.set_threshold(20000, 20, 50)
    bound_heap()  # big texts come and go as the user types: give their memory back
    if os.environ.get("TVL_LSP_WATCHDOG"):
        start_watchdog(os.environ["TVL_LSP_WATCHDOG"])
    _stop_on_sigterm(server)
    try:
        if tcp is not None:
            from .transport import serve_tcp
            serve_tcp(server, *tcp)
            return server.protocol.exit_code or 0
        from .transport import serve_stdio
        try:
            serve_stdio(server)
        finally:
            # the client went away (end of input, or exit): stop the workers now
            server.restart_proc_pool()
            server.restart_check_pool()
            server.stop_background_pool()
        # ``exit`` after ``shutdown``: 0, without: 1 (LSP); the end of the input: 0
        return server.protocol.exit_code or 0
    finally:
        # the interpreter's teardown collects what is left, extension types included: frozen,
        # they outlived it (nanobind: "leaked N instances ... py_d4" on every exit)
        gc.unfreeze()

if __name__ == "__main__":
    sys.exit(main())
