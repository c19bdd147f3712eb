"""Code actions, answered at once (the light bulb never waits for a check).

Every ``Diagnostic.fixes`` becomes a quick fix (add the missing ``<arg name="X"/>``, rename an
unknown name to a close one, ``and`` → ``&&``, ``constant`` → ``const``, …), "add all missing
args" at once, and the generation of configuration launch files (a source action whose edit is
computed when it is picked: ``codeAction/resolve``).

How a request is answered -- the mechanism every code action plugs into:

- the diagnostics come from what is known *now* (:meth:`KnownDiagnostics.known_diagnostics`,
  ``lsp/known.py``): the quick pass of the current text, plus the findings of the last full
  check moved through the edits made since (those an edit touched, and fixes whose edits it
  touched, are left out).  A request never waits for a pending check; when the check lands,
  its diagnostics are published and clients ask again (VS Code whenever the diagnostics or the
  cursor change, Neovim when the user asks);
- each *provider* (:func:`provider`) is called in order with an :class:`ActionRequest` and
  returns code actions; providers must not wait for anything (no worker, no check);
- work that needs a worker process (products, a SAT question...) goes into a *resolver*
  (:func:`resolver`): the provider returns the action without its edit and with
  ``data={"tvl-lsp.resolve": NAME, "args": {...}}`` (JSON), and ``codeAction/resolve`` awaits
  ``RESOLVERS[NAME](ls, args)`` for the ``WorkspaceEdit`` when the user picks it.  Clients
  that cannot resolve edits get a command instead (see :func:`_generation`).

A new kind of quick fix (model anomalies, Python launch files...) is either a ``Fix`` on the
core's diagnostic (nothing to do here) or a provider in its own feature module, registered at
import (``provider(fn)``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Awaitable, Callable, Iterable, Optional

from lsprotocol import types

from ...base.diagnostics import Diagnostic, Fix, TextEdit
from ...base.text import Span
from ..convert import fix_to_edit, from_lsp_range, spans_overlap, to_lsp_diagnostic
from ...project.facts import MODEL_KINDS
from . import quickfix
from .commands import GENERATE, can_create, check_targets, creation_edit, plan


@dataclass
class ActionRequest:
    """One ``textDocument/codeAction`` request, as providers see it."""
    uri: str
    doc: Any                      # lsp.documents.Document (its current text)
    span: Span                    # the requested range, in the core's positions
    known: list[Diagnostic]       # the document's diagnostics known now (current positions)
    only: Optional[list]          # the kinds the client wants (None: all)
    invoked: bool                 # asked by the user (not the light bulb's automatic request)

    def at_range(self) -> list[Diagnostic]:
        """The known diagnostics of this document that touch the requested range."""
        return [d for d in self.known if (not d.path or d.path == self.doc.path) and spans_overlap(d.span, self.span)]


Provider = Callable[[Any, ActionRequest], Iterable[types.CodeAction]]
Resolver = Callable[[Any, dict], Awaitable[Optional[types.WorkspaceEdit]]]

PROVIDERS: list[Provider] = []
RESOLVERS: dict[str, Resolver] = {}
RESOLVE_KEY = "tvl-lsp.resolve"


def provider(fn: Provider) -> Provider:
    """Register a code action provider (called for every request, in registration order)."""
    PROVIDERS.append(fn)
    return fn


def resolver(name: str):
    """Register the resolver of the actions whose ``data`` names ``name`` (see the module
    docstring)."""
    def deco(fn: Resolver) -> Resolver:
        RESOLVERS[name] = fn
        return fn
    return deco


def lazy_action(title: str, kind, name: str, args: dict, **more) -> types.CodeAction:
    """A code action whose edit ``RESOLVERS[name](ls, args)`` computes when it is picked."""
    return types.CodeAction(title=title, kind=kind, data={RESOLVE_KEY: name, "args": args}, **more)


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


# ------------------------------------------------------------------ the built-in providers

@provider
def _diagnostic_fixes(ls, req: ActionRequest) -> list[types.CodeAction]:
    """The fixes of the diagnostics at the range."""
    out = []
    enc = ls.encoding
    for d in req.at_range():
        if not d.fixes:
            continue
        sev = ls.settings.severity(d)
        if sev is None:
            continue
        ld = to_lsp_diagnostic(d, req.doc.index, enc, ls.index_of, sev)
        for fx in d.fixes:
            out.append(types.CodeAction(
                title=fx.title, kind=types.CodeActionKind.QuickFix, diagnostics=[ld],
                is_preferred=fx.preferred or None, edit=fix_to_edit(fx, ls.index_of, enc)))
    return out


@provider
def _all_missing_args(ls, req: ActionRequest) -> list[types.CodeAction]:
    """"Add all N missing <arg> tags", at any of them."""
    missing = [d for d in req.known if d.code == "missing-arg" and d.fixes and (not d.path or d.path == req.doc.path)
               and ls.settings.severity(d) is not None]
    if len(missing) < 2 or not any(spans_overlap(d.span, req.span) for d in missing):
        return []
    enc = ls.encoding
    what = "DeclareLaunchArgument actions" if req.doc.path.endswith(".py") else "<arg> tags"
    fx = merge_fixes(f"Add all {len(missing)} missing {what}", [f for d in missing for f in d.fixes[:1]])
    diags = [to_lsp_diagnostic(d, req.doc.index, enc, ls.index_of) for d in missing]
    return [types.CodeAction(title=fx.title, kind=types.CodeActionKind.QuickFix, diagnostics=diags,
                             edit=fix_to_edit(fx, ls.index_of, enc))]


@provider
def _generation(ls, req: ActionRequest) -> list[types.CodeAction]:
    """Generate configuration launch files (the products are computed when it is picked)."""
    if req.only and not any(_kind(types.CodeActionKind.Source).startswith(_kind(w)) for w in req.only):
        return []  # (the pairing look-up is skipped when only quick fixes are wanted)
    doc = req.doc
    paired = bool(ls.launches_for_model(doc.path)) if doc.kind in MODEL_KINDS else bool(ls.models_for_launch(doc.path))
    if not paired:
        return []
    out = []
    limit = ls.settings.generate_limit
    resolvable = "edit" in (ls.cap("text_document.code_action.resolve_support.properties", []) or [])
    for mode, title in (("one", "Generate a configuration launch file for one product"),
                        ("completions", "Generate configuration launch files for every completion "
                                        f"of the current configuration (up to {limit})"),
                        ("all", f"Generate configuration launch files for all products (up to {limit})")):
        opts = {"uri": req.uri, "mode": mode, "limit": limit}
        if resolvable and can_create(ls):
            out.append(lazy_action(title, types.CodeActionKind.Source, "generate", opts))
        else:
            out.append(types.CodeAction(title=title, kind=types.CodeActionKind.Source,
                                        command=types.Command(title=title, command=GENERATE, arguments=[opts])))
    return out


@resolver("generate")
async def _resolve_generation(ls, opts: dict) -> Optional[types.WorkspaceEdit]:
    files, out_dir, truncated = await plan(ls, opts)
    check_targets(ls, files)  # (no link, no FIFO among them: the editor writes them)
    return creation_edit(files)


def _kind(k) -> str:
    # kinds are str enums: compare their values ('quickfix'), not str() ('CodeActionKind.QuickFix')
    return str(getattr(k, "value", k))


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
        want = params.context.only
        req = ActionRequest(uri, doc, from_lsp_range(doc.index, params.range, ls.encoding),
                            ls.known_diagnostics(uri), list(want) if want else None,
                            params.context.trigger_kind != types.CodeActionTriggerKind.Automatic)
        actions: list[types.CodeAction] = []
        for p in PROVIDERS:
            try:
                actions.extend(p(ls, req))
            except Exception:  # one provider's bug must not take the others' actions away
                import logging
                logging.getLogger("tvl_lsp.server").exception("code action provider %s failed",
                                                              getattr(p, "__name__", p))
        if not want or any(_kind(types.CodeActionKind.QuickFix).startswith(_kind(w)) for w in want):
            # model anomalies: fixes checked in a worker (quickfix.py), prepared after the check;
            # the automatic light bulb takes those ready now, a request the user makes waits a
            # bounded time for the others
            at = req.at_range()
            try:
                actions += (await quickfix.actions(ls, uri, doc, at)) if req.invoked \
                    else quickfix.cached_actions(ls, uri, doc, at)
            except Exception:
                import logging
                logging.getLogger("tvl_lsp.server").exception("model quick fixes failed")
        if want:
            actions = [a for a in actions if a.kind and any(_kind(a.kind).startswith(_kind(w)) for w in want)]
        return actions

    @ls.feature(types.CODE_ACTION_RESOLVE)
    async def resolve(ls, action: types.CodeAction):
        data = action.data if isinstance(action.data, dict) else {}
        name, args = data.get(RESOLVE_KEY), data.get("args")
        if name is None and isinstance(data.get("tvl-lsp.generate"), dict):  # (before #28)
            name, args = "generate", data["tvl-lsp.generate"]
        fn = RESOLVERS.get(name) if isinstance(name, str) else None
        if fn is not None and isinstance(args, dict) and action.edit is None:
            action.edit = await fn(ls, args)
        return action
