"""T-wise sampling: a small set of valid products that together contain every valid pair
(t = 2) or every valid literal (t = 1) of features.

A greedy covering in the style of YASA / Chvatal's algorithm, over an *oracle* that answers
"is there a product with these feature literals?" and "complete these literals to a product":

1. the valid literals, then for each valid literal ``a`` the literals ``b`` it can be combined
   with (one pass over the d-DNNF per literal: every feature's count under ``a``);
2. while some valid pair is uncovered: start from the decisions, walk the uncovered pairs in
   a seeded order and add a pair's literals whenever the product being built can still have
   them (the oracle says which literals are still possible after each addition), then
   complete it to a product (uniformly at random among its completions with the d-DNNF) and
   mark every pair it contains as covered.

Every configuration is a product (the oracle completes it), every valid pair ends up covered
(each round covers at least the first pair it tries, which is valid), and with the same seed
the sample is the same.  Pairs are kept as bitsets (one Python int per literal), so a model
of ``n`` features needs ``4 n^2`` bits.
"""

from __future__ import annotations

import random
import time
from typing import Optional, Sequence

from .errors import CancelLike, CountCancelled, CountTimeout, is_cancelled

MAX_FEATURES = 1500  # open features: 2n literal passes and 4n^2 bits of bookkeeping: beyond, too slow here


def _idx(x: int) -> int:
    return 2 * (abs(x) - 1) + (1 if x < 0 else 0)


def _lit(i: int) -> int:
    v = i // 2 + 1
    return -v if i & 1 else v


class CircuitOracle:
    """Answers from a compiled d-DNNF (:class:`.circuit.Circuit`)."""

    def __init__(self, circuit, n: int):
        self.c = circuit
        self.n = n

    def support(self, lits: Sequence[int]) -> int:
        """Bitset of the literal indices some product with ``lits`` has (0: no product)."""
        r = self.c.counts(lits)
        if not r.total:
            return 0
        bits = 0
        for v in range(1, self.n + 1):
            p = r.positive[v]
            if p:
                bits |= 1 << (2 * (v - 1))
            if r.total - p:
                bits |= 1 << (2 * (v - 1) + 1)
        return bits

    def sat(self, lits: Sequence[int]) -> bool:
        return self.c.count(lits) > 0

    def complete(self, lits: Sequence[int], rng: random.Random) -> Optional[list[int]]:
        s = self.c.sample(rng, lits)
        if s is None:
            return None
        return [x for x in s if abs(x) <= self.n]


class SatOracle:
    """Answers with a SAT solver (python-sat) on the CNF: the fallback when the d-DNNF does
    not count products (attribute values the features do not determine)."""

    def __init__(self, clauses: Sequence[Sequence[int]], n: int):
        from ..sat import BoundedSolver as Solver
        self.s = Solver(name="minisat22", bootstrap_with=[list(c) for c in clauses])
        self.n = n

    def close(self) -> None:
        self.s.delete()

    def sat(self, lits: Sequence[int]) -> bool:
        return bool(self.s.solve(assumptions=list(lits)))

    def support(self, lits: Sequence[int]) -> int:
        if not self.sat(lits):
            return 0
        m = self.s.get_model()
        bits = 0
        # the model found settles one literal of each feature; ask only about the other
        for v in range(1, self.n + 1):
            x = v if m[v - 1] > 0 else -v
            bits |= 1 << _idx(x)
            if self.s.solve(assumptions=list(lits) + [-x]):
                bits |= 1 << _idx(-x)
        return bits

    def complete(self, lits: Sequence[int], rng: random.Random) -> Optional[list[int]]:
        # random phases, so that the free features of the sample vary
        self.s.set_phases([v if rng.random() < 0.5 else -v for v in range(1, self.n + 1)])
        if not self.s.solve(assumptions=list(lits)):
            return None
        m = self.s.get_model()
        return [m[v - 1] if v - 1 < len(m) else -v for v in range(1, self.n + 1)]


def _bits(x: int):
    while x:
        low = x & -x
        yield low.bit_length() - 1
        x ^= low


def twise(oracle, n: int, t: int = 2, seed: Optional[int] = 0, assumptions: Sequence[int] = (),
          timeout: Optional[float] = None, cancel: CancelLike = None) -> list[list[int]]:
    """Products (lists of the ``n`` feature literals) covering every valid ``t``-combination
    (t = 1 or 2) of feature literals among the products with ``assumptions``."""
    if t not in (1, 2):
        raise ValueError("t-wise sampling supports t = 1 and t = 2")
    start = time.monotonic()

    def check():
        if is_cancelled(cancel):
            raise CountCancelled()
        if timeout is not None and time.monotonic() - start > timeout:
            raise CountTimeout(f"no sample within {timeout:g} s")

    rng = random.Random(seed)
    base = list(assumptions)
    valid = oracle.support(base)
    if not valid:
        return []
    lits = list(_bits(valid))
    # a feature with one valid literal (decided, core or dead) is in every product as it is: its
    # literal combines with every valid literal, no pass needed to know which
    open_ = {i >> 1 for i in lits if (valid >> (i ^ 1)) & 1}
    if len(open_) > MAX_FEATURES:
        raise ValueError(f"t-wise sampling handles up to {MAX_FEATURES} open features, "
                         f"not {len(open_)}")
    # uncovered[i]: bitset of the literals j > i such that (i, j) is valid and not yet covered
    # (t = 1: uncovered[i] has bit i itself when literal i is valid and not yet covered)
    uncovered: dict[int, int] = {}
    if t == 1:
        for i in lits:
            uncovered[i] = 1 << i
    else:
        for i in lits:
            check()
            sup = oracle.support(base + [_lit(i)]) if (i >> 1) in open_ else valid
            # pairs with a literal of another variable, above i
            mask = sup & ~((1 << (i | 1) + 1) - 1)
            if mask:
                uncovered[i] = mask
    out: list[list[int]] = []
    while uncovered:
        check()
        cur = list(base)
        have = 0  # bitset of the literals in cur
        for x in base:
            have |= 1 << _idx(x)
        allowed = valid
        keys = list(uncovered)
        rng.shuffle(keys)
        for i in keys:
            rest = uncovered.get(i, 0)
            if not rest or not (allowed >> i) & 1:
                continue
            cands = rest & allowed
            if t == 1:
                cands = 1 << i
            for j in _bits(cands):
                if not (allowed >> j) & 1 or not (allowed >> i) & 1:
                    continue
                need = [x for x in {i, j} if not (have >> x) & 1]
                if not need:
                    continue
                trial = cur + [_lit(x) for x in need]
                if len(need) == 2:
                    check()
                    if not oracle.sat(trial):
                        continue
                cur = trial
                for x in need:
                    have |= 1 << x
                check()
                allowed = oracle.support(cur)
                if t == 1:
                    break
        product = oracle.complete(cur, rng)
        if product is None:  # cannot happen: cur was checked satisfiable
            raise RuntimeError("the sampler lost a product")
        pbits = 0
        for x in product:
            pbits |= 1 << _idx(x)
        for i in list(uncovered):
            if (pbits >> i) & 1:
                left = uncovered[i] & ~pbits
                if left:
                    uncovered[i] = left
                else:
                    del uncovered[i]
        out.append(product)
    return out
