"""A CNF made smaller before d4 compiles it, every count staying exact (issue #30).

d4 spends most of its time on a feature model's CNF *before* its search: reading the clauses
and computing a tree decomposition of their primal graph (flow-cutter), which grows with the
clauses and the variables.  A feature model's CNF says most things many times over (every
child implies its parent, and the exporters add the implied ancestors; mandatory children are
equivalent to their parents; core features are true in every product), so the formula handed
to d4 is first reduced by transformations that keep its models in a known correspondence:

- **unit propagation** and **failed literals** of the binary clauses (a literal that implies
  its own negation through them is false): variables fixed in every model;
- **equivalent literals** (a cycle of binary implications, ``a -> b -> a``): one variable of
  each class stays, the others are substituted by it;
- **transitive reduction** of the binary implications (``a -> c`` is dropped when ``a -> b ->
  c``), **hidden tautologies** (a longer clause that the binary clauses already imply) and
  **hidden literals** (``a`` dropped from a clause that also holds ``b`` when ``a -> b``): the
  formula stays equivalent;
- the **backbone** (core and dead features, one SAT call per flipped candidate set, as
  :func:`tvl_lsp.analysis.backbone.backbone_of` does for the anomalies);
- **elimination of auxiliary variables** (the Tseitin and counter variables of the TVL / UVL
  encodings, numbered above the features) by clause distribution when it does not make the
  formula bigger: a variable *defined* by the others (every model of the rest extends to
  exactly one value of it, which the service's ``determined`` flag guarantees for the
  encoding's auxiliary variables) leaves the count unchanged when it is existentially
  quantified away, and resolution on it is that quantification;
- variables left in no clause are **free**: each doubles the count.

What stays is renumbered ``1..k``.  :class:`Reduction` keeps the way back: each original
variable is fixed, free, mapped to a literal of the reduced CNF, or an eliminated auxiliary
variable; :class:`LiftedCircuit` answers every query of the original variables (the total,
counts under decisions, every feature's count, uniform samples) from the reduced circuit.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from typing import Iterable, Optional, Sequence

from .circuit import PassResult

# bounds that keep the preprocessing a small part of a compilation
MAX_ROUNDS = 12            # rounds of propagation / equivalences / reduction
MIN_GAIN = 0.005           # a round after the first must remove this share of the clauses (or more)
REACH_MAX_BITS = 1 << 28   # reachability bitsets (parts of the implication graph, size^2) up to 32 MB
BACKBONE_SECONDS = 0.25    # the backbone is given up (nothing proved) after this long
HIDDEN_MAX_LEN = 64        # longer clauses are not searched for hidden tautologies / literals
BVE_MAX_PAIRS = 4096       # an auxiliary variable with more (positive x negative) clause pairs is kept
BVE_MAX_RESOLVENT = 24     # nor eliminated when a resolvent would be longer than this
FORMAT = 1                 # of the stored reduction (Reduction.to_json)


class _Unsat(Exception):
    pass


@dataclass
class Reduction:
    """How a CNF over ``1..nvars`` maps to its reduced form over ``1..k``.

    ``fixed``: variables with one value in every model; ``lit_of``: original variable ->
    literal of the reduced CNF (the variables that stay, and those equivalent to one that
    stays, possibly negated); ``free``: counted variables in no clause (each doubles the
    count); every other variable is an eliminated auxiliary variable (determined by the rest:
    no factor).  ``void``: the CNF has no model."""
    nvars: int
    k: int = 0
    clauses: list[list[int]] = field(default_factory=list)
    fixed: dict[int, bool] = field(default_factory=dict)
    lit_of: dict[int, int] = field(default_factory=dict)
    free: list[int] = field(default_factory=list)
    void: bool = False
    seconds: float = 0.0
    stats: dict = field(default_factory=dict)

    @property
    def scale_bits(self) -> int:
        return len(self.free)

    def to_json(self) -> bytes:
        fixed = [v if val else -v for v, val in sorted(self.fixed.items())]
        lit_of = [x for v, y in sorted(self.lit_of.items()) for x in (v, y)]
        return json.dumps({"format": FORMAT, "nvars": self.nvars, "k": self.k, "void": self.void,
                           "fixed": fixed, "lit_of": lit_of, "free": self.free},
                          separators=(",", ":")).encode()

    @classmethod
    def from_json(cls, data: bytes, nvars: int) -> Optional["Reduction"]:
        """The stored reduction, or None when it is not one of this CNF's (damaged, another
        format, another size)."""
        try:
            d = json.loads(data)
            if d.get("format") != FORMAT or d.get("nvars") != nvars:
                return None
            k = int(d["k"])
            fixed = {abs(int(x)): int(x) > 0 for x in d["fixed"]}
            pairs = [int(x) for x in d["lit_of"]]
            lit_of = dict(zip(pairs[0::2], pairs[1::2]))
            free = [int(v) for v in d["free"]]
            seen = set(fixed)
            for v in list(lit_of) + free:
                if not 1 <= v <= nvars or v in seen:
                    return None
                seen.add(v)
            if any(not y or abs(y) > k for y in lit_of.values()):
                return None
            return cls(nvars=nvars, k=k, fixed=fixed, lit_of=lit_of, free=free, void=bool(d["void"]))
        except (ValueError, TypeError, KeyError, AttributeError):
            return None

    # ------------------------------------------------------------------ queries
    def map_lits(self, lits: Sequence[int]) -> Optional[tuple[list[int], dict[int, bool]]]:
        """Literals over the original variables -> (literals of the reduced CNF, decided free
        variables), or None when they contradict the fixed variables or each other."""
        out: dict[int, int] = {}
        decided: dict[int, bool] = {}
        for x in lits:
            v = abs(x)
            f = self.fixed.get(v)
            if f is not None:
                if f != (x > 0):
                    return None
                continue
            y = self.lit_of.get(v)
            if y is None:  # a free variable (or an eliminated auxiliary one: never asked)
                if decided.get(v, x > 0) != (x > 0):
                    return None
                decided[v] = x > 0
                continue
            if x < 0:
                y = -y
            if out.get(abs(y), y) != y:
                return None
            out[abs(y)] = y
        return list(out.values()), decided


class LiftedCircuit:
    """A circuit of the reduced CNF, answering for the original variables (the interface of
    :class:`~tvl_lsp.analysis.counting.circuit.Circuit` that the service uses: ``count``,
    ``counts``, ``sample``)."""

    def __init__(self, inner, reduction: Reduction, universe: Iterable[int]):
        self.inner = inner
        self.red = reduction
        self.nvars = reduction.nvars
        self.free = [v for v in reduction.free]
        # variables counted that the reduction leaves free: in the universe only
        u = set(universe)
        self.free = [v for v in self.free if v in u]

    def count(self, assumptions: Sequence[int] = ()) -> int:
        m = self.red.map_lits(assumptions)
        if m is None or self.red.void:
            return 0
        lits, decided = m
        n = self.inner.count(lits) if self.inner is not None else 1
        return n << (len(self.free) - len(decided))

    def counts(self, assumptions: Sequence[int] = ()) -> PassResult:
        n = self.nvars
        m = self.red.map_lits(assumptions)
        if m is None or self.red.void:
            return PassResult(0, [0] * (n + 1))
        lits, decided = m
        if self.inner is not None:
            r = self.inner.counts(lits)
            itotal, ipos = r.total, r.positive
        else:
            itotal, ipos = 1, [0]
        shift = len(self.free) - len(decided)
        total = itotal << shift
        pos = [0] * (n + 1)
        if not total:
            return PassResult(0, pos)
        for v, val in self.red.fixed.items():
            if v <= n and val:
                pos[v] = total
        for v, y in self.red.lit_of.items():
            p = ipos[y] if y > 0 else itotal - ipos[-y]
            pos[v] = p << shift
        half = total >> 1
        for v in self.free:
            d = decided.get(v)
            pos[v] = half if d is None else (total if d else 0)
        return PassResult(total, pos)

    def sample(self, rng, assumptions: Sequence[int] = ()) -> Optional[list[int]]:
        m = self.red.map_lits(assumptions)
        if m is None or self.red.void:
            return None
        lits, decided = m
        inner = self.inner.sample(rng, lits) if self.inner is not None else []
        if inner is None:
            return None
        val = {abs(x): x > 0 for x in inner}
        out: dict[int, bool] = {}
        for v, b in self.red.fixed.items():
            out[v] = b
        for v, y in self.red.lit_of.items():
            out[v] = val[abs(y)] == (y > 0)
        for v in self.free:
            d = decided.get(v)
            out[v] = (rng.random() < 0.5) if d is None else d
        return [v if out[v] else -v for v in sorted(out)]


# ---------------------------------------------------------------------- the reduction
def reduce_cnf(nvars: int, clauses: Sequence[Sequence[int]], n_features: int, universe: Iterable[int],
               eliminate_aux: bool = False, backbone: bool = True,
               deadline: Optional[float] = None) -> Reduction:
    """The reduced form of the CNF.  ``universe``: the variables counted (the others -- unused
    auxiliary variables -- are neither free nor kept).  ``eliminate_aux``: the variables above
    ``n_features`` are determined by the features (the count over all variables is the count
    of products), so they may be eliminated.  ``deadline`` (``time.monotonic()``): the
    optional steps (backbone, elimination) are skipped once it has passed."""
    t0 = time.monotonic()
    st = _State(nvars, n_features)
    try:
        cls = st.normalise(clauses)
        cls = st.propagate(cls, [])
        if eliminate_aux and nvars > n_features:
            cls = st.propagate(st.eliminate(cls), [])
        cls = st.rounds(cls)
        if backbone and cls and not _late(deadline):
            box = time.monotonic() + BACKBONE_SECONDS
            bb = _sat_backbone(cls, box if deadline is None else min(box, deadline))
            if bb is None:
                raise _Unsat()
            if bb:
                st.stats["backbone"] = len(bb)
                cls = st.rounds(cls, [v if val else -v for v, val in bb.items()])
        if eliminate_aux and nvars > n_features and cls and not _late(deadline):
            cls2 = st.eliminate(cls)
            if cls2 is not cls:
                cls = st.rounds(cls2)
    except _Unsat:
        red = Reduction(nvars=nvars, void=True, seconds=time.monotonic() - t0, stats=st.stats)
        return red
    return st.finish(cls, universe, time.monotonic() - t0)


def _late(deadline: Optional[float]) -> bool:
    return deadline is not None and time.monotonic() > deadline


def _sat_backbone(cls: list[list[int]], deadline: Optional[float]) -> Optional[dict[int, bool]]:
    """The literals true in every model of ``cls`` (None: no model; {} when the deadline
    passed first)."""
    from ..backbone import backbone_of, new_solver
    s = new_solver(cls)
    try:
        if not s.solve():
            return None
        m = s.get_model()
        used = {abs(x) for c in cls for x in c}
        cand = {abs(x): x > 0 for x in m if abs(x) in used}
        bb = backbone_of(s, cand, [], deadline=deadline, n_features=len(m))
        return bb or {}
    finally:
        s.delete()


class _State:
    def __init__(self, nvars: int, n_features: int):
        self.nvars = nvars
        self.n_features = n_features
        self.fixed: dict[int, bool] = {}
        self.rep: dict[int, int] = {}       # var -> literal it equals (chains resolved in finish)
        self.eliminated: set[int] = set()
        self.stats: dict = {"rounds": 0, "equivalent": 0, "failed": 0, "transitive": 0, "hidden_taut": 0,
                            "hidden_lit": 0, "eliminated": 0}

    # ------------------------------------------------------------------ basic steps
    def normalise(self, clauses: Sequence[Sequence[int]]) -> list[list[int]]:
        """The clauses without tautologies and repeated literals (the clauses given are not
        changed: those already so are kept as they are)."""
        out = []
        for c in clauses:
            if len(c) == 2:  # most clauses of a feature model
                a, b = c
                if a != b and a != -b:
                    out.append(c)
                elif a == b:
                    out.append([a])
                continue
            if not c:
                raise _Unsat()
            s = set(c)
            if len(s) == len(c):
                if s.isdisjoint([-x for x in c]):
                    out.append(c if type(c) is list else list(c))
                continue  # (a tautology)
            if any(-x in s for x in s):
                continue
            out.append(list(dict.fromkeys(c)))
        return out

    def propagate(self, cls: list[list[int]], units: list[int]) -> list[list[int]]:
        """Unit propagation: ``units`` and the unit clauses, to a fixed point; the clauses left
        mention no fixed variable.  One pass over the clauses per level of propagation, each
        clause looked at by two set operations in C (a feature model's CNF: a few passes)."""
        queue = list(units)
        queue += [c[0] for c in cls if len(c) == 1]
        fixed = self.fixed
        while queue:
            true: set[int] = set()
            for x in queue:
                f = fixed.get(abs(x))
                if f is not None:
                    if f != (x > 0):
                        raise _Unsat()
                    continue
                fixed[abs(x)] = x > 0
                true.add(x)
            queue = []
            if not true:
                break
            false = {-x for x in true}
            sat, cut = true.isdisjoint, false.isdisjoint
            out = []
            for c in cls:
                if not sat(c):
                    continue
                if not cut(c):
                    c = [y for y in c if y not in false]
                    if len(c) < 2:
                        if not c:
                            raise _Unsat()
                        queue.append(c[0])
                        continue
                out.append(c)
            cls = out
        return cls

    def substitute(self, cls: list[list[int]], sub: dict[int, int]) -> list[list[int]]:
        """Every variable of ``sub`` replaced by its literal; tautologies dropped."""
        out = []
        untouched = sub.keys().isdisjoint  # (in C: most clauses hold no substituted literal)
        get = sub.get
        for c in cls:
            if untouched(c):
                out.append(c)
                continue
            nc = [get(x, x) for x in c]
            s = set(nc)
            if any(-y in s for y in s):
                continue
            if len(s) != len(nc):
                nc = list(dict.fromkeys(nc))
            out.append(nc)
        return out

    # ------------------------------------------------------------------ binary implications
    def rounds(self, cls: list[list[int]], units: Sequence[int] = ()) -> list[list[int]]:
        """Propagation and looks at the binary implications, to a fixed point or until a round
        gains less than MIN_GAIN of the clauses (each round is a few passes over them: on a
        big CNF, rounds that change a handful of clauses cost more than d4 gains)."""
        units = list(units)
        for i in range(MAX_ROUNDS):
            self.stats["rounds"] += 1
            cls = self.propagate(cls, units)
            before = len(cls) - len(self.rep) - self.stats["hidden_lit"]
            cls, changed, units = self._binary_round(cls)
            if not changed and not units:
                break
            gain = before - (len(cls) - len(self.rep) - self.stats["hidden_lit"]) + len(units)
            if i and gain < MIN_GAIN * len(cls):
                break
        return self.propagate(cls, units)

    def _binary_round(self, cls: list[list[int]]) -> tuple[list[list[int]], bool, list[int]]:
        """One look at the binary implication graph: equivalences (substituted: changed),
        else failed literals (returned as units), else transitive reduction and hidden
        tautologies / literals of the longer clauses."""
        succ: dict[int, list[int]] = {}
        for c in cls:
            if len(c) == 2:
                a, b = c
                if a < 0 and b < 0:
                    # an exclusion (x -> !y): on no cycle unless a clause (u | w) leads back
                    # from a negative literal to a positive one, rare in feature models and
                    # left out (fewer equivalences found, none wrong); they are most of the
                    # binary clauses of a model with big alternative groups
                    continue
                lst = succ.get(-a)
                if lst is None:
                    succ[-a] = [b]
                else:
                    lst.append(b)
                lst = succ.get(-b)
                if lst is None:
                    succ[-b] = [a]
                else:
                    lst.append(a)
        if not succ:
            return cls, False, []
        order, comp_of = _tarjan(succ)
        # equivalences: an SCC of more than one literal
        sub: dict[int, int] = {}
        for scc in comp_of:
            if len(scc) > 1:
                r = min(scc, key=abs)
                for x in scc:
                    if x == -r:
                        raise _Unsat()
                for x in scc:
                    if x != r:
                        sub[x] = r
                        sub[-x] = -r
        if sub:
            for x, y in sub.items():
                if x > 0:
                    self.rep[x] = y
            self.stats["equivalent"] += sum(1 for x in sub if x > 0)
            return self.substitute(cls, sub), True, []
        # a DAG: reachability as bitsets over each weakly connected part, sinks first
        comp, index = _parts(order, succ)
        sizes: dict[int, int] = {}
        for r in comp.values():
            sizes[r] = sizes.get(r, 0) + 1
        if sum(k * k for k in sizes.values()) > REACH_MAX_BITS:
            self.stats["reach_skipped"] = 1
            return cls, False, []  # the bitsets would take too much memory: equivalences only
        reach: dict[int, int] = {}
        for u in order:
            r = 0
            for w in succ.get(u, ()):
                r |= reach[w] | (1 << index[w])
            reach[u] = r
        units = []
        for u in order:
            nu = -u
            if comp.get(nu) == comp[u] and (reach[u] >> index[nu]) & 1:
                units.append(nu)  # u implies its negation: u is false
        if units:
            self.stats["failed"] += len(units)
            return cls, False, units
        # transitive reduction (a clause is its two contrapositive edges: one is enough)
        redundant: set[tuple[int, int]] = set()
        for u, ws in succ.items():
            if len(ws) < 2:
                continue
            acc = 0
            for w in ws:
                acc |= reach[w]
            if not acc:
                continue
            for w in ws:
                if (acc >> index[w]) & 1:
                    a, b = -u, w
                    redundant.add((a, b) if a < b else (b, a))
        out = []
        changed = False
        ntaut = nlit = 0
        for c in cls:
            n = len(c)
            if n == 2:
                a, b = c
                if redundant and ((a, b) if a < b else (b, a)) in redundant:
                    changed = True
                    continue
                out.append(c)
                continue
            if n > HIDDEN_MAX_LEN:
                out.append(c)
                continue
            # hidden tautology: -a -> b for two literals a, b of the clause
            inds = [(x, comp.get(x), comp.get(-x)) for x in c]
            taut = False
            for a, _, cna in inds:
                if cna is None:
                    continue
                ra = reach[-a]
                if not ra:
                    continue
                for b, cb, _ in inds:
                    if b != a and cb == cna and (ra >> index[b]) & 1:
                        taut = True
                        break
                if taut:
                    break
            if taut:
                ntaut += 1
                changed = True
                continue
            # hidden literal: a -> b with both in the clause: a can go
            drop = set()
            for a, ca, _ in inds:
                if ca is None:
                    continue
                ra = reach[a]
                if not ra:
                    continue
                for b, cb, _ in inds:
                    if b != a and cb == ca and b not in drop and (ra >> index[b]) & 1:
                        drop.add(a)
                        break
            if drop:
                nlit += len(drop)
                changed = True
                c = [x for x in c if x not in drop]
            out.append(c)
        self.stats["transitive"] += len(redundant)
        self.stats["hidden_taut"] += ntaut
        self.stats["hidden_lit"] += nlit
        # (dropped clauses change no reachability; a shortened one may add an implication)
        return out, nlit > 0, []

    # ------------------------------------------------------------------ auxiliary variables
    def eliminate(self, cls: list[list[int]]) -> list[list[int]]:
        """Bounded variable elimination of the auxiliary variables (above ``n_features``):
        a variable goes when the non-tautological resolvents of its clauses are no more than
        its clauses.  Returns ``cls`` itself when nothing was eliminated."""
        nf = self.n_features
        occ: dict[int, list[int]] = {}
        for i, c in enumerate(cls):
            for x in c:
                if abs(x) > nf:
                    occ.setdefault(x, []).append(i)
        cand = sorted({abs(x) for x in occ}, key=lambda v: len(occ.get(v, ())) * len(occ.get(-v, ())))
        alive = [True] * len(cls)
        cur = list(cls)
        added: list[list[int]] = []
        n = 0
        for v in cand:
            pos = [i for i in occ.get(v, ()) if alive[i]]
            neg = [i for i in occ.get(-v, ()) if alive[i]]
            if len(pos) * len(neg) > BVE_MAX_PAIRS:
                continue
            res = []
            ok = True
            for i in pos:
                ci = [x for x in cur[i] if x != v]
                for j in neg:
                    s = set(ci)
                    taut = False
                    for x in cur[j]:
                        if x == -v:
                            continue
                        if -x in s:
                            taut = True
                            break
                        s.add(x)
                    if taut:
                        continue
                    if len(s) > BVE_MAX_RESOLVENT:
                        ok = False
                        break
                    res.append(sorted(s, key=abs))
                    if len(res) > len(pos) + len(neg):
                        ok = False
                        break
                if not ok:
                    break
            if not ok:
                continue
            for i in pos + neg:
                alive[i] = False
            for r in res:
                if not r:
                    raise _Unsat()
                idx = len(cur)
                cur.append(r)
                alive.append(True)
                for x in r:
                    if abs(x) > nf:
                        occ.setdefault(x, []).append(idx)
                added.append(r)
            self.eliminated.add(v)
            n += 1
        if not n:
            return cls
        self.stats["eliminated"] += n
        return [c for c, a in zip(cur, alive) if a]

    # ------------------------------------------------------------------ renumbering
    def finish(self, cls: list[list[int]], universe: Iterable[int], seconds: float) -> Reduction:
        rep, fixed = self.rep, self.fixed

        def resolve(v: int) -> tuple[int, int]:
            """(the variable at the end of v's equivalence chain, +1 / -1: v's sign to it)."""
            sign = 1
            for _ in range(len(rep) + 1):  # representatives are smaller: chains end
                y = rep.get(v)
                if y is None:
                    return v, sign
                if y < 0:
                    sign = -sign
                v = abs(y)
            raise RuntimeError("equivalence chain loops")

        used = {abs(x) for c in cls for x in c}
        ends: dict[int, tuple[int, int]] = {}
        for v in universe:
            r, sign = resolve(v)
            ends[v] = (r, sign)
            if r != v and r not in fixed and r not in self.eliminated:
                # v equals a variable that stays (kept in the reduced CNF even if it is in no
                # clause: the pair doubles the count once, not twice)
                used.add(r)
        kept = sorted(used)
        new = {v: i + 1 for i, v in enumerate(kept)}
        lit = {v: i for v, i in new.items()}
        lit.update({-v: -i for v, i in new.items()})
        get = lit.__getitem__
        out = [list(map(get, c)) for c in cls]
        lit_of: dict[int, int] = {}
        fixed_out: dict[int, bool] = {}
        free: list[int] = []
        for v, (r, sign) in ends.items():
            f = fixed.get(r)
            if f is not None:
                fixed_out[v] = f == (sign > 0)
            elif r in new:
                lit_of[v] = sign * new[r]
            elif r in self.eliminated:
                pass  # determined by the others: no factor
            else:
                free.append(v)
        return Reduction(nvars=self.nvars, k=len(kept), clauses=out, fixed=fixed_out, lit_of=lit_of,
                         free=sorted(free), seconds=seconds, stats=self.stats)


def _tarjan(succ: dict[int, list[int]]) -> tuple[list[int], list[list[int]]]:
    """Strongly connected components of the literal graph (iterative Tarjan): (the nodes in
    the order their components were completed -- sinks first --, the components)."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on: set[int] = set()
    stack: list[int] = []
    order: list[int] = []
    comps: list[list[int]] = []
    counter = 0
    nodes = set(succ)
    for ws in succ.values():
        nodes.update(ws)
    for root in nodes:
        if root in index:
            continue
        work = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on.add(root)
        while work:
            v, i = work[-1]
            ws = succ.get(v, ())
            if i < len(ws):
                work[-1] = (v, i + 1)
                w = ws[i]
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, 0))
                elif w in on:
                    if index[w] < low[v]:
                        low[v] = index[w]
                continue
            work.pop()
            if work:
                u = work[-1][0]
                if low[v] < low[u]:
                    low[u] = low[v]
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                comps.append(comp)
                order.extend(comp)
    return order, comps


def _parts(order: list[int], succ: dict[int, list[int]]) -> tuple[dict[int, int], dict[int, int]]:
    """Weakly connected parts of the (acyclic) graph: (node -> part, node -> its index in its
    part, increasing along ``order``), so that reachability bitsets stay as small as a part."""
    parent: dict[int, int] = {u: u for u in order}

    def find(x: int) -> int:
        root = x
        while parent[root] != root:
            root = parent[root]
        while parent[x] != root:
            parent[x], x = root, parent[x]
        return root

    for u, ws in succ.items():
        ru = find(u)
        for w in ws:
            rw = find(w)
            if rw != ru:
                parent[rw] = ru
    comp: dict[int, int] = {}
    index: dict[int, int] = {}
    counters: dict[int, int] = {}
    for u in order:
        r = find(u)
        comp[u] = r
        k = counters.get(r, 0)
        index[u] = k
        counters[r] = k + 1
    return comp, index
