"""The graph of all products, projected on each product, is that product's graph.

For every product of the in-repo hinted workspace (tests/data/graph/ws: namespaces, private /
relative / global names, remaps at launch, group and node level under their own conditions, an
include with a namespace, services, parameters, a node name used by two node types, a node
without hints), the projection of the symbolic graph equals the graph built directly from the
concrete load of that product -- and, where Debian's roslaunch is installed, the graph the
real roslaunch + rosgraph.names give.  Then the thesis's three turtlerand configurations
(Figures 3, 5 and 7) as explicit cases.
"""

from __future__ import annotations

import pytest

from tvl_lsp.base import formula as fm
from tvl_lsp.graph import NoProducts, UnknownFeature, project

from graph_helpers import (GRAPH_WS, ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT, links_of, nodes_of, oracle,
                           resources_of, roslaunch_available, setup, turtlerand_ws)


@pytest.fixture(scope="module")
def robot():
    s = setup(ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT)
    yield s
    s.logic.close()


def test_robot_has_18_products(robot):
    assert len(robot.products()) == 18
    assert robot.project(count=True).products == 18


def test_every_product_projection_equals_its_direct_graph(robot):
    products = robot.products()
    for product in products:
        direct = robot.product_graph(product)
        proj = robot.project(product)
        label = sorted(k for k, v in product.items() if v)
        assert nodes_of(proj) == nodes_of(direct), label
        assert links_of(proj) == links_of(direct), label
        assert resources_of(proj) == resources_of(direct), label
        # a complete product: everything is certain
        for el in list(proj.nodes.values()) + list(proj.resources.values()) + list(proj.links.values()):
            assert el.condition is None, (label, el.id)
        # the ids are those of the graph of all products
        assert set(proj.nodes) <= set(robot.graph.nodes)
        assert set(proj.links) <= set(robot.graph.links)


@pytest.mark.skipif(not roslaunch_available(), reason="Debian's python3-roslaunch is not installed (apt-get install python3-roslaunch)")
def test_every_product_matches_real_roslaunch_and_rosgraph(robot):
    products = robot.products()
    jobs = [{"file": robot.launch, "args": {k: "true" if v else "false" for k, v in p.items()}}
            for p in products]
    results = oracle(GRAPH_WS / "src", robot.hints, jobs)
    assert len(results) == len(products)
    for product, res in zip(products, results):
        label = sorted(k for k, v in product.items() if v)
        assert res["ok"], (label, res)
        proj = robot.project(product)
        assert {tuple(n) for n in res["nodes"]} == nodes_of(proj), label
        assert {tuple(x) for x in res["links"]} == links_of(proj), label


def test_remaps_apply_under_their_own_conditions(robot):
    g = robot.project()
    links = {(g.nodes[ln.node].name, ln.kind, g.resources[ln.resource].name): ln for ln in g.links.values()}
    # node-level remap with if=: the omni driver listens on cmd_vel_omni only with navigation
    omni = "node:/base/driver#robot_drivers/omni_drive"
    assert str(g.links[f"subscribe:{omni}>topic:/base/cmd_vel_omni"].condition) == "Omni && Nav"
    assert str(g.links[f"subscribe:{omni}>topic:/base/cmd_vel"].condition) == "Omni && !Nav"
    diff = "node:/base/driver#robot_drivers/diff_drive"
    assert str(g.links[f"subscribe:{diff}>topic:/base/cmd_vel"].condition) == "Diff"
    # group-level remap: applies to the planner (in the group), not to the teleop (outside)
    assert links[("/planner", "publish", "/cmd_vel_safe")].condition is not None
    assert ("/teleop", "publish", "/cmd_vel_safe") not in links
    # launch-level remap, resolved in each node's namespace: /base/odom -> /robot/odom
    assert ("/base/driver", "publish", "/robot/odom") in links
    assert not any(r.name == "/base/odom" for r in g.resources.values())
    # remaps with if/unless on the same `from` (logger's image)
    assert str(links[("/diag/logger", "subscribe", "/sensors/camera/image_compressed")].condition) == "Compress"
    assert str(links[("/diag/logger", "subscribe", "/sensors/camera/image_raw")].condition) == "!Compress"
    # a group remap passes into an included file (the camera's info)
    assert ("/sensors/camera", "publish", "/camera_info") in links


