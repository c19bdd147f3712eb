"""Definition, declaration, references and rename across models and their paired launch files."""

from __future__ import annotations

import re
from typing import Optional

from lsprotocol import types

from pygls.exceptions import JsonRpcInvalidParams

from ..convert import from_lsp_position, path_to_uri, to_lsp_range
from ...base.text import LineIndex, Span
from ...tvl import model as M
from ...project import facts as F
from ...project.facts import MODEL_KINDS

FEATURE_NAME = re.compile(r"^[A-Z][A-Za-z0-9_]*$")
ARG_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_/\-.]*$")


def _keywords() -> set[str]:
    try:
        from ...tvl.lexer import KEYWORDS
        return set(KEYWORDS)
    except ImportError:
        return set()


class Symbol:
    """What the cursor is on: a model element, a launch arg, or both (a feature arg)."""

    def __init__(self, name: str, span: Span, model_path: Optional[str] = None, target=None,
                 launch_path: Optional[str] = None):
        self.name = name
        self.span = span
        self.model_path = model_path
        self.target = target
        self.launch_path = launch_path

    @property
    def is_feature(self) -> bool:
        return isinstance(self.target, M.Feature)


async def symbol_at(ls, doc, pos) -> Optional[Symbol]:
    if doc.kind in MODEL_KINDS:
        res = await ls.parsed(doc.path)
        model = getattr(res, "model", None)
        if model is None:
            return None
        hit = F.name_at(model, doc.path, pos)
        if hit is None or hit[0] is None:
            return None
        target, span = hit
        name = getattr(target, "name", None)
        if name is None:
            return None
        return Symbol(name, span or getattr(target, "name_span", None), doc.path, target)
    analysis = await ls.parsed(doc.path)
    if analysis is None or not hasattr(analysis, "elements"):
        return None
    name = span = None
    hit = F.subst_at(analysis, doc.path, pos)
    if hit is not None and hit[1].kind in ("arg", "var") and hit[1].args:
        name = hit[1].args[0]
        span = F.arg_name_span(hit[1], doc.index) or hit[1].span
    else:
        el = F.element_at(analysis, doc.path, pos)
        if el is not None and el.tag == "arg" and "name" in el.attrs and el.attrs["name"].value_span.contains(pos):
            name, span = el.attrs["name"].value, el.attrs["name"].value_span
    if name is None:
        return None
    sym = Symbol(name, span, launch_path=doc.path)
    for mp in ls.models_for_launch(doc.path):
        res = await ls.parsed(mp)
        model = getattr(res, "model", None)
        f = model.feature(name) if model is not None else None
        if f is not None:
            sym.model_path, sym.target = mp, f
            break
    return sym


async def launch_locations(ls, launch_path: str, name: str, decls: bool = True, uses: bool = True):
    """(path, span) of ``<arg name=name>`` declarations and ``$(arg name)`` uses in a launch
    file (not the args passed to includes: those belong to the included file)."""
    analysis = await ls.parsed(launch_path)
    if analysis is None or not hasattr(analysis, "elements"):
        return []
    text = ls.read_file(launch_path) or ""
    index = LineIndex(text)
    out = []
    if decls:
        for e in F.arg_decls(analysis, launch_path, name):
            if e.parent is not None and e.parent.tag == "include":
                continue
            out.append((launch_path, e.attrs["name"].value_span))
    if uses:
        for e, s in F.arg_uses(analysis, launch_path, name):
            sp = F.arg_name_span(s, index)
            if sp is not None:
                out.append((launch_path, sp))
    return out


async def all_locations(ls, sym: Symbol, include_decl: bool = True) -> list[tuple[str, Span]]:
    out: list[tuple[str, Span]] = []
    if sym.model_path and sym.target is not None:
        res = await ls.parsed(sym.model_path)
        model = getattr(res, "model", None)
        if model is not None:
            out.extend(F.references(model, sym.target))
    launches = []
    if sym.is_feature:
        launches = ls.launches_for_model(sym.model_path)
    if sym.launch_path and sym.launch_path not in launches:
        launches.append(sym.launch_path)
    if sym.is_feature or sym.launch_path:
        for lp in launches:
            out.extend(await launch_locations(ls, lp, sym.name))
    return list(dict.fromkeys(out))  # without repeats, in order


def _loc(ls, path: str, span: Span) -> types.Location:
    idx = ls.index_of(path) or LineIndex("")
    return types.Location(uri=path_to_uri(path), range=to_lsp_range(idx, span, ls.encoding))


