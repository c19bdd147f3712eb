"""The CNF of a plain UVL model (:func:`tvl_lsp.uvl.plain.read_plain`), clause for clause and in
the same order as :func:`.encode.encode` makes it from the full model: the same variables (the
features in document order, then the Tseitin and counter variables in the order they are
made), so the same counting-cache key.  What it ports from the encoding works on the plain
expressions (a feature's number, ``("!", e)``, ``(op, left, right)``) instead of the model's
objects (chains of ``&&`` / ``||`` are one node there): :meth:`Encoding._encode_structure` / ``_encode_group`` and, for the constraints,
``_assert``, ``_disjuncts``, ``_blit`` and :class:`.distribute.DistributeMixin`; the clause-level
helpers are shared (:mod:`.clauses`).  ``tests/test_uvl_plain.py`` checks the two agree.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from .clauses import PRODUCT_ITEM_MAX, Lit, _Builder, _clean, _tautology, distribute

DISTRIBUTE_MAX = 16  # .encode.DISTRIBUTE_MAX (a test keeps them equal)


@dataclass
class PlainCNF:
    n_features: int
    nvars: int
    clauses: list[list[int]]


def encode_plain(p) -> PlainCNF:
    """The CNF of a :class:`tvl_lsp.uvl.plain.Plain` model."""
    n = len(p.names)
    hard: list[list[int]] = []
    enc = _Enc(_Builder(n, hard))
    elems: list[list[list[int]]] = [[[1]]]  # the root
    parent = p.parent
    for f in range(2, n + 1):
        elems.append([[-f, parent[f - 1]]])
    for f in range(1, n + 1):
        for g in p.groups[f - 1]:
            enc.group(f, g, elems)
    for e in p.constraints:
        out: list[list[int]] = []
        enc.iff_memo = {}
        enc.assert_(e, [], True, out)
        elems.append(out)
    clauses = list(hard)
    for el in elems:
        clauses.extend(el)
    return PlainCNF(n, enc.b.top, clauses)


def _chain(e, op: str) -> list:
    """:func:`.distribute._chain`: the plain reader keeps chains flat already."""
    if type(e) is tuple and e[0] == op:
        return e[1]
    return [e]


class _Enc:
    __slots__ = ("b", "iff_memo")

    def __init__(self, b: _Builder):
        self.b = b
        self.iff_memo: dict = {}

    def group(self, pv: int, g, elems) -> None:
        kids = g.children
        mand = [] if g.kind == "optional" else kids
        n_opt = len(kids) - len(mand)
        if g.hi is not None and g.hi < len(kids):
            elems.append([[-pv] + c for c in self.b.at_most(list(kids), g.hi)])
        need = g.lo - n_opt
        if need <= 0:
            return
        if need > len(mand):
            elems.append([[-pv]])
        elif need == len(mand):
            for c in mand:
                elems.append([[-pv, c]])
        else:
            elems.append([[-pv] + c for c in self.b.at_least(list(mand), need)])

    # ---------------------------------------------------------------- Encoding._assert
    def assert_(self, e, prefix: list, pos: bool, out: list) -> None:
        if type(e) is tuple:
            op = e[0]
            if op == "!":
                return self.assert_(e[1], prefix, not pos, out)
            if (op == "&&" and pos) or (op == "||" and not pos):
                for x in _chain(e, op):
                    self.assert_(x, prefix, pos, out)
                return
            if op == "->":
                if pos:
                    return self.assert_(e[2], prefix + self.disjuncts(e[1], False), True, out)
                self.assert_(e[1], prefix, True, out)
                self.assert_(e[2], prefix, False, out)
                return
            cnf = self.cnf(e, pos, DISTRIBUTE_MAX)
            if cnf is not None:
                for cl in cnf:
                    c = _clean(prefix + cl)
                    if c is not None:
                        out.append(c)
                return
            if (op == "||" and pos) or (op == "&&" and not pos):
                inner = "&&" if pos else "||"
                parts = _chain(e, op)
                width = [len(_chain(x, inner)) if type(x) is tuple else 1 for x in parts]
                i = max(range(len(parts)), key=width.__getitem__)
                if width[i] > 1:
                    rest: list = []
                    for j, x in enumerate(parts):
                        if j != i:
                            rest += self.disjuncts(x, pos)
                    return self.assert_(parts[i], prefix + rest, pos, out)
        c = _clean(prefix + self.disjuncts(e, pos))
        if c is not None:
            out.append(c)

    def disjuncts(self, e, pos: bool) -> list:
        out: list = []
        stack = [(e, pos)]
        while stack:
            e, pos = stack.pop()
            if type(e) is tuple:
                op = e[0]
                if op == "!":
                    stack.append((e[1], not pos))
                    continue
                if (op == "||" and pos) or (op == "&&" and not pos):
                    stack.extend([(x, pos) for x in reversed(e[1])])
                    continue
                if op == "->" and pos:
                    stack.append((e[2], True))
                    stack.append((e[1], False))
                    continue
            x = self.blit(e)
            out.append(x if pos else self.b.not_(x))
        return out

    def blit(self, e) -> Lit:
        if type(e) is int:
            return e
        b = self.b
        op = e[0]
        if op == "!":
            return b.not_(self.blit(e[1]))
        if op == "&&" or op == "||":
            xs = [self.blit(x) for x in _chain(e, op)]
            return b.and_(xs) if op == "&&" else b.or_(xs)
        if op == "->":
            left, right = self.blit(e[1]), self.blit(e[2])
            return b.or_([b.not_(left), right])
        return b.iff(self.blit(e[1]), self.blit(e[2]))  # "<->"

    # ---------------------------------------------------------------- DistributeMixin
    def cnf(self, e, pos: bool, limit: int) -> Optional[list]:
        if type(e) is int:  # (a feature: what the end of this method gives for it)
            return [[e if pos else -e]]
        if type(e) is tuple:
            op = e[0]
            if op == "!":
                return self.cnf(e[1], not pos, limit)
            if op == "&&" or op == "||":
                parts = e[1]  # (_chain(e, op))
                for x in parts:
                    if type(x) is not int:
                        break
                else:  # features only: what the general code below makes of them
                    if (op == "&&") == pos:
                        return None if len(parts) > limit else [[x if pos else -x] for x in parts]
                    base = [x if pos else -x for x in parts]
                    return [] if _tautology(base) else [base]
                if (op == "&&") == pos:
                    out: list = []
                    for p in parts:
                        c = self.cnf(p, pos, limit)
                        if c is None:
                            return None
                        out += c
                        if len(out) > limit:
                            return None
                    return out
                return self.product([(p, pos) for p in parts], limit)
            if op == "->":
                if pos:
                    return self.product([(e[1], False), (e[2], True)], limit)
                return self.product_and([(e[1], True), (e[2], False)], limit)
            # "<->" (remembered, as DistributeMixin does: nested equivalences)
            key = (id(e), pos, limit)
            hit = self.iff_memo.get(key)
            if hit is not None and hit[0] is e:
                return hit[1]
            left, right = e[1], e[2]
            if pos:
                a = self.product([(left, False), (right, True)], limit)
                b_ = self.product([(left, True), (right, False)], limit) if a is not None else None
            else:
                a = self.product([(left, True), (right, True)], limit)
                b_ = self.product([(left, False), (right, False)], limit) if a is not None else None
            r = None if a is None or b_ is None or len(a) + len(b_) > limit else a + b_
            self.iff_memo[key] = (e, r)
            return r
        x = self.blit(e)
        return [[x if pos else self.b.not_(x)]]

    def product_and(self, items, limit: int) -> Optional[list]:
        out: list = []
        for p, s in items:
            c = self.cnf(p, s, limit)
            if c is None:
                return None
            out += c
            if len(out) > limit:
                return None
        return out

    def product(self, items, limit: int) -> Optional[list]:
        for p, _ in items:
            if type(p) is not int:
                break
        else:  # features only: one clause (what the loops below make of them)
            base = [p if s else -p for p, s in items]
            return [] if _tautology(base) else [base]
        base: list = []
        multi: list = []
        inner = max(limit, PRODUCT_ITEM_MAX)
        pure = True  # every disjunct in multi a conjunction of features: _absorb keeps them all
        for p, s in items:
            if type(p) is int:
                base.append(p if s else -p)
                continue
            if s and p[0] == "&&":
                parts = p[1]
                for x in parts:
                    if type(x) is not int:
                        break
                else:  # (what cnf makes of it)
                    if len(parts) > inner:
                        return None
                    multi.append([[x] for x in parts])
                    continue
            c = self.cnf(p, s, inner)
            if c is None:
                return None
            if not c:
                return []
            if len(c) == 1:
                base.extend(c[0])
            else:
                multi.append(c)
                pure = False
        return distribute(base, multi, limit, inner, absorb=not pure)
