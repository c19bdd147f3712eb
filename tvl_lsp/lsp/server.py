"""The language server: thin glue between LSP (pygls 2) and the pure core.

    tvl-lsp                    serve LSP on stdio
    tvl-lsp --tcp [HOST:]PORT  serve LSP on TCP

Settings (``initializationOptions`` or ``workspace/configuration`` section ``tvl-lsp``)::

    {"diagnostics": {"<code>": "off" | "error" | "warning" | "information" | "hint"},
     "count": {"timeBudget": 10},          # seconds per count / solver-backed check
     "generate": {"folder": "configs",     # relative to the launch file's package, or absolute
                  "limit": 100},           # files per "generate" action
     "debounce": 0.15}                     # seconds of quiet before the solver-backed pass

Commands (``workspace/executeCommand``, see ``tvl_lsp.features.commands``): ``tvl-lsp.include``,
``tvl-lsp.exclude``, ``tvl-lsp.reset``, ``tvl-lsp.count``, ``tvl-lsp.listProducts``,
``tvl-lsp.generateConfigurations``.

The server keeps its own copy of every open document (unsaved editor text wins over disk:
:meth:`TvlLanguageServer.read_file` consults open documents first), runs the same pure check
pipeline as ``tvl-lsp --check`` off the event loop, and converts results to the client's
position encoding (``tvl_lsp.lsp_convert``).  Each LSP feature lives in its own module under
``tvl_lsp.features``; they are registered in one place (``tvl_lsp.features.register_all``).
"""

from __future__ import annotations

import asyncio
import concurrent.futures as cf
from concurrent.futures.process import BrokenProcessPool
import hashlib
import logging
import os
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol
from pygls.protocol.language_server import lsp_method

from .. import __version__
from ..base.diagnostics import Diagnostic, Severity
from .convert import encoding_name, path_to_uri, to_lsp_diagnostic, uri_to_path
from ..base.text import LineIndex

log = logging.getLogger("tvl_lsp.server")

LAUNCH_SUFFIXES = (".launch", ".launch.xml", ".test")
MAX_DIAGNOSTICS = 1000  # per document: beyond this an editor is no help anyway
SEVERITIES = {"error": Severity.ERROR, "warning": Severity.WARNING,
              "information": Severity.INFORMATION, "info": Severity.INFORMATION, "hint": Severity.HINT}


def file_kind(path: str) -> Optional[str]:
    p = path.lower()
    if p.endswith(".tvl"):
        return "tvl"
    if p.endswith(LAUNCH_SUFFIXES) or p.endswith(".xml") and "launch" in p:
        return "launch"
    return None


# ---------------------------------------------------------------- settings

@dataclass
class Settings:
    diagnostics: dict[str, str] = field(default_factory=dict)  # code -> off|error|warning|information|hint
    time_budget: float = 10.0      # seconds for a count / solver-backed check
    generate_folder: Optional[str] = None
    generate_limit: int = 100
    debounce: float = 0.15         # seconds of quiet before the solver-backed pass

    def update(self, data: Any) -> None:
        if not isinstance(data, dict):
            return
        if "tvl-lsp" in data and isinstance(data["tvl-lsp"], dict):
            data = data["tvl-lsp"]
        # flat keys as some clients send them: "count.timeBudget", "tvl-lsp.generate.folder"
        nested: dict = {}
        for k, v in data.items():
            parts = str(k).split(".")
            if parts[0] == "tvl-lsp":
                parts = parts[1:]
            if len(parts) > 1:
                cur = nested
                for p in parts[:-1]:
                    cur = cur.setdefault(p, {})
                cur[parts[-1]] = v
        if nested:
            data = {**{k: v for k, v in data.items() if "." not in str(k)}, **nested}
        diags = data.get("diagnostics")
        if isinstance(diags, dict):
            self.diagnostics = {str(k): str(v).lower() for k, v in diags.items()
                                if str(v).lower() in SEVERITIES or str(v).lower() == "off"}
        count = data.get("count")
        if isinstance(count, dict) and isinstance(count.get("timeBudget"), (int, float)):
            self.time_budget = max(0.1, float(count["timeBudget"]))
        gen = data.get("generate")
        if isinstance(gen, dict):
            if isinstance(gen.get("folder"), str):
                self.generate_folder = gen["folder"] or None
            if isinstance(gen.get("limit"), int) and gen["limit"] > 0:
                self.generate_limit = gen["limit"]
        if isinstance(data.get("debounce"), (int, float)):
            self.debounce = max(0.0, float(data["debounce"]))

    def severity(self, d: Diagnostic) -> Optional[Severity]:
        """The severity to report ``d`` with, or None when its code is turned off."""
        s = self.diagnostics.get(d.code)
        if s is None:
            return d.severity
        if s == "off":
            return None
        return SEVERITIES[s]


