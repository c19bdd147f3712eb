"""The UVL front end's fast paths give what its general path gives.

The lexer reads a line that is one name without its general pattern, and the parser builds a
clean file's feature tree straight from the lines' indentation (falling back to the LALR driver
with line recovery on anything else).  Random texts -- well-formed models and models broken in
the ways people break them -- are read both ways and must give the same lines, the same model
and the same diagnostics.
"""

from __future__ import annotations

import enum
import functools
import random

import pytest

from tvl_lsp.uvl import build as uvl_build
from tvl_lsp.uvl import parse_uvl
from tvl_lsp.uvl.lexer import tokenize

_KWS = ["optional", "mandatory", "or", "alternative", "[1..2]", "[2]", "[0..*]", "[ 1 .. 3 ]"]
_NOISE = ["optional", "or", "[1..3]", "{abstract}", "{a 1, b 'x'}", "{abstract true}", "=>", "<=>", "&",
          "|", "!", "(", ")", "{", "}", "[", "]", ",", ".", '"q x"', '"a.b"', "'s'", "3", "-2", "1.5",
          "cardinality [1..2]", "Integer", "String", "constraint A", "constraints [A, B]", "\t", "    ",
          "é", "ß", "\u00a0", "\f", "//c", "/*", "*/", "/* x */", "\r\n", "\r", "\n", "optinal",
          "features", "constraints", "namespace", "imports", "sum(A.b)", "A.b", "X", "F1", "->", "&&",
          "== 3", "@", '"', "'", "A#b", "true", "group-cardinality"]