def register(ls) -> None:
    async def _sym(ls, params):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind is None:
            return None, None
        pos = from_lsp_position(doc.index, params.position, ls.encoding)
        return doc, await symbol_at(ls, doc, pos)

    @ls.feature(types.TEXT_DOCUMENT_DEFINITION)
    async def definition(ls, params: types.DefinitionParams):
        doc, sym = await _sym(ls, params)
        if sym is None:
            return None
        if sym.target is not None:
            t = sym.target
            if isinstance(t, M.Feature):
                p, s = (t.decl_spans[0] if t.decl_spans else (t.path, t.name_span))
                return [_loc(ls, p, s)]
            if hasattr(t, "name_span"):
                return [_loc(ls, t.path, t.name_span)]
        if sym.launch_path:
            locs = await launch_locations(ls, sym.launch_path, sym.name, uses=False)
            return [_loc(ls, p, s) for p, s in locs] or None
        return None

    @ls.feature(types.TEXT_DOCUMENT_DECLARATION)
    async def declaration(ls, params: types.DeclarationParams):
        doc, sym = await _sym(ls, params)
        if sym is None:
            return None
        if sym.launch_path:
            locs = await launch_locations(ls, sym.launch_path, sym.name, uses=False)
            if locs:
                return [_loc(ls, p, s) for p, s in locs]
        if sym.target is not None and hasattr(sym.target, "name_span"):
            t = sym.target
            spans = t.decl_spans if isinstance(t, M.Feature) and t.decl_spans else [(t.path, t.name_span)]
            return [_loc(ls, p, s) for p, s in spans]
        return None

    @ls.feature(types.TEXT_DOCUMENT_REFERENCES)
    async def references(ls, params: types.ReferenceParams):
        doc, sym = await _sym(ls, params)
        if sym is None:
            return None
        return [_loc(ls, p, s) for p, s in await all_locations(ls, sym)]

    @ls.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    async def prepare_rename(ls, params: types.PrepareRenameParams):
        doc, sym = await _sym(ls, params)
        if sym is None or sym.span is None:
            return None
        if sym.target is not None and not isinstance(sym.target, (M.Feature, M.Attribute, M.Constant, M.TypeDecl)):
            return None
        return types.PrepareRenamePlaceholder(range=to_lsp_range(doc.index, sym.span, ls.encoding),
                                              placeholder=sym.name)

    @ls.feature(types.TEXT_DOCUMENT_RENAME)
    async def rename(ls, params: types.RenameParams):
        doc, sym = await _sym(ls, params)
        if sym is None:
            raise JsonRpcInvalidParams("nothing to rename here")
        new = params.new_name.strip()
        if new == sym.name:
            return types.WorkspaceEdit(changes={})
        await check_new_name(ls, sym, new)
        changes: dict[str, list[types.TextEdit]] = {}
        for p, s in await all_locations(ls, sym):
            idx = ls.index_of(p) or LineIndex("")
            changes.setdefault(path_to_uri(p), []).append(
                types.TextEdit(range=to_lsp_range(idx, s, ls.encoding), new_text=new))
        return types.WorkspaceEdit(changes=changes)


async def check_new_name(ls, sym: Symbol, new: str) -> None:
    if new in _keywords():
        raise JsonRpcInvalidParams(f"`{new}` is a TVL keyword")
    if sym.is_feature:
        if not FEATURE_NAME.match(new):
            raise JsonRpcInvalidParams(
                f"`{new}` is not a valid feature name: it must start with an upper-case letter "
                "and contain only letters, digits and `_`")
        res = await ls.parsed(sym.model_path)
        model = getattr(res, "model", None)
        if model is not None and model.features_named(new):
            raise JsonRpcInvalidParams(f"the model already has a feature named `{new}`")
        for lp in ls.launches_for_model(sym.model_path):
            if await launch_locations(ls, lp, new, uses=False):
                raise JsonRpcInvalidParams(f"{lp} already declares an arg named `{new}`")
    elif isinstance(sym.target, (M.Attribute, M.Constant, M.TypeDecl)):
        if not re.match(r"^[a-z][A-Za-z0-9_]*$", new):
            raise JsonRpcInvalidParams(f"`{new}` is not a valid name: it must start with a lower-case letter")
        owner = getattr(sym.target, "owner", None)
        if owner is not None and any(a.name == new for a in owner.attributes):
            raise JsonRpcInvalidParams(f"`{owner.name}` already has an attribute named `{new}`")
    else:
        if not ARG_NAME.match(new):
            raise JsonRpcInvalidParams(f"`{new}` is not a valid arg name")
        if sym.launch_path and await launch_locations(ls, sym.launch_path, new, uses=False):
            raise JsonRpcInvalidParams(f"this file already declares an arg named `{new}`")
