"""``tvl-lsp.configurator``: the configurator's one request for the VS Code webview (and any
client that draws it), answered by the same pure API as ``tvl-lsp ui``
(:mod:`tvl_lsp.configurator.api`).

    workspace/executeCommand tvl-lsp.configurator [uri, op, params?]

``uri``: a model, or a launch file paired with one; ``op``: model | state | decide | reset | graph |
counts | problems | generate | excerpt | explain | set | complete | configs | save | load | launches
(see :mod:`tvl_lsp.configurator.api`), or pair (``{launch}``: the launch file the model configures
from now on, chosen on the page).  The decisions are
the server's (``tvl-lsp.include`` / ``exclude`` / ``reset`` share them); ``generate`` writes the
files through ``workspace/applyEdit`` when the client can create files, else itself, in the
folder of the ``generate.folder`` setting.
"""

from __future__ import annotations

from pygls.exceptions import JsonRpcInvalidParams

from .commands import _in_worker, _path, _refresh_lens, model_of, write_generated

CONFIGURATOR = "tvl-lsp.configurator"
_OPS = ("model", "state", "decide", "reset", "counts", "graph", "problems", "generate", "excerpt",
        "explain", "set", "complete", "configs", "save", "load", "launches", "pair", "close")


def register(ls) -> None:
    @ls.command(CONFIGURATOR)
    async def configurator(ls, *args):
        from ...configurator import pool
        from ..checks import file_kind
        path = _path(args[0] if args else None)
        op = args[1] if len(args) > 1 else "model"
        if op not in _OPS:
            raise JsonRpcInvalidParams(f"the second argument must be one of: {', '.join(_OPS)}")
        params = args[2] if len(args) > 2 and isinstance(args[2], dict) else {}
        model = model_of(ls, path)
        launch = path if file_kind(path) != "tvl" else None
        roots = ls.roots_for(model)
        pairings = ls.__dict__.setdefault("configurator_pairings", {})
        if op == "pair":  # the page chose the launch file this model configures
            from ...project.generate import inside
            chosen = params.get("launch")
            if not isinstance(chosen, str) or file_kind(chosen) == "tvl" or not inside(chosen, roots):
                raise JsonRpcInvalidParams("pair needs a launch file of the workspace")
            pairings[model] = chosen
            return {"model": model, "launch": chosen}
        launch = launch or pairings.get(model)
        if op == "close":  # the panel closed: its compilations end with it
            res = await _in_worker(ls, pool.close, model)
            return res["result"]
        texts: dict[str, str] = dict(await ls.model_sources(model) or {})
        for lf in ([launch] if launch else ls.launches_for_model(model)):
            t = ls.read_file(lf)
            if t is not None:
                texts[lf] = t
        decisions = dict(ls.decisions.get(model, {}))
        res = await _in_worker(ls, pool.run, model, roots, texts, op, params, decisions, launch,
                               ls.settings.generate_folder or None, ls.settings.generate_limit)
        if "error" in res:
            raise JsonRpcInvalidParams(res["error"])
        if res["decisions"] != decisions:
            ls.decisions[model] = res["decisions"]
            _refresh_lens(ls)
        out = res["result"]
        if op == "generate":
            out["written"] = await _write(ls, out["files"], roots)
        if op == "save":
            out["written"] = await _write(ls, [{"path": out["path"], "text": out["text"]}], roots)
        return out


async def _write(ls, files: list[dict], roots: list[str]) -> list[str]:
    from ...project.generate import GeneratedFile, inside
    if ls.roots:  # (the configurator's roots are the model's workspace; writes: the folders)
        roots = [r for r in roots if inside(r, ls.roots)] or list(ls.roots)
    for f in files:
        if not inside(f["path"], roots):
            raise JsonRpcInvalidParams(f"{f['path']} is outside the workspace: not written")
    gen = [GeneratedFile(f["path"], f["text"]) for f in files]
    if gen and not await write_generated(ls, gen, roots):
        raise JsonRpcInvalidParams("the editor did not create the files")
    return [f.path for f in gen]
