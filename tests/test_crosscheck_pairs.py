"""Cross-checks of launch files against their models on the pairs in tests/data/pairs.

robot/: robot.tvl (Robot: Base oneOf {Wheels, Tracks}, opt Camera, Arm, Lidar; Arm -> Camera)
with robot.launch, which has every kind of problem; clean/: a correct pair (no warnings);
alone/: a launch file without a model (its top-level args are free booleans).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tvl_lsp.base import formula as fm
from tvl_lsp.analysis.crosscheck import cross_check
from tvl_lsp.analysis.solve import PairLogic
from tvl_lsp.project.check import check_document, check_paths
from tvl_lsp.base.diagnostics import Severity
from tvl_lsp.launch import analyse_launch
from tvl_lsp.tvl import parse_model

HERE = Path(__file__).resolve().parent
PAIRS = HERE / "data" / "pairs"
ROBOT_FEATURES = ["Robot", "Base", "Camera", "Arm", "Lidar", "Wheels", "Tracks"]


def _line_of(path: Path, needle: str) -> int:
    for i, line in enumerate(path.read_text().splitlines()):
        if needle in line:
            return i
    raise AssertionError(needle)


@pytest.fixture(scope="module")
def robot():
    return check_paths([str(PAIRS / "robot")], jobs=1)


def _by_code(diags, code):
    return [d for d in diags if d.code == code]


def _product(w):
    return {k for k, v in w.items() if v}


def test_missing_args_are_on_the_launch_start_tag_with_the_feature(robot):
    lf = PAIRS / "robot/robot.launch"
    miss = _by_code(robot, "missing-arg")
    assert sorted(d.data["feature"] for d in miss) == ["Lidar", "Tracks"]
    for d in miss:
        assert d.path == str(lf) and d.severity == Severity.WARNING
        assert (d.span.start.line, d.span.start.col, d.span.end.col) == (0, 0, len("<launch>"))
        (rel,) = d.related
        assert rel.path == str(PAIRS / "robot/robot.tvl")
        line = (PAIRS / "robot/robot.tvl").read_text().splitlines()[rel.span.start.line]
        assert line[rel.span.start.col:rel.span.end.col] == d.data["feature"]
        # the quick fix inserts the arg after the last top-level arg
        (fix,) = d.fixes
        (edit,) = fix.edits
        assert edit.new_text == f'\n  <arg name="{d.data["feature"]}"/>'
        assert edit.span.start.line == _line_of(lf, '<arg name="Lidr"/>')


def test_unmatched_arg_suggests_the_closest_feature(robot):
    (d,) = _by_code(robot, "unmatched-arg")
    lf = PAIRS / "robot/robot.launch"
    line = lf.read_text().splitlines()[d.span.start.line]
    assert line[d.span.start.col:d.span.end.col] == "Lidr"
    assert "`Lidar`" in d.message and d.data["suggestion"] == "Lidar"
    assert d.fixes[0].edits[0].new_text == "Lidar"


def test_undefined_arg_only_in_products_with_the_arm(robot):
    (d,) = _by_code(robot, "undefined-arg")
    lf = PAIRS / "robot/robot.launch"
    line = lf.read_text().splitlines()[d.span.start.line]
    assert line[d.span.start.col:d.span.end.col] == "$(arg arm_speed)"
    assert "arm_speed" in d.message
    # smallest product with Arm: Arm needs Camera, Base needs one of Wheels / Tracks; with
    # Wheels and Camera roslaunch would first stop on the duplicate node /driver: Tracks
    assert set(d.witness) == set(ROBOT_FEATURES) | {"Lidr"}
    assert _product(d.witness) == {"Robot", "Base", "Camera", "Arm", "Tracks"}


def test_duplicate_node_with_wheels_and_camera_and_arg_with_tracks_and_camera(robot):
    (node,) = _by_code(robot, "duplicate-node")
    assert "/driver" in node.message
    assert _product(node.witness) == {"Robot", "Base", "Wheels", "Camera"}
    assert node.related, "the other node is a related location"
    (arg,) = _by_code(robot, "duplicate-arg")
    assert "rate" in arg.message
    # rate is declared if Camera and unless Wheels: both with Camera and Tracks
    assert _product(arg.witness) == {"Robot", "Base", "Tracks", "Camera"}


def test_dead_element_is_reported_once_at_the_topmost_element(robot):
    (d,) = _by_code(robot, "dead-element")
    lf = PAIRS / "robot/robot.launch"
    assert d.span.start.line == _line_of(lf, 'name="blind_grasp"')
    assert d.witness is None and "never loaded" in d.message
    # its <param> child is not reported again
    assert not any(x.span.start.line == _line_of(lf, 'name="mode"') for x in robot)


def test_constant_condition_on_a_mandatory_feature(robot):
    (d,) = _by_code(robot, "constant-condition")
    lf = PAIRS / "robot/robot.launch"
    line = lf.read_text().splitlines()[d.span.start.line]
    assert line[d.span.start.col:d.span.end.col] == "$(arg Base)"
    assert d.severity == Severity.INFORMATION


def test_robot_pair_reports_exactly_these_codes(robot):
    assert sorted(d.code for d in robot) == sorted([
        "missing-arg", "missing-arg", "unmatched-arg", "undefined-arg", "duplicate-node",
        "duplicate-arg", "dead-element", "constant-condition"])


def test_correct_pair_has_no_warnings():
    diags = check_paths([str(PAIRS / "clean")], jobs=1)
    assert diags == []
    # and the same launch file paired through a HAROS project file
    diags = check_paths([str(PAIRS / "ws")], jobs=1)
    assert diags == []


def test_alone_launch_file_uses_free_booleans():
    diags = check_paths([str(PAIRS / "alone")], jobs=1)
    assert sorted(d.code for d in diags) == ["dead-element", "duplicate-node", "unset-arg", "unset-arg"]
    # roslaunch run with the file's defaults fails: its free args have none (warnings)
    assert sorted(d.data["arg"] for d in _by_code(diags, "unset-arg")) == ["real", "sim"]
    assert all(d.severity == Severity.WARNING for d in _by_code(diags, "unset-arg"))
    (dup,) = _by_code(diags, "duplicate-node")
    assert dup.witness == {"sim": True, "real": True}
    (dead,) = _by_code(diags, "dead-element")
    assert 'name="watchdog"' in dead.message


def test_the_model_decides_whether_a_duplicate_is_real(tmp_path):
    # Sim and Real exclude each other in this model: the duplicate node cannot happen
    (tmp_path / "alone.tvl").write_text("root R { group oneOf { Sim, Real } }\n")
    text = (PAIRS / "alone/alone.launch").read_text().replace("sim", "Sim").replace("real", "Real")
    text = text.replace('<arg name="Sim"/>', '<arg name="R"/>\n  <arg name="Sim"/>')
    (tmp_path / "alone.launch").write_text(text)
    diags = check_paths([str(tmp_path)], jobs=1)
    assert sorted(d.code for d in diags) == ["dead-element"]


def test_check_document_matches_check_paths_for_one_file():
    lf = PAIRS / "robot/robot.launch"
    one = check_document(str(lf))
    assert [(d.code, d.span, d.message) for d in one] == \
        [(d.code, d.span, d.message) for d in check_paths([str(PAIRS / "robot")], jobs=1) if d.path == str(lf)]
    # unsaved text is what is checked
    text = lf.read_text().replace('<arg name="Lidr"/>', '<arg name="Lidar"/>\n  <arg name="Tracks"/>')
    codes = {d.code for d in check_document(str(lf), text)}
    assert "unmatched-arg" not in codes and "missing-arg" not in codes


def test_void_model_suppresses_variability_checks(tmp_path):
    (tmp_path / "v.tvl").write_text("root V { group allOf { A } A -> !A; }\n")
    (tmp_path / "v.launch").write_text('<launch><arg name="V"/><arg name="A"/>'
                                       '<node pkg="p" type="t" name="n" if="$(arg A)"/></launch>')
    diags = check_paths([str(tmp_path)], jobs=1)
    assert "void-model" in {d.code for d in diags}
    assert not {"dead-element", "constant-condition"} & {d.code for d in diags}


def test_pair_logic_witness_is_smallest_and_canonical():
    res = parse_model((PAIRS / "robot/robot.tvl").read_text(), str(PAIRS / "robot/robot.tvl"))
    from tvl_lsp.analysis.encode import encode
    enc = encode(res.model)
    lg = PairLogic(enc, ["extra"])
    w = lg.witness(fm.TRUE)
    assert _product(w) == {"Robot", "Base", "Wheels"}   # Wheels declared before Tracks
    assert lg.witness(fm.conj([fm.Var("Arm"), fm.neg(fm.Var("Camera"))])) is None
    w = lg.witness(fm.Var("extra"))
    assert _product(w) == {"Robot", "Base", "Wheels", "extra"}
    assert lg.valid(fm.Var("Base")) and not lg.valid(fm.Var("Camera"))
    # asking other questions first does not change the answer
    lg2 = PairLogic(enc, ["extra"])
    for f in ("Lidar", "Tracks", "Arm"):
        lg2.witness(fm.Var(f))
    assert lg2.witness(fm.TRUE) == lg.witness(fm.TRUE)
    lg.close()
    lg2.close()


def test_cross_check_without_model_on_a_bare_analysis():
    text = '<launch><arg name="a"/><node pkg="p" type="t" name="n" if="$(arg a)"/>' \
           '<node pkg="p" type="t" name="n" unless="$(arg a)"/></launch>'
    la = analyse_launch(text, "/tmp/x.launch", features=["a"])
    # alone, `a` has no default: roslaunch needs it on the command line (a warning)
    assert [(d.code, d.severity) for d in cross_check(la)] == [("unset-arg", Severity.WARNING)]
    la = analyse_launch(text.replace('<arg name="a"/>', '<arg name="a" default="true"/>'), "/tmp/x.launch",
                        features=["a"])
    assert cross_check(la) == []


def test_a_model_with_syntax_errors_postpones_the_cross_checks(tmp_path):
    (tmp_path / "robot.tvl").write_text("root Robot {\n  group allOf { Camera Lidar }\n}\n")
    (tmp_path / "robot.launch").write_text('<launch>\n  <arg name="Robot"/>\n  <arg name="Cam"/>\n'
                                           '  <node pkg="p" type="t" name="n" args="$(arg nope)"/>\n</launch>\n')
    diags = check_paths([str(tmp_path)], jobs=1)
    lf = [d for d in diags if d.path.endswith(".launch")]
    codes = sorted(d.code for d in lf)
    assert codes == ["paired-model-invalid", "undefined-arg"]   # no unmatched-arg for `Cam`
    note = next(d for d in lf if d.code == "paired-model-invalid")
    assert note.related and note.related[0].path.endswith("robot.tvl")


def test_nav_pair_scopes_namespaces_and_includes():
    """nav/: a conditional arg declaration, a group-local arg used outside its group, a node
    name clash through a namespace, a dead include, and includes the model keeps apart."""
    diags = check_paths([str(PAIRS / "nav")], jobs=1)
    lf = PAIRS / "nav/nav.launch"
    got = sorted((d.code, d.span.start.line + 1) for d in diags)
    assert got == [("dead-element", 27), ("duplicate-node", 23), ("undefined-arg", 12), ("undefined-arg", 17),
                   ("unmatched-arg", 11)]
    by = {(d.code, d.span.start.line + 1): d for d in diags}
    speed = by[("undefined-arg", 12)]
    assert "'speed'" in speed.message and _product(speed.witness) == {"Nav", "Planner", "Dwa"}
    assert not speed.witness["Fast"]
    mapf = by[("undefined-arg", 17)]
    # the smallest product with Localization where roslaunch does not stop earlier on `speed`
    assert _product(mapf.witness) == {"Nav", "Planner", "Localization", "Teb"}
    dup = by[("duplicate-node", 23)]
    assert "/nav/slam" in dup.message and _product(dup.witness) == {"Nav", "Planner", "Mapping", "Teb"}
    dead = by[("dead-element", 27)]
    line = lf.read_text().splitlines()[26]
    assert line[dead.span.start.col:dead.span.end.col].startswith("<include")
    assert {r.path for r in dead.related} == {str(PAIRS / "nav/nav.tvl")}
    # explained by the model's part that excludes it
    assert "Because: constraint `Mapping -> !Localization;`" in dead.message
    assert any("Mapping -> !Localization" in r.message for r in dead.related)


def test_missing_arg_points_at_a_feature_arg_hidden_in_a_group(tmp_path):
    (tmp_path / "r.tvl").write_text("root R { group allOf { opt A } }\n")
    (tmp_path / "r.launch").write_text('<launch>\n  <arg name="R"/>\n  <group>\n    <arg name="A" default="true"/>\n'
                                       '  </group>\n</launch>\n')
    (d,) = check_paths([str(tmp_path)], jobs=1)
    assert d.code == "missing-arg" and d.data == {"feature": "A"}
    assert "on line 4 is inside <group>" in d.message


def test_each_undeclared_arg_of_a_value_is_its_own_problem(tmp_path):
    """`$(arg cam) $(arg rate)` with neither declared: roslaunch stops at cam, but rate is just as
    undeclared -- two problems, each about one arg, not one message chaining both."""
    (tmp_path / "bot.tvl").write_text("root Bot {\n  group allOf {\n    opt Cam\n  }\n}\n")
    lf = tmp_path / "bot.launch"
    lf.write_text('<launch>\n  <arg name="Bot"/>\n  <arg name="Cam"/>\n'
                  '  <param name="p" value="$(arg cam) $(arg rate)" if="$(arg Cam)"/>\n</launch>\n')
    ds = [d for d in check_paths([str(tmp_path)], jobs=1) if d.code == "undefined-arg"]
    text = lf.read_text().splitlines()[3]
    by_arg = {d.data["arg"]: d for d in ds}
    assert sorted(by_arg) == ["cam", "rate"], [d.message for d in ds]
    for name, d in by_arg.items():
        assert text[d.span.start.col:d.span.end.col] == f"$(arg {name})"
        assert "either" not in d.message and "in the same value" not in d.message and d.message.count("arg to be set") == 1
        assert d.message.startswith(f"bot.launch requires the '{name}' arg to be set")
        assert _product(d.witness) == {"Bot", "Cam"}
    assert "did you mean `Cam`?" in by_arg["cam"].message
    assert by_arg["rate"].data["stops_at"] == "cam" and "stops_at" not in by_arg["cam"].data
    (rel,) = by_arg["rate"].related
    assert rel.span == by_arg["cam"].span and "roslaunch stops earlier" in rel.message


def test_related_information_names_files_relative_to_the_workspace(tmp_path):
    """The pairing note in a problem's related information reads as the Problems panel shows
    paths: relative to the workspace root, not absolute."""
    import shutil
    ws = tmp_path / "ws"
    shutil.copytree(PAIRS / "ws", ws)
    lf = ws / "src/bot/launch/generic.launch"
    lf.write_text(lf.read_text().replace('  <arg name="Autonomy"/>\n', ""))
    (d,) = [d for d in check_paths([str(ws)], jobs=1) if d.code == "missing-arg"]
    notes = [r.message for r in d.related if r.message.startswith("paired with")]
    assert notes == [f"paired with {os.path.join('src', 'bot', 'models', 'rover.tvl')} by a HAROS project file "
                     f"(haros_bot.yaml:{d.related[-1].span.start})"], notes
    assert not any(str(tmp_path) in r.message for r in d.related)
