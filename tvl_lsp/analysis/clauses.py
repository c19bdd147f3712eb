"""The clause-level pieces of the encodings, free of any model object (so that counting a plain
UVL model, :mod:`.plaincnf`, loads no model classes): :class:`_Builder` (Tseitin gates with
constant folding and structural caching; cardinality by defined sequential counters),
:func:`_clean`, and the distribution helpers :func:`_absorb`, :func:`_minimal`,
:func:`_tautology` that :mod:`.distribute` and :mod:`.plaincnf` share."""

from __future__ import annotations

from typing import Iterable, Optional, Union

Lit = Union[int, bool]  # a literal, or a folded constant
# a disjunct of a distributed disjunction may have this many clauses (the result stays within
# the caller's limit): absorption can make a long disjunct short
PRODUCT_ITEM_MAX = 256
# at-most-one constraints over up to this many literals are pairwise clauses (no counter)
PAIRWISE_MAX = 128


class _Builder:
    """Literal-level Tseitin builder with constant folding and structural caching."""

    def __init__(self, top: int, hard: list[list[int]]):
        self.top = top
        self.hard = hard
        self._and_cache: dict[frozenset, int] = {}

    def new_var(self) -> int:
        self.top += 1
        return self.top

    @staticmethod
    def not_(x: Lit) -> Lit:
        if x is True:
            return False
        if x is False:
            return True
        return -x

    def and_(self, xs: Iterable[Lit]) -> Lit:
        out: set[int] = set()
        for x in xs:
            if x is True:
                continue
            if x is False:
                return False
            if -x in out:
                return False
            out.add(x)
        if not out:
            return True
        if len(out) == 1:
            return next(iter(out))
        key = frozenset(out)
        a = self._and_cache.get(key)
        if a is None:
            a = self.new_var()
            for x in out:
                self.hard.append([-a, x])
            self.hard.append([a] + [-x for x in out])
            self._and_cache[key] = a
        return a

    def or_(self, xs: Iterable[Lit]) -> Lit:
        return self.not_(self.and_(self.not_(x) for x in xs))

    def iff(self, a: Lit, b: Lit) -> Lit:
        return self.and_([self.or_([self.not_(a), b]), self.or_([a, self.not_(b)])])

    def ite(self, c: Lit, a: Lit, b: Lit) -> Lit:
        return self.or_([self.and_([c, a]), self.and_([self.not_(c), b])])

    def exactly_one(self, lits: list[int]) -> None:
        if len(lits) == 1:
            self.hard.append([lits[0]])
            return
        self.hard.append(list(lits))
        self.hard.extend(self.at_most(lits, 1))

    def at_most(self, lits: list[int], k: int) -> list[list[int]]:
        """Clauses for sum(lits) <= k.  The auxiliary variables are *defined* (hard Tseitin
        clauses, see :meth:`_counter`), so they are functions of ``lits``: a count of all
        variables equals the count projected on ``lits`` (what d4 counts)."""
        n = len(lits)
        if k >= n:
            return []
        if k <= 0:
            return [[-x] for x in lits]
        if k == 1 and n <= PAIRWISE_MAX:
            # pairwise: more clauses than a counter but no variable; d4's decomposition (its
            # time grows with the variables) and the solvers' propagation both prefer it, and
            # the DIMACS exports of feature models are written so
            return [[-lits[i], -lits[j]] for i in range(n) for j in range(i + 1, n)]
        out: list[list[int]] = []
        # sequential counter: x_i may not be selected once k of x_1..x_{i-1} are
        for i, r in enumerate(self._counter(lits[:-1], k)):
            c = _clean([-lits[i + 1], self.not_(r[k])])
            if c is not None:
                out.append(c)
        return out

    def at_least(self, lits: list[int], k: int) -> list[list[int]]:
        n = len(lits)
        if k <= 0:
            return []
        if k > n:
            return [[]]
        if k == 1:
            return [list(lits)]
        if k == n:
            return [[x] for x in lits]
        last = None
        for last in self._counter(lits, k):
            pass
        c = _clean([last[k]])
        return [] if c is None else [c]

    def _counter(self, lits: list[int], k: int):
        """For each prefix x_1..x_i of ``lits`` (i = 1..n), the list r with r[j] the literal
        (or constant) "at least j of x_1..x_i are true", j = 0..k, each defined by
        r_i[j] <-> r_{i-1}[j] || (x_i && r_{i-1}[j-1]) (a sequential counter whose counter
        variables are functions of the inputs)."""
        prev: list[Lit] = [True] + [False] * k
        for x in lits:
            cur: list[Lit] = [True]
            for j in range(1, k + 1):
                cur.append(self.or_([prev[j], self.and_([x, prev[j - 1]])]))
            prev = cur
            yield cur


