"""The document store: the server's own copy of every open document (unsaved editor text
wins over the disk), a cache of disk files, the latest parse of each file, the workspace
(files, packages, pairings) behind a path, and a small content-keyed cache.

:class:`DocumentStore` is a mixin of :class:`~tvl_lsp.lsp.server.TvlLanguageServer`; its
state is set up by :meth:`DocumentStore._init_documents`.
"""

from __future__ import annotations

import asyncio
import hashlib
import logging
import os
import re
from pathlib import Path
from typing import Any, Callable, Optional

from ..base.files import read_text_or_none
from ..base.text import LineIndex
from . import checks
from .checks import file_kind
from .convert import path_to_uri, uri_to_path

log = logging.getLogger("tvl_lsp.server")

FIRST_PARSE_WAIT = 1.2  # the same when the file was never parsed
PARSE_WAIT = 0.7  # seconds a request waits for the parse of the current text (then: the last parse)


MAX_EDITS = 1000  # changes remembered per document (to map older results onto the text)

Edit = tuple  # (start, end, inserted length): code-point offsets in the text before the change


class Document:
    __slots__ = ("uri", "path", "text", "version", "_index", "kind", "_edits", "_edits_from")

    def __init__(self, uri: str, text: str, version: Optional[int]):
        self.uri = uri
        self.path = uri_to_path(uri)
        self.text = text
        self.version = version
        self._index: Optional[LineIndex] = None
        self.kind = file_kind(self.path)
        # the changes since version ``_edits_from``: (version after the change, Edit), in order
        self._edits: list[tuple[Optional[int], Edit]] = []
        self._edits_from = version

    def set_text(self, text: str, version: Optional[int], edits: Optional[list[Edit]] = None) -> None:
        """The text of ``version``; ``edits``: the changes from the previous text, in order
        (None: one change found by comparing the two texts)."""
        if edits is None:
            edits = [text_diff(self.text, text)]
        self._edits.extend((version, e) for e in edits)
        if len(self._edits) > MAX_EDITS:
            drop = len(self._edits) - MAX_EDITS // 2
            self._edits_from = self._edits[drop - 1][0]
            del self._edits[:drop]
        self.text = text
        self.version = version
        self._index = None

    def edits_since(self, version: Optional[int]) -> Optional[list[Edit]]:
        """The changes that turned the text of ``version`` into the current one, in order;
        None when they are not known (too old, or versions the client did not number)."""
        if version == self.version:
            return []
        if version is None or self.version is None or self._edits_from is None or version < self._edits_from:
            return None
        if version > self.version:
            return None
        return [e for v, e in self._edits if v is not None and v > version]

    @property
    def index(self) -> LineIndex:
        if self._index is None:
            self._index = LineIndex(self.text)
        return self._index


