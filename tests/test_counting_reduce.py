"""The CNF reduction before d4 (:mod:`tvl_lsp.analysis.counting.simplify`, issue #30) keeps every
count exact: the total, the counts under decisions and every variable's count, compared with
brute-force enumeration on seeded random CNFs built to trigger each reduction (units, failed
literals, equivalent literals, implication chains, hidden tautologies and literals, core and
dead variables, variables in no clause, unused auxiliary variables), and a UVL model against its
DIMACS twin written by hand."""

import itertools
import random
from pathlib import Path

import pytest

from tvl_lsp.analysis.counting import service as S
from tvl_lsp.analysis.counting.simplify import LiftedCircuit, Reduction, reduce_cnf

DATA = Path(__file__).parent / "data" / "counting" / "twin"


def brute(nvars, clauses, lits=(), project=None):
    """(models, models with each variable true), over variables 1..nvars (or, with ``project``,
    the number of distinct assignments of variables 1..project among the models)."""
    total = 0
    pos = [0] * (nvars + 1)
    seen = set()
    fixed = {abs(x): x > 0 for x in lits}
    for bits in itertools.product((False, True), repeat=nvars):
        val = (None,) + bits
        if any(val[v] != b for v, b in fixed.items()):
            continue
        if all(any(val[abs(x)] == (x > 0) for x in c) for c in clauses):
            if project is not None:
                key = bits[:project]
                if key in seen:
                    continue
                seen.add(key)
            total += 1
            for v in range(1, nvars + 1):
                pos[v] += val[v]
    return total, pos


