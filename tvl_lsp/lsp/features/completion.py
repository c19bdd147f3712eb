"""Completion: TVL keywords, feature and attribute names; launch tags and attributes,
``$(arg `` → args in scope and features, ``$(find `` → workspace packages.  ROS 2 files
(XML and YAML): their tags / keys and attributes, ``$(var `` and ``$(find-pkg-share ``.  Python
launch files: argument names in ``LaunchConfiguration('…')`` (and ``context.launch_configurations``),
the paired model's features without an argument in ``DeclareLaunchArgument('…')``, and the
included file's arguments as keys of an include's ``launch_arguments``."""

from __future__ import annotations

import re

from lsprotocol import types

from ..convert import from_lsp_position, to_lsp_range
from ...base.text import Pos, Span

TVL_KEYWORDS = [
    "root", "group", "oneOf", "someOf", "allOf", "opt", "shared", "bool", "int", "real", "enum",
    "struct", "const", "ifIn:", "ifOut:", "is", "in", "data", "include", "true", "false",
    "requires", "excludes", "children", "selectedChildren", "parent", "this",
    "sum", "mul", "min", "max", "avg", "count", "and", "or", "xor", "abs",
]

# roslaunch 1 XML: tag -> attributes (required first)
LAUNCH_TAGS: dict[str, list[str]] = {
    "launch": ["deprecated"],
    "node": ["pkg", "type", "name", "args", "machine", "respawn", "respawn_delay", "required", "ns",
             "clear_params", "output", "cwd", "launch-prefix", "if", "unless"],
    "test": ["pkg", "type", "test-name", "name", "args", "ns", "clear_params", "cwd", "launch-prefix",
             "retry", "time-limit", "if", "unless"],
    "machine": ["name", "address", "env-loader", "default", "user", "password", "timeout", "if", "unless"],
    "include": ["file", "ns", "clear_params", "pass_all_args", "if", "unless"],
    "remap": ["from", "to", "if", "unless"],
    "env": ["name", "value", "if", "unless"],
    "param": ["name", "value", "type", "textfile", "binfile", "command", "if", "unless"],
    "rosparam": ["command", "file", "param", "ns", "subst_value", "if", "unless"],
    "group": ["ns", "clear_params", "if", "unless"],
    "arg": ["name", "default", "value", "doc", "if", "unless"],
}
CHILD_TAGS = {
    "launch": ["node", "param", "rosparam", "include", "group", "arg", "env", "machine", "remap", "test"],
    "group": ["node", "param", "rosparam", "include", "group", "arg", "env", "machine", "remap", "test"],
    "node": ["remap", "param", "rosparam", "env"],
    "test": ["remap", "param", "rosparam", "env"],
    "include": ["arg", "env"],
}

_SUBST_ARG = re.compile(r"\$\(\s*(?:arg|var)\s+([\w/\-.]*)$")
_SUBST_FIND = re.compile(r"\$\(\s*(?:find|find-pkg-share|find-pkg-prefix)\s+([\w\-.]*)$")
_SUBST_CMD = re.compile(r"\$\(\s*([\w\-]*)$")
_YAML_ITEM = re.compile(r"^(\s*)-\s*([\w\-]*)$")
_YAML_KEY = re.compile(r"^(\s*)(?:-\s*)?([\w\-]*)$")
_IN_TAG = re.compile(r"<([\w\-]+)(\s+[^<>]*)?$", re.S)
_OPEN_TAG = re.compile(r"<([\w\-]*)$")


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_COMPLETION,
                types.CompletionOptions(trigger_characters=["<", " ", "(", "."]))
    async def completion(ls, params: types.CompletionParams):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind is None:
            return None
        pos = from_lsp_position(doc.index, params.position, ls.encoding)
        if doc.kind == "tvl":
            items = await tvl_items(ls, doc, pos)
        elif doc.path.endswith(".py"):
            items = await python_items(ls, doc, pos)
        else:
            items = await launch_items(ls, doc, pos)
        return types.CompletionList(is_incomplete=False, items=items)


def _item(label, kind, detail=None, sort=None, insert=None):
    return types.CompletionItem(label=label, kind=kind, detail=detail, sort_text=sort, insert_text=insert)


