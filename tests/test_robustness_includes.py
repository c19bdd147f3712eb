"""Includes outside the workspace: one rule in every command (issue #28, defect 13; the rule is
in docs/architecture.md, "Includes outside the workspace").

Before, ``tvl-lsp launch`` followed an include outside the workspace and printed its nodes,
``graph`` and the configurator left it out silently, and ``--check`` called a symbolically linked
one missing.  Now every command reads only the workspace and its packages (links resolved), and
reports an existing file outside as not read: ``include-outside-workspace`` in ``--check``, the
editor and the configurator's problems, "not read: outside the workspace" in ``tvl-lsp launch``,
a note in the graphs.  A package that is a link into the workspace is inside; a FIFO or a link to
``/dev/zero`` inside the workspace is read through the bounded reader (refused, never a hang)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

MODEL = "root Robot {\n  group allOf { opt Lidar, opt Camera, opt Arm, opt Gripper }\n}\n"
GENERIC = """<launch>
  <arg name="Robot"/>
  <arg name="Lidar"/>
  <arg name="Camera"/>
  <arg name="Arm"/>
  <arg name="Gripper"/>
  <node pkg="robot" type="base" name="base"/>
  <include file="{outside}/lidar.launch" if="$(arg Lidar)"/>
  <include file="$(find robot)/launch/camera.launch" if="$(arg Camera)"/>
  <include file="$(dirname)/../../../../outside/arm.launch" if="$(arg Arm)"/>
  <include file="$(find gripper)/launch/gripper.launch" if="$(arg Gripper)"/>
