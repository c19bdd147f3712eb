"""``workspace/executeCommand``: the configurator (include / exclude / reset a feature, count,
list the remaining products) and the generation of configuration launch files.

Every command takes, as its first argument, the URI (or path) of a model or of a launch file
paired with one; the configurator keeps one set of decisions per model.

- ``tvl-lsp.include``  [uri, feature]     -> propagation {decisions, forced, conflict, remaining}
- ``tvl-lsp.exclude``  [uri, feature]     -> same
- ``tvl-lsp.reset``    [uri, feature?]    -> same (no feature: forget every decision)
- ``tvl-lsp.count``    [uri]              -> {total, remaining, decisions} (…Text: decimal strings)
- ``tvl-lsp.listProducts`` [uri, limit?]  -> {products: [[selected features]], remaining, truncated}
- ``tvl-lsp.generateConfigurations`` [{uri, mode: one|completions|all, limit?, folder?, launch?}]
      -> {files: [paths], applied: bool}: created through workspace/applyEdit (CreateFile +
      edits) when the client supports resource operations, else written by the server.
"""

from __future__ import annotations

import asyncio
import os
from pathlib import Path
from typing import Any, Optional

from lsprotocol import types

from pygls.exceptions import JsonRpcException, JsonRpcInvalidParams

from ...project.generate import GenerateError, plan_configurations, resolve_folder, ros2_choices
from ..convert import path_to_uri, uri_to_path
from ...project import facts as F
from ...project.facts import MODEL_KINDS

INCLUDE, EXCLUDE, RESET = "tvl-lsp.include", "tvl-lsp.exclude", "tvl-lsp.reset"
COUNT, LIST, GENERATE = "tvl-lsp.count", "tvl-lsp.listProducts", "tvl-lsp.generateConfigurations"
DOC_STATE = "tvl-lsp.documentState"


def _path(arg: Any) -> str:
    if isinstance(arg, dict):
        arg = arg.get("uri") or arg.get("path")
    if not isinstance(arg, str) or not arg:
        raise JsonRpcInvalidParams("the first argument must be the URI of a model or launch file")
    return uri_to_path(arg) if "://" in arg else str(Path(arg).absolute())


def model_of(ls, path: str) -> str:
    from ..checks import file_kind
    if file_kind(path) in MODEL_KINDS:
        return path
    models = ls.models_for_launch(path)
    if not models:
        raise JsonRpcInvalidParams(f"{Path(path).name} is not paired with a model")
    return models[0]


async def _in_worker(ls, fn, *args, title: Optional[str] = None):
    async def run():
        try:
            return await asyncio.wrap_future(ls.proc_pool.submit(fn, *args))
        except F.UnknownFeatures as e:  # decisions the edited model no longer has
            raise JsonRpcInvalidParams(f"{e.args[0]}: reset them (tvl-lsp.reset)")
    if title:
        return await ls.with_progress(title, run())
    return await run()