async def tvl_items(ls, doc, pos: Pos):
    line = doc.index.line_text(pos.line)[: pos.col]
    items = []
    res = ls.parsed_now(doc.path) or await ls.parsed(doc.path)
    model = getattr(res, "model", None)
    m = re.search(r"([A-Za-z_][\w]*)\.([\w]*)$", line)
    if m and model is not None:
        f = model.feature(m.group(1))
        if f is not None:
            for a in f.attributes:
                items.append(_item(a.name, types.CompletionItemKind.Field, f"{a.type} attribute of {f.name}"))
            for c in f.children:
                items.append(_item(c.name, types.CompletionItemKind.Class, f"child of {f.name}"))
            return items
    for kw in TVL_KEYWORDS:
        items.append(_item(kw, types.CompletionItemKind.Keyword, sort="2" + kw))
    if model is not None:
        seen = set()
        for f in model.features:
            if f.name in seen:
                continue
            seen.add(f.name)
            items.append(_item(f.name, types.CompletionItemKind.Class, "feature " + f.long_name, "1" + f.name))
            for a in f.attributes:
                items.append(_item(a.name, types.CompletionItemKind.Field,
                                   f"{a.type} attribute of {f.name}", "1" + a.name))
        for c in model.constants:
            items.append(_item(c.name, types.CompletionItemKind.Constant, f"const {c.type}", "1" + c.name))
        for t in model.types:
            items.append(_item(t.name, types.CompletionItemKind.TypeParameter, f"type ({t.base})", "1" + t.name))
    return items


def _enclosing_tag(text_before: str) -> str:
    """The innermost open element before the cursor (a cheap scan; good enough to rank tags)."""
    stack = []
    for m in re.finditer(r"<(/?)([\w\-]+)[^<>]*?(/?)>", text_before):
        if m.group(1):
            if stack and stack[-1] == m.group(2):
                stack.pop()
        elif not m.group(3):
            stack.append(m.group(2))
    return stack[-1] if stack else ""


def _ros2(doc) -> bool:
    from ...launch import dialect_of
    try:
        return dialect_of(doc.path, doc.text).ros2
    except Exception:
        return False


def _yaml_entity_above(doc, pos: Pos, indent: int) -> str:
    """The entity whose keys a YAML line at ``indent`` completes: the nearest ``- tag:`` above
    with a smaller indentation (or ``tag:`` of a mapping)."""
    for ln in range(pos.line - 1, -1, -1):
        t = doc.index.line_text(ln)
        m = re.match(r"^(\s*)(-\s*)?([\w\-]+)\s*:", t)
        if not m or not t.strip():
            continue
        ind = len(m.group(1)) + (len(m.group(2)) if m.group(2) else 0)
        if ind < indent:
            return m.group(3)
    return ""


def _yaml_items(doc, pos: Pos, line: str):
    from ...launch.ros2.schema import CHILD_TAGS as R2_CHILD, TAG_ATTRS as R2_ATTRS
    m = _YAML_ITEM.match(line)
    if m:
        parent = _yaml_entity_above(doc, pos, len(m.group(1)))
        parent = "launch" if parent in ("children", "") else parent
        tags = R2_CHILD.get(parent, R2_CHILD["launch"])
        return [_item(t, types.CompletionItemKind.Keyword, f"{t}:", f"{i:02d}", insert=f"{t}:")
                for i, t in enumerate(tags)]
    m = _YAML_KEY.match(line)
    if m:
        tag = _yaml_entity_above(doc, pos, len(line) - len(line.lstrip(" -")) if line.strip() else len(line))
        attrs = R2_ATTRS.get(tag, [])
        kids = [c for c in R2_CHILD.get(tag, []) if c not in ("keep",) or tag == "group"]
        out = [_item(a, types.CompletionItemKind.Property, f"attribute of {tag}", f"0{i:02d}", insert=f"{a}: ")
               for i, a in enumerate(attrs)]
        if tag == "group":
            kids = ["children", "keep"]
        out += [_item(k, types.CompletionItemKind.Module, f"list of {k} in {tag}", f"1{i:02d}", insert=f"{k}:")
                for i, k in enumerate(kids) if k in ("remap", "param", "env", "arg", "choice", "keep", "children",
                                                     "composable_node", "extra_arg")]
        return out
    return []


