"""What the sampler learns about a formula before it samples: the core and dead features, the
literals each literal implies, and the features that are equivalent to others.

- **Backbone** (core and dead features, and the decisions): features with one value in every
  product.  An interaction with one of them is covered by any configuration that covers the
  rest of it, so they take no part in the interactions.
- **Implications**: unit propagation of each open literal on the solver (which sees every
  clause, not only the binary ones), as a bitset of the literals it forces.  ``a`` forces ``x``
  means the pair ``(a, not x)`` is invalid: most invalid pairs of a feature model (a child
  without its parent, two alternatives of a group, ``requires`` / ``excludes``) are known from
  this alone, without a SAT call.
- **Equivalent features** (a mandatory child and its parent, features that imply each other):
  ``u`` and ``v`` with ``u -> v`` and ``v -> u`` (or ``u -> not v`` and ``not v -> u``) are one
  class; only its representative (the smallest variable) takes part in interactions: an
  interaction with ``v`` is covered exactly when the same interaction with the representative
  is.

The solver is kept: the backbone is added to it as unit clauses, and the sampler asks it its
questions under assumptions (warm: learnt clauses and phases carry over between calls).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional, Sequence

from ..sat import BoundedSolver
from ..solve import backbone_of, new_solver
from .bits import even_mask, idx, negate


class SamplingTimeout(Exception):
    """The budget ran out before the preparation was done (nothing to show yet)."""


@dataclass
class Prepared:
    n: int                            # the features are variables 1..n
    solver: Optional[BoundedSolver]   # the CNF, the decisions and the backbone; None when void
    void: bool
    fixed: dict[int, bool] = field(default_factory=dict)   # var -> value in every product
    rep_of: dict[int, int] = field(default_factory=dict)   # open var -> its representative literal
    reps: list[int] = field(default_factory=list)          # representative variables, increasing
    imp: dict[int, int] = field(default_factory=dict)      # rep literal bit -> rep literal bits it forces
    nimp: dict[int, int] = field(default_factory=dict)     # ... -> the negations of it and what it forces
    even: int = 0                     # positive-literal bits of variables 1..n
    repmask: int = 0                  # both literal bits of every representative variable
    model: Optional[list[int]] = None  # a product (a solver model)
    seconds: float = 0.0
    sat_calls: int = 0

    def close(self) -> None:
        if self.solver is not None:
            self.solver.delete()
            self.solver = None

    @property
    def open_vars(self) -> int:
        return len(self.rep_of)


def prepare(clauses: Sequence[Sequence[int]], n: int, assumptions: Sequence[int] = (),
            deadline: Optional[float] = None) -> Prepared:
    """Prepare the CNF ``clauses`` whose features are variables ``1..n`` for sampling, under
    ``assumptions`` (feature literals every configuration must have).  ``deadline``: a
    ``time.monotonic()`` after which :class:`SamplingTimeout` is raised."""
    t0 = time.monotonic()
    s = new_solver(clauses)
    known = max(0, s.nof_vars() or 0)
    for v in range(known + 1, n + 1):  # features in no clause: the solver must know them
        s.add_clause([v, -v])          # (its models then list every feature)
    for x in assumptions:
        s.add_clause([x])
    if not s.solve():
        s.delete()
        return Prepared(n=n, solver=None, void=True, seconds=time.monotonic() - t0)
    m = s.get_model()
    cand = {v: m[v - 1] > 0 for v in range(1, n + 1) if v <= len(m)}
    calls = [0]

    def seen(_m):
        calls[0] += 1
    bb = backbone_of(s, cand, [], record=seen, deadline=deadline, n_features=n)
    if bb is None:
        s.delete()
        raise SamplingTimeout("the core and dead features were not found in time")
    for v, val in bb.items():
        s.add_clause([v if val else -v])
    fixed = dict(bb)
    open_vars = [v for v in range(1, n + 1) if v not in fixed]
    # unit propagation of every open literal
    prop: dict[int, list[int]] = {}
    for k, v in enumerate(open_vars):
        if deadline is not None and not k % 256 and time.monotonic() > deadline:
            s.delete()
            raise SamplingTimeout("the implications were not found in time")
        for x in (v, -v):
            ok, lits = s.propagate(assumptions=[x])
            if not ok:  # cannot happen: x is in some product (not in the backbone)
                raise RuntimeError(f"literal {x} propagates to a conflict but is not dead")
            prop[x] = [y for y in lits if -n <= y <= n and y != x and abs(y) not in fixed]
    # equivalent variables: v -> y and y -> v for a literal y of another variable; each class
    # (a connected component of these edges) is represented by its smallest variable
    edges: dict[int, list[int]] = {}
    for v in open_vars:
        for y in prop[v]:
            if v in prop.get(y, ()):
                edges.setdefault(v, []).append(y)
                edges.setdefault(abs(y), []).append(v if y > 0 else -v)
    rep_of: dict[int, int] = {}
    for v in open_vars:  # increasing: the first variable met of a class is its smallest
        if v in rep_of:
            continue
        rep_of[v] = v
        stack = [v]
        while stack:
            u = stack.pop()
            ru = rep_of[u]
            for y in edges.get(u, ()):
                w = abs(y)
                if w not in rep_of:
                    rep_of[w] = ru if y > 0 else -ru
                    stack.append(w)
    reps = [v for v in open_vars if rep_of[v] == v]
    even = even_mask(n)
    repmask = 0
    for v in reps:
        repmask |= 3 << (2 * v - 2)
    imp: dict[int, int] = {}
    nimp: dict[int, int] = {}
    for v in reps:
        for x in (v, -v):
            b = 0
            for y in prop[x]:
                r = rep_of[abs(y)]
                z = r if y > 0 else -r
                if z != x:
                    b |= 1 << (2 * z - 2 if z > 0 else -2 * z - 1)
            imp[idx(x)] = b
            nimp[idx(x)] = negate(b | (1 << idx(x)), even)
    return Prepared(n=n, solver=s, void=False, fixed=fixed, rep_of=rep_of, reps=reps, imp=imp, nimp=nimp, even=even,
                    repmask=repmask, model=m, seconds=time.monotonic() - t0, sat_calls=calls[0] + 1)
