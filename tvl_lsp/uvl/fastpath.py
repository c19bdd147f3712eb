"""The UVL parser's fast path for clean files: the feature tree built straight from the lines'
indentation.  In a big model the tree is nearly all of the file, and nearly all of its lines are
one name; the LALR driver spends most of its time on them.

:func:`fast_parse` is tried first on a file without lexical errors; anything it does not take
sends the file to the general path (:func:`.parser.parse_lines` and its line recovery), which
then reads it from scratch.  tests/test_uvl_fastpath.py checks both give the same on random texts.
"""

from __future__ import annotations

from typing import Optional

from .lexer import Line, Tok, layout
from .parser import (_BUILDER, _GROUP_KWS, _LOCK, RawConstraint, RawFeature, RawFile, RawGroup, RawRef, _Ctx, _run,
                     _SyntaxError, _tables)

_SYN_FEATURES = Tok("FEATURES", "features", 0, 0)
_SYN_NL = Tok("_NL", "", 0, 0)
_SYN_INDENT = Tok("_INDENT", "", 0, 0)
_SYN_DEDENT = Tok("_DEDENT", "", 0, 0)
_SYN_CONSTRAINTS = Tok("CONSTRAINTS", "constraints", 0, 0)


def fast_parse(lines: list[Line], end_pos: int, span, path: str) -> Optional[RawFile]:
    """A clean file read with its feature tree built straight from the lines' indentation
    (the LALR driver's time is mostly the tree's lines, one name each); the rest of the file
    (header, the ``features`` line, constraints) goes through the driver as usual.

    None -- and nothing changed -- as soon as anything is not plain: a line the grammar might
    reject, an empty group, indentation matching no level, any syntax error elsewhere; the
    general path then reads the file and says what is wrong.  What this returns is what the
    general path returns for the same lines (the tests compare both on random texts)."""
    with _LOCK:
        _tables()
        return _fast_parse(lines, end_pos, span, path)


def _fast_parse(lines: list[Line], end_pos: int, span, path: str) -> Optional[RawFile]:
    n = len(lines)
    fi = -1
    for i in range(n):
        ln = lines[i]
        if ln.indent == 0 and ln.toks[0].type == "FEATURES":
            fi = i
            break
    if fi < 0 or len(lines[fi].toks) != 1:
        return None
    hi = fi + 1
    while hi < n and lines[hi].indent != 0:
        hi += 1
    if hi - fi < 2:
        return None
    ctx = _Ctx(span, path, [])
    _BUILDER.ctx = ctx
    roots = _fast_tree(lines, fi + 1, hi, end_pos)
    if roots is None or ctx.issues:
        return None
    rest = lines[hi:]
    constraints = None
    if (len(rest) > 1 and len(rest[0].toks) == 1 and rest[0].toks[0].type == "CONSTRAINTS"
            and all(ln.indent == rest[1].indent for ln in rest[2:])):
        # a ``constraints`` block, each line at one indentation: read line by line below, the
        # driver sees the keyword alone
        constraints = _fast_constraints(rest[1:], end_pos)
        if constraints is None or ctx.issues:
            return None
        rest = rest[:1]
    lay = layout(lines[:fi + 1] + rest, end_pos)
    if lay.problems:
        return None
    try:
        raw = _run(lay.tokens, end_pos)
    except _SyntaxError:
        return None
    if ctx.issues or raw.features_kw is not lines[fi].toks[0] or raw.roots:
        return None
    if constraints is not None:
        if raw.constraints:
            return None
        raw.constraints = constraints
    raw.roots = roots
    raw.broken_names = set()
    return raw


def _fast_tree(lines: list[Line], lo: int, hi: int, end_pos: int) -> Optional[list[RawFeature]]:
    """The features of ``lines[lo:hi]`` (the body of ``features``) as the grammar's
    ``feature_list`` would make them, or None when a line is not plain.  A line that is one
    name is made here; a longer feature line (attributes, a type, a cardinality, a dotted
    name) is read alone by the LALR driver."""
    roots: list[RawFeature] = []
    # open blocks: (indentation, holds groups?, items, owner); the layout's stack less level 0
    frames: list[tuple] = [(lines[lo].indent, False, roots, None)]
    need_block = False  # the last line was a group keyword: its features must follow, indented
    group_kws = _GROUP_KWS
    for i in range(lo, hi):
        ln = lines[i]
        ind = ln.indent
        top = frames[-1]
        if ind > top[0]:
            items = top[2]
            if top[1]:
                g = items[-1]
                g.features = []
                frames.append((ind, False, g.features, g))
            else:
                f = items[-1]
                f.groups = []
                frames.append((ind, True, f.groups, f))
            top = frames[-1]
        else:
            if need_block:
                return None
            if ind < top[0]:
                while frames and frames[-1][0] > ind:
                    _close(frames.pop())
                if not frames or frames[-1][0] != ind:
                    return None
                top = frames[-1]
        need_block = False
        toks = ln.toks
        t = toks[0]
        if top[1]:
            if len(toks) != 1 or t.type not in group_kws:
                return None
            top[2].append(RawGroup(t, None, t.start, t.end))
            need_block = True
        elif len(toks) == 1 and (t.type == "ID" or t.type == "QID"):
            top[2].append(RawFeature(None, RawRef((t,)), None, (), None, (), t.start, t.end))
        else:
            rf = _fast_line(toks, end_pos)
            if rf is None:
                return None
            top[2].append(rf)
    if need_block:
        return None
    while frames:
        _close(frames.pop())
    return roots


