"""The graph's variability-aware checks: one finding per problem, each with a witness product in
which the problem really shows (checked by loading that product directly), anchored on the
launch file's tags, with the hint entries as related locations."""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_lsp.base.diagnostics import CODES, Severity
from tvl_lsp.graph import GraphLogic, build_graph, graph_diagnostics, parse_hints
from tvl_lsp.launch import analyse_launch

from graph_helpers import ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT, links_of, setup, turtlerand_ws


@pytest.fixture(scope="module")
def robot():
    s = setup(ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT)
    s.diags = graph_diagnostics(s.graph, s.logic, s.analysis)
    yield s
    s.logic.close()


def _by(diags, code):
    return {d.data.get("topic") or d.data.get("from"): d for d in diags if d.code == code}


def test_codes_registered():
    for code, sev in (("topic-without-publisher", Severity.WARNING), ("topic-without-subscriber",
                      Severity.INFORMATION), ("topic-type-mismatch", Severity.WARNING),
                      ("remap-unused", Severity.WARNING), ("invalid-hint", Severity.WARNING)):
        assert CODES[code].severity == sev


def test_robot_findings(robot):
    got = sorted((d.code, d.data.get("topic") or d.data.get("from")) for d in robot.diags)
    assert got == [
        ("remap-unused", "/diag/imu"),
        ("topic-type-mismatch", "/sensors/camera/image_compressed"),
        ("topic-without-publisher", "/base/cmd_vel"),
        ("topic-without-publisher", "/camera_info"),
        ("topic-without-publisher", "/diag/logger/level_changes"),
        ("topic-without-publisher", "/sensors/camera/image_raw"),
        ("topic-without-subscriber", "/base/driver/status"),
        ("topic-without-subscriber", "/base/imu"),
    ]


def test_witnesses_really_show_the_problem(robot):
    for d in robot.diags:
        product = {k: v for k, v in d.witness.items() if k in robot.features}
        g = robot.product_graph(product)
        links = links_of(g)
        if d.code in ("topic-without-publisher", "topic-without-subscriber"):
            t = d.data["topic"]
            subs = {x for x in links if x[2] == t and x[1] == "subscribe"}
            pubs = {x for x in links if x[2] == t and x[1] == "publish"}
            if d.code == "topic-without-publisher":
                assert subs and not pubs, (d.message, product)
            else:
                assert pubs and not subs, (d.message, product)
        elif d.code == "topic-type-mismatch":
            types = {x[3] for x in links if x[2] == d.data["topic"]}
            assert len(types) >= 2, (d.message, product)
        elif d.code == "remap-unused":
            assert any(n.name == "/diag/logger" for n in g.nodes.values())
            assert not any(r.name == "/base/imu" for r in g.resources.values()
                           if any(ln.resource == r.id and g.nodes[ln.node].name == "/diag/logger"
                                  for ln in g.links.values()))


def test_witness_is_smallest_and_message_says_when(robot):
    d = _by(robot.diags, "topic-without-publisher")["/base/cmd_vel"]
    assert {k for k, v in d.witness.items() if v} == {"Robot", "Base", "Diff"}
    assert "when !Nav && !Teleop" in d.message or "when !Teleop && !Nav" in d.message
    assert "/teleop" in d.message and "/safety" in d.message  # publishers in other products
    d = _by(robot.diags, "topic-without-publisher")["/diag/logger/level_changes"]
    assert "(in every product)" in d.message


def test_locations_and_related(robot):
    launch = str(ROBOT_LAUNCH)
    text = ROBOT_LAUNCH.read_text().splitlines()
    d = _by(robot.diags, "topic-without-publisher")["/base/cmd_vel"]
    assert d.path == launch
    assert text[d.span.start.line][d.span.start.col:].startswith('<node pkg="robot_drivers" type="diff_drive"')
    rel = {(Path(r.path).name, r.message) for r in d.related}
    assert ("haros.yaml", "hint: robot_drivers/diff_drive subscribes to `cmd_vel` [geometry_msgs/Twist]") in rel
    assert any(m.startswith("/teleop: publishes /base/cmd_vel in other products") for _, m in rel)
    # a node of an included file: on the <include>, related to the <node> there
    d = _by(robot.diags, "topic-type-mismatch")["/sensors/camera/image_compressed"]
    assert d.path == launch
    assert text[d.span.start.line][d.span.start.col:].startswith("<include")
    assert any(Path(r.path).name == "camera.launch" and "<node" in r.message for r in d.related)
    assert "sensor_msgs/CompressedImage" in d.message and "sensor_msgs/Image" in d.message
    assert {k for k, v in d.witness.items() if v} == {"Robot", "Base", "Diff", "Camera", "Compress"}
    # remap-unused: on the <remap>, related: the node and its hints
    d = _by(robot.diags, "remap-unused")["/diag/imu"]
    assert text[d.span.start.line][d.span.start.col:].startswith('<remap from="imu" to="/base/imu"/>')
    assert any(r.message == "the names tools/logger uses" for r in d.related)


