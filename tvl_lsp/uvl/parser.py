"""UVL syntax: lark's LALR table for ``grammars/uvl.lark`` run by a lean driver over the tokens
of :mod:`.lexer`, building raw declarations (features, groups, attributes, imports) and model
expressions (constraints) inline.

Recovery is by line, UVL's unit of meaning, so that one mistake gives one error and the rest of
the file is still read:

- a broken line in the feature tree keeps its leading name (``Camera {price 3`` still declares
  ``Camera``, so constraints naming it are checked) and loses the rest; if even the name cannot
  stand there, the line is dropped;
- a broken constraint is dropped whole (half a constraint would mean something else);
- each line is reported once; indentation that matches no enclosing level is reported once and
  read as the nearest enclosing level.

The work is bounded: after :data:`MAX_ERRORS` broken lines the rest of the file is not reported.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any, Optional

from ..tvl import model as m
from .lexer import Line, Tok, layout

MAX_ERRORS = 100
MAX_DEPTH = 200  # expression nesting analysed


def _grammar_text() -> str:
    from ..base.files import package_text
    return package_text("grammars", "uvl.lark")


# ---------------------------------------------------------------- raw declarations

@dataclass(eq=False, slots=True)
class RawRef:
    parts: list[Tok]

    @property
    def start(self) -> int:
        return self.parts[0].start

    @property
    def end(self) -> int:
        return self.parts[-1].end

    @property
    def text(self) -> str:
        return ".".join(_unquote(t) for t in self.parts)


@dataclass(eq=False, slots=True)
class RawValue:
    kind: str  # bool int float string attrs vector
    value: Any
    start: int
    end: int


@dataclass(eq=False, slots=True)
class RawAttr:
    key: Optional[Tok]          # None for constraint / constraints
    kind: str                   # flag value constraint constraints
    value: Optional[RawValue]
    constraints: list[m.Expr]
    start: int
    end: int


@dataclass(eq=False, slots=True)
class RawGroup:
    kw: Tok
    features: list["RawFeature"]
    start: int
    end: int


@dataclass(eq=False, slots=True)
class RawFeature:
    type_tok: Optional[Tok]
    ref: RawRef
    card: Optional[Tok]
    attrs: list[RawAttr]
    attrs_span: Optional[tuple[int, int]]
    groups: list[RawGroup] = field(default_factory=list)
    start: int = 0
    end: int = 0
    depth: int = 0
    built: Any = None  # the feature the builder made of it


@dataclass(eq=False, slots=True)
class RawImport:
    ref: RawRef
    alias: Optional[RawRef]
    start: int
    end: int


@dataclass(eq=False, slots=True)
class RawConstraint:
    expr: m.Expr
    start: int
    end: int


@dataclass(eq=False, slots=True)
class RawInclude:
    level: str
    start: int
    end: int


@dataclass
class RawFile:
    namespace: Optional[RawRef] = None
    includes: list[RawInclude] = field(default_factory=list)
    imports: list[RawImport] = field(default_factory=list)
    features_kw: Optional[Tok] = None
    roots: list[RawFeature] = field(default_factory=list)
    constraints: list[RawConstraint] = field(default_factory=list)
    # names of features on lines dropped by the recovery (constraints naming them are left out
    # without a second message)
    broken_names: set[str] = field(default_factory=set)


@dataclass
class SyntaxIssue:
    start: int
    end: int
    message: str


class StrLit(m.Expr):
    """A UVL string literal ``'...'`` (type level; never analysed)."""

    def __init__(self, value: str, **kw):
        super().__init__(**kw)
        self.value = value


def _unquote(t: Tok) -> str:
    v = t.value
    return v[1:-1] if t.type == "QID" else v


# ---------------------------------------------------------------- lark plumbing

_OPS = {"AND": "&&", "OR": "||", "IMPLIES": "->", "IFF": "<->", "EQ": "==", "NEQ": "!=", "LT": "<",
        "GT": ">", "LEQ": "<=", "GEQ": ">=", "PLUS": "+", "MINUS": "-", "TIMES": "*", "DIV": "/"}


def _s(x) -> int:
    return x.start if isinstance(x, (Tok, RawRef, RawValue)) else x._s


def _e(x) -> int:
    return x.end if isinstance(x, (Tok, RawRef, RawValue)) else x._e


class _Builder:
    """The grammar's callbacks (by rule alias or name), called by :func:`_run`."""

    def __init__(self):
        self.ctx: "_Ctx" = None

    def _mk(self, node: m.Expr, s: int, e: int, depth: int) -> m.Expr:
        ctx = self.ctx
        node.span = ctx.span(s, e)
        node.path = ctx.path
        node._s = s
        node._e = e
        if depth > MAX_DEPTH:
            node.too_deep = True
        node._d = depth
        return node

    @staticmethod
    def _list(c):
        if len(c) == 1:
            return [c[0]]
        lst = c[0]
        lst.append(c[-1])
        return lst

    # -- lists
    def include_list(self, c):
        return self._list(c)

    def import_list(self, c):
        return self._list(c)

    def feature_list(self, c):
        return self._list(c)

    def group_list(self, c):
        return self._list(c)

    def attr_list(self, c):
        return [c[0]] if len(c) == 1 else self._list([c[0], c[2]])

    def constraint_list(self, c):
        return [c[0]] if len(c) == 1 else self._list([c[0], c[2]])

    def value_list(self, c):
        return [c[0]] if len(c) == 1 else self._list([c[0], c[2]])

    def constraint_lines(self, c):
        return self._list(c)

    # -- names
    def id(self, c):
        return c[0]

    def reference(self, c):
        if len(c) == 1:
            return RawRef([c[0]])
        r = c[0]
        r.parts.append(c[2])
        return r

    # -- header
    def namespace(self, c):
        return ("namespace", c[1])

    def major_level(self, c):
        return c[0]

    def minor_level(self, c):
        return c[0]

    def include_line(self, c):
        toks = [t for t in c if t.type != "_NL"]
        return RawInclude("".join(t.value for t in toks), toks[0].start, toks[-1].end)

    def includes(self, c):
        return ("includes", c[3])

    def includes_empty(self, c):
        return ("includes", [])

    def import_line(self, c):
        r = c[0]
        return RawImport(r, None, r.start, r.end)

    def import_alias(self, c):
        return RawImport(c[0], c[2], c[0].start, c[2].end)

    def imports(self, c):
        return ("imports", c[3])

    def imports_empty(self, c):
        return ("imports", [])

    # -- features
    def feature_type(self, c):
        return c[0]

    def feature_card(self, c):
        return c[1]

    def feature_head(self, c):
        ty = c[0] if isinstance(c[0], Tok) else None
        rest = c[1:] if ty is not None else c
        ref = rest[0]
        card = None
        attrs = None
        for x in rest[1:]:
            if isinstance(x, Tok):
                card = x
            else:
                attrs = x
        f = RawFeature(ty, ref, card, attrs[0] if attrs else [], (attrs[1], attrs[2]) if attrs else None)
        f.start = ty.start if ty is not None else ref.start
        f.end = attrs[2] if attrs else (card.end if card is not None else ref.end)
        return f

    def feature(self, c):
        return c[0]

    def feature_groups(self, c):
        f = c[0]
        f.groups = c[3]
        if f.groups:
            f.end = max(f.end, f.groups[-1].end)
            f.depth = max(max((x.depth for x in g.features), default=0) for g in f.groups) + 1
        return f

    def group_kw(self, c):
        return c[0]

    def group(self, c):
        kw, feats = c[0], c[3]
        end = feats[-1].end if feats else kw.end
        return RawGroup(kw, feats, kw.start, end)

    def group_empty(self, c):
        kw = c[0]
        iss = SyntaxIssue(kw.start, kw.end, f"the group '{kw.value}' has no features: write them below it, indented")
        iss.empty_group = True
        self.ctx.issues.append(iss)
        return RawGroup(kw, [], kw.start, kw.end)

    def features(self, c):
        return ("features", c[0], c[3])

    def features_empty(self, c):
        return ("features", c[0], [])

    # -- attributes
    def attributes(self, c):
        items = c[1] if len(c) == 3 else []
        return (items, c[0].start, c[-1].end)

    def key(self, c):
        return c[0]

    def attr_flag(self, c):
        k = c[0]
        return RawAttr(k, "flag", RawValue("bool", True, k.end, k.end), [], k.start, k.end)

    def attr_value(self, c):
        k, v = c
        return RawAttr(k, "value", v, [], k.start, v.end)

    def attr_constraint(self, c):
        kw, e = c
        return RawAttr(None, "constraint", None, [e], kw.start, _e(e))

    def attr_constraints(self, c):
        kw = c[0]
        return RawAttr(None, "constraints", None, c[2], kw.start, c[-1].end)

    def attr_constraints_empty(self, c):
        kw = c[0]
        return RawAttr(None, "constraints", None, [], kw.start, c[-1].end)

    def v_true(self, c):
        return RawValue("bool", True, c[0].start, c[0].end)

    def v_false(self, c):
        return RawValue("bool", False, c[0].start, c[0].end)

    def v_int(self, c):
        return RawValue("int", int(c[0].value), c[0].start, c[0].end)

    def v_float(self, c):
        return RawValue("float", float(c[0].value), c[0].start, c[0].end)

    def v_string(self, c):
        return RawValue("string", c[0].value[1:-1], c[0].start, c[0].end)

    def v_qstring(self, c):
        return RawValue("string", c[0].value[1:-1], c[0].start, c[0].end)

    def v_attrs(self, c):
        items, s, e = c[0]
        return RawValue("attrs", items, s, e)

    def v_vector(self, c):
        return RawValue("vector", c[1], c[0].start, c[-1].end)

    def v_vector_empty(self, c):
        return RawValue("vector", [], c[0].start, c[-1].end)

    def v_card_vector(self, c):
        t = c[0]
        inner = t.value.strip()[1:-1].strip()
        vals = [RawValue("int", int(x), t.start, t.end) for x in inner.split("..") if x.strip().isdigit()]
        return RawValue("vector", vals, t.start, t.end)

    # -- constraints
    def constraints(self, c):
        return ("constraints", c[3])

    def constraints_empty(self, c):
        return ("constraints", [])

    def constraint_line(self, c):
        e = c[0]
        return RawConstraint(e, e._s, e._e)

    def name(self, c):
        r: RawRef = c[0]
        ctx = self.ctx
        parts = r.parts
        if len(parts) == 1:  # the common case: the name's span is its part's
            t = parts[0]
            sp = ctx.span(t.start, t.end)
            node = m.Name([t.value[1:-1] if t.type == "QID" else t.value], part_spans=[sp])
            node.span = sp
            node.path = ctx.path
            node._s = t.start
            node._e = t.end
            node._d = 1
            return node
        node = m.Name([_unquote(t) for t in parts], part_spans=[ctx.span(t.start, t.end) for t in parts])
        return self._mk(node, r.start, r.end, 1)

    def int_lit(self, c):
        t = c[0]
        return self._mk(m.IntLit(int(t.value)), t.start, t.end, 1)

    def float_lit(self, c):
        t = c[0]
        return self._mk(m.RealLit(float(t.value), text=t.value), t.start, t.end, 1)

    def string_lit(self, c):
        t = c[0]
        return self._mk(StrLit(t.value[1:-1]), t.start, t.end, 1)

    def paren(self, c):
        inner = c[1]
        node = self._mk(inner, c[0].start, c[2].end, getattr(inner, "_d", 1) + 1)
        node.parens = getattr(inner, "parens", 0) + 1
        return node

    def binop(self, c):
        left, op, right = c
        d = max(getattr(left, "_d", 1), getattr(right, "_d", 1)) + 1
        if op.type in ("AND", "OR") and isinstance(left, m.Binary) and left.op == _OPS[op.type] \
                and not getattr(left, "parens", 0):
            d = max(getattr(left, "_d", 1), getattr(right, "_d", 1) + 1)  # a flat chain is not nesting
        return self._mk(m.Binary(_OPS[op.type], left, right), _s(left), _e(right), d)

    def unop(self, c):
        op, operand = c
        return self._mk(m.Unary("!", operand), op.start, _e(operand), getattr(operand, "_d", 1) + 1)

    def agg_func(self, c):
        return c[0]

    def aggregate(self, c):
        f, _l, r, rp = c
        arg = self.name([r])
        return self._mk(m.Aggregate(f.value, args=[arg]), f.start, rp.end, 2)

    def aggregate2(self, c):
        f, _l, r1, _c, r2, rp = c
        args = [self.name([r1]), self.name([r2])]
        return self._mk(m.Aggregate(f.value, args=args), f.start, rp.end, 2)

    def start(self, c):
        out = RawFile()
        for x in c:
            if x[0] == "namespace":
                out.namespace = x[1]
            elif x[0] == "includes":
                out.includes = x[1]
            elif x[0] == "imports":
                out.imports = x[1]
            elif x[0] == "features":
                out.features_kw = x[1]
                out.roots = x[2]
            elif x[0] == "constraints":
                out.constraints = x[1]
        return out


