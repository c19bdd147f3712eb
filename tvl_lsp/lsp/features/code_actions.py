"""Code actions: every ``Diagnostic.fixes`` becomes a quick fix (add the missing
``<arg name="X"/>``, rename an unknown name to a close one, ``and`` → ``&&``,
``constant`` → ``const``, …), "add all missing args" at once, and the generation of
configuration launch files (a command: products are computed off the event loop)."""

from __future__ import annotations

from lsprotocol import types

from ...base.diagnostics import Fix, TextEdit
from ..convert import fix_to_edit, from_lsp_range, spans_overlap, to_lsp_diagnostic
from ...project.facts import MODEL_KINDS
from . import quickfix
from .commands import GENERATE, can_create, check_targets, creation_edit, plan


def _kind(k) -> str:
    # kinds are str enums: compare their values ('quickfix'), not str() ('CodeActionKind.QuickFix')
    return str(getattr(k, "value", k))


def _same(lsp_diag: types.Diagnostic, d, rng) -> bool:
    return lsp_diag.code == d.code and lsp_diag.range == rng


def merge_fixes(title: str, fixes: list[Fix]) -> Fix:
    """One fix applying several (edits at the same place are concatenated in order)."""
    merged: dict[tuple, TextEdit] = {}
    order = []
    seen = set()
    for f in fixes:
        for e in f.edits:
            k = (e.path, e.span)
            if (k, e.new_text) in seen:
                continue  # the same edit in several fixes (e.g. an import a Python file needs once)
            seen.add((k, e.new_text))
            if k in merged:
                merged[k] = TextEdit(e.path, e.span, merged[k].new_text + e.new_text)
            else:
                merged[k] = e
                order.append(k)
    return Fix(title, tuple(merged[k] for k in order), preferred=False)


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_CODE_ACTION,
                types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix,
                                                           types.CodeActionKind.Source],
                                        resolve_provider=True))
    async def code_action(ls, params: types.CodeActionParams):
        uri = params.text_document.uri
        doc = ls.docs.get(uri)
        if doc is None or doc.kind is None:
            return None
        res = ls.results.get(uri)
        if res is None or res.version != doc.version:
            res = await ls.wait_full(uri, 2.0)
        want = params.context.only
        actions: list[types.CodeAction] = []
        span = from_lsp_range(doc.index, params.range, ls.encoding)
        enc = ls.encoding
        all_missing = []
        if res is not None and res.version == doc.version:
            for d in res.diagnostics:
                if d.path and d.path != doc.path:
                    continue
                if d.code == "missing-arg" and d.fixes:
                    all_missing.append(d)
                if not d.fixes or not spans_overlap(d.span, span):
                    continue
                sev = ls.settings.severity(d)
                if sev is None:
                    continue
                ld = to_lsp_diagnostic(d, doc.index, enc, ls.index_of, sev)
                for fx in d.fixes:
                    actions.append(types.CodeAction(
                        title=fx.title, kind=types.CodeActionKind.QuickFix, diagnostics=[ld],
                        is_preferred=fx.preferred or None, edit=fix_to_edit(fx, ls.index_of, enc)))
            if not want or any(_kind(types.CodeActionKind.QuickFix).startswith(_kind(w)) for w in want):
                # model anomalies: checked fixes, computed off the event loop (quickfix.py)
                at = [d for d in res.diagnostics if (not d.path or d.path == doc.path) and spans_overlap(d.span, span)]
                actions += await quickfix.actions(ls, uri, doc, at)
        if len(all_missing) > 1 and any(spans_overlap(d.span, span) for d in all_missing):
            what = "DeclareLaunchArgument actions" if doc.path.endswith(".py") else "<arg> tags"
            fx = merge_fixes(f"Add all {len(all_missing)} missing {what}",
                             [f for d in all_missing for f in d.fixes[:1]])
            diags = [to_lsp_diagnostic(d, doc.index, enc, ls.index_of) for d in all_missing]
            actions.append(types.CodeAction(title=fx.title, kind=types.CodeActionKind.QuickFix,
                                            diagnostics=diags, edit=fix_to_edit(fx, ls.index_of, enc)))
        paired = bool(ls.launches_for_model(doc.path)) if doc.kind in MODEL_KINDS else bool(ls.models_for_launch(doc.path))
        if paired:
            limit = ls.settings.generate_limit
            resolvable = "edit" in (ls.cap("text_document.code_action.resolve_support.properties", []) or [])
            for mode, title in (("one", "Generate a configuration launch file for one product"),
                                ("completions", "Generate configuration launch files for every completion "
                                                f"of the current configuration (up to {limit})"),
                                ("all", f"Generate configuration launch files for all products (up to {limit})")):
                opts = {"uri": uri, "mode": mode, "limit": limit}
                if resolvable and can_create(ls):
                    # the products are computed when the user picks the action (codeAction/resolve)
                    actions.append(types.CodeAction(title=title, kind=types.CodeActionKind.Source,
                                                    data={"tvl-lsp.generate": opts}))
                else:
                    actions.append(types.CodeAction(
                        title=title, kind=types.CodeActionKind.Source,
                        command=types.Command(title=title, command=GENERATE, arguments=[opts])))
        if want:
            # kinds are str enums: compare their values ('quickfix'), not str() ('CodeActionKind.QuickFix')
            actions = [a for a in actions if a.kind and any(getattr(a.kind, 'value', a.kind).startswith(getattr(w, 'value', w))
                                                           for w in want)]
        return actions

    @ls.feature(types.CODE_ACTION_RESOLVE)
    async def resolve(ls, action: types.CodeAction):
        data = action.data if isinstance(action.data, dict) else {}
        opts = data.get("tvl-lsp.generate")
        if isinstance(opts, dict) and action.edit is None:
            files, out_dir, truncated = await plan(ls, opts)
            check_targets(ls, files)  # (no link, no FIFO among them: the editor writes them)
            action.edit = creation_edit(files)
        return action
