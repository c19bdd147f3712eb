"""roslaunch fidelity, third pass (issue 27): each class of disagreement found on unseen real
repositories, on a fixture of our own (tests/data/launch/ws/src/epsilon, and the package zeta
in tests/data/launch/outside, which only ROS_PACKAGE_PATH holds), against the real roslaunch
(Debian's python3-roslaunch, /usr/bin/python3).

1. ``$(eval)`` calling methods of dicts, lists and strings is evaluated; an expression tvl-lsp
   cannot evaluate is an unknown: ``if`` / ``unless`` of it exclude each other, no error;
2. an arg without a boolean default passed to a package outside the workspace and read by
   ``if`` / ``unless`` in an included file: no false ``duplicate-arg`` / ``arg-already-set``;
3. a default that is no boolean read by ``if``: ``--check`` reports what roslaunch run with the
   defaults says (``invalid-condition``), as ``tvl-lsp launch`` does;
4. an unset arg inside an ``$(eval)`` that also calls ``find()`` on a package outside the
   workspace: the missing arg is reported;
5. a witness gives string args no true/false: they are not free booleans;
6. one package resolver, with roslaunch's precedence between ``ROS_PACKAGE_PATH`` and the
   workspace;
7. a file named on the command line that is not a launch file is an error, as in roslaunch.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

from testenv import ROSLAUNCH_MISSING, SYS_PY, have_roslaunch
from tvl_lsp.base.diagnostics import Severity
from tvl_lsp.launch import analyse_launch, check_launch, find_packages, load_launch
from tvl_lsp.launch.model import json_value
from tvl_lsp.project import check as pcheck

HERE = Path(__file__).resolve().parent
WS = HERE / "data" / "launch" / "ws"
SRC = WS / "src"
OUTSIDE = HERE / "data" / "launch" / "outside"
EPS = SRC / "epsilon" / "launch"
ORACLE = HERE / "data" / "launch" / "roslaunch_oracle.py"
PK = find_packages(str(SRC))                       # the workspace: zeta is not in it
PK_ALL = {**find_packages(str(OUTSIDE)), **PK}     # what roslaunch finds with zeta on ROS_PACKAGE_PATH
PATH_ALL = f"{SRC}{os.pathsep}{OUTSIDE}"

pytestmark = pytest.mark.skipif(not have_roslaunch(), reason=ROSLAUNCH_MISSING)


def oracle(jobs: list[dict]) -> list[dict]:
    r = subprocess.run([SYS_PY, str(ORACLE)], input=json.dumps(jobs), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def same_value(a, b) -> bool:
    if type(a) is not type(b):
        return False
    if isinstance(a, list):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_value(a[k], b[k]) for k in a)
    return a == b


def assert_same_load(path: Path, args: dict, o: dict, packages: dict) -> None:
    """tvl-lsp launch loads what roslaunch loads (nodes and parameters), or fails where it fails."""
    lr = load_launch(str(path), args, packages=packages, env={})
    assert (lr.error is None) == o["ok"], (path.name, args, lr.error, o)
    if o["ok"]:
        assert sorted(n["name"] for n in lr.nodes) == sorted(o["nodes"]), (path.name, args)
        mine = {k: json_value(v) for k, v in lr.params.items()}
        assert mine.keys() == o["values"].keys(), (path.name, args)
        assert all(same_value(mine[k], o["values"][k]) for k in mine), (path.name, args, mine, o["values"])


def check_errors(path: Path, packages: dict = PK, env: dict | None = None) -> list:
    """What --check says of the file checked alone (its free args as booleans), errors only."""
    text = path.read_text()
    free = pcheck.free_top_args(text, str(path), str(WS))
    la = analyse_launch(text, str(path), packages=packages, features=free, env=env or {})
    from tvl_lsp.analysis.crosscheck import cross_check
    return [d for d in la.diagnostics + cross_check(la, None, None, launch_text=text) if d.severity == Severity.ERROR]


# ---------------------------------------------------------------- class 1

@pytest.mark.parametrize("robot", [None, "iron", "steel", "titanium", "nickel"])
def test_eval_calls_methods_of_dicts_lists_and_strings_as_roslaunch(robot):
    path = EPS / "eval_methods.launch"
    args = {} if robot is None else {"robot": robot}
    (o,) = oracle([dict(file=str(path), args=args, package_path=str(SRC))])
    assert o["ok"] == (robot != "nickel")         # ['iron', 'steel', 'titanium'].index('nickel') fails
    assert_same_load(path, args, o, PK)
    if robot is None:
        # checked alone: no duplicate-arg / arg-already-set from if= and unless= of the eval
        assert check_errors(path) == []


def test_an_eval_tvl_lsp_cannot_evaluate_is_an_unknown_not_an_error():
    path = EPS / "eval_unknown.launch"
    for args in ({}, {"mode": "slow"}):
        (o,) = oracle([dict(file=str(path), args=args, package_path=str(SRC))])
        assert o["ok"]
        lr = load_launch(str(path), args, packages=PK, env={})
        assert lr.error is None
        # what the unknown decides is listed as if it were true (one /worker, never two), and said
        assert sorted(n["name"] for n in lr.nodes) == sorted(o["nodes"]) == ["/planner", "/worker"]
        assert any("cannot evaluate the condition" in w for w in lr.warnings)
    assert check_errors(path) == []
    a = analyse_launch(path.read_text(), str(path), packages=PK)
    assert {f.code for f in a.facts} == {"condition-not-analysable"}


# ---------------------------------------------------------------- class 2

@pytest.mark.parametrize("name", ["outside_include", "outside_pass_all", "outside_nested", "outside_eval_default"])
def test_an_arg_passed_outside_the_workspace_and_to_if_unless_gives_no_false_duplicate(name):
    path = EPS / f"{name}.launch"
    assigns = [{}, {"robot": "iron"}] if name == "outside_eval_default" else \
        [{"use_lidar": "true"}, {"use_lidar": "false"}]
    results = oracle([dict(file=str(path), args=a, package_path=PATH_ALL) for a in assigns])
    for a, o in zip(assigns, results):
        assert o["ok"], (name, a, o)
        assert_same_load(path, a, o, PK_ALL)
    # --check of the workspace alone (zeta not in it): no error at all
    assert check_errors(path) == [], [d.message for d in check_errors(path)]


# ---------------------------------------------------------------- class 3

def test_a_default_that_is_no_boolean_read_by_if_is_reported_by_check_as_by_launch(monkeypatch):
    monkeypatch.delenv("TVL_TEST_USE_CAMERA", raising=False)
    path = EPS / "optenv_condition.launch"
    o_default, o_set = oracle([dict(file=str(path), args={}, package_path=str(SRC)),
                               dict(file=str(path), args={}, package_path=str(SRC),
                                    env={"TVL_TEST_USE_CAMERA": "true"})])
    assert not o_default["ok"] and "is not a 'bool' type" in o_default["message"]
    assert o_set["ok"]
    lr = load_launch(str(path), {}, packages=PK, env={})
    assert lr.error_code == "invalid-condition"
    # --check (the whole pipeline, as the command line runs it): the same error, on the if=
    diags = pcheck.check_paths([str(path)], jobs=1)
    (d,) = [d for d in diags if d.severity == Severity.ERROR]
    line = path.read_text().splitlines()[d.span.start.line]
    assert d.code == "invalid-condition" and line[d.span.start.col:d.span.end.col] == "$(arg use_camera)"
    # with the variable set when checking, as when launching: no error, and the same load
    monkeypatch.setenv("TVL_TEST_USE_CAMERA", "true")
    assert [d for d in pcheck.check_paths([str(path)], jobs=1) if d.severity == Severity.ERROR] == []
    lr = load_launch(str(path), {}, packages=PK, env={"TVL_TEST_USE_CAMERA": "true"})
    assert lr.error is None and sorted(n["name"] for n in lr.nodes) == sorted(o_set["nodes"])


# ---------------------------------------------------------------- class 4

def test_a_missing_arg_inside_an_eval_with_find_outside_the_workspace_is_reported():
    path = EPS / "eval_find_outside.launch"
    o_none, o_set = oracle([dict(file=str(path), args={}, package_path=PATH_ALL),
                            dict(file=str(path), args={"calibration": "c1"}, package_path=PATH_ALL)])
    assert not o_none["ok"] and "arg 'calibration' is not defined" in o_none["message"]
    assert o_set["ok"]
    assert_same_load(path, {"calibration": "c1"}, o_set, PK_ALL)
    # checked in the workspace alone, find('zeta') is unknown; the unset arg is certain
    a = analyse_launch(path.read_text(), str(path), packages=PK)
    unset = [f for f in a.facts if f.code == "unset-arg"]
    assert unset and all("'calibration'" in f.message for f in unset)
    assert str(unset[0].condition) == "true"        # in every product (the first eval reads it always)
    lr = load_launch(str(path), {}, packages=PK_ALL, env={})
    assert lr.error is not None and "calibration" in lr.error


# ---------------------------------------------------------------- class 5

def test_witnesses_give_no_string_arg_true_or_false():
    path = EPS / "witness_strings.launch"
    text = path.read_text()
    free = pcheck.free_top_args(text, str(path), str(WS))
    assert "robot" not in free and "end_effector" not in free and "sim" in free
    diags = pcheck.check_launch(str(path), None, [], str(WS))
    errors = [d for d in diags if d.severity == Severity.ERROR]
    assert errors and all(d.witness for d in errors)
    for d in errors:
        assert set(d.witness) <= set(free)
        # the witness, given to roslaunch as printed, reproduces the error
        args = {k: "true" if v else "false" for k, v in d.witness.items()}
        (o,) = oracle([dict(file=str(path), args=args, package_path=str(SRC))])
        assert not o["ok"] and "titanium_sim.yaml" in o["message"], (d.message, args, o)


# ---------------------------------------------------------------- class 6

def _two_copies(tmp: Path) -> tuple[Path, Path, Path]:
    """A workspace with package dup and another folder holding a package dup too; only the
    other's has launch/extra.launch."""
    xml = '<package format="2"><name>{}</name><version>0.0.0</version></package>'
    ws, other = tmp / "ws", tmp / "other"
    for root, node in ((ws / "src" / "dup", "from_ws"), (other / "dup", "from_other")):
        (root / "launch").mkdir(parents=True)
        (root / "package.xml").write_text(xml.format("dup"))
        (root / "launch" / "part.launch").write_text(f'<launch><node pkg="dup" type="t" name="{node}"/></launch>')
    (other / "dup" / "launch" / "extra.launch").write_text('<launch><param name="extra" value="1"/></launch>')
    app = ws / "src" / "app"
    (app / "launch").mkdir(parents=True)
    (app / "package.xml").write_text(xml.format("app"))
    main = app / "launch" / "main.launch"
    main.write_text('<launch>\n  <include file="$(find dup)/launch/part.launch"/>\n'
                    '  <include file="$(find dup)/launch/extra.launch"/>\n</launch>\n')
    return ws, other, main


