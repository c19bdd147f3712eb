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
           reset that feature)                message}, state}`` (decisions unchanged);
                                              with ``counts`` (feature names) also
                                              ``counts`` (as the counts request's) when the
                                              model is compiled -- so do set, complete, load
reset      -                                  ``{ok, state}`` with no decision
counts     ``features`` (optional order),     ``{total, remaining, features: {name: n},
           ``timeout`` (s), ``wait`` (s,      complete, engine, pending, status, message}``
           default 1: how long to wait for    (counts are decimal strings); ``pending: true``
           the model's compilation)           while the model compiles in the background:
                                              ask again
generate   ``mode``: current|completions|     ``{files: [{path, relative, text}], folder}``
           sample|all, ``limit``, ``folder``  -- planned only: the host writes them
excerpt    ``path``, ``line`` (0-based)       ``{path, relative, start, line, lines}``
explain    ``feature``                        why it is included / excluded: ``{feature, value,
                                              implied, byDecisions, because, text}``
set        ``decisions`` (``{name: bool}``)   ``{ok, state}`` -- every decision replaced (an undo,
                                              a loaded configuration); ``refused`` when they
                                              conflict (the ones before the conflict are kept)
complete   ``how``: minimal|random, ``seed``  ``{ok, state, added: {name: bool}, how, engine}``:
                                              every open feature decided
configs    -                                  ``{folder, files: [{path, name, format}], formats}``:
                                              configurations saved next to the model
save       ``name``, ``format``: json|         ``{path, relative, text, format}`` -- planned only:
           featureide|uvl                     the host writes it
load       ``path`` (a saved configuration)   ``{ok, state, loaded: {format, unknown, ignored,
           or ``text`` + ``filename``         path}}`` (+ ``refused``): its decisions replace
                                              yours
launches   -                                  ``{launch, candidates: [{path, relative, args,
                                              matches}]}``: the launch files it could configure
=========  =================================  ==============================================

Generate's answer also says ``products`` (planned), ``limit``, ``cut`` (more products than the
limit) and ``available`` (how many there are, when known).

Errors raise :class:`~tvl_lsp.configurator.session.SessionError` (a message for the user).
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional

from . import configs, decisions as dec
from .session import Session, SessionError

OPS = ("model", "state", "decide", "reset", "counts", "graph", "problems", "generate", "excerpt",
       "explain", "set", "complete", "configs", "save", "load", "launches")
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
        return _with_counts(session, out, new, params, cancel), new
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
        out = {"files": [{"path": f.path, "relative": session.relative(f.path), "text": f.text} for f in files],
               "folder": out_dir, "mode": mode}
        out.update(session.last_plan)
        session.known_extra.update(f.path for f in files)  # each written file can be shown
        return out, decisions
    if op == "explain":
        feature = params.get("feature")
        if not isinstance(feature, str) or not feature:
            raise SessionError("explain needs a feature")
        return dec.why(session, decisions, feature), decisions
    if op == "set":
        given = params.get("decisions")
        if not isinstance(given, dict):
            raise SessionError("set needs decisions: {feature: true | false}")
        new, refusal = dec.replace(session, given)
        out = {"ok": refusal is None, "state": session.state(new)}
        if refusal is not None:
            out["refused"] = refusal.to_json()
        return _with_counts(session, out, new, params, cancel), new
    if op == "complete":
        how = params.get("how") or "minimal"
        seed = params.get("seed")
        seed = seed if isinstance(seed, int) and not isinstance(seed, bool) else None
        new, info = dec.complete(session, decisions, how, seed)
        return _with_counts(session, dict(info, ok=True, state=session.state(new)), new, params, cancel), new
    if op == "configs":
        folder = os.path.dirname(session.model_path)
        return {"folder": folder, "relative": session.relative(folder), "formats": list(configs.FORMATS),
                "files": [dict(f, relative=session.relative(f["path"]))
                          for f in configs.listed(folder, session.model_path)]}, decisions
    if op == "save":
        fmt = params.get("format") or "json"
        name = params.get("name") if isinstance(params.get("name"), str) else ""
        name = name or os.path.splitext(os.path.basename(session.model_path))[0]
        path = os.path.join(os.path.dirname(session.model_path), configs.file_name(name, fmt))
        existing = session.read_file(path) if os.path.lexists(path) else None
        if os.path.lexists(path) and (existing is None or not configs.is_configuration(existing, path)):
            raise SessionError(f"{os.path.basename(path)} already exists and is not a configuration: "
                               "choose another name (nothing was written)")
        st = session.state(decisions)
        text = configs.render(fmt, session.model_path, session.names, decisions, st["implied"])
        session.known_extra.add(path)
        return {"path": path, "relative": session.relative(path), "text": text, "format": fmt}, decisions
    if op == "load":
        text, where = _config_text(session, params)
        try:
            loaded = configs.parse(text, where, session.accepted_names())
        except configs.ConfigError as e:
            raise SessionError(f"{os.path.basename(where)}: {e}") from None
        new, refusal = dec.replace(session, loaded.decisions)
        out = {"ok": refusal is None, "state": session.state(new),
               "loaded": {"format": loaded.format, "unknown": loaded.unknown[:50], "unknownCount": len(loaded.unknown),
                          "ignored": loaded.ignored[:50], "path": where, "decisions": len(loaded.decisions)}}
        if refusal is not None:
            out["refused"] = refusal.to_json()
        return _with_counts(session, out, new, params, cancel), new
    if op == "launches":
        return {"launch": session.launch, "candidates": session.launch_candidates()}, decisions
    if op == "excerpt":
        path = params.get("path")
        if not isinstance(path, str):
            raise SessionError("excerpt needs a path")
        return session.excerpt(path, _int(params.get("line"), 0, 0, 10**9),
                               _int(params.get("context"), 4, 0, 400)), decisions
    raise SessionError(f"unknown request {op!r} (one of: {', '.join(OPS)})")


def _with_counts(session: Session, out: dict, decisions: dict[str, bool], params: Mapping[str, Any], cancel) -> dict:
    """``counts`` (a list of features) in a request that changes the decisions: the answer
    carries their counts too when the model is compiled (one pass, already made to propagate
    the decisions) -- one request per click instead of two."""
    feats = params.get("counts")
    if (isinstance(feats, list) and all(isinstance(f, str) for f in feats) and len(feats) <= 5000
            and session.analysis.counter.ready()):
        try:
            out["counts"] = session.counts(decisions, feats, 10.0, cancel, wait=0)
        except SessionError:
            pass
    return out


def _config_text(session: Session, params: Mapping[str, Any]) -> tuple[str, str]:
    """(text, path or file name) of the configuration to load: a file next to the model or
    inside the workspace (``path``), or a text the page read from the user's disk (``text``,
    ``filename``)."""
    from ..project.generate import inside
    text = params.get("text")
    if isinstance(text, str):
        name = params.get("filename") if isinstance(params.get("filename"), str) else "configuration.json"
        return text, os.path.basename(name)
    path = params.get("path")
    if not isinstance(path, str) or not path:
        raise SessionError("load needs the path of a configuration (or its text)")
    path = os.path.normpath(os.path.join(os.path.dirname(session.model_path), path))
    if not inside(path, session.roots):
        raise SessionError("the configuration is outside the workspace: not read")
    if configs.format_of(path) is None:
        raise SessionError(f"{os.path.basename(path)} is not a configuration (.config.json, .uvl.json, .xml)")
    from ..base.files import Unreadable, read_text
    try:
        return read_text(path, configs.MAX_CONFIG_BYTES), path
    except Unreadable as e:
        raise SessionError(f"cannot read {os.path.basename(path)}: {e.reason}") from None
    except OSError as e:
        raise SessionError(f"cannot read {os.path.basename(path)}: {e.strerror or e}") from None


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
