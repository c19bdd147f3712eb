"""Configuration propagation: the HAROS-TVL configurator's include / exclude / unassign.

Given decisions (feature name -> included?), say which other features they force in or out,
whether they conflict (with a minimal set of conflicting decisions), and how many products
remain.  Unassigning a feature is dropping it from the decisions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Optional, Protocol, Sequence

from .counting.errors import CountCancelled, CountTimeout
from .encode import Encoding
from .solve import decide


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


def _from_circuit(analysis, lits: list[int]):
    """Every feature's count under ``lits`` from the model's compiled d-DNNF when it is in
    memory (None otherwise, or when the decisions conflict: the SAT path finds the minimal set
    of conflicting decisions)."""
    if getattr(type(analysis), "counter", None) is None:
        return None
    r = analysis.counter.feature_counts_if_ready(lits)
    return r if r is not None and r.total else None


def propagate(analysis: Countable, decisions: Mapping[str, bool], count: bool = True,
              timeout: Optional[float] = 5.0) -> Propagation:
    enc = analysis.encoding
    lits: dict[int, str] = {}
    for name, val in decisions.items():
        v = enc.var(name)
        lits[v if val else -v] = name
    res = Propagation(dict(decisions))
    fast = _from_circuit(analysis, list(lits))
    if fast is not None:
        # the model is compiled: one pass over the d-DNNF gives every feature's count under
        # the decisions, and so what they force (count = remaining: in every product; 0: in
        # none) and the remaining count -- instead of a SAT call per open feature
        decided = {abs(x) for x in lits}
        forced = {v: fast.counts[v] == fast.total for v in enc.var_of_feature.values()
                  if v not in decided and fast.counts[v] in (0, fast.total)}
        res.forced = {enc.name_of(enc.feature_of_var[v]): val for v, val in sorted(forced.items())}
        res.open = [enc.name_of(f) for f, v in enc.var_of_feature.items()
                    if v not in decided and v not in forced]
        res.count = fast.total if count else None
        return res
    conflict, forced = decide(enc, list(lits))
    if conflict is not None:
        res.conflict = [lits[x] for x in conflict]
        res.count = 0 if count else None
        return res
    decided = {abs(x) for x in lits}
    res.forced = {enc.name_of(enc.feature_of_var[v]): val for v, val in sorted(forced.items())}
    res.open = [enc.name_of(f) for f, v in enc.var_of_feature.items()
                if v not in decided and v not in forced]
    if count:
        inc = [k for k, val in decisions.items() if val]
        exc = [k for k, val in decisions.items() if not val]
        try:
            res.count = analysis.count(include=inc, exclude=exc, timeout=timeout)
        except (CountTimeout, CountCancelled):
            res.count = None
    return res
