"""Source edits of a Python launch file, for the editor's quick fixes: where a new
``DeclareLaunchArgument`` goes and how it is written so that it looks like the file's own.

Pure (no LSP): :func:`declare_argument_planner` reads the file's syntax tree (Python's ``ast``,
never run) and the analysis of the file, and returns a function ``name -> edits`` that inserts
``DeclareLaunchArgument('name', default_value='false')``

- after the file's last top-level ``DeclareLaunchArgument``, in the same form: an element of the
  same list (its indentation, quotes, trailing comma, one element a line or all on one line), or a
  statement like its own (``ld.add_action(DeclareLaunchArgument(...))``,
  ``declared_arguments.append(...)``), laid out like it (arguments on one line or one a line);
- in a file that declares none: at the start of the list given to the ``LaunchDescription`` that
  ``generate_launch_description()`` returns, or, when the file builds it with
  ``ld.add_action(...)``, as an ``ld.add_action(...)`` before the first one;

every insertion is such that the insertions of several arguments at one place, one after the
other, are valid too (the editor's "add all missing arguments" concatenates them);

and, when the file does not import ``DeclareLaunchArgument``, the import: added to its
``from launch.actions import ...`` (in alphabetical place when the names are sorted), else as a
line of its own among the ``launch`` imports.  Where none of this applies (no
``generate_launch_description``, a description built in a way these rules do not cover) the
planner returns None: no fix rather than a wrong one.

The completion of names in the file's strings asks :func:`string_context` what the string at
the cursor names (a launch configuration, a new argument, an include's argument).
"""

from __future__ import annotations

import ast
from typing import Callable, Optional

from ...base.diagnostics import TextEdit
from ...base.text import LineIndex, Pos, Span

DLA = "DeclareLaunchArgument"
ACTIONS = "launch.actions"


class _Src:
    """The file's text with ast positions (1-based lines, UTF-8 byte columns) as code points."""

    def __init__(self, text: str, tree: ast.Module):
        self.text = text
        self.tree = tree
        self.index = LineIndex(text)
        self.ascii = text.isascii()
        self.parents: dict[int, ast.AST] = {}
        for node in ast.walk(tree):
            for child in ast.iter_child_nodes(node):
                self.parents[id(child)] = node

    def col(self, lineno: int, col_bytes: int) -> int:
        if self.ascii:
            return col_bytes
        t = self.index.line_text(lineno - 1)
        return len(t.encode("utf-8")[:col_bytes].decode("utf-8", "replace"))

    def start(self, node) -> int:
        return self.index.offset(Pos(node.lineno - 1, self.col(node.lineno, node.col_offset)))

    def end(self, node) -> int:
        return self.index.offset(Pos(node.end_lineno - 1, self.col(node.end_lineno, node.end_col_offset)))

    def span(self, node) -> Span:
        return Span(self.index.pos(self.start(node)), self.index.pos(self.end(node)))

    def src(self, node) -> str:
        return self.text[self.start(node):self.end(node)]

    def parent(self, node):
        return self.parents.get(id(node))

    def line_indent(self, line: int) -> str:
        t = self.index.line_text(line)
        return t[: len(t) - len(t.lstrip())]

    def starts_line(self, node) -> bool:
        """Is ``node`` the first thing on its line?"""
        a = self.start(node)
        ls = self.index.offset(Pos(self.index.pos(a).line, 0))
        return not self.text[ls:a].strip()

    def edit(self, path: str, at: int, new: str, end: Optional[int] = None) -> TextEdit:
        return TextEdit(path, Span(self.index.pos(at), self.index.pos(at if end is None else end)), new)


def _callee(node) -> str:
    f = node.func
    return f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""


def _str_const(node) -> Optional[str]:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def _name_arg(call: ast.Call):
    if call.args:
        return call.args[0]
    return next((k.value for k in call.keywords if k.arg == "name"), None)


def _generate_function(tree: ast.Module) -> Optional[ast.FunctionDef]:
    for st in tree.body:
        if isinstance(st, ast.FunctionDef) and st.name == "generate_launch_description":
            return st
    return None


