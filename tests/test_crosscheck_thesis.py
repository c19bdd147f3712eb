"""What is really wrong in the thesis's workspace (thesis/ws of the corpus), determined by hand.

Corpus suite: runs with ``--corpus DIR`` (tests/conftest.py); tests/test_crosscheck_ws.py is its
counterpart on the in-repository workspace.

Pairings (haros_*.yaml, same stem): turtlerand generic.launch <-> generic.tvl,
generic_alt.launch <-> generic_alt.tvl, turtlebot_bringup generic.launch <-> turtlebot.tvl,
lizi generic.launch <-> lizi generic.tvl; the other launch files have no model.

- every model feature has its top-level arg and every top-level arg is a feature, in all four
  pairs: no missing-arg / unmatched-arg;
- lizi line 74: ``$(arg depth_cam)`` / ``$(arg cam)`` inside ``<group if="$(arg Gazebo)">``:
  only ``Depth_cam`` / ``Cam`` are declared, so roslaunch stops with "requires the 'depth_cam'
  arg to be set" in every product with Gazebo (the smallest is {Lizi, Gazebo}); it never gets to
  ``cam``, which the same diagnostic names;
- turtlebot line 135: ``arg('battery')`` of the group arg ``battery`` declared without a value:
  "requires the 'battery' arg to be set" whenever Battery is selected (unset-arg);
- constant conditions: turtlerand generic(_alt).launch ``if="$(arg Turtlesim)"`` (Turtlesim is
  mandatory); turtlebot line 24 ``if="true"``; lines 32/33 ``$(arg Stacks)`` /
  ``$(arg Sensor_3D)`` inside ``<group if="$(arg Base)">`` (Base, Stacks and Sensor_3D are all
  mandatory children of Minimal: one is selected exactly when the others are);
- no element is dead, no node is loaded twice (Create/Roomba/Kobuki and the sensors are
  oneOf groups), no arg is declared twice in a scope (the urdf_file args are in sibling groups).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_lsp.project.check import check_paths

pytestmark = pytest.mark.corpus

CROSS = {"missing-arg", "unmatched-arg", "undefined-arg", "dead-element", "constant-condition",
         "duplicate-node", "duplicate-arg", "invalid-condition", "void-model", "dead-feature",
         "false-optional"}

LIZI = "src/lizi/launch/generic.launch"
TB = "src/turtlebot_bringup/launch/generic.launch"
TR = "src/turtlerand/launch/generic.launch"
TR_ALT = "src/turtlerand/launch/generic_alt.launch"


@pytest.fixture(scope="module")
def ws(corpus_dir) -> Path:
    return corpus_dir / "thesis" / "ws"


def _check(ws, jobs):
    with pytest.MonkeyPatch.context() as mp:  # as on a machine where the robot is not set up
        mp.delenv("TURTLEBOT_SIMULATION", raising=False)
        mp.delenv("TURTLEBOT_SERIAL_PORT", raising=False)
        return check_paths([str(ws)], jobs=jobs)


@pytest.fixture(scope="module")
def diags(ws):
    return _check(ws, 1)


@pytest.fixture(scope="module")
def rel(ws):
    return lambda d: str(Path(d.path).relative_to(ws))


def _text(d):
    line = Path(d.path).read_text().splitlines()[d.span.start.line]
    return line[d.span.start.col:d.span.end.col] if d.span.start.line == d.span.end.line else None


def test_exactly_the_real_cross_file_problems(diags, rel):
    got = sorted((rel(d), d.span.start.line + 1, d.code) for d in diags if d.code in CROSS)
    assert got == sorted([
        (LIZI, 74, "undefined-arg"),
        (LIZI, 74, "undefined-arg"),
        (TB, 24, "constant-condition"),
        (TB, 32, "constant-condition"),
        (TB, 33, "constant-condition"),
        (TR, 7, "constant-condition"),
        (TR_ALT, 9, "constant-condition"),
    ])


def test_lizi_undefined_depth_cam_with_witness(diags):
    d, cam = sorted((d for d in diags if d.code == "undefined-arg"), key=lambda d: d.span.start.col)
    assert _text(d) == "$(arg depth_cam)"
    assert "`Depth_cam`" in d.message            # the close name is suggested
    assert len(d.witness) == 16                  # every feature of the lizi model
    assert {k for k, v in d.witness.items() if v} == {"Lizi", "Gazebo"}
    # roslaunch stops at depth_cam; cam, in the same value, is undeclared too: its own problem
    assert _text(cam) == "$(arg cam)" and "'cam' is not declared" in cam.message
    assert "did you mean `Cam`?" in cam.message and "depth_cam" not in cam.message
    assert cam.witness == d.witness and cam.related[0].span == d.span


def test_turtlebot_battery_is_never_set(diags, rel):
    ds = [d for d in diags if d.code == "unset-arg" and "'battery'" in d.message]
    assert ds and all(rel(d) == TB and d.span.start.line + 1 == 135 for d in ds)
    w = ds[0].witness
    assert len(w) == 22 and w["Battery"] and w["Minimal"]
    # smallest: the root, Minimal with its mandatory children and one choice per oneOf group
    assert {k for k, v in w.items() if v} == {"TurtleBot", "Minimal", "Base", "Sensor_3D", "Stacks",
                                                "Battery", "Create", "Kinect", "Circles"}


def test_constant_conditions_point_at_the_condition(diags, rel):
    cc = {(rel(d), d.span.start.line + 1): _text(d) for d in diags if d.code == "constant-condition"}
    assert cc == {(TB, 24): "true", (TB, 32): "$(arg Stacks)", (TB, 33): "$(arg Sensor_3D)",
                  (TR, 7): "$(arg Turtlesim)", (TR_ALT, 9): "$(arg Turtlesim)"}


def test_unpaired_thesis_launch_files_are_clean_of_cross_problems(diags, rel):
    paired = {LIZI, TB, TR, TR_ALT}
    others = [d for d in diags if d.code in CROSS and rel(d) not in paired]
    assert others == []


def test_thesis_model_of_figure_15_has_its_dead_feature(corpus_dir):
    diags = check_paths([str(corpus_dir / "thesis" / "models")], jobs=1)
    dead = [d for d in diags if d.code == "dead-feature"]
    assert [d.data.get("feature") for d in dead] == ["J"]


def test_output_does_not_depend_on_parallelism(ws, diags):
    par = _check(ws, 2)
    key = lambda d: (d.path, d.span, d.code, d.message, tuple(sorted((d.witness or {}).items())))
    assert [key(d) for d in par] == [key(d) for d in diags]


def test_unset_environment_is_reported_once_not_as_unset_args(diags, rel):
    # simulation / serialport default to $(env TURTLEBOT_...): when the variable is unset,
    # roslaunch stops at the $(env); the args are not "declared without value or default"
    env = [d for d in diags if d.code == "env-not-set" and rel(d) == TB]
    assert sorted(d.span.start.line + 1 for d in env) == [25, 26]
    cascades = [d for d in diags if d.code in ("unset-arg", "include-arg-no-value")
                and ("'simulation'" in d.message or "'serialport'" in d.message)]
    assert cascades == []