@pytest.mark.parametrize("first", ["other", "workspace"])
def test_check_and_launch_resolve_a_package_as_roslaunch_does(tmp_path, monkeypatch, first):
    ws, other, main = _two_copies(tmp_path)
    rpp = os.pathsep.join([str(other), str(ws / "src")] if first == "other" else [str(ws / "src"), str(other)])
    (o,) = oracle([dict(file=str(main), args={}, package_path=rpp)])
    assert o["ok"] == (first == "other")
    monkeypatch.setenv("ROS_PACKAGE_PATH", rpp)
    from tvl_lsp.cli.commands.launch import main as launch_main
    lr = load_launch(str(main), {}, workspace_root=str(ws), env={"ROS_PACKAGE_PATH": rpp})
    assert (lr.error is None) == o["ok"], lr.error
    if o["ok"]:
        assert [n["name"] for n in lr.nodes] == o["nodes"] == ["/from_other"]
    diags = pcheck.check_paths([str(ws)], jobs=1)
    errors = [d for d in diags if d.severity == Severity.ERROR]
    assert bool(errors) == (not o["ok"]), [d.message for d in errors]
    # a note says the name is ambiguous, and which folder is used
    (note,) = {d.message for d in diags if d.code == "package-ambiguous"}
    used = other / "dup" if first == "other" else ws / "src" / "dup"
    assert note.startswith(f"$(find dup) is {used}: 2 folders hold a package named 'dup'")
    assert launch_main([str(main)]) == (0 if o["ok"] else 1)