def _returned_description(src: _Src, fn: ast.FunctionDef):
    """(the LaunchDescription call, the name it is bound to or None) that the function returns."""
    for node in ast.walk(fn):
        if not isinstance(node, ast.Return) or node.value is None:
            continue
        v = node.value
        if isinstance(v, ast.Call) and _callee(v) == "LaunchDescription":
            return v, None
        if isinstance(v, ast.Name):
            for st in ast.walk(fn):
                if isinstance(st, ast.Assign) and len(st.targets) == 1 and isinstance(st.targets[0], ast.Name) \
                        and st.targets[0].id == v.id and isinstance(st.value, ast.Call) \
                        and _callee(st.value) == "LaunchDescription":
                    return st.value, v.id
    return None, None


# ------------------------------------------------------------------ the new call's text

class _Style:
    """How the file writes a DeclareLaunchArgument: callee, quotes, layout."""

    def __init__(self, callee: str = DLA, quote: str = "'", multiline: bool = False, inner: str = "",
                 close_own_line: bool = False, outer: str = "", name_kw: bool = False,
                 description: bool = False, cont: Optional[str] = None):
        self.callee = callee
        self.quote = quote
        self.multiline = multiline      # each argument on a line of its own
        self.inner = inner              # their indentation
        self.close_own_line = close_own_line
        self.outer = outer              # the indentation of a ``)`` on a line of its own
        self.name_kw = name_kw          # name='X' rather than 'X'
        self.description = description
        self.cont = cont                # continuation indentation of description= (one-line head)
        self.trailing_comma = False     # a comma after the last argument (one a line)

    def q(self, s: str) -> str:
        body = s.replace("\\", "\\\\").replace(self.quote, "\\" + self.quote)
        return f"{self.quote}{body}{self.quote}"

    def call(self, name: str, description: Optional[str]) -> str:
        args = [(f"name={self.q(name)}" if self.name_kw else self.q(name)), f"default_value={self.q('false')}"]
        if self.description and description:
            args.append(f"description={self.q(description)}")
        if self.multiline:
            body = ",\n".join(self.inner + a for a in args) + ("," if self.trailing_comma else "")
            close = f"\n{self.outer})" if self.close_own_line else ")"
            return f"{self.callee}(\n{body}{close}"
        if len(args) == 3 and self.cont is not None:
            return f"{self.callee}({args[0]}, {args[1]},\n{self.cont}{args[2]})"
        return f"{self.callee}({', '.join(args)})"


def _style_of(src: _Src, call: ast.Call, callee: str) -> _Style:
    st = _Style(callee=callee)
    name = _name_arg(call)
    if name is not None:
        lit = src.src(name).lstrip("rRuU")
        if lit[:1] in ("'", '"'):
            st.quote = lit[0]
    st.name_kw = not call.args and any(k.arg == "name" for k in call.keywords)
    st.description = any(k.arg == "description" for k in call.keywords)
    parts = list(call.args) + [k for k in call.keywords]
    if parts:
        first = parts[0]
        if first.lineno > call.lineno or (isinstance(first, ast.keyword) and first.value.lineno > call.lineno):
            st.multiline = True
            st.inner = src.line_indent((first.lineno if not isinstance(first, ast.keyword) else first.value.lineno) - 1)
            close_line = call.end_lineno - 1
            last = parts[-1]
            last_end = (last.value if isinstance(last, ast.keyword) else last).end_lineno - 1
            st.close_own_line = close_line > last_end
            st.trailing_comma = "," in src.text[src.end(last.value if isinstance(last, ast.keyword) else last):
                                                src.end(call)]
            st.outer = src.line_indent(close_line)
        else:
            desc = next((k for k in call.keywords if k.arg == "description"), None)
            if desc is not None and desc.value.lineno > call.lineno:
                st.cont = src.line_indent(desc.value.lineno - 1)
    return st


# ------------------------------------------------------------------ the planner

