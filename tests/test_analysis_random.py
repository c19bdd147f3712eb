"""Random small feature models: the SAT analyses against an independent brute force.

The models are built directly as ``tvl_lsp.tvl.model`` objects (random trees, random group
cardinalities, optional and shared children, random plain / ifIn / ifOut constraints); the
brute force enumerates every selection of features and applies the reference semantics
literally.  Also checks that every explanation is a minimal unsatisfiable set of elements.
"""

import itertools
import random

import pytest
from pysat.solvers import Solver

from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.base import formula as fm
from tvl_lsp.base.text import ZERO_SPAN
from tvl_lsp.tvl import model as M


def name(f):
    return M.Name([f.name], target=f)


def random_model(rng: random.Random, n: int) -> M.Model:
    root = M.Feature("F0", ZERO_SPAN, ZERO_SPAN, "r.tvl", is_root=True)
    feats = [root]
    for i in range(1, n):
        parent = rng.choice(feats)
        f = M.Feature(f"F{i}", ZERO_SPAN, ZERO_SPAN, "r.tvl", parent=parent)
        if parent.group is None:
            parent.group = M.Group("card", parent, ZERO_SPAN, ZERO_SPAN, "r.tvl")
        parent.group.children.append(M.GroupChild(f, rng.random() < 0.4, False, ZERO_SPAN, "r.tvl"))
        feats.append(f)
    # a shared child now and then
    if n > 3 and rng.random() < 0.5:
        f = rng.choice(feats[2:])
        others = [p for p in feats if p is not f and p is not f.parent and not _is_desc(p, f)]
        if others:
            p = rng.choice(others)
            if p.group is None:
                p.group = M.Group("card", p, ZERO_SPAN, ZERO_SPAN, "r.tvl")
            if all(c.feature is not f for c in p.group.children):
                p.group.children.append(M.GroupChild(f, rng.random() < 0.4, True, ZERO_SPAN, "r.tvl"))
                f.shared_parents.append(p)
    for f in feats:
        g = f.group
        if g is None:
            continue
        k = len(g.children)
        kind = rng.choice(["oneOf", "someOf", "allOf", "card", "card"])
        g.kind = kind
        if kind == "oneOf":
            g.lo, g.hi = 1, 1
        elif kind == "someOf":
            g.lo, g.hi = 1, None
        elif kind == "allOf":
            g.lo, g.hi = k, k
        else:
            g.lo = rng.randint(0, k)
            g.hi = rng.choice([None, rng.randint(g.lo, k + 1), max(0, g.lo - 1) if rng.random() < 0.1 else g.lo])
    for _ in range(rng.randint(0, 4)):
        a, b = rng.sample(feats, 2)
        op = rng.choice(["->", "excludes", "||", "&&", "<->", "requires"])
        e = M.Binary(op, name(a), name(b))
        if rng.random() < 0.3:
            e = M.Unary("!", e)
        if rng.random() < 0.25 and len(feats) >= 4:
            # an OR of ANDs too big to distribute: Tseitin variables (hard clauses) shared with
            # the other constraints, which explanations must take along (solve.Analyzer._hard_cone)
            terms = [M.Binary("&&", name(x), name(y)) for x, y in (rng.sample(feats, 2) for _ in range(5))]
            e = terms[0]
            for t in terms[1:]:
                e = M.Binary("||", e, t)
        owner = rng.choice(feats)
        owner.constraints.append(M.Constraint(e, rng.choice(["plain", "plain", "ifIn", "ifOut"]), owner,
                                              ZERO_SPAN, "r.tvl"))
    return M.Model("r.tvl", root=root, features=feats)


def _is_desc(p, f):
    while p is not None:
        if p is f:
            return True
        p = p.parent
    return False


def ev(e, sel):
    if isinstance(e, M.Name):
        return sel[e.target.name]
    if isinstance(e, M.Unary):
        return not ev(e.operand, sel)
    a, b = ev(e.left, sel), ev(e.right, sel)
    return {"->": (not a) or b, "requires": (not a) or b, "excludes": not (a and b), "||": a or b,
            "&&": a and b, "<->": a == b}[e.op]


