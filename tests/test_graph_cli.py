"""``tvl-lsp graph``: the JSON / DOT / Mermaid of a generic launch file found from its workspace
(pairing and hints as --check finds them), decisions, counts and exit codes."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from tvl_lsp.main import main

from graph_helpers import GRAPH_WS, ROBOT_LAUNCH, turtlerand_ws


def _run(argv, capsys):
    code = main(["graph", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def _links(doc):
    return {(x["node"], x["kind"], x["topic"]) for x in doc["links"]}


def test_json_of_all_products(capsys):
    code, out, err = _run([str(ROBOT_LAUNCH), "--count"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["model"].endswith("robot.tvl") and doc["hints"][0].endswith("haros.yaml")
    assert doc["products"] == 18 and doc["decisions"] == {}
    planner = next(n for n in doc["nodes"] if n["name"] == "/planner")
    assert planner["condition"] == "Nav" and planner["count"] == 6
    assert ("/planner", "publish", "/cmd_vel_safe") in _links(doc)


def test_decisions_project_the_graph(capsys):
    code, out, _ = _run([str(ROBOT_LAUNCH), "--include", "Nav", "--include", "Diff", "--exclude", "Camera"], capsys)
    assert code == 0
    doc = json.loads(out)
    assert doc["decisions"] == {"Nav": True, "Diff": True, "Camera": False}
    assert all(x["condition"] is None for k in ("nodes", "topics", "links") for x in doc[k])
    assert _links(doc) >= {("/planner", "publish", "/cmd_vel_safe"), ("/safety", "subscribe", "/cmd_vel_safe"),
                           ("/safety", "publish", "/base/cmd_vel"), ("/base/driver", "subscribe", "/base/cmd_vel")}
    assert not any(n["name"].startswith("/sensors") for n in doc["nodes"])


def test_exit_codes(capsys, tmp_path):
    code, _, err = _run([str(ROBOT_LAUNCH), "--include", "Camra"], capsys)
    assert code == 2 and "did you mean `Camera`?" in err
    code, _, err = _run([str(ROBOT_LAUNCH), "--include", "Nav", "--include", "Teleop"], capsys)
    assert code == 1 and "no product" in err and "Nav" in err and "Teleop" in err
    code, _, err = _run([str(tmp_path / "nowhere.launch")], capsys)
    assert code == 2 and "no such file" in err
    code, _, err = _run([str(ROBOT_LAUNCH), "--include", "Nav", "--exclude", "Nav"], capsys)
    assert code == 2


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed (apt-get install graphviz)")
def test_dot_renders(capsys, tmp_path):
    out_file = tmp_path / "g.dot"
    code, out, _ = _run([str(ROBOT_LAUNCH), "--format", "dot", "-o", str(out_file)], capsys)
    assert code == 0 and out == ""
    r = subprocess.run(["dot", "-Tsvg", str(out_file)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and "<svg" in r.stdout, r.stderr
    assert "/planner" in r.stdout and "stroke-dasharray" in r.stdout  # conditional: dashed


def test_mermaid_and_no_params(capsys):
    code, out, _ = _run([str(ROBOT_LAUNCH), "--format", "mermaid", "--no-params"], capsys)
    assert code == 0 and out.startswith("flowchart LR") and ":::param" not in out


def test_explicit_project_file_and_legacy_name_hints(capsys, tmp_path):
    ws = turtlerand_ws(tmp_path)
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    code, out, _ = _run([str(launch), "--include", "Teleop", "--exclude", "Random"], capsys)
    assert code == 0
    assert _links(json.loads(out)) == {("/Teleop", "publish", "/turtle1/cmd_vel"),
                                       ("/Turtlesim", "subscribe", "/turtle1/cmd_vel")}
    other = tmp_path / "other.yaml"
    other.write_text("configurations:\n  c:\n    launch: [turtlerand/launch/generic.launch]\n    hints:\n"
                     "      /Turtlesim: {subscribe: {/turtle1/pose_in: turtlesim/Pose}}\n")
    code, out, _ = _run([str(launch), "--project", str(other)], capsys)
    assert code == 0
    doc = json.loads(out)
    assert _links(doc) == {("/Turtlesim", "subscribe", "/turtle1/pose_in")}
    assert any("no hints for turtlesim/turtle_teleop_key in other.yaml" in n.get("note", "") for n in doc["nodes"])


def test_unhinted_workspace_gives_nodes_with_notes(capsys, tmp_path):
    ws = turtlerand_ws(tmp_path, hints="")
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    code, out, err = _run([str(launch)], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert {n["name"] for n in doc["nodes"]} == {"/Turtlesim", "/Teleop", "/Random", "/Multiplexer"}
    assert doc["links"] == [] and all(not n["hinted"] and n["note"] for n in doc["nodes"])


def test_console_script_in_a_fresh_process():
    r = subprocess.run([sys.executable, "-m", "tvl_lsp", "graph", str(ROBOT_LAUNCH), "-x", "Nav"],
                       capture_output=True, text=True, timeout=120, cwd=str(GRAPH_WS))
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["decisions"] == {"Nav": False}


# ------------------------------------------------------------------ tvl-lsp --check

def _check_json(path, capsys):
    code = main(["--check", str(path), "--format", "json", "-q"])
    out = capsys.readouterr().out
    return code, json.loads(out)


def test_check_reports_graph_findings_with_witnesses(capsys):
    code, diags = _check_json(GRAPH_WS, capsys)
    assert code == 0  # warnings only
    pub = [d for d in diags if d["code"] == "topic-without-publisher"]
    assert sorted(d["message"].split()[1] for d in pub) == ["/base/cmd_vel", "/camera_info",
                                                           "/diag/logger/level_changes", "/sensors/camera/image_raw"]
    d = next(d for d in pub if "/base/cmd_vel" in d["message"])
    assert d["witness"] == {"Robot": True, "Base": True, "Diff": True, "Omni": False, "Camera": False,
                            "Compress": False, "Teleop": False, "Nav": False}
    assert any(r["path"].endswith("haros.yaml") for r in d["related"])
    # the included fragment (no project names it) is not checked as an application on its own
    assert not any(d["path"].endswith("camera.launch") for d in diags)
    codes = {d["code"] for d in diags}
    assert {"topic-type-mismatch", "remap-unused", "topic-without-subscriber"} <= codes


def test_check_no_finding_when_every_product_is_connected(capsys, tmp_path):
    ws = turtlerand_ws(tmp_path)
    model = ws / "src" / "turtlerand" / "launch" / "generic.tvl"
    model.write_text(model.read_text().replace("!Multiplexer -> !(Teleop && Random);",
                                               "!Multiplexer -> !(Teleop && Random);\n  Turtlesim -> (Teleop || Random);"))
    code, diags = _check_json(ws, capsys)
    assert code == 0
    assert not [d for d in diags if d["code"].startswith("topic-") or d["code"] == "remap-unused"]
    # and without the constraint: the simulator alone has no publisher
    model.write_text(model.read_text().replace("\n  Turtlesim -> (Teleop || Random);", ""))
    code, diags = _check_json(ws, capsys)
    pub = [d for d in diags if d["code"] == "topic-without-publisher"]
    assert len(pub) == 1 and pub[0]["witness"] == {"Turtlerand": True, "Turtlesim": True, "Teleop": False,
                                                   "Random": False, "Multiplexer": False, "Vel": False}


def test_check_reports_invalid_hints_on_the_project_file(capsys, tmp_path):
    ws = turtlerand_ws(tmp_path)
    pf = ws / "haros.yaml"
    pf.write_text(pf.read_text().replace("    subscribe:\n      /turtle1/cmd_vel", "    subscibe:\n      /turtle1/cmd_vel", 1))
    code, diags = _check_json(ws, capsys)
    bad = [d for d in diags if d["code"] == "invalid-hint"]
    assert len(bad) == 1 and bad[0]["path"].endswith("haros.yaml") and "did you mean `subscribe`?" in bad[0]["message"]