@dataclass
class _Ctx:
    span: Any      # (start, end) -> Span
    path: str
    issues: list[SyntaxIssue]


_LOCK = threading.Lock()
_BUILDER = _Builder()
_TABLES = None
_IDENTITY = {"id", "key", "major_level", "minor_level", "feature_type", "group_kw", "agg_func"}


def _tables():
    """(rows, start state, end state): ``rows[state][terminal]`` is ``(True, next state, 0, None)``
    to shift, or ``(False, rule origin, rule size, callback or None)`` to reduce.

    The table is the one lark computes for ``grammars/uvl.lark``; it is stored in
    :mod:`._uvl_table` (written by ``python -m tvl_lsp.uvl.parser``, checked against lark by
    tests/test_uvl_table.py) so that reading a UVL file neither imports lark nor builds the
    LALR automaton (0.05 s of every cold start).  When the grammar no longer matches the stored
    table (its SHA-256 differs), lark computes the table here as before."""
    global _TABLES
    if _TABLES is None:
        serial = _stored_table()
        if serial is None:
            serial = _lark_table()
        rows, start, end = serial
        table = []
        for d in rows:
            if d is None:
                table.append(None)
                continue
            table.append({sym: (act if act[0] or act[3] is None else (False, act[1], act[2], getattr(_BUILDER, act[3])))
                          for sym, act in d.items()})
        _TABLES = (table, start, end)
    return _TABLES