def test_private_relative_and_global_names(robot):
    g = robot.project()
    names = {(g.nodes[ln.node].name, v.name, g.resources[ln.resource].name)
             for ln in g.links.values() for v in ln.via}
    assert ("/base/driver", "~status", "/base/driver/status") in names          # private
    assert ("/sensors/camera", "camera/image_raw", "/sensors/camera/image_raw") in names  # relative, in ns
    assert ("/planner", "/robot/odom", "/robot/odom") in names                 # global
    assert ("/teleop", "~cmd_vel", "/base/cmd_vel") in names                   # private, remapped
    assert ("/diag/logger", "~level", "/diag/logger/level") in names           # a private parameter
    assert ("/base/driver", "set_mode", "/base/set_mode") in names             # a service


def test_node_name_of_two_types_gets_two_ids(robot):
    ids = sorted(n.id for n in robot.graph.nodes.values() if n.name == "/base/driver")
    assert ids == ["node:/base/driver#robot_drivers/diff_drive", "node:/base/driver#robot_drivers/omni_drive"]


def test_unhinted_node_has_a_note_and_no_links(robot):
    mapper = robot.graph.nodes["node:/mapper"]
    assert not mapper.hinted and "no hints for nav/mapper" in mapper.note
    assert not [ln for ln in robot.graph.links.values() if ln.node == "node:/mapper"]
    assert any("nav/mapper" in n for n in robot.graph.notes)


def test_partial_projection_solid_conditional_gone(robot):
    g = robot.project({"Nav": True, "Omni": True}, count=True)
    assert g.products == 3  # camera: none, camera, camera+compress
    assert g.nodes["node:/planner"].condition is None
    assert "node:/teleop" not in g.nodes                   # Nav excludes Teleop: gone
    assert "node:/base/driver#robot_drivers/diff_drive" not in g.nodes
    cam = g.nodes["node:/sensors/camera"]
    assert str(cam.condition) == "Camera" and cam.count == 2
    assert g.nodes["node:/sensors/compressor"].count == 1
    ln = g.links["subscribe:node:/base/driver#robot_drivers/omni_drive>topic:/base/cmd_vel_omni"]
    assert ln.condition is None and ln.count == 3


def test_counts_of_all_products(robot):
    g = robot.project(count=True)
    assert g.nodes["node:/diag/logger"].condition is None and g.nodes["node:/diag/logger"].count == 18
    for n in g.nodes.values():
        expected = sum(1 for p in robot.products() if fm.evaluate(robot.graph.nodes[n.id].condition, p))
        assert n.count == expected, n.id


def test_bad_decisions(robot):
    with pytest.raises(UnknownFeature, match="did you mean `Camera`"):
        robot.project({"Camra": True})
    with pytest.raises(NoProducts) as e:
        robot.project({"Nav": True, "Teleop": True})
    assert set(e.value.conflict) == {"Nav", "Teleop"}


# ------------------------------------------------------------------ the thesis's figures

@pytest.fixture(scope="module")
def turtlerand(tmp_path_factory):
    ws = turtlerand_ws(tmp_path_factory.mktemp("turtlerand"))
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    s = setup(launch, launch.with_suffix(".tvl"), ws / "haros.yaml")
    yield s
    s.logic.close()


FIGURES = {
    # Figure 3: teleop only -- turtle_teleop_key -> /turtle1/cmd_vel -> turtlesim
    "figure 3 (teleop)": ({"Teleop": True, "Random": False}, {
        ("/Teleop", "publish", "/turtle1/cmd_vel", "geometry_msgs/Twist"),
        ("/Turtlesim", "subscribe", "/turtle1/cmd_vel", "geometry_msgs/Twist")}),
    # Figure 5: random only -- random_controller's cmd_vel remapped to /turtle1/cmd_vel
    "figure 5 (random)": ({"Teleop": False, "Random": True}, {
        ("/Random", "publish", "/turtle1/cmd_vel", "geometry_msgs/Twist"),
        ("/Turtlesim", "subscribe", "/turtle1/cmd_vel", "geometry_msgs/Twist")}),
    # Figure 7: both, through the multiplexer (high: teleop, low: random)
    "figure 7 (multiplexer)": ({"Teleop": True, "Random": True}, {
        ("/Teleop", "publish", "/cmd_vel_high", "geometry_msgs/Twist"),
        ("/Random", "publish", "/cmd_vel_low", "geometry_msgs/Twist"),
        ("/Multiplexer", "subscribe", "/cmd_vel_high", "geometry_msgs/Twist"),
        ("/Multiplexer", "subscribe", "/cmd_vel_low", "geometry_msgs/Twist"),
        ("/Multiplexer", "publish", "/turtle1/cmd_vel", "geometry_msgs/Twist"),
        ("/Turtlesim", "subscribe", "/turtle1/cmd_vel", "geometry_msgs/Twist")}),
}


