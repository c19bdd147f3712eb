"""Configuration propagation: the HAROS-TVL configurator's include / exclude / unassign.

Given decisions (feature name -> included?), say which other features they force in or out,
whether they conflict (with a minimal set of conflicting decisions), and how many products
remain.  Unassigning a feature is dropping it from the decisions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Optional, Protocol, Sequence

from pysat.solvers import Solver

from .count import CountCancelled, CountTimeout
from .encode import Encoding
from .solve import SOLVER, backbone_of


class Countable(Protocol):
    """What propagation needs of a model's analysis (``engine.ModelAnalysis`` is one): its
    encoding and a count under include / exclude decisions."""

    encoding: Encoding

    def count(self, *, include: Sequence[str] = (), exclude: Sequence[str] = (),
              timeout: Optional[float] = None) -> Optional[int]: ...


@dataclass
class Propagation:
    decisions: dict[str, bool]
    # features (not decided) that every product respecting the decisions selects (True) or not
    forced: dict[str, bool] = field(default_factory=dict)
    # a minimal set of decisions that cannot hold together (None: no conflict)
    conflict: Optional[list[str]] = None
    # products that remain (None: not counted, or no answer in time)
    count: Optional[int] = None
    # features whose value is still open
    open: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.conflict is None


def propagate(analysis: Countable, decisions: Mapping[str, bool], count: bool = True,
              timeout: Optional[float] = 5.0) -> Propagation:
    enc = analysis.encoding
    lits: dict[int, str] = {}
    for name, val in decisions.items():
        v = enc.var(name)
        lits[v if val else -v] = name
    res = Propagation(dict(decisions))
    s = Solver(name=SOLVER, bootstrap_with=enc.clauses())
    try:
        assumptions = list(lits)
        if not s.solve(assumptions=assumptions):
            core = [x for x in (s.get_core() or []) if x in lits]
            i = 0
            while i < len(core):  # deletion-based: every kept decision is needed
                trial = core[:i] + core[i + 1:]
                if s.solve(assumptions=trial):
                    i += 1
                else:
                    got = set(s.get_core() or [])
                    core = [x for x in trial if x in got]
            res.conflict = [lits[x] for x in core]
            res.count = 0 if count else None
            return res
        n = enc.n_features
        m = s.get_model()
        decided = {abs(x) for x in lits}
        cand = {v: m[v - 1] > 0 for v in range(1, n + 1) if v not in decided}
        forced = backbone_of(s, cand, assumptions)
        res.forced = {enc.name_of(enc.feature_of_var[v]): val for v, val in sorted(forced.items())}
        res.open = [enc.name_of(f) for f, v in enc.var_of_feature.items()
                    if v not in decided and v not in forced]
    finally:
        s.delete()
    if count:
        inc = [k for k, val in decisions.items() if val]
        exc = [k for k, val in decisions.items() if not val]
        try:
            res.count = analysis.count(include=inc, exclude=exc, timeout=timeout)
        except (CountTimeout, CountCancelled):
            res.count = None
    return res