def declare_argument_planner(text: str, path: str, analysis) -> Optional[Callable[[str, Optional[str]], Optional[list]]]:
    """``insert(name, description) -> [TextEdit]`` (the import first when one is needed), or None
    when the file gives no place for a new argument (see the module docstring)."""
    from .frontend import parse_python
    tree, _ = parse_python(text, path)
    if tree is None:
        return None
    fn = _generate_function(tree)
    if fn is None:
        return None
    src = _Src(text, tree)
    binding, import_edit = _import(src, path)
    neighbour = _last_declaration(src, analysis, path)
    if neighbour is not None:
        # the file calls it already (by that very name): no import
        call, place = neighbour
        return _inserter(src, path, place, call, _style_of(src, call, src.src(call.func)), None)
    style = _Style(callee=binding or DLA, quote=_file_quote(src))
    place = _description_place(src, fn)
    if place is None:
        return None
    return _inserter(src, path, place, None, style, import_edit)


def _inserter(src: _Src, path: str, place, neighbour, style: _Style, import_edit):
    kind = place[0]

    def insert(name: str, description: Optional[str] = None) -> Optional[list]:
        new = style.call(name, description)
        edits = [import_edit] if import_edit is not None else []
        if kind == "after-element":
            edits.append(_after_element(src, path, place[1], place[2], new))
        elif kind == "list-start":
            edits.append(_list_start(src, path, place[1], new))
        elif kind == "after-statement":
            stmt, call = place[1], place[2]
            s_src = src.src(stmt)
            a, b = src.start(call) - src.start(stmt), src.end(call) - src.start(stmt)
            body = s_src[:a] + new + s_src[b:]
            at = src.index.line_end(stmt.end_lineno - 1)
            edits.append(src.edit(path, at, "\n" + src.line_indent(stmt.lineno - 1) + body))
        elif kind == "before-statement":
            stmt, receiver, attr = place[1], place[2], place[3]
            indent = src.line_indent(stmt.lineno - 1)
            at = src.index.offset(Pos(stmt.lineno - 1, 0))
            edits.append(src.edit(path, at, f"{indent}{receiver}.{attr}({new})\n"))
        else:
            return None
        return edits
    return insert


