"""The configurator's session logic (tvl_lsp/configurator), without any host."""

from __future__ import annotations

import itertools
import os
import shutil
from pathlib import Path

import pytest

from tvl_lsp.base import formula as fm
from tvl_lsp.configurator import Session, SessionError
from tvl_lsp.configurator.api import handle, write_files
from tvl_lsp.configurator.problems import parse_condition

from model_gen import generated_model

REPO = Path(__file__).resolve().parent.parent
TURTLE = REPO / "examples" / "ws" / "src" / "turtlerand" / "launch"
BOT_WS = REPO / "tests" / "data" / "configurator" / "ws"
BOT = BOT_WS / "src" / "bot" / "launch"


@pytest.fixture(scope="module")
def turtle():
    return Session.open(str(TURTLE / "generic.tvl"))


@pytest.fixture(scope="module")
def bot():
    return Session.open(str(BOT / "robot.launch"))


def test_open_from_model_or_launch(turtle):
    s = Session.open(str(TURTLE / "generic.launch"))
    assert s.model_path == turtle.model_path
    assert s.launch == str(TURTLE / "generic.launch")
    with pytest.raises(SessionError):
        Session.open(str(REPO / "README.md"))


def test_tree_is_the_thesis_diagram(turtle):
    t = turtle.tree()
    assert t["id"] == "Turtlerand" and t["group"]["text"] == "allOf"
    (sim,) = t["children"]
    assert sim["name"] == "Turtlesim" and sim["optional"] is False
    kids = {c["name"]: c for c in sim["children"]}
    assert set(kids) == {"Teleop", "Random", "Multiplexer"}
    assert all(c["optional"] for c in kids.values())
    assert kids["Random"]["children"][0]["name"] == "Vel"
    assert kids["Random"]["location"]["line"] == 13  # 0-based: "opt Random," in generic.tvl
    card = Session.open(str(BOT / "robot.tvl")).tree()
    base = next(c for c in card["children"] if c["name"] == "Base")
    assert base["group"]["kind"] == "oneOf" and base["group"]["lo"] == 1 and base["group"]["hi"] == 1


def test_include_random_propagates_and_counts(turtle):
    d, refusal = turtle.decide({}, "Random", True)
    assert refusal is None and d == {"Random": True}
    st = turtle.state(d)
    assert st["decisions"] == {"Random": True}
    assert st["implied"] == {"Turtlerand": True, "Turtlesim": True, "Vel": True}
    assert "Teleop" in st["open"] and not st["complete"]
    c0, c1 = turtle.counts({}, wait=120), turtle.counts(d, wait=120)
    assert (c0["total"], c0["remaining"], c1["remaining"]) == ("4", "4", "2")
    assert c1["complete"] and c1["features"] == {"Turtlerand": "2", "Turtlesim": "2", "Teleop": "1", "Random": "2",
                                                 "Multiplexer": "1", "Vel": "2"}
    # reset one feature
    d2, refusal = turtle.decide(d, "Random", None)
    assert d2 == {} and refusal is None


def test_conflicting_click_is_refused_with_the_minimal_reason(turtle):
    d, _ = turtle.decide({}, "Random", True)
    d2, refusal = turtle.decide(d, "Vel", False)
    assert d2 == d  # unchanged
    assert refusal.conflicts_with == {"Random": True}
    assert [b["label"] for b in refusal.because] == ["Vel is mandatory in Random"]
    assert "conflicts with your decision to include Random" in refusal.message
    # without any decision of the user: the model alone forbids it
    _, r = turtle.decide({}, "Turtlesim", False)
    assert r.conflicts_with == {} and "no product excludes it" in r.message
    assert {b["label"] for b in r.because} == {"Turtlerand is the root: it is always selected",
                                                "Turtlesim is mandatory in Turtlerand"}
    # only the decisions in the conflict are named, not the others
    d3 = {"Random": True, "Teleop": True}
    _, r = turtle.decide(d3, "Multiplexer", False)
    assert r.conflicts_with == {"Random": True, "Teleop": True}


