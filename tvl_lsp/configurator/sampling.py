"""A pairwise (t = 2) sample of the products that remain under decisions.

Interim greedy covering on the SAT solver, to be replaced by the counting service's t-wise
sampling (issue #15, ddnnife) through :data:`SAMPLER`: every configuration is a valid product
respecting the decisions, and every pair of literals of the open features that some such product
has is covered by one of them (up to ``limit`` configurations).
"""

from __future__ import annotations

import itertools
import time
from typing import Mapping, Optional

from pysat.solvers import Solver

from ..analysis.solve import SOLVER


def greedy_pairwise(analysis, decisions: Mapping[str, bool], open_features: list[str],
                    limit: int = 100, timeout: Optional[float] = 20.0) -> list[dict[str, bool]]:
    enc = analysis.encoding
    base = [enc.var(k) if v else -enc.var(k) for k, v in decisions.items()]
    lits = [enc.var(f) for f in open_features]
    n = enc.n_features
    deadline = None if timeout is None else time.monotonic() + timeout
    s = Solver(name=SOLVER, bootstrap_with=enc.clauses())
    out: list[dict[str, bool]] = []
    try:
        if not s.solve(assumptions=base):
            return []
        uncovered = set()
        for a, b in itertools.combinations(lits, 2):
            for x, y in ((a, b), (a, -b), (-a, b), (-a, -b)):
                uncovered.add((x, y))
        if not lits:
            m = s.get_model()
            return [analysis._product(m)]
        for a in lits:  # single features too (a model with one open feature has no pairs)
            uncovered.add((a, a))
            uncovered.add((-a, -a))
        while uncovered and len(out) < limit:
            if deadline is not None and time.monotonic() > deadline:
                break
            first = min(uncovered, key=lambda p: (abs(p[0]), abs(p[1]), p))
            assume = base + list(dict.fromkeys(first))
            if not s.solve(assumptions=assume):
                uncovered.discard(first)  # no product has this pair
                continue
            # greedily add more uncovered pairs that still leave a product
            for p in sorted(uncovered, key=lambda p: (abs(p[0]), abs(p[1]), p)):
                if p == first:
                    continue
                if -p[0] in assume or -p[1] in assume:
                    continue
                trial = assume + [x for x in dict.fromkeys(p) if x not in assume]
                if len(trial) == len(assume) or s.solve(assumptions=trial):
                    assume = trial
            s.solve(assumptions=assume)
            m = s.get_model()
            val = {v: m[v - 1] > 0 for v in range(1, n + 1)}
            covered = {p for p in uncovered
                       if val[abs(p[0])] == (p[0] > 0) and val[abs(p[1])] == (p[1] > 0)}
            uncovered -= covered
            out.append(analysis._product(m))
    finally:
        s.delete()
    return out


SAMPLER = greedy_pairwise


def set_sampler(fn) -> None:
    global SAMPLER
    SAMPLER = fn
