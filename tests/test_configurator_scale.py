"""The configurator at the size of real robots and models (issue 29), below the page: the kind of
a feature in words true to the model, implied states explained, decisions replaced and
completed, configurations saved and loaded (tvl-lsp JSON, FeatureIDE XML, uvls .uvl.json),
Generate's readable names and stated limit, the HAROS project rules evaluated on the graph of
every product, includes that are not followed drawn as placeholders, the launch file chosen when
no rule pairs one, and counts that give up after the compile budget."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

from tvl_lsp.configurator import Session, SessionError, api
from tvl_lsp.configurator import configs, decisions as dec, rules

REPO = Path(__file__).resolve().parent.parent
DATA = REPO / "tests" / "data" / "configurator" / "robot_ws"


@pytest.fixture()
def ws(tmp_path):
    d = tmp_path / "robot_ws"
    shutil.copytree(DATA, d)
    return d


@pytest.fixture()
def nav(ws):
    return Session(str(ws / "src" / "nav" / "launch" / "nav.tvl"))


def run(s, op, current=None, **params):
    """``api.handle`` with ``current`` decisions (``params``: the request's)."""
    return api.handle(s, op, params, current or {})


def nodes(tree):
    out = {tree["name"]: tree}
    for c in tree["children"]:
        out.update(nodes(c))
    return out


# ------------------------------------------------------------------ the tree

def test_kind_words_follow_the_model(ws, nav):
    t = nodes(nav.tree())
    assert t["Robot"]["kind"] == "root"
    assert t["Base"]["kind"] == "mandatory" and t["Base"]["kindText"].startswith("mandatory")
    assert t["Lidar"]["kind"] == "optional" and t["Lidar"]["optional"]
    # a oneOf child is neither mandatory nor optional: a member of its group
    assert t["Wheels"]["kind"] == "member"
    assert t["Wheels"]["kindText"] == "group member: oneOf, exactly one of 2"
    u = nodes(Session(str(ws / "src" / "uvlbot" / "model.uvl")).tree())
    assert u["Drive"]["kind"] == "mandatory" and u["Arm"]["kind"] == "optional"
    assert u["Legs"]["kindText"] == "group member: alternative, exactly one of 2"
    assert u["Sonar"]["kindText"] == "group member: or, at least one of 2"
    # a UVL feature with a mandatory and an optional group: each group named once
    assert u["Bot"]["group"]["text"] == "mandatory + optional"


# ------------------------------------------------------------------ decisions

def test_implied_states_are_explained(nav):
    x, _ = run(nav, "explain", {"Amcl": True}, feature="Lidar")
    assert x["implied"] and x["value"] is True and x["byDecisions"] == {"Amcl": True}
    assert x["text"] == "included because you included Amcl: constraint `Amcl -> Lidar;`"
    assert x["because"][0]["location"]["path"].endswith("nav.tvl")
    x, _ = run(nav, "explain", {}, feature="Base")
    assert x["implied"] and x["byDecisions"] == {} and x["text"].startswith("included in every product of the model: ")
    assert "Base is mandatory in Robot" in x["text"]
    x, _ = run(nav, "explain", {"Wheels": True}, feature="Tracks")
    assert x["value"] is False and x["text"].startswith("excluded because you included Wheels")
    x, _ = run(nav, "explain", {}, feature="Camera")
    assert not x["implied"] and x["text"].startswith("open")
    x, _ = run(nav, "explain", {"Camera": False}, feature="Camera")
    assert x["text"] == "excluded: your decision"


def test_set_replaces_the_decisions_and_stops_at_a_conflict(nav):
    out, d = run(nav, "set", {"Camera": True}, decisions={"Lidar": True, "Wheels": True})
    assert out["ok"] and d == {"Lidar": True, "Wheels": True}
    assert out["state"]["implied"]["Tracks"] is False
    # the third contradicts the first two: those are kept, the refusal says why
    out, d = run(nav, "set", {}, decisions={"Amcl": True, "Wheels": True, "Lidar": False})
    assert not out["ok"] and d == {"Amcl": True, "Wheels": True}
    assert out["refused"]["feature"] == "Lidar" and out["refused"]["conflictsWith"] == {"Amcl": True}
    with pytest.raises(SessionError):
        run(nav, "set", {}, decisions={"Nope": True})


def test_complete_decides_every_open_feature(nav):
    out, d = run(nav, "complete", {"Camera": True}, how="minimal")
    assert out["ok"] and out["state"]["complete"] and out["state"]["open"] == []
    assert d["Camera"] is True
    selected = {k for k, v in {**out["state"]["implied"], **d}.items() if v}
    # the smallest product with Camera: the root, the base and one drive, the camera
    assert selected in ({"Robot", "Base", "Wheels", "Camera"}, {"Robot", "Base", "Tracks", "Camera"})
    assert set(out["added"]) == {"Lidar", "Amcl", "Wheels", "Tracks"}
    seen = set()
    for seed in range(12):
        out, d = run(nav, "complete", {"Amcl": True}, how="random", seed=seed)
        assert out["state"]["complete"] and out["state"]["implied"]["Lidar"] is True   # implied, not decided
        seen.add(d["Wheels"])
    assert seen == {True, False}                                  # random, not always the same
    with pytest.raises(SessionError):
        run(nav, "complete", {}, how="largest")


# ------------------------------------------------------------------ configurations

@pytest.mark.parametrize("fmt", configs.FORMATS)
def test_a_saved_configuration_loads_back(nav, fmt):
    d = {"Amcl": True, "Tracks": True, "Camera": False}
    saved, _ = run(nav, "save", d, name="field test", format=fmt)
    assert saved["path"].endswith(configs.file_name("field test", fmt))
    assert Path(saved["path"]).parent == Path(nav.model_path).parent          # next to the model
    Path(saved["path"]).write_text(saved["text"])
    listed, _ = run(nav, "configs")
    assert [f["name"] for f in listed["files"]] == [Path(saved["path"]).name]
    out, got = run(nav, "load", {}, path=saved["path"])
    assert out["ok"] and out["loaded"]["format"] == fmt
    if fmt == "json":
        assert got == d
    else:  # FeatureIDE and uvls files say what every feature is: the decisions are yours again
        assert {k: v for k, v in got.items() if k in d} == d
        assert out["state"]["implied"].get("Lidar") is True or got.get("Lidar") is True


def test_save_never_overwrites_a_file_that_is_not_a_configuration(nav):
    urdf = Path(nav.model_path).parent / "robot.xml"
    urdf.write_text("<robot name='r'/>\n")
    with pytest.raises(SessionError, match="already exists and is not a configuration"):
        run(nav, "save", {"Amcl": True}, name="robot", format="featureide")
    assert urdf.read_text() == "<robot name='r'/>\n"
    saved, _ = run(nav, "save", {"Amcl": True}, name="again", format="json")
    Path(saved["path"]).write_text(saved["text"])
    saved, _ = run(nav, "save", {"Amcl": False}, name="again", format="json")   # a configuration: replaced
    assert '"Amcl": false' in saved["text"]


def test_featureide_formats(nav):
    known = nav.accepted_names()
    xml = ('<?xml version="1.0" encoding="UTF-8" standalone="no"?>\n<configuration>\n'
           '  <feature automatic="selected" manual="undefined" name="Robot"/>\n'
           '  <feature manual="selected" name="Amcl"/>\n'
           '  <feature manual="unselected" name="Camera"/>\n'
           '  <feature manual="selected" name="Gripper"/>\n</configuration>\n')
    got = configs.parse(xml, "x.xml", known)
    assert got.decisions == {"Amcl": True, "Camera": False} and got.unknown == ["Gripper"]
    # the older format: the selected features only
    old = '<configuration><feature name="Amcl"/><feature name="Wheels"/></configuration>'
    assert configs.parse(old, "y.xml", known).decisions == {"Amcl": True, "Wheels": True}
    # FeatureIDE's plain .config: one selected feature a line, the others excluded
    plain = configs.parse("Robot\nBase\nWheels\n", "z.config", known)
    assert plain.decisions["Wheels"] is True and plain.decisions["Camera"] is False
    with pytest.raises(configs.ConfigError, match="DOCTYPE"):
        configs.parse('<!DOCTYPE x [<!ENTITY a "b">]><configuration/>', "e.xml", known)
    with pytest.raises(configs.ConfigError):
        configs.parse("{not json", "c.config.json", known)
    uvl = configs.parse(json.dumps({"file": "nav.tvl", "config": {"Lidar": True, "rate": 3}}), "n.uvl.json", known)
    assert uvl.decisions == {"Lidar": True} and uvl.ignored == ["rate"]


def test_load_refuses_files_outside_the_workspace(nav, tmp_path):
    outside = tmp_path / "elsewhere.config.json"
    outside.write_text(json.dumps({"decisions": {"Amcl": True}}))
    with pytest.raises(SessionError, match="outside the workspace"):
        run(nav, "load", path=str(outside))
    out, d = run(nav, "load", text=json.dumps({"decisions": {"Amcl": True, "Drone": True}}), filename="mine.config.json")
    assert d == {"Amcl": True} and out["loaded"]["unknown"] == ["Drone"]


# ------------------------------------------------------------------ generate

def test_generate_names_files_readably_and_states_its_limit(nav):
    out, _ = run(nav, "generate", {"Amcl": True, "Tracks": True, "Camera": False}, mode="current")
    names = [Path(f["path"]).name for f in out["files"]]
    # the features not every product has, not a digest
    assert names == ["nav_tracks-lidar-amcl.launch"], names
    assert out["products"] == 1 and not out["cut"]
    nav.compile_status()
    nav.analysis.counter.wait(60)
    out, _ = run(nav, "generate", {}, mode="all", limit=3)
    assert out["cut"] and out["limit"] == 3 and out["products"] == 3 and out["available"] == 12
    names = [Path(f["path"]).name for f in out["files"]]
    assert len(set(names)) == 3 and not any(re.search(r"[0-9a-f]{8}", n) for n in names), names


def test_generate_long_names_use_your_decisions_and_a_number(tmp_path):
    pkg = tmp_path / "ws" / "src" / "big" / "launch"
    pkg.mkdir(parents=True)
    names = [f"Sensor_number_{i}" for i in range(12)]
    (pkg / "big.tvl").write_text("root Big {\n  group allOf {\n" + ",\n".join(f"    opt {n}" for n in names) + "\n  }\n}\n")
    (pkg / "big.launch").write_text("<launch>\n  <arg name=\"Big\"/>\n" + "".join(f'  <arg name="{n}"/>\n' for n in names)
                                    + "</launch>\n")
    s = Session(str(pkg / "big.tvl"))
    d = {n: True for n in names[:8]}
    out, _ = run(s, "generate", d, mode="completions", limit=4)
    got = [Path(f["path"]).name for f in out["files"]]
    assert all(len(n) < 90 for n in got) and len(set(got)) == 4, got
    assert all(n.startswith("big_sensor_number_0-sensor_number_1-sensor_number_2_") for n in got), got


def test_generate_without_a_launch_file_says_so(ws):
    s = Session(str(ws / "src" / "uvlbot" / "model.uvl"))
    with pytest.raises(SessionError, match="paired with no launch file"):
        run(s, "generate", mode="all")


# ------------------------------------------------------------------ graph and rules

def test_rules_are_evaluated_on_the_graph_of_every_product(nav):
    out, _ = run(nav, "problems")
    by = {p["message"].split(" -- ")[0]: p for p in out["problems"] if p["code"].startswith("haros-rule")}
    readers = by["rule Parameters readers: One or more parameters are being read."]
    assert readers["code"] == "haros-rule" and readers["condition"] == "Amcl"
    assert readers["location"]["path"].endswith("haros.yaml")
    assert readers["related"][0]["location"]["path"].endswith("nav.launch")
    assert by["rule Scan publishers"]["condition"] == "Lidar"
    skipped = by["rule First publisher"]
    assert skipped["code"] == "haros-rule-not-evaluated" and "n.publishers[0]" in skipped["message"]
    # filtered by the decisions like every problem
    st, _ = run(nav, "state", {"Amcl": False})
    assert st["problems"][readers["id"]] == "excluded"
    st, _ = run(nav, "state", {"Amcl": True})
    assert st["problems"][readers["id"]] == "certain"


def test_rule_queries_on_conditional_links():
    from tvl_lsp.base import formula as fm
    from tvl_lsp.graph.model import Graph, GraphNode, Link, Resource
    g = Graph("x.launch")
    g.nodes["node:/a"] = GraphNode("node:/a", "/a", "p", "t", "/", fm.var("A"))
    g.resources["param:/r"] = Resource("param:/r", "parameter", "/r", fm.TRUE)
    g.resources["param:/q"] = Resource("param:/q", "parameter", "/q", fm.TRUE)
    g.links["read:1"] = Link("read:1", "node:/a", "param:/r", "read", fm.var("B"))
    g.links["read:2"] = Link("read:2", "node:/a", "param:/q", "read", fm.var("C"))
    items = rules.items_of(g)

    def ask(where):
        r = rules.Rule("k", "k", "", f"for n in <configs/nodes> where {where} return n", "p.yaml", None)
        return [str(c) for _, c in rules.evaluate(r, items)]
    assert ask("len(n.reads) > 0") == ["A && (B || C)"]
    assert ask("len(n.reads) >= 2") == ["A && B && C"]
    assert ask("len(n.reads) == 0") == ["A && !(B || C)"]
    assert ask("n.name == '/a' and not n.reads") == ["A && !(B || C)"]
    assert ask("n.package == 'other'") == []
    with pytest.raises(rules.NotEvaluated, match="no such attribute"):
        ask("n.weight > 3")
    with pytest.raises(rules.NotEvaluated, match="the path"):
        rules.evaluate(rules.Rule("k", "k", "", "for n in <configs/launch> return n", "p", None), items)


def test_an_include_outside_the_workspace_is_a_placeholder(nav):
    g, _ = run(nav, "graph")
    inc = [e for e in g["elements"] if e["kind"] == "include"]
    assert len(inc) == 1
    assert inc[0]["condition"] == "Camera" and inc[0]["label"] == "camera_driver/camera.launch"
    assert "camera_driver is not in the workspace" in inc[0]["details"]["not followed"]
    st, _ = run(nav, "state", {"Camera": False})
    assert st["graph"][inc[0]["id"]] == "absent"
    st, _ = run(nav, "state", {"Camera": True})
    assert st["graph"][inc[0]["id"]] == "certain"
    assert "noTopics" not in g   # its nodes have hints: /scan is there


def test_a_graph_without_topics_says_what_would_add_them(ws):
    (ws / "haros.yaml").write_text("project: nav\npackages: [nav]\nconfigurations:\n"
                                   "  {lf: nav/launch/nav.launch, tvl: nav/launch/nav.tvl}\n")
    g, _ = run(Session(str(ws / "src" / "nav" / "launch" / "nav.tvl")), "graph")
    assert g["noTopics"]["types"] == ["nav/amcl_node", "nav/base_node", "nav/lidar_node", "nav/track_node"]
    assert g["noTopics"]["sourcesHere"] == ["nav"]


# ------------------------------------------------------------------ pairing (the HTTP host)

def test_the_launch_file_of_an_unpaired_model_is_chosen(ws):
    from tvl_lsp.ui.server import App
    app = App(str(ws))
    spare = str(ws / "src" / "nav" / "launch" / "spare.tvl")
    m = app.request("model", {"model": spare})
    assert m["launch"] is None
    cands = app.request("launches", {"model": spare})["candidates"]
    assert cands[0]["relative"] == "src/nav/launch/other.launch" and cands[0]["matches"] == 3
    with pytest.raises(SessionError):
        app.request("pair", {"model": spare, "launch": str(ws / "haros.yaml")})
    got = app.request("pair", {"model": spare, "launch": cands[0]["path"]})
    assert got["launch"] == cands[0]["path"]
    assert app.request("model", {"model": spare})["launch"] == cands[0]["path"]
    g = app.request("graph", {"model": spare})
    assert [e["id"] for e in g["elements"]] == ["node:/fast"]
    app.close()


def test_save_writes_next_to_the_model_through_the_host(ws):
    from tvl_lsp.ui.server import App
    app = App(str(ws))
    model = str(ws / "src" / "nav" / "launch" / "nav.tvl")
    app.request("decide", {"model": model, "feature": "Amcl", "value": True})
    out = app.request("save", {"model": model, "name": "demo", "format": "featureide"})
    assert out["written"] == [str(ws / "src" / "nav" / "launch" / "demo.xml")]
    text = Path(out["written"][0]).read_text()
    assert '<feature automatic="undefined" manual="selected" name="Amcl"/>' in text
    assert '<feature automatic="selected" manual="undefined" name="Lidar"/>' in text
    app.request("reset", {"model": model})
    out = app.request("load", {"model": model, "path": out["written"][0]})
    assert out["state"]["decisions"] == {"Amcl": True}
    # the written file can be shown on the page
    ex = app.request("excerpt", {"model": model, "path": str(ws / "src" / "nav" / "launch" / "demo.xml"),
                                 "line": 0, "context": 400})
    assert ex["lines"][1] == "<configuration>"
    app.close()


# ------------------------------------------------------------------ counts

def test_counts_give_up_after_the_compile_budget(tmp_path, fresh_cache):
    from model_gen import generated_model
    p = tmp_path / "big.tvl"
    p.write_text(generated_model(600))
    s = Session(str(p))
    s.compile_budget = 0.01          # d4 cannot even start in that time
    s.compile_status()
    s.analysis.counter.wait(30)
    c = s.counts({}, wait=0)
    assert c["status"] == "gave-up" and c["remaining"] is None and not c["pending"]
    assert "within its budget of 0.01 s" in c["message"]
    # the configurator goes on: decisions, propagation and explanations without counts
    out, d = run(s, "decide", feature="F1", value=True)
    assert out["ok"] and "counts" not in out


def test_decisions_carry_the_counts_when_the_model_is_compiled(nav):
    nav.compile_status()
    nav.analysis.counter.wait(60)
    out, _ = run(nav, "decide", feature="Amcl", value=True, counts=["Lidar", "Camera"])
    assert out["counts"]["remaining"] == "4" and out["counts"]["features"] == {"Lidar": "4", "Camera": "2"}