def test_unknown_feature_and_bad_values(turtle):
    with pytest.raises(SessionError):
        turtle.decide({}, "Nope", True)
    with pytest.raises(SessionError):
        turtle.state({"Random": "yes"})
    with pytest.raises(SessionError):
        handle(turtle, "decide", {"feature": "Random", "value": 1}, {})
    with pytest.raises(SessionError):
        handle(turtle, "frobnicate", {}, {})


def test_graph_projection(turtle):
    ids = {e["id"] for e in turtle.graph_json({})["elements"]}
    assert {"node:/Turtlesim", "node:/Random", "node:/Teleop", "node:/Multiplexer", "param:/vel"} <= ids
    g = {e["id"]: e for e in turtle.graph_json({})["elements"]}
    assert g["node:/Turtlesim"]["condition"] is None          # in every product: solid from the start
    assert g["node:/Random"]["condition"] == "Random"
    assert g["node:/Random"]["location"]["line"] == 21
    before = turtle.state({})["graph"]
    assert before["node:/Random"] == "possible" and before["node:/Turtlesim"] == "certain"
    after = turtle.state({"Random": True})["graph"]
    assert after["node:/Random"] == "certain" and after["param:/vel"] == "certain"
    assert after["node:/Teleop"] == "possible"
    gone = turtle.state({"Random": False})["graph"]
    assert gone["node:/Random"] == "absent" and gone["param:/vel"] == "absent"


def test_every_product_projects_to_its_own_elements(turtle):
    """For each complete product every element is certain or absent (never conditional); with
    the interim graph: certain exactly when its condition holds."""
    conds = getattr(turtle.graph, "conditions", None)
    names = [n for n in turtle.names]
    for values in itertools.product([True, False], repeat=len(names)):
        d = dict(zip(names, values))
        try:
            st = turtle.state(d)
        except SessionError:
            continue  # not a product
        assert set(st["graph"].values()) <= {"certain", "absent"}, d
        for eid, cond in (conds or {}).items():
            assert st["graph"][eid] == ("certain" if fm.evaluate(cond, d) else "absent"), (d, eid)


def test_problems_filtered_by_decisions(bot):
    pj = bot.problems_json({})
    dup = [p for p in pj["problems"] if p["code"] == "duplicate-node"]
    assert len(dup) == 1 and dup[0]["condition"] == "Lidar && Camera"
    pid = dup[0]["id"]
    assert pj["status"][pid] == "possible"
    assert bot.state({"Camera": False})["problems"][pid] == "excluded"
    assert bot.state({"Camera": True, "Lidar": True})["problems"][pid] == "certain"
    assert bot.state({"Camera": True})["problems"][pid] == "possible"


def test_cardinality_counts_and_refusal(bot):
    assert bot.counts({}, wait=120)["remaining"] == "12"
    d, _ = bot.decide({}, "Sonar", True)
    st = bot.state(d)
    assert st["implied"]["Tracks"] is True and st["implied"]["Wheels"] is False
    assert bot.counts(d, wait=120)["remaining"] == "4"
    _, r = bot.decide(d, "Wheels", True)
    assert r.conflicts_with == {"Sonar": True}
    labels = " ".join(b["label"] for b in r.because)
    assert "Sonar -> Tracks" in labels


