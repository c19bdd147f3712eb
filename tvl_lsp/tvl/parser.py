"""Syntax: lark LALR over the tokens of :mod:`.lexer`, building raw declarations and model
expressions inline (no parse tree), with error recovery.

lark builds the LALR(1) table from ``grammars/tvl.lark`` and the callbacks; a lean driver
(:func:`_run_lalr`) runs it over our own tokens (lark's generic loop is several times slower on
this grammar's long chains of unit rules).

Recovery: on a syntax error the statement around the offending token (back to the previous
``;``/``{``/``}`` of the same brace level, forward to the next ``;`` of that level) is dropped
and the token list is parsed again; a missing ``,``/``;`` between two names is reported and
supplied, as is a missing ``}`` at the end of the file.  Each error is reported once and
everything else is still built.  The work is bounded: past a budget, the rest of the file
after the last error is given up (and said so).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Optional

from lark import Lark, Transformer
from lark.lexer import Lexer

from bisect import bisect_right as _bisect_right

from ..base.text import LineIndex, Pos, Span, fast_span, single_file_span
from . import model as m
from .lexer import Tok
from .raw import (RawAttr, RawBody, RawChild, RawConst, RawConstraint, RawData, RawFeatureDecl, RawGroup, RawType,
                  SyntaxIssue)
from .recovery import (_DECL_START, _block_range, _declaration_head, _find, _item_range, _missing_braces,
                       _prev_alive, _separator, _statement_range)

MAX_CHAIN = 5000  # terms of a flat `a && b && ...` / `a || b || ...` chain
MAX_DEPTH = 200  # expression / feature nesting handled (deeper input is reported, not crashed on)


def _grammar_text() -> str:
    from ..base.files import package_text
    return package_text("grammars", "tvl.lark")


# ---------------------------------------------------------------- lark plumbing

class _ListLexer(Lexer):
    """Placeholder lexer: lark only builds the table and callbacks here; the tokens come from
    :mod:`.lexer` and are fed by :func:`_run_fast` / :func:`_run_lalr`."""

    def __init__(self, lexer_conf):
        pass

    def lex(self, data, *_):  # pragma: no cover - never used
        return iter(getattr(data, "tokens", ()))


def _s(x) -> int:
    if isinstance(x, Tok):
        return x.start
    return x._s


def _e(x) -> int:
    if isinstance(x, Tok):
        return x.end
    return x._e


def _tok(t: Tok) -> Tok:
    return t


class _Builder(Transformer):
    """Inline callbacks: expressions become model Expr objects, declarations Raw* objects."""

    def __init__(self):
        super().__init__(visit_tokens=False)
        self.ctx: "_Ctx" = None  # set per parse

    # -- helpers
    def _mk(self, node: m.Expr, s: int, e: int, depth: int) -> m.Expr:
        ctx = self.ctx
        if depth > MAX_DEPTH:
            if not ctx.too_deep:
                ctx.too_deep = True
                ctx.issues.append(SyntaxIssue("nesting-too-deep", s, e,
                                              f"expression nested more than {MAX_DEPTH} levels deep; it is not analysed"))
            node = m.BoolLit(True)
            depth = 0
            node.too_deep = True
        node.span = ctx.smap.span(s, e)
        node.path = ctx.smap.path(s)
        node._s = s
        node._e = e
        node._d = depth
        return node

    @staticmethod
    def _d(x) -> int:
        return getattr(x, "_d", 0)

    # -- lists (left-recursive rules, appended in place)
    @staticmethod
    def _list(c):
        if len(c) == 1 or (len(c) == 2 and isinstance(c[0], Tok)):  # first element (cond_list: COMMA x)
            return [c[-1]]
        lst = c[0]
        lst.append(c[-1])
        return lst

    def item_list(self, c):
        return self._list(c)

    def field_list(self, c):
        return self._list(c)

    def body_list(self, c):
        return self._list(c)

    def ref_list(self, c):
        return self._list(c)

    def data_list(self, c):
        return self._list(c)

    def cond_list(self, c):
        return self._list(c)

    # -- expressions
    def int_lit(self, c):
        t = c[0]
        return self._mk(m.IntLit(int(t.value)), t.start, t.end, 1)

    def real_lit(self, c):
        t = c[0]
        return self._mk(m.RealLit(float(t.value), text=str(t.value)), t.start, t.end, 1)

    def bool_lit(self, c):
        t = c[0]
        return self._mk(m.BoolLit(t.type == "TRUE"), t.start, t.end, 1)

    def long_id(self, c):
        # head | long_id DOT tail: the list of name tokens, built in place
        if len(c) == 1:
            return [c[0]]
        lst = c[0]
        lst.append(c[2])
        return lst

    def head(self, c):
        return c[0]

    def tail(self, c):
        return c[0]

    def name(self, c):
        toks = c[0]
        ctx = self.ctx
        idx = ctx.smap
        part_spans = [idx.span(t.start, t.end) for t in toks]
        node = m.Name([t.value for t in toks], part_spans=part_spans)
        if len(toks) == 1:  # the common case: reuse the part's span
            t = toks[0]
            node.span = part_spans[0]
            node.path = idx.path(t.start)
            node._s = t.start
            node._e = t.end
            node._d = 1
            return node
        return self._mk(node, toks[0].start, toks[-1].end, 1)

    def paren(self, c):
        inner = c[1]
        node = self._mk(inner, c[0].start, c[2].end, self._d(inner) + 1)
        node.parens = getattr(inner, "parens", 0) + 1
        return node

    def binop(self, c):
        left, op, right = c
        d = max(self._d(left), self._d(right)) + 1
        if (str(op.value) in ("&&", "||") and isinstance(left, m.Binary) and left.op == str(op.value)
                and not getattr(left, "too_deep", False)):
            # a flat chain `a || b || c ...` (generated models have long ones) is not nesting:
            # what follows the parser walks such chains without recursion (up to MAX_CHAIN terms)
            n = getattr(left, "_n", 2) + 1
            d = max(self._d(left), self._d(right) + 1) if n <= MAX_CHAIN else MAX_DEPTH + 1
            node = self._mk(m.Binary(str(op.value), left, right), _s(left), _e(right), d)
            node._n = n
            return node
        return self._mk(m.Binary(str(op.value), left, right), _s(left), _e(right), d)

    def unop(self, c):
        op, operand = c
        return self._mk(m.Unary(str(op.value), operand), op.start, _e(operand), self._d(operand) + 1)

    def ternary(self, c):
        cond, _q, then, _c, other = c
        d = max(self._d(cond), self._d(then), self._d(other)) + 1
        return self._mk(m.Ternary(cond, then, other), _s(cond), _e(other), d)

    def abs_e(self, c):
        inner = c[2]
        return self._mk(m.Unary("abs", inner), c[0].start, c[3].end, self._d(inner) + 1)

    def agg_func(self, c):
        return c[0]

    def sel(self, c):
        return c[0]

    def expr_list(self, c):
        return self._list(c)

    def agg_list(self, c):
        f, _l, args, r = c
        d = max((self._d(a) for a in args), default=0) + 1
        return self._mk(m.Aggregate(str(f.value), args=args), f.start, r.end, d)

    def agg_over(self, c):
        f, _l, sel, _dot, attr, r = c
        over = "children" if sel.type == "CHILDREN" else "selectedChildren"
        node = m.Aggregate(str(f.value), over=over, attr=str(attr.value),
                           attr_span=self.ctx.smap.span(attr.start, attr.end))
        node.sel_span = self.ctx.smap.span(sel.start, sel.end)
        node.sel_text = str(sel.value)
        return self._mk(node, f.start, r.end, 1)

    def agg_count(self, c):
        f, _l, sel, r = c
        over = "children" if sel.type == "CHILDREN" else "selectedChildren"
        node = m.Aggregate("count", over=over)
        node.sel_span = self.ctx.smap.span(sel.start, sel.end)
        node.sel_text = str(sel.value)
        return self._mk(node, f.start, r.end, 1)

    def set_lit(self, c):
        l, items, r = c
        d = max((self._d(a) for a in items), default=0) + 1
        return self._mk(m.SetLit(items), l.start, r.end, d)

    def range_hi(self, c):
        x = c[0]
        if isinstance(x, Tok):  # '*'
            node = m.Name(["*"], part_spans=[self.ctx.smap.span(x.start, x.end)])
            node.star = True
            return self._mk(node, x.start, x.end, 1)
        return x

    def range_lit(self, c):
        l, lo, _dd, hi, r = c
        d = max(self._d(lo), self._d(hi)) + 1
        return self._mk(m.RangeLit(lo, hi), l.start, r.end, d)

    # -- attributes
    def attr_type(self, c):
        return c[0]

    def attr_is(self, c):
        return ("is", c[1], c[0])

    def attr_in(self, c):
        return ("in", c[1], c[0])

    def cond_in(self, c):
        kind, val, kw = c[2]
        return ("ifin", kind, val, c[0])

    def cond_out(self, c):
        kind, val, kw = c[2]
        return ("ifout", kind, val, c[0])

    def attr_body(self, c):
        out = []
        for x in c:
            if isinstance(x, list):
                out.extend(x)
            else:
                out.append(x)
        return out

    def _fill(self, a: RawAttr, parts):
        seen = set()
        for p in parts:
            if p[0] in ("is", "in"):
                slot = "value" if p[0] == "is" else "domain"
                kwt = p[2]
            else:
                slot = ("if_in_" if p[0] == "ifin" else "if_out_") + ("value" if p[1] == "is" else "domain")
                kwt = p[3]
            if slot in seen or getattr(a, slot) is not None:
                a.dup_parts.append((slot, kwt.start, _e(p[2] if p[0] in ("is", "in") else p[2])))
                continue
            seen.add(slot)
            setattr(a, slot, p[1] if p[0] in ("is", "in") else p[2])

    def attr_decl(self, c):
        ty, name, body, semi = c
        a = RawAttr(_tok(ty), _tok(name), ty.start, semi.end)
        self._fill(a, body)
        return a

    def field_ref(self, c):
        name, body, semi = c
        a = RawAttr(Tok("ID", "", name.start, name.start), _tok(name), name.start, semi.end)
        self._fill(a, body)
        return a

    def struct_attr(self, c):
        ty, name, _l = c[0], c[1], c[2]
        r = c[-1]
        refs = c[3] if len(c) == 5 else []
        a = RawAttr(_tok(ty), _tok(name), ty.start, r.end, refinements=refs)
        return a

    # -- constraints / data
    def constraint_plain(self, c):
        return RawConstraint("plain", c[0], _s(c[0]), c[1].end)

    def constraint_in(self, c):
        return RawConstraint("ifIn", c[2], c[0].start, c[3].end)

    def constraint_out(self, c):
        return RawConstraint("ifOut", c[2], c[0].start, c[3].end)

    def data_entry(self, c):
        k, v = c[0], c[1]
        return (k.value[1:-1], v.value[1:-1], k.start, c[-1].end)

    def data_block(self, c):
        entries = c[2] if len(c) == 4 else []
        return RawData(entries, c[0].start, c[-1].end)

    # -- groups and features
    def bound(self, c):
        return c[0]

    def card_kw(self, c):
        t = c[0]
        kind = {"ONEOF": "oneOf", "SOMEOF": "someOf", "ALLOF": "allOf"}[t.type]
        return (kind, t.start, t.end, None, None)

    def card_range(self, c):
        l, lo, _d, hi, r = c
        return ("card", l.start, r.end, _tok(lo), _tok(hi))

    def children(self, c):
        return self._list(c)

    def child_decl(self, c):
        opt = bool(c and isinstance(c[0], Tok) and c[0].type == "OPT")
        rest = c[1:] if opt else c
        parts = rest[0]
        body = rest[1] if len(rest) > 1 else None
        start = c[0].start if opt else parts[0].start
        end = body.end if body is not None else parts[-1].end
        depth = (body.depth + 1) if body is not None else 1
        if depth > MAX_DEPTH:
            ctx = self.ctx
            if not ctx.too_deep:
                ctx.too_deep = True
                ctx.issues.append(SyntaxIssue("nesting-too-deep", start, end,
                                              f"features nested more than {MAX_DEPTH} levels deep; the deeper ones are not analysed"))
            body = None
            depth = 1
        return RawChild(opt, False, parts, body, start, end, depth)

    def child_shared(self, c):
        opt = c[0].type == "OPT"
        rest = c[1:] if opt else c
        parts = rest[1]
        return RawChild(opt, True, parts, None, c[0].start, parts[-1].end, 1)

    def group_decl(self, c):
        g, card, _l, children, r = c
        kind, ks, ke, lo, hi = card
        return RawGroup(kind, ks, ke, lo, hi, children, g.start, r.end)

    def body(self, c):
        items = c[1] if len(c) == 3 else []
        depth = max((ch.depth for it in items if isinstance(it, RawGroup) for ch in it.children), default=0)
        return RawBody(items, c[0].start, c[-1].end, depth)

    def body_group(self, c):
        g = c[0]
        depth = max((ch.depth for ch in g.children), default=0)
        return RawBody([g], g.start, g.end, depth)

    def root_decl(self, c):
        root, ids, body = c
        parts = ids
        return RawFeatureDecl(True, _tok(root), parts, body, root.start, body.end)

    def reopen_decl(self, c):
        ids, body = c
        parts = ids
        return RawFeatureDecl(False, None, parts, body, parts[0].start, body.end)

    def type_kw(self, c):
        return c[0]

    def struct_field(self, c):
        return c[0]

    def type_simple(self, c):
        kw, name = c[0], c[1]
        dom = c[3] if len(c) == 5 else None
        return RawType(_tok(kw), _tok(name), dom, [], kw.start, c[-1].end)

    def type_struct(self, c):
        kw, name = c[0], c[1]
        fields = c[3] if len(c) == 5 else []
        return RawType(_tok(kw), _tok(name), None, fields, kw.start, c[-1].end)

    def const_decl(self, c):
        _k, ty, name, val, semi = c
        return RawConst(_tok(ty), _tok(name), val, _k.start, semi.end)

    def start(self, c):
        return c[0] if c else []


@dataclass
class _Ctx:
    smap: "SourceMap"
    issues: list[SyntaxIssue]
    too_deep: bool = False


# the hot-path Span makers live in base.text (the UVL front end uses them without this parser)
_span = fast_span
_single_file_span = single_file_span


class SourceMap:
    """Global offsets over several files (``include`` splices files textually): file ``k``'s
    text occupies ``[base_k, base_k + len)`` of one virtual address space."""

    def __init__(self):
        self.bases: list[int] = []
        self.paths: list[str] = []
        self.indexes: list[LineIndex] = []
        self.next_base = 0

    def add(self, path: str, text: str) -> int:
        base = self.next_base
        self.bases.append(base)
        self.paths.append(path)
        self.indexes.append(LineIndex(text))
        self.next_base = base + len(text) + 1
        if len(self.bases) == 1:  # specialised hot paths for the one-file case
            self.span = _single_file_span(self.indexes[0])
            only = path
            self.path = lambda off: only
        else:
            self.__dict__.pop("span", None)
            self.__dict__.pop("path", None)
        return base

    def _k(self, off: int) -> int:
        if len(self.bases) == 1:
            return 0
        return max(0, _bisect_right(self.bases, off) - 1)

    def path(self, off: int) -> str:
        paths = self.paths
        if len(paths) == 1:
            return paths[0]
        return paths[self._k(off)] if paths else ""

    def span(self, s: int, e: int) -> Span:
        if len(self.bases) == 1:
            # one file: the hot path
            idx = self.indexes[0]
            starts = idx.starts
            n = len(idx.text)
            if s > n:
                s = n
            if e < s:
                e = s
            elif e > n:
                e = n
            l1 = _bisect_right(starts, s) - 1
            if l1 + 1 >= len(starts) or e < starts[l1 + 1]:
                return _span(l1, s - starts[l1], l1, e - starts[l1])
            l2 = _bisect_right(starts, e) - 1
            return _span(l1, s - starts[l1], l2, e - starts[l2])
        k = self._k(s)
        base = self.bases[k]
        if e < s or self._k(e) != k:
            e = base + len(self.indexes[k].text)
        idx = self.indexes[k]
        starts = idx.starts
        n = len(idx.text)
        s -= base
        e -= base
        if s < 0:
            s = 0
        elif s > n:
            s = n
        if e < s:
            e = s
        elif e > n:
            e = n
        l1 = _bisect_right(starts, s) - 1
        # most spans sit on one line
        if l1 + 1 >= len(starts) or e < starts[l1 + 1]:
            return _span(l1, s - starts[l1], l1, e - starts[l1])
        l2 = _bisect_right(starts, e) - 1
        return _span(l1, s - starts[l1], l2, e - starts[l2])

    def end_of(self, k: int = 0) -> int:
        return self.bases[k] + len(self.indexes[k].text)


_LOCK = threading.Lock()
_BUILDER = _Builder()
_PARSER: Optional[Lark] = None


def _parser() -> Lark:
    global _PARSER
    if _PARSER is None:
        _PARSER = Lark(_grammar_text(), parser="lalr", lexer=_ListLexer, transformer=_BUILDER,
                       maybe_placeholders=False)
    return _PARSER


_DISPLAY = {v: f"'{k}'" for k, v in __import__("tvl_lsp.tvl.lexer", fromlist=["OPERATORS"]).OPERATORS.items()}
_DISPLAY.update({"ID": "a name", "INT": "an integer", "REAL": "a real number", "STRING": "a string",
                 "$END": "end of file", "INTK": "'int'", "REALK": "'real'", "ANDAGG": "'and'",
                 "ORAGG": "'or'", "XORAGG": "'xor'", "SCHILDREN": "'selectedChildren'",
                 "ONEOF": "'oneOf'", "SOMEOF": "'someOf'", "ALLOF": "'allOf'", "IFIN": "'ifIn'",
                 "IFOUT": "'ifOut'"})


def _disp(t: str) -> str:
    return _DISPLAY.get(t, f"'{t.lower()}'")


_EXPR_START = {"INT", "ID", "LPAR", "NOT", "TRUE"}
_OPERATORS = {"EQ", "NEQ", "AND", "OR", "IMPLIES", "PLUS", "TIMES", "GEQ"}
_PUNCT = ("SEMI", "COMMA", "RPAR", "RBRACE", "RBRACK", "COLON", "LBRACE", "QUEST", "DOTDOT")


def _expected(exp) -> str:
    exp = set(exp)
    if _EXPR_START <= exp:
        rest = [_disp(t) for t in sorted(exp) if t in ("RBRACE", "IFIN", "IFOUT", "GROUP", "DATA", "RPAR")]
        return "an expression" + (" or " + ", ".join(rest) if rest and len(rest) < 4 else "")
    if _OPERATORS <= exp:
        rest = [_disp(t) for t in _PUNCT if t in exp]
        return "an operator" + (" or " + ", ".join(rest) if rest else "")
    names = sorted({_disp(t) for t in exp})
    if len(names) > 6:
        names = names[:6] + ["..."]
    return ", ".join(names)


class _SyntaxError(Exception):
    def __init__(self, tok: Tok, expected: set):
        self.token = tok
        self.expected = expected


_TABLES = None
# rules whose callback returns its single child unchanged
_IDENTITY = {"head", "tail", "type_kw", "attr_type", "bound", "struct_field", "agg_func", "sel"}


def _tables():
    """lark's LALR table, re-keyed for a lean driver loop (lark's own ``feed_token`` spends most
    of its time in ``Token.__eq__``/``Rule.__eq__`` on this grammar)."""
    global _TABLES
    if _TABLES is None:
        from lark.parsers.lalr_analysis import Shift
        pp = _parser().parser.parser.parser
        pt = pp.parse_table
        cbs = pp.callbacks
        states = {}
        for st, acts in pt.states.items():
            d = {}
            for sym, (action, arg) in acts.items():
                if action is Shift:
                    d[str(sym)] = (True, arg, 0, None)
                else:
                    origin = str(arg.origin.name)
                    size = len(arg.expansion)
                    unit = size == 1 and ((arg.options.expand1 and arg.alias is None) or origin in _IDENTITY)
                    # call our builder method directly (lark's wrappers only filter what this
                    # grammar never has: anonymous tokens and placeholders)
                    meth = getattr(_BUILDER, str(arg.alias or origin), None)
                    if unit:
                        cb = None
                    elif (meth is not None and not arg.options.expand1 and not arg.options.keep_all_tokens
                          and not any(str(x.name).startswith("_") for x in arg.expansion)):
                        cb = meth
                    else:
                        cb = cbs[arg]
                    d[str(sym)] = (False, origin, size, cb)
            states[st] = d
        rows = [None] * (max(states) + 1)
        for st, d in states.items():
            rows[st] = d
        _TABLES = (rows, pt.start_states["start"], pt.end_states["start"])
    return _TABLES


def _run_fast(tokens: list[Tok], end_pos: int):
    """The hot loop: LALR over ``tokens`` then $END; raises _SyntaxError."""
    rows, start, end = _tables()
    ss = [start]
    vs: list = []
    push_s = ss.append
    push_v = vs.append
    st = start
    for tok in tokens:
        ttype = tok.type
        while True:
            act = rows[st].get(ttype)
            if act is None:
                raise _SyntaxError(tok, {k for k in rows[st] if k.isupper()})
            if act[0]:
                st = act[1]
                push_s(st)
                push_v(tok)
                break
            cb = act[3]
            if cb is None:
                st = rows[ss[-2]][act[1]][1]
                ss[-1] = st
                continue
            size = act[2]
            if size:
                args = vs[-size:]
                del ss[-size:]
                del vs[-size:]
            else:
                args = []
            push_v(cb(args))
            st = rows[ss[-1]][act[1]][1]
            push_s(st)
    tok = Tok("$END", "", end_pos, end_pos)
    while True:
        act = rows[st].get("$END")
        if act is None or act[0]:
            raise _SyntaxError(tok, {k for k in rows[st] if k.isupper()})
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
            push_v(cb(args))
            st = rows[ss[-1]][act[1]][1]
            push_s(st)
        if st == end:
            return vs[-1]


def _run_lalr(tokens: list[Tok], end_pos: int, panic: bool = False):
    """Run the LALR table over ``tokens``.  With ``panic``, a token that cannot be used is
    skipped (and at the end, missing ';' / '}' are supplied) instead of raising."""
    states, start, end = _tables()
    ss = [start]
    vs: list = []
    end_tok = Tok("$END", "", end_pos, end_pos)
    stream = tokens + [end_tok]
    i = 0
    fixes = 0
    while i < len(stream):
        tok = stream[i]
        i += 1
        ttype = tok.type
        while True:
            row = states[ss[-1]]
            act = row.get(ttype)
            if act is None and panic:
                if ttype != "$END":
                    break  # skip this token
                fixes += 1
                for fill in ("SEMI", "RBRACE", "RPAR", "RBRACK"):
                    if fill in row and fixes < 1000:
                        i -= 1  # feed the filler, then $END again
                        stream.insert(i, Tok(fill, "", end_pos, end_pos))
                        break
                else:
                    return []
                break
            if act is None:
                raise _SyntaxError(tok, {k for k in row if k.isupper()})
            if act[0]:
                ss.append(act[1])
                vs.append(tok)
                break
            cb = act[3]
            if cb is None:  # unit rule whose value is its child: only the state changes
                ss[-1] = states[ss[-2]][act[1]][1]
                if ttype == "$END" and ss[-1] == end:
                    return vs[-1]
                continue
            size = act[2]
            if size:
                args = vs[-size:]
                del ss[-size:]
                del vs[-size:]
            else:
                args = []
            vs.append(cb(args))
            ss.append(states[ss[-1]][act[1]][1])
            if ttype == "$END" and ss[-1] == end:
                return vs[-1]


_CLOSERS = frozenset({"RBRACE", "RPAR", "RBRACK", "SEMI"})
def _in_set(toks, depth, k) -> bool:
    """Token ``k`` is inside the braces of a set (`in {1, 2}`)."""
    j = k - 1
    while j >= 0 and not (toks[j].type == "LBRACE" and depth[j] == depth[k] - 1):
        j -= 1
    return j > 0 and toks[j - 1].type == "IN"


def parse_tokens(toks: list[Tok], smap: "SourceMap") -> tuple[list, list[SyntaxIssue]]:
    """Parse ``toks`` (from :func:`tokenize`), recovering from syntax errors."""
    issues: list[SyntaxIssue] = []
    toks = _missing_braces(toks, smap, issues)
    depth = []
    d = 0
    for t in toks:
        if t.type == "RBRACE":
            d = max(0, d - 1)
        depth.append(d)
        if t.type == "LBRACE":
            d += 1
    alive = [True] * len(toks)
    extra: list[Tok] = []
    last_err = None
    last_drop = None
    patched: set[int] = set()
    toks = list(toks)
    end_pos = toks[-1].end if toks else 0
    ctx = _Ctx(smap, [])
    budget = max(3 * len(toks), 1_500_000)  # tokens fed over all attempts
    gave_up = False
    with _LOCK:
        _tables()
        for _attempt in range(62):
            if (_attempt >= 60 or budget <= 0) and not gave_up and last_drop is not None:
                # too many errors: keep what precedes the last one, give up the rest
                gave_up = True
                a = min(last_drop + 1, len(toks) - 1)
                issues.append(SyntaxIssue("syntax-error", toks[a].start, toks[a].end,
                                          "too many syntax errors: from here on, what cannot be "
                                          "understood is skipped without further messages"))
                budget = 0
                continue
            elif _attempt >= 60 or budget <= 0:
                # last resort, one pass that skips what it cannot use
                ctx = _Ctx(smap, [])
                _BUILDER.ctx = ctx
                feed = [t for t, a in zip(toks, alive) if a]
                try:
                    items = _run_lalr(feed, end_pos, panic=True)
                except Exception:  # pragma: no cover - defensive
                    items = []
                issues.extend(ctx.issues)
                return items, issues
            ctx = _Ctx(smap, [])
            _BUILDER.ctx = ctx
            feed = (toks if all(alive) else [t for t, a in zip(toks, alive) if a]) + extra
            budget -= len(feed)
            try:
                items = _run_fast(feed, end_pos)
                issues.extend(ctx.issues)
                return items, issues
            except _SyntaxError as e:
                tok = e.token
                if tok.type == "$END":
                    if extra:
                        break
                    issues.append(SyntaxIssue("syntax-error", toks[-1].start if toks else 0, end_pos,
                                              f"unexpected end of file; expected {_expected(e.expected)}"
                                              + (f" (missing {d} '}}')" if d else "")))
                    if d:
                        extra = [Tok("RBRACE", "}", end_pos, end_pos) for _ in range(d)]
                        continue
                    break
                k = _find(toks, tok)
                if k is None:
                    break
                at = (tok.start, tok.end)
                if tok.type == "RBRACE" and "SEMI" in e.expected:
                    msg = "missing ';' before '}'"
                elif tok.type in ("ANDAGG", "ORAGG"):
                    msg = (f"unexpected '{tok.value}': here it can only be the aggregate function "
                           f"{tok.value}(...); use {'&&' if tok.type == 'ANDAGG' else '||'}")
                elif (tok.type in ("ID", "OPT", "SHARED") and k > 0 and toks[k - 1].type in ("ID", "RBRACE")
                      and ("COMMA" in e.expected or "SEMI" in e.expected)):
                    msg = f"unexpected '{tok.value}': is a ',' or ';' missing before it?"
                elif (tok.type in ("ALLOF", "ONEOF", "SOMEOF") and k > 0 and toks[k - 1].type == "ID"
                      and toks[k - 1].value.lower() != "group"
                      and sorted(toks[k - 1].value.lower()) == sorted("group")):
                    msg = f"'{toks[k - 1].value}' is not a keyword: is it a misspelt 'group'?"
                    at = (toks[k - 1].start, toks[k - 1].end)
                    if (k - 1) not in patched and alive[k - 1]:
                        # read it as the 'group' it means: dropping the group would leave its
                        # children undeclared, and every reopening of them an error
                        patched.add(k - 1)
                        issues.append(SyntaxIssue("syntax-error", at[0], at[1], msg))
                        toks[k - 1] = Tok("GROUP", toks[k - 1].value, toks[k - 1].start, toks[k - 1].end)
                        last_err = None
                        continue
                elif tok.type in ("INT", "REAL") and tok.value.startswith("-"):
                    msg = (f"unexpected number '{tok.value}': TVL reads '-' glued to a number as its sign; "
                           f"put a space after '-' to subtract")
                else:
                    what = (f"'{tok.value}'" if tok.type not in ("ID", "INT", "REAL", "STRING")
                            else f"{_disp(tok.type).split(' ', 1)[-1]} '{tok.value}'")
                    msg = f"unexpected {what}; expected {_expected(e.expected)}"
                jc = _prev_alive(alive, k)
                if (tok.type in ("RBRACE", "RPAR", "RBRACK") and tok.value and jc is not None
                        and toks[jc].type == "COMMA" and toks[jc].value and jc not in patched):
                    # '{ A, B, }': a ',' with nothing after it; the list before it is fine
                    patched.add(jc)
                    issues.append(SyntaxIssue("syntax-error", tok.start, tok.end,
                                              f"unexpected '{tok.value}' after ',': remove the ',' at the end of "
                                              f"the list"))
                    alive[jc] = False
                    last_err = None
                    continue
                if (tok.type in _DECL_START and jc is not None and k not in patched
                        and toks[jc].type in ("RBRACK", "INT", "REAL", "ID", "TRUE", "FALSE", "RPAR")
                        and "SEMI" in e.expected):
                    # 'int w in [1..3] int h ...': the ';' ending the declaration before is missing
                    patched.add(k)
                    issues.append(SyntaxIssue("syntax-error", toks[jc].start, toks[jc].end,
                                              f"missing ';' after '{toks[jc].value}'"))
                    toks.insert(k, Tok("SEMI", "", toks[jc].end, toks[jc].end))
                    depth.insert(k, depth[k])
                    alive.insert(k, True)
                    patched = {i + 1 if i >= k else i for i in patched}
                    last_err = None
                    continue
                if tok.type == "RBRACE" and k > 0 and toks[k - 1].type == "SEMI" and "STRING" in e.expected \
                        and (k - 1) not in patched and toks[k - 1].value:
                    # data { "k" "v"; }: the reference takes no ';' after the last entry
                    patched.add(k - 1)
                    issues.append(SyntaxIssue("reference-rejects", toks[k - 1].start, toks[k - 1].end,
                                              "';' after the last entry of a data block: tvl-lsp reads it, but "
                                              "the TVL reference parser rejects it (TVL separates entries with ';')"))
                    alive[k - 1] = False
                    last_err = None
                    continue
                if tok.type == "STRING" and k > 0 and toks[k - 1].type == "STRING" and "SEMI" in e.expected \
                        and k not in patched:
                    patched.add(k)
                    issues.append(SyntaxIssue("syntax-error", tok.start, tok.end,
                                              "missing ';' between two entries of a data block"))
                    toks.insert(k, Tok("SEMI", "", tok.start, tok.start))
                    depth.insert(k, depth[k])
                    alive.insert(k, True)
                    patched = {i + 1 if i >= k else i for i in patched}
                    last_err = None
                    continue
                j = _prev_alive(alive, k)
                if (j is not None and k not in patched and tok.type != "$END"
                        and ("SEMI" in e.expected or "COMMA" in e.expected)
                        and toks[j].type not in ("SEMI", "COMMA", "LBRACE", "LPAR", "LBRACK")
                        and toks[j].value != ""
                        and smap.span(toks[j].end, tok.start).start.line < smap.span(toks[j].end, tok.start).end.line):
                    # the line before ends without its ';' (or ','): report it where it is missing,
                    # at the end of that line, and read on as if it were there
                    sep = _separator(toks, depth, alive, k, e.expected)
                    mark = ';' if sep == "SEMI" else ','
                    prev = toks[j]
                    patched.add(k)
                    what = prev.value if len(prev.value) <= 30 else prev.value[:27] + "..."
                    issues.append(SyntaxIssue("syntax-error", prev.start, prev.end,
                                              f"missing '{mark}' after '{what}' at the end of the line"))
                    toks.insert(k, Tok(sep, "", prev.end, prev.end))
                    depth.insert(k, depth[k])
                    alive.insert(k, True)
                    patched = {i + 1 if i >= k else i for i in patched}
                    last_err = None
                    continue
                if tok.type == "RBRACE" and "SEMI" in e.expected and k not in patched and k > 0 \
                        and toks[k - 1].type != "SEMI":
                    # 'B -> C }': the ';' is missing, not the statement: supply it (dropping the
                    # statement would drop the block around it and cascade)
                    patched.add(k)
                    issues.append(SyntaxIssue("syntax-error", tok.start, tok.end, msg))
                    toks.insert(k, Tok("SEMI", "", tok.start, tok.start))
                    depth.insert(k, depth[k])
                    alive.insert(k, True)
                    patched = {i + 1 if i >= k else i for i in patched}
                    last_err = None
                    continue
                if k not in patched and k > 0 and (
                        (tok.type in ("ID", "OPT", "SHARED") and toks[k - 1].type in ("ID", "RBRACE")
                         and ("COMMA" in e.expected or "SEMI" in e.expected))
                        or (tok.type in ("INT", "REAL", "ID") and toks[k - 1].type in ("INT", "REAL", "ID")
                            and "COMMA" in e.expected and _in_set(toks, depth, k))):  # in {1 2}
                    # a missing separator: report it and read it as if it were there
                    sep = "COMMA" if "COMMA" in e.expected else "SEMI"
                    patched.add(k)
                    issues.append(SyntaxIssue("syntax-error", tok.start, tok.end,
                                              f"missing '{',' if sep == 'COMMA' else ';'}' before '{tok.value}'"))
                    toks.insert(k, Tok(sep, "", tok.start, tok.start))
                    depth.insert(k, depth[k])
                    alive.insert(k, True)
                    patched = {i + 1 if i >= k else i for i in patched}
                    last_err = None
                    continue
                # a '}' right after what we dropped is an artefact of the drop (e.g. a group left
                # empty): drop the enclosing construct instead, without a second report
                cascade = (tok.type == "RBRACE" and last_drop is not None and last_drop < k
                           and not any(alive[last_drop + 1:k]))
                # likewise a closer or ';' right after a drop inside brackets ('{1 2};'): the statement
                # around it is what is left of the reported mistake
                cascade = cascade or (tok.type in _CLOSERS and last_drop is not None and last_drop < k
                                      and all(toks[i].type in _CLOSERS for i in range(last_drop + 1, k) if alive[i]))
                synthetic = tok.value == "" and tok.type in ("COMMA", "SEMI")
                if last_err != k and not cascade and not synthetic:
                    issues.append(SyntaxIssue("syntax-error", at[0], at[1], msg))
                if tok.type == "RBRACE":
                    a, b = _block_range(toks, depth, k)
                else:
                    a, b = _statement_range(toks, depth, alive, k)
                if last_err == k or not any(alive[a:b + 1]):
                    a, b = _item_range(toks, depth, alive, k)
                elif tok.type != "RBRACE":
                    keep = _declaration_head(toks, depth, alive, a, b, k)
                    if keep:  # keep 'TYPE NAME ;': its uses further down are not unknown names
                        last_err = k
                        last_drop = b
                        for i in range(a, b + 1):
                            if i not in keep:
                                alive[i] = False
                        continue
                last_err = k
                last_drop = b
                for i in range(a, b + 1):
                    alive[i] = False
        issues.extend(ctx.issues)
        return [], issues