async def launch_items(ls, doc, pos: Pos):
    offset = doc.index.offset(pos)
    before = doc.text[max(0, offset - 4000): offset]
    line = doc.index.line_text(pos.line)[: pos.col]
    ros2 = _ros2(doc)
    m = _SUBST_ARG.search(line)
    if m:
        return await arg_items(ls, doc)
    m = _SUBST_FIND.search(line)
    if m:
        try:
            pkgs = ls.workspace_model(doc.path).packages
        except Exception:
            pkgs = {}
        return [_item(name, types.CompletionItemKind.Module, folder) for name, folder in sorted(pkgs.items())]
    m = _SUBST_CMD.search(line)
    if m:
        if ros2:
            from ...launch.ros2.schema import SUBSTITUTIONS
            return [_item(c, types.CompletionItemKind.Function, "substitution") for c in SUBSTITUTIONS]
        return [_item(c, types.CompletionItemKind.Function, "substitution")
                for c in ("arg", "find", "env", "optenv", "anon", "dirname", "eval")]
    if doc.path.endswith((".yaml", ".yml")):
        return _yaml_items(doc, pos, line)
    tag_attrs, child_tags = LAUNCH_TAGS, CHILD_TAGS
    if ros2:
        from ...launch.ros2.schema import CHILD_TAGS as child_tags, TAG_ATTRS as tag_attrs
    m = _OPEN_TAG.search(line)
    if m:
        parent = _enclosing_tag(before[: len(before) - len(m.group(0))])
        tags = child_tags.get(parent, list(tag_attrs))
        return [_item(t, types.CompletionItemKind.Keyword, f"<{t}>", f"{i:02d}") for i, t in enumerate(tags)]
    m = _IN_TAG.search(before)
    if m and not re.search(r"=\s*\"[^\"]*$", before[m.start():]) and not re.search(r"=\s*'[^']*$", before[m.start():]):
        tag = m.group(1)
        present = set(re.findall(r"([\w\-]+)\s*=", m.group(2) or ""))
        attrs = [a for a in tag_attrs.get(tag, []) if a not in present]
        return [_item(a, types.CompletionItemKind.Property, f"attribute of <{tag}>", f"{i:02d}")
                for i, a in enumerate(attrs)]
    return []


async def arg_items(ls, doc):
    items = []
    seen = set()
    analysis = ls.parsed_now(doc.path) or await ls.parsed(doc.path)
    if analysis is not None and hasattr(analysis, "elements"):
        for e in analysis.elements:
            if e.path == doc.path and e.tag in ("arg", "let") and "name" in e.attrs:
                if e.parent is not None and e.parent.tag == "include":
                    continue
                n = e.attrs["name"].value
                if n not in seen:
                    seen.add(n)
                    items.append(_item(n, types.CompletionItemKind.Variable, "arg", "1" + n))
    for mp in ls.models_for_launch(doc.path):
        res = await ls.parsed(mp)
        model = getattr(res, "model", None)
        if model is None:
            continue
        for f in model.features:
            if f.name not in seen:
                seen.add(f.name)
                items.append(_item(f.name, types.CompletionItemKind.Class, "feature (no <arg> yet)", "2" + f.name))
    return items


async def python_items(ls, doc, pos: Pos):
    """Inside a string literal of a Python launch file: see the module docstring."""
    from ...launch.ros2py.editing import string_context
    from ...project import facts as F
    offset = doc.index.offset(pos)
    ctx = string_context(doc.text, offset)
    if ctx is None:
        return []
    rng = to_lsp_range(doc.index, Span(doc.index.pos(ctx.start), pos), ls.encoding)

    def item(name, kind, detail, sort):
        return types.CompletionItem(label=name, kind=kind, detail=detail, sort_text=sort,
                                    text_edit=types.TextEdit(range=rng, new_text=name))
    analysis = _last_good(ls, doc.path, ls.parsed_now(doc.path) or await ls.parsed(doc.path))
    has = hasattr(analysis, "elements")
    declared = []
    if has:
        for e in analysis.elements:
            if e.path == doc.path and e.include_depth == 0 and e.tag in ("arg", "let") and "name" in e.attrs \
                    and not (e.parent is not None and e.parent.tag == "include"):
                declared.append(e)
    names = list(dict.fromkeys(e.attrs["name"].value for e in declared))
    features = []
    for mp in ls.models_for_launch(doc.path):
        res = await ls.parsed(mp)
        model = getattr(res, "model", None)
        if model is not None:
            features += [(f.name, mp) for f in model.features]
    if ctx.kind == "config":
        items = [item(n, types.CompletionItemKind.Variable, "launch argument", "1" + n) for n in names]
        items += [item(f, types.CompletionItemKind.Class, "feature (no DeclareLaunchArgument yet)", "2" + f)
                  for f, _ in dict.fromkeys(features) if f not in names]
        return items
    if ctx.kind == "declare":
        import os
        return [item(f, types.CompletionItemKind.Class, f"feature of {os.path.basename(mp)}", f"{i:05d}")
                for i, (f, mp) in enumerate(dict.fromkeys(features)) if f not in names]
    if ctx.kind == "key" and has:
        return await _include_key_items(ls, doc, analysis, ctx, item)
    return []