def random_cnf(rng: random.Random, n: int):
    """A CNF over 1..n shaped like a feature model's (implications, equivalences, exclusions,
    groups) with some noise; a few variables left in no clause."""
    cls = []
    lits = list(range(1, n + 1))
    used = rng.sample(lits, max(1, n - rng.randrange(3)))
    for _ in range(rng.randrange(n // 2, 2 * n)):
        kind = rng.random()
        a, b = rng.sample(used, 2) if len(used) > 1 else (used[0], used[0])
        if kind < 0.08:
            cls.append([rng.choice((a, -a))])                      # unit
        elif kind < 0.35:
            cls.append([-a, b])                                    # a -> b
        elif kind < 0.45:
            cls += [[-a, b], [-b, a]]                              # a <-> b
        elif kind < 0.55:
            cls.append([-a, -b])                                   # exclusion
        elif kind < 0.6:
            cls.append([a, b])
        elif kind < 0.62:
            cls.append([a, -a])                                    # tautology
        elif kind < 0.64:
            cls.append([a, a, -b])                                 # repeated literal
        else:
            k = rng.randrange(3, min(6, len(used)) + 1) if len(used) >= 3 else len(used)
            cls.append([x if rng.random() < 0.6 else -x for x in rng.sample(used, k)])
    return cls


def lifted(nvars, clauses, red: Reduction, universe):
    """The reduced CNF "compiled" by enumeration: a circuit with the interface LiftedCircuit
    needs, so that the reduction alone is under test."""

    class Enum:
        def count(self, lits=()):
            return brute(red.k, red.clauses, lits)[0]

        def counts(self, lits=()):
            from tvl_lsp.analysis.counting.circuit import PassResult
            t, p = brute(red.k, red.clauses, lits)
            return PassResult(t, p)

    return LiftedCircuit(Enum() if red.k and not red.void else None, red, universe)


@pytest.mark.parametrize("seed", range(150))
def test_reduction_keeps_every_count(seed):
    rng = random.Random(seed)
    n = rng.randrange(2, 11)
    cls = random_cnf(rng, n)
    universe = range(1, n + 1)
    red = reduce_cnf(n, cls, n, universe, backbone=seed % 2 == 0)
    circ = lifted(n, cls, red, universe)
    for lits in ([], [rng.choice((1, -1)) * rng.randrange(1, n + 1)],
                 [x * rng.choice((1, -1)) for x in rng.sample(range(1, n + 1), min(2, n))]):
        total, pos = brute(n, cls, lits)
        assert circ.count(lits) == total, (seed, lits, cls)
        r = circ.counts(lits)
        assert r.total == total and r.positive[1:] == pos[1:], (seed, lits, cls)
    # the reduction read back from its stored form answers the same
    back = Reduction.from_json(red.to_json(), n)
    back.clauses = red.clauses
    assert lifted(n, cls, back, universe).counts([]).positive == circ.counts([]).positive


@pytest.mark.parametrize("seed", range(40))
def test_defined_auxiliary_variables_eliminated_keep_the_projected_count(seed):
    """Auxiliary variables defined by the features (Tseitin gates) may be eliminated: the count
    of the features' assignments stays (the service leaves this off, see CNFCounter._compile)."""
    rng = random.Random(1000 + seed)
    nf = rng.randrange(3, 8)
    cls = random_cnf(rng, nf)
    top = nf
    for _ in range(rng.randrange(1, 4)):
        a, b = (x * rng.choice((1, -1)) for x in rng.sample(range(1, top + 1), 2))
        top += 1
        g = top  # g <-> a & b
        cls += [[-g, a], [-g, b], [g, -a, -b]]
        if rng.random() < 0.7:
            cls.append([g, rng.choice((1, -1)) * rng.randrange(1, nf + 1)])
    universe = range(1, top + 1)
    red = reduce_cnf(top, cls, nf, universe, eliminate_aux=True)
    circ = lifted(top, cls, red, universe)
    total, _ = brute(top, cls, project=nf)
    assert circ.count() == total, (seed, cls)
    for v in range(1, nf + 1):
        assert circ.count([v]) == brute(top, cls, [v], project=nf)[0], (seed, v, cls)


def test_unused_auxiliary_variables_are_not_counted(fresh_cache):
    """Variables above the features in no clause: neither free nor kept (as before)."""
    cls = [[1, 2], [-1, 3], [-3, 1]]
    svc = S.CNFCounter(6, cls, 3)
    assert svc.count().value == brute(3, cls)[0]
    r = svc.feature_counts()
    assert r.counts[1:] == brute(3, cls)[1][1:]


@pytest.mark.parametrize("seed", range(40))
def test_the_service_counts_the_same_with_and_without_reduction(seed, fresh_cache):
    """d4 on the reduced CNF, lifted back, against d4 on the CNF and brute force; the circuit
    read back from the disk cache answers the same."""
    rng = random.Random(5000 + seed)
    n = rng.randrange(3, 13)
    cls = random_cnf(rng, n)
    red = S.CNFCounter(n, cls, n)
    raw = S.CNFCounter(n, cls, n, reduce=False)
    assert red.key != raw.key
    total, pos = brute(n, cls)
    assert red.count().value == raw.count().value == total
    d = rng.randrange(1, n + 1) * rng.choice((1, -1))
    assert red.count([d]).value == raw.count([d]).value == brute(n, cls, [d])[0]
    assert red.feature_counts().counts[1:] == raw.feature_counts().counts[1:] == pos[1:]
    S.MEMORY.clear()
    again = S.CNFCounter(n, cls, n)
    comp = again.circuit()
    assert comp.source == "disk"
    assert again.feature_counts([d]).counts[1:] == brute(n, cls, [d])[1][1:]
    if total:
        rows, engine = again.sample_uniform(5, seed=seed)
        assert engine == "d4" and len(rows) == 5
        for row in rows:
            val = {abs(x): x > 0 for x in row}
            assert all(any(val[abs(x)] == (x > 0) for x in c) for c in cls)


def test_a_void_cnf_counts_zero(fresh_cache):
    cls = [[1, 2], [-1], [-2, 3], [-3]]
    svc = S.CNFCounter(3, cls, 3)
    assert svc.count().value == 0
    assert svc.feature_counts().counts[1:] == [0, 0, 0]
    assert svc.sample_uniform(2, seed=1)[0] == []


def test_a_damaged_stored_reduction_is_compiled_again(fresh_cache):
    cls = [[1, 2], [-1, 3], [-3, 1], [4, -2]]
    svc = S.CNFCounter(4, cls, 4)
    n = svc.count().value
    p = S.DISK.path(svc.key)
    text = p.read_text()
    assert text.startswith(S.REDUCTION_TAG)
    p.write_text(text.replace('"nvars":4', '"nvars":5', 1))
    S.MEMORY.clear()
    S.forget_failures()
    assert S.CNFCounter(4, cls, 4).feature_counts().total == n == brute(4, cls)[0]


def test_uvl_model_and_its_dimacs_twin_count_the_same(fresh_cache):
    """robot.dimacs is robot.uvl's product line written by hand: the same total and the same
    count for every feature (by name), both equal to enumeration of the DIMACS clauses."""
    from tvl_lsp.analysis.dimacs_read import parse_dimacs
    from tvl_lsp.cli.commands.count import load
    dimacs_text = (DATA / "robot.dimacs").read_text()
    nv, cls, names, _ = parse_dimacs(dimacs_text)
    total, pos = brute(nv, cls)
    uvl, errors = load(str(DATA / "robot.uvl"))
    assert not errors
    twin, _ = load(str(DATA / "robot.dimacs"))
    tu, per_u, _ = uvl.per_feature([], [], None)
    td, per_d, _ = twin.per_feature([], [], None)
    assert tu == td == total == 28
    expected = {names[v]: pos[v] for v in range(1, nv + 1)}
    assert {k: per_u[k] for k in expected} == expected
    assert {k: per_d[k] for k in expected} == expected
    assert uvl.count(["Legs"], ["Lidar"], None).value == twin.count(["Legs"], ["Lidar"], None).value \
        == brute(nv, cls, [8, -4])[0]


@pytest.mark.parametrize("seed", range(20))
def test_without_reachability_the_counts_stay(seed, monkeypatch):
    """A CNF whose implication graph is too big for the reachability bitsets: equivalences and
    propagation only, the same counts."""
    from tvl_lsp.analysis.counting import simplify
    monkeypatch.setattr(simplify, "REACH_MAX_BITS", 0)
    rng = random.Random(9000 + seed)
    n = rng.randrange(2, 11)
    cls = random_cnf(rng, n)
    red = reduce_cnf(n, cls, n, range(1, n + 1), backbone=False)
    assert red.void or not red.stats.get("transitive")
    circ = lifted(n, cls, red, range(1, n + 1))
    total, pos = brute(n, cls)
    r = circ.counts([])
    assert r.total == total and r.positive[1:] == pos[1:]
