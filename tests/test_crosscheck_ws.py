"""What is really wrong in the test workspace (examples/ws + tests/data/ws), determined by hand.

Pairings (haros.yaml, haros_scout.yaml, haros_crawler.yaml, same stem): turtlerand
generic.launch <-> generic.tvl, generic_alt.launch <-> generic_alt.tvl, scout generic.launch <->
generic.tvl, crawler_bringup generic.launch <-> crawler/models/crawler.tvl; the other launch
files (generic_nested.launch, first.launch, configs/teleop.launch, the crawler's includes) have no
model.

- every model feature has its top-level arg and every top-level arg is a feature, in all four
  pairs: no missing-arg / unmatched-arg;
- scout line 61: ``$(arg stereo_cam)`` / ``$(arg webcam)`` inside ``<group if="$(arg Simulation)">``:
  only ``Stereo_cam`` / ``Webcam`` are declared, so roslaunch stops with "requires the
  'stereo_cam' arg to be set" in every product with Simulation (the smallest is {Scout,
  Simulation}); it never gets to ``webcam``, which the same diagnostic names;
- crawler line 79: ``arg('battery')`` of the group arg ``battery`` declared without a value:
  "requires the 'battery' arg to be set" whenever Battery is selected (unset-arg);
- crawler lines 26-27: ``$(env CRAWLER_SIMULATION)`` / ``$(env CRAWLER_SERIAL_PORT)`` defaults:
  env-not-set when the variables are not set, and no unset-arg cascade for their args;
- constant conditions: turtlerand generic(_alt).launch ``if="$(arg Turtlesim)"`` (Turtlesim is
  mandatory); crawler line 25 ``if="true"``; lines 33/34 ``$(arg Frame)`` / ``$(arg Camera_3D)``
  inside ``<group if="$(arg Base)">`` (Base, Frame and Camera_3D are all mandatory children of
  Minimal: one is selected exactly when the others are);
- no element is dead, no node is loaded twice (``joy_node`` / ``joy_teleop`` are in both the
  Gamepad and the Joystick groups, which the model's constraints keep apart; the three
  ``camera`` nodes are a oneOf group), no arg is declared twice in a scope (the urdf_file args
  are in sibling groups);
- generic_alt.tvl writes ``and`` / ``or`` (infix-and-or); tests/data/models/coffee.tvl has a
  dead feature.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from testenv import DATA, make_ws
from tvl_lsp.project.check import check_paths

CROSS = {"missing-arg", "unmatched-arg", "undefined-arg", "dead-element", "constant-condition",
         "duplicate-node", "duplicate-arg", "invalid-condition", "void-model", "dead-feature",
         "false-optional"}

SCOUT = "src/scout/launch/generic.launch"
CB = "src/crawler_bringup/launch/generic.launch"
TR = "src/turtlerand/launch/generic.launch"
TR_ALT = "src/turtlerand/launch/generic_alt.launch"
ENV = ("CRAWLER_SIMULATION", "CRAWLER_SERIAL_PORT")


@pytest.fixture(scope="module")
def ws(tmp_path_factory) -> Path:
    return make_ws(tmp_path_factory.mktemp("crosscheck") / "ws")


def _check(ws: Path, jobs: int, **env):
    with pytest.MonkeyPatch.context() as mp:  # as on a machine where the robot is not set up
        for k in ENV:
            mp.delenv(k, raising=False)
        for k, v in env.items():
            mp.setenv(k, v)
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
        (SCOUT, 61, "undefined-arg"),
        (SCOUT, 61, "undefined-arg"),
        (CB, 25, "constant-condition"),
        (CB, 33, "constant-condition"),
        (CB, 34, "constant-condition"),
        (TR, 10, "constant-condition"),
        (TR_ALT, 10, "constant-condition"),
    ])


def test_everything_reported(diags, rel):
    """Nothing else either: the model errors, the environment and the unset arg."""
    got = sorted((rel(d), d.span.start.line + 1, d.code) for d in diags if d.code not in CROSS)
    assert got == [
        (CB, 26, "env-not-set"),
        (CB, 27, "env-not-set"),
        (CB, 79, "unset-arg"),
        # the product {Turtlerand, Turtlesim}: turtlesim listens on /turtle1/cmd_vel and nothing
        # publishes there (random_controller's and multiplexer's sources, haros.yaml's hints)
        (TR, 10, "topic-without-publisher"),
        ("src/turtlerand/launch/generic_alt.tvl", 10, "infix-and-or"),
        ("src/turtlerand/launch/generic_alt.tvl", 11, "infix-and-or"),
        # checked alone (no model): its feature args have no default, so roslaunch run with the
        # file's defaults fails -- a warning on each declaration (issue 14)
        ("src/turtlerand/launch/generic_nested.launch", 5, "unset-arg"),
        ("src/turtlerand/launch/generic_nested.launch", 6, "unset-arg"),
        ("src/turtlerand/launch/generic_nested.launch", 7, "unset-arg"),
    ]


def test_scout_undefined_stereo_cam_with_witness(diags):
    d, webcam = sorted((d for d in diags if d.code == "undefined-arg"), key=lambda d: d.span.start.col)
    assert _text(d) == "$(arg stereo_cam)"
    assert "`Stereo_cam`" in d.message          # the close name is suggested
    assert len(d.witness) == 15                 # every feature of the scout model
    assert {k for k, v in d.witness.items() if v} == {"Scout", "Simulation"}
    # roslaunch stops at stereo_cam; webcam, in the same value, is undeclared too: its own problem
    assert _text(webcam) == "$(arg webcam)" and "'webcam' is not declared" in webcam.message
    assert "did you mean `Webcam`?" in webcam.message and "stereo_cam" not in webcam.message
    assert webcam.witness == d.witness and webcam.data["stops_at"] == "stereo_cam"
    assert webcam.related[0].span == d.span


def test_crawler_battery_is_never_set(diags, rel):
    ds = [d for d in diags if d.code == "unset-arg" and "'battery'" in d.message]
    assert ds and all(rel(d) == CB and d.span.start.line + 1 == 79 for d in ds)
    assert _text(ds[0]) == "$(eval arg('battery') == 'None')"
    w = ds[0].witness
    assert len(w) == 22 and w["Battery"] and w["Minimal"]
    # smallest: the root, Minimal with its mandatory children and one choice per oneOf group
    assert {k for k, v in w.items() if v} == {"Crawler", "Minimal", "Base", "Camera_3D", "Frame",
                                                "Battery", "Tracks", "Realsense", "Short"}


def test_constant_conditions_point_at_the_condition(diags, rel):
    cc = {(rel(d), d.span.start.line + 1): _text(d) for d in diags if d.code == "constant-condition"}
    assert cc == {(CB, 25): "true", (CB, 33): "$(arg Frame)", (CB, 34): "$(arg Camera_3D)",
                  (TR, 10): "$(arg Turtlesim)", (TR_ALT, 10): "$(arg Turtlesim)"}


def test_unpaired_launch_files_are_clean_of_cross_problems(diags, rel):
    paired = {SCOUT, CB, TR, TR_ALT}
    others = [d for d in diags if d.code in CROSS and rel(d) not in paired]
    assert others == []
    # the launch file checked alone (its args free booleans) has nothing to report either, but
    # that its args have no default (roslaunch needs them on the command line)
    nested = [d for d in diags if rel(d) == "src/turtlerand/launch/generic_nested.launch"]
    assert sorted((d.code, d.data["arg"]) for d in nested) == [
        ("unset-arg", "Random"), ("unset-arg", "Teleop"), ("unset-arg", "Turtlesim")]


def test_model_with_a_dead_feature():
    diags = check_paths([str(DATA / "models")], jobs=1)
    dead = [d for d in diags if d.code == "dead-feature"]
    assert [d.data.get("feature") for d in dead] == ["Decaf"]
    assert [d.code for d in diags] == ["dead-feature"]


def test_output_does_not_depend_on_parallelism(ws, diags):
    par = _check(ws, 2)
    key = lambda d: (d.path, d.span, d.code, d.message, tuple(sorted((d.witness or {}).items())))
    assert [key(d) for d in par] == [key(d) for d in diags]


def test_unset_environment_is_reported_once_not_as_unset_args(diags, rel):
    # simulation / serialport default to $(env CRAWLER_...): when the variable is unset,
    # roslaunch stops at the $(env); the args are not "declared without value or default"
    env = [d for d in diags if d.code == "env-not-set" and rel(d) == CB]
    assert sorted((d.span.start.line + 1, _text(d)) for d in env) == [
        (26, "$(env CRAWLER_SIMULATION)"), (27, "$(env CRAWLER_SERIAL_PORT)")]
    cascades = [d for d in diags if d.code in ("unset-arg", "include-arg-no-value")
                and ("'simulation'" in d.message or "'serialport'" in d.message)]
    assert cascades == []


def test_set_environment_removes_the_env_diagnostics(ws, rel):
    diags = _check(ws, 1, CRAWLER_SIMULATION="false", CRAWLER_SERIAL_PORT="/dev/ttyUSB0")
    assert not [d for d in diags if d.code == "env-not-set"]
    assert [(rel(d), d.span.start.line + 1) for d in diags if d.code == "unset-arg"
            and "generic_nested" not in d.path] == [(CB, 79)]