def test_a_workspace_not_on_ros_package_path_comes_first(tmp_path):
    """As once its setup file is sourced (ROS_PACKAGE_PATH=ws/src:...)."""
    ws, other, main = _two_copies(tmp_path)
    from tvl_lsp.launch.packages import ros_packages
    pk = ros_packages(str(ws), {"ROS_PACKAGE_PATH": str(other)})
    assert pk["dup"] == str(ws / "src" / "dup") and pk.ambiguous["dup"][1:] == [str(other / "dup")]
    (o,) = oracle([dict(file=str(main), args={}, package_path=os.pathsep.join([str(ws / "src"), str(other)]))])
    lr = load_launch(str(main), {}, workspace_root=str(ws), env={"ROS_PACKAGE_PATH": str(other)})
    assert (lr.error is None) == o["ok"] is False


def test_find_sees_the_system_packages_debian_roslaunch_sees(tmp_path):
    """Debian's rospkg searches /usr/share last, one level deep (roslaunch, rosparam ...)."""
    f = tmp_path / "where.launch"
    f.write_text('<launch><param name="where" value="$(find rosparam)"/></launch>')
    (o,) = oracle([dict(file=str(f), args={}, package_path=str(SRC))])
    lr = load_launch(str(f), {}, workspace_root=str(tmp_path), env={"ROS_PACKAGE_PATH": str(SRC)})
    assert (lr.error is None) == o["ok"], (lr.error, o)
    if o["ok"]:
        assert lr.params["/where"] == o["values"]["/where"]


# ---------------------------------------------------------------- class 7

def test_a_file_named_on_the_command_line_that_is_not_a_launch_file_is_an_error(tmp_path):
    f = tmp_path / "robot.xml"
    f.write_text("<?xml version='1.0'?>\n<robot name='r'><link name='base'/></robot>\n")
    (o,) = oracle([dict(file=str(f), args={}, package_path=str(SRC))])
    assert not o["ok"] and "launch" in o["message"]
    diags = pcheck.check_paths([str(f)], jobs=1)
    assert [d.code for d in diags if d.severity == Severity.ERROR] == ["no-launch-root"]
    # found by walking a folder, it is passed over
    assert [d for d in pcheck.check_paths([str(tmp_path)], jobs=1)] == []