def _grammar_digest() -> str:
    import hashlib
    return hashlib.sha256(_grammar_text().encode("utf-8")).hexdigest()


def _stored_table():
    try:
        from . import _uvl_table
    except ImportError:  # pragma: no cover - the file is part of the package
        return None
    if _uvl_table.GRAMMAR_SHA256 != _grammar_digest():
        return None
    syms = _uvl_table.SYMBOLS
    rules = [(False, *r) for r in _uvl_table.RULES]
    rows = []
    for flat in _uvl_table.ROWS:
        d = {}
        for k in range(0, len(flat), 2):
            code = flat[k + 1]
            d[syms[flat[k]]] = (True, code, 0, None) if code >= 0 else rules[-1 - code]
        rows.append(d)
    return rows, _uvl_table.START, _uvl_table.END


def _lark_table():
    """The table as lark computes it from the grammar, callbacks named (``None``: a unit rule
    whose value is its only child)."""
    from lark import Lark
    from lark.lexer import Lexer
    from lark.parsers.lalr_analysis import Shift

    class _ListLexer(Lexer):
        def __init__(self, lexer_conf):
            pass

        def lex(self, data, *_):  # pragma: no cover - never used
            return iter(())

    parser = Lark(_grammar_text(), parser="lalr", lexer=_ListLexer, transformer=_BUILDER, maybe_placeholders=False)
    pp = parser.parser.parser.parser
    pt = pp.parse_table
    rows: dict[int, dict] = {}
    for st, acts in pt.states.items():
        d = {}
        for sym, (action, arg) in acts.items():
            if action is Shift:
                d[str(sym)] = (True, arg, 0, None)
                continue
            origin = str(arg.origin.name)
            size = len(arg.expansion)
            unit = size == 1 and ((arg.options.expand1 and arg.alias is None) or origin in _IDENTITY)
            name = str(arg.alias or origin)
            if unit:
                cb = None
            elif (getattr(_BUILDER, name, None) is not None and not arg.options.expand1
                  and not arg.options.keep_all_tokens):
                cb = name
            else:  # lark's callback: the builder's method itself for every rule of the grammar
                f = pp.callbacks[arg]
                if getattr(f, "__self__", None) is not _BUILDER:  # pragma: no cover - the table test checks
                    raise RuntimeError(f"uvl.lark: rule {name!r} has no builder method")
                cb = f.__name__
            d[str(sym)] = (False, origin, size, cb)
        rows[st] = d
    return _canonical(rows, pt.start_states["start"], pt.end_states["start"])


