"""A DIMACS CNF of a model (see :mod:`tvl_lsp.analysis.convert`)."""

from __future__ import annotations

from ...tvl import model as M
from ..encode import Element, Encoding, _Builder
from .common import MAX_COMPILE_FEATURES, PAIRWISE_MAX, Conversion, _definitions, _feature_names, _project, _pure_vars


# ====================================================================== DIMACS

class DimacsWriter:
    """A CNF whose models are exactly the products (every auxiliary variable is a function of
    the features), with FeatureIDE's ``c <var> <name>`` lines."""

    def __init__(self, model: M.Model, enc: Encoding):
        self.model = model
        self.enc = enc
        self.notes: list[str] = []
        self.exact = True

    def run(self) -> Conversion:
        enc = self.enc
        n = enc.n_features
        names = _feature_names(self.model, "dimacs", self.notes)
        pure = _pure_vars(enc)
        defs = _definitions(enc)
        out: list[list[int]] = []
        # our own builder for cardinalities: functional definitions only
        top = max(enc.nvars, n)
        hard: list[list[int]] = []
        b = _Builder(top, hard)
        impure: list[Element] = []
        used_defs: set[int] = set()
        for e in enc.elements:
            if e.kind in ("group", "group-lower"):
                out += self._group(e, b)
                continue
            vs = {abs(x) for c in e.clauses for x in c if abs(x) > n}
            if vs <= pure:
                out += e.clauses
                used_defs |= vs
            else:
                impure.append(e)
        if impure:
            by = {}
            for e in impure:
                by.setdefault(e.kind, []).append(e)
            clauses = [c for e in impure for c in e.clauses]
            proj = _project(enc, clauses)
            if proj is None:
                self.exact = False
                self.notes.append("NOT converted exactly: attribute constraints over more than "
                                  f"{MAX_COMPILE_FEATURES} features are left out; the CNF may have more models")
            else:
                out += proj
        # Tseitin definitions of the auxiliaries used (and of the ones they use)
        need = set(used_defs)
        stack = list(used_defs)
        while stack:
            v = stack.pop()
            for x in defs.get(v, ()):
                if abs(x) > n and abs(x) not in need:
                    need.add(abs(x))
                    stack.append(abs(x))
        for v in sorted(need):
            key = defs[v]
            for x in key:
                out.append([-v, x])
            out.append([v] + [-x for x in key])
        out += hard
        # renumber: features 1..n, then the auxiliaries in order of first use
        ren: dict[int, int] = {}
        nxt = n
        final = []
        for c in out:
            cc = []
            for x in c:
                v = abs(x)
                if v > n:
                    if v not in ren:
                        nxt += 1
                        ren[v] = nxt
                    v = ren[v]
                cc.append(v if x > 0 else -v)
            final.append(cc)
        feats = enc.features
        lines = [f"c {i} {names[f]}" for i, f in enumerate(feats, start=1)]
        if nxt > n:
            lines.append(f"c variables {n + 1}..{nxt} are auxiliary: each is defined by the features "
                         "(the models of this CNF are the products)")
        lines.append(f"p cnf {nxt} {len(final)}")
        lines += [" ".join(map(str, c)) + " 0" for c in final]
        return Conversion("\n".join(lines) + "\n", self.notes, self.exact)

    def _group(self, e: Element, b: _Builder) -> list[list[int]]:
        """A group's bound with a functional encoding (no free auxiliary variable)."""
        g: M.Group = e.obj
        v = self.enc.var_of_feature
        p = v[g.owner]
        seen = set()
        kids = []
        for c in g.children:
            if c.feature in v and c.feature not in seen:
                seen.add(c.feature)
                kids.append(c)
        if e.kind == "group":  # at most hi of all children
            lits = [v[c.feature] for c in kids]
            return [[-p] + c for c in _at_most(b, lits, g.hi)]
        mand = [c for c in kids if not c.optional]
        need = g.lo - (len(kids) - len(mand))
        if need > len(mand):
            return [[-p]]
        return [[-p] + c for c in _at_least(b, [v[c.feature] for c in mand], need)]


def _counter(b: _Builder, lits: list[int], k: int) -> list:
    """``c[j]`` (j = 1..k) is true iff at least j of ``lits`` are (defined, not just implied)."""
    c: list = [True] + [False] * k
    for x in lits:
        new = [True]
        for j in range(1, k + 1):
            new.append(b.or_([c[j], b.and_([c[j - 1], x])]))
        c = new
    return c


def _at_most(b: _Builder, lits: list[int], k: int) -> list[list[int]]:
    n = len(lits)
    if k >= n:
        return []
    if k <= 0:
        return [[-x] for x in lits]
    if k == 1 and n <= PAIRWISE_MAX:
        return [[-lits[i], -lits[j]] for i in range(n) for j in range(i + 1, n)]
    c = _counter(b, lits, k + 1)
    x = c[k + 1]
    return [] if x is False else [[]] if x is True else [[-x]]


def _at_least(b: _Builder, lits: list[int], k: int) -> list[list[int]]:
    n = len(lits)
    if k <= 0:
        return []
    if k > n:
        return [[]]
    if k == 1:
        return [list(lits)]
    if k == n:
        return [[x] for x in lits]
    c = _counter(b, lits, k)
    x = c[k]
    return [] if x is True else [[]] if x is False else [[x]]

