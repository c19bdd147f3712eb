"""ROS 2 launch files in the pipeline: --check (twins of ROS 1 files get the same findings),
`tvl-lsp launch --json`, `generate` in ROS 2 form, <choice> args paired with the model, files
that only other files include, and the ROS 2 quick fix."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

from tvl_lsp.base.text import LineIndex
from tvl_lsp.main import main
from tvl_lsp.launch.ros2 import load_launch2
from tvl_lsp.project.check import check_document, check_paths

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "ros2"
WS = DATA / "ws"
TWINS = DATA / "twins"
ROBOT = WS / "src" / "r2_robot" / "launch"

# the findings that must be the same for a generic launch file and its ROS 1 twin
TWIN_CODES = {"undefined-arg", "unmatched-arg", "missing-arg", "dead-element", "duplicate-node",
              "constant-condition", "invalid-condition"}


def _key(d):
    return (d.code, d.span.start.line, d.span.start.col, d.span.end.line, d.span.end.col,
            tuple(sorted((d.witness or {}).items())))


def test_ros2_twin_gets_the_findings_of_its_ros1_twin():
    ros1 = check_document(str(TWINS / "ros1/src/twin_robot/launch/robot.launch"))
    ros2 = check_document(str(TWINS / "ros2/src/twin_robot/launch/robot.launch.xml"))
    a = sorted(_key(d) for d in ros1 if d.code in TWIN_CODES)
    b = sorted(_key(d) for d in ros2 if d.code in TWIN_CODES)
    assert a == b
    assert {k[0] for k in a} == {"missing-arg", "unmatched-arg", "duplicate-node", "dead-element",
                                 "constant-condition", "undefined-arg"}
    # nothing else on the ROS 2 side (no spurious "required arg" or dialect notes)
    assert {d.code for d in ros2} <= TWIN_CODES
    # two undeclared args in one value: one problem each, the later one says where ros2 launch stops
    pair = [d for d in ros2 if d.code == "undefined-arg" and d.span.start.line == 20]
    assert len(pair) == 2 and "cam_b" in pair[1].message + pair[0].message
    later = max(pair, key=lambda d: d.span.start.col)
    assert "$(var cam_b)" in later.message and "ros2 launch stops earlier" in later.related[0].message


def test_courier_twins_get_the_same_findings_with_exact_ranges():
    # a second pair, with a mistake of each kind: args for two features missing, a misspelt
    # feature arg, a non-feature top-level arg, a node name clash, an element the model
    # rules out (Lift -> !Bumper), a condition the model makes constant (Docking -> Sonar), an
    # undeclared arg, and a condition that is never a boolean
    ros1_path = TWINS / "ros1/src/courier/launch/courier.launch"
    ros2_path = TWINS / "ros2/src/courier/launch/courier.launch.xml"
    ros1, ros2 = check_document(str(ros1_path)), check_document(str(ros2_path))
    a = sorted(_key(d) for d in ros1 if d.code in TWIN_CODES)
    b = sorted(_key(d) for d in ros2 if d.code in TWIN_CODES)
    assert a == b
    assert {d.code for d in ros1} == {d.code for d in ros2} <= TWIN_CODES
    text = ros2_path.read_text()
    idx = LineIndex(text)
    got = sorted((d.code, text[idx.offset(d.span.start):idx.offset(d.span.end)]) for d in ros2
                 if d.code != "missing-arg")
    assert got == [("constant-condition", "$(var Sonar)"), ("dead-element", '<node pkg="lift" exec="lift_guard" '
                                                            'name="lift_guard" if="$(var Lift)"/>'),
                   ("duplicate-node", "ranger"), ("invalid-condition", "$(var Localisation)_on"),
                   ("undefined-arg", "$(var dock_station)"), ("unmatched-arg", "Sonr"), ("unmatched-arg", "map")]
    missing = sorted(d.message.split("`")[1] for d in ros2 if d.code == "missing-arg")
    assert missing == ["Docking", "Sonar"]
    wit = {d.code: d.witness for d in ros2 if d.witness}
    assert wit["duplicate-node"]["Bumper"] and wit["duplicate-node"]["Sonar"]
    assert wit["undefined-arg"]["Docking"] and wit["invalid-condition"]["Localisation"]


def test_check_of_the_ros2_generic_file_has_exact_ranges():
    path = ROBOT / "issues.launch.xml"
    text = path.read_text()
    idx = LineIndex(text)
    got = {}
    for d in check_document(str(path)):
        got.setdefault(d.code, []).append(text[idx.offset(d.span.start):idx.offset(d.span.end)])
    assert got["undefined-arg"] == ["$(var lidar_frame)"]
    assert got["duplicate-node"] == ["driver"]
    assert got["include-arg-leak"] == ["$(var rate)"]
    assert got["dead-element"][0].startswith('<node pkg="r2_bringup" exec="fusion"')
    assert sorted(got["unmatched-arg"]) == ["Gps", "rate"]
    assert sorted(got["invalid-condition"]) == ["$(var Teleop)yes", "$(var Teleop)yes"]


def test_yaml_generic_file_is_paired_by_its_marker_and_checked():
    path = ROBOT / "generic.launch.yaml"
    diags = check_document(str(path))
    assert not [d for d in diags if d.severity == 1], diags
    # its twin in XML: the same (clean) result
    assert not [d for d in check_document(str(ROBOT / "generic.launch.xml")) if d.severity <= 2]


def test_check_paths_over_the_ros2_workspace_discovers_xml_and_yaml():
    diags = check_paths([str(WS)], jobs=1)
    files = {os.path.basename(d.path) for d in diags}
    assert "issues.launch.xml" in files and "errors.launch.xml" in files
    # the YAML file with a malformed node and the Python launch file
    assert "bad.launch.yaml" in files
    assert not any(d.path.endswith(".py") for d in diags)


# ------------------------------------------------------------------ <choice> args

def test_choice_args_pair_with_an_alternative_group_and_an_enum_attribute():
    path = ROBOT / "choices.launch.xml"
    diags = check_document(str(path))
    by = {}
    for d in diags:
        by.setdefault(d.code, []).append(d)
    assert "missing-arg" not in by, "the alternatives need no <arg> of their own"
    assert "unmatched-arg" not in by, "mode pairs with the attribute Rover.mode"
    assert "invalid-choice" not in by
    mism = sorted(d.message for d in by["choice-mismatch"])
    assert any("`Legs`" in m for m in mism) and any('"Wheelz"' in m for m in mism)
    dead = sorted(d.message.split(" is never")[0] for d in by["dead-element"])
    assert dead == ['<node name="legs">', '<node name="simulator">']
    assert "duplicate-node" not in by, "Diff and Omni exclude each other"


def test_generate_passes_the_selected_alternative(tmp_path):
    out = tmp_path / "cfg"
    ws = tmp_path / "ws"
    shutil.copytree(WS, ws)
    launch = ws / "src" / "r2_robot" / "launch" / "choices.launch.xml"
    assert main(["generate", str(launch), "--mode", "all", "--out", str(ws / "src" / "r2_robot" / "configs")]) == 0
    files = sorted((ws / "src" / "r2_robot" / "configs").glob("*.launch.xml"))
    assert len(files) == 6
    texts = [f.read_text() for f in files]
    assert all('<include file="$(find-pkg-share r2_robot)/launch/choices.launch.xml">' in t for t in texts)
    assert sum('<arg name="Drive" value="Omni"/>' in t for t in texts) == 2
    assert not any('name="Diff"' in t or 'name="Legs"' in t for t in texts)
    assert not out.exists()


# ------------------------------------------------------------------ generate, launch --json

def test_generated_ros2_configuration_launches_like_the_generic_file(tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(WS, ws)
    generic = ws / "src" / "r2_robot" / "launch" / "generic.launch.xml"
    assert main(["generate", str(generic), "--mode", "all"]) == 0
    configs = sorted((ws / "src" / "r2_robot" / "configs").glob("generic_*.launch.xml"))
    assert len(configs) == 20
    for cfg in configs[:6]:
        text = cfg.read_text()
        assert text.startswith('<launch>\n  <include file="$(find-pkg-share r2_robot)/launch/generic.launch.xml">')
        args = dict((a.split('" value="')[0], a.split('" value="')[1]) for a in
                    [ln.strip()[len('<arg name="'):-3] for ln in text.splitlines() if ln.strip().startswith("<arg ")])
        via_config = load_launch2(str(cfg), {}, workspace_root=str(ws), env={})
        direct = load_launch2(str(generic), args, workspace_root=str(ws), env={})
        assert via_config.error is None and direct.error is None
        assert [n["name"] for n in via_config.nodes] == [n["name"] for n in direct.nodes]


def test_launch_json_is_the_oracles_shape(capsys):
    golden = json.loads((DATA / "golden" / "nodes_r2.json").read_text())
    case = golden["case"]
    argv = ["launch", str(WS / "src" / case["file"]), *[f"{k}:={v}" for k, v in case["args"].items()],
            "--json", "--workspace", str(WS)]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["dialect"] == "ros2" and out["error"] is None
    want = [(n["name"], n["package"], n["executable"], n["remaps"]) for n in golden["result"]["nodes"]]
    assert [(n["name"], n["package"], n["executable"], n["remaps"]) for n in out["nodes"]] == want


def test_launch_json_error_and_exit_status(capsys):
    golden = json.loads((DATA / "golden" / "errors_undefined.json").read_text())
    argv = ["launch", str(WS / "src" / golden["case"]["file"]), "use_undefined:=true", "--json",
            "--workspace", str(WS)]
    assert main(argv) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["error"] == golden["result"]["error"]
    assert out["error_type"] == golden["result"]["error_type"]
    assert out["error_code"] == "undefined-arg" and out["error_line"] == 16


def test_launch_text_output(capsys):
    assert main(["launch", str(WS / "src/r2_bringup/launch/nodes.launch.xml"), "robot:=r2",
                 "--workspace", str(WS)]) == 0
    out = capsys.readouterr().out
    assert "/r2/perception/fusion  (r2_bringup/fusion_node, ns /r2/perception)" in out
    assert "remap scan -> /r2/scan" in out


# ------------------------------------------------------------------ partial files, quick fix

def test_a_file_only_included_reads_its_includers_configurations(tmp_path):
    ws = tmp_path / "ws" / "src" / "pkg"
    (ws / "launch").mkdir(parents=True)
    (ws / "package.xml").write_text("<package format='3'><name>pkg</name><export><build_type>ament_cmake"
                                    "</build_type></export></package>")
    (ws / "launch" / "main.launch.xml").write_text(
        '<launch>\n  <arg name="robot" default="r1"/>\n'
        '  <include file="$(find-pkg-share pkg)/launch/part.launch.xml"/>\n</launch>\n')
    part = ws / "launch" / "part.launch.xml"
    part.write_text('<launch>\n  <node pkg="pkg" exec="x" name="$(var robot)_x"/>\n</launch>\n')
    assert not [d for d in check_document(str(part)) if d.severity == 1]
    # alone (nobody here includes it): ros2 launch fails on it if launched on its own, unless an
    # including file elsewhere sets `robot` -- a warning
    (ws / "launch" / "main.launch.xml").unlink()
    from tvl_lsp.project.check import invalidate_workspaces
    invalidate_workspaces()
    got = [(d.code, d.severity) for d in check_document(str(part)) if d.code == "undefined-arg"]
    assert got == [("undefined-arg", 2)]
    # a name the file declares, read where it is not set, stays an error
    part.write_text('<launch>\n  <group>\n    <arg name="robot" default="r1"/>\n  </group>\n'
                    '  <node pkg="pkg" exec="x" name="$(var robot)_x"/>\n</launch>\n')
    got = [(d.code, d.severity) for d in check_document(str(part)) if d.code == "undefined-arg"]
    assert got == [("undefined-arg", 1)]


def test_missing_arg_quick_fix_inserts_a_ros2_arg(tmp_path):
    d = tmp_path / "ws" / "src" / "r"
    (d / "launch").mkdir(parents=True)
    (d / "package.xml").write_text("<package format='3'><name>r</name><export><build_type>ament_cmake"
                                   "</build_type></export></package>")
    (d / "launch" / "robot.tvl").write_text("root Robot { group allOf { opt Lidar, opt Camera } }\n")
    xml = d / "launch" / "robot.launch.xml"
    xml.write_text('<launch>\n  <arg name="Robot" default="true"/>\n  <arg name="Lidar" default="false"/>\n'
                   '  <node pkg="r" exec="l" name="l" if="$(var Lidar)"/>\n</launch>\n')
    fix = [d for d in check_document(str(xml)) if d.code == "missing-arg"][0].fixes[0]
    assert fix.edits[0].new_text == '\n  <arg name="Camera" default="false"/>'
    assert fix.edits[0].span.start.line == 2
    yml = d / "launch" / "robot.launch.yaml"
    yml.write_text('launch:\n  - arg: {name: Robot, default: "true"}\n  - arg: {name: Lidar, default: "false"}\n'
                   '  - node: {pkg: r, exec: l, name: l, if: "$(var Lidar)"}\n')
    fix = [d for d in check_document(str(yml)) if d.code == "missing-arg"][0].fixes[0]
    assert fix.edits[0].new_text == '\n  - arg: {name: Camera, default: "false"}'
    assert fix.edits[0].span.start.line == 2


@pytest.mark.parametrize("name,dialect", [("generic.launch.xml", "ros2"), ("choices.launch.xml", "ros2")])
def test_analysis_says_its_dialect(name, dialect):
    from tvl_lsp.launch import analyse_any
    p = ROBOT / name
    assert analyse_any(p.read_text(), str(p)).dialect == dialect


def test_an_installed_file_maps_back_to_its_source(tmp_path):
    """$(find-pkg-share pk)/launch/r1.launch.xml where the package keeps it in launch/robots/
    (its build installs it flat): the one file of that name in the package is followed.  (A package
    name has two characters at least: ament_index refuses "p".)"""
    pkg = tmp_path / "ws" / "src" / "pk"
    (pkg / "launch" / "robots").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package format='3'><name>pk</name><export><build_type>ament_cmake"
                                     "</build_type></export></package>")
    main_file = pkg / "launch" / "main.launch.xml"
    main_file.write_text('<launch>\n  <include file="$(find-pkg-share pk)/launch/r1.launch.xml"/>\n</launch>\n')
    (pkg / "launch" / "robots" / "r1.launch.xml").write_text(
        '<launch>\n  <node pkg="pk" exec="x" name="r1node" namespace="$(var undeclared)"/>\n</launch>\n')
    diags = check_document(str(main_file))
    assert [d.code for d in diags] == ["undefined-arg"], diags
    assert "in the included file r1.launch.xml" in diags[0].message


# ------------------------------------------------------------------ configurations set by includers

def test_a_condition_on_a_configuration_an_includer_sets_is_neither_constant_nor_dead():
    # headless/sim.launch.xml reads 'headless', which headless/common.launch.xml declares
    # (default false) and the command line may set: its if/unless are not constant
    sim = WS / "src" / "r2_bringup" / "launch" / "headless" / "sim.launch.xml"
    diags = check_document(str(sim))
    assert not [d for d in diags if d.code in ("constant-condition", "dead-element", "undefined-arg")], diags
    top = WS / "src" / "r2_bringup" / "launch" / "headless.launch.xml"
    assert not [d for d in check_document(str(top)) if d.severity <= 2]


def test_a_configuration_nobody_declares_is_one_warning_per_read_and_no_cascade(tmp_path):
    # on its own (no file includes it): each read of 'headless' is a warning; 'sim_name' is set
    # by one of the two <let>s whatever 'headless' turns out to be: no error on $(var sim_name)
    pkg = tmp_path / "ws" / "src" / "p"
    shutil.copytree(WS / "src" / "r2_bringup" / "launch" / "headless", pkg / "launch")
    (pkg / "launch" / "common.launch.xml").unlink()
    shutil.copy(WS / "src" / "r2_bringup" / "package.xml", pkg / "package.xml")
    diags = check_document(str(pkg / "launch" / "sim.launch.xml"))
    text = (pkg / "launch" / "sim.launch.xml").read_text()
    idx = LineIndex(text)
    got = sorted((d.code, d.severity, text[idx.offset(d.span.start):idx.offset(d.span.end)]) for d in diags)
    assert got == [("undefined-arg", 2, "$(var headless)")] * 3, got


# ------------------------------------------------------------------ launch extensions

def test_a_tag_of_a_launch_extension_in_the_workspace_is_a_note_not_an_error(tmp_path):
    # r2_ext exposes <mark> (entry point launch.frontend.launch_extension): with r2_ext installed,
    # ros2 launch loads extension.launch.xml (golden/extension_*.json); tvl-lsp says it does not
    # model what <mark> does, and analyses the rest
    path = WS / "src" / "r2_bringup" / "launch" / "extension.launch.xml"
    text = path.read_text()
    idx = LineIndex(text)
    diags = check_document(str(path))
    got = [(d.code, d.severity, text[idx.offset(d.span.start):idx.offset(d.span.end)]) for d in diags]
    assert got == [("extension-tag", 3, "mark"), ("extension-tag", 3, "mark")], got
    assert "r2_ext" in diags[0].message
    res = load_launch2(str(path), {"use_cam": "true"}, workspace_root=str(WS), env={})
    assert res.error is None and [n["name"] for n in res.nodes] == ["/planner", "/cam"]
    assert any("<mark>" in w and "r2_ext" in w for w in res.warnings)
    # without the extension package, ros2 launch refuses the file: so does tvl-lsp
    ws = tmp_path / "ws"
    shutil.copytree(WS, ws, ignore=shutil.ignore_patterns("r2_ext"))
    other = ws / "src" / "r2_bringup" / "launch" / "extension.launch.xml"
    codes = [(d.code, d.severity) for d in check_document(str(other))]
    assert ("unknown-tag", 1) in codes and "extension-tag" not in {c for c, _ in codes}
    res = load_launch2(str(other), {}, workspace_root=str(ws), env={})
    assert res.error and "Unrecognized entity of the type: mark" in res.error


def test_a_condition_reading_a_let_computed_from_an_overridable_arg_is_neither_dead_nor_constant():
    # ros2 launch with mode:=real starts real_lidar (golden let_from_arg_real): --check once
    # called it dead and sim_lidar's condition constant, taking mode at its default
    p = Path(__file__).resolve().parent / "data" / "ros2" / "ws" / "src" / "r2_bringup" / "launch" / \
        "let_from_arg.launch.xml"
    assert [d.code for d in check_document(str(p))] == []