def _canonical(rows: dict[int, dict], start: int, end: int):
    """The table with its states numbered in breadth-first order from the start state, symbols
    in sorted order (lark numbers them in an order that changes from run to run)."""
    order = {start: 0}
    queue = [start]
    for st in queue:
        for sym in sorted(rows[st]):
            act = rows[st][sym]
            if act[0] and act[1] not in order:
                order[act[1]] = len(order)
                queue.append(act[1])
    if end not in order:  # pragma: no cover - the end state is reached by shifting $END
        order[end] = len(order)
    table: list = [None] * len(order)
    for st, k in order.items():
        d = rows.get(st, {})
        table[k] = {sym: ((True, order[d[sym][1]], 0, None) if d[sym][0] else d[sym]) for sym in sorted(d)}
    return table, order[start], order[end]


def table_module_text() -> str:
    """The text of :mod:`._uvl_table` for the current grammar (``python -m tvl_lsp.uvl.parser``
    writes it): symbol names, reductions, and each state's row as flat ``(symbol, action)``
    integer pairs, an action being the next state (shift) or ``-1 - reduction`` (small integers
    load faster than the tuples they stand for)."""
    rows, start, end = _lark_table()
    symbols = sorted({sym for d in rows for sym in d})
    sym_ix = {sym: k for k, sym in enumerate(symbols)}
    rules: list = []
    rule_ix: dict = {}
    flat = []
    for d in rows:
        row = []
        for sym, act in d.items():
            if act[0]:
                code = act[1]
            else:
                key = act[1:]
                if key not in rule_ix:
                    rule_ix[key] = len(rules)
                    rules.append(key)
                code = -1 - rule_ix[key]
            row += [sym_ix[sym], code]
        flat.append(tuple(row))
    out = ['"""The LALR table of ``grammars/uvl.lark``, as lark computes it (see :func:`.parser._tables`).',
           "Generated by ``python -m tvl_lsp.uvl.parser``; do not edit.  tests/test_uvl_table.py checks it.\"\"\"",
           "", "# flake8: noqa", f"GRAMMAR_SHA256 = {_grammar_digest()!r}", f"START = {start!r}", f"END = {end!r}",
           f"SYMBOLS = {tuple(symbols)!r}", "RULES = ("]
    out += [f"    {r!r}," for r in rules]
    out.append(")")
    out.append("ROWS = (")
    out += [f"    {r!r}," for r in flat]
    out.append(")")
    return "\n".join(out) + "\n"