# ---------------------------------------------------------------- documents

class Document:
    __slots__ = ("uri", "path", "text", "version", "_index", "kind")

    def __init__(self, uri: str, text: str, version: Optional[int]):
        self.uri = uri
        self.path = uri_to_path(uri)
        self.text = text
        self.version = version
        self._index: Optional[LineIndex] = None
        self.kind = file_kind(self.path)

    def set_text(self, text: str, version: Optional[int]) -> None:
        self.text = text
        self.version = version
        self._index = None

    @property
    def index(self) -> LineIndex:
        if self._index is None:
            self._index = LineIndex(self.text)
        return self._index


def content_key(*parts: str) -> str:
    h = hashlib.sha1()
    for p in parts:
        h.update(p.encode("utf-8", "surrogatepass"))
        h.update(b"\0")
    return h.hexdigest()


class TvlProtocol(LanguageServerProtocol):
    """The server keeps its own documents (LSP line rules, robust to bad positions), so
    pygls's own workspace copy is not updated on every keystroke."""

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams):
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: types.DidOpenTextDocumentParams):
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_OPEN)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: types.DidCloseTextDocumentParams):
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CLOSE)) is not None:
            yield handler, (params,), None


@dataclass
class CheckResult:
    version: Optional[int]
    phase: str  # "syntax" | "full"
    diagnostics: list[Diagnostic]


