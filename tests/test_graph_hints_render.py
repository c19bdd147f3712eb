"""HAROS node hints (the project file's `nodes:` and per-configuration `hints:`), and the graph's
outputs: JSON (stable ids, null conditions), DOT (rendered by Graphviz when installed) and
Mermaid."""

from __future__ import annotations

import json
import shutil
import subprocess

import pytest

from tvl_lsp.graph import parse_hints, to_dot, to_json, to_mermaid
from tvl_lsp.base.text import Pos, Span

from graph_helpers import ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT, setup

THESIS_STYLE = """project: SAFER
packages: ["turtlerand"]
configurations:
    {lf: turtlerand/launch/generic.launch, tvl: turtlerand/launch/generic.tvl}
nodes:
    turtlesim/turtlesim_node:
        subscribe:
            /turtle1/cmd_vel: geometry_msgs/Twist
    turtlesim/turtle_teleop_key:
        advertise:
            /turtle1/cmd_vel: geometry_msgs/Twist
rules:
    parameters_readers:
        name: Parameters readers
"""


def test_thesis_nodes_hints_with_spans():
    h = parse_hints("/p/haros.yaml", THESIS_STYLE)
    assert h.diagnostics == []
    assert sorted(h.by_type) == ["turtlesim/turtle_teleop_key", "turtlesim/turtlesim_node"]
    sim = h.by_type["turtlesim/turtlesim_node"]
    assert sim.span == Span(Pos(5, 4), Pos(5, 28))
    (e,) = sim.entries
    assert (e.kind, e.name, e.type) == ("subscribe", "/turtle1/cmd_vel", "geometry_msgs/Twist")
    assert e.span == Span(Pos(7, 12), Pos(7, 28))


def test_list_forms_services_and_params():
    h = parse_hints("/p/h.yaml", """nodes:
  a/b:
    advertise: [chatter]
    subscribe:
      - {name: in, type: std_msgs/String}
      - topic: other
        msg_type: std_msgs/Int32
    service: {set: std_srvs/SetBool}
    client: {/get: std_srvs/Trigger}
    readParam: {~rate: int}
    writeParam: {/state: str}
    rosname: b_node
""")
    assert h.diagnostics == []
    got = [(e.kind, e.name, e.type) for e in h.by_type["a/b"].entries]
    assert got == [("publish", "chatter", None), ("subscribe", "in", "std_msgs/String"),
                   ("subscribe", "other", "std_msgs/Int32"), ("service", "set", "std_srvs/SetBool"),
                   ("client", "/get", "std_srvs/Trigger"), ("read", "~rate", "int"), ("write", "/state", "str")]


def test_malformed_hints_get_diagnostics_not_exceptions():
    h = parse_hints("/p/h.yaml", """nodes:
  turtlesim:
    subscribe: {/x: t}
  a/b:
    advertize: {/x: std_msgs/String}
    subscribe: 3
    client: [{type: x}]
  c/d: [1, 2]
""")
    msgs = [(d.code, d.span.start.line, d.message) for d in h.diagnostics]
    assert all(c == "invalid-hint" for c, _, _ in msgs)
    assert any(line == 1 and "package/executable" in m for _, line, m in msgs)
    assert any(line == 4 and "did you mean `advertise`?" in m for _, line, m in msgs)
    assert any(line == 5 and "must map names to types" in m for _, line, m in msgs)
    assert any(line == 6 and "needs a `name`" in m for _, line, m in msgs)
    assert any(line == 7 and "expected a mapping" in m for _, line, m in msgs)
    assert "a/b" in h.by_type and "turtlesim" not in h.by_type


@pytest.mark.parametrize("text", ["", "nodes: [", "nodes:\n  - a\n", ": : :", "nodes: !!python/object:os.system x",
                                  "x" * 100 + "nodes"])
def test_bad_yaml_never_raises(text):
    h = parse_hints("/p/h.yaml", text)
    assert not h.by_type


def test_configuration_hints_by_node_name():
    h = parse_hints("/p/legacy.yaml", """configurations:
  teleop_key:
    launch: [turtlerand/launch/first.launch]
    hints:
      /turtle_teleop_key:
        advertise:
          /turtle1/cmd_vel: geometry_msgs/Twist
  other:
    launch: [turtlerand/launch/second.launch]
    hints:
      /turtlesim_node:
        subscribe:
          /turtle1/cmd_vel: geometry_msgs/Twist
""")
    assert h.diagnostics == []
    assert [x.key for x in h.for_node("turtlesim", "turtle_teleop_key", "/turtle_teleop_key")] == ["/turtle_teleop_key"]
    assert h.for_node("turtlesim", "turtlesim_node", "/turtlesim_node", configs=["teleop_key"]) == []
    assert len(h.for_node("turtlesim", "turtlesim_node", "/turtlesim_node", configs=["other"])) == 1


def test_merge_keeps_both_files_entries():
    a = parse_hints("/a.yaml", "nodes:\n  p/t: {advertise: {x: T}}\n")
    b = parse_hints("/b.yaml", "nodes:\n  p/t: {subscribe: {y: T}}\n  p/u: {}\n")
    m = a.merge(b)
    assert [(e.kind, e.name) for e in m.by_type["p/t"].entries] == [("publish", "x"), ("subscribe", "y")]
    assert set(m.by_type) == {"p/t", "p/u"} and m.sources == ["/a.yaml", "/b.yaml"]


