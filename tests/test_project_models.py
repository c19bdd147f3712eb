"""One parse and one encoding per model text in a process (tvl_lsp.project.models): the server's
check and its counts share them, an edited include is a new model."""

from __future__ import annotations

import time

import pytest

from tvl_lsp.analysis.counting import service as S
from tvl_lsp.lsp import checks
from tvl_lsp.project import facts, models

MAIN = """root Station {
  group allOf {
    Sensors group someOf { Wind, Rain, opt Sun },
    opt Display
  }
}
include(extra.tvl);
"""
EXTRA = """Station {
  Display -> Wind;
}
"""


@pytest.fixture()
def ws(tmp_path, monkeypatch):
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    models.clear()
    S.MEMORY.clear()
    S.forget_failures()
    (tmp_path / "station.tvl").write_text(MAIN)
    (tmp_path / "extra.tvl").write_text(EXTRA)
    yield tmp_path
    models.clear()
    S.MEMORY.clear()
    S.forget_failures()


def _parsed():
    return models.STATS["parsed"]


def test_same_text_same_analysis_and_includes_are_part_of_the_content(ws):
    path = str(ws / "station.tvl")
    files = {path: MAIN, str(ws / "extra.tvl"): EXTRA}
    n = _parsed()
    r1, a1 = models.load(path, MAIN, files.get)
    r2, a2 = models.load(path, MAIN, files.get)
    assert a1 is a2 and r1 is r2 and _parsed() == n + 1
    prods = list(a1.enumerate(limit=None))
    assert a1.count() == len(prods) and all(p["Wind"] for p in prods if p["Display"])
    # an edited include: parsed again, and the new constraint counts
    files[str(ws / "extra.tvl")] = "Station {\n  Display -> Wind;\n  Sun -> Rain;\n}\n"
    _, a3 = models.load(path, MAIN, files.get)
    assert a3 is not a1 and _parsed() == n + 2
    assert a3.count() != a1.count()
    assert a3.count() == sum(1 for p in a3.enumerate(limit=None)
                             if (not p["Display"] or p["Wind"]) and (not p["Sun"] or p["Rain"]))


def test_the_servers_check_and_counts_parse_the_model_once(ws, monkeypatch):
    """What the language server's check process does for an open model: the full check (which
    also starts d4 in the background), then the facts for hover and code lens, asked again
    until the compilation is done -- one parse, one encoding, one compilation."""
    import tvl_lsp.tvl as T
    calls = []
    real = T.parse_model

    def counting(text, p, *a, **k):
        calls.append(p)
        return real(text, p, *a, **k)
    monkeypatch.setattr(T, "parse_model", counting)
    path = str(ws / "station.tvl")
    texts = {path: MAIN}
    n = _parsed()
    diags = checks.full_check_worker("tvl", path, MAIN, texts, [str(ws)], 10.0, 1)
    assert not [d for d in diags if d.severity.name == "ERROR"]
    deadline = time.monotonic() + 60
    while True:
        f = facts.compute_model_facts(path, {path: MAIN, str(ws / "extra.tvl"): EXTRA}, 10.0, 0.2)
        if f.pending != "compiling" or time.monotonic() > deadline:
            break
    assert f.pending is None and f.error is None
    _, a = models.load(path, MAIN, {path: MAIN, str(ws / "extra.tvl"): EXTRA}.get)
    prods = list(a.enumerate(limit=None))
    assert f.total == len(prods)
    assert f.per_feature["Wind"] == sum(1 for p in prods if p["Wind"])
    assert f.per_feature["Display"] == sum(1 for p in prods if p["Display"])
    assert _parsed() == n + 1 and calls == [path]
    assert a.counter.ready()


def test_facts_of_a_model_d4_cannot_count_say_fallback(ws, monkeypatch):
    path = str(ws / "station.tvl")
    sources = {path: MAIN, str(ws / "extra.tvl"): EXTRA}
    _, a = models.load(path, MAIN, sources.get)
    monkeypatch.setattr(a.counter, "determined", False)
    assert facts.compute_model_facts(path, sources, 10.0, 0.2).pending == "fallback"
    f = facts.compute_model_facts(path, sources, 10.0)  # the count process's call: pyganak
    assert f.pending is None and f.total == a.count()


def test_decisions_on_features_the_model_lacks_are_named_not_a_solver_key_error(tmp_path):
    """Found by bench/bench_server_fuzz.py (a decision kept while the model was edited): the
    product look-ups name the unknown features (UnknownFeatures, a KeyError for the CLI)."""
    path = str(tmp_path / "m.tvl")
    sources = {path: "root A { group someOf { B, C } }\n"}
    for call in (lambda d: facts.generation_products(path, sources, d, "one", 5),
                 lambda d: facts.generation_products(path, sources, d, "sample", 5),
                 lambda d: facts.list_products(path, sources, d, 5, 5.0)):
        with pytest.raises(facts.UnknownFeatures) as ei:
            call({"B": True, "Gone": False, "Zed": True})
        assert ei.value.args[0] == "unknown feature(s): Gone, Zed"
        assert call({"B": True})  # known decisions still work
    assert facts.configure(path, sources, {"Gone": True}, 5.0)["error"] == "unknown feature(s): Gone"


def test_a_count_under_a_condition_naming_no_feature_of_the_model_is_none(tmp_path):
    """Found by bench/bench_server_fuzz.py: hovering a launch element whose condition names an
    arg the (edited) model has no feature for raised KeyError in the worker (a traceback in
    the server's log); it is not countable: None."""
    from tvl_lsp.base import formula as fm
    path = str(tmp_path / "m.tvl")
    sources = {path: "root A { group someOf { B, C } }\n"}
    assert facts.count_under(path, sources, fm.var("B"), 5.0) == 2
    assert facts.count_under(path, sources, fm.conj([fm.var("B"), fm.var("Gone")]), 5.0) is None
