"""The DIMACS fast paths (parse, clause constraints, clause elements, solver loading) give what the
general code gave: each is checked against the code it replaced, on random CNFs with repeated
and complementary literals, empty clauses, clauses over several lines, comments and bad tokens."""

import itertools
import random

import pytest
from pysat.solvers import Solver

from tvl_lsp.analysis.dimacs import ClauseConstraint, DimacsError, _parse, dimacs_to_model, parse_dimacs
from tvl_lsp.analysis.encode import Element, Encoding, _clean, encode
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.labels import line_text, source_text
from tvl_lsp.analysis.solve import SOLVER, Analyzer, add_clauses, new_solver
from tvl_lsp.base.text import Pos, Span


def old_parse(text, errors=None):
    """parse_dimacs as it was: token by token."""
    nvars, names, clauses, lines_of, cur, cur_line, seen_p = 0, {}, [], [], [], 0, False

    def bad(ln, c0, c1, msg):
        if errors is None:
            raise DimacsError(f"line {ln + 1}: {msg}")
        if len(errors) < 100:
            errors.append((ln, c0, c1, msg))

    for ln, line in enumerate(text.splitlines()):
        s = line.strip()
        if not s:
            continue
        if s[0] == "c":
            parts = s.split(None, 2)
            if len(parts) == 3 and parts[1].isdigit():
                names[int(parts[1])] = parts[2].strip()
            continue
        if s[0] == "p":
            parts = s.split()
            lead = len(line) - len(line.lstrip())
            if len(parts) < 4 or parts[1] != "cnf" or not parts[2].isdigit() or not parts[3].isdigit():
                bad(ln, lead, len(line.rstrip()), f"bad problem line {s!r}: expected 'p cnf VARIABLES CLAUSES'")
                continue
            if seen_p:
                bad(ln, lead, len(line.rstrip()), "a second problem line")
            seen_p = True
            nvars = int(parts[2])
            continue
        if s[0] == "%":
            break
        col = 0
        for tok in s.split():
            col = line.index(tok, col)
            try:
                x = int(tok)
            except ValueError:
                bad(ln, col, col + len(tok), f"{tok!r} is not a literal (a signed variable number, 0 ends a clause)")
                col += len(tok)
                continue
            col += len(tok)
            if not cur:
                cur_line = ln
            if x == 0:
                clauses.append(cur)
                lines_of.append(cur_line)
                cur = []
            else:
                cur.append(x)
    if cur:
        clauses.append(cur)
        lines_of.append(cur_line)
    return nvars, clauses, names, lines_of


def random_dimacs(seed: int, n: int = 12, m: int = 30, messy: bool = True) -> str:
    """Clauses with repeated and complementary literals, empty clauses, named and unnamed
    variables; ``messy``: also clauses over several lines, comments between clauses, blank
    lines, tabs, bad tokens, CRLF line ends and a '%' line."""
    rng = random.Random(seed)
    lines = [f"c {i} v{i}" for i in range(1, n + 1) if rng.random() < 0.6]
    lines.append(f"p cnf {n} {m}")
    for _ in range(m):
        k = rng.choice([1, 1, 2, 2, 2, 3, 3, 4]) if rng.random() < 0.97 else 0  # 0: an empty clause
        c = [rng.choice([-1, 1]) * rng.randint(1, n) for _ in range(k)]
        if c and rng.random() < 0.2:
            c.append(c[0])  # a repeated literal
        if c and rng.random() < 0.1:
            c.insert(rng.randrange(len(c) + 1), -c[0])  # a tautology
        toks = [str(x) for x in c] + ["0"]
        if messy and rng.random() < 0.1:
            toks.insert(rng.randrange(len(toks)), rng.choice(["x", "1.5", "--2", "0x3"]))
        if messy and rng.random() < 0.1 and len(toks) > 1:
            i = rng.randrange(1, len(toks))
            lines += [" ".join(toks[:i]), " ".join(toks[i:])]
        else:
            sep = "\t" if messy and rng.random() < 0.1 else " "
            lines.append(("  " if messy and rng.random() < 0.1 else "") + sep.join(toks))
        if messy and rng.random() < 0.05:
            lines.append(rng.choice(["", "c a comment", "c 3 renamed"]))
    if messy and rng.random() < 0.2:
        lines += ["%", "0", "c 2 after"]
    end = "\r\n" if messy and rng.random() < 0.1 else "\n"
    return end.join(lines) + end