class TvlLanguageServer(LanguageServer):
    def __init__(self):
        super().__init__("tvl-lsp", __version__, protocol_cls=TvlProtocol,
                         text_document_sync_kind=types.TextDocumentSyncKind.Incremental)
        self.docs: dict[str, Document] = {}
        self.settings = Settings()
        self.roots: list[str] = []
        self.executor = cf.ThreadPoolExecutor(max_workers=2, thread_name_prefix="tvl-check")
        self._proc_pool: Optional[cf.ProcessPoolExecutor] = None
        self._check_pool: Optional[cf.ProcessPoolExecutor] = None
        self._check_running: dict[str, tuple] = {}
        self._proc_lock = threading.Lock()
        # per-uri scheduling
        self._generation: dict[str, int] = {}
        self._syntax_running: dict[str, asyncio.Task] = {}
        self._syntax_dirty: set[str] = set()
        self._full_tasks: dict[str, asyncio.Task] = {}
        self.results: dict[str, CheckResult] = {}
        self.published: dict[str, list[types.Diagnostic]] = {}
        # caches keyed by content
        self.cache: dict[tuple, Any] = {}
        self.parsed_cache: dict[str, tuple] = {}
        self._cache_order: list[tuple] = []
        self._facts_futures: dict[str, asyncio.Future] = {}
        self._facts_queued: dict[str, tuple] = {}
        self.disk_cache: dict[str, tuple[float, str]] = {}
        self.progress_counter = 0
        self.epoch = 0  # bumped when files on disk or workspace folders change

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
        return self.cap("text_document.diagnostic") is not None

    @property
    def supports_progress(self) -> bool:
        return bool(self.cap("window.work_done_progress", False))

    # ------------------------------------------------------------ files
    def read_file(self, path: str) -> Optional[str]:
        """Text of ``path``: the open document if there is one, else the disk."""
        uri = path_to_uri(path)
        doc = self.docs.get(uri)
        if doc is not None:
            return doc.text
        try:
            st = os.stat(path)
        except OSError:
            return None
        hit = self.disk_cache.get(path)
        if hit and hit[0] == st.st_mtime_ns:
            return hit[1]
        try:
            with open(path, encoding="utf-8", errors="replace") as fh:
                text = fh.read()
        except OSError:
            return None
        if len(self.disk_cache) > 2000:
            self.disk_cache.clear()
        self.disk_cache[path] = (st.st_mtime_ns, text)
        return text

    def snapshot_reader(self) -> Callable[[str], Optional[str]]:
        """A thread-safe reader over the open documents as they are now, then the disk."""
        texts = {d.path: d.text for d in self.docs.values()}

        def read(path: str) -> Optional[str]:
            p = str(Path(path))
            if p in texts:
                return texts[p]
            try:
                with open(p, encoding="utf-8", errors="replace") as fh:
                    return fh.read()
            except OSError:
                return None
        return read

    def index_of(self, path: str) -> Optional[LineIndex]:
        doc = self.docs.get(path_to_uri(path))
        if doc is not None:
            return doc.index
        text = self.read_file(path)
        return LineIndex(text) if text is not None else None

    def workspace_root_for(self, path: str) -> Optional[str]:
        from .checks import _root_for
        return _root_for(path, self.roots)

    # ------------------------------------------------------------ parsed documents, workspace, facts
    def _parse_key(self, path: str, text: str) -> tuple:
        return (content_key(text), self.epoch)

    def _store_parsed(self, path: str, text: str, parsed) -> None:
        """Keep the latest parse of each file only (parsed trees are big: keeping one per
        keystroke would grow memory and garbage-collection pauses)."""
        if parsed is not None:
            self.parsed_cache[path] = (self._parse_key(path, text), parsed)
            if len(self.parsed_cache) > 256:
                for k in list(self.parsed_cache)[:64]:
                    if path_to_uri(k) not in self.docs:
                        self.parsed_cache.pop(k, None)

    def parsed_now(self, path: str):
        """The parsed document for the current text of ``path`` if already known."""
        text = self.read_file(path)
        if text is None:
            return None
        hit = self.parsed_cache.get(path)
        if hit is not None and hit[0] == self._parse_key(path, text):
            return hit[1]
        return None

    async def parsed(self, path: str):
        """The parsed document (TvlResult / LaunchAnalysis) for the current text of ``path``."""
        from . import checks
        from .server import file_kind as _fk
        text = self.read_file(path)
        kind = _fk(path)
        if text is None or kind is None:
            return None
        hit = self.parsed_now(path)
        if hit is not None:
            return hit
        parsed = await self.run_in_thread(checks.parse_document, kind, path, text,
                                          self.snapshot_reader(), self.roots)
        self._store_parsed(path, text, parsed)
        return parsed

    def roots_for(self, path: str) -> list[str]:
        root = self.workspace_root_for(path)
        if root:
            return [root]
        from ..project.workspace import find_workspace_root
        try:
            return [find_workspace_root(path)]
        except Exception:
            return [str(Path(path).parent)]

    def workspace_model(self, path: str):
        """The Workspace (files, packages, pairings) that contains ``path``."""
        from ..project.workspace import load_workspace
        roots = tuple(self.roots_for(path))
        key = ("workspace", roots, self.epoch)
        return self.cached(key, lambda: load_workspace(roots, read_file=self.read_file))

    def models_for_launch(self, path: str) -> list[str]:
        try:
            ws = self.workspace_model(path)
            pairings, _ = ws.pair(path, self.read_file(path))
            return [p.model for p in pairings if p.model]
        except Exception:
            log.exception("pairing failed")
            return []

    def launches_for_model(self, path: str) -> list[str]:
        try:
            ws = self.workspace_model(path)
            return sorted({p.launch for p in ws.launches_for_model(path)})
        except Exception:
            log.exception("pairing failed")
            return []

    async def model_sources(self, model_path: str) -> Optional[dict[str, str]]:
        res = await self.parsed(model_path)
        model = getattr(res, "model", None)
        if model is None:
            return None
        sources = dict(model.sources or {})
        text = self.read_file(model_path)
        if text is not None:
            sources[model_path] = text
        return sources

    def facts_ready(self, sources: dict[str, str]):
        return self.cache.get(("facts", content_key(*sorted(f"{k}\0{v}" for k, v in sources.items()))))

    async def model_facts(self, model_path: str, wait: Optional[float] = None):
        """Counts and anomalies of a model, computed in a worker process (so a slow count
        never blocks the event loop), cached by content.  With ``wait``, give up waiting
        after that many seconds (the computation goes on and lands in the cache)."""
        from ..project import facts as _facts
        sources = await self.model_sources(model_path)
        if sources is None:
            return None
        budget = self.settings.time_budget
        key = ("facts", content_key(*sorted(f"{k}\0{v}" for k, v in sources.items())), budget)
        hit = self.cache.get(key)
        if hit is not None:
            return hit
        # a count queued for an older text of this model is stale: drop it
        old = self._facts_queued.get(model_path)
        if old is not None and old[0] != key[1]:
            old[1].cancel()
        fut = self._facts_futures.get(key[1])
        if fut is None:
            loop = asyncio.get_running_loop()

            async def compute():
                cfut = None
                try:
                    cfut = self.proc_pool.submit(_facts.compute_model_facts, model_path, sources, budget)
                    self._facts_queued[model_path] = (key[1], cfut)
                    afut = asyncio.wrap_future(cfut)
                    afut.add_done_callback(_consume)
                    facts = await asyncio.wait_for(asyncio.shield(afut), budget + 30)
                except (cf.CancelledError, asyncio.CancelledError):
                    if cfut is not None and cfut.cancelled():
                        return _facts.ModelFacts(error="cancelled: the model changed")
                    raise
                except Exception as e:
                    facts = _facts.ModelFacts(error=f"{type(e).__name__}: {e}")
                    if isinstance(e, (BrokenProcessPool, asyncio.TimeoutError)):
                        self.restart_proc_pool()
                    return facts
                # (a count that ran out of its budget is cached too: the same text and
                # budget would run out again)
                self.cache[key] = facts
                self._remember(key)
                return facts

            async def run():
                try:
                    return await self.with_progress(f"Counting the products of {Path(model_path).name}", compute())
                finally:
                    self._facts_futures.pop(key[1], None)
            fut = loop.create_task(run())
            self._facts_futures[key[1]] = fut
        if wait is None:
            return await asyncio.shield(fut)
        try:
            return await asyncio.wait_for(asyncio.shield(fut), wait)
        except asyncio.TimeoutError:
            return None

    async def count_under(self, model_path: str, formula, wait: Optional[float] = None):
        from ..project import facts as _facts
        sources = await self.model_sources(model_path)
        if sources is None:
            return None
        key = ("count", content_key(*sorted(f"{k}\0{v}" for k, v in sources.items())), str(formula))
        if key in self.cache:
            return self.cache[key]
        budget = self.settings.time_budget
        cfut = self.proc_pool.submit(_facts.count_under, model_path, sources, formula, budget)
        afut = asyncio.wrap_future(cfut)
        afut.add_done_callback(_consume)
        try:
            n = await asyncio.wait_for(asyncio.shield(afut), wait or budget + 5)
        except asyncio.TimeoutError:
            return None
        except Exception:
            log.exception("count failed")
            return None
        self.cache[key] = n
        self._remember(key)
        return n

    # ------------------------------------------------------------ cache
    def _remember(self, key: tuple) -> None:
        self._cache_order.append(key)
        if len(self._cache_order) > 512:
            old = self._cache_order.pop(0)
            self.cache.pop(old, None)

    def cached(self, key: tuple, compute: Callable[[], Any]) -> Any:
        try:
            return self.cache[key]
        except KeyError:
            pass
        value = compute()
        self.cache[key] = value
        self._cache_order.append(key)
        if len(self._cache_order) > 256:
            old = self._cache_order.pop(0)
            self.cache.pop(old, None)
        return value

    async def run_in_thread(self, fn, *args):
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self.executor, fn, *args)

    @property
    def proc_pool(self) -> cf.ProcessPoolExecutor:
        with self._proc_lock:
            if self._proc_pool is None:
                import multiprocessing as mp
                self._proc_pool = cf.ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("spawn"),
                                                         initializer=_worker_init)
            return self._proc_pool

    @property
    def check_pool(self) -> cf.ProcessPoolExecutor:
        with self._proc_lock:
            if self._check_pool is None:
                import multiprocessing as mp
                self._check_pool = cf.ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("spawn"),
                                                          initializer=_worker_init)
            return self._check_pool

    def restart_check_pool(self) -> None:
        with self._proc_lock:
            pool, self._check_pool = self._check_pool, None
        _kill_pool(pool)

    def warm_up(self) -> None:
        """Start the worker processes now, so the first check / count does not pay for it."""
        try:
            self.proc_pool.submit(_warm)
            self.check_pool.submit(_warm)
        except Exception:
            pass

    def restart_proc_pool(self) -> None:
        with self._proc_lock:
            pool, self._proc_pool = self._proc_pool, None
        _kill_pool(pool)

    # ------------------------------------------------------------ scheduling
    def schedule(self, uri: str, syntax: bool = True) -> None:
        """(Re)check ``uri``: the syntax pass at once (coalesced while one runs), the
        solver-backed pass after ``settings.debounce`` of quiet."""
        doc = self.docs.get(uri)
        if doc is None or doc.kind is None:
            return
        self._generation[uri] = self._generation.get(uri, 0) + 1
        if syntax:
            if uri in self._syntax_running:
                self._syntax_dirty.add(uri)
            else:
                self._syntax_running[uri] = asyncio.ensure_future(self._syntax_pass(uri))
        old = self._full_tasks.pop(uri, None)
        if old is not None and not old.done():
            old.cancel()
        self._full_tasks[uri] = asyncio.ensure_future(self._full_pass(uri, self._generation[uri]))

    async def _syntax_pass(self, uri: str) -> None:
        from . import checks
        try:
            while True:
                self._syntax_dirty.discard(uri)
                doc = self.docs.get(uri)
                if doc is None:
                    return
                version, text, path, kind = doc.version, doc.text, doc.path, doc.kind
                reader = self.snapshot_reader()
                try:
                    diags, parsed = await self.run_in_thread(checks.syntax_check, kind, path, text, reader, self.roots)
                    self._store_parsed(path, text, parsed)
                except Exception:
                    log.exception("syntax check of %s failed", path)
                    diags = []
                doc = self.docs.get(uri)
                cur = self.results.get(uri)
                if doc is not None and doc.version == version and not (
                        cur and cur.version == version and cur.phase == "full"):
                    self.results[uri] = CheckResult(version, "syntax", diags)
                    self.publish(uri)
                if uri not in self._syntax_dirty:
                    return
        finally:
            self._syntax_running.pop(uri, None)

    async def _full_pass(self, uri: str, generation: int) -> None:
        from . import checks
        try:
            await asyncio.sleep(self.settings.debounce)
            if self._generation.get(uri) != generation:
                return
            doc = self.docs.get(uri)
            if doc is None:
                return
            version, text, path, kind = doc.version, doc.text, doc.path, doc.kind
            budget = self.settings.time_budget
            texts = {d.path: d.text for d in self.docs.values()}
            running = self._check_running.get(uri)
            if running is not None and not running.done():
                # one check per document at a time: wait for the one on an older text (each
                # newer keystroke cancels this wait, so only the latest text is checked next)
                try:
                    await asyncio.wait_for(asyncio.shield(running), budget + 10)
                except asyncio.TimeoutError:
                    log.warning("a check of %s hangs: restarting the check process", path)
                    self.restart_check_pool()
                except asyncio.CancelledError:
                    raise
                except Exception:
                    pass
                if self._generation.get(uri) != generation:
                    return
            try:
                cfut = self.check_pool.submit(checks.full_check_worker, kind, path, text, texts,
                                              self.roots_for(path), budget, self.epoch)
                afut = asyncio.wrap_future(cfut)
                afut.add_done_callback(_consume)
                self._check_running[uri] = afut
                diags = await asyncio.wait_for(asyncio.shield(afut), timeout=budget + 10)
            except asyncio.TimeoutError:
                log.warning("check of %s ran out of its time budget", path)
                self.restart_check_pool()
                return
            except asyncio.CancelledError:
                raise
            except BrokenProcessPool:
                log.warning("the check process died; restarting it")
                self.restart_check_pool()
                return
            except Exception:
                log.exception("check of %s failed", path)
                return
            doc = self.docs.get(uri)
            if doc is None or doc.version != version or self._generation.get(uri) != generation:
                return  # stale: the text changed meanwhile
            self.results[uri] = CheckResult(version, "full", diags)
            self.publish(uri)
            self.prefetch_facts(path, kind)
        except asyncio.CancelledError:
            pass

    def prefetch_facts(self, path: str, kind: str) -> None:
        """Start counting the products of the model behind ``path`` (the model itself, or the
        models paired with a launch file) in the background, so that the first hover and the
        code lens find the counts ready instead of saying "counting…"."""
        try:
            models = [path] if kind == "tvl" else list(self.models_for_launch(path))
        except Exception:
            log.exception("pairing failed")
            return
        for mp in models:
            task = asyncio.ensure_future(self.model_facts(mp))
            task.add_done_callback(_consume)

    async def wait_full(self, uri: str, timeout: float) -> Optional[CheckResult]:
        """The latest results of ``uri`` once no check of it is pending (or time runs out)."""
        loop = asyncio.get_running_loop()
        end = loop.time() + timeout
        while True:
            task = self._full_tasks.get(uri)
            left = end - loop.time()
            if task is None or task.done() or left <= 0:
                break
            try:
                await asyncio.wait_for(asyncio.shield(task), left)
            except (asyncio.TimeoutError, asyncio.CancelledError):
                if loop.time() >= end:
                    break
        return self.results.get(uri)

    def recheck_dependents(self, path: str) -> None:
        """Editing a model re-checks its paired launch files and vice versa (open ones)."""
        from . import checks
        for uri, doc in list(self.docs.items()):
            if doc.path == path or doc.kind is None:
                continue
            if checks.depends_on(self, doc, path):
                self.schedule(uri, syntax=False)

    def recheck_all(self) -> None:
        for uri in list(self.docs):
            self.schedule(uri)

    # ------------------------------------------------------------ publishing
    def lsp_diagnostics(self, uri: str) -> list[types.Diagnostic]:
        doc = self.docs.get(uri)
        res = self.results.get(uri)
        if doc is None or res is None:
            return []
        out = []
        enc = self.encoding
        memo: dict[str, Optional[LineIndex]] = {doc.path: doc.index}

        def index_of(p: str) -> Optional[LineIndex]:
            if p not in memo:
                memo[p] = self.index_of(p)
            return memo[p]
        for d in res.diagnostics:
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
        if not self.pull_diagnostics:
            self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))

    # ------------------------------------------------------------ progress
    async def with_progress(self, title: str, coro):
        """Run ``coro`` with a ``$/progress`` bar when the client supports it."""
        if not self.supports_progress:
            return await coro
        self.progress_counter += 1
        token = f"tvl-lsp-{os.getpid()}-{self.progress_counter}"
        try:
            await asyncio.wait_for(self.work_done_progress.create_async(token), 2)
        except Exception:
            return await coro
        self.work_done_progress.begin(token, types.WorkDoneProgressBegin(title=title, cancellable=False))
        try:
            return await coro
        finally:
            self.work_done_progress.end(token, types.WorkDoneProgressEnd(message="done"))

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


