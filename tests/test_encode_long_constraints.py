"""Constraints too long to distribute within DISTRIBUTE_MAX clauses (issue #30: a UVL model's CNF
as small as its DIMACS twin's): a disjunction holding a long conjunction ("(C1 & .. & Cn) | S")
is asserted under a prefix, and a disjunction's clauses absorbed by another disjunct ("A1 |
!A1 & A2 | !A1 & !A2 & A3", KConfig's "the first selected") are dropped.  Seeded random UVL
constraints of those shapes (and random noise around them): the product count against
brute-force evaluation of the constraint, and no auxiliary variable where none is needed."""

import itertools
import random

import pytest

from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.formats import parse_any_model


def ev(e, val):
    kind = e[0]
    if kind == "v":
        return val[e[1]]
    if kind == "!":
        return not ev(e[1], val)
    if kind == "&":
        return all(ev(x, val) for x in e[1])
    return any(ev(x, val) for x in e[1])


def text(e) -> str:
    kind = e[0]
    if kind == "v":
        return f"F{e[1]}"
    if kind == "!":
        return f"!({text(e[1])})"
    sep = " & " if kind == "&" else " | "
    return "(" + sep.join(text(x) for x in e[1]) + ")"


def lit(rng, n):
    v = ("v", rng.randrange(n))
    return v if rng.random() < 0.6 else ("!", v)


def small(rng, n):
    k = rng.randrange(1, 4)
    xs = [lit(rng, n) for _ in range(k)]
    return xs[0] if k == 1 else (rng.choice("&|"), xs)


def first_selected(rng, n):
    """!S | C1 | !C1 & C2 | !C1 & !C2 & C3 ... (Ci conjunctions of two literals)"""
    cs = [("&", [lit(rng, n), lit(rng, n)]) for _ in range(rng.randrange(2, 7))]
    ds = [("&", [("!", c) for c in cs[:i]] + [cs[i]]) if i else cs[0] for i in range(len(cs))]
    return ("|", [lit(rng, n)] + ds)


def long_conj(rng, n):
    """(C1 & .. & Ck) | S with k clauses above DISTRIBUTE_MAX, each Ci a small disjunction"""
    conj = ("&", [("|", [lit(rng, n) for _ in range(rng.randrange(1, 4))]) for _ in range(rng.randrange(17, 30))])
    return ("|", [conj] + [small(rng, n) for _ in range(rng.randrange(1, 3))])


def model(n, constraints) -> str:
    feats = "".join(f"\t\t\tF{i}\n" for i in range(n))
    return "features\n\tRoot\n\t\toptional\n" + feats + "constraints\n" + \
        "".join(f"\t{text(c)}\n" for c in constraints)


@pytest.mark.parametrize("seed", range(60))
def test_long_constraints_count_exactly(seed):
    rng = random.Random(seed)
    n = rng.randrange(3, 9)
    shapes = [first_selected, long_conj, lambda r, k: (r.choice("&|"), [small(r, k), small(r, k)])]
    cons = [rng.choice(shapes)(rng, n) for _ in range(rng.randrange(1, 4))]
    res = parse_any_model(model(n, cons), "m.uvl")
    assert not res.errors
    a = ModelAnalysis(res.model)
    want = sum(1 for bits in itertools.product((False, True), repeat=n)
               if all(ev(c, bits) for c in cons))
    assert a.count() == want, (seed, [text(c) for c in cons])


def test_first_selected_needs_no_auxiliary_variable():
    rng = random.Random(7)
    n = 12
    cs = [("&", [("v", 0), ("v", i)]) for i in range(1, n)]
    ds = [("&", [("!", c) for c in cs[:i]] + [cs[i]]) if i else cs[0] for i in range(len(cs))]
    cons = [("|", [("!", ("v", n))] + ds),
            ("|", [("&", [("|", [("!", ("v", i)), ("!", ("v", j))]) for i in range(1, n) for j in range(i + 1, n)]),
                   ("v", n)])]
    res = parse_any_model(model(n + 1, cons), "m.uvl")
    enc = ModelAnalysis(res.model).encoding
    assert enc.nvars == enc.n_features
    want = sum(1 for bits in itertools.product((False, True), repeat=n + 1) if all(ev(c, bits) for c in cons))
    assert ModelAnalysis(res.model).count() == want
    del rng
