"""3-wise covering: the pairwise engine's greedy one level up.

``tri[a][b]`` (``a < b``, literal bits of two representative variables) is the bitset of the
literals ``c`` such that the triple ``{a, b, c}`` is neither covered nor known invalid; each
triple is in the bitsets of its three pairs.  ``act[a]`` is the bitset of the ``b`` whose
``tri`` is not empty (either order), so that the work of a configuration shrinks with what is
left to cover.

A configuration starts from an uncovered triple the solver accepts (one that it refuses is
learnt invalid, and when the core is a pair, the whole pair is), then each variable takes the
literal that completes more uncovered triples with two literals the configuration already has;
unit propagation rules out most conflicts and one SAT call (more when the core says a decision
must go) checks the result, as for pairs.
"""

from __future__ import annotations

from itertools import compress
from typing import Optional

from .bits import from_model, iter_bits, lit, shuffled
from .pairwise import CoverState, PairCover, initial_pairs
from .prepare import Prepared


def triple_memory(p: Prepared) -> int:
    """Bytes the bookkeeping of :func:`initial_triples` takes, about."""
    k = 2 * len(p.reps)
    return (k * k // 2) * (k // 8 + 48) + k * 16 * p.n


class TripleState(CoverState):
    def __init__(self, tri: list[list[int]], act: list[int], total: int):
        super().__init__(unc=act, total=total)
        self.tri = tri
        self.act_ = act  # (the same list as unc: literal -> partners with uncovered triples)

    def left(self) -> int:
        # each triple is in the bitsets of its three pairs
        return sum(sum(map(int.bit_count, row)) for row in self.tri) // 3


def initial_triples(p: Prepared) -> TripleState:
    pairs = initial_pairs(p)  # unc[a]: partners of a valid (as far as propagation knows)
    nb_ok = pairs.unc
    size = 2 * p.n
    tri = [[0] * size for _ in range(size)]
    act = [0] * size
    total = 0
    lits = [i for i in range(size) if nb_ok[i]]
    for a in lits:
        ua = nb_ok[a]
        row = tri[a]
        above = ua & ~((1 << (a | 1) + 1) - 1)
        for b in iter_bits(above):
            c = ua & nb_ok[b]
            if c:
                row[b] = c
                act[a] |= 1 << b
                act[b] |= 1 << a
                total += c.bit_count()
    return TripleState(tri, act, total // 3)


class TripleCover(PairCover):
    st: TripleState

    def _get(self, a: int, b: int) -> int:
        return self.st.tri[a][b] if a < b else self.st.tri[b][a]

    def _clear_pair(self, a: int, b: int) -> None:
        """The pair (a, b) is in no product: no triple with it is."""
        tri, act = self.st.tri, self.st.act_
        x, y = (a, b) if a < b else (b, a)
        bits = tri[x][y]
        for c in iter_bits(bits):
            self._drop(a, c, b)
            self._drop(b, c, a)
        tri[x][y] = 0
        act[a] &= ~(1 << b)
        act[b] &= ~(1 << a)
        self.st.invalid += bits.bit_count()

    def _drop(self, a: int, b: int, c: int) -> None:
        tri = self.st.tri
        x, y = (a, b) if a < b else (b, a)
        v = tri[x][y] & ~(1 << c)
        tri[x][y] = v
        if not v:
            act = self.st.act_
            act[a] &= ~(1 << b)
            act[b] &= ~(1 << a)

    def _learn(self, a: int, b: int, c: int) -> None:
        core = set(self.s.get_core() or ())
        for x, y, z in ((a, b, c), (a, c, b), (b, c, a)):
            if core <= {lit(x), lit(y)}:
                self._clear_pair(x, y)
                return
        if (self._get(a, b) >> c) & 1:
            self.st.invalid += 1
        self._drop(a, b, c)
        self._drop(a, c, b)
        self._drop(b, c, a)

    def _seed3(self) -> Optional[tuple[int, int, int]]:
        act = self.st.act_
        order = shuffled(list(compress(range(len(act)), act)), self.rng)
        if not order:
            return None
        for a in order:
            while act[a]:
                # the partner with the most uncovered triples with a
                best, bc = -1, -1
                for b in iter_bits(act[a]):
                    c = self._get(a, b).bit_count()
                    if c > bc:
                        best, bc = b, c
                b = best
                bits = self._get(a, b)
                c = (bits & -bits).bit_length() - 1
                if self._sat([lit(a), lit(b), lit(c)]):
                    return a, b, c
                self._learn(a, b, c)
        return None

    def next_configuration(self) -> Optional[list[int]]:
        p, imp, nimp = self.p, self.p.imp, self.p.nimp
        tri, act = self.st.tri, self.st.act_
        n = self.n
        seed = self._seed3()
        if seed is None:
            return None
        dec = [lit(x) for x in seed]
        L = NL = 0
        for x in seed:
            L |= imp[x] | (1 << x)
            NL |= nimp[x]
        bad = 0
        rnd = self.rng.random
        size = len(act)
        avars = shuffled(sorted({a >> 1 for a in compress(range(size), act)}), self.rng)
        skipped = avars
        for rounds in range(3):
            todo, skipped = skipped, []
            for v in todo:
                i = 2 * v
                if (L >> i) & 3:
                    continue
                g = [0, 0]
                xs = (act[i] & L, act[i + 1] & L)
                for s_ in (0, 1):
                    c = i + s_
                    row = tri[c]
                    tot = 0
                    for x in iter_bits(xs[s_]):
                        tot += ((row[x] if c < x else tri[x][c]) & L).bit_count()
                    g[s_] = tot
                gp, gn = g
                if not gp and not gn:
                    skipped.append(v)
                    continue
                first = i if gp > gn or (gp == gn and rnd() < 0.5) else i + 1
                for c in (first, first ^ 1):
                    if c != first and not g[c - i]:
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
            # the tail: an uncovered triple of undecided literals that fits
            added = False
            order = shuffled(list(compress(range(len(act)), act)), self.rng)
            for a in order:
                ab = 1 << a
                if (NL | bad) & ab or imp[a] & NL:
                    continue
                for b in iter_bits(act[a] & ~(NL | bad)):
                    if imp[b] & (NL | nimp[a]):
                        continue
                    nl2 = NL | nimp[a] | nimp[b]
                    cands = self._get(a, b) & ~(nl2 | bad)
                    for c in iter_bits(cands):
                        if imp[c] & nl2:
                            continue
                        for x in (a, b, c):
                            if not (L >> x) & 1:
                                dec.append(lit(x))
                                L |= imp[x] | (1 << x)
                                NL |= nimp[x]
                        added = True
                        break
                    if added:
                        break
                if added:
                    break
            if not added:
                break
        pref = []
        for v in p.reps:
            if not (L >> (2 * v - 2)) & 3:
                pref.append(v if rnd() < 0.5 else -v)
        self.s.set_phases(pref)
        while not self._sat(dec):
            core = set(self.s.get_core() or ())
            pos = {x: k for k, x in enumerate(dec)}
            drop = max((pos[x] for x in core if x in pos and pos[x] >= 3), default=None)
            if drop is None:
                raise RuntimeError("the seed triple of a configuration became unsatisfiable")
            del dec[drop]
        product = self.model[:n]
        wb = from_model(product, n) & p.repmask
        for a in iter_bits(wb):
            row = tri[a]
            for b in iter_bits(act[a] & wb & ~((1 << (a + 1)) - 1)):
                v = row[b] & ~wb
                row[b] = v
                if not v:
                    act[a] &= ~(1 << b)
                    act[b] &= ~(1 << a)
        self.check()
        return product