# ------------------------------------------------------------------ outputs

@pytest.fixture(scope="module")
def robot():
    s = setup(ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT)
    yield s
    s.logic.close()


def test_json_schema_and_stable_ids(robot):
    full = to_json(robot.project(count=True))
    part = to_json(robot.project({"Nav": True, "Omni": True}, count=True))
    json.dumps(full)
    assert full["products"] == 18 and part["products"] == 3
    assert part["decisions"] == {"Nav": True, "Omni": True}
    for key in ("nodes", "topics", "services", "parameters", "links", "notes"):
        assert key in full
    n = next(x for x in full["nodes"] if x["name"] == "/planner")
    assert {"id", "name", "package", "type", "namespace", "condition", "hinted", "locations", "count"} <= set(n)
    assert n["condition"] == "Nav" and n["count"] == 6
    assert n["locations"][0]["file"] == str(ROBOT_LAUNCH) and n["locations"][0]["range"]["start"]["line"] == 34
    ln = next(x for x in full["links"] if x["node"] == "/planner" and x["kind"] == "publish")
    assert {"node", "topic", "kind", "condition", "id", "node_id", "resource_id", "type", "via"} <= set(ln)
    assert ln["topic"] == "/cmd_vel_safe" and ln["via"][0]["name"] == "cmd_vel"
    assert ln["via"][0]["remap"]["label"] == '<remap from="cmd_vel" to="/cmd_vel_safe">'
    # the same element has the same id in every projection
    ids_full = {x["id"] for k in ("nodes", "topics", "services", "parameters", "links") for x in full[k]}
    ids_part = {x["id"] for k in ("nodes", "topics", "services", "parameters", "links") for x in part[k]}
    assert ids_part <= ids_full
    pl = next(x for x in part["nodes"] if x["name"] == "/planner")
    assert pl["id"] == n["id"] and pl["condition"] is None
    svc = next(x for x in full["services"] if x["name"] == "/base/set_mode")
    assert svc["type"] == "std_srvs/SetBool"
    assert {x["kind"] for x in full["links"] if x["topic"] == "/base/set_mode"} == {"service", "client"}
    par = next(x for x in full["parameters"] if x["name"] == "/diag/logger/level")
    assert par["value"] == "debug" and par["condition"] is None


def test_dot_is_drawn_as_haros_draws(robot):
    dot = to_dot(robot.project())
    assert '"node:/planner" [shape=box, style="filled,dashed", fillcolor="#ffffff", label="/planner\\n[Nav]"' in dot
    assert '"node:/diag/logger" [shape=box, style="filled", fillcolor="#ffffff"' in dot
    assert 'fillcolor="#a3d977"' in dot and 'fillcolor="#8cb8f0"' in dot and 'fillcolor="#c9a3e6"' in dot
    assert '"node:/planner" -> "topic:/cmd_vel_safe" [style="dashed", label="Nav"' in dot


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed (apt-get install graphviz)")
@pytest.mark.parametrize("decisions", [{}, {"Nav": True}, {"Nav": False, "Camera": True, "Compress": True}])
def test_dot_renders_with_graphviz(robot, decisions):
    dot = to_dot(robot.project(decisions, count=True))
    r = subprocess.run(["dot", "-Tsvg"], input=dot, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.lstrip().startswith("<?xml") and "<svg" in r.stdout and not r.stderr.strip()


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed (apt-get install graphviz)")
def test_dot_escapes_awkward_names(tmp_path):
    from tvl_lsp.graph import GraphLogic, build_graph, project
    from tvl_lsp.launch import analyse_launch
    text = '<launch><arg name="a"/><node pkg="p" type="t" name="n" if="$(arg a)"/></launch>'
    a = analyse_launch(text, str(tmp_path / "x.launch"))
    h = parse_hints("/h.yaml", 'nodes:\n  p/t: {advertise: {"we\\"ird\\\\name": "x/Y"}}\n')
    with GraphLogic(None, a.free_args) as logic:
        dot = to_dot(project(build_graph(a, h), logic))
        mer = to_mermaid(project(build_graph(a, h), logic))
    r = subprocess.run(["dot", "-Tsvg"], input=dot, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert '#quot;' in mer and '"' not in mer.split('["', 1)[1].split('"]', 1)[0]


def test_mermaid(robot):
    m = to_mermaid(robot.project())
    lines = m.splitlines()
    assert lines[0] == "flowchart LR"
    assert any(x.strip().startswith("n") and '["/planner<br/><small>[Nav]</small>"]:::rosnode' in x for x in lines)
    assert any('-.->|"Nav"|' in x for x in lines)
    assert any(x.strip().startswith("class ") and x.strip().endswith(" conditional") for x in lines)
    full = to_mermaid(robot.project({"Nav": True, "Omni": True, "Camera": False}))
    assert "-.->" not in full  # one product: nothing conditional