class _SyntaxError(Exception):
    def __init__(self, index: int, tok: Tok, expected: set):
        self.index = index
        self.token = tok
        self.expected = expected


def _run(tokens: list[Tok], end_pos: int):
    rows, start, end = _tables()
    ss = [start]
    vs: list = []
    st = start
    n = len(tokens)
    i = 0
    while True:
        tok = tokens[i] if i < n else Tok("$END", "", end_pos, end_pos)
        ttype = tok.type
        while True:
            act = rows[st].get(ttype)
            if act is None:
                raise _SyntaxError(i, tok, {k for k in rows[st]})
            if act[0]:
                st = act[1]
                ss.append(st)
                vs.append(tok)
                break
            cb = act[3]
            if cb is None:
                st = rows[ss[-2]][act[1]][1]
                ss[-1] = st
            else:
                size = act[2]
                if size:
                    args = vs[-size:]
                    del ss[-size:]
                    del vs[-size:]
                else:
                    args = []
                vs.append(cb(args))
                st = rows[ss[-1]][act[1]][1]
                ss.append(st)
            if ttype == "$END" and st == end:
                return vs[-1]
        i += 1


# ---------------------------------------------------------------- messages

_DISPLAY = {
    "ID": "a name", "QID": "a quoted name", "INT": "an integer", "FLOAT": "a number", "STRING": "a string",
    "CARD": "a cardinality like [1..3]", "$END": "end of file", "_NL": "end of line",
    "_INDENT": "an indented block", "_DEDENT": "the end of the indented block", "OR_G": "'or'",
    "STRING_T": "'String'", "INTEGER_T": "'Integer'", "BOOLEAN_T": "'Boolean'", "REAL_T": "'Real'",
    "TYPE_KW": "'Type'", "ARITHMETIC_KW": "'Arithmetic'", "GROUP_CARD_KW": "'group-cardinality'",
    "FEATURE_CARD_KW": "'feature-cardinality'", "AGGREGATE_KW": "'aggregate-function'",
    "STRING_CONSTRAINTS_KW": "'string-constraints'",
}


