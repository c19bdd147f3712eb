"""The configurator's one request API, shared by its two hosts: the browser host
(:mod:`tvl_lsp.ui`, HTTP) and the language server (command ``tvl-lsp.configurator``).

``handle(session, op, params, decisions) -> (result, decisions)``: the host keeps the
decisions (a ``{feature: bool}`` dict) and passes them in; every answer is plain JSON.

=========  =================================  ==============================================
op         params                             result
=========  =================================  ==============================================
model      -                                  the feature tree and ``state``
graph      -                                  the all-products graph ``{elements, edges,
                                              status}`` (built on first use)
state      -                                  ``{decisions, implied, open, complete,
                                              graph: {id: status} | null (not built yet),
                                              problems: {id: status} | null (not checked yet)}``
problems   -                                  ``{problems: [...], status: {id: status}}``
                                              (checks the files on first use)
decide     ``feature``, ``value`` (true:      ``{ok, state}`` or ``{ok: false, refused:
           include, false: exclude, null:     {feature, value, conflictsWith, because,
           reset that feature)                message}, state}`` (decisions unchanged)
reset      -                                  ``{ok, state}`` with no decision
counts     ``features`` (optional order),     ``{total, remaining, features: {name: n},
           ``timeout`` (s), ``wait`` (s,      complete, engine, pending, status, message}``
           default 1: how long to wait for    (counts are decimal strings); ``pending: true``
           the model's compilation)           while the model compiles in the background:
                                              ask again
generate   ``mode``: current|completions|     ``{files: [{path, relative, text}], folder}``
           sample|all, ``limit``, ``folder``  -- planned only: the host writes them
excerpt    ``path``, ``line`` (0-based)       ``{path, relative, start, line, lines}``
=========  =================================  ==============================================

Errors raise :class:`~tvl_lsp.configurator.session.SessionError` (a message for the user).
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional

from .session import Session, SessionError

OPS = ("model", "state", "decide", "reset", "counts", "graph", "problems", "generate", "excerpt")
MAX_LIMIT = 1000


def _int(v: Any, default: int, lo: int = 1, hi: int = MAX_LIMIT) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return default
    return max(lo, min(hi, int(v)))


def handle(session: Session, op: str, params: Optional[Mapping[str, Any]],
           decisions: Mapping[str, bool], cancel=None, generate_folder: Optional[str] = None,
           generate_limit: int = 100) -> tuple[dict, dict[str, bool]]:
    params = dict(params or {})
    decisions = session.check_decisions(decisions)
    if op == "model":
        out = session.model_json()
        out["state"] = session.state(decisions)
        return out, decisions
    if op == "state":
        return session.state(decisions), decisions
    if op == "graph":
        return session.graph_json(decisions), decisions
    if op == "problems":
        session.problems()
        return session.problems_json(decisions), decisions
    if op == "decide":
        feature = params.get("feature")
        if not isinstance(feature, str) or not feature:
            raise SessionError("decide needs a feature")
        value = params.get("value")
        if value is not None and not isinstance(value, bool):
            raise SessionError("value must be true (include), false (exclude) or null (reset)")
        new, refusal = session.decide(decisions, feature, value)
        out: dict = {"ok": refusal is None, "state": session.state(new)}
        if refusal is not None:
            out["refused"] = refusal.to_json()
        return out, new
    if op == "reset":
        return {"ok": True, "state": session.state({})}, {}
    if op == "counts":
        feats = params.get("features")
        if feats is not None and (not isinstance(feats, list) or not all(isinstance(f, str) for f in feats)):
            raise SessionError("features must be a list of names")
        timeout = params.get("timeout")
        timeout = float(timeout) if isinstance(timeout, (int, float)) and not isinstance(timeout, bool) else 10.0
        timeout = max(0.1, min(timeout, 120.0))
        wait = params.get("wait")
        wait = float(wait) if isinstance(wait, (int, float)) and not isinstance(wait, bool) else 1.0
        wait = max(0.0, min(wait, 10.0))
        return session.counts(decisions, feats, timeout, cancel, wait=wait), decisions
    if op == "generate":
        mode = params.get("mode") or "current"
        folder = params.get("folder") if isinstance(params.get("folder"), str) and params.get("folder") else generate_folder
        files, out_dir = session.plan_generation(decisions, mode, folder,
                                                 _int(params.get("limit"), generate_limit))
        return {"files": [{"path": f.path, "relative": session.relative(f.path), "text": f.text} for f in files],
                "folder": out_dir, "mode": mode}, decisions
    if op == "excerpt":
        path = params.get("path")
        if not isinstance(path, str):
            raise SessionError("excerpt needs a path")
        return session.excerpt(path, _int(params.get("line"), 0, 0, 10**9)), decisions
    raise SessionError(f"unknown request {op!r} (one of: {', '.join(OPS)})")


def write_files(session: Session, files: list[dict]) -> list[str]:
    """Write planned files (``generate``'s result), only inside the session's workspace: atomic,
    never through a symbolic link, the output folder opened once (no check-then-write race;
    :func:`tvl_lsp.project.generate.write_configurations`).  Raises SessionError for a path
    outside the workspace, :class:`~tvl_lsp.base.safewrite.WriteError` (an ``OSError``, one
    line) for a file that cannot be written safely."""
    from ..project.generate import inside, write_configurations
    for f in files:
        path = f["path"]
        if not inside(path, session.roots) or not inside(os.path.dirname(path), session.roots):
            raise SessionError(f"{path} is outside the workspace: not written")
    return write_configurations(files, session.roots)
