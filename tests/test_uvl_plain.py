"""Plain UVL read for counting (:mod:`tvl_lsp.uvl.plain` + :mod:`tvl_lsp.analysis.plaincnf`)
gives the full path's CNF clause for clause, or declines.

Random models of the plain subset (every group kind, quoted names, attributes, constraints of
every Boolean operator, nested, chained, KConfig-style disjunctions of conjunctions) and the
same models broken: whenever the plain reader accepts a text, the full front end must find no
error in it and its encoding must be the same variables and the same clauses in the same order.
"""

from __future__ import annotations

import json
import random

import pytest

from tvl_lsp.analysis import encode as encode_mod
from tvl_lsp.analysis.encode import encode
from tvl_lsp.analysis.plaincnf import DISTRIBUTE_MAX, encode_plain
from tvl_lsp.uvl import parse_uvl
from tvl_lsp.uvl import plain as plain_mod
from tvl_lsp.uvl.plain import read_plain

_GROUPS = ["mandatory", "optional", "alternative", "or", "[1..2]", "[2]", "[0..*]", "[1..1]", "[2..3]", "[0]"]
_TAILS = [""] * 8 + [" {abstract}", " {abstract true}", " {abstract false}", " {desc 'x, y}'}",
                     ' {abstract true, note "a b"}', "{abstract}"]
_NOISE = ["optional", "or", "[1..3]", "[ 1..3]", "{abstract}", "{a 1, b 'x'}", "{flag}", "{abstract 'x'}", "=>",
          "<=>", "&", "|", "!", "(", ")", "{", "}", "[", "]", ",", ".", '"q x"', '"a.b"', "'s'", "3", "-2",
          "cardinality [1..2]", "Integer", "String", "constraint A", "\t", "    ", "é", "\u00a0", "\f", "//c",
          "/*", "\r\n", "\r", "\n", "features", "constraints", "namespace", "imports", "A.b", "X", "F1", "->",
          "&&", "== 3", "@", '"', "'", "true", "group-cardinality", "[3..1]", "\"\"", "R.F1"]


def _expr(rng: random.Random, names: list[str], depth: int = 0) -> str:
    r = rng.random()
    if depth > 5 or r < 0.3:
        return rng.choice(names)
    if r < 0.42:
        return "!" * rng.randint(1, 3) + _expr(rng, names, depth + 1)
    if r < 0.54:
        return "(" * (k := rng.randint(1, 2)) + _expr(rng, names, depth + 1) + ")" * k
    if r < 0.6:
        # a KConfig export's choice: long disjunctions of conjunctions (absorption, Tseitin)
        a = rng.choice(names)
        parts = [f"{a} & {rng.choice(names)}" for _ in range(rng.randint(2, 9))]
        return "(" + " | ".join(parts + [f"!{a}", f"!{rng.choice(names)}"]) + ")"
    op = rng.choice(["&", "|", "=>", "<=>"])
    return " ".join(_expr(rng, names, depth + 1) if i % 2 == 0 else op for i in range(2 * rng.randint(1, 4) - 1))