</launch>
"""
PACKAGE = ('<?xml version="1.0"?>\n<package format="2"><name>{name}</name><version>0.1.0</version>'
           '<description>d</description><maintainer email="a@b.c">m</maintainer><license>BSD</license></package>\n')


def node_file(name: str) -> str:
    return f'<launch>\n  <node pkg="{name}_drv" type="{name}" name="{name}"/>\n</launch>\n'


@pytest.fixture()
def ws(tmp_path) -> Path:
    """ws/src/robot: the generic file; its includes: an absolute path outside (lidar), a link in
    the package to a file outside (camera), `..` out of the workspace (arm), and a package that
    is a link to a folder outside the workspace (gripper: inside, as catkin sees it)."""
    outside, repos, ws = tmp_path / "outside", tmp_path / "repos", tmp_path / "ws"
    for name in ("lidar", "camera", "arm"):
        outside.mkdir(exist_ok=True)
        (outside / f"{name}.launch").write_text(node_file(name))
    (repos / "gripper" / "launch").mkdir(parents=True)
    (repos / "gripper" / "package.xml").write_text(PACKAGE.format(name="gripper"))
    (repos / "gripper" / "launch" / "gripper.launch").write_text(node_file("gripper"))
    launch = ws / "src" / "robot" / "launch"
    launch.mkdir(parents=True)
    (ws / ".catkin_workspace").touch()
    (ws / "src" / "robot" / "package.xml").write_text(PACKAGE.format(name="robot"))
    (launch / "generic.tvl").write_text(MODEL)
    (launch / "generic.launch").write_text(GENERIC.format(outside=outside))
    (launch / "camera.launch").symlink_to(outside / "camera.launch")
    (ws / "src" / "gripper").symlink_to(repos / "gripper")
    return ws


OUTSIDE = {"lidar", "camera", "arm"}


def generic(ws: Path) -> Path:
    return ws / "src" / "robot" / "launch" / "generic.launch"


def cli(*args, cwd=None) -> subprocess.CompletedProcess:
    p = subprocess.run([sys.executable, "-m", "tvl_lsp", *map(str, args)], capture_output=True, text=True,
                       timeout=180, cwd=cwd, env=dict(os.environ, PYTHONPATH=str(REPO), ROS_PACKAGE_PATH=""))
    assert "Traceback" not in p.stderr, p.stderr[-3000:]
    return p


def outside_named(texts) -> set[str]:
    """Which of lidar / camera / arm the texts say are outside the workspace."""
    texts = list(texts)
    return {n for n in OUTSIDE for t in texts if f"{n}.launch" in t and "outside the workspace" in t}


def test_launch_command(ws):
    p = cli("launch", generic(ws), "--json", *(f"{a}:=true" for a in ("Robot", "Lidar", "Camera", "Arm", "Gripper")))
    out = json.loads(p.stdout)
    assert sorted(n["name"] for n in out["nodes"]) == ["/base", "/gripper"]  # nothing read from outside
    marked = {Path(i["file"]).stem for i in out["includes"] if i.get("outside")}
    assert marked == OUTSIDE and outside_named(out["warnings"]) == OUTSIDE
    text = cli("launch", generic(ws), "Lidar:=true", "Camera:=false", "Arm:=false", "Gripper:=false", "Robot:=true").stdout
    assert "lidar.launch [ns /]  (not read: outside the workspace)" in text and "/lidar " not in text


def test_check_and_the_editor(ws):
    from tvl_lsp.project.check import check_document
    p = cli("--check", ws, "--format", "json")
    diags = json.loads(p.stdout)
    diags = diags if isinstance(diags, list) else diags["diagnostics"]
    got = [d for d in diags if d["code"] == "include-outside-workspace"]
    assert outside_named(d["message"] for d in got) == OUTSIDE
    assert not [d for d in diags if d["code"] == "include-not-found"]  # (the link was "missing")
    editor = [d for d in check_document(str(generic(ws)), roots=[str(ws)]) if d.code == "include-outside-workspace"]
    assert sorted(d.message for d in editor) == sorted(d["message"] for d in got)
    assert {(d.span.start.line, d.span.start.col) for d in editor} == {(d["range"]["start"]["line"], d["range"]["start"]["character"]) for d in got}


def test_graph_command(ws):
    g = json.loads(cli("graph", generic(ws), "--format", "json").stdout)
    names = {n.get("name") for n in g["nodes"]}
    assert names == {"/base", "/gripper"}
    assert outside_named(g["notes"]) == OUTSIDE


def test_configurator(ws):
    from tvl_lsp.configurator import Session
    s = Session.open(str(generic(ws)), [str(ws)])
    graph = s.graph_json({})
    assert outside_named(graph["notes"]) == OUTSIDE
    names = {e.get("label") or e.get("name") for e in graph["elements"] if e.get("kind") in ("node", "rosnode")}
    assert not any(n and n.strip("/") in OUTSIDE for n in names)
    s.problems()
    probs = json.dumps(s.problems_json({}))
    assert probs.count("include-outside-workspace") >= 3


@pytest.mark.parametrize("special", ["fifo", "dev-zero"])
def test_a_special_file_included_inside_the_workspace_is_refused_by_every_command(ws, special):
    inc = ws / "src" / "robot" / "launch" / "special.launch"
    if special == "fifo":
        os.mkfifo(inc)
    else:
        inc.symlink_to("/dev/zero")
    g = generic(ws)
    g.write_text(g.read_text().replace("</launch>", '  <include file="$(find robot)/launch/special.launch"/>\n</launch>'))
    p = cli("launch", g, "--json", "Robot:=true")
    assert p.returncode in (0, 1) and json.loads(p.stdout)
    p = cli("--check", ws, "--format", "json")
    assert p.returncode in (0, 1)
    assert json.loads(cli("graph", g, "--format", "json").stdout)["nodes"]


def test_ros2_the_same_rule(tmp_path):
    outside, ws = tmp_path / "outside", tmp_path / "ws"
    outside.mkdir()
    (outside / "lidar.launch.xml").write_text('<launch>\n  <node pkg="lidar_drv" exec="lidar" name="lidar"/>\n</launch>\n')
    launch = ws / "src" / "robot" / "launch"
    launch.mkdir(parents=True)
    (ws / "src" / "robot" / "package.xml").write_text(PACKAGE.format(name="robot"))
    (launch / "generic.tvl").write_text("root Robot {\n  group allOf { opt Lidar, opt Camera }\n}\n")
    (launch / "camera.launch.xml").symlink_to(outside / "lidar.launch.xml")
    g = launch / "generic.launch.xml"
    g.write_text(f"""<launch>
  <arg name="Robot" default="true"/>
  <arg name="Lidar" default="false"/>
  <arg name="Camera" default="false"/>
  <node pkg="robot" exec="base" name="base"/>
  <include file="{outside}/lidar.launch.xml" if="$(var Lidar)"/>
  <include file="$(find-pkg-share robot)/launch/camera.launch.xml" if="$(var Camera)"/>
</launch>
""")
    out = json.loads(cli("launch", g, "--json", "Lidar:=true", "Camera:=true").stdout)
    assert [n["name"].strip("/") for n in out["nodes"]] == ["base"]
    assert len([i for i in out["includes"] if i.get("outside")]) == 2
    diags = json.loads(cli("--check", ws, "--format", "json").stdout)
    diags = diags if isinstance(diags, list) else diags["diagnostics"]
    assert len([d for d in diags if d["code"] == "include-outside-workspace"]) == 2
    assert not [d for d in diags if d["code"] == "include-not-found"]