@pytest.mark.parametrize("seed", range(60))
def test_parse_is_the_token_by_token_parse(seed):
    text = random_dimacs(seed)
    e_old, e_new = [], []
    assert parse_dimacs(text, e_new) == old_parse(text, e_old)
    assert e_new == e_old
    # the encoder's numbering: x -> x + 1, -x -> -x - 1
    _, shifted, _, lines_of, lens, _ = _parse(text, [], True)
    assert shifted == [[x + 1 if x > 0 else x - 1 for x in c] for c in old_parse(text, [])[1]]
    assert lens == [len(x) for x in text.splitlines()]
    try:
        want = old_parse(text)
    except DimacsError as ex:
        with pytest.raises(DimacsError, match=str(ex).replace(".", r"\.").replace("(", r"\(").replace(")", r"\)")):
            parse_dimacs(text)
    else:
        assert parse_dimacs(text) == want


def old_line_text(model, c, cache, limit=80):
    lines = cache.get(("lines", c.path))
    if lines is None:
        lines = cache[("lines", c.path)] = (model.sources.get(c.path) or "").splitlines()
    ln = c.span.start.line
    s = " ".join(lines[ln].split()) if 0 <= ln < len(lines) and c.span.start.col == 0 else ""
    if not s:
        return source_text(model, c.path, c.span, limit, cache)
    return s if len(s) <= limit else s[: limit - 1] + "…"


class OldEncoding(Encoding):
    """The encoder's DIMACS-clause branch as it was (one Element per clause, made eagerly)."""

    def _encode_constraints(self):
        v = self.var_of_feature
        feats = self.model.features
        cache: dict = {}
        for c in self.model.root.constraints:
            cl = _clean([v[feats[x]] if x > 0 else -v[feats[-x]] for x in c.clause])
            clauses = [] if cl is None else [cl]
            text = old_line_text(self.model, c, cache) or "constraint"
            neg = [-x for x in clauses[0]] if len(clauses) == 1 else [False] if not clauses else None
            self._add(Element("constraint", f"constraint `{text}`", c.path, c.span, c, clauses, negation=neg))


def old_encode(model):
    enc = OldEncoding(model)
    enc._encode_structure()
    enc._encode_constraints()
    enc._encode_attributes()
    return enc


def element_view(e):
    return (e.kind, e.label, e.path, e.span, e.clauses, e.negation, e.obj)


@pytest.mark.parametrize("seed", range(40))
def test_clause_elements_are_the_general_elements(seed):
    text = random_dimacs(seed, messy=seed % 2 == 0)
    model = dimacs_to_model(text, "r.dimacs", [])
    new, old = encode(model), old_encode(model)
    assert [element_view(e) for e in new.elements] == [element_view(e) for e in old.elements]
    assert new.clauses() == old.clauses() and new.hard == old.hard and new.nvars == old.nvars


@pytest.mark.parametrize("seed", range(30))
def test_anomalies_and_explanations_are_the_general_ones(seed):
    # void models (many short clauses) and models with dead features
    text = random_dimacs(seed, n=10, m=[8, 14, 22][seed % 3], messy=seed % 2 == 0)
    model = dimacs_to_model(text, "r.dimacs", [])
    got = ModelAnalysis(model).anomalies(time_budget=None)
    want = ModelAnalysis(model, old_encode(model)).anomalies(time_budget=None)
    assert [(d.code, d.message, d.span, d.related) for d in got] == \
        [(d.code, d.message, d.span, d.related) for d in want]


def test_labels_name_the_clause_line_in_messages():
    text = "c 1 A\nc 2 B\np cnf 2 4\n1   2 0\n-1\t2 0\n  1 -2 0\n-1 -2 -1 0\n"
    a = ModelAnalysis.from_dimacs(text, "v.dimacs")
    (d,) = a.anomalies(time_budget=None)
    assert d.code == "void-model"
    labels = {r.message for r in d.related}
    assert labels == {"constraint `1 2 0`", "constraint `-1 2 0`", "constraint `1 -2 0`",
                      "constraint `-1 -2 -1 0`"}
    assert {r.span for r in d.related} == {Span(Pos(ln, 0), Pos(ln, len(text.splitlines()[ln]))) for ln in (3, 4, 5, 6)}