def test_generate_current_completions_and_pairwise(tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(BOT_WS, ws)
    s = Session.open(str(ws / "src" / "bot" / "launch" / "robot.tvl"))
    with pytest.raises(SessionError, match="not complete"):
        s.plan_generation({}, "current")
    d = {"Tracks": True, "Sensors": True, "Lidar": True, "Camera": False, "Sonar": False}
    files, out = s.plan_generation(d, "current")
    assert len(files) == 1 and out == str(ws / "src" / "bot" / "configs")
    assert '<arg name="Tracks" value="true"/>' in files[0].text
    assert '<include file="$(find bot)/launch/robot.launch">' in files[0].text
    written = write_files(s, [{"path": f.path, "text": f.text} for f in files])
    assert Path(written[0]).read_text() == files[0].text
    comp, _ = s.plan_generation({"Tracks": True}, "completions")
    assert len(comp) == 8
    sample, _ = s.plan_generation({}, "sample")
    prods = [f.product for f in sample]
    assert len(prods) < 12
    # every valid pair of literals over the features is covered by the sample
    allp = [p for p in s.analysis.enumerate(limit=None)]
    feats = s.names
    for a, b in itertools.combinations(feats, 2):
        for va, vb in itertools.product([True, False], repeat=2):
            if any(p[a] == va and p[b] == vb for p in allp):
                assert any(p.get(a) == va and p.get(b) == vb for p in prods), (a, va, b, vb)
    with pytest.raises(SessionError, match="outside the workspace"):
        s.plan_generation(d, "current", folder=str(tmp_path / "elsewhere"))
    with pytest.raises(SessionError, match="outside the workspace"):
        write_files(s, [{"path": str(tmp_path / "x.launch"), "text": "x"}])


def test_excerpt_only_of_own_files(turtle):
    x = turtle.excerpt(str(TURTLE / "generic.launch"), 21)
    assert x["lines"][x["line"] - x["start"]].strip().startswith('<node pkg="turtlerand" type="random_controller"')
    with pytest.raises(SessionError):
        turtle.excerpt(str(REPO / "pyproject.toml"), 0)
    with pytest.raises(SessionError):
        turtle.excerpt("/etc/passwd", 0)


def test_parse_condition_round_trips():
    for text in ["a", "!a", "a && b", "a || b && c", "(a || b) && !c", "!(a && b) || c", "true", "false"]:
        f = parse_condition(text)
        assert parse_condition(str(f)) == f
    assert parse_condition("(a || b) && !c") == fm.conj([fm.disj([fm.var("a"), fm.var("b")]), fm.neg(fm.var("c"))])


def test_api_model_state_counts(turtle):
    out, d = handle(turtle, "model", {}, {})
    assert out["tree"]["id"] == "Turtlerand" and out["state"]["decisions"] == {}
    out, d = handle(turtle, "decide", {"feature": "Random", "value": True}, d)
    assert out["ok"] and d == {"Random": True}
    out, d2 = handle(turtle, "decide", {"feature": "Vel", "value": False}, d)
    assert not out["ok"] and d2 == d and out["refused"]["conflictsWith"] == {"Random": True}
    out, _ = handle(turtle, "counts", {"features": ["Teleop"]}, d)
    assert out["remaining"] == "2" and out["features"] == {"Teleop": "1"}
    out, d = handle(turtle, "reset", {}, d)
    assert d == {} and out["state"]["decisions"] == {}


# ------------------------------------------------------------------ counts from the counting service

@pytest.fixture()
def d4_calls(tmp_path, monkeypatch):
    """Every compilation d4 does (in this process or in its child process), with an empty disk
    and memory cache; pyganak must not be asked."""
    from tvl_lsp.analysis.counting import d4, projected
    from tvl_lsp.analysis.counting import service as S
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    S.MEMORY.clear()
    S.forget_failures()
    calls: list[str] = []
    real_in, real_child = d4.compile_inprocess, d4.compile_cnf

    def inproc(*a, **k):
        calls.append("in-process")
        return real_in(*a, **k)

    def child(*a, **k):
        calls.append("child process")
        return real_child(*a, **k)

    def no_pyganak(*a, **k):
        raise AssertionError("the configurator counted with pyganak")

    monkeypatch.setattr(d4, "compile_inprocess", inproc)
    monkeypatch.setattr(d4, "compile_cnf", child)
    monkeypatch.setattr(projected, "count_cnf", no_pyganak)
    yield calls
    S.MEMORY.clear()
    S.forget_failures()


def test_counts_come_from_one_compilation_per_model_content(tmp_path, d4_calls):
    ws = tmp_path / "ws"
    shutil.copytree(BOT_WS, ws)
    s = Session.open(str(ws / "src" / "bot" / "launch" / "robot.tvl"))
    allp = list(s.analysis.enumerate(limit=None))
    decisions: dict = {}
    for feature, value in [("Sensors", True), ("Lidar", False), ("Tracks", True), ("Camera", True)]:
        decisions, refusal = s.decide(decisions, feature, value)
        assert refusal is None
        c = s.counts(decisions, wait=120)
        sel = [p for p in allp if all(p[k] == v for k, v in decisions.items())]
        assert c["engine"] == "d4" and not c["pending"] and c["complete"]
        assert c["remaining"] == str(len(sel)) and c["total"] == str(len(allp))
        assert c["features"] == {n: str(sum(1 for p in sel if p[n])) for n in s.names}
    assert d4_calls == ["in-process"]  # one compilation for every decision
    # a second session on the same text (another view, a host restart in the same process)
    s2 = Session.open(str(ws / "src" / "bot" / "launch" / "robot.tvl"))
    assert s2.counts({"Wheels": True}, wait=120)["remaining"] == str(sum(1 for p in allp if p["Wheels"]))
    assert d4_calls == ["in-process"]
    # a new text is a new model: compiled once more
    model = ws / "src" / "bot" / "launch" / "robot.tvl"
    model.write_text(model.read_text().replace("Sonar -> Tracks;", "Sonar -> Tracks;\n  Camera -> Lidar;"))
    s3 = Session.open(str(model))
    assert s3.counts({}, wait=120)["remaining"] == str(sum(1 for p in allp if not p["Camera"] or p["Lidar"]))
    assert d4_calls == ["in-process", "in-process"]


def test_counts_are_pending_while_the_model_compiles(tmp_path, d4_calls):
    ws = tmp_path / "ws" / "src" / "big" / "launch"
    ws.mkdir(parents=True)
    (ws / "big.tvl").write_text(generated_model(400))
    s = Session.open(str(ws / "big.tvl"), roots=[str(tmp_path / "ws")])
    assert s.analysis.encoding.nvars > 150  # compiled in d4's child process
    first, _ = handle(s, "counts", {"wait": 0}, {})
    assert first["pending"] and first["status"] == "compiling" and first["remaining"] is None
    assert first["features"] == {}
    import time
    deadline = time.monotonic() + 120
    c = first
    while c["pending"] and time.monotonic() < deadline:
        time.sleep(0.05)
        c, _ = handle(s, "counts", {"wait": 0}, {})
    assert not c["pending"] and c["engine"] == "d4" and c["complete"]
    assert d4_calls == ["child process"]
    total = int(c["remaining"])
    assert total == s.analysis.count()  # the same service: no second compilation
    # a decision is one pass over the circuit: no compilation, every feature counted
    f = next(n for n in s.names if n != "Root" and c["features"][n] not in ("0", c["remaining"]))
    d, refusal = s.decide({}, f, True)
    assert refusal is None
    c2, _ = handle(s, "counts", {"wait": 0}, d)
    assert not c2["pending"] and c2["remaining"] == c["features"][f] and len(c2["features"]) == len(s.names)
    assert c2["features"][f] == c2["remaining"]
    assert d4_calls == ["child process"]


def test_pairwise_sample_needs_no_compilation(tmp_path, d4_calls):
    ws = tmp_path / "ws"
    shutil.copytree(BOT_WS, ws)
    s = Session.open(str(ws / "src" / "bot" / "launch" / "robot.launch"))
    d = {"Sensors": True}
    prods = s.products(d, "sample")
    assert d4_calls == []  # the sampler asks a SAT solver: nothing compiled for it
    allp = [p for p in s.analysis.enumerate(limit=None) if p["Sensors"]]
    keys = {tuple(sorted(p.items())) for p in allp}
    assert prods and all(tuple(sorted(p.items())) in keys for p in prods)
    for a, b in itertools.combinations(s.names, 2):
        for va, vb in itertools.product([True, False], repeat=2):
            if any(p[a] == va and p[b] == vb for p in allp):
                assert any(p[a] == va and p[b] == vb for p in prods), (a, va, b, vb)
    with pytest.raises(SessionError, match="more than the limit"):
        s.products(d, "sample", limit=1)
