"""Sessions kept by content, for a host that calls the configurator from a worker process (the
language server): ``run(...)`` opens -- or reuses, while the files are unchanged -- the session
and answers one :func:`~tvl_lsp.configurator.api.handle` request.  Pure: no LSP here."""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from typing import Any, Mapping, Optional, Sequence

from ..project.workspace import default_read_file, norm
from . import api
from .session import Session, SessionError

MAX_SESSIONS = 8
MAX_PER_MODEL = 2  # sessions of one model (and launch file): its current texts and the ones before
_SESSIONS: "OrderedDict[tuple, Session]" = OrderedDict()
_LOCK = threading.Lock()


def _key(model: str, launch: Optional[str], roots: Sequence[str], texts: Mapping[str, str]) -> tuple:
    h = hashlib.sha256()
    for p in sorted(texts):
        h.update(p.encode() + b"\0" + texts[p].encode() + b"\0")
    return (norm(model), norm(launch) if launch else None, tuple(norm(r) for r in roots), h.hexdigest())


def session(model: str, roots: Sequence[str], texts: Mapping[str, str], launch: Optional[str] = None) -> Session:
    """The session for ``model`` (and ``launch``, if given) where ``texts`` override the files on
    disk (the editor's unsaved buffers)."""
    key = _key(model, launch, roots, texts)
    with _LOCK:
        s = _SESSIONS.get(key)
        if s is not None:
            _SESSIONS.move_to_end(key)
            return s
    texts = {norm(p): t for p, t in texts.items()}

    def read(p: str) -> Optional[str]:
        q = norm(p)
        return texts[q] if q in texts else default_read_file(p)

    s = Session(model, roots, read, launches=[launch] if launch else None)
    with _LOCK:
        _SESSIONS[key] = s
        # a session holds its model's analysis: older texts of a model being edited go first
        same = [k for k in _SESSIONS if k[:3] == key[:3]]
        for k in same[:max(0, len(same) - MAX_PER_MODEL)]:
            del _SESSIONS[k]
        while len(_SESSIONS) > MAX_SESSIONS:
            _SESSIONS.popitem(last=False)
    return s


def run(model: str, roots: Sequence[str], texts: Mapping[str, str], op: str, params: Optional[dict],
        decisions: Mapping[str, bool], launch: Optional[str] = None, folder: Optional[str] = None,
        limit: int = 100) -> dict[str, Any]:
    """``{"result": ..., "decisions": ...}`` or ``{"error": message}`` (never raises for bad input)."""
    try:
        s = session(model, roots, texts, launch)
        out, new = api.handle(s, op, params, decisions, generate_folder=folder, generate_limit=limit)
    except SessionError as e:
        return {"error": str(e)}
    return {"result": out, "decisions": new}


def close(model: str) -> dict[str, Any]:
    """The configurator of ``model`` was closed (the VS Code panel): stop its background
    compilation (d4 is killed and reaped) and forget its sessions."""
    from ..analysis.counting.service import cancel_owned
    model = norm(model)
    stopped = cancel_owned(model, wait=3.0)
    with _LOCK:
        for k in [k for k in _SESSIONS if k[0] == model]:
            _SESSIONS.pop(k, None)
    return {"result": {"stopped": stopped}, "decisions": None}