def test_labels_of_a_text_with_other_line_breaks():
    # "\x0c" and "\r" break lines for str.splitlines: the labels and spans follow it
    text = "p cnf 2 3\r1 2 0\x0c-1 0\r\n-2 0\n"
    a = ModelAnalysis.from_dimacs(text, "v.dimacs")
    (d,) = a.anomalies(time_budget=None)
    assert [r.message for r in d.related] == ["constraint `1 2 0`", "constraint `-1 0`", "constraint `-2 0`"]
    cache: dict = {}
    for c in a.model.root.constraints:
        assert line_text(a.model, c, cache) == old_line_text(a.model, c, {})


def test_long_clause_lines_are_shortened_in_labels():
    n = 60
    text = f"p cnf {n} 2\n" + " ".join(map(str, range(1, n + 1))) + " 0\n" + "0\n"
    enc = encode(dimacs_to_model(text, "l.dimacs"))
    old = old_encode(dimacs_to_model(text, "l.dimacs"))
    assert [e.label for e in enc.elements] == [e.label for e in old.elements]
    assert enc.elements[-2].label.endswith("…`") and len(enc.elements[-2].label) == len("constraint ``") + 80


def test_clause_constraint_reads_and_assignments():
    model = dimacs_to_model("c 1 A\np cnf 3 2\n1 -3 0\n-2 0\n", "m.dimacs")
    c, d = model.root.constraints
    assert isinstance(c, ClauseConstraint) and c.kind == "plain" and not c.has_errors
    assert c.clause == [1, -3] and c.lits == [2, -4] and d.clause == [-2]
    assert c.span == Span(Pos(2, 0), Pos(2, 6)) and c.path == "m.dimacs" and c.owner is model.root
    assert c.expr.op == "||"  # the OR tree, made when asked for
    c.clause = [2, 3]
    assert c.lits == [3, 4] and c.clause == [2, 3]
    c.span, c.path, c.owner = Span(Pos(0, 0), Pos(0, 1)), "x.dimacs", model.features[1]
    assert (c.span, c.path, c.owner) == (Span(Pos(0, 0), Pos(0, 1)), "x.dimacs", model.features[1])
    assert (d.span, d.path, d.owner) == (Span(Pos(3, 0), Pos(3, 4)), "m.dimacs", model.root)
    enc = encode(model)
    assert [e.clauses for e in enc.elements if e.kind == "constraint"] == [[[3, 4]], [[-3]]]
    e = enc.elements[-1]
    e.label, e.negation = "mine", [1]
    assert (e.label, e.negation) == ("mine", [1])


@pytest.mark.parametrize("seed", range(10))
def test_add_clauses_is_bootstrap(seed):
    rng = random.Random(seed)
    cls = [[rng.choice([-1, 1]) * rng.randint(1, 8) for _ in range(rng.randint(0 if seed == 3 else 1, 3))]
           for _ in range(rng.randint(1, 30))]
    a, b = new_solver(cls), Solver(name=SOLVER, bootstrap_with=cls)
    try:
        assert a.solver.status == b.solver.status
        assert a.solve() == b.solve()
        assert a.get_model() == b.get_model() and a.get_core() == b.get_core()
    finally:
        a.delete()
        b.delete()


def brute_products(n, clauses):
    for bits in itertools.product([False, True], repeat=n):
        if all(any((x > 0) == bits[abs(x) - 1] for x in c) for c in clauses):
            yield bits


@pytest.mark.parametrize("seed", range(25))
def test_backbone_and_false_optional_are_exact(seed):
    text = random_dimacs(seed, n=9, m=[4, 7, 10][seed % 3], messy=False)
    model = dimacs_to_model(text, "b.dimacs")
    enc = encode(model)
    an = Analyzer(enc)
    prods = list(brute_products(enc.n_features, enc.clauses()))
    assert an.is_void() == (not prods)
    if not prods:
        return
    forced = {v: prods[0][v - 1] for v in range(1, enc.n_features + 1)
              if all(p[v - 1] == prods[0][v - 1] for p in prods)}
    assert an.backbone() == forced
    # every variable is an optional child of the root, which every product selects
    want = [(enc.feature_of_var[v], model.root) for v in range(2, enc.n_features + 1) if forced.get(v) is True]
    assert an.false_optional() == want