def _worker_init() -> None:
    """Worker processes (checks, counts) yield the CPU to the process answering the editor,
    and die with it (an editor may kill the server without a ``shutdown``)."""
    try:
        os.nice(10)
    except (OSError, AttributeError):
        pass
    parent = os.getppid()
    try:  # Linux: SIGKILL when the parent dies
        import ctypes
        import signal
        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except Exception:
        pass

    def orphan_watch():  # elsewhere (or if the parent died before prctl): poll
        while True:
            time.sleep(1.0)
            if os.getppid() != parent:
                os._exit(0)
    threading.Thread(target=orphan_watch, daemon=True).start()


def _consume(fut) -> None:
    """Retrieve a future's exception so that asyncio does not log it as never retrieved."""
    if not fut.cancelled():
        fut.exception()


def _kill_pool(pool) -> None:
    if pool is None:
        return
    try:
        for p in list((getattr(pool, "_processes", None) or {}).values()):
            p.kill()
    except Exception:
        pass
    try:
        pool.shutdown(wait=True, cancel_futures=True)  # quick: its processes are gone
    except Exception:
        pass


def _warm() -> None:
    try:
        from ..project import facts as _facts  # noqa: F401
        from ..analysis import engine  # noqa: F401
        from ..tvl import parse_model  # noqa: F401
    except Exception:
        pass