_LAUNCH_NAME = re.compile(r"""["']([\w.\-]+(?:[._]launch\.(?:py|xml|yaml|yml)))["']""")
_PACKAGE_WORD = re.compile(r"""["']([A-Za-z0-9][\w\-]+)["']""")
_TYPED_KEY = re.compile(r"""[({,]\s*["']([\w/\-.]+)["']\s*[,:]""")


def _typed_include(ls, doc, ctx):
    """(the workspace launch file the text of an include being typed names, the keys typed
    already): the launch file name written in it (a package named in it, or in the file,
    decides between files of that name)."""
    import os
    segment = doc.text[ctx.include_at:ctx.start]
    names = _LAUNCH_NAME.findall(segment)
    if not names:
        return None, set()
    try:
        ws = ls.workspace_model(doc.path)
    except Exception:
        return None, set()
    cands = [lf for lf in ws.files.launches if os.path.basename(lf) == names[-1]]
    if len(cands) > 1:
        pkgs = set(_PACKAGE_WORD.findall(segment)) | set(_PACKAGE_WORD.findall(doc.text))
        inpkg = [lf for lf in cands if ws.package_of(lf) in pkgs]
        cands = inpkg or cands
    if len(cands) != 1:
        return None, set()
    return cands[0], set(_TYPED_KEY.findall(segment))


def _last_good(ls, path: str, analysis):
    """``analysis``, or -- while the text does not parse (it is being typed: an open string,
    an unclosed call) -- the last analysis of the file that did."""
    if analysis is None or any(d.code == "python-syntax" for d in getattr(analysis, "diagnostics", ())):
        return ls.good_parsed.get(path, analysis)
    return analysis


async def _include_key_items(ls, doc, analysis, ctx, item):
    """The arguments of the file the include around the cursor includes (those not passed yet)."""
    import os
    from ...project import facts as F
    offset = doc.index.offset
    includes = [e for e in F.own_elements(analysis, doc.path) if e.tag == "include" and F.included_file(e)]
    cursor = ctx.start
    inc = None
    around = [e for e in includes if offset(e.span.start) <= cursor <= offset(e.span.end)]
    if around:
        inc = max(around, key=lambda e: offset(e.span.start))
    else:
        # a dict of arguments made apart from the include (launch_arguments=args.items()): the
        # include whose passed arguments are written inside these brackets
        after = [(offset(c.attrs["name"].value_span.start), e) for e in includes for c in e.children
                 if c.tag == "arg" and "name" in c.attrs and offset(c.attrs["name"].value_span.start) > ctx.bracket]
        if after:
            first, inc = min(after, key=lambda x: x[0])
            from ...launch.ros2py.editing import string_context
            there = string_context(doc.text, first)
            if there is None or there.bracket != ctx.bracket:
                inc = None  # (no argument of an include is written in these brackets)
    if inc is not None:
        target = F.included_file(inc)
        passed = {c.attrs["name"].value for c in inc.children if c.tag == "arg" and "name" in c.attrs
                  and offset(c.attrs["name"].value_span.start) != ctx.start}
    elif ctx.include_at is not None:
        # an include being typed (not analysed yet): the launch file its text names
        target, passed = _typed_include(ls, doc, ctx)
    else:
        return []
    if target is None:
        return []
    included = await ls.parsed(target)
    if included is None or not hasattr(included, "elements"):
        return []
    out = []
    seen = set()
    for e in F.own_elements(included, target):
        if e.tag != "arg" or "name" not in e.attrs or (e.parent is not None and e.parent.tag == "include"):
            continue
        n = e.attrs["name"].value
        if n in seen or n in passed:
            continue
        seen.add(n)
        default = f" (default `{e.attrs['default'].value}`)" if "default" in e.attrs else " (no default)"
        out.append(item(n, types.CompletionItemKind.Variable, f"argument of {os.path.basename(target)}{default}",
                        f"{len(out):05d}"))
    return out
