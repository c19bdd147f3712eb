"""The TVL formatter: idempotent, meaning-preserving, None on syntax errors."""


import pytest

from conftest import corpus_option
from testenv import REPO
from tvl_lsp.tvl import parse_model
from tvl_lsp.tvl.format import format_tvl
from tvl_lsp.tvl import model as m

# every model of the repository (examples, test fixtures); with --corpus, the corpus's too
OWN = sorted(p for d in (REPO / "examples", REPO / "tests" / "data") for p in d.rglob("*.tvl"))


def pytest_generate_tests(metafunc):
    if "path" not in metafunc.fixturenames:
        return
    params = [pytest.param(p, id=str(p.relative_to(REPO))) for p in OWN]
    corpus = corpus_option(metafunc.config)
    if corpus is not None:
        params += [pytest.param(p, id="corpus:" + str(p.relative_to(corpus)), marks=pytest.mark.corpus)
                   for p in sorted(corpus.rglob("*.tvl"))]
    metafunc.parametrize("path", params)


def _expr_sig(e):
    if e is None:
        return None
    if isinstance(e, m.Binary):
        return (e.op, _expr_sig(e.left), _expr_sig(e.right))
    if isinstance(e, m.Unary):
        return (e.op, _expr_sig(e.operand))
    if isinstance(e, m.Ternary):
        return ("?:", _expr_sig(e.cond), _expr_sig(e.then), _expr_sig(e.other))
    if isinstance(e, m.Aggregate):
        return (e.func, e.over, e.attr, tuple(_expr_sig(a) for a in e.args))
    if isinstance(e, m.SetLit):
        return ("set", tuple(_expr_sig(a) for a in e.items))
    if isinstance(e, m.RangeLit):
        return ("range", _expr_sig(e.lo), _expr_sig(e.hi))
    if isinstance(e, m.Name):
        return ("name", tuple(e.parts))
    return (type(e).__name__, getattr(e, "value", None))


def signature(res):
    mdl = res.model
    feats = []
    for f in mdl.features:
        g = f.group
        feats.append((f.long_name, f.is_root,
                      (g.kind, g.lo, g.hi, tuple((c.feature.long_name, c.optional, c.shared) for c in g.children)) if g else None,
                      tuple((a.name, a.type, _expr_sig(a.value), _expr_sig(a.domain), _expr_sig(a.if_in_value),
                             _expr_sig(a.if_out_value)) for a in f.attributes),
                      tuple((c.kind, _expr_sig(c.expr)) for c in f.constraints),
                      tuple((d.key, d.value) for d in f.data)))
    return (tuple(feats), tuple((t.name, t.base, _expr_sig(t.domain)) for t in mdl.types),
            tuple((c.name, c.type, _expr_sig(c.value)) for c in mdl.constants),
            tuple(sorted((d.code, d.message) for d in res.diagnostics)))


def test_format_is_idempotent_and_meaning_preserving(path):
    text = path.read_text(encoding="utf-8", errors="replace")
    out = format_tvl(text)
    before = parse_model(text, str(path))
    if any(d.code == "syntax-error" for d in before.diagnostics):
        assert out is None
        return
    assert out is not None
    assert format_tvl(out) == out
    after = parse_model(out, str(path))
    assert signature(after) == signature(before)


def test_format_reindents_and_normalises_blanks():
    src = "root   A{\n\n\n\tgroup allOf {B,\n        C}\n   B   ->   C ;   // why\n/* keep\n   me */ }\n"
    out = format_tvl(src)
    assert out == "root A{\n\n  group allOf {B,\n    C}\n  B -> C ; // why\n  /* keep\n   me */ }\n"
    assert format_tvl(out) == out


def test_format_never_glues_tokens():
    # 'x - 1' must not become 'x -1' (a signed literal in TVL) and vice versa
    src = "root A { int x; x - 1 > 0; x == -1; }\n"
    assert format_tvl(src) == src


def test_format_returns_none_on_errors():
    assert format_tvl("root A { group allOf { B } ") is None
    assert format_tvl("root A { # }") is None