def _start_watchdog(path: str, threshold: float = 0.3) -> None:
    """Debug aid (``TVL_LSP_WATCHDOG=FILE``): log the event loop's stack whenever it is
    blocked for more than ``threshold`` seconds."""
    import traceback
    main_id = threading.get_ident()
    beat = [time.monotonic()]

    async def heartbeat():
        while True:
            beat[0] = time.monotonic()
            await asyncio.sleep(0.05)

    def watch():
        while True:
            time.sleep(0.1)
            stalled = time.monotonic() - beat[0]
            if stalled > threshold:
                frame = sys._current_frames().get(main_id)
                with open(path, "a") as fh:
                    fh.write(f"--- loop blocked {stalled:.2f}s\n")
                    fh.write("".join(traceback.format_stack(frame)[-12:]))
    threading.Thread(target=watch, daemon=True).start()
    _WATCHDOG.append(heartbeat)


_WATCHDOG: list = []


def create_server() -> TvlLanguageServer:
    from .features import register_all
    server = TvlLanguageServer()
    register_all(server)
    return server


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0
    logfile = os.environ.get("TVL_LSP_LOGFILE")
    if logfile:
        logging.basicConfig(level=os.environ.get("TVL_LSP_LOG", "WARNING"), filename=logfile)
    else:
        logging.basicConfig(level=os.environ.get("TVL_LSP_LOG", "WARNING"), stream=sys.stderr)
    server = create_server()
    # parsed models are large, long-lived object graphs: collect the young generation less
    # often and keep start-up objects out of full collections (fewer, shorter GC pauses)
    import gc
    gc.collect()
    gc.freeze()
    gc.set_threshold(20000, 20, 50)
    if os.environ.get("TVL_LSP_WATCHDOG"):
        _start_watchdog(os.environ["TVL_LSP_WATCHDOG"])
    if argv and argv[0] == "--stdio":
        argv = argv[1:]
    if argv and argv[0] == "--tcp":
        target = argv[1] if len(argv) > 1 else "127.0.0.1:2087"
        host, _, port = target.rpartition(":")
        try:
            port_n = int(port)
        except ValueError:
            print(f"tvl-lsp: bad port {port!r} (use --tcp [HOST:]PORT)", file=sys.stderr)
            return 2
        server.start_tcp(host or "127.0.0.1", port_n)
        return 0
    if argv:
        print(f"tvl-lsp: unknown arguments {' '.join(argv)} (see tvl-lsp --help)", file=sys.stderr)
        return 2
    try:
        server.start_io()
    finally:
        # the client went away (end of input, or exit): stop the workers now
        server.restart_proc_pool()
        server.restart_check_pool()
    return 0


if __name__ == "__main__":
    sys.exit(main())