def _model(rng: random.Random) -> str:
    out = []
    if rng.random() < 0.3:
        out.append(rng.choice(["namespace N", 'namespace "n x"', "namespace root"]))
    out.append("features")
    tab = rng.choice(["\t", "    ", "  "])
    n = [0]
    names: list[str] = []

    def feature(depth: int, budget: int) -> None:
        n[0] += 1
        name = rng.choice([f"F{n[0]}", f"F{n[0]}", f'"F {n[0]}"', f"Fä{n[0]}", f"f_{n[0]}#", f'"F//{n[0]}"'])
        names.append(name)
        out.append(tab * depth + name + rng.choice(_TAILS))
        if budget <= 1 or depth > 8:
            return
        for _ in range(rng.choice([1, 1, 1, 2])):
            out.append(tab * (depth + 1) + rng.choice(_GROUPS))
            k = rng.randint(1, 4)
            for _ in range(k):
                feature(depth + 2, budget // (k + 1))

    feature(1, rng.randint(1, 60))
    if rng.random() < 0.8:
        out.append("constraints")
        for _ in range(rng.randint(0, 8)):
            out.append(tab + _expr(rng, names))
    text = "\n".join(out) + rng.choice(["\n", "", "\n\n"])
    if rng.random() < 0.15:
        text = text.replace("\n", rng.choice(["\r\n", "\r"]))
    return text


def _mutate(rng: random.Random, text: str) -> str:
    for _ in range(rng.choice([1, 1, 2, 3])):
        i = rng.randrange(len(text) + 1)
        op = rng.randrange(5)
        if op == 0:
            text = text[:i] + text[i + rng.randrange(1, 6):]
        elif op == 1:
            text = text[:i] + rng.choice(_NOISE) + text[i:]
        elif op == 2:
            text = text[:i] + " " + rng.choice(_NOISE) + " " + text[i:]
        elif op == 3:
            lines = text.split("\n")
            j = rng.randrange(len(lines))
            lines[j] = rng.choice(["", " ", "\t", "   ", "      "]) + lines[j].lstrip(" \t")
            text = "\n".join(lines)
        else:
            lines = text.split("\n")
            lines.insert(rng.randrange(len(lines) + 1), rng.choice(lines))
            text = "\n".join(lines)
    return text


def _check(text: str) -> bool:
    """When the plain reader accepts ``text``: the full path has no error and the same CNF.
    True when it accepted."""
    p = read_plain(text)
    if p is None:
        return False
    r = parse_uvl(text, "/m/model.uvl", read_file=lambda path: None)
    assert not r.errors, (text, [d.message for d in r.errors])
    enc = encode(r.model)
    assert not enc.diagnostics(), text
    assert p.names == [f.name for f in r.model.features], text
    c = encode_plain(p)
    assert (c.n_features, c.nvars) == (enc.n_features, enc.nvars), text
    assert c.clauses == enc.clauses(), text
    return True


@pytest.mark.parametrize("seed", range(8))
def test_plain_cnf_is_the_encodings(seed):
    rng = random.Random(7000 + seed)
    accepted = 0
    for _ in range(40):
        accepted += _check(_model(rng))
    # (most clean models are plain: the reader must not pass by declining them)
    assert accepted >= 25


@pytest.mark.parametrize("seed", range(6))
def test_broken_models_are_declined_or_equal(seed):
    rng = random.Random(9100 + seed)
    for _ in range(60):
        _check(_mutate(rng, _model(rng)))  # (most are declined; those accepted must be equal)


def test_big_groups_and_long_constraints():
    """An alternative of 150 children (a sequential counter, not pairwise), an or of 3 of 5,
    and constraints long enough for Tseitin variables: the same CNF."""
    kids = "\n".join(f"\t\t\tK{i}" for i in range(150))
    dis = " | ".join(f"K{i} & K{i + 1}" for i in range(0, 40, 2))
    text = (f"features\n\tR\n\t\talternative\n{kids}\n\t\t[3..4]\n\t\t\tA\n\t\t\tB\n\t\t\tC\n\t\t\tD\n\t\t\tE\n"
            f"constraints\n\t{dis}\n\t!({dis}) | A\n\t(A <=> B) <=> (C <=> (D | E))\n\t"
            + " & ".join(f"(K{i} => A | !B)" for i in range(30)) + "\n")
    assert _check(text)
    c = encode_plain(read_plain(text))
    assert c.nvars > 155  # counter and Tseitin variables were made


@pytest.mark.parametrize("text", [
    "features\n\tR // c\n",                                      # comments
    "imports\n\tX as Y\nfeatures\n\tR\n",
    "features\n\tInteger R\n",                                   # typed feature
    "features\n\tR cardinality [1..2]\n",
    "features\n\tR {price 3}\n",                                 # a number attribute
    "features\n\tR {flag}\n",                                    # a Boolean attribute other than abstract
    "features\n\tR {abstract 'x'}\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tA\n",          # two features of one name
    "features\n\tR\n\t\toptional\n\t\t\tA\n\tS\n",               # a second root
    "features\n\tR\n\t\toptional\n\t\t\tA\n\t\t  B\n",           # between two levels
    "features\n\tR\n\t\tA\n",                                    # no group keyword
    "features\n\tR\n\t\toptional\n",                             # an empty group
    "features\n\tR\n\t\t[3..1]\n\t\t\tA\n",                      # bounds the wrong way round
    "features\n\tR\n\t\t[ 1..2]\n\t\t\tA\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tR.A => A\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tB => A\n",   # unknown name
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA => true\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA == R\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t(A\n\t| R)\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA\n\t\t| R\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t" + "(" * 201 + "A" + ")" * 201 + "\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t" + " => ".join(["A"] * 202) + "\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA\u00a0=> R\n",
    "features\n\tR\nconstraints\n\tR\nfeatures\n\tS\n",
    "namespace\nfeatures\n\tR\n",
    "features\n\t\"a.b\"\n",
    "features\n\t\"a\" // c \"b\"\n",                        # a comment between quoted names
    "features\n\tR {d 'x \"y'} // \"z\"\n",
    "features\n\t\"a /* b\"\n\t\t/* \"\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA => R // \"A\"\n",
])
def test_declined(text):
    assert read_plain(text) is None


@pytest.mark.parametrize("text", [
    "features\n\tR\n",
    "namespace N\r\nfeatures\r\n  R {abstract}\r\n    alternative\r\n      \"A x\"\r\n      Bä\r\n"
    "constraints\r\n  \"A x\" => !Bä\r\n",
    "features\n    R\n        [2..*]\n            A {desc 'a, b'}\n            B\n            C\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t" + "(" * 60 + "A" + ")" * 60 + "\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t" + " & ".join(["A"] * 500) + "\n",
    "features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t" + " => ".join(["A"] * 150) + "\n",
    # "//" and "/*" inside quoted names and strings are no comments (uvl-models' Financial Services)
    "features\n\tR {d 'http://x /* y'}\n\t\toptional\n\t\t\t\"F_a//b\"\n\t\t\t\"c/*d\"\n"
    "constraints\n\t\"F_a//b\" => !\"c/*d\"\n\t(\"c/*d\")|R\n",
])
def test_accepted(text):
    assert _check(text)


def test_constants_follow_the_full_path():
    from tvl_lsp.uvl import lexer, parser
    assert plain_mod.KEYWORDS == set(lexer.KEYWORDS) | set(lexer.HYPHENATED)
    assert plain_mod.MAX_DEPTH == parser.MAX_DEPTH
    assert DISTRIBUTE_MAX == encode_mod.DISTRIBUTE_MAX


def test_count_command_plain_and_full_agree(tmp_path, monkeypatch, capsys):
    """``tvl-lsp count`` of a plain model reads it without the full front end, and prints what
    the full path prints: total, per feature, with decisions."""
    from tvl_lsp.cli.commands import count
    from tvl_lsp.uvl import build
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    path = tmp_path / "m.uvl"
    path.write_text("features\n\tR\n\t\tor\n\t\t\tA\n\t\t\tB\n\t\t\tC\n\t\toptional\n\t\t\tD\n"
                    "\t\t\t\talternative\n\t\t\t\t\tE\n\t\t\t\t\tF\nconstraints\n\tA => !B\n\tE | C\n")
    runs = {}
    real = build.UvlBuilder.__init__
    for plain in (True, False):
        for argv in (["--json"], ["--per-feature"], ["-i", "A", "-x", "F", "--json"]):
            if not plain:
                monkeypatch.setattr(plain_mod, "read_plain", lambda text: None)
            called = []

            def spy(self, *a, **k):
                called.append(1)
                return real(self, *a, **k)

            monkeypatch.setattr(build.UvlBuilder, "__init__", spy)
            assert count.main([str(path)] + argv) == 0
            out = capsys.readouterr().out
            if "--json" in argv:
                out = json.loads(out)
                out.pop("seconds")
            runs[(plain, tuple(argv))] = out
            assert bool(called) != plain  # the plain path never builds the full model
    for argv in (["--json"], ["--per-feature"], ["-i", "A", "-x", "F", "--json"]):
        assert runs[(True, tuple(argv))] == runs[(False, tuple(argv))]
    assert runs[(True, ("--json",))]["count"] == 11