def _model(rng: random.Random) -> str:
    """A random, mostly well-formed UVL model."""
    out = []
    if rng.random() < 0.3:
        out.append("namespace N")
    if rng.random() < 0.1:
        out.append("include\n\tBoolean.*")
    out.append("features")
    tab = rng.choice(["\t", "    ", "  "])
    n = [0]
    names = []

    def feature(depth: int, budget: int) -> None:
        n[0] += 1
        name = rng.choice([f"F{n[0]}", f"F{n[0]}", f'"F {n[0]}"', f"Fä{n[0]}"])
        names.append(name)
        tail = rng.choice([""] * 8 + [" {abstract}", " {price 3, tag 'x'}", " cardinality [1..2]",
                                      " {constraint F1 => F2}"])
        head = rng.choice([""] * 12 + ["Integer ", "String "])
        out.append(tab * depth + head + name + tail)
        if budget <= 1 or depth > 8:
            return
        for _ in range(rng.choice([1, 1, 1, 2])):
            out.append(tab * (depth + 1) + rng.choice(_KWS))
            k = rng.randint(1, 4)
            for _ in range(k):
                feature(depth + 2, budget // (k + 1))

    feature(1, rng.randint(1, 60))
    if rng.random() < 0.7:
        out.append("constraints")
        for _ in range(rng.randint(0, 5)):
            a, b = rng.choice(names), rng.choice(names)
            out.append(tab + rng.choice([f"{a} => {b}", f"!{a} | {b}", f"({a} & {b}) <=> {a}", f"{a}.price > 2"]))
    text = "\n".join(out) + rng.choice(["\n", "", "\n\n"])
    if rng.random() < 0.15:
        text = text.replace("\n", rng.choice(["\r\n", "\r"]))
    return text


def _mutate(rng: random.Random, text: str) -> str:
    for _ in range(rng.choice([0, 1, 1, 2, 4])):
        i = rng.randrange(len(text) + 1)
        op = rng.randrange(5)
        if op == 0:
            text = text[:i] + text[i + rng.randrange(1, 8):]
        elif op == 1:
            text = text[:i] + rng.choice(_NOISE) + text[i:]
        elif op == 2:
            text = text[:i] + " " + rng.choice(_NOISE) + " " + text[i:]
        elif op == 3:
            lines = text.split("\n")
            j = rng.randrange(len(lines))
            lines[j] = rng.choice(["", " ", "\t", "   "]) + lines[j].lstrip(" \t")
            text = "\n".join(lines)
        else:
            lines = text.split("\n")
            lines.insert(rng.randrange(len(lines) + 1), rng.choice(lines))
            text = "\n".join(lines)
    return text


def _canon(root) -> str:
    """Everything reachable from ``root`` (objects numbered in first-visit order)."""
    ids: dict[int, int] = {}
    todo = []

    def ref(x):
        if x is None or isinstance(x, (bool, int, float, str, enum.Enum)):
            return repr(x)
        if isinstance(x, (list, tuple)):
            return "[" + ",".join(ref(y) for y in x) + "]"
        if isinstance(x, (set, frozenset)):
            return "{" + ",".join(sorted(ref(y) for y in x)) + "}"
        if isinstance(x, dict):
            return "{" + ",".join(ref(k) + ":" + ref(v) for k, v in x.items()) + "}"
        if type(x).__name__ in ("Span", "Pos"):
            return repr(x)
        if id(x) not in ids:
            ids[id(x)] = len(ids)
            todo.append(x)
        return f"#{ids[id(x)]}"

    ref(root)
    out = []
    while todo:
        x = todo.pop()
        attrs = dict(getattr(x, "__dict__", {}))
        for cls in type(x).__mro__:
            for s in getattr(cls, "__slots__", ()):
                if hasattr(x, s) and s != "built":
                    attrs[s] = getattr(x, s)
        out.append((ids[id(x)], type(x).__name__ + " " + " ".join(f"{a}={ref(attrs[a])}" for a in sorted(attrs))))
    return "\n".join(s for _, s in sorted(out))


def _both(text: str, monkeypatch) -> tuple[str, str]:
    fast = parse_uvl(text, "/m/model.uvl", read_file=lambda p: None)
    with monkeypatch.context() as mp:
        mp.setattr(uvl_build, "tokenize", functools.partial(tokenize, fast=False))
        mp.setattr(uvl_build, "fast_parse", lambda *a: None)
        slow = parse_uvl(text, "/m/model.uvl", read_file=lambda p: None)
    return (_canon((fast.model, fast.diagnostics)), _canon((slow.model, slow.diagnostics)))


def _lines(text: str, fast: bool):
    lines, errors = tokenize(text, fast=fast)
    return ([(ln.indent, ln.start, ln.alive, ln.keep, [(t.type, t.value, t.start, t.end) for t in ln.toks])
             for ln in lines], [(e.kind, e.start, e.end, e.text) for e in errors])


@pytest.mark.parametrize("seed", range(8))
def test_fast_and_general_paths_agree(seed, monkeypatch):
    rng = random.Random(seed)
    taken = []
    real = uvl_build.fast_parse

    def counted(*a):
        r = real(*a)
        taken.append(r is not None)
        return r

    monkeypatch.setattr(uvl_build, "fast_parse", counted)
    for _ in range(40):
        text = _model(rng)
        if rng.random() < 0.6:
            text = _mutate(rng, text)
        assert _lines(text, True) == _lines(text, False), text
        fast, slow = _both(text, monkeypatch)
        assert fast == slow, text
    assert sum(taken) > 8  # the fast path was taken, not only the general one


def test_fast_path_shapes(monkeypatch):
    """Hand-picked shapes at the edge of what the fast path takes."""
    texts = [
        "features\n\tR\n",
        "features\n\tR\n\t\toptional\n",                       # an empty group
        "features\n\tR\n\t\toptional\n\t\t\tA\n\t\tB\n",       # a feature where a group is expected
        "features\n\tR\n\t\toptional\n\t\t\tA\n\t  B\n",       # indentation between levels
        "features\n\tR\n\tS\n",                                 # two roots
        "features\n\tR\n\t\t\tA\n",                             # a feature without a group
        "features\n\tR\n\t\toptional\n\t\t\t\"A.b\"\n\t\t\tA.b\n",
        "features\n\tR\n\t\toptional\n\t\t\tA {abstract}\n\t\t\tB {x\n\t\t\tC\n",
        "features\n\tR\n\t\toptional\n\t\t\tA (\n\t\t\tB\n",
        "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tA\nconstraints\n\tA => B\n",
        "features\n\tR\n\t\toptional\n\t\t\tA\nfeatures\n\tS\n",
        "features\n\tR\nX\n",
        "namespace N\nfeatures\n\tR\n\t\t[1..2]\n\t\t\tA\n\t\t\tB\n\t\tmandatory\n\t\t\tC\nconstraints\n\t!A\n",
        "features x\n\tR\n",
        "features\n \tR\n\t\toptional\n\t\t\tA\n",
        "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\t\toptional\n\t\t\t\t\tB\n\t\t\tC\n",
        "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\t\toptional\n\t\t\t\t\tB\n\t\t\t\toptional\n",
        "features\r\n\tR\r\n\t\toptional\r\n\t\t\tA\r\n",
        "features\n\tR\n\t\toptional\n\t\t\ttrue\n",
        "features\n\tR\n\t\toptional\n\t\t\tor\n",
        "features\n\tR\n\t\toptional\n\t\t\tInteger A\n\t\t\tB cardinality [1..2]\n",
    ]
    for text in texts:
        assert _lines(text, True) == _lines(text, False), text
        fast, slow = _both(text, monkeypatch)
        assert fast == slow, text


def _expr(rng: random.Random, names: list[str], depth: int = 0) -> str:
    """A random constraint over ``names``: every operator of the grammar, parentheses, negations,
    dotted and quoted names, sometimes arithmetic (read by the driver, line by line)."""
    r = rng.random()
    if depth > 5 or r < 0.3:
        return rng.choice(names + ["R.F1", '"F 2"', "Fä3"])
    if r < 0.45:
        return "!" * rng.randint(1, 3) + _expr(rng, names, depth + 1)
    if r < 0.6:
        return "(" * (k := rng.randint(1, 3)) + _expr(rng, names, depth + 1) + ")" * k
    if r < 0.65:
        return rng.choice([f"{rng.choice(names)}.price > 2", f"sum(F1.price) < 10", "F1.w + 1 == 3 * 2",
                           f"{rng.choice(names)}.tag == 'x'"])
    op = rng.choice(["&", "|", "=>", "<=>"])
    return " ".join(_expr(rng, names, depth + 1) if i % 2 == 0 else op for i in range(2 * rng.randint(1, 4) - 1))


@pytest.mark.parametrize("seed", range(6))
def test_fast_constraints_agree_with_the_driver(seed, monkeypatch):
    """Constraints of every Boolean operator, nested, chained, negated, with dotted / quoted
    names and arithmetic lines among them: the fast path's model and diagnostics are the
    general path's, and so are the CNF and the count the analysis makes of them."""
    from tvl_lsp.analysis.encode import encode
    from tvl_lsp.analysis.engine import ModelAnalysis
    rng = random.Random(1000 + seed)
    taken = []
    real = uvl_build.fast_parse

    def counted(*a):
        r = real(*a)
        taken.append(r is not None and bool(r.constraints))
        return r

    monkeypatch.setattr(uvl_build, "fast_parse", counted)
    for k in range(25):
        names = [f"F{i}" for i in range(1, 9)] + ['"F 2"']
        tab = rng.choice(["\t", "  "])
        feats = ["features", f"{tab}R", f"{tab * 2}optional"] + [f"{tab * 3}{n}" for n in names[:-1]]
        feats += [f"{tab * 2}alternative", f"{tab * 3}\"F 2\"", f"{tab * 3}Fä3 {{price 3}}", f"{tab * 3}X"]
        cons = [tab + _expr(rng, names) for _ in range(rng.randint(1, 8))]
        text = "\n".join(feats + ["constraints"] + cons) + "\n"
        if k % 5 == 4:  # a broken one now and then: the general path reports it
            text = _mutate(rng, text)
        fast, slow = _both(text, monkeypatch)
        assert fast == slow, text
        if k % 5 == 0:
            a = parse_uvl(text, "/m/model.uvl", read_file=lambda p: None)
            with monkeypatch.context() as mp:
                mp.setattr(uvl_build, "fast_parse", lambda *a: None)
                b = parse_uvl(text, "/m/model.uvl", read_file=lambda p: None)
            ea, eb = encode(a.model), encode(b.model)
            assert (ea.nvars, ea.clauses()) == (eb.nvars, eb.clauses()), text
            if not a.errors:
                assert ModelAnalysis(a.model).count_result().value == ModelAnalysis(b.model).count_result().value
    assert sum(taken) >= 15


def test_fast_constraints_shapes(monkeypatch):
    base = "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tB\n\t\t\tC\nconstraints\n"
    for c in ["A", "!A", "!!(A)", "((A))", "A & B | C", "A | B & C", "A => B => C", "A <=> B <=> C",
              "A => B <=> C | !A & B", "R.A => B", "A.", "A &", "(A", "A)", "A B", "!", "()", "A.price > 3",
              "A => B\n\tB => C", "A\n\t\tB", "A\n B", "(" * 80 + "A" + ")" * 80, "!" * 80 + "A",
              " & ".join("ABC" * 50), "A\nfeatures\n\tS"]:
        text = base + "\t" + c + "\n"
        fast, slow = _both(text, monkeypatch)
        assert fast == slow, text
