"""Definition, declaration, references and rename across models and their paired launch files."""

from __future__ import annotations

import os
import re
from typing import Optional

from lsprotocol import types

from pygls.exceptions import JsonRpcContentModified, JsonRpcInvalidParams

from ..convert import from_lsp_position, path_to_uri, to_lsp_range
from ..documents import PARSE_WAIT
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
    owner = doc.path  # the launch file that declares the arg
    hit = F.subst_at(analysis, doc.path, pos)
    if hit is not None and hit[1].kind in ("arg", "var") and hit[1].args:
        name = hit[1].args[0]
        span = F.arg_name_span(hit[1], doc.index) or hit[1].span
    else:
        el = F.element_at(analysis, doc.path, pos)
        if el is not None and el.tag == "arg" and "name" in el.attrs and el.attrs["name"].value_span.contains(pos):
            name, span = el.attrs["name"].value, el.attrs["name"].value_span
            if el.parent is not None and el.parent.tag == "include":
                # an arg passed to an include (an <arg> of <include>, a key of launch_arguments):
                # the included file's
                owner = F.included_file(el.parent)
                if owner is None:
                    return None
    if name is None:
        return None
    sym = Symbol(name, span, launch_path=owner)
    for mp in ls.models_for_launch(owner):
        res = await ls.parsed(mp)
        model = getattr(res, "model", None)
        f = model.feature(name) if model is not None else None
        if f is not None:
            sym.model_path, sym.target = mp, f
            break
    return sym


def _named(index: LineIndex, span: Optional[Span], name: str) -> bool:
    """Is the text at ``span`` the name itself (a range a rename may replace)?"""
    return span is not None and F.text_at(index, span) == name


async def launch_locations(ls, launch_path: str, name: str, decls: bool = True, uses: bool = True,
                           wait: Optional[float] = PARSE_WAIT):
    """(path, span) of ``<arg name=name>`` / ``DeclareLaunchArgument('name')`` declarations and
    ``$(arg name)`` / ``$(var name)`` / ``LaunchConfiguration('name')`` uses in a launch file (not
    the args passed to includes: those belong to the included file, see :func:`include_sites`).
    Only ranges whose text is the name itself."""
    analysis = await ls.parsed(launch_path, wait=wait)
    if analysis is None or not hasattr(analysis, "elements"):
        return []
    text = ls.read_file(launch_path) or ""
    index = LineIndex(text)
    out = []
    if decls:
        for e in F.arg_decls(analysis, launch_path, name):
            if e.parent is not None and e.parent.tag == "include":
                continue
            if _named(index, e.attrs["name"].value_span, name):
                out.append((launch_path, e.attrs["name"].value_span))
    if uses:
        for e, s in F.arg_uses(analysis, launch_path, name):
            sp = F.arg_name_span(s, index)
            if _named(index, sp, name):
                out.append((launch_path, sp))
    return out


MAX_INCLUDERS = 40  # launch files parsed to find who includes a file


async def includers(ls, target: str, name: Optional[str] = None, wait: Optional[float] = PARSE_WAIT):
    """(launch file, its analysis) for the workspace's launch files that include ``target``
    (and mention ``name``, when given), at most MAX_INCLUDERS of them parsed."""
    try:
        ws = ls.workspace_model(target)
    except Exception:
        return []
    base = os.path.basename(target)
    norm = os.path.normpath(target)
    out = []
    n = 0
    for lf in ws.files.launches:
        if os.path.normpath(lf) == norm:
            continue
        text = ls.read_file(lf) or ""
        if base not in text or (name is not None and name not in text):
            continue
        n += 1
        if n > MAX_INCLUDERS:
            break
        analysis = await ls.parsed(lf, wait=wait)
        if analysis is not None and hasattr(analysis, "elements"):
            out.append((lf, analysis))
    return out


async def include_sites(ls, target: str, name: str, wait: Optional[float] = PARSE_WAIT):
    """(path, span) of the args named ``name`` that the workspace's launch files pass to
    ``target`` (``<arg name>`` of their ``<include>``, keys of ``launch_arguments``)."""
    out = []
    for lf, analysis in await includers(ls, target, name, wait):
        index = ls.index_of(lf) or LineIndex("")
        for e in F.include_args(analysis, lf, target, name):
            sp = e.attrs["name"].value_span
            if _named(index, sp, name):
                out.append((lf, sp))
    return out