def _file_quote(src: _Src) -> str:
    n = {"'": 0, '"': 0}
    for node in ast.walk(src.tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and getattr(node, "end_lineno", None):
            c = src.text[src.start(node):src.start(node) + 1]
            if c in n:
                n[c] += 1
    return '"' if n['"'] > n["'"] else "'"


def _last_declaration(src: _Src, analysis, path: str):
    """(call, place) of the last top-level DeclareLaunchArgument of the file that a new one can
    follow: an element of a list / tuple, or the argument of an ``x.add_action(...)`` /
    ``x.append(...)`` statement."""
    spans = set()
    for a in getattr(analysis, "feature_args", None) or ():
        if getattr(a, "path", path) in (path, "") and a.span is not None:
            spans.add((a.span.start, a.span.end))
    best = None
    for node in ast.walk(src.tree):
        if not isinstance(node, ast.Call) or _callee(node) != DLA:
            continue
        sp = src.span(node)
        if (sp.start, sp.end) not in spans:
            continue
        parent = src.parent(node)
        place = None
        if isinstance(parent, (ast.List, ast.Tuple)) and any(e is node for e in parent.elts):
            place = ("after-element", parent, node)
        elif isinstance(parent, ast.Call) and isinstance(parent.func, ast.Attribute) and \
                parent.func.attr in ("add_action", "append") and len(parent.args) == 1 and parent.args[0] is node \
                and isinstance(src.parent(parent), ast.Expr):
            place = ("after-statement", src.parent(parent), node)
        if place is not None and (best is None or sp.start > best[2]):
            best = (node, place, sp.start)
    return (best[0], best[1]) if best else None


def _description_place(src: _Src, fn: ast.FunctionDef):
    """Where the first argument of a file that declares none goes."""
    call, bound = _returned_description(src, fn)
    if call is None:
        return None
    lists = []
    if call.args:
        stack = [call.args[0]]
        while stack:
            x = stack.pop()
            if isinstance(x, ast.List):
                lists.append(x)
            elif isinstance(x, ast.BinOp) and isinstance(x.op, ast.Add):
                stack += [x.right, x.left]
        if lists:
            return ("list-start", lists[0])
    if bound is not None:
        for st in fn.body:
            if isinstance(st, ast.Expr) and isinstance(st.value, ast.Call) and \
                    isinstance(st.value.func, ast.Attribute) and st.value.func.attr == "add_action" and \
                    isinstance(st.value.func.value, ast.Name) and st.value.func.value.id == bound:
                return ("before-statement", st, bound, "add_action")
    return None


def _after_element(src: _Src, path: str, container, node, new: str) -> TextEdit:
    elts = container.elts
    i = next(k for k, e in enumerate(elts) if e is node)
    one_a_line = len(elts) > 1 and all(elts[k].lineno > elts[k - 1].end_lineno for k in range(1, len(elts))) \
        or (len(elts) == 1 and src.starts_line(node))
    end = src.end(node)
    if not one_a_line:
        return src.edit(path, end, ", " + new)
    indent = src.line_indent(node.lineno - 1) if src.starts_line(node) else " " * src.index.pos(src.start(node)).col
    rest = src.text[end:src.index.line_end(node.end_lineno - 1)]
    comma = rest.lstrip().startswith(",")
    last = i == len(elts) - 1
    if comma:
        after = rest.split(",", 1)[1]
        if not after.strip() or after.strip().startswith("#"):
            # after the comma and any comment: a line of its own
            return src.edit(path, src.index.line_end(node.end_lineno - 1), f"\n{indent}{new},")
        at = end + rest.index(",") + 1
        return src.edit(path, at, f"\n{indent}{new},")
    if last:
        return src.edit(path, end, f",\n{indent}{new}")
    return src.edit(path, end, f",\n{indent}{new}")


def _list_start(src: _Src, path: str, lst: ast.List, new: str) -> TextEdit:
    if not lst.elts:
        return src.edit(path, src.start(lst) + 1, f"{new}, ")
    first = lst.elts[0]
    if first.lineno > lst.lineno and src.starts_line(first):
        indent = src.line_indent(first.lineno - 1)
        return src.edit(path, src.start(first), f"{new},\n{indent}")
    return src.edit(path, src.start(first), f"{new}, ")


# ------------------------------------------------------------------ the import

def _import(src: _Src, path: str) -> tuple[Optional[str], Optional[TextEdit]]:
    """(the name DeclareLaunchArgument is called by, the edit that imports it or None)."""
    launch_imports = []
    last_import = None
    for st in src.tree.body:
        if isinstance(st, ast.ImportFrom) and st.level == 0:
            last_import = st
            if st.module and (st.module == "launch" or st.module.startswith("launch.")):
                launch_imports.append(st)
            if st.module == ACTIONS:
                for al in st.names:
                    if al.name == DLA:
                        return al.asname or DLA, None
                    if al.name == "*":
                        return DLA, None
        elif isinstance(st, ast.Import):
            last_import = st
            for al in st.names:
                if al.asname is None and (al.name == "launch" or al.name == ACTIONS):
                    return f"{ACTIONS}.{DLA}", None
    actions = next((st for st in launch_imports if st.module == ACTIONS), None)
    if actions is not None:
        return DLA, _add_to_import(src, path, actions)
    line_text = f"from {ACTIONS} import {DLA}\n"
    after = [st for st in launch_imports if st.module < ACTIONS]
    before = [st for st in launch_imports if st.module > ACTIONS]
    if before and (not after or before[0].lineno > after[-1].lineno):
        at = src.index.offset(Pos(before[0].lineno - 1, 0))
    elif launch_imports:
        anchor = after[-1] if after else launch_imports[-1]
        at = src.index.line_end(anchor.end_lineno - 1)
        return DLA, src.edit(path, at, "\n" + line_text.rstrip("\n"))
    elif last_import is not None:
        at = src.index.line_end(last_import.end_lineno - 1)
        return DLA, src.edit(path, at, "\n" + line_text.rstrip("\n"))
    else:
        at = _top_of_module(src)
    return DLA, src.edit(path, at, line_text)


def _top_of_module(src: _Src) -> int:
    """After the module docstring (else at the first statement's line, after the comments)."""
    body = src.tree.body
    if body and isinstance(body[0], ast.Expr) and _str_const(body[0].value) is not None:
        line = body[0].end_lineno
        return src.index.offset(Pos(min(line, src.index.line_count - 1), 0)) if line < src.index.line_count \
            else len(src.text)
    if body:
        return src.index.offset(Pos(body[0].lineno - 1, 0))
    return len(src.text)


def _add_to_import(src: _Src, path: str, st: ast.ImportFrom) -> TextEdit:
    names = st.names
    plain = [al.name for al in names]
    pos = len(names)
    if plain == sorted(plain):
        pos = next((k for k, n in enumerate(plain) if n > DLA), len(names))
    one_a_line = len(names) > 1 and all(names[k].lineno > names[k - 1].end_lineno for k in range(1, len(names)))
    if one_a_line:
        ref = names[min(pos, len(names) - 1)]
        indent = src.line_indent(ref.lineno - 1)
        if pos < len(names):
            return src.edit(path, src.start(names[pos]), f"{DLA},\n{indent}")
        end = src.end(names[-1])
        rest = src.text[end:src.index.line_end(names[-1].end_lineno - 1)]
        if rest.lstrip().startswith(","):
            return src.edit(path, end + rest.index(",") + 1, f"\n{indent}{DLA},")
        return src.edit(path, end, f",\n{indent}{DLA}")
    if pos < len(names):
        return src.edit(path, src.start(names[pos]), f"{DLA}, ")
    return src.edit(path, src.end(names[-1]), f", {DLA}")


# ------------------------------------------------------------------ completion context

import re  # noqa: E402
from dataclasses import dataclass  # noqa: E402

_TOKEN = re.compile(r"""(?P<str>(?:[rRbBuUfF]{1,2})?(?:'''|\"\"\"|'|"))|(?P<com>\#[^\n]*)|(?P<open>[(\[{])"""
                    r"""|(?P<close>[)\]}])|(?P<comma>,)|(?P<colon>:)|(?P<eq>==|=)|(?P<name>[A-Za-z_][\w.]*)"""
                    r"""|(?P<other>\S)""")
CONFIG_CALLS = ("LaunchConfiguration", "LaunchConfigurationEquals", "LaunchConfigurationNotEquals")
MAX_SCAN = 400_000


@dataclass
class StringContext:
    """The string literal the cursor is in, and what it names there."""
    kind: str          # "config" (a launch configuration's name), "declare" (a new argument's name),
                       # "key" (a key of a dict / first item of a tuple: maybe an include's argument)
    prefix: str        # the literal's text before the cursor
    start: int         # offset of the literal's first character (after the quote)
    bracket: int       # offset of the innermost open bracket around the literal
    launch_arguments: bool = False  # "key": inside launch_arguments=...
    include_at: Optional[int] = None  # "key": the ``(`` of the IncludeLaunchDescription around it


class _Open:
    __slots__ = ("ch", "at", "label", "kw", "items", "tokens", "colon", "cur_kw")

    def __init__(self, ch: str, at: int, label: Optional[str], kw: Optional[str]):
        self.ch, self.at, self.label, self.kw = ch, at, label, kw
        self.items = 0
        self.tokens = 0
        self.colon = False
        self.cur_kw: Optional[str] = None


def string_context(text: str, offset: int) -> Optional[StringContext]:
    """What the string literal at ``offset`` of a Python launch file's text names, read from the
    text before it (which may not parse: it is being typed): the name of a launch configuration
    (``LaunchConfiguration('|``, ``context.launch_configurations['|``, ``.get('|``), of a new
    argument (``DeclareLaunchArgument('|``), or a key (``launch_arguments={'|`` / ``[('|``).
    None elsewhere (not in a string, an f-string, a comment)."""
    if offset > MAX_SCAN or offset > len(text):
        return None
    stack: list[_Open] = []
    last_name: Optional[str] = None
    last_kind = None
    pos = 0
    while pos < offset:
        m = _TOKEN.search(text, pos, offset)
        if m is None:
            return None
        kind = m.lastgroup
        tok = m.group()
        top = stack[-1] if stack else None
        if kind == "str":
            quote = tok.lstrip("rRbBuUfF")
            body = m.end()
            if len(quote) == 3:
                end = text.find(quote, body, offset)
                close = end + 3 if end >= 0 else -1
            else:
                close = -1
                i = body
                while i < offset:
                    c = text[i]
                    if c == "\\":
                        i += 2
                        continue
                    if c == "\n":
                        break
                    if c == quote:
                        close = i + 1
                        break
                    i += 1
                if close < 0 and i < offset:  # an unterminated literal ended by the line
                    pos, last_kind = i, "str"
                    continue
            if close < 0:
                if "f" in tok[: len(tok) - len(quote)].lower() or len(quote) == 3:
                    return None
                return _context(stack, text[body:offset], body, last_name, last_kind)
            if top is not None:
                top.tokens += 1
            pos, last_kind, last_name = close, "str", None
            continue
        pos = m.end()
        if kind == "com":
            continue
        if kind == "open":
            label = last_name if last_kind == "name" else None
            if top is not None:
                top.tokens += 1
            stack.append(_Open(tok, m.start(), label, top.cur_kw if top is not None else None))
        elif kind == "close":
            if stack:
                stack.pop()
        elif kind == "comma" and top is not None:
            top.items += 1
            top.tokens = 0
            top.colon = False
            top.cur_kw = None
        elif kind == "colon" and top is not None:
            top.colon = True
            top.tokens = 0
        elif kind == "eq" and tok == "=" and top is not None and last_kind == "name" and top.tokens == 1:
            top.cur_kw = last_name
            top.tokens = 0
        elif top is not None:
            top.tokens += 1
        last_kind = kind
        last_name = tok if kind == "name" else None
    return None


def _context(stack: list, prefix: str, start: int, last_name, last_kind) -> Optional[StringContext]:
    if not stack:
        return None
    top = stack[-1]
    if top.tokens != 0:
        return None
    label = (top.label or "").rsplit(".", 1)[-1]
    dotted = top.label or ""
    if top.ch == "(" and label in CONFIG_CALLS and (
            (top.items == 0 and top.cur_kw is None) or top.cur_kw in ("variable_name", "launch_configuration_name")):
        return StringContext("config", prefix, start, top.at)
    if top.ch == "(" and dotted.endswith("launch_configurations.get") and top.items == 0:
        return StringContext("config", prefix, start, top.at)
    if top.ch == "[" and dotted.endswith("launch_configurations") and top.label is not None:
        return StringContext("config", prefix, start, top.at)
    if top.ch == "(" and label == "DeclareLaunchArgument" and (
            (top.items == 0 and top.cur_kw is None) or top.cur_kw == "name"):
        return StringContext("declare", prefix, start, top.at)
    include_at = next((b.at for b in reversed(stack) if b.ch == "(" and
                       (b.label or "").rsplit(".", 1)[-1] == "IncludeLaunchDescription"), None)
    if top.ch == "{" and not top.colon:
        return StringContext("key", prefix, start, top.at, top.kw == "launch_arguments", include_at)
    if top.ch == "(" and top.label is None and top.items == 0 and len(stack) > 1:
        outer = stack[-2]
        if outer.ch in "[(" and outer.label is None:
            return StringContext("key", prefix, start, top.at, outer.kw == "launch_arguments", include_at)
    return None


def name_literals(text: str, path: str, name: str) -> list[Span]:
    """The ranges (between the quotes) of the plain one-line string literals of the file whose
    value is ``name``: after a rename, those it did not change may still name the argument
    (a list the file declares its arguments from) -- or something else (a node of that name)."""
    from .frontend import parse_python
    tree, _ = parse_python(text, path)
    if tree is None or name not in text:
        return []
    src = _Src(text, tree)
    out = []
    for node in ast.walk(tree):
        if _str_const(node) != name or getattr(node, "end_lineno", None) != node.lineno:
            continue
        raw = src.src(node)
        body = raw.lstrip("rRuU")
        q = body[:3] if body[:3] in ('"""', "'''") else body[:1]
        if q not in ("'", '"', '"""', "'''") or body[len(q):len(body) - len(q)] != name:
            continue  # (escapes, implicit concatenation: not the name's characters)
        a = src.start(node) + (len(raw) - len(body)) + len(q)
        out.append(Span(src.index.pos(a), src.index.pos(a + len(name))))
    return out