def _close(frame: tuple) -> None:
    """What the driver's reductions do at the end of a block."""
    _, groups, items, owner = frame
    if owner is None:
        return
    if groups:  # feature_groups
        owner.groups = items
        owner.end = max(owner.end, items[-1].end)
        owner.depth = max(max((x.depth for x in g.features), default=0) for g in items) + 1
    else:  # group
        owner.end = items[-1].end


def _fast_line(toks: list[Tok], end_pos: int) -> Optional[RawFeature]:
    """One feature line read alone by the driver, as the only feature of a ``features``
    block."""
    try:
        raw = _run([_SYN_FEATURES, _SYN_NL, _SYN_INDENT, *toks, _SYN_NL, _SYN_DEDENT], end_pos)
    except _SyntaxError:
        return None
    if len(raw.roots) != 1 or raw.roots[0].groups:
        return None
    return raw.roots[0]


# ---------------------------------------------------------------- constraints

class _NotPlain(Exception):
    pass


_LEVELS = ("IFF", "IMPLIES", "OR", "AND")  # the grammar's binary levels, loosest first, all left-associative
_PLAIN = frozenset(("ID", "QID", "DOT", "NOT", "LPAR", "RPAR") + _LEVELS)
_MAX_NEST = 60  # deeper parentheses / negations: the driver (it has no recursion limit)


def _fast_constraints(lines: list[Line], end_pos: int) -> Optional[list[RawConstraint]]:
    """The constraints of ``lines`` (one per line), as the driver's ``constraint_line`` makes
    them.  A Boolean line (names, ``! & | => <=>``, parentheses) is read by :class:`_Expr`,
    calling the builder's callbacks as the driver's reductions would; any other line
    (arithmetic, aggregates, literals) is read alone by the driver.  None on any syntax error."""
    out = []
    for ln in lines:
        toks = ln.toks
        e = None
        if all(t.type in _PLAIN for t in toks):
            try:
                e = _Expr(toks).parse()
            except _NotPlain:
                e = None
        if e is None:
            try:
                raw = _run([_SYN_CONSTRAINTS, _SYN_NL, _SYN_INDENT, *toks, _SYN_NL, _SYN_DEDENT], end_pos)
            except _SyntaxError:
                return None
            if len(raw.constraints) != 1:
                return None
            out.append(raw.constraints[0])
            continue
        out.append(RawConstraint(e, e._s, e._e))
    return out


class _Expr:
    """Precedence climbing over one line's tokens for the Boolean part of the grammar::

        iff_e: impl_e (IFF impl_e)*     impl_e: or_e (IMPLIES or_e)*     or_e: and_e (OR and_e)*
        and_e: not_e (AND not_e)*       not_e: NOT not_e | atom          atom: reference | ( iff_e )

    The values are the builder's (``binop``, ``unop``, ``name``, ``paren``, ``reference``) for
    the same arguments the LALR reductions pass; anything else raises :class:`_NotPlain`."""

    __slots__ = ("toks", "i", "n", "nest")

    def __init__(self, toks: list[Tok]):
        self.toks = toks
        self.i = 0
        self.n = len(toks)
        self.nest = 0

    def parse(self):
        e = self.level(0)
        if self.i != self.n:
            raise _NotPlain
        return e

    def level(self, k: int):
        if k == 4:
            return self.unary()
        left = self.level(k + 1)
        op_type = _LEVELS[k]
        toks = self.toks
        binop = _BUILDER.binop
        while self.i < self.n and toks[self.i].type == op_type:
            op = toks[self.i]
            self.i += 1
            right = self.level(k + 1)
            left = binop([left, op, right])
        return left

    def unary(self):
        if self.i >= self.n:
            raise _NotPlain
        t = self.toks[self.i]
        tt = t.type
        if tt == "NOT" or tt == "LPAR":
            self.nest += 1
            if self.nest > _MAX_NEST:
                raise _NotPlain
            self.i += 1
            if tt == "NOT":
                e = _BUILDER.unop([t, self.unary()])
            else:
                inner = self.level(0)
                if self.i >= self.n or self.toks[self.i].type != "RPAR":
                    raise _NotPlain
                rp = self.toks[self.i]
                self.i += 1
                e = _BUILDER.paren([t, inner, rp])
            self.nest -= 1
            return e
        if tt != "ID" and tt != "QID":
            raise _NotPlain
        self.i += 1
        ref = _BUILDER.reference([t])
        toks, n = self.toks, self.n
        while self.i + 1 < n and toks[self.i].type == "DOT" and toks[self.i + 1].type in ("ID", "QID"):
            ref = _BUILDER.reference([ref, toks[self.i], toks[self.i + 1]])
            self.i += 2
        return _BUILDER.name([ref])
