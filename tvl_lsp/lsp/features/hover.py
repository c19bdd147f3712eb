"""Hover: features (in the model, or as ``<arg>`` / ``$(arg X)`` in a launch file) with their
product counts; the root with the total; launch elements with their presence condition; inside a
diagnostic's range, its code's page from the diagnostics catalogue (``explain.py``); in a node's
C++ / Python source, the call under the cursor (:mod:`.sources`)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

from lsprotocol import types

from ..checks import is_node_source
from ..convert import from_lsp_position, to_lsp_range
from .explain import hover_notes
from ...tvl import model as M
from ...project import facts as F
from ...project.facts import MODEL_KINDS

HOVER_WAIT = 0.3  # seconds a hover waits for counts before answering without them


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_HOVER)
    async def hover(ls, params: types.HoverParams):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None:
            return None
        if doc.kind is None:
            if not is_node_source(doc.path):
                return None
            from .sources import source_hover
            md, span = await source_hover(ls, doc, from_lsp_position(doc.index, params.position, ls.encoding))
            if not md:
                return None
            rng = to_lsp_range(doc.index, span, ls.encoding) if span is not None else None
            return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=md), range=rng)
        pos = from_lsp_position(doc.index, params.position, ls.encoding)
        if doc.kind in MODEL_KINDS:
            md, span = await tvl_hover(ls, doc.path, pos)
        else:
            md, span = await launch_hover(ls, doc, pos)
        # inside a diagnostic's range: its code's page from the catalogue (lsp/features/explain.py)
        notes, note_span = hover_notes(ls, params.text_document.uri, doc.path, pos)
        if notes:
            md = f"{md}\n\n---\n\n{notes}" if md else notes
            span = span if span is not None else note_span
        if not md:
            return None
        rng = to_lsp_range(doc.index, span, ls.encoding) if span is not None else None
        return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=md), range=rng)


def _rel(ls, path: str) -> str:
    root = ls.workspace_root_for(path)
    if root:
        return os.path.relpath(path, root)
    return Path(path).name


def count_line(facts, f: M.Feature) -> str:
    return F.count_line(facts, f)


def feature_markdown(ls, f: M.Feature, facts) -> str:
    return F.feature_markdown(f, facts)


async def tvl_hover(ls, path: str, pos):
    if ls.parsed_now(path) is None:
        # a model counted before, not parsed yet here (just reopened): its features'
        # declarations answer from the facts stored for this very text
        hit = await ls.stored_feature_hover(path, pos)
        if hit is not None:
            return hit
    res = await ls.parsed(path)
    model = getattr(res, "model", None)
    if model is None:
        return None, None
    hit = F.name_at(model, path, pos)
    if hit is None or hit[0] is None:
        return None, None
    target, span = hit
    if isinstance(target, M.Feature):
        facts = await ls.model_facts(path, wait=HOVER_WAIT)
        return feature_markdown(ls, target, facts), span
    if isinstance(target, M.Attribute):
        owner = f" of `{target.owner.long_name}`" if target.owner else ""
        return f"**attribute** `{target.type} {target.name}`{owner}", span
    if isinstance(target, M.Constant):
        return f"**constant** `{target.type} {target.name}`", span
    if isinstance(target, M.TypeDecl):
        return f"**type** `{target.name}` ({target.base})", span
    if isinstance(target, M.EnumValue):
        return f"**enum value** `{target.name}`", span
    return None, None


async def paired_feature(ls, launch_path: str, name: str):
    """(model path, feature) of the paired model's feature named ``name``."""
    for mp in ls.models_for_launch(launch_path):
        res = await ls.parsed(mp)
        model = getattr(res, "model", None)
        if model is None:
            continue
        f = model.feature(name)
        if f is not None:
            return mp, f
    return None, None


def _py(path: str) -> bool:
    return path.endswith(".py")


def _arg_markdown(ls, decls) -> list[str]:
    lines = []
    for e in decls:
        a = e.attrs
        bits = []
        if "value" in a:
            bits.append(f"value `{a['value'].value}`")
        if "default" in a:
            bits.append(f"default `{a['default'].value}`")
        if not bits:
            bits.append("no value: it must be set by the includer or on the command line")
        where = f"{_rel(ls, e.path)}:{e.span.start}"
        cond = "" if str(e.condition) == "true" else f" when `{e.condition}`"
        decl = f"`DeclareLaunchArgument('{a['name'].value}')`" if _py(e.path) else f"`<arg name=\"{a['name'].value}\">`"
        lines.append(f"- {decl} at {where}: " + ", ".join(bits) + cond)
        for key in ("doc", "description"):
            if key in a:
                lines.append(f"  - {a[key].value}")
    return lines


async def arg_markdown(ls, doc, analysis, name: str, owner: Optional[str] = None) -> str:
    """The hover of the arg ``name`` of the launch file ``owner`` (default: the document's)."""
    owner = owner or doc.path
    lines = []
    mp, f = await paired_feature(ls, owner, name)
    if f is not None:
        facts = await ls.model_facts(mp, wait=HOVER_WAIT)
        lines.append(feature_markdown(ls, f, facts))
        lines.append("")
        lines.append(f"feature of {_rel(ls, mp)}")
        lines.append("")
    if owner != doc.path:
        analysis = await ls.parsed(owner)
    decls = F.arg_decls(analysis, owner, name) if analysis is not None and hasattr(analysis, "elements") else []
    decls = [e for e in decls if e.parent is None or e.parent.tag != "include"]
    word = "argument" if _py(owner) else "arg"
    if decls:
        lines.append(f"**{word}** `{name}`" + ("" if owner == doc.path else f" of {_rel(ls, owner)}"))
        lines.extend(_arg_markdown(ls, decls))
        setters = await arg_setters(ls, owner, name)
        if setters:
            lines.append("")
            lines.append("set by the files that include this one:")
            lines.extend(setters)
    elif f is None:
        lines.append(f"**{word}** `{name}`: not declared in " + ("this file" if owner == doc.path else _rel(ls, owner)))
    return "\n".join(lines)


