"""The graph from the sources (issue #26): the fixture robot (tests/data/sources/ws, robot_bringup:
a generic launch file over the fixture packages, a namespace, remaps, a hinted run-time value)
-- names resolved as ROS does for each launched node and product (checked against the
concrete load and, where Debian's roslaunch is installed, against the real rosgraph.names),
hints merged with what the sources say, dynamic names, and the graph checks firing with a
witness product and a link to the source line."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from tvl_lsp.graph import build_product_graph
from tvl_lsp.graph.hints import ProjectHints
from tvl_lsp.launch import load_launch
from tvl_lsp.main import main
from tvl_lsp.project.graph import load_graph

from graph_helpers import links_of, nodes_of, oracle, resources_of, roslaunch_available

WS = Path(__file__).parent / "data" / "sources" / "ws"
LAUNCH = WS / "src" / "robot_bringup" / "launch" / "robot.launch"
ALL = {"Robot": True, "Talker": True, "Listener": True, "Legacy": True}


@pytest.fixture(scope="module")
def ctx():
    c = load_graph(str(LAUNCH))
    yield c
    c.close()


def _product(**on) -> dict:
    return {k: on.get(k, k == "Robot") for k in ALL}


def test_extracted_links_resolved_in_the_nodes_namespace(ctx):
    g = ctx.project(ALL)
    got = links_of(g)
    for link in [("/robot/talker", "publish", "/robot/chatter", "std_msgs/String"),       # relative
                 ("/robot/talker", "publish", "/diagnostics_agg", "std_msgs/String"),     # global
                 ("/robot/talker", "publish", "/robot/talker/robot/count", "std_msgs/Int32"),  # private
                 ("/robot/talker", "publish", "/robot/arm/joint", "std_msgs/Int32"),      # child handle
                 ("/robot/talker", "publish", "/robot/speech", "std_msgs/String"),        # values: out: speech
                 ("/robot/talker", "read", "/robot/talker/rate", "int"),
                 ("/robot/listener", "subscribe", "/base_scan", "sensor_msgs/LaserScan"),  # <remap from="scan">
                 ("/robot/listener", "subscribe", "/robot/chatter", "std_msgs/String"),
                 ("/robot/legacy", "subscribe", "/robot/chatter", "std_msgs/String"),
                 ("/robot/legacy", "publish", "/robot/chatter", "std_msgs/String")]:     # the hint adds it
        assert link in got, link
    assert not any(r.dynamic for r in g.resources.values())
    n = g.nodes["node:/robot/talker"]
    assert n.extracted and not n.hinted
    ln = g.links["publish:node:/robot/talker>topic:/robot/chatter"]
    src = [v.source for v in ln.via if v.source is not None][0]
    assert src.path.endswith("talker.cpp") and src.span.start.line == 13   # line 14, 0-based


def test_every_product_projection_equals_its_concrete_load(ctx):
    sources = ctx.extraction.by_node_type()
    for t in (False, True):
        for li in (False, True):
            for le in (False, True):
                product = _product(Talker=t, Listener=li, Legacy=le)
                res = load_launch(str(LAUNCH), {k: "true" if v else "false" for k, v in product.items()})
                assert res.error is None
                direct = build_product_graph(res, ctx.hints, str(LAUNCH), sources=sources)
                proj = ctx.project(product)
                assert nodes_of(proj) == nodes_of(direct), product
                assert links_of(proj) == links_of(direct), product
                assert resources_of(proj) == resources_of(direct), product


@pytest.mark.skipif(not roslaunch_available(),
                    reason="Debian's python3-roslaunch is not installed (apt-get install python3-roslaunch)")
def test_names_resolve_as_the_real_rosgraph_does(ctx):
    """The extracted names (as hints for the oracle) resolved by roslaunch + rosgraph.names."""
    from tvl_lsp.graph.hints import HintEntry, NodeHints
    from tvl_lsp.graph.sources import LINK_OF_KIND
    from tvl_lsp.base.text import Pos, Span
    values = {k: h.values for k, h in ctx.hints.by_type.items()}
    as_hints = ProjectHints()
    for key, exe in ctx.extraction.by_node_type().items():
        nh = NodeHints(key, "", Span(Pos(0, 0), Pos(0, 0)))
        for e in exe.endpoints:
            kind = LINK_OF_KIND.get(e.kind)
            name = e.name
            for k, v in values.get(key, {}).items():
                name = name.replace("{" + k + "}", v)
            if kind is None or "{" in name:
                continue
            nh.entries.append(HintEntry(kind, name, e.type, "", nh.span))
        for h in ctx.hints.by_type.get(key, NodeHints(key, "", nh.span)).entries:
            nh.entries.append(h)
        as_hints.by_type[key] = nh
    products = [_product(Talker=t, Listener=li, Legacy=le) for t in (False, True) for li in (False, True)
                for le in (False, True)]
    jobs = [{"file": str(LAUNCH), "args": {k: "true" if v else "false" for k, v in p.items()}} for p in products]
    results = oracle(WS / "src", as_hints, jobs)
    for product, res in zip(products, results):
        assert res["ok"], res
        proj = ctx.project(product)
        assert {tuple(x) for x in res["links"]} == links_of(proj), product


def test_checks_fire_with_a_witness_and_the_source_line(ctx):
    diags = ctx.diagnostics()
    by = {(d.code, d.data.get("topic") or d.data.get("from")): d for d in diags}
    d = by[("topic-without-publisher", "/robot/chatter")]
    assert d.witness == _product(Listener=True)
    assert Path(d.path) == LAUNCH and d.span.start.line == 8      # the listener's <node>
    rel = [r for r in d.related if r.path.endswith("listener.cpp")]
    assert rel and rel[0].span.start.line == 33 and "subscribes to `chatter`" in rel[0].message
    d = by[("topic-type-mismatch", "/robot/status")]
    assert d.witness == _product(Talker=True, Legacy=True)
    files = {Path(r.path).name: r.span.start.line + 1 for r in d.related}
    assert files.get("talker.cpp") == 15 and files.get("legacy.py") == 12
    d = by[("remap-unused", "/robot/laser")]
    assert d.witness == _product(Listener=True) and "/front_laser" in d.message
    assert ("remap-unused", "/robot/scan") not in by                        # the sources use scan
    assert ("topic-without-publisher", "/base_scan") in by
    assert not any("{out}" in x.message or "{real_name}" in x.message for x in diags)


def _copy(tmp_path) -> Path:
    ws = tmp_path / "ws"
    shutil.copytree(WS, ws)
    return ws


def test_a_hint_overrides_its_node_and_leaves_the_others_extracted(tmp_path):
    ws = _copy(tmp_path)
    (ws / "haros.yaml").write_text(
        "configurations:\n  {lf: robot_bringup/launch/robot.launch, tvl: robot_bringup/launch/robot.tvl}\n"
        "nodes:\n  ros1_cpp/listener:\n    subscribe:\n      scan: sensor_msgs/PointCloud2\n"
        "      /extra: std_msgs/Empty\n")
    with load_graph(str(ws / "src" / "robot_bringup" / "launch" / "robot.launch")) as c:
        got = links_of(c.project(ALL))
    assert ("/robot/listener", "subscribe", "/base_scan", "sensor_msgs/PointCloud2") in got
    assert ("/robot/listener", "subscribe", "/base_scan", "sensor_msgs/LaserScan") not in got
    assert ("/robot/listener", "subscribe", "/extra", "std_msgs/Empty") in got
    assert ("/robot/listener", "subscribe", "/robot/odom", "nav_msgs/Odometry") in got    # still extracted
    assert ("/robot/talker", "publish", "/robot/chatter", "std_msgs/String") in got       # other nodes too
    # without values, the run-time name stays dynamic: shown as such, no finding about it
    with load_graph(str(ws / "src" / "robot_bringup" / "launch" / "robot.launch")) as c:
        g = c.project(ALL)
        dyn = [r for r in g.resources.values() if r.dynamic]
        assert [r.name for r in dyn] == ["/robot/{out}"]
        assert not any("{out}" in d.message for d in c.diagnostics())


def test_graph_command_with_no_project_file(tmp_path, capsys):
    ws = _copy(tmp_path)
    (ws / "haros.yaml").unlink()
    code = main(["graph", str(ws / "src" / "robot_bringup" / "launch" / "robot.launch"), "-i", "Talker",
                 "-i", "Listener", "-x", "Legacy", "--no-params"])
    out, err = capsys.readouterr()
    assert code == 0, err
    doc = json.loads(out)
    assert doc["hints"] == []
    links = {(x["node"], x["kind"], x["topic"]) for x in doc["links"]}
    assert ("/robot/talker", "publish", "/robot/chatter") in links
    assert ("/robot/talker", "publish", "/robot/{out}") in links
    assert next(t for t in doc["topics"] if t["name"] == "/robot/{out}")["dynamic"] is True
    talker = next(n for n in doc["nodes"] if n["name"] == "/robot/talker")
    assert talker["extracted"] and "note" not in talker
    via = next(x for x in doc["links"] if x["topic"] == "/robot/chatter" and x["kind"] == "publish")["via"][0]
    assert via["source"]["file"].endswith("talker.cpp") and via["source"]["range"]["start"]["line"] == 13
    # the thesis's figures: rqt_graph's view (no leaf topics, no services)
    code = main(["graph", str(ws / "src" / "robot_bringup" / "launch" / "robot.launch"), "-i", "Talker",
                 "-i", "Listener", "-x", "Legacy", "--no-leaf-topics", "--no-services", "--format", "mermaid",
                 "--no-params"])
    out, _ = capsys.readouterr()
    assert code == 0 and "/robot/chatter" in out and "/diagnostics_agg" not in out and "/base_scan" not in out
    code = main(["graph", str(ws / "src" / "robot_bringup" / "launch" / "robot.launch"), "--no-sources"])
    doc = json.loads(capsys.readouterr()[0])
    assert code == 0 and doc["links"] == []


def test_the_thesis_figures_from_the_examples_sources(capsys):
    """examples/ws: random_controller and multiplexer read from their sources (thesis Listings 2.4
    and 2.7), turtlesim's two nodes hinted (their sources are not in the repository); the graphs
    of the three configurations of chapter 2, drawn as rqt_graph draws them, are Figures 3, 5, 7."""
    launch = Path(__file__).parents[1] / "examples" / "ws" / "src" / "turtlerand" / "launch" / "generic.launch"
    twist = "geometry_msgs/Twist"
    figures = {
        ("Teleop",): {("/Teleop", "publish", "/turtle1/cmd_vel", twist),
                      ("/Turtlesim", "subscribe", "/turtle1/cmd_vel", twist)},                      # Figure 3
        ("Random",): {("/Random", "publish", "/turtle1/cmd_vel", twist),
                      ("/Turtlesim", "subscribe", "/turtle1/cmd_vel", twist)},                      # Figure 5
        ("Teleop", "Random", "Multiplexer"): {
            ("/Teleop", "publish", "/cmd_vel_high", twist), ("/Random", "publish", "/cmd_vel_low", twist),
            ("/Multiplexer", "subscribe", "/cmd_vel_high", twist),
            ("/Multiplexer", "subscribe", "/cmd_vel_low", twist),
            ("/Multiplexer", "publish", "/turtle1/cmd_vel", twist),
            ("/Turtlesim", "subscribe", "/turtle1/cmd_vel", twist)},                                # Figure 7
    }
    for on, links in figures.items():
        argv = ["graph", str(launch), "--no-leaf-topics", "--no-services", "--no-params"]
        for f in ("Teleop", "Random", "Multiplexer"):
            argv += ["-i" if f in on else "-x", f]
        code = main(argv)
        out, err = capsys.readouterr()
        assert code == 0, err
        doc = json.loads(out)
        assert {(x["node"], x["kind"], x["topic"], x["type"]) for x in doc["links"]} == links, on
        assert {t["name"]: t["type"] for t in doc["topics"]} == {x[2]: twist for x in links}
    # the parameter Random reads is the launch file's <param name="vel">
    code = main(["graph", str(launch), "-i", "Random"])
    doc = json.loads(capsys.readouterr()[0])
    vel = next(p for p in doc["parameters"] if p["name"] == "/vel")
    assert vel["value"] == "0.5" and vel["type"] == "double"
    assert any(x["node"] == "/Random" and x["kind"] == "read" and x["topic"] == "/vel" for x in doc["links"])
