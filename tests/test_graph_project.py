"""The project layer's graph entries: load_graph from a workspace (pairing, hints of the project
files naming the launch file, unsaved texts), the server's command JSON and node hover data,
and the cache that notices edited files."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tvl_lsp.project.graph import GraphError, cached_graph, graph_document, load_graph, node_info

from graph_helpers import GRAPH_WS, ROBOT_LAUNCH


def _node_start(launch: Path, needle: str):
    from tvl_lsp.base.text import Pos
    for i, line in enumerate(launch.read_text().splitlines()):
        if needle in line:
            return Pos(i, line.index("<node"))
    raise AssertionError(needle)


def test_load_graph_pairs_and_reads_hints():
    with load_graph(str(ROBOT_LAUNCH)) as ctx:
        assert ctx.model_path.endswith("robot.tvl")
        assert [Path(p).name for p in ctx.hints.sources] == ["haros.yaml"]
        assert ctx.configs == []  # the HAROS-TVL configuration has no name
        assert len(ctx.graph.nodes) == 9


def test_unsaved_texts_are_used(tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(GRAPH_WS, ws)
    launch = ws / "src" / "robot" / "launch" / "robot.launch"
    text = launch.read_text().replace('name="planner"', 'name="planner2"')
    with load_graph(str(launch), text=text) as ctx:
        assert "node:/planner2" in ctx.graph.nodes and "node:/planner" not in ctx.graph.nodes


def test_model_with_syntax_errors_is_an_error(tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(GRAPH_WS, ws)
    (ws / "src" / "robot" / "launch" / "robot.tvl").write_text("root Robot { group allOf { Base Camera } }")
    with pytest.raises(GraphError, match="syntax errors"):
        load_graph(str(ws / "src" / "robot" / "launch" / "robot.launch"))


def test_graph_document_command():
    doc = graph_document(str(ROBOT_LAUNCH), decisions={"Nav": True}, count=True)
    assert doc["products"] == 6 and doc["decisions"] == {"Nav": True}
    bad = graph_document(str(ROBOT_LAUNCH), decisions={"Nav": True, "Teleop": True})
    assert "no product" in bad["error"] and set(bad["conflict"]) == {"Nav", "Teleop"}
    assert "did you mean" in graph_document(str(ROBOT_LAUNCH), decisions={"nav": True})["error"]


def test_node_info_for_hover():
    infos = node_info(str(ROBOT_LAUNCH), _node_start(ROBOT_LAUNCH, 'type="omni_drive"'))
    assert len(infos) == 1
    i = infos[0]
    assert (i.name, i.package, i.type, i.hinted) == ("/base/driver", "robot_drivers", "omni_drive", True)
    uses = {(u.kind, u.name): u for u in i.uses}
    assert uses[("subscribe", "/base/cmd_vel_omni")].condition == "Nav"
    assert uses[("subscribe", "/base/cmd_vel_omni")].remap == '<remap from="cmd_vel" to="cmd_vel_omni">'
    assert uses[("subscribe", "/base/cmd_vel")].condition == "!Nav"
    assert uses[("publish", "/robot/odom")].condition is None and uses[("publish", "/robot/odom")].written == ["odom"]
    assert ("service", "/base/set_mode") in uses
    mapper = node_info(str(ROBOT_LAUNCH), _node_start(ROBOT_LAUNCH, 'type="mapper"'))[0]
    assert not mapper.hinted and mapper.uses == [] and "no hints" in mapper.note


def test_cache_notices_edits(tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(GRAPH_WS, ws)
    launch = ws / "src" / "robot" / "launch" / "robot.launch"
    a = cached_graph(str(launch))
    assert cached_graph(str(launch)) is a
    pf = ws / "haros.yaml"
    pf.write_text(pf.read_text().replace("nav/safety:", "nav/safety2:"))
    b = cached_graph(str(launch))
    assert b is not a and not b.graph.nodes["node:/safety"].hinted
    inc = ws / "src" / "robot" / "launch" / "camera.launch"
    inc.write_text(inc.read_text().replace('name="camera"', 'name="cam"'))
    c = cached_graph(str(launch))
    assert c is not b and "node:/sensors/cam" in c.graph.nodes