def _disp(t: str) -> str:
    if t in _DISPLAY:
        return _DISPLAY[t]
    from .lexer import KEYWORDS, OPERATORS
    for table in (OPERATORS, KEYWORDS):
        for k, v in table.items():
            if v == t:
                return f"'{k}'"
    return t.lower()


_GROUP_KWS = {"OR_G", "ALTERNATIVE", "OPTIONAL", "MANDATORY", "CARD"}
_EXPR_START = {"ID", "LPAR", "NOT"}
_BIN_OPS = {"AND", "OR", "IMPLIES", "IFF"}


def _expected(exp: set) -> str:
    exp = {t for t in exp if t.isupper() or t.startswith("_") or t == "$END"}
    if _GROUP_KWS <= exp:
        rest = [_disp(t) for t in sorted(exp - _GROUP_KWS) if t in ("_DEDENT",)]
        return "a group keyword (mandatory, optional, or, alternative, [n..m])" + (" or " + rest[0] if rest else "")
    if _EXPR_START <= exp:
        return "a feature name, '!' or '('"
    if _BIN_OPS <= exp:
        rest = [_disp(t) for t in sorted(exp) if t in ("RPAR", "_NL", "COMMA", "RBRACK")]
        return "an operator (&, |, =>, <=>)" + (" or " + ", ".join(rest) if rest else "")
    names = sorted({_disp(t) for t in exp})
    if len(names) > 6:
        names = names[:6] + ["..."]
    return ", ".join(names)


def _describe(tok: Tok) -> str:
    if tok.type in ("_NL",):
        return "end of line"
    if tok.type == "_INDENT":
        return "indentation"
    if tok.type == "_DEDENT":
        return "end of the indented block"
    if tok.type == "$END":
        return "end of file"
    if tok.type in ("ID", "QID"):
        return f"name {tok.value}"
    if tok.type in ("INT", "FLOAT"):
        return f"number {tok.value}"
    if tok.type == "STRING":
        return f"string {tok.value}"
    return f"'{tok.value}'"


# ---------------------------------------------------------------- driver

def parse_lines(lines: list[Line], text: str, end_pos: int, span, path: str,
                lex_errors: tuple = ()) -> tuple[RawFile, list[SyntaxIssue]]:
    """Parse the logical lines of one file, recovering line by line.  A line with a lexical
    error (``lex_errors``: offsets, already reported) gets no syntax error of its own.
    (:func:`.fastpath.fast_parse` reads most clean files faster.)"""
    issues: list[SyntaxIssue] = []
    reported: set[int] = set()
    bad_lines = {_line_start(text, off) for off in lex_errors}
    if bad_lines:
        for i, ln in enumerate(lines):
            if any(_line_start(text, t.start) in bad_lines for t in (ln.toks[0], ln.toks[-1])) or ln.start in bad_lines:
                reported.add(i)
    tries: dict[int, int] = {}
    broken: set[str] = set()
    lines = list(lines)
    with _LOCK:
        _tables()
        for attempt in range(MAX_ERRORS * 4 + 8):
            section = _sections(lines)
            lay = layout(lines, end_pos)
            if attempt == 0:
                for li, s, e, msg in lay.problems:
                    if li not in reported:
                        issues.append(SyntaxIssue(s, e, msg))
                        reported.add(li)
            ctx = _Ctx(span, path, [])
            _BUILDER.ctx = ctx
            try:
                raw = _run(lay.tokens, end_pos)
                issues.extend(i for i in ctx.issues if not _dropped_below(i, lines))
                raw.broken_names = broken
                return raw, issues
            except _SyntaxError as ex:
                tok = ex.token
                own = lay.line_of_token
                if ex.index >= len(own) or own[ex.index] >= len(lines):
                    # at the very end: blame the last line read
                    li = max((i for i, ln in enumerate(lines) if ln.alive), default=-1)
                    if li < 0 or tries.get(li, 0) > 2:
                        issues.append(SyntaxIssue(tok.start, tok.end,
                                                  f"unexpected end of file; expected {_expected(ex.expected)}"))
                        raw = RawFile()
                        raw.broken_names = broken
                        return raw, issues
                elif tok.type == "_DEDENT" and ex.index > 0:
                    li = own[ex.index - 1]
                else:
                    li = own[ex.index]
                ln = lines[li]
                # an error on a later physical line of a line joined by an open bracket: the
                # bracket is what is wrong; split the line there and read the rest as lines
                if tok.start > ln.toks[0].start and _line_start(text, tok.start) > _line_start(text, ln.toks[0].start) \
                        and tok.type not in ("_NL", "_DEDENT", "_INDENT", "$END"):
                    cut = next(i for i, t in enumerate(ln.toks) if t.start >= _line_start(text, tok.start))
                    tail = ln.toks[cut:]
                    ln.toks = ln.toks[:cut]
                    ln.keep = None
                    extra = _split_physical(text, tail)
                    lines[li + 1:li + 1] = extra
                    reported = {i + len(extra) if i > li else i for i in reported}
                    tries = {(i + len(extra) if i > li else i): v for i, v in tries.items()}
                    section = _sections(lines)
                    if li not in reported and len(reported) < MAX_ERRORS:
                        reported.add(li)
                        opener = _unclosed(ln.toks)
                        if opener is not None:
                            issues.append(SyntaxIssue(opener.start, opener.end,
                                                      f"this '{opener.value}' is never closed on its line"))
                        else:
                            issues.append(_issue(tok, ex.expected, ln, section[li]))
                    continue
                if li not in reported:
                    reported.add(li)
                    if len(reported) <= MAX_ERRORS:
                        issues.append(_issue(tok, ex.expected, ln, section[li]))
                    elif len(reported) == MAX_ERRORS + 1:
                        issues.append(SyntaxIssue(tok.start, tok.end,
                                                  "too many syntax errors: the rest of the file is not reported"))
                k = tries.get(li, 0)
                tries[li] = k + 1
                if not _repair(ln, k, section[li]):
                    # the line is dropped: so is what is indented below it (its features, or
                    # the continuation of a constraint), without further messages
                    ln.alive = False
                    broken.update(_names(ln, section[li]))
                    j = li + 1
                    while j < len(lines) and lines[j].indent > ln.indent and section[j] == section[li]:
                        if lines[j].alive:
                            lines[j].alive = False
                            broken.update(_names(lines[j], section[j]))
                        j += 1
        issues.append(SyntaxIssue(0, 0, "the file could not be read"))
        raw = RawFile()
        raw.broken_names = broken
        return raw, issues