async def arg_setters(ls, launch_path: str, name: str) -> list[str]:
    """Where ``name`` is set for ``launch_path``: the ``<arg>`` children of the workspace's
    ``<include>`` tags that include it (e.g. the configuration launch files) and the
    ``launch_arguments`` of Python includes."""
    from .navigation import includers
    out: list[str] = []
    for lf, analysis in await includers(ls, launch_path, name):
        target = os.path.normpath(launch_path)
        for inc in getattr(analysis, "includes", None) or []:
            if not inc.file or os.path.normpath(inc.file) != target:
                continue
            el = inc.element
            if "pass_all_args" in el.attrs and el.attrs["pass_all_args"].value.lower() in ("true", "1"):
                out.append(f"- {_rel(ls, lf)}:{el.span.start}: passes all its args")
        for c in F.include_args(analysis, lf, launch_path, name):
            v = c.attrs["value"].value if "value" in c.attrs else \
                c.attrs["default"].value if "default" in c.attrs else "(no value)"
            cond = "" if str(c.condition) == "true" else f" when `{c.condition}`"
            out.append(f"- {_rel(ls, lf)}:{c.span.start}: `{v}`{cond}")
    return out[:20]


async def launch_hover(ls, doc, pos):
    analysis = await ls.parsed(doc.path)
    if analysis is None or not hasattr(analysis, "elements"):
        return None, None
    hit = F.subst_at(analysis, doc.path, pos)
    if hit is not None:
        el, s = hit
        if s.kind in ("arg", "var") and s.args:
            return await arg_markdown(ls, doc, analysis, s.args[0]), s.span
        if s.kind in ("find", "find-pkg-share", "find-pkg-prefix") and s.args:
            pkg_dir = None
            try:
                pkg_dir = ls.workspace_model(doc.path).packages.get(s.args[0])
            except Exception:
                pass
            where = f"`{pkg_dir}`" if pkg_dir else "not in this workspace"
            return f"**package** `{s.args[0]}`: {where}", s.span
    el = F.element_at(analysis, doc.path, pos)
    if el is None:
        return None, None
    if el.tag == "arg" and "name" in el.attrs and el.attrs["name"].value_span.contains(pos):
        name = el.attrs["name"].value
        if el.parent is not None and el.parent.tag == "include":
            return await include_arg_markdown(ls, doc, analysis, el), el.attrs["name"].value_span
        return await arg_markdown(ls, doc, analysis, name), el.attrs["name"].value_span
    return await element_markdown(ls, doc, el), el.tag_span or el.span


async def include_arg_markdown(ls, doc, analysis, el) -> str:
    """An arg passed to an include: the included file's arg, and the value passed here."""
    name = el.attrs["name"].value
    target = F.included_file(el.parent)
    v = el.attrs["value"].value if "value" in el.attrs else "(no value)"
    cond = "" if str(el.condition) == "true" else f" when `{el.condition}`"
    here = f"passed to the included file: `{v}`{cond}"
    if target is None:
        return f"**{'argument' if _py(doc.path) else 'arg'}** `{name}` {here} (tvl-lsp does not know which file it includes)"
    body = await arg_markdown(ls, doc, analysis, name, owner=target)
    return f"{body}\n\n{here}"


def python_class(el, text: str) -> str:
    """The launch class of a Python launch file's element as the file writes it (``Node``,
    ``launch_ros.actions.Node`` -> ``Node``), from its source."""
    import re
    from ...base.text import LineIndex
    idx = LineIndex(text)
    m = re.match(r"\s*([A-Za-z_][\w.]*)\s*\(", F.text_at(idx, el.span)[:200])
    from ...analysis.crosscheck import PYTHON_CLASSES
    return m.group(1).rsplit(".", 1)[-1] if m else PYTHON_CLASSES.get(el.tag, el.tag)


async def element_markdown(ls, doc, el) -> str:
    name = el.attrs.get("name").value if "name" in el.attrs else None
    tag = python_class(el, doc.text) if _py(el.path) and el.path == doc.path else f"<{el.tag}>"
    head = f"**{tag}**" + (f" `{name}`" if name else "")
    cond = el.condition
    text = str(cond)
    lines = [head, ""]
    if text == "true":
        lines.append("loaded in every product (no condition)")
    elif text == "false":
        lines.append("loaded in **no** product")
    else:
        lines.append(f"loaded when `{text}`")
    models = ls.models_for_launch(doc.path)
    if models and text not in ("false",):
        mp = models[0]
        facts = await ls.model_facts(mp, wait=HOVER_WAIT)
        total = facts.total if facts else None
        n = total if text == "true" else await ls.count_under(mp, cond, wait=HOVER_WAIT)
        if n is not None and total is not None:
            lines.append("")
            lines.append(f"loaded in **{n} of {total} products** ({F.percent(n, total)}) of {_rel(ls, mp)}")
        else:
            lines.append("")
            lines.append("products: counting… (hover again in a moment)")
    if el.tag == "node" and el.path == doc.path and text != "false":
        from .graph import node_markdown
        lines += await node_markdown(ls, doc, el)
    return "\n".join(lines)
