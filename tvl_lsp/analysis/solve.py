"""SAT analyses of an :class:`~tvl_lsp.analysis.encode.Encoding` with python-sat.

Two incremental solvers share the encoding:

- a *plain* one on the model's CNF, for detection: void model, backbone (core and dead
  features) with a model-based filter (a literal seen flipped in any solution found so far needs
  no check), and false-optional features (an optional child that is selected in every product
  where its parent is), each with one call under assumptions at most;
- a *selector* one where every element's clauses carry ``!s_e``, for explanations: a minimal
  unsatisfiable subset (MUS) of the selectors, from the solver's unsat core shrunk by deletion
  (each kept element is necessary: dropping it makes the query satisfiable).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional

from pysat.solvers import Solver

from .encode import Element, Encoding
from ..tvl import model as M

SOLVER = "glucose4"


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
        self._backbone: Optional[dict[int, bool]] = None
        self._void: Optional[bool] = None
        self._seen_true: set[int] = set()
        self._seen_false: set[int] = set()
        self._witness: Optional[list[int]] = None
        self._opt_pairs: Optional[list] = None
        self._witnessed: set[tuple[int, int]] = set()

    # ------------------------------------------------------------------ solvers
    @property
    def plain(self) -> Solver:
        if self._plain is None:
            self._plain = Solver(name=SOLVER, bootstrap_with=self.enc.clauses())
        return self._plain

    @property
    def selector_solver(self) -> Solver:
        if self._sel is None:
            s = Solver(name=SOLVER, bootstrap_with=self.enc.hard)
            top = self.enc.nvars
            for e in self.enc.elements:
                top += 1
                e.selector = top
                self._sel_of[top] = e
                self._selectors.append(top)
                for c in e.clauses:
                    s.add_clause(c + [-top])
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

    def _record(self, model: list[int]) -> None:
        n = self.enc.n_features
        for x in model[:n]:
            if x > 0:
                self._seen_true.add(x)
            else:
                self._seen_false.add(-x)
        # model-based filter for false-optional: this product shows "parent without child"
        for pv, fv, _, _ in self._optional_pairs():
            if model[pv - 1] > 0 and model[fv - 1] < 0:
                self._witnessed.add((pv, fv))

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

    def backbone(self, deadline: Optional[float] = None) -> dict[int, bool]:
        """Feature variable -> forced value, for every feature with one value in all products."""
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
        bb: dict[int, bool] = {}
        for v in range(1, n + 1):
            if v not in cand:
                continue
            val = cand[v]
            lit = v if val else -v
            # push the solver away from every remaining candidate value: many fall at once
            s.set_phases([(-u if cand[u] else u) for u in cand])
            if s.solve(assumptions=[-lit]):
                m = s.get_model()
                self._record(m)
                for u in list(cand):
                    if (m[u - 1] > 0) != cand[u]:
                        del cand[u]
            else:
                bb[v] = val
                del cand[v]
                s.add_clause([lit])
        self._backbone = bb
        return bb

    def core(self) -> list[M.Feature]:
        return [self.enc.feature_of_var[v] for v, val in sorted(self.backbone().items()) if val]

    def dead(self) -> list[M.Feature]:
        return [self.enc.feature_of_var[v] for v, val in sorted(self.backbone().items()) if not val]

    def _optional_pairs(self) -> list[tuple[int, int, M.Feature, M.Feature]]:
        if self._opt_pairs is None:
            v = self.enc.var_of_feature
            seen: set = set()
            out = []
            for p in self.enc.features:
                if p.group is None:
                    continue
                for gc in p.group.children:
                    if gc.optional and gc.feature in v and (v[p], v[gc.feature]) not in seen:
                        seen.add((v[p], v[gc.feature]))
                        out.append((v[p], v[gc.feature], gc.feature, p))
            self._opt_pairs = out
        return self._opt_pairs

    def false_optional(self) -> list[tuple[M.Feature, M.Feature]]:
        """(feature, parent): optional in the parent's group, not dead, yet selected in every
        product that selects the parent."""
        if self.is_void():
            return []
        bb = self.backbone()
        out = []
        s = self.plain
        for pv, fv, f, p in self._optional_pairs():
            if bb.get(pv) is False or bb.get(fv) is False:
                continue
            if bb.get(fv) is True:
                out.append((f, p))
                continue
            if (pv, fv) in self._witnessed:
                continue
            if s.solve(assumptions=[pv, -fv]):
                self._record(s.get_model())
            else:
                out.append((f, p))
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
            if e.negation is None or e.negation == [False]:
                continue
            others = [x for x in allsel if x != e.selector]
            neg = [x for x in e.negation if x is not True]
            if not s.solve(assumptions=others + neg):
                redundant.append(e)
        return redundant, always_false

    # ------------------------------------------------------------------ explanations
    def explain(self, extra: list[int], deadline: Optional[float] = None,
                among: Optional[list[int]] = None) -> Optional[Explanation]:
        """A minimal set of elements that, with the ``extra`` assumption literals, is
        unsatisfiable; None when the query is satisfiable."""
        s = self.selector_solver
        sels = self._selectors if among is None else among
        if s.solve(assumptions=sels + extra):
            return None
        selset = set(sels)
        core = [x for x in (s.get_core() or []) if x in selset]
        core = sorted(set(core), key=lambda x: x)
        minimal = True
        i = 0
        while i < len(core):
            if deadline is not None and time.monotonic() > deadline:
                minimal = False
                break
            trial = core[:i] + core[i + 1:]
            if s.solve(assumptions=trial + extra):
                i += 1
            else:
                got = set(s.get_core() or [])
                core = [x for x in trial if x in got]
        return Explanation([self._sel_of[x] for x in core], minimal)

    def witness(self) -> Optional[list[int]]:
        self.is_void()
        return self._witness