def _dropped_below(iss: SyntaxIssue, lines: list[Line]) -> bool:
    """An empty group whose features were dropped by the recovery (already reported)."""
    if not getattr(iss, "empty_group", False):
        return False
    for i, ln in enumerate(lines):
        if ln.toks and ln.toks[0].start == iss.start:
            return i + 1 < len(lines) and not lines[i + 1].alive and lines[i + 1].indent > ln.indent
    return False


def _line_start(text: str, off: int) -> int:
    return max(text.rfind("\n", 0, off), text.rfind("\r", 0, off)) + 1


def _split_physical(text: str, toks: list[Tok]) -> list[Line]:
    from .lexer import _width
    out: list[Line] = []
    cur_start = None
    for t in toks:
        ls = _line_start(text, t.start)
        if ls != cur_start:
            cur_start = ls
            out.append(Line(_width(text, ls), [], ls))
        out[-1].toks.append(t)
    return out


def _unclosed(toks: list[Tok]) -> Optional[Tok]:
    stack = []
    for t in toks:
        if t.type in ("LPAR", "LBRACK", "LBRACE"):
            stack.append(t)
        elif t.type in ("RPAR", "RBRACK", "RBRACE") and stack:
            stack.pop()
    return stack[0] if stack else None


def _names(ln: Line, section: str) -> set[str]:
    if section != "features":
        return set()
    k = _name_prefix(ln.toks)
    toks = ln.toks[:k]
    return {_unquote(t) for t in toks if t.type in ("ID", "QID")}


def _sections(lines: list[Line]) -> list[str]:
    """The section each line is in (by the top-level keyword above it)."""
    out = []
    cur = "header"
    for ln in lines:
        t = ln.toks[0]
        if ln.indent == 0 and t.type in ("FEATURES", "CONSTRAINTS", "IMPORTS", "INCLUDE", "NAMESPACE"):
            cur = {"FEATURES": "features", "CONSTRAINTS": "constraints", "IMPORTS": "imports",
                   "INCLUDE": "include", "NAMESPACE": "header"}[t.type]
            out.append("keyword")
            continue
        out.append(cur)
    return out