async def all_locations(ls, sym: Symbol, include_decl: bool = True,
                        wait: Optional[float] = PARSE_WAIT) -> list[tuple[str, Span]]:
    out: list[tuple[str, Span]] = []
    if sym.model_path and sym.target is not None:
        res = await ls.parsed(sym.model_path, wait=wait)
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
            out.extend(await launch_locations(ls, lp, sym.name, wait=wait))
        for lp in launches:
            out.extend(await include_sites(ls, lp, sym.name, wait=wait))
    return list(dict.fromkeys(out))  # without repeats, in order


def _loc(ls, path: str, span: Span) -> types.Location:
    idx = ls.index_of(path) or LineIndex("")
    return types.Location(uri=path_to_uri(path), range=to_lsp_range(idx, span, ls.encoding))


def register(ls) -> None:
    async def _sym(ls, params, current: bool = False):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind is None:
            return None, None
        if current:  # (a rename: the parse of the current text, however long it takes)
            await ls.parsed(doc.path, wait=None)
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
        doc, sym = await _sym(ls, params, current=True)
        if sym is None or sym.span is None:
            return None
        if sym.target is not None and not isinstance(sym.target, (M.Feature, M.Attribute, M.Constant, M.TypeDecl)):
            return None
        return types.PrepareRenamePlaceholder(range=to_lsp_range(doc.index, sym.span, ls.encoding),
                                              placeholder=sym.name)

    @ls.feature(types.TEXT_DOCUMENT_RENAME)
    async def rename(ls, params: types.RenameParams):
        doc, sym = await _sym(ls, params, current=True)
        if sym is None:
            raise JsonRpcInvalidParams("nothing to rename here")
        new = params.new_name.strip()
        if new == sym.name:
            return types.WorkspaceEdit(changes={})
        await check_new_name(ls, sym, new)
        # the edits are computed on the current text of every file (never on an older parse)
        # and carry the version of each open document: a client applies them to that version only
        versions = {u: d.version for u, d in ls.docs.items()}
        locations = await all_locations(ls, sym, wait=None)
        by_uri: dict[str, list[types.TextEdit]] = {}
        for p, s in locations:
            idx = ls.index_of(p) or LineIndex("")
            by_uri.setdefault(path_to_uri(p), []).append(
                types.TextEdit(range=to_lsp_range(idx, s, ls.encoding), new_text=new))
        for uri in by_uri:
            d = ls.docs.get(uri)
            if d is not None and versions.get(uri) != d.version:
                raise JsonRpcContentModified("the document changed during the rename: try again")
        _warn_leftovers(ls, sym.name, new, locations)
        if ls.cap("workspace.workspace_edit.document_changes", False):
            return types.WorkspaceEdit(document_changes=[
                types.TextDocumentEdit(text_document=types.OptionalVersionedTextDocumentIdentifier(
                    uri=uri, version=ls.docs[uri].version if uri in ls.docs else None), edits=edits)
                for uri, edits in by_uri.items()])
        return types.WorkspaceEdit(changes=by_uri)


def _warn_leftovers(ls, old: str, new: str, locations) -> None:
    """Say which strings ``'old'`` of the Python launch files the rename touches it leaves as they
    are: tvl-lsp cannot tell whether they name the argument (a list the file declares its
    arguments from) or something else (a node of that name)."""
    from ...launch.ros2py.editing import name_literals
    done = set(locations)
    notes = []
    for p in dict.fromkeys(p for p, _ in locations):
        if not p.endswith(".py"):
            continue
        left = [s for s in name_literals(ls.read_file(p) or "", p, old) if (p, s) not in done]
        if left:
            lines = ", ".join(str(s.start.line + 1) for s in left[:5]) + (", ..." if len(left) > 5 else "")
            notes.append(f"{os.path.basename(p)} (line {lines})")
    if notes:
        ls.warn(f"Renamed `{old}` to `{new}`; strings '{old}' left as they are in {'; '.join(notes)}: "
                "tvl-lsp cannot tell whether they name this argument")


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
            if await launch_locations(ls, lp, new, uses=False, wait=None):
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
        if sym.launch_path and await launch_locations(ls, sym.launch_path, new, uses=False, wait=None):
            raise JsonRpcInvalidParams(f"this file already declares an arg named `{new}`")
