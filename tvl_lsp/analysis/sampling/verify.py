"""Is a t-wise sample valid and complete?  An independent check for tests and benchmarks.

    r = verify(clauses, n, configurations, t=2)      # configurations: lists of literals
    r.valid, r.complete, r.missing[:10], r.summary()

- **valid**: every configuration is a product: a SAT call with its literals as assumptions (the
  CNF may have auxiliary variables above ``n``; a configuration may leave features unset: a
  partial configuration counts as valid when some product extends it);
- **complete**: every valid interaction of ``t`` literals of distinct features ``1..n`` occurs in
  some configuration (a literal a partial configuration leaves unset covers nothing).  Checked
  *exhaustively* for t <= 2 when the uncovered pairs are few enough to ask each (an uncovered pair
  must be invalid: unit propagation or a SAT call says so), for t = 3 triple by triple on small
  models and otherwise every triple containing each of ``pair_sample`` random pairs; and in any
  case on ``random_sample`` (3,000) interactions drawn uniformly at random.

The check shares nothing with the sampler but the solver library: no implication graph, no
equivalence classes, no backbone; a fresh solver on the CNF as given.
"""

from __future__ import annotations

import itertools
import random
import time
from dataclasses import dataclass, field
from typing import Iterable, Optional, Sequence

from ..sat import BoundedSolver
from .bits import even_mask as EVEN, iter_bits, lit

EXHAUSTIVE_CHECKS = 400_000  # SAT calls at most for an exhaustive pair check
EXHAUSTIVE_TRIPLES = 2_000_000  # literal triples at most for an exhaustive triple check


@dataclass
class Verification:
    t: int
    configurations: int
    valid: bool = True
    invalid_configurations: list[int] = field(default_factory=list)  # indices
    complete: bool = True
    exhaustive: bool = False
    checked: int = 0           # interactions checked (covered, or proven invalid)
    covered: int = 0           # of the checked ones, covered by the sample
    random_checked: int = 0
    missing: list[tuple[int, ...]] = field(default_factory=list)  # valid interactions not covered
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        return self.valid and self.complete

    def summary(self) -> str:
        how = "every interaction" if self.exhaustive else "sampled interactions"
        return (f"{self.configurations} configurations, t = {self.t}: "
                f"{'valid' if self.valid else f'{len(self.invalid_configurations)} invalid'}, "
                f"{'complete' if self.complete else f'{len(self.missing)}+ valid interactions missing'} "
                f"({how}: {self.checked} checked, {self.random_checked} at random) in {self.seconds:.1f} s")


def _bit(x: int) -> int:
    return 2 * x - 2 if x > 0 else -2 * x - 1


def verify(clauses: Sequence[Sequence[int]], n: int, configurations: Sequence[Iterable[int]], t: int = 2,
           seed: int = 0, random_sample: int = 3000, pair_sample: int = 300,
           exhaustive: bool = True, deadline: Optional[float] = None) -> Verification:
    t0 = time.monotonic()
    confs = [sorted({x for x in c if x and abs(x) <= n}, key=abs) for c in configurations]
    r = Verification(t=t, configurations=len(confs))
    s = BoundedSolver(name="minisat22", bootstrap_with=[list(c) for c in clauses])
    try:
        for k, c in enumerate(confs):
            if not s.solve(assumptions=c):
                r.valid = False
                r.invalid_configurations.append(k)
        # occ[i]: bitset of the configurations with literal bit i; sets[k]: configuration k's bits
        occ = [0] * (2 * n)
        sets = []
        for k, c in enumerate(confs):
            b = 0
            for x in c:
                i = _bit(x)
                occ[i] |= 1 << k
                b |= 1 << i
            sets.append(b)
        dead: dict[int, bool] = {}
        prop: dict[int, int] = {}

        def implied(x: int) -> Optional[int]:
            """Bits of the literals unit propagation forces from x (None: x alone is unsat)."""
            if x not in prop:
                ok, lits = s.propagate(assumptions=[x])
                if not ok:
                    prop[x] = -1
                else:
                    b = 0
                    for y in lits:
                        if -n <= y <= n and y:
                            b |= 1 << _bit(y)
                    prop[x] = b
            v = prop[x]
            return None if v == -1 else v

        def valid(xs: Sequence[int]) -> bool:
            for x in xs:
                imp = implied(x)
                if imp is None:
                    return False
                for y in xs:
                    if y != x and (imp >> _bit(-y)) & 1:
                        return False
            return bool(s.solve(assumptions=list(xs)))

        def covered(xs: Sequence[int]) -> bool:
            m = -1
            for x in xs:
                m &= occ[_bit(x)]
                if not m:
                    return False
            return m != 0

        def check(xs: Sequence[int]) -> None:
            r.checked += 1
            if covered(xs):
                r.covered += 1
            elif valid(xs):
                r.complete = False
                if len(r.missing) < 100:
                    r.missing.append(tuple(xs))

        def out_of_time() -> bool:
            return deadline is not None and time.monotonic() > deadline

        rng = random.Random(seed)
        if t == 1:
            for v in range(1, n + 1):
                for x in (v, -v):
                    check([x])
            r.exhaustive = True
        elif t == 2 and exhaustive:
            r.exhaustive = _pairs_exhaustive(n, occ, sets, check, covered, implied, r, out_of_time)
        elif t == 3 and exhaustive:
            r.exhaustive = _triples(n, occ, sets, check, rng, pair_sample, r, out_of_time)
        # uniformly random interactions (t distinct variables, random signs)
        if n >= t:
            for _ in range(random_sample):
                vs = rng.sample(range(1, n + 1), t)
                check([v if rng.random() < 0.5 else -v for v in vs])
                r.random_checked += 1
    finally:
        s.delete()
    r.seconds = time.monotonic() - t0
    return r


