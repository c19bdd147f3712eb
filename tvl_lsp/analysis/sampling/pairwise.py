"""Pairwise (and 1-wise) covering: configurations grown greedily with a warm SAT solver.

The interactions are the pairs of literals of two representative variables (see
:mod:`.prepare`).  ``unc[a]`` is the bitset of the literals ``b`` such that the pair ``(a, b)`` is
not covered yet and not known to be invalid (symmetric: ``b`` in ``unc[a]`` iff ``a`` in
``unc[b]``).  Pairs known invalid from the implications never enter it.

One configuration at a time (IncLing's order, AETG's density, YASA's tests):

- **seed**: the literal with the most uncovered pairs and its partner with the most; the solver
  confirms the pair (a pair it refuses is invalid: it leaves ``unc`` for good, learnt once);
- **density**: every variable with uncovered pairs, in a seeded order, takes the literal with
  more uncovered pairs with the literals the configuration already has (what its decisions force
  by unit propagation, ``L``), unless propagation says it conflicts with them (``NL``);
- **tail**: when no variable gains anything, an uncovered pair of two undecided variables that
  fits is added, and the density pass runs again;
- **check**: one SAT call with the decisions as assumptions (the undecided variables with
  uncovered pairs get phases towards their better literal); when propagation missed a conflict,
  the core names the decisions involved and the latest goes;
- the configuration is the solver's model: every pair of its literals is covered.

Every configuration is a model of the CNF, and each covers at least its seed pair (or the seed
proves invalid), so the loop ends with every valid pair covered.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from itertools import compress
from typing import Callable, Optional

from .bits import from_model, iter_bits, lit, negate, shuffled
from .prepare import Prepared


class Stop(Exception):
    """The budget ran out (or the caller cancelled): the sample so far is partial."""


@dataclass
class CoverState:
    """What is left to cover, shared by the configurations of one run."""
    unc: list[int]                    # literal bit -> uncovered partners (t = 2) / itself (t = 1)
    total: int                        # interactions at the start (before any SAT call)
    invalid: int = 0                  # proven invalid since
    products: list[list[int]] = field(default_factory=list)  # solver models, features only
    sat_calls: int = 0
    cnt: list[int] = field(default_factory=list)  # unc[i].bit_count(), kept up to date (t = 2)

    def left(self) -> int:
        return sum(map(int.bit_count, self.unc)) // 2


def initial_pairs(p: Prepared) -> CoverState:
    """Every pair of literals of two representative variables not known invalid by unit
    propagation."""
    size = 2 * p.n
    unc = [0] * size
    even = p.even
    # nb[a]: partners known invalid with a (a forces not b, or b forces not a)
    nb = [0] * size
    for i, b in p.imp.items():
        nb[i] |= negate(b, even)
    for i in list(p.imp):
        for j in iter_bits(nb[i]):
            nb[j] |= 1 << i
    total = 0
    for v in p.reps:
        for i in (2 * v - 2, 2 * v - 1):
            u = p.repmask & ~(3 << (2 * v - 2)) & ~nb[i]
            unc[i] = u
            total += u.bit_count()
    return CoverState(unc=unc, total=total // 2, cnt=list(map(int.bit_count, unc)))


class PairCover:
    def __init__(self, p: Prepared, state: CoverState, rng: random.Random,
                 check: Callable[[], None]):
        self.p = p
        self.st = state
        self.rng = rng
        self.check = check
        self.s = p.solver
        self.model = list(p.model or [])
        self.n = p.n

    # ------------------------------------------------------------------ SAT
    def _sat(self, assumptions: list[int]) -> bool:
        self.st.sat_calls += 1
        ok = self.s.solve(assumptions=assumptions)
        if ok:
            self.model = self.s.get_model()
        return ok

    def _learn_invalid(self, a: int, b: int) -> None:
        unc, cnt = self.st.unc, self.st.cnt
        if (unc[a] >> b) & 1:
            unc[a] &= ~(1 << b)
            unc[b] &= ~(1 << a)
            self.st.invalid += 1
            if cnt:
                cnt[a] -= 1
                cnt[b] -= 1

    # ------------------------------------------------------------------ one configuration
    def _seed(self, active: list[int]) -> Optional[tuple[int, int]]:
        """The pair to start a configuration from: a literal with the most uncovered pairs and
        its partner with the most; a pair that proves invalid is learnt, and the next tried."""
        unc, cnt = self.st.unc, self.st.cnt
        key = cnt.__getitem__
        while True:
            if not active:
                return None
            best = max(active, key=key)
            if cnt[best] <= 0:
                return None
            b = max(iter_bits(unc[best]), key=key)
            if self._sat([lit(best), lit(b)]):
                return best, b
            self._learn_invalid(best, b)

    def next_configuration(self) -> Optional[list[int]]:
        """Grow one configuration; return it (the literals of features 1..n), or None when
        every pair is covered or proven invalid."""
        p, unc, imp, nimp = self.p, self.st.unc, self.p.imp, self.p.nimp
        even, n = p.even, self.n
        active = list(compress(range(len(unc)), unc))
        seed = self._seed(active)
        if seed is None:
            return None
        a, b = seed
        dec = [lit(a), lit(b)]
        L = imp[a] | imp[b] | (1 << a) | (1 << b)
        NL = negate(L, even)
        bad = 0
        avars = shuffled(sorted({i >> 1 for i in active}), self.rng)
        rnd = self.rng.random
        order = shuffled(active, self.rng)
        skipped = avars
        for rounds in range(3):
            # A: each variable towards the literal with more uncovered pairs with the literals
            # already in the configuration (AETG's density)
            todo, skipped = skipped, []
            for v2 in todo:
                i = 2 * v2
                if (L >> i) & 3:
                    continue  # decided (by a decision or what it forces)
                gp = (unc[i] & L).bit_count()
                gn = (unc[i + 1] & L).bit_count()
                if not gp and not gn:
                    skipped.append(v2)
                    continue
                first = i if gp > gn or (gp == gn and rnd() < 0.5) else i + 1
                for c in (first, first ^ 1):
                    if c != first and not (gp if c == i else gn):
                        break
                    cb = 1 << c
                    if (NL | bad) & cb or imp[c] & NL:
                        continue
                    dec.append(lit(c))
                    L |= imp[c] | cb
                    NL |= nimp[c]
                    break
            if rounds == 2 or not skipped:
                break
            # B: an uncovered pair of two undecided variables that fits (the tail: pairs that
            # share no literal with the configuration so far)
            added = False
            blocked = L | NL | bad
            for x in order:
                xb = 1 << x
                if blocked & xb or imp[x] & NL:
                    continue
                cand = unc[x] & ~blocked
                if not cand:
                    continue
                lx = imp[x] | xb
                nlx = negate(lx, even)
                for y in iter_bits(cand):
                    yb = 1 << y
                    if yb & nlx or imp[y] & (NL | nlx):
                        continue
                    dec.append(lit(x))
                    dec.append(lit(y))
                    L |= lx | imp[y] | yb
                    NL |= nimp[x] | nimp[y]
                    blocked = L | NL | bad
                    added = True
                    break
            if not added:
                break
        # complete: the undecided variables with uncovered pairs towards their better literal (the
        # others cover nothing whatever they are); one SAT call (more when unit propagation
        # missed a conflict: drop the latest decision of the core)
        pref = []
        for v2 in skipped:
            i = 2 * v2
            if not (L >> i) & 3:
                gp = (unc[i] & L).bit_count()
                gn = (unc[i + 1] & L).bit_count()
                pref.append(v2 + 1 if gp > gn or (gp == gn and rnd() < 0.5) else -v2 - 1)
        self.s.set_phases(pref)
        while not self._sat(dec):
            core = set(self.s.get_core() or ())
            pos = {x: k for k, x in enumerate(dec)}
            drop = max((pos[x] for x in core if x in pos and pos[x] >= 2), default=None)
            if drop is None:
                raise RuntimeError("the seed pair of a configuration became unsatisfiable")
            del dec[drop]
        product = self.model[:n]
        wb = from_model(product, n) & p.repmask
        cnt = self.st.cnt
        for i in iter_bits(wb):
            u = unc[i]
            if u:
                u &= ~wb
                unc[i] = u
                cnt[i] = u.bit_count()
        return product


def initial_literals(p: Prepared) -> CoverState:
    """t = 1: every literal of a representative variable (each is in some product: the
    backbone holds the others).  ``unc[a]`` is ``a``'s own bit while ``a`` is uncovered."""
    unc = [0] * (2 * p.n)
    for v in p.reps:
        for i in (2 * v - 2, 2 * v - 1):
            unc[i] = 1 << i
    return CoverState(unc=unc, total=2 * len(p.reps))


class LiteralCover(PairCover):
    """t = 1: each configuration takes the uncovered literals that fit, in a seeded order."""

    def next_configuration(self) -> Optional[list[int]]:
        p, unc, imp, nimp = self.p, self.st.unc, self.p.imp, self.p.nimp
        even, n = p.even, self.n
        order = shuffled(list(compress(range(len(unc)), unc)), self.rng)
        if not order:
            return None
        dec: list[int] = []
        L = NL = 0
        for x in order:
            xb = 1 << x
            if (L | NL) & xb or imp[x] & NL:
                continue
            dec.append(lit(x))
            L |= imp[x] | xb
            NL |= nimp[x]
        pref = [v if unc[2 * v - 2] else -v for v in p.reps if not (L >> (2 * v - 2)) & 3]
        self.s.set_phases(pref)
        while not self._sat(dec):
            core = set(self.s.get_core() or ())
            pos = {x: k for k, x in enumerate(dec)}
            drop = max((pos[x] for x in core if x in pos and pos[x] >= 1), default=None)
            if drop is None:
                raise RuntimeError("an open literal became unsatisfiable")
            del dec[drop]
        product = self.model[:n]
        for i in iter_bits(from_model(product, n) & p.repmask):
            unc[i] = 0
        return product