def _name_prefix(toks: list[Tok]) -> int:
    """Number of leading tokens forming ``[Type] name(.name)*``."""
    i = 0
    if toks and toks[0].type in ("STRING_T", "INTEGER_T", "BOOLEAN_T", "REAL_T") and len(toks) > 1:
        i = 1
    if i >= len(toks) or toks[i].type not in ("ID", "QID"):
        return 0
    i += 1
    while i + 1 < len(toks) and toks[i].type == "DOT" and toks[i + 1].type in ("ID", "QID"):
        i += 2
    return i


def _repair(ln: Line, attempt: int, section: str) -> bool:
    """Shorten a broken line to what can still stand (True), or give it up (False)."""
    if section == "features" and attempt == 0:
        k = _name_prefix(ln.toks)
        if 0 < k < len(ln.toks):
            ln.keep = k
            return True
        if k == 0 and ln.toks[0].type in _GROUP_KWS and len(ln.toks) > 1:
            ln.keep = 1
            return True
    return False


def _issue(tok: Tok, expected: set, ln: Line, section: str) -> SyntaxIssue:
    exp = _expected(expected)
    t = tok.type
    if t == "_INDENT":
        first = ln.toks[0]
        what = "a group keyword" if section == "features" and first.type in ("ID", "QID") else "this line"
        return SyntaxIssue(first.start, ln.toks[-1].end,
                           f"unexpected indentation: {what} is indented deeper than its block allows")
    if t == "_DEDENT":
        return SyntaxIssue(tok.start, tok.end, f"the indented block ends too early; expected {exp}")
    if t == "_NL":
        return SyntaxIssue(tok.start, tok.end, f"unexpected end of line; expected {exp}")
    if t in _GROUP_KWS and ("ID" in expected or "_DEDENT" in expected) and section == "features" \
            and "OR_G" not in expected:
        return SyntaxIssue(tok.start, tok.end,
                           f"'{tok.value}' stands where a feature is expected: indent it under the feature "
                           "whose children it groups")
    if t == "DOT" and section == "features":
        return SyntaxIssue(tok.start, tok.end, f"unexpected '.'; expected {exp}")
    if t == "QID" and "." in tok.value and section == "features":
        return SyntaxIssue(tok.start, tok.end,
                           "a quoted feature name cannot contain '.' (it separates an import's name from its features)")
    if section == "features" and t == "ID" and _GROUP_KWS & set(expected):
        import difflib
        close = difflib.get_close_matches(tok.value, ["mandatory", "optional", "or", "alternative"], n=1, cutoff=0.7)
        if close:
            return SyntaxIssue(tok.start, tok.end, f"unexpected name {tok.value}: did you mean the group keyword "
                                                   f"'{close[0]}'?")
    if section == "features" and t in ("ID", "QID") and "_NL" in expected:
        return SyntaxIssue(tok.start, tok.end,
                           f"unexpected {_describe(tok)}: one feature per line (a name with spaces is written in double quotes)")
    if t in ("INT", "FLOAT") and section == "features":
        nxt = next((x for x in ln.toks if x.start == tok.end), None)
        if nxt is not None and nxt.type in ("ID", "INT"):
            return SyntaxIssue(tok.start, nxt.end,
                               f"a feature name cannot begin with a digit: write it in double quotes "
                               f"(\"{tok.value}{nxt.value}\")")
    if section == "constraints" and t in ("AND", "OR", "GT"):
        prev = next((x for x in ln.toks if x.end == tok.start), None)
        if prev is not None and prev.type == t and t in ("AND", "OR"):
            op = "&" if t == "AND" else "|"
            return SyntaxIssue(prev.start, tok.end, f"UVL writes '{op}', not '{op}{op}'")
        if prev is not None and t == "GT" and prev.type == "MINUS":
            return SyntaxIssue(prev.start, tok.end, "UVL writes an implication '=>', not '->'")
    if t in ("INT", "FLOAT") and tok.value.startswith("-") and section == "constraints":
        return SyntaxIssue(tok.start, tok.end,
                           f"unexpected number {tok.value}: UVL reads '-' glued to a number as its sign; "
                           "put a space after '-' to subtract")
    return SyntaxIssue(tok.start, tok.end, f"unexpected {_describe(tok)}; expected {exp}")


if __name__ == "__main__":  # pragma: no cover - regenerates the stored table
    import os
    from ..base.safewrite import write_files
    here = os.path.dirname(os.path.abspath(__file__))
    write_files(here, {"_uvl_table.py": table_module_text()}, within=[here])