def text_diff(old: str, new: str) -> Edit:
    """The one change (start, end in ``old``, inserted length) that turns ``old`` into ``new``:
    their common prefix and suffix kept (a client that sends whole texts)."""
    n = min(len(old), len(new))
    a, step = 0, 4096
    while a < n:  # blocks first (compared in C), then characters
        k = min(step, n - a)
        if old[a:a + k] == new[a:a + k]:
            a += k
        elif k == 1:
            break
        else:
            step = max(1, k // 8)
    m = min(len(old), len(new)) - a  # the suffix may not overlap the prefix
    z, step = 0, 4096
    while z < m:
        k = min(step, m - z)
        if old[len(old) - z - k:len(old) - z] == new[len(new) - z - k:len(new) - z]:
            z += k
        elif k == 1:
            break
        else:
            step = max(1, k // 8)
    return (a, len(old) - z, len(new) - z - a)


def content_key(*parts: str) -> str:
    h = hashlib.sha1()
    for p in parts:
        h.update(p.encode("utf-8", "surrogatepass"))
        h.update(b"\0")
    return h.hexdigest()

class DocumentStore:
    """Open documents, file texts, parses and pairings (a mixin of the server)."""

    def _init_documents(self) -> None:
        self.docs: dict[str, Document] = {}
        self.roots: list[str] = []
        self.disk_cache: dict[str, tuple[float, str]] = {}
        self.parsed_cache: dict[str, tuple] = {}
        # the last parse of each open launch file that had no syntax error (completion answers
        # from it while the text is being typed and does not parse)
        self.good_parsed: dict[str, Any] = {}
        self._parsing: dict[str, tuple] = {}  # path -> (parse key, task): parses under way
        # caches keyed by content
        self.cache: dict[tuple, Any] = {}
        self._cache_order: list[tuple] = []
        self.epoch = 0  # bumped when files on disk or workspace folders change

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
        text = read_text_or_none(path)  # regular files within the size cap only (never a FIFO)
        if text is None:
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
            return read_text_or_none(p)  # regular files within the size cap only
        return read

    def index_of(self, path: str) -> Optional[LineIndex]:
        doc = self.docs.get(path_to_uri(path))
        if doc is not None:
            return doc.index
        text = self.read_file(path)
        return LineIndex(text) if text is not None else None

    def workspace_root_for(self, path: str) -> Optional[str]:
        return checks._root_for(path, self.roots)

    # ------------------------------------------------------------ parsed documents, workspace, facts
    def _parse_key(self, path: str, text: str) -> tuple:
        if file_kind(path) == "launch":
            # a launch file is analysed with the features of its models (as --check does): their
            # texts are part of its parse's key
            return (content_key(text), self.epoch, self._models_key(path, text))
        return (content_key(text), self.epoch)

    def _paired_models(self, path: str, text: str) -> tuple:
        return self.cached(("paired-models", path, hash(text), self.epoch), lambda: tuple(self.models_for_launch(path)))

    def _models_key(self, path: str, text: str) -> tuple:
        out = []
        for m in self._paired_models(path, text):
            t = self.read_file(m)
            out.append((m, hash(t) if t is not None else None))  # (str hashes are cached by Python)
        return tuple(out)

    async def launch_features(self, path: str, text: str) -> Optional[list[str]]:
        """The features of the model paired with the launch file at ``path`` (by the names its
        presence conditions use), or None when it is paired with none (or the model does not
        parse): its analysis then treats the file's own boolean args as free, as --check does
        without a model."""
        models = self._paired_models(path, text)
        if not models:
            return None
        res = await self.parsed(models[0], wait=None)
        model = getattr(res, "model", None)
        if model is None or getattr(model, "root", None) is None:
            return None
        from ..project.facts import formula_names
        return formula_names(model)

    def _store_parsed(self, path: str, text: str, parsed) -> None:
        """Keep the latest parse of each file only (parsed trees are big: keeping one per
        keystroke would grow memory and garbage-collection pauses)."""
        if parsed is not None:
            self.parsed_cache[path] = (self._parse_key(path, text), parsed)
            if hasattr(parsed, "elements") and not any(d.code in ("python-syntax", "xml-syntax")
                                                       for d in getattr(parsed, "diagnostics", ())):
                self.good_parsed[path] = parsed
            if len(self.parsed_cache) > 256:
                for k in list(self.parsed_cache)[:64]:
                    if path_to_uri(k) not in self.docs:
                        self.parsed_cache.pop(k, None)
                        self.good_parsed.pop(k, None)

    def parsed_now(self, path: str):
        """The parsed document for the current text of ``path`` if already known."""
        text = self.read_file(path)
        if text is None:
            return None
        hit = self.parsed_cache.get(path)
        if hit is not None and hit[0] == self._parse_key(path, text):
            return hit[1]
        return None

    async def parsed(self, path: str, wait: Optional[float] = PARSE_WAIT):
        """The parsed document (TvlResult / LaunchAnalysis) for the current text of ``path``
        (``wait``: see below; None: the current text's, however long it takes)."""
        text = self.read_file(path)
        kind = file_kind(path)
        if text is None or kind is None:
            return None
        hit = self.parsed_now(path)
        if hit is not None:
            return hit
        # one parse per text, shared by every request that needs it; a request waits for it at
        # most PARSE_WAIT seconds, then answers from the last parse of the file (ranges are
        # clamped to the current text by convert.py): a long parse never stalls a request
        task = self.parse_task(path, kind, text)
        if wait is not None and path not in self.parsed_cache:
            wait = FIRST_PARSE_WAIT  # nothing to answer from yet: wait a little longer
        try:
            return await asyncio.wait_for(asyncio.shield(task), wait)
        except asyncio.TimeoutError:
            log.info("parse of %s still running: answering from the last parse", path)
            last = self.parsed_cache.get(path)
            return last[1] if last is not None else None

    def parse_task(self, path: str, kind: str, text: str) -> asyncio.Future:
        """The parse of ``text`` (the text of ``path``), in a thread: one per text, shared by
        the syntax pass and every request (a big model parsed twice at once in one process
        takes twice as long: the two threads share one interpreter lock)."""
        key = self._parse_key(path, text)
        running = self._parsing.get(path)
        if running is None or running[0] != key:
            # one parse of a file at a time: a newer text waits for the parse of the older one
            # to end (a thread cannot be stopped), so a burst of edits to a big model never
            # has two of its parses in memory at once
            before = running[1] if running is not None and not running[1].done() else None
            task = asyncio.ensure_future(self._parse_now(path, kind, text, before))
            task.add_done_callback(lambda t: t.cancelled() or t.exception())
            self._parsing[path] = running = (key, task)
        return running[1]

    async def _parse_now(self, path: str, kind: str, text: str, before: Optional[asyncio.Future] = None):
        if before is not None:
            try:
                await asyncio.shield(before)
            except BaseException:
                if not before.done():
                    raise  # (this parse was cancelled)
                # (the older parse failed: its own waiters see how)
        try:
            features = await self.launch_features(path, text) if kind == "launch" else None
            parsed = await self.run_in_thread(checks.parse_document, kind, path, text,
                                              self.snapshot_reader(), self.roots, features)
            self._store_parsed(path, text, parsed)
            return parsed
        finally:
            cur = self._parsing.get(path)
            if cur is not None and cur[0] == self._parse_key(path, text):
                self._parsing.pop(path, None)

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

    def own_sources(self, model_path: str) -> Optional[dict[str, str]]:
        """``{model_path: text}`` when the model's text cannot read another file (no word
        ``include`` in a TVL model, ``import`` in a UVL one; a DIMACS file never does): its
        :meth:`model_sources` without waiting for its parse -- the counts start at once."""
        kind = file_kind(model_path)
        text = self.read_file(model_path)
        if text is None or kind not in ("tvl", "uvl", "dimacs"):
            return None
        word = {"tvl": "include", "uvl": "import"}.get(kind)
        if word is not None and re.search(word, text, re.IGNORECASE):
            return None
        return {model_path: text}

    async def model_sources(self, model_path: str) -> Optional[dict[str, str]]:
        res = await self.parsed(model_path, wait=None)
        model = getattr(res, "model", None)
        if model is None:
            return None
        sources = dict(model.sources or {})
        text = self.read_file(model_path)
        if text is not None:
            sources[model_path] = text
        return sources

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