def _clean(clause: Iterable[Lit]) -> Optional[list[int]]:
    """Drop false literals; None when the clause holds (a true literal or x, -x)."""
    out: list[int] = []
    seen: set[int] = set()
    for x in clause:
        if x is True:
            return None
        if x is False:
            continue
        if -x in seen:
            return None
        if x not in seen:
            seen.add(x)
            out.append(x)
    return out


def distribute(base: list[Lit], multi: list[list[list[Lit]]], limit: int, inner: int,
               absorb: bool = True) -> Optional[list[list[Lit]]]:
    """The CNF of the disjunction of the literals ``base`` (mutated) and the CNFs ``multi``,
    distributed clause by clause with the tautologies dropped as they appear (a KConfig export's
    "A & B1 | A & B2 | !A | !B3" is one clause, !A | B1 | B2 | !B3, not 2^k); None when a step
    takes more than ``inner`` clauses or leaves more than ``limit``.  ``absorb=False``: every
    CNF in ``multi`` is a conjunction of literals, which :func:`_absorb` keeps as it is."""
    if multi and absorb:
        multi = _absorb(multi, base)
        if multi is None:
            return []
    if _tautology(base):
        return []
    acc = [base]
    i = 0
    if multi:
        # while one disjunct at a time survives beside the clause so far (a KConfig choice,
        # "R & A1 | R & A2 | !R | !A3": R dies on !R), the clause grows by it: what the loop
        # below does then, without its sets made again for every disjunct
        a = list(base)
        sa = {x for x in a if type(x) is int}
        for c in multi:
            survivor = None
            alive = 0
            for b in c:
                if len(b) == 1:
                    x = b[0]
                    if type(x) is int and -x in sa:
                        continue
                elif any(type(x) is int and -x in sa for x in b):
                    continue
                alive += 1
                if alive > 1:
                    break
                survivor = b
            if alive != 1:
                break
            if limit < 1:
                return None
            a.extend([x for x in survivor if x not in sa])
            for x in survivor:
                if type(x) is int:
                    sa.add(x)
            i += 1
        acc = [a]
    for c in multi[i:]:
        nxt = []
        for a in acc:
            sa = {x for x in a if type(x) is int}
            for b in c:
                if any(type(x) is int and -x in sa for x in b):
                    continue
                nxt.append(a + [x for x in b if x not in sa])
                if len(nxt) > inner:
                    return None
        acc = _minimal(nxt)
        if len(acc) > limit:
            return None
        if not acc:
            return []
    return acc


def _absorb(multi: list[list[list[Lit]]], base: list[Lit]) -> Optional[list[list[list[Lit]]]]:
    """The disjuncts (each a CNF) of a disjunction with the clauses absorbed by another
    disjunct dropped: ``(A & K) | D | ...`` is ``A | D | ...`` when ``!K`` is ``D`` (``K`` a
    clause, ``D`` a conjunction of literals or one literal of ``base``).  Applied one disjunct
    after the other, each against the disjunction as it stands, so every step keeps it
    equivalent.  A KConfig export's "the first of A1..An selected" (``R & A1 | !(R & A1) & R
    & A2 | ...``: 228 KB in embtoolkit.uvl, 202 Tseitin variables) becomes ``R & A1 | R & A2 |
    ...``.  Single-clause disjuncts move to ``base``; None: a disjunct became true."""
    from collections import Counter

    def pure(c) -> Optional[frozenset]:
        if all(len(k) == 1 and type(k[0]) is int for k in c):
            return frozenset(k[0] for k in c)
        return None

    pures = [pure(c) for c in multi]
    keys = Counter(frozenset([x]) for x in base if type(x) is int)
    for k in pures:
        if k is not None:
            keys[k] += 1
    out = []
    for c, own in zip(multi, pures):
        if own is not None:
            out.append(c)
            continue
        kept = []
        for k in c:
            if len(k) > 1 and all(type(x) is int for x in k) and keys.get(frozenset(-x for x in k)):
                continue
            if len(k) == 1 and type(k[0]) is int and keys.get(frozenset([-k[0]])):
                continue
            kept.append(k)
        if not kept:
            return None
        if len(kept) == 1:
            base.extend(kept[0])
            for x in kept[0]:
                if type(x) is int:
                    keys[frozenset([x])] += 1
            continue
        k = pure(kept)
        if k is not None:
            keys[k] += 1
        out.append(kept)
    return out


def _minimal(clauses: list[list[Lit]]) -> list[list[Lit]]:
    """The clauses without those another one subsumes (and without repeats)."""
    if len(clauses) < 2:
        return clauses
    order = sorted(range(len(clauses)), key=lambda i: len(clauses[i]))
    kept: set[int] = set()
    sets: list[set] = []
    for i in order:
        sc = set(clauses[i])
        if any(s <= sc for s in sets):
            continue
        kept.add(i)
        sets.append(sc)
    return [c for i, c in enumerate(clauses) if i in kept]  # (in their order)


def _tautology(clause: list[Lit]) -> bool:
    ints = {x for x in clause if type(x) is int}
    return any(-x in ints for x in ints)