def brute(m: M.Model):
    feats = m.features
    out = []
    for bits in itertools.product([False, True], repeat=len(feats)):
        sel = {f.name: b for f, b in zip(feats, bits)}
        if not sel[m.root.name]:
            continue
        ok = True
        for f in feats:
            if sel[f.name] and f.parents and not any(sel[p.name] for p in f.parents):
                ok = False
            g = f.group
            if ok and g is not None and sel[f.name]:
                s = {c.feature.name for c in g.children if sel[c.feature.name]}
                mand = {c.feature.name for c in g.children if not c.optional}
                nopt = len({c.feature.name for c in g.children if c.optional})
                if g.hi is not None and len(s) > g.hi:
                    ok = False
                if len(s & mand) + nopt < g.lo:
                    ok = False
            for c in f.constraints:
                v = ev(c.expr, sel)
                if c.kind == "plain" and not v or c.kind == "ifIn" and sel[f.name] and not v \
                        or c.kind == "ifOut" and not sel[f.name] and not v:
                    ok = False
            if not ok:
                break
        if ok:
            out.append(sel)
    return out


def check_minimal(an, expl_elements, extra):
    enc = an.encoding
    def sat(elems):
        with Solver(name="minisat22", bootstrap_with=enc.hard) as s:
            for e in elems:
                for c in e.clauses:
                    s.add_clause(c)
            return s.solve(assumptions=extra)
    assert not sat(expl_elements)
    for i in range(len(expl_elements)):
        assert sat(expl_elements[:i] + expl_elements[i + 1:])


@pytest.mark.parametrize("seed", range(150))
def test_random_model_against_brute_force(seed):
    rng = random.Random(seed)
    m = random_model(rng, rng.randint(2, 9))
    prods = brute(m)
    a = ModelAnalysis(m)
    assert a.count() == len(prods)
    assert a.is_void() == (not prods)
    names = [f.name for f in m.features]
    if prods:
        dead = sorted(n for n in names if not any(p[n] for p in prods))
        core = sorted(n for n in names if all(p[n] for p in prods))
        assert sorted(a.dead_features()) == dead
        assert sorted(a.core_features()) == core
        fo = set()
        for p in m.features:
            for c in (p.group.children if p.group else []):
                f = c.feature
                if c.optional and p.name not in dead and f.name not in dead \
                        and all(q[f.name] for q in prods if q[p.name]):
                    fo.add((f.name, p.name))
        assert {(f.name, p.name) for f, p in a.analyzer.false_optional()} == fo
        # per-feature counts and counts under a partial configuration
        fc = a.feature_counts()
        for n in names:
            assert fc[n] == sum(1 for p in prods if p[n])
        x, y = rng.sample(names, 2)
        assert a.count(include=[x], exclude=[y]) == sum(1 for p in prods if p[x] and not p[y])
        f = fm.disj([fm.var(x), fm.neg(fm.var(y))])
        assert a.count(formula=f) == sum(1 for p in prods if p[x] or not p[y])
        # explanations are minimal unsatisfiable element sets
        v = a.encoding.var_of_feature
        for fe in a.analyzer.dead():
            check_minimal(a, a.analyzer.explain([v[fe]]).elements, [v[fe]])
        for fe, pe in a.analyzer.false_optional():
            check_minimal(a, a.analyzer.explain([v[pe], -v[fe]]).elements, [v[pe], -v[fe]])
        # smallest product
        best = a.find_product(include=[x])
        want = [p for p in prods if p[x]]
        if want:
            assert best is not None and best[x]
            assert sum(best.values()) == min(sum(p.values()) for p in want)
            assert best in prods
        else:
            assert best is None
    else:
        check_minimal(a, a.analyzer.explain([]).elements, [])
        assert any(d.code == "void-model" for d in a.anomalies())