def test_one_finding_per_problem(robot):
    keys = [(d.code, d.data.get("topic") or d.data.get("from")) for d in robot.diags]
    assert len(keys) == len(set(keys))


def test_well_connected_product_line_has_no_finding(tmp_path):
    """turtlerand whose model requires a controller for the simulator: every product connected."""
    ws = turtlerand_ws(tmp_path)
    model = ws / "src" / "turtlerand" / "launch" / "generic.tvl"
    model.write_text(model.read_text().replace("!Multiplexer -> !(Teleop && Random);",
                                               "!Multiplexer -> !(Teleop && Random);\n  Turtlesim -> (Teleop || Random);"))
    s = setup(model.with_suffix(".launch"), model, ws / "haros.yaml")
    try:
        assert len(s.products()) == 3
        assert graph_diagnostics(s.graph, s.logic, s.analysis) == []
    finally:
        s.logic.close()


def test_turtlerand_simulator_alone_has_no_publisher(tmp_path):
    ws = turtlerand_ws(tmp_path)
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    s = setup(launch, launch.with_suffix(".tvl"), ws / "haros.yaml")
    try:
        diags = graph_diagnostics(s.graph, s.logic, s.analysis)
        assert [(d.code, d.data["topic"]) for d in diags] == [("topic-without-publisher", "/turtle1/cmd_vel")]
        d = diags[0]
        assert {k for k, v in d.witness.items() if v} == {"Turtlerand", "Turtlesim"}
        assert "when !Teleop && !Random" in d.message or "when !Random && !Teleop" in d.message
    finally:
        s.logic.close()


def _alone(text: str, hints_text: str, tmp_path: Path):
    path = tmp_path / "a.launch"
    path.write_text(text)
    a = analyse_launch(text, str(path))
    hints = parse_hints(str(tmp_path / "haros.yaml"), hints_text)
    g = build_graph(a, hints)
    logic = GraphLogic(None, a.free_args)
    try:
        return graph_diagnostics(g, logic, a)
    finally:
        logic.close()


def test_group_remap_unused_only_where_its_user_is_absent(tmp_path):
    text = """<launch>
  <arg name="nav"/>
  <group>
    <remap from="cmd_vel" to="/safe"/>
    <node pkg="p" type="planner" name="planner" if="$(arg nav)"/>
    <node pkg="p" type="logger" name="logger"/>
  </group>
</launch>"""
    hints = """nodes:
  p/planner: {advertise: {cmd_vel: geometry_msgs/Twist}}
  p/logger: {subscribe: {/safe: geometry_msgs/Twist}}
"""
    diags = [d for d in _alone(text, hints, tmp_path) if d.code == "remap-unused"]
    assert len(diags) == 1
    assert diags[0].witness == {"nav": False}
    assert "/logger uses `/safe`" in diags[0].message


def test_remap_on_unhinted_node_is_not_reported_and_unknown_nodes_are_named(tmp_path):
    text = """<launch>
  <node pkg="p" type="mystery" name="mystery"><remap from="a" to="b"/></node>
  <node pkg="p" type="listener" name="listener"/>
</launch>"""
    hints = "nodes:\n  p/listener: {subscribe: {chatter: std_msgs/String}}\n"
    diags = _alone(text, hints, tmp_path)
    assert [d.code for d in diags] == ["topic-without-publisher"]
    assert "unless a node without hints does: /mystery" in diags[0].message



def test_unhinted_nodes_of_other_products_of_the_finding_are_named(tmp_path):
    """The finding holds in products with and without the node that has no hints: its witness
    (the smallest product) has none, but the caveat names it: in the products where it runs the
    finding may not hold (the thesis's Random, remapped to the topic, in its generic.launch)."""
    text = """<launch>
  <arg name="rnd"/>
  <node pkg="p" type="listener" name="listener"/>
  <node pkg="p" type="mystery" name="mystery" if="$(arg rnd)"/>
</launch>"""
    hints = "nodes:\n  p/listener: {subscribe: {chatter: std_msgs/String}}\n"
    diags = _alone(text, hints, tmp_path)
    assert [d.code for d in diags] == ["topic-without-publisher"]
    assert diags[0].witness == {"rnd": False}
    assert "unless a node without hints does: /mystery" in diags[0].message

def test_no_hints_no_findings(tmp_path):
    assert _alone("<launch><node pkg='p' type='t' name='n'/></launch>", "project: x\n", tmp_path) == []