def _pairs_exhaustive(n, occ, sets, check, covered, implied, r, out_of_time) -> bool:
    """Every pair of literals: covered, or invalid.  The pairs a sample covers are found with
    bitsets (the literals of the configurations with ``a``); the others are asked one by one
    (unit propagation first), unless there are more than :data:`EXHAUSTIVE_CHECKS`."""
    size = 2 * n
    full = (1 << size) - 1
    # nb[a]: partners b with (a, b) invalid by unit propagation (a forces not b, b forces not a)
    nb = [0] * size
    none = []
    for a in range(size):
        imp = implied(lit(a))
        if imp is None:
            none.append(a)
            continue
        nb[a] |= ((imp & EVEN(n)) << 1) | ((imp >> 1) & EVEN(n))
    for a in range(size):
        for b in iter_bits(nb[a]):
            nb[b] |= 1 << a
    for a in none:
        nb[a] = full
        for b in range(size):
            nb[b] |= 1 << a
    uncov: list[tuple[int, int]] = []
    for a in range(size):
        part = 0
        for k in iter_bits(occ[a]):
            part |= sets[k]
        above = full & ~((1 << (a | 1) + 1) - 1)  # literals of the variables above a's
        got = (part & above).bit_count()
        r.checked += got
        r.covered += got
        rest = above & ~part & ~nb[a]
        if rest:
            x = lit(a)
            for b in iter_bits(rest):
                uncov.append((x, lit(b)))
            if len(uncov) > EXHAUSTIVE_CHECKS:
                return False
    for xs in uncov:
        if out_of_time():
            return False
        check(list(xs))
    return True


def _triples(n, occ, sets, check, rng, pair_sample, r, out_of_time) -> bool:
    """Every triple on small models; otherwise every triple that contains one of
    ``pair_sample`` random pairs of literals."""
    size = 2 * n
    total = size * (size - 2) * (size - 4) // 6
    if total <= EXHAUSTIVE_TRIPLES:
        for va, vb, vc in itertools.combinations(range(1, n + 1), 3):
            for sa, sb, sc in itertools.product((1, -1), repeat=3):
                if out_of_time():
                    return False
                check([sa * va, sb * vb, sc * vc])
        return True
    full = (1 << size) - 1
    for _ in range(pair_sample):
        if out_of_time():
            break
        va, vb = rng.sample(range(1, n + 1), 2)
        a, b = (va if rng.random() < 0.5 else -va), (vb if rng.random() < 0.5 else -vb)
        both = occ[_bit(a)] & occ[_bit(b)]
        part = 0
        for k in iter_bits(both):
            part |= sets[k]
        rest = full & ~part & ~(3 << (2 * va - 2)) & ~(3 << (2 * vb - 2))
        for c in iter_bits(rest):
            check([a, b, lit(c)])
    return False