def register(ls) -> None:
    ls.decisions = {}  # model path -> {feature: bool}

    async def propagate(ls, model: str) -> dict:
        sources = await ls.model_sources(model)
        if sources is None:
            raise JsonRpcInvalidParams(f"cannot read {model}")
        res = await _in_worker(ls, F.configure, model, sources, dict(ls.decisions.get(model, {})),
                               ls.settings.time_budget)
        if res.get("error"):
            raise JsonRpcInvalidParams(res["error"])
        _refresh_lens(ls)
        return res

    async def decide(ls, args, selected: bool):
        model = model_of(ls, _path(args[0] if args else None))
        feature = _feature_arg(args)
        ls.decisions.setdefault(model, {})[feature] = selected
        return await _checked(ls, propagate, model, feature)

    @ls.command(INCLUDE)
    async def include(ls, *args):
        return await decide(ls, args, True)

    @ls.command(EXCLUDE)
    async def exclude(ls, *args):
        return await decide(ls, args, False)

    @ls.command(RESET)
    async def reset(ls, *args):
        model = model_of(ls, _path(args[0] if args else None))
        if len(args) > 1 and isinstance(args[1], str):
            ls.decisions.get(model, {}).pop(args[1], None)
        else:
            ls.decisions.pop(model, None)
        return await propagate(ls, model)

    @ls.command(COUNT)
    async def count(ls, *args):
        model = model_of(ls, _path(args[0] if args else None))
        facts = await ls.model_facts(model)
        decisions = dict(ls.decisions.get(model, {}))
        remaining = facts.total if facts else None
        if decisions:
            remaining = (await propagate(ls, model)).get("remaining")
        return {"total": facts.total if facts else None,
                "totalText": None if not facts or facts.total is None else str(facts.total),
                "remaining": remaining, "remainingText": None if remaining is None else str(remaining),
                "decisions": decisions, "error": facts.error if facts else "no model"}

    @ls.command(LIST)
    async def list_products(ls, *args):
        model = model_of(ls, _path(args[0] if args else None))
        limit = args[1] if len(args) > 1 and isinstance(args[1], int) and args[1] > 0 else 100
        sources = await ls.model_sources(model)
        return await _in_worker(ls, F.list_products, model, sources, dict(ls.decisions.get(model, {})),
                                limit, ls.settings.time_budget, title="Listing products")

    @ls.command(GENERATE)
    async def generate(ls, *args):
        opts = args[0] if args and isinstance(args[0], dict) else {"uri": args[0] if args else None}
        return await generate_configurations(ls, opts)

    @ls.command(DOC_STATE)
    def document_state(ls, *args):
        """Diagnostics aid (used by the soak test): the server's copy of a document."""
        uri = args[0] if args else ""
        doc = ls.docs.get(uri)
        rss = None
        try:
            from ...base.files import read_head
            rss = int((read_head("/proc/self/statm", 256) or b"").split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except (OSError, ValueError, IndexError):
            pass
        res = ls.results.get(uri)
        return {"text": doc.text if doc else None, "version": doc.version if doc else None,
                "phase": res.phase if res else None, "resultVersion": res.version if res else None,
                "rss": rss, "documents": len(ls.docs), "cache": len(ls.cache),
                "handlers": len(ls.protocol._request_futures), "debounce": ls.settings.debounce}


def _feature_arg(args) -> str:
    if len(args) < 2 or not isinstance(args[1], str) or not args[1]:
        raise JsonRpcInvalidParams("the second argument must be a feature name")
    return args[1]


async def _checked(ls, propagate, model, feature):
    try:
        return await propagate(ls, model)
    except JsonRpcInvalidParams:
        ls.decisions.get(model, {}).pop(feature, None)
        raise


def _refresh_lens(ls) -> None:
    if ls.cap("workspace.code_lens.refresh_support", False):
        try:
            ls.workspace_code_lens_refresh(None)
        except Exception:
            pass


def can_create(ls) -> bool:
    """Can the client create files through a WorkspaceEdit?  (Resource operations only
    exist inside ``documentChanges``, so advertising ``create`` implies them.)"""
    ops = ls.cap("workspace.workspace_edit.resource_operations", []) or []
    return any(getattr(o, "value", o) == "create" for o in ops)


def write_roots(ls, path: str) -> list[str]:
    """Where generated files may be written for ``path``: inside the client's workspace
    folders (the one that holds ``path``; a file outside every folder gets nothing written);
    without workspace folders (a single file), its workspace as found from the file."""
    if not ls.roots:
        return ls.roots_for(path)
    from ...project.generate import inside
    if not inside(path, ls.roots):
        raise JsonRpcInvalidParams(f"{Path(path).name} is outside the workspace folders: "
                                   "configurations are only written inside them")
    return [r for r in ls.roots if inside(path, [r])]


async def plan(ls, opts: dict):
    """(files, out_dir, truncated) for a generation request (nothing written)."""
    path = _path(opts)
    from ..checks import file_kind
    mode = opts.get("mode") or "all"
    if mode not in ("one", "completions", "all"):
        raise JsonRpcInvalidParams("mode must be one of: one, completions, all")
    limit = opts.get("limit") if isinstance(opts.get("limit"), int) and opts["limit"] > 0 else ls.settings.generate_limit
    if file_kind(path) in MODEL_KINDS:
        model = path
        launch = _path(opts["launch"]) if opts.get("launch") else None
        if launch is None:
            launches = ls.launches_for_model(model)
            if not launches:
                raise JsonRpcInvalidParams(f"{Path(model).name} is paired with no launch file")
            launch = launches[0]
    else:
        launch, model = path, model_of(ls, path)
    analysis = await ls.parsed(launch, wait=None)
    res = await ls.parsed(model, wait=None)
    m = getattr(res, "model", None)
    if analysis is None or m is None:
        raise JsonRpcInvalidParams("cannot analyse the launch file or its model")
    feature_names = {f.name for f in m.features} | {f.long_name for f in m.features}
    features = [a.name for a in analysis.feature_args
                if a.name in feature_names and getattr(a, "value", None) is None]
    roots = write_roots(ls, launch)
    try:
        out_dir = resolve_folder(opts.get("folder") or ls.settings.generate_folder, launch, roots)
    except GenerateError as e:
        raise JsonRpcInvalidParams(str(e))
    ws = ls.workspace_model(launch)
    package = ws.package_of(launch)
    package_dir = ws.packages.get(package) if package else None
    sources = await ls.model_sources(model)
    decisions = dict(ls.decisions.get(model, {}))
    products = await _in_worker(ls, F.generation_products, model, sources, decisions, mode, limit,
                                title="Generating configurations")
    try:
        files = plan_configurations(products, features, launch, out_dir, roots, package, package_dir,
                                    omit=[m.root.name] if m.root else (),
                                    dialect=getattr(analysis, "dialect", "ros1"), choices=ros2_choices(analysis, m))
    except GenerateError as e:
        raise JsonRpcInvalidParams(str(e))
    return files, out_dir, mode != "one" and len(products) >= limit


class RequestFailed(JsonRpcException):
    """LSP's RequestFailed (-32803): a valid request that could not be done (a file that cannot
    be written: a link, a full disk...); its message is one line the editor shows."""
    CODE = -32803


async def write_generated(ls, files, roots: list[str], label: str = "Generate configuration launch files") -> bool:
    """Write planned configuration files (GeneratedFile) inside ``roots``: through the editor
    (``workspace/applyEdit``, after checking that no target is a link or a special file) when it
    can create files, else here (:func:`tvl_lsp.project.generate.write_configurations`: atomic,
    never through a link).  True when written; raises RequestFailed with a one-line reason."""
    from ...project.generate import check_configurations, write_configurations
    try:
        if can_create(ls):
            check_configurations(files, roots)
        else:
            await ls.run_in_thread(write_configurations, list(files), list(roots))
            return True
    except OSError as e:
        from ...base.safewrite import WriteError, summary
        raise RequestFailed(summary(e, len(files)) if isinstance(e, WriteError) else str(e))
    result = await ls.workspace_apply_edit_async(types.ApplyWorkspaceEditParams(
        edit=creation_edit(files), label=label))
    return bool(getattr(result, "applied", False))


def check_targets(ls, files) -> None:
    """Raise RequestFailed when a planned file could not be written safely (a symbolic link, a
    FIFO, a folder that is a link): before an edit that lets the editor write them."""
    from ...project.generate import check_configurations
    if not files:
        return
    try:
        check_configurations(files, write_roots(ls, files[0].path))
    except OSError as e:
        raise RequestFailed(str(e))


def creation_edit(files) -> types.WorkspaceEdit:
    changes: list = []
    for f in files:
        uri = path_to_uri(f.path)
        changes.append(types.CreateFile(uri=uri, options=types.CreateFileOptions(overwrite=True)))
        changes.append(types.TextDocumentEdit(
            text_document=types.OptionalVersionedTextDocumentIdentifier(uri=uri, version=None),
            edits=[types.TextEdit(range=types.Range(start=types.Position(line=0, character=0),
                                                    end=types.Position(line=0, character=0)),
                                  new_text=f.text)]))
    return types.WorkspaceEdit(document_changes=changes)


async def generate_configurations(ls, opts: dict) -> dict:
    files, out_dir, truncated = await plan(ls, opts)
    if not files:
        return {"files": [], "applied": False, "message": "no product matches the current configuration"}
    applied = await write_generated(ls, files, write_roots(ls, files[0].path))
    if applied and not can_create(ls):
        ls.info(f"tvl-lsp: wrote {len(files)} configuration launch file(s) to {out_dir}")
    return {"files": [f.path for f in files], "applied": applied, "folder": out_dir, "truncated": truncated}
