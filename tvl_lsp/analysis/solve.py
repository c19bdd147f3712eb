"""The SAT service: every satisfiability question of the analysis goes through this module
(python-sat).

:class:`Analyzer` answers a model's own questions.  Two incremental solvers share the encoding:

- a *plain* one on the model's CNF, for detection: void model, backbone (core and dead
  features) with a model-based filter (a literal seen flipped in any solution found so far needs
  no check), and false-optional features (an optional child that is selected in every product
  where its parent is), each with one call under assumptions at most;
- a *selector* one where every element's clauses carry ``!s_e``, for explanations: a minimal
  unsatisfiable subset (MUS) of the selectors, from the solver's unsat core shrunk by deletion
  (each kept element is necessary: dropping it makes the query satisfiable).

:class:`PairLogic` answers the cross-check's questions about formulas over feature / arg
names (is it satisfiable, valid, the smallest witness product) for one pairing of a model and
a launch file: one incremental solver over the model's CNF plus a Tseitin encoding of each
queried formula.  :func:`decide` answers the configurator's (do these decisions conflict,
which features do they force); :func:`products` and :func:`smallest_product` enumerate products
and find the one with the fewest selected features (MaxSAT, RC2).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from itertools import compress
from operator import and_, neg, not_
from typing import Iterable, Iterator, Optional, Sequence

from pysat.card import ITotalizer

from ..base import formula as fm
from ..tvl import model as M
from .choices import value_literal
from .sat import BoundedSolver as Solver
from .encode import Element, Encoding, _Builder
# the SAT helpers the counting service shares (imported from here by older callers)
from .backbone import SOLVER, add_clauses, backbone_of, new_solver  # noqa: F401

CANONICAL_MAX_VARS = 400  # witnesses over more names are smallest, not canonical


@dataclass
class Explanation:
    elements: list[Element]
    minimal: bool = True


@dataclass
class Anomalies:
    void: bool
    core: list[M.Feature] = field(default_factory=list)
    dead: list[M.Feature] = field(default_factory=list)
    # (feature, parent) pairs: optional in parent's group, yet always selected with it
    false_optional: list[tuple[M.Feature, M.Feature]] = field(default_factory=list)
    redundant: list[Element] = field(default_factory=list)
    always_false: list[Element] = field(default_factory=list)


class Analyzer:
    def __init__(self, enc: Encoding):
        self.enc = enc
        self._plain: Optional[Solver] = None
        self._sel: Optional[Solver] = None
        self._sel_of: dict[int, Element] = {}
        self._selectors: list[int] = []
        self._selector_range = range(0)  # the same numbers (a cheap membership test)
        self._backbone: Optional[dict[int, bool]] = None
        self._void: Optional[bool] = None
        self._seen_true: set[int] = set()
        self._seen_false: set[int] = set()
        self._witness: Optional[list[int]] = None
        self._opt_pairs: Optional[list] = None
        self._witnessed: set[tuple[int, int]] = set()
        self._pending: Optional[tuple[list[tuple[int, int]], list[int], list[int]]] = None
        self._hard_index: Optional[dict[int, list[int]]] = None
        self._hard_always: list[int] = []

    # ------------------------------------------------------------------ solvers
    @property
    def plain(self) -> Solver:
        if self._plain is None:
            self._plain = new_solver(self.enc.clauses())
        return self._plain

    @property
    def selector_solver(self) -> Solver:
        if self._sel is None:
            s = new_solver(self.enc.hard)
            elements = self.enc.elements
            top = self.enc.nvars
            sels = range(top + 1, top + 1 + len(elements))
            self._sel_of.update(zip(sels, elements))
            self._selectors.extend(sels)
            self._selector_range = sels

            def guarded():  # each element's clauses with !s_e, in order
                for t, e in zip(sels, elements):
                    e.selector = t
                    for c in e.clauses:
                        yield [*c, -t]
            add_clauses(s, guarded())
            self._sel = s
        return self._sel

    def close(self) -> None:
        for s in (self._plain, self._sel):
            if s is not None:
                s.delete()
        self._plain = self._sel = None

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def _record(self, model: list[int], seen: bool = True) -> None:
        """Note what a solution shows: the values it gives the features (``seen``: only the
        backbone's candidates need them, before it starts) and the optional pairs it witnesses."""
        n = self.enc.n_features
        if seen:
            head = model[:n]
            self._seen_true.update(filter((0).__lt__, head))
            self._seen_false.update(map(neg, filter((0).__gt__, head)))
        # model-based filter for false-optional: this product shows "parent without child"
        # (the pending pairs, their parents' and their children's indexes in a model: the tests
        # are C loops, 10^5 pairs in a flat model)
        if self._pending is None:
            pairs = [(pv, fv) for pv, fv, _, _ in self._optional_pairs()]
            self._pending = (pairs, [pv - 1 for pv, _ in pairs], [fv - 1 for _, fv in pairs])
        pairs, pidx, fidx = self._pending
        if not pairs:
            return
        get = model.__getitem__
        shown = list(map(and_, map((0).__lt__, map(get, pidx)), map((0).__gt__, map(get, fidx))))
        if True in shown:
            self._witnessed.update(compress(pairs, shown))
            keep = list(map(not_, shown))
            self._pending = (list(compress(pairs, keep)), list(compress(pidx, keep)), list(compress(fidx, keep)))

    # ------------------------------------------------------------------ detection
    def is_void(self) -> bool:
        if self._void is None:
            ok = self.plain.solve()
            self._void = not ok
            if ok:
                m = self.plain.get_model()
                self._witness = m
                self._record(m)
        return self._void

    def backbone(self, deadline: Optional[float] = None) -> Optional[dict[int, bool]]:
        """Feature variable -> forced value, for every feature with one value in all products;
        None when ``deadline`` passes first (asked again, it starts again)."""
        if self._backbone is not None:
            return self._backbone
        if self.is_void():
            self._backbone = {}
            return self._backbone
        s = self.plain
        n = self.enc.n_features
        cand: dict[int, bool] = {}
        for v in range(1, n + 1):
            t, f = v in self._seen_true, v in self._seen_false
            if t != f:
                cand[v] = t
        bb = backbone_of(s, cand, [], lambda m: self._record(m, seen=False), deadline, n_features=n)
        if bb is None:
            return None
        for v, val in bb.items():
            s.add_clause([v if val else -v])
        self._backbone = bb
        return bb

    def core(self) -> list[M.Feature]:
        return [self.enc.feature_of_var[v] for v, val in sorted(self.backbone().items()) if val]

    def dead(self) -> list[M.Feature]:
        return [self.enc.feature_of_var[v] for v, val in sorted(self.backbone().items()) if not val]

    def _optional_pairs(self) -> list[tuple[int, int, M.Feature, M.Feature]]:
        if self._opt_pairs is None:
            v = self.enc.var_of_feature
            get = v.get
            seen: set = set()
            out = []
            for p in self.enc.features:
                if p.group is None and not p.extra_groups:
                    continue
                for g in p.groups:
                    for gc in g.children:
                        if gc.optional:
                            f = gc.feature
                            vf = get(f)
                            if vf is not None:
                                vp = v[p]
                                if (vp, vf) not in seen:
                                    seen.add((vp, vf))
                                    out.append((vp, vf, f, p))
            self._opt_pairs = out
        return self._opt_pairs

    def false_optional(self, deadline: Optional[float] = None) -> Optional[list[tuple[M.Feature, M.Feature]]]:
        """(feature, parent): optional in the parent's group, not dead, yet selected in every
        product that selects the parent; None when ``deadline`` passes first."""
        if self.is_void():
            return []
        bb = self.backbone(deadline)
        if bb is None:
            return None
        out = []
        todo = []
        for pv, fv, f, p in self._optional_pairs():
            if bb.get(pv) is False or bb.get(fv) is False:
                continue
            if bb.get(fv) is True:
                out.append((f, p))
            elif (pv, fv) not in self._witnessed:
                todo.append((pv, fv, f, p))
        if todo:
            # like the backbone: "can some remaining pair have its parent without its child?"
            # in one call; UNSAT proves all the remaining pairs false-optional at once
            s = self.plain
            top = s.nof_vars()
            d_of = {}
            for pv, fv, _, _ in todo:
                top += 1
                d_of[(pv, fv)] = top
                s.add_clause([-top, pv])
                s.add_clause([-top, -fv])
            left = list(todo)
            while left:
                if deadline is not None and time.monotonic() > deadline:
                    return None
                top += 1
                act = top
                s.add_clause([-act] + [d_of[(pv, fv)] for pv, fv, _, _ in left])
                s.set_phases([d_of[(pv, fv)] for pv, fv, _, _ in left])
                ok = s.solve(assumptions=[act])
                m = s.get_model() if ok else None
                s.add_clause([-act])
                if not ok:
                    break
                self._record(m, seen=False)
                left = [x for x in left if not (m[x[0] - 1] > 0 and m[x[1] - 1] < 0)]
            out.extend((f, p) for _, _, f, p in left)
        key = {(id(f), id(p)): i for i, (_, _, f, p) in enumerate(self._optional_pairs())}
        out.sort(key=lambda fp: key[(id(fp[0]), id(fp[1]))])
        return out

    def redundant_and_always_false(self, max_constraints: int = 300,
                                   deadline: Optional[float] = None) -> tuple[list[Element], list[Element]]:
        """Constraints implied by the rest of the model, and constraints that contradict the
        feature diagram.  Only for models with few constraints (it costs one call each)."""
        cons = [e for e in self.enc.elements if e.kind == "constraint"]
        if len(cons) > max_constraints:
            return [], []
        s = self.selector_solver
        structure = [e.selector for e in self.enc.elements if e.kind not in ("constraint",)]
        if not s.solve(assumptions=structure):
            return [], []
        redundant, always_false = [], []
        allsel = self._selectors
        for e in cons:
            if deadline is not None and time.monotonic() > deadline:
                break
            if not s.solve(assumptions=structure + [e.selector]):
                always_false.append(e)
                continue
            if e.negation == [False]:
                redundant.append(e)  # always holds
                continue
            if e.negation is None:
                continue
            others = [x for x in allsel if x != e.selector]
            neg = [x for x in e.negation if x is not True]
            if not s.solve(assumptions=others + neg):
                redundant.append(e)
        return redundant, always_false

    # ------------------------------------------------------------------ explanations
    def explain(self, extra: list[int], deadline: Optional[float] = None,
                among: Optional[list[int]] = None, side_clauses: list[list[int]] = ()) -> Optional[Explanation]:
        """A minimal set of elements that, with the ``extra`` assumption literals, is
        unsatisfiable; None when the query is satisfiable.  (``side_clauses``: clauses the
        caller added to the selector solver for this query, e.g. a guarded formula.)"""
        s = self.selector_solver
        sels = self._selectors if among is None else among
        if s.solve(assumptions=extra + sels):
            return None
        selset = self._selector_range if among is None else set(sels)
        core = sorted({x for x in (s.get_core() or []) if x in selset})
        # shrink by deletion in a small solver that holds only the core's elements: every
        # candidate set is a subset of the core, and a small solver answers "satisfiable"
        # without assigning the whole model
        # (variables renumbered 1..k: a solver assigns every variable it knows of)
        ren: dict[int, int] = {}

        def r(x: int) -> int:
            y = ren.get(abs(x))
            if y is None:
                y = ren[abs(x)] = len(ren) + 1
            return y if x > 0 else -y

        small = Solver(name=SOLVER)
        try:
            side_clauses = list(side_clauses)
            seeds = [c for x in core for c in self._sel_of[x].clauses] + side_clauses + [[x] for x in extra]
            for c in self._hard_cone(seeds) + side_clauses:
                small.add_clause([r(x) for x in c])
            for x in core:
                for c in self._sel_of[x].clauses:
                    small.add_clause([r(y) for y in c] + [-r(x)])
            extra_r = [r(x) for x in extra]
            back = {}
            for x in core:
                back[r(x)] = x
            minimal = True
            i = 0
            cur = [r(x) for x in core]
            while i < len(cur):
                if deadline is not None and time.monotonic() > deadline:
                    minimal = False
                    break
                trial = cur[:i] + cur[i + 1:]
                if small.solve(assumptions=extra_r + trial):
                    i += 1
                else:
                    got = set(small.get_core() or [])
                    cur = [x for x in trial if x in got]
            core = [back[x] for x in cur]
        finally:
            small.delete()
        return Explanation([self._sel_of[x] for x in core], minimal)

    def _hard_cone(self, seeds: list[list[int]]) -> list[list[int]]:
        """The hard clauses the ``seeds`` clauses depend on: those reachable from the seeds'
        auxiliary (non-feature) variables through hard clauses that share one.  Every other hard
        clause is a Tseitin definition of (or a one-hot domain over) variables nothing here
        mentions, satisfiable whatever the rest is: leaving them out keeps every query's answer
        and makes each explanation cost its own size, not the model's (Linux: 8,000 hard
        clauses copied per dead feature before)."""
        nf = self.enc.n_features
        index = self._hard_index
        if index is None:
            index = self._hard_index = {}
            for i, c in enumerate(self.enc.hard):
                for x in c:
                    if abs(x) > nf:
                        index.setdefault(abs(x), []).append(i)
            self._hard_always = [i for i, c in enumerate(self.enc.hard) if all(abs(x) <= nf for x in c)]
        hard = self.enc.hard
        taken: set[int] = set(self._hard_always)
        seen: set[int] = set()
        todo = [abs(x) for c in seeds for x in c if abs(x) > nf]
        while todo:
            v = todo.pop()
            if v in seen:
                continue
            seen.add(v)
            for i in index.get(v, ()):
                if i not in taken:
                    taken.add(i)
                    todo.extend(abs(x) for x in hard[i] if abs(x) > nf and abs(x) not in seen)
        return [hard[i] for i in sorted(taken)]

    def witness(self) -> Optional[list[int]]:
        self.is_void()
        return self._witness


# ------------------------------------------------------------------ configurator decisions

def decide(enc: Encoding, assumptions: Sequence[int]) -> tuple[Optional[list[int]], dict[int, bool]]:
    """Can the decisions (feature literals ``assumptions``) hold together?  ``(conflict, {})``
    with a minimal subset of them that cannot (every kept literal is necessary), or
    ``(None, forced)`` with every undecided feature variable they force (var -> value)."""
    s = new_solver(enc.clauses())
    try:
        assumptions = list(assumptions)
        if not s.solve(assumptions=assumptions):
            given = set(assumptions)
            core = [x for x in (s.get_core() or []) if x in given]
            i = 0
            while i < len(core):  # deletion-based: every kept decision is needed
                trial = core[:i] + core[i + 1:]
                if s.solve(assumptions=trial):
                    i += 1
                else:
                    got = set(s.get_core() or [])
                    core = [x for x in trial if x in got]
            return core, {}
        n = enc.n_features
        m = s.get_model()
        decided = {abs(x) for x in assumptions}
        cand = {v: m[v - 1] > 0 for v in range(1, n + 1) if v not in decided}
        return None, backbone_of(s, cand, assumptions, n_features=n)
    finally:
        s.delete()


# ------------------------------------------------------------------ formula queries (the cross-check)

class PairLogic:
    """SAT over (model CNF ∧ formula) where formulas are over arg / feature names.

    ``encoding`` is the model's :class:`~tvl_lsp.analysis.encode.Encoding` (None: no model,
    every name is a free boolean).  ``free_names`` are names that must appear in witnesses
    even when no formula mentions them (the launch file's free top-level args).
    """

    def __init__(self, encoding=None, free_names: Iterable[str] = ()):
        self.enc = encoding
        self.solver = new_solver(encoding.clauses() if encoding is not None else [])
        # the encoder's Tseitin builder (constant folding, structural caching); the clauses it
        # defines are handed to the incremental solver as they appear (see _flush)
        self._b = _Builder(encoding.nvars if encoding is not None else 0, [])
        self.var_of: dict[str, int] = {}
        self.names: list[tuple[str, int]] = []  # witness names in order
        if encoding is not None:
            for f in encoding.features:
                v = encoding.var_of_feature[f]
                name = encoding.name_of(f)
                self.var_of[name] = v
                self.names.append((name, v))
        for n in free_names:
            self._var(n)
        self._tot: Optional[ITotalizer] = None
        self._tot_size = 0
        self._cache: dict[fm.Formula, int] = {}
        self._void: Optional[bool] = None

    @property
    def top(self) -> int:
        return self._b.top

    @top.setter
    def top(self, value: int) -> None:
        self._b.top = value

    def close(self) -> None:
        if self._tot is not None:
            self._tot.delete()
            self._tot = None
        self.solver.delete()

    def _new(self) -> int:
        return self._b.new_var()

    def _var(self, name: str) -> int:
        v = self.var_of.get(name)
        if v is None and self.enc is not None:
            f = self.enc.feature_by_name(name)
            if f is not None:
                v = self.enc.var_of_feature[f]
                self.var_of[name] = v
                return v
            lit = value_literal(self.enc, name)  # ATTR=VALUE of an encoded attribute
            if lit is not None:
                self.var_of[name] = lit
                return lit
        if v is None:
            v = self._new()
            self.var_of[name] = v
            if not fm.is_unknown(name):  # an unknown condition is no arg a witness could give
                self.names.append((name, v))
        return v

    def _flush(self) -> None:
        for c in self._b.hard:
            self.solver.add_clause(c)
        self._b.hard.clear()

    def _go(self, f: fm.Formula):
        if isinstance(f, fm.Const):
            return f.value
        if isinstance(f, fm.Var):
            return self._var(f.name)
        if isinstance(f, fm.Not):
            return self._b.not_(self._go(f.arg))
        hit = self._cache.get(f)
        if hit is None:
            lits = [self._go(a) for a in f.args]
            hit = self._b.and_(lits) if isinstance(f, fm.And) else self._b.or_(lits)
            self._cache[f] = hit
        return hit

    def _lit(self, f: fm.Formula):
        """Tseitin: a literal (or a bool) equivalent to ``f``, its definitions in the solver."""
        x = self._go(f)
        self._flush()
        return x

    def _assume(self, f: fm.Formula) -> Optional[list[int]]:
        """Assumptions asserting f; None when f is constant false."""
        x = self._lit(f)
        if x is False:
            return None
        return [] if x is True else [x]

    def void(self) -> bool:
        if self._void is None:
            self._void = not self.solver.solve()
        return self._void

    def sat(self, f: fm.Formula) -> bool:
        a = self._assume(f)
        return a is not None and self.solver.solve(assumptions=a)

    def valid(self, f: fm.Formula) -> bool:
        """f holds in every product (vacuously true for a void model)."""
        return not self.sat(fm.neg(f))

    def lit(self, f: fm.Formula):
        """A solver literal (or a bool) equivalent to f."""
        return self._lit(f)

    def and_lits(self, a, b):
        """A literal (or bool) for ``a && b`` of two literals / bools."""
        y = self._b.and_([a, b])
        self._flush()
        return y

    def witness(self, f: fm.Formula, guard=True) -> Optional[dict[str, bool]]:
        """A product satisfying f (and the literal ``guard``) with the fewest selected
        features (and free args)."""
        a = self._assume(f)
        if a is None or guard is False:
            return None
        if guard is not True:
            a = a + [guard]
        if not self.solver.solve(assumptions=a):
            return None
        # names created by f itself must be counted too: rebuild the totalizer when they grew
        lits = [v for _, v in self.names]
        if self._tot is None or self._tot_size != len(lits):
            if self._tot is not None:
                self._tot.delete()
            self._tot = ITotalizer(lits=lits, ubound=len(lits), top_id=self.top)
            self.top = self._tot.top_id
            for c in self._tot.cnf.clauses:
                self.solver.add_clause(c)
            self._tot_size = len(lits)
            self.solver.solve(assumptions=a)
        def on(m: list[int], v: int) -> bool:
            return v <= len(m) and m[v - 1] > 0

        best = self.solver.get_model() or []
        count = sum(1 for v in lits if on(best, v))
        rhs = self._tot.rhs
        while count > 0:
            # at most count-1 selected: rhs[count-1] false
            if not self.solver.solve(assumptions=a + [-rhs[count - 1]]):
                break
            best = self.solver.get_model() or []
            count = sum(1 for v in lits if on(best, v))
        if len(lits) <= CANONICAL_MAX_VARS:
            # canonical among the smallest: prefer the features declared first, so the answer
            # does not depend on what the solver was asked before
            fixed: list[int] = []
            bound = [-rhs[count]] if count < len(lits) else []
            for v in lits:
                if sum(1 for x in fixed if x > 0) >= count:
                    fixed.append(-v)
                    continue
                if on(best, v) or self.solver.solve(assumptions=a + bound + fixed + [v]):
                    if not on(best, v):
                        best = self.solver.get_model() or []
                    fixed.append(v)
                else:
                    fixed.append(-v)
            if self.solver.solve(assumptions=a + bound + fixed):
                best = self.solver.get_model() or best
        return {name: on(best, v) for name, v in self.names}


# ---------------------------------------------------------------------------- products
def _product_solver(enc: Encoding, lits: Sequence[int], extra: Sequence[Sequence[int]] = ()) -> Solver:
    s = new_solver(enc.clauses())
    for x in lits:
        s.add_clause([x])
    for c in extra:
        s.add_clause(list(c))
    return s


def products(enc: Encoding, lits: Sequence[int] = (), extra: Sequence[Sequence[int]] = (),
             limit: Optional[int] = 100) -> Iterator[list[int]]:
    """The model's products under the literals ``lits`` and the clauses ``extra``, one by one
    (each a model over the features' variables ``1..n_features``), at most ``limit``."""
    s = _product_solver(enc, lits, extra)
    n = enc.n_features
    k = 0
    try:
        while limit is None or k < limit:
            if not s.solve():
                return
            m = s.get_model()[:n]
            yield m
            k += 1
            s.add_clause([-x for x in m])
    finally:
        s.delete()


def smallest_product(enc: Encoding, lits: Sequence[int] = (), extra: Sequence[Sequence[int]] = (),
                     smallest: bool = True) -> Optional[list[int]]:
    """A product under ``lits`` and ``extra`` (the one with the fewest selected features when
    ``smallest``: MaxSAT with RC2), as literals over ``1..n_features``; None when there is none."""
    n = enc.n_features
    s = _product_solver(enc, lits, extra)
    try:
        if not s.solve():
            return None
        if not smallest:
            return s.get_model()[:n]
    finally:
        s.delete()
    from pysat.examples.rc2 import RC2
    from pysat.formula import WCNF
    w = WCNF()
    for c in enc.clauses():
        w.append(c)
    for x in lits:
        w.append([x])
    for c in extra:
        w.append(list(c))
    for v in range(1, n + 1):
        w.append([-v], weight=1)
    with RC2(w, solver=SOLVER) as rc2:
        m = rc2.compute()
    if m is None:
        return None
    full = [0] * n
    for x in m:
        if 0 < abs(x) <= n:
            full[abs(x) - 1] = x
    return full
