"""Anomaly diagnostics on TVL text: codes, ranges, explanations."""

import pytest

from testenv import DATA, OVERLAY_WS
from tvl_lsp.base import formula as fm
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.tvl import parse_model

COFFEE = DATA / "models" / "coffee.tvl"
CRAWLER = OVERLAY_WS / "src" / "crawler" / "models" / "crawler.tvl"


def analysis(text):
    res = parse_model(text, "/tmp/a.tvl")
    assert not res.errors, [d.message for d in res.errors]
    return ModelAnalysis(res.model)


def by_code(diags, code):
    return [d for d in diags if d.code == code]


def line(text, d):
    return text.splitlines()[d.span.start.line]


def test_dead_decaf_explained():
    p = COFFEE
    text = p.read_text()
    a = ModelAnalysis(parse_model(text, str(p)).model)
    dead = by_code(a.anomalies(), "dead-feature")
    assert [d.data["feature"] for d in dead] == ["Decaf"]
    d = dead[0]
    assert text.splitlines()[d.span.start.line][d.span.start.col:d.span.end.col] == "Decaf"
    labels = [r.message for r in d.related]
    # Decaf is excluded by Conical || Flat, and Grinder (always there) has one of them
    assert any("Conical || Flat -> !Decaf" in m for m in labels)
    assert any("oneOf" in m for m in labels) and any("Grinder is mandatory" in m for m in labels)
    assert all(r.path == str(p) for r in d.related)
    # each related location points at what it names
    lines = text.splitlines()
    for r in d.related:
        if r.message.startswith("constraint"):
            assert lines[r.span.start.line].strip() == "Conical || Flat -> !Decaf;"


@pytest.mark.corpus
def test_listing_4_3_dead_J_explained(corpus_dir):
    p = corpus_dir / "thesis" / "models" / "example_4_3.tvl"
    text = p.read_text()
    a = ModelAnalysis(parse_model(text, str(p)).model)
    dead = by_code(a.anomalies(), "dead-feature")
    assert [d.data["feature"] for d in dead] == ["J"]
    d = dead[0]
    assert text.splitlines()[d.span.start.line][d.span.start.col:d.span.end.col] == "J"
    labels = [r.message for r in d.related]
    # J is excluded by C || D, and B (always there) has C or D
    assert any("C || D -> !J" in m for m in labels)
    assert any("oneOf" in m for m in labels) and any("B is mandatory" in m for m in labels)
    assert all(r.path == str(p) for r in d.related)


def test_false_optional_and_redundant_and_trivial():
    text = """root R {
  group allOf { opt A, opt B, opt C }
  R -> A;
  A -> B;
  R -> B;
  C || !C;
}"""
    a = analysis(text)
    diags = a.anomalies()
    fo = by_code(diags, "false-optional")
    assert sorted(d.data["feature"] for d in fo) == ["A", "B"]
    red = by_code(diags, "redundant-constraint")
    lines = sorted(line(text, d).strip() for d in red)
    # each of A -> B and R -> B is implied by the others (B always holds); C || !C always holds
    assert lines == ["A -> B;", "C || !C;", "R -> B;"]
    for d in red:
        if "always holds" not in d.message:
            assert d.related


def test_void_model_and_always_false_constraint():
    text = """root R {
  group oneOf { A, B }
  A && B;
}"""
    a = analysis(text)
    diags = a.anomalies()
    void = by_code(diags, "void-model")
    assert len(void) == 1 and a.is_void()
    assert {r.message.split(":")[0] for r in void[0].related} >= {"constraint `A && B;`"}
    af = by_code(diags, "always-false-constraint")
    assert len(af) == 1 and line(text, af[0]).strip() == "A && B;"
    assert not by_code(diags, "dead-feature")
    assert a.count() == 0
    assert a.find_product() is None
    assert list(a.enumerate()) == []


def test_explain_a_partial_configuration_and_formula():
    a = ModelAnalysis(parse_model(CRAWLER.read_text(), str(CRAWLER)).model)
    ex = a.explain(include=["Gamepad", "Joystick"])
    assert ex is not None and [e.kind for e in ex] == ["constraint"]
    assert a.explain(include=["Gamepad"]) is None
    ex = a.explain(formula=fm.conj([fm.var("Tracks"), fm.neg(fm.var("Base"))]))
    assert ex is not None and {e.kind for e in ex} <= {"parent-link", "root", "mandatory"}
    w = a.find_product(formula=fm.disj([fm.var("Bumpers"), fm.var("Phone")]))
    assert w["Phone"] and sum(w.values()) == 3  # Crawler, Teleop, Phone


def test_time_budget_zero_still_reports_anomalies_without_explanations():
    text = "root R { group allOf { opt A, opt B } A -> B; A -> !B; }"
    a = analysis(text)
    diags = a.anomalies(time_budget=0)
    dead = by_code(diags, "dead-feature")
    assert len(dead) == 1 and "time budget" in dead[0].message


def test_the_search_for_dead_features_stops_at_its_budget_and_says_so(monkeypatch):
    """Issue 12: a model whose backbone search outlasts the budget gets one anomaly-budget note
    and no unproved dead feature, instead of overrunning the budget."""
    from tvl_lsp.analysis import engine
    text = "root R { group allOf { opt A, opt B, opt C } A -> B; A -> !B; }"
    full = analysis(text).anomalies(time_budget=10)
    assert [d.code for d in full if d.code == "dead-feature"] == ["dead-feature"]
    monkeypatch.setattr(engine, "MIN_DETECTION", 0.0)
    cut = analysis(text).anomalies(time_budget=0)
    assert [d.code for d in cut] == ["anomaly-budget"]
    assert "none are reported" in cut[0].message and cut[0].severity.name == "INFORMATION"


def test_the_backbone_of_a_big_layered_model_takes_few_solver_calls():
    """Issue 12: the backbone search sets the phases of the auxiliary (counter) variables and of
    the features already known to be free, not only the candidates'.  Left at their saved
    phases they pulled the candidates back to their old values, one freed per solver call: 183
    calls on this 15,000-feature model (1,846 and 19 s on its 80,000-feature big brother)."""
    import sys
    from testenv import REPO
    sys.path.insert(0, str(REPO / "bench"))
    from bench_parse import generate
    from tvl_lsp.analysis import solve
    a = analysis(generate(20000))
    calls = []
    real = solve.backbone_of
    def counted(*args, **kw):
        if len(args) > 3 and args[3] is not None:
            rec = args[3]
            args = args[:3] + (lambda m: (calls.append(1), rec(m)),) + args[4:]
        return real(*args, **kw)
    import unittest.mock
    with unittest.mock.patch.object(solve, "backbone_of", counted):
        bb = a.analyzer.backbone()
    assert [a.encoding.feature_of_var[v].name for v, val in bb.items() if val] == ["Bench"]
    assert not [v for v, val in bb.items() if not val]
    assert len(calls) <= 30, len(calls)