@pytest.mark.parametrize("figure", sorted(FIGURES))
def test_thesis_figures(turtlerand, figure):
    decisions, expected = FIGURES[figure]
    g = turtlerand.project(decisions, count=True)
    assert g.products == 1
    assert links_of(g) == expected
    assert all(ln.condition is None for ln in g.links.values())
    assert {n.name for n in g.nodes.values()} == {x[0] for x in expected}
    # the same as loading that configuration directly
    product = next(p for p in turtlerand.products() if all(p[k] == v for k, v in decisions.items()))
    assert links_of(turtlerand.product_graph(product)) == expected


def test_turtlerand_all_products_annotated(turtlerand):
    g = turtlerand.project(count=True)
    assert g.products == 4
    got = {(g.nodes[ln.node].name, ln.kind, g.resources[ln.resource].name): (str(ln.condition)
                                                                             if ln.condition else None)
           for ln in g.links.values()}
    assert got == {
        ("/Turtlesim", "subscribe", "/turtle1/cmd_vel"): None,
        ("/Teleop", "publish", "/turtle1/cmd_vel"): "Teleop && !Multiplexer",
        ("/Random", "publish", "/turtle1/cmd_vel"): "Random && !Multiplexer",
        ("/Teleop", "publish", "/cmd_vel_high"): "Multiplexer",
        ("/Random", "publish", "/cmd_vel_low"): "Multiplexer",
        ("/Multiplexer", "subscribe", "/cmd_vel_high"): "Multiplexer",
        ("/Multiplexer", "subscribe", "/cmd_vel_low"): "Multiplexer",
        ("/Multiplexer", "publish", "/turtle1/cmd_vel"): "Multiplexer",
    }


def test_projection_is_independent_of_what_was_asked_before(robot):
    a = robot.project({"Camera": True})
    robot.project({"Nav": True})
    b = robot.project({"Camera": True})
    assert {k: str(v.condition) for k, v in a.links.items()} == {k: str(v.condition) for k, v in b.links.items()}


def test_projection_without_model():
    """An unpaired launch file: its free args are the products."""
    from tvl_lsp.graph import GraphLogic, build_graph, parse_hints
    from tvl_lsp.launch import analyse_launch
    text = """<launch>
  <arg name="fast"/>
  <node pkg="p" type="talker" name="talker">
    <remap from="chatter" to="fast_chatter" if="$(arg fast)"/>
  </node>
  <node pkg="p" type="listener" name="listener" unless="$(arg fast)"/>
</launch>"""
    hints = parse_hints("/x/haros.yaml", "nodes:\n  p/talker: {advertise: {chatter: std_msgs/String}}\n"
                                         "  p/listener: {subscribe: {chatter: std_msgs/String}}\n")
    a = analyse_launch(text, "/x/a.launch")
    assert a.free_args == ["fast"]
    g = build_graph(a, hints)
    with GraphLogic(None, a.free_args) as logic:
        p = project(g, logic, {}, count=True)
        assert p.products == 2
        assert {(ln.kind, p.resources[ln.resource].name, str(ln.condition)) for ln in p.links.values()} == {
            ("publish", "/fast_chatter", "fast"), ("publish", "/chatter", "!fast"),
            ("subscribe", "/chatter", "!fast")}
        q = project(g, logic, {"fast": False})
        assert {p.resources[ln.resource].name for ln in q.links.values()} == {"/chatter"}


def test_void_model_has_no_graph(tmp_path):
    from tvl_lsp.analysis.engine import ModelAnalysis
    from tvl_lsp.graph import GraphLogic, build_graph, graph_diagnostics
    from tvl_lsp.launch import analyse_launch
    from tvl_lsp.tvl import parse_model
    m = parse_model("root R { group allOf { A } A -> !A; }", "/x/m.tvl").model
    ma = ModelAnalysis(m)
    a = analyse_launch('<launch><arg name="R"/><arg name="A"/><node pkg="p" type="t" name="n" if="$(arg A)"/></launch>',
                       "/x/a.launch", features=["R", "A"])
    g = build_graph(a)
    with GraphLogic(ma.encoding, ["R", "A"], ma) as logic:
        with pytest.raises(NoProducts, match="void"):
            project(g, logic, {})
        assert graph_diagnostics(g, logic, a) == []
