"""Parsed and encoded models kept by content, for the life of a process: the check, the counts
(hover, code lens), the configurator and the graph of one process share one parse, one
encoding and one :class:`~tvl_lsp.analysis.engine.ModelAnalysis` -- and with it the counting
service's compiled circuit and the solver's cached answers -- per model text.

    load(path, text, read_file) -> (TvlResult, ModelAnalysis)

A hit needs the same model text *and* the same text of every file its parse read (its
includes), read again through the caller's ``read_file``: an edited include is a new model.
Pure: no LSP; the cache is bounded: :data:`MAX_MODELS` models, at most :data:`MAX_PER_PATH` texts
of one file and :data:`MAX_MODEL_CHARS` characters of text in all (least recently used dropped
first; the latest model is always kept).  A parsed, encoded and analysed model takes about 100
bytes per character of its text (automotive2_1.dimacs: 3.9 MB, 360 MB): a server's worker that
kept six texts of a big model being edited held 1.9 GB (issue #28).
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from typing import Callable, Optional

from .workspace import norm

ReadFile = Callable[[str], Optional[str]]

MAX_MODELS = 6
MAX_PER_PATH = 2  # the current text of a file being edited and the one before (an undo)
MAX_MODEL_CHARS = 4_000_000


class _Entry:
    __slots__ = ("result", "analysis", "deps", "weight")

    def __init__(self, result, analysis, deps: dict[str, Optional[str]], weight: int = 0):
        self.result = result
        self.analysis = analysis
        self.deps = deps
        self.weight = weight


_CACHE: "OrderedDict[tuple[str, str], _Entry]" = OrderedDict()
_LOCK = threading.Lock()
_PARSING: dict[tuple[str, str], threading.Lock] = {}
STATS = {"parsed": 0, "reused": 0}


def _key(path: str, text: str) -> tuple[str, str]:
    return norm(path), hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()


def _valid(e: _Entry, read_file: ReadFile) -> bool:
    for p, t in e.deps.items():
        try:
            if read_file(p) != t:
                return False
        except Exception:  # noqa: BLE001 (a reader that fails: parse again, it reports it)
            return False
    return True


def load(path: str, text: str, read_file: ReadFile):
    """``(result, analysis)``: the model at ``path`` with the given ``text`` parsed
    (:func:`tvl_lsp.analysis.formats.parse_any_model`: TVL, UVL or DIMACS by the name; includes and
    imports read through ``read_file``) and its analysis,
    from the cache when nothing it read has changed.  Callers must not modify either."""
    from ..analysis.engine import ModelAnalysis
    from ..analysis.formats import parse_any_model as parse_model
    key = _key(path, text)
    with _LOCK:
        lk = _PARSING.setdefault(key, threading.Lock())
    with lk:  # one parse per text even when two threads ask at once
        with _LOCK:
            e = _CACHE.get(key)
        if e is not None and _valid(e, read_file):
            with _LOCK:
                if key in _CACHE:
                    _CACHE.move_to_end(key)
                STATS["reused"] += 1
            return e.result, e.analysis
        deps: dict[str, Optional[str]] = {}

        def recording(p: str) -> Optional[str]:
            t = read_file(p)
            deps[p] = t
            return t

        res = parse_model(text, path, read_file=recording)
        weight = len(text) + sum(len(t) for t in deps.values() if t)
        e = _Entry(res, ModelAnalysis(res.model), deps, weight)
        with _LOCK:
            _CACHE[key] = e
            _CACHE.move_to_end(key)
            _evict(key)
            STATS["parsed"] += 1
        return e.result, e.analysis


def _evict(newest: tuple[str, str]) -> None:
    """Drop the least recently used models beyond the bounds (``_LOCK`` held)."""
    same = [k for k in _CACHE if k[0] == newest[0]]
    for k in same[:max(0, len(same) - MAX_PER_PATH)]:
        _drop(k)
    total = sum(e.weight for e in _CACHE.values())
    while len(_CACHE) > 1 and (len(_CACHE) > MAX_MODELS or total > MAX_MODEL_CHARS):
        old = next(iter(_CACHE))
        total -= _CACHE[old].weight
        _drop(old)


def _drop(key: tuple[str, str]) -> None:
    _CACHE.pop(key, None)
    _PARSING.pop(key, None)


def clear() -> None:
    """Forget every cached model (tests)."""
    with _LOCK:
        _CACHE.clear()
        _PARSING.clear()
