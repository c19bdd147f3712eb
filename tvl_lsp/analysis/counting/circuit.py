"""A d-DNNF in d4's NNF format, and the counting passes the editor needs on it.

d4 writes a decision-DNNF as nodes (``o ID 0`` or-node, ``a ID 0`` and-node, ``t ID 0`` true,
``f ID 0`` false) and edges ``PARENT CHILD L1 .. Lk 0``: the child conjoined with the
literals ``L1 .. Lk``.  And-nodes are decomposable (their children share no variable),
or-nodes deterministic (their children have no model in common); the circuit is *not* smooth:
a variable an or-branch does not mention is free on that branch.

Counting over a universe of variables ``U`` (the features, plus the auxiliary variables that
occur in the CNF) under assumptions ``A``:

- upward: ``mc(e) = mc(child)`` if the edge's literals agree with ``A`` (else 0); an and-node
  multiplies its edges, an or-node adds them, each scaled by ``2^k`` for the ``k`` unassigned
  variables of the node that the edge does not mention (smoothing without building it);
- downward (one pass, Darwiche's differential approach): ``D(node)`` is how much one model of
  the node is worth at the root; an edge's literal ``x`` is fixed on all ``D(edge) * mc(edge)``
  models through the edge, so ``delta(x) = #(F & A & x) - #(F & A & !x)`` accumulates over
  the edges, and ``#(F & A & x) = (#(F & A) + delta(x)) / 2`` for every unassigned ``x`` (a
  variable left free somewhere contributes equally to both sides).

So the count of every variable costs one upward and one downward pass: linear in the
circuit, exact (Python integers).  Variable sets are Python ints used as bitsets.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Optional, Sequence


class NNFError(ValueError):
    pass


@dataclass
class PassResult:
    total: int
    # positive[v] = number of models (within the assumptions) with v true, for v in 1..nvars
    positive: list[int]


class Circuit:
    """A parsed d-DNNF.  ``universe``: the variables counted (a variable of ``1..nvars`` not in
    it is neither counted nor constrained; by default every variable)."""

    def __init__(self, text: str, nvars: int, universe: Optional[Iterable[int]] = None):
        self.nvars = nvars
        self._parse(text)
        if universe is None:
            self.universe = (1 << (nvars + 1)) - 2  # bits 1..nvars
        else:
            u = 0
            for v in universe:
                u |= 1 << v
            self.universe = u
        self._prepare()

    # ------------------------------------------------------------------ parsing
    def _parse(self, text: str) -> None:
        kinds: dict[int, str] = {}
        edges: dict[int, list[tuple[int, tuple[int, ...]]]] = {}
        for line in text.splitlines():
            if not line:
                continue
            c = line[0]
            if c in "oatf":
                parts = line.split()
                kinds[int(parts[1])] = c
                continue
            if c == "c":
                continue
            nums = line.split()
            if len(nums) < 3 or nums[-1] != "0":
                raise NNFError(f"bad NNF line {line[:60]!r}")
            p, ch = int(nums[0]), int(nums[1])
            lits = tuple(int(x) for x in nums[2:-1])
            edges.setdefault(p, []).append((ch, lits))
        if not kinds:
            raise NNFError("empty NNF")
        for p, es in edges.items():
            if p not in kinds:
                raise NNFError(f"edge from undeclared node {p}")
            for ch, lits in es:
                if ch not in kinds:
                    raise NNFError(f"edge to undeclared node {ch}")
                for x in lits:
                    if x == 0 or abs(x) > self.nvars:
                        raise NNFError(f"literal {x} out of range 1..{self.nvars}")
        # root: the node that is no one's child (d4: node 1)
        children = {ch for es in edges.values() for ch, _ in es}
        roots = [n for n in kinds if n not in children]
        if len(roots) != 1:
            raise NNFError(f"{len(roots)} roots")
        self.root = roots[0]
        # topological order, children first (iterative DFS)
        order: list[int] = []
        state: dict[int, int] = {}
        stack = [(self.root, 0)]
        while stack:
            n, i = stack.pop()
            if i == 0:
                if state.get(n) == 2:
                    continue
                state[n] = 1
            es = edges.get(n, ())
            if i < len(es):
                stack.append((n, i + 1))
                ch = es[i][0]
                st = state.get(ch)
                if st is None:
                    stack.append((ch, 0))
                elif st == 1:
                    raise NNFError("the NNF has a cycle")
            else:
                state[n] = 2
                order.append(n)
        index = {n: i for i, n in enumerate(order)}
        self.kind = [kinds[n] for n in order]
        # per node: list of (child index, positive-literal mask, negative-literal mask, lits)
        self.edges: list[list[tuple[int, int, int, tuple[int, ...]]]] = []
        for n in order:
            out = []
            for ch, lits in edges.get(n, ()):
                pm = nm = 0
                for x in lits:
                    if x > 0:
                        pm |= 1 << x
                    else:
                        nm |= 1 << -x
                out.append((index[ch], pm, nm, lits))
            self.edges.append(out)
        self.root_index = index[self.root]

    def _prepare(self) -> None:
        """Variable sets of nodes and edges (bitsets), restricted to the universe."""
        u = self.universe
        mentioned = 0
        for es in self.edges:
            for _, pm, nm, _ in es:
                mentioned |= pm | nm
        if mentioned & ~u:
            raise NNFError("the circuit mentions variables outside the counted universe")
        vs: list[int] = []
        evs: list[list[int]] = []
        for i, k in enumerate(self.kind):
            acc = 0
            ev = []
            for ch, pm, nm, _ in self.edges[i]:
                m = (vs[ch] | pm | nm) & u
                ev.append(m)
                acc |= m
            vs.append(acc)
            evs.append(ev)
        self.vars_of = vs
        self.edge_vars = evs
        # per edge: the node's variables the edge does not mention (free on that branch)
        self.edge_gap = [[vs[i] & ~m for m in ev] for i, ev in enumerate(evs)]
        self.size = sum(len(e) for e in self.edges) + len(self.kind)

    # ------------------------------------------------------------------ passes
    @staticmethod
    def _masks(assumptions: Sequence[int]) -> tuple[int, int]:
        pos = neg = 0
        for x in assumptions:
            if x > 0:
                pos |= 1 << x
            else:
                neg |= 1 << -x
        if pos & neg:
            return -1, -1
        return pos, neg

    def _up(self, pos: int, neg: int) -> tuple[list[int], list[list[int]], int]:
        """(mc per node, value per edge (mc of the edge, before the or-node's scaling), root scale)."""
        free = self.universe & ~(pos | neg)
        mc: list[int] = []
        evals: list[list[int]] = []
        for i, k in enumerate(self.kind):
            es = self.edges[i]
            if k == "t":
                mc.append(1)
                evals.append([])
                continue
            if k == "f":
                mc.append(0)
                evals.append([])
                continue
            vals = []
            for ch, pm, nm, _ in es:
                if (pm & neg) or (nm & pos):
                    vals.append(0)
                else:
                    vals.append(mc[ch])
            evals.append(vals)
            if k == "a":
                acc = 1
                for v in vals:
                    acc *= v
                    if not acc:
                        break
                mc.append(acc)
            else:  # or
                acc = 0
                for v, gap in zip(vals, self.edge_gap[i]):
                    if v:
                        acc += v << ((gap & free).bit_count())
                mc.append(acc)
        scale = (self.universe & ~self.vars_of[self.root_index] & free).bit_count()
        return mc, evals, scale

    def count(self, assumptions: Sequence[int] = ()) -> int:
        """Models over the universe that agree with ``assumptions``."""
        pos, neg = self._masks(assumptions)
        if pos < 0:
            return 0
        mc, _, scale = self._up(pos, neg)
        return mc[self.root_index] << scale

    def counts(self, assumptions: Sequence[int] = ()) -> PassResult:
        """The count under ``assumptions`` and, for every variable v, the count with v true."""
        n = self.nvars
        pos, neg = self._masks(assumptions)
        if pos < 0:
            return PassResult(0, [0] * (n + 1))
        mc, evals, scale = self._up(pos, neg)
        r = self.root_index
        total = mc[r] << scale
        delta = [0] * (n + 1)
        if total:
            free = self.universe & ~(pos | neg)
            d = [0] * len(self.kind)
            d[r] = 1 << scale
            for i in range(len(self.kind) - 1, -1, -1):
                di = d[i]
                if not di:
                    continue
                k = self.kind[i]
                if k in "tf":
                    continue
                es = self.edges[i]
                vals = evals[i]
                if k == "a":
                    zeros = [j for j, v in enumerate(vals) if not v]
                    if len(zeros) > 1:
                        continue
                    prod = mc[i] if not zeros else None
                    for j, (ch, pm, nm, lits) in enumerate(es):
                        if zeros:
                            if j != zeros[0]:
                                continue
                            other = 1
                            for jj, v in enumerate(vals):
                                if jj != j:
                                    other *= v
                            de = di * other
                        else:
                            de = di * (prod // vals[j])
                        # the edge is inconsistent with the assumptions: no model goes through
                        if not vals[j]:
                            continue
                        d[ch] += de
                        if lits:
                            w = de * vals[j]
                            for x in lits:
                                if x > 0:
                                    delta[x] += w
                                else:
                                    delta[-x] -= w
                else:
                    gaps = self.edge_gap[i]
                    for j, (ch, pm, nm, lits) in enumerate(es):
                        v = vals[j]
                        if not v:
                            continue
                        de = di << ((gaps[j] & free).bit_count())
                        d[ch] += de
                        if lits:
                            w = de * v
                            for x in lits:
                                if x > 0:
                                    delta[x] += w
                                else:
                                    delta[-x] -= w
        positive = [0] * (n + 1)
        u = self.universe
        for v in range(1, n + 1):
            bit = 1 << v
            if pos & bit:
                positive[v] = total
            elif neg & bit:
                positive[v] = 0
            elif not (u & bit):
                positive[v] = total  # not counted: does not split the models
            else:
                positive[v] = (total + delta[v]) >> 1
        return PassResult(total, positive)

    # ------------------------------------------------------------------ sampling
    def sample(self, rng, assumptions: Sequence[int] = ()) -> Optional[list[int]]:
        """One model over the universe, uniformly at random among those agreeing with
        ``assumptions`` (None when there is none): top-down, each or-branch taken with
        probability proportional to its count.  Returns a full assignment: list of literals
        for the variables of the universe, in variable order."""
        pos, neg = self._masks(assumptions)
        if pos < 0:
            return None
        mc, evals, scale = self._up(pos, neg)
        if not mc[self.root_index]:
            return None
        free = self.universe & ~(pos | neg)
        value: dict[int, bool] = {}
        stack = [self.root_index]
        while stack:
            i = stack.pop()
            k = self.kind[i]
            if k in "tf":
                continue
            es = self.edges[i]
            vals = evals[i]
            if k == "a":
                chosen = list(range(len(es)))
            else:
                weights = [v << ((self.edge_gap[i][j] & free).bit_count()) if v else 0
                           for j, v in enumerate(vals)]
                pick = rng.randrange(sum(weights))
                j = 0
                while pick >= weights[j]:
                    pick -= weights[j]
                    j += 1
                chosen = [j]
            for j in chosen:
                ch, pm, nm, lits = es[j]
                for x in lits:
                    value[abs(x)] = x > 0
                stack.append(ch)
        out = []
        u = self.universe
        for v in range(1, self.nvars + 1):
            if not (u >> v) & 1:
                continue
            if (pos >> v) & 1:
                out.append(v)
            elif (neg >> v) & 1:
                out.append(-v)
            elif v in value:
                out.append(v if value[v] else -v)
            else:  # free wherever the walk went: uniform
                out.append(v if rng.random() < 0.5 else -v)
        return out
