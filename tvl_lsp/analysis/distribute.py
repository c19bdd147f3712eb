"""Clauses by distribution: a constraint whose CNF is small (``A & B | !C`` is two clauses,
``A <=> B & C`` three) needs no Tseitin variable.  A mixin of :class:`.encode.Encoding`, which
calls :meth:`DistributeMixin._cnf` before falling back to Tseitin definitions."""

from __future__ import annotations

from typing import Optional

from ..tvl import model as M
from .clauses import PRODUCT_ITEM_MAX, Lit, distribute


class NotEncodable(Exception):
    pass


def _chain(e: M.Expr, op: str) -> list[M.Expr]:
    """The operands of a chain ``a op b op c ...`` (either nesting), in order, without recursion."""
    out: list[M.Expr] = []
    stack = [e]
    while stack:
        x = stack.pop()
        if isinstance(x, M.Binary) and _ALIAS.get(x.op, x.op) == op:
            stack.append(x.right)
            stack.append(x.left)
        else:
            out.append(x)
    return out


def _check_read(e: M.Expr) -> None:
    """The parser stands a ``true`` in for an expression nested too deeply to read: encoding it
    would make the constraint look redundant and the counts silently wrong."""
    if getattr(e, "too_deep", False):
        raise NotEncodable("it is nested too deeply to be read")


_ALIAS = {"and": "&&", "or": "||"}


class DistributeMixin:
    """Needs ``_blit``, ``_is_bool``, ``b`` (the Tseitin builder) from the encoding."""

    def _cnf(self, e: M.Expr, pos: bool, ctx, limit: int) -> Optional[list[list[Lit]]]:
        """Clauses meaning ``e`` (``!e`` when not pos) by distribution, or None when that takes
        more than ``limit`` clauses (then Tseitin variables are cheaper)."""
        if isinstance(e, M.Unary) and e.op == "!":
            return self._cnf(e.operand, not pos, ctx, limit)
        if isinstance(e, M.BoolLit):
            _check_read(e)
            return [] if bool(e.value) == pos else [[]]
        if isinstance(e, M.Binary):
            op = _ALIAS.get(e.op, e.op)
            if op in ("&&", "||"):
                parts = _chain(e, op)
                if (op == "&&") == pos:
                    out: list[list[Lit]] = []
                    for p in parts:
                        c = self._cnf(p, pos, ctx, limit)
                        if c is None:
                            return None
                        out += c
                        if len(out) > limit:
                            return None
                    return out
                return self._product([(p, pos) for p in parts], ctx, limit)
            if op in ("->", "requires", "<-"):
                a, b_ = (e.left, e.right) if op != "<-" else (e.right, e.left)
                if pos:
                    return self._product([(a, False), (b_, True)], ctx, limit)
                return self._product_and([(a, True), (b_, False)], ctx, limit)
            if op == "excludes":
                if pos:
                    return self._product([(e.left, False), (e.right, False)], ctx, limit)
                return self._product_and([(e.left, True), (e.right, True)], ctx, limit)
            if op == "<->" or (op in ("==", "!=") and self._is_bool(e.left) and self._is_bool(e.right)):
                # remembered: an equivalence distributes both its sides in both polarities, so
                # each one nested in it was distributed again for every enclosing one --
                # exponential in their nesting (a 700-character constraint of mixed <=> and =>
                # took 5 s).  The same node, polarity and limit give the same clauses (the
                # Tseitin builder returns the variable it made before), and no caller changes
                # the lists it is given.
                memo = self.__dict__.setdefault("_iff_memo", {})
                key = (id(e), pos, id(ctx), limit)
                hit = memo.get(key)
                if hit is not None and hit[0] is e and hit[1] is ctx:
                    return hit[2]
                same = pos if op != "!=" else not pos
                if same:
                    a = self._product([(e.left, False), (e.right, True)], ctx, limit)
                    b_ = self._product([(e.left, True), (e.right, False)], ctx, limit) if a is not None else None
                else:
                    a = self._product([(e.left, True), (e.right, True)], ctx, limit)
                    b_ = self._product([(e.left, False), (e.right, False)], ctx, limit) if a is not None else None
                r = None if a is None or b_ is None or len(a) + len(b_) > limit else a + b_
                memo[key] = (e, ctx, r)  # (holding e: its id is not reused meanwhile)
                return r
        x = self._blit(e, ctx)
        return [[x if pos else self.b.not_(x)]]

    def _product_and(self, items, ctx, limit: int) -> Optional[list[list[Lit]]]:
        out: list[list[Lit]] = []
        for p, s in items:
            c = self._cnf(p, s, ctx, limit)
            if c is None:
                return None
            out += c
            if len(out) > limit:
                return None
        return out

    def _product(self, items, ctx, limit: int) -> Optional[list[list[Lit]]]:
        """The CNF of a disjunction of ``(expr, pos)`` items."""
        base: list[Lit] = []
        multi: list[list[list[Lit]]] = []
        # a disjunct may be bigger than the result (see _absorb)
        inner = max(limit, PRODUCT_ITEM_MAX)
        for p, s in items:
            c = self._cnf(p, s, ctx, inner)
            if c is None:
                return None
            if not c:
                return []  # a disjunct that always holds
            if len(c) == 1:
                base.extend(c[0])
            else:
                multi.append(c)
        return distribute(base, multi, limit, inner)
