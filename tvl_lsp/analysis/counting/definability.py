"""Are the auxiliary variables of an encoding functions of its features?

If every auxiliary variable (numbered above the features) is determined by the features, each
product extends to exactly one model of the CNF, so a count over all variables -- what d4's
d-DNNF gives -- is the number of products.  The TVL encoding's Tseitin and counter variables are
determined by construction (their defining clauses are equivalences), so only the variables that
hold attribute values need a check: Padoa's test, one SAT call.
"""

from __future__ import annotations

import threading
from typing import Optional, Sequence


def attributes_determined(clauses: Sequence[Sequence[int]], n_features: int, nvars: int,
                          attribute_vars: Sequence[int], time_budget: Optional[float] = 5.0) -> bool:
    """The CNF twice, the features shared, some attribute variable different: unsatisfiable iff
    every attribute variable is determined by the features.  Attribute variables that occur in
    no clause are left out (they are not counted).  False when the SAT call does not finish
    within ``time_budget``."""
    used = {abs(x) for c in clauses for x in c}
    attrs = [v for v in attribute_vars if v in used]
    if not attrs:
        return True
    from ..sat import BoundedSolver as Solver
    n, top = n_features, nvars

    def shift(x: int) -> int:
        return x if abs(x) <= n else (x + top - n if x > 0 else x - top + n)

    cnf = [list(c) for c in clauses] + [[shift(x) for x in c] for c in clauses]
    diff = []
    for i, v in enumerate(attrs):
        d = 2 * top + i + 1
        w = shift(v)
        cnf.append([-d, v, w])
        cnf.append([-d, -v, -w])
        diff.append(d)
    cnf.append(diff)
    with Solver(name="minisat22", bootstrap_with=cnf) as s:
        if time_budget is None:
            res = s.solve()
        else:
            timer = threading.Timer(time_budget, s.interrupt)
            timer.start()
            try:
                res = s.solve_limited(expect_interrupt=True)
            finally:
                timer.cancel()
    # unsatisfiable: no two models agree on the features and differ on an attribute
    return res is False
