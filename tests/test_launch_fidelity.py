"""roslaunch fidelity (issue 14), without the real roslaunch: parameters as roslaunch sets them,
subst_value, pass_all_args, the typing of free args, rostest discovery.  (The same fixtures run
against the real roslaunch in test_launch_differential.py.)"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from tvl_lsp.base.diagnostics import Severity
from tvl_lsp.launch import analyse_launch, check_launch, find_packages, load_launch
from tvl_lsp.project.check import check_paths, free_top_args

WS = Path(__file__).resolve().parent / "data" / "launch" / "ws"
GAMMA = WS / "src" / "gamma"
PK = find_packages(str(WS))


def load(rel: str, **args):
    return load_launch(str(GAMMA / rel), {k: str(v).lower() if isinstance(v, bool) else v for k, v in args.items()},
                       packages=PK)


def analyse(text: str, path: str = "/w/pkg/launch/t.launch", **kw):
    return analyse_launch(text, path, packages=kw.pop("packages", {}), **kw)


def span_text(text: str, span) -> str:
    lines = text.splitlines(keepends=True)
    if span.start.line == span.end.line:
        return lines[span.start.line][span.start.col:span.end.col]
    return lines[span.start.line][span.start.col:] + "".join(lines[span.start.line + 1:span.end.line]) + \
        lines[span.end.line][:span.end.col]


# ---------------------------------------------------------------- rosparam's YAML

def test_degrees_and_radians_tags_and_expressions_are_floats():
    r = load("launch/yaml_tags.launch", use_file=True)
    assert r.error is None
    p = r.params
    assert p["/joint_limits/shoulder/max_velocity"] == pytest.approx(math.radians(150))
    assert p["/joint_limits/shoulder/min_position"] == pytest.approx(-math.pi / 2)
    assert p["/joint_limits/elbow/max_velocity"] == pytest.approx(math.pi / 2)
    assert p["/joint_limits/elbow/max_position"] == pytest.approx(3 * math.pi / 4)
    assert p["/joint_limits/elbow/quoted"] == "deg(90)"          # quoted: a string
    assert p["/joint_limits/wrist/home"] == 0.0
    assert p["/offsets"] == pytest.approx([math.radians(10), 0.5, 3])
    assert p["/tilt"] == pytest.approx(-math.pi / 4)
    assert p["/as_yaml"] == {"a": 1, "b": ["x", 2.5]}
    r = load("launch/yaml_tags.launch", use_file=False)
    assert r.params["/inline/spin"] == pytest.approx(2 * math.pi)
    assert r.params["/inline/not_an_angle"] == "degrees"
    # no invalid-param in --check
    a = analyse_launch((GAMMA / "launch/yaml_tags.launch").read_text(), str(GAMMA / "launch/yaml_tags.launch"),
                       packages=PK)
    assert [d.code for d in check_launch(a) if d.severity == Severity.ERROR] == []


@pytest.mark.parametrize("body", ["a: !degrees abc", "a: !radians foo", "a: !radians 1+"])
def test_a_tag_rosparam_cannot_convert_is_invalid_param(body):
    a = analyse(f"<launch><rosparam>{body}</rosparam></launch>")
    (f,) = [f for f in a.facts if f.code == "invalid-param"]
    assert "invalid YAML" in f.message


# ---------------------------------------------------------------- subst_value

def test_subst_value_resolves_the_body_and_the_file():
    r = load("launch/subst_value.launch", left=True)
    assert r.error is None
    p = r.params
    assert p["/planning/group"] == "left_arm"
    assert p["/planning/speed_scale"] == 0.25                     # typed after substitution
    assert p["/planning/base_frame"] == "ur_base_link"
    assert p["/planning/here"] == str(GAMMA / "launch")
    assert p["/arm_list"] == ["left_arm", "spare"]
    assert p["/controller_list"][0]["name"] == "left_arm_controller"
    assert p["/controller_list"][0]["joints"] == ["ur_joint_1", "ur_joint_2"]
    assert p["/left_arm_gains/p"] == 10                           # a substituted key
    assert p["/data_dir"] == str(GAMMA / "config")
    assert p["/literal/text"] == "$(arg prefix) kept as written"  # no subst_value: as written
    assert p["/mover/side"] == "left_arm" and p["/mover/limits/v"] == 0.25
    # the symbolic analysis has both cases
    a = analyse_launch((GAMMA / "launch/subst_value.launch").read_text(), str(GAMMA / "launch/subst_value.launch"),
                       packages=PK)
    assert a.free_args == ["left"]
    groups = {str(p.condition): p.data for p in a.params if p.name == "/planning/group"}
    assert groups == {"left": "left_arm", "!left": "right_arm"}


def test_substitution_findings_in_a_rosparam_body_have_exact_ranges():
    text = ('<launch>\n  <arg name="declared"/>\n  <rosparam subst_value="true">\n'
            '    a: $(arg nope)   # &amp; more\n'
            '    <![CDATA[b: <$(arg declared)>]]>\n'
            '    c: $(foo bar)\n  </rosparam>\n</launch>\n')
    a = analyse(text)
    # roslaunch stops at the first failing substitution: $(arg nope)
    (f,) = a.facts
    assert f.code == "undefined-arg" and span_text(text, f.span) == "$(arg nope)"
    text = text.replace("$(arg nope)", "fine")
    (f,) = analyse(text, features=[]).facts
    assert f.code == "unset-arg" and span_text(text, f.span) == "$(arg declared)"
    assert f.severity == Severity.WARNING          # the command line can give it
    text = text.replace("$(arg declared)", "fine")
    (f,) = analyse(text).facts
    assert f.code == "unknown-substitution" and span_text(text, f.span) == "$(foo bar)"
    # a tag that is not a substitution: roslaunch's resolve_args rejects it
    b = analyse('<launch><rosparam subst_value="true">c: $(foo bar)</rosparam></launch>')
    assert [f.code for f in b.facts] == ["unknown-substitution"]
    # without subst_value nothing is substituted, nothing is reported
    c = analyse('<launch><rosparam>a: $(arg nope)</rosparam></launch>')
    assert c.facts == [] and c.params[0].data == "$(arg nope)"


def test_substitution_findings_in_a_rosparam_file_point_at_the_file_attribute(tmp_path):
    (tmp_path / "p.yaml").write_text("x: $(arg missing)\n")
    text = f'<launch><rosparam file="{tmp_path}/p.yaml" subst_value="true"/></launch>'
    a = analyse(text, str(tmp_path / "t.launch"))
    (f,) = [f for f in a.facts if f.code == "undefined-arg"]
    assert span_text(text, f.span) == f"{tmp_path}/p.yaml"


def test_subst_value_must_be_a_boolean():
    a = analyse('<launch><rosparam subst_value="yes">{a: 1}</rosparam><rosparam subst_value="">{a: 1}</rosparam>'
                "</launch>")
    assert sorted(f.message.split(": ", 1)[1] for f in a.facts if f.code == "invalid-attribute-value") == [
        "bool value for subst_value must be non-empty", "invalid bool value for subst_value: yes"]


# ---------------------------------------------------------------- <param>

def test_params_are_named_and_typed_as_roslaunch_does():
    r = load("launch/node_params.launch", sim=True)
    assert r.error is None
    p = r.params
    assert p["/padded"] == "text with spaces"            # name and value stripped
    assert p["/flag"] is True and p["/switch"] is True
    assert p["/ratio"] == 3.0 and isinstance(p["/ratio"], float)
    assert p["/count"] == 7 and p["/word"] == "1.5"
    assert p["/version"] == "1_000" and p["/exp"] == "1e3"   # convert_value's quirks
    # inside <node>: the node's private namespace, whatever the name says
    assert p["/robot/driver/absolute"] == "inside" and "/absolute" not in p
    assert p["/robot/driver/private"] == "p" and p["/robot/driver/nested/deep"] == "d"
    # the scope's ~params first, then the node's own <param> (which wins)
    assert p["/robot/driver/rate"] == 50 and p["/robot/driver/gain"] == 0.5
    assert p["/robot/sub/second/rate"] == 20 and p["/top/rate"] == 20
    # a <rosparam param="/abs"> inside a node stays global; its dicts are unrolled
    assert p["/global_list"] == [1, 2] and p["/robot/driver/local_map/k"] == "v"
    assert "/robot/driver/gain" not in load("launch/node_params.launch", sim=False).params


def test_tilde_params_of_an_included_file_reach_the_includer_when_roslaunch_shares_its_list():
    # roslaunch's LoaderContext shares the params list with an include's context when it is not
    # empty: the child's ~from_child then applies to the includer's later nodes too
    p = load("launch/pass_all.launch", with_extra=False).params
    assert p["/after_include/from_child"] == "chomp" and p["/after_include/shared"] == "from_top"
    a = analyse('<launch><include file="$(dirname)/c.launch"/><node pkg="p" type="t" name="n"/></launch>',
                "/w/a.launch")
    assert a.params == []


def test_launch_json_gives_typed_values_and_sources(tmp_path):
    f = tmp_path / "t.launch"
    (tmp_path / "doc.txt").write_text("hello")
    f.write_text(f'<launch><param name="n" value="3"/><param name="t" textfile="{tmp_path}/doc.txt"/>'
                 '<param name="c" command="echo hi"/><rosparam>{l: [1, deg(180)]}</rosparam></launch>')
    r = subprocess.run([sys.executable, "-m", "tvl_lsp", "launch", str(f), "--json"], capture_output=True, text=True)
    out = json.loads(r.stdout)
    assert out["params"]["/n"] == 3 and out["params"]["/l"] == [1, math.pi]
    assert out["param_sources"] == {"/t": "textfile", "/c": "command"}
    assert out["params"]["/t"] == f"{tmp_path}/doc.txt" and out["params"]["/c"] == "echo hi"


# ---------------------------------------------------------------- pass_all_args and unset args

def _check(tmp_path: Path, files: dict[str, str]) -> list:
    for name, text in files.items():
        p = tmp_path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return check_paths([str(tmp_path / "main.launch")], jobs=1)


CHILD = '<launch><arg name="robot_ip"/><node pkg="p" type="t" name="d" args="$(arg robot_ip)"/></launch>'


def test_an_arg_an_include_with_pass_all_args_needs_is_a_warning(tmp_path):
    diags = _check(tmp_path, {"child.launch": CHILD, "main.launch":
                              '<launch><include file="$(dirname)/child.launch" pass_all_args="true"/></launch>'})
    (d,) = [d for d in diags if d.code == "unset-arg"]
    assert d.severity == Severity.WARNING and "command line" in d.message
    assert "included file child.launch" in d.message


def test_an_arg_an_include_without_pass_all_args_needs_is_an_error(tmp_path):
    diags = _check(tmp_path, {"child.launch": CHILD, "main.launch":
                              '<launch><include file="$(dirname)/child.launch"/></launch>'})
    (d,) = [d for d in diags if d.code == "unset-arg"]
    assert d.severity == Severity.ERROR and "pass_all_args" in d.message


def test_an_arg_only_forwarded_and_required_below_is_reported():
    # issue 14, class 6: roslaunch run with the file's defaults fails; --check says so
    diags = check_paths([str(GAMMA / "launch/forwarded.launch")], jobs=1)
    (d,) = [d for d in diags if d.code == "unset-arg"]
    assert d.severity == Severity.WARNING and "'model'" in d.message
    assert free_top_args((GAMMA / "launch/forwarded.launch").read_text(), str(GAMMA / "launch/forwarded.launch"),
                         str(WS)) == ["debug"]


# ---------------------------------------------------------------- which args are booleans

@pytest.mark.parametrize("child,free", [
    ('<include file="$(dirname)/inc/$(arg x)_pipeline.launch.xml"/>', []),          # a file name
    ('<node pkg="p" type="t" name="n" if="$(arg x)"/>', ["x"]),                      # a condition
    ('<param name="p" value="$(arg x)"/>', []),                                      # a parameter value
    ('<group if="$(eval arg(\'x\') == \'ompl\')"/>', []),                            # string comparison
    ('<group if="$(eval not arg(\'x\') and true)"/>', ["x"]),                        # boolean operand
    ('<arg name="y" value="$(arg x)"/><group unless="$(arg y)"/>', ["x"]),           # followed through y
    ('<arg name="y" value="$(arg x)_suffix"/><group if="$(arg y)"/>', []),          # part of a string
    ('<node pkg="p" type="t" name="n" args="$(eval arg(\'x\') + \'/\')"/>', []),    # arithmetic
])
def test_free_args_follow_the_value_through_pass_all_args(tmp_path, child, free):
    (tmp_path / "child.launch").write_text(f'<launch><arg name="x" default="a"/>{child}</launch>')
    # (a boolean default where x is a boolean: a default that is none is no free arg, below)
    default = "false" if free else "ompl"
    main = (f'<launch><arg name="x" default="{default}"/><include file="$(dirname)/child.launch" '
            'pass_all_args="true"/></launch>')
    (tmp_path / "main.launch").write_text(main)
    assert free_top_args(main, str(tmp_path / "main.launch")) == free
    # and through an <arg> of the include
    main2 = main.replace(' pass_all_args="true"/>', '><arg name="x" value="$(arg x)"/></include>')
    assert free_top_args(main2, str(tmp_path / "main.launch")) == free


def test_a_string_arg_forwarded_by_pass_all_args_gets_no_meaningless_witness():
    # issue 14, class 7: planner is a file name below; true/false would give include-not-found
    diags = check_paths([str(GAMMA / "launch/pass_all.launch")], jobs=1)
    assert [d for d in diags if d.severity == Severity.ERROR] == []
    assert not any("false_pipeline" in d.message or "true_pipeline" in d.message for d in diags)


# ---------------------------------------------------------------- rostest files

def test_check_on_a_folder_finds_rostest_files():
    diags = check_paths([str(GAMMA)], jobs=1)
    assert not [d for d in diags if d.severity == Severity.ERROR]
    from tvl_lsp.project.workspace import discover_files
    found = discover_files([str(GAMMA)])
    assert str(GAMMA / "test" / "params.test") in found.launches
    assert len([f for f in found.launches if f.endswith(".launch.xml")]) == 2


# ---------------------------------------------------------------- the command line as roslaunch reads it

def test_an_arg_the_command_line_cannot_set_is_not_free_and_its_use_is_an_error(tmp_path):
    # roslaunch ignores 3d_sensor:=... (not a legal ROS name): the arg is never set
    main = '<launch><arg name="3d_sensor"/><param name="s" value="$(arg 3d_sensor)"/></launch>'
    diags = _check(tmp_path, {"main.launch": main})
    (d,) = [d for d in diags if d.code == "unset-arg"]
    assert d.severity == Severity.ERROR and "3d_sensor:=" in d.message
    assert free_top_args(main, str(tmp_path / "main.launch")) == []
    lr = load_launch(str(tmp_path / "main.launch"), {"3d_sensor": "kinect"}, packages={})
    assert lr.error is not None and any("roslaunch ignores '3d_sensor:=kinect'" in w for w in lr.warnings)


def test_the_uses_of_an_arg_with_a_default_are_the_uses_of_the_args_its_default_reads(tmp_path):
    # base only reaches a parameter through model's default: it is a string, not a boolean
    main = ('<launch><arg name="base"/><arg name="model" default="$(arg base).urdf"/>'
            '<param name="m" value="$(arg model)"/></launch>')
    assert free_top_args(main, str(tmp_path / "main.launch")) == []
    main = ('<launch><arg name="on"/><arg name="cam" default="$(arg on)"/>'
            '<node pkg="p" type="t" name="n" if="$(arg cam)"/></launch>')
    assert free_top_args(main, str(tmp_path / "main.launch")) == ["on", "cam"]


def test_a_relative_include_is_a_warning(tmp_path):
    # roslaunch opens a relative include file from the folder it is started in
    text = '<launch>\n  <include file="launch/part.launch"/>\n</launch>\n'
    diags = _check(tmp_path, {"main.launch": text, "launch/part.launch": "<launch/>"})
    (d,) = [d for d in diags if d.code == "include-not-found"]
    assert d.severity == Severity.WARNING and "relative path" in d.message
    assert span_text(text, d.span) == "launch/part.launch"


def test_a_program_missing_from_a_package_of_the_workspace_is_a_warning():
    # roslaunch on the sources cannot run $(find delta)/scripts/no_such_generator.py: the package
    # is in the workspace, the file is not in it (a build could put a program of that name in
    # the package's lib folder, where $(find) looks too: a warning)
    diags = check_paths([str(WS / "src" / "delta" / "launch" / "missing_script.launch")], jobs=1)
    (d,) = [d for d in diags if d.code == "command-not-found"]
    assert d.severity == Severity.WARNING and "package delta has no such file" in d.message


def test_an_undeclared_arg_the_command_line_may_give_is_a_warning_and_a_typo_an_error(tmp_path):
    # roslaunch puts its whole command line into the root file's args, declared or not
    diags = check_paths([str(WS / "src" / "delta" / "launch" / "undeclared_cmdline.launch")], jobs=1)
    (d,) = [d for d in diags if d.code == "undefined-arg"]
    assert d.severity == Severity.WARNING and "bag_filename:=" in d.message
    # close to a declared arg: a typo, an error
    main = '<launch><arg name="Depth_cam" default="x"/><param name="p" value="$(arg depth_cam)"/></launch>'
    (d,) = [d for d in _check(tmp_path, {"main.launch": main}) if d.code == "undefined-arg"]
    assert d.severity == Severity.ERROR
    # an included file only gets what its <include> passes
    diags = _check(tmp_path, {"child.launch": '<launch><param name="p" value="$(arg bag)"/></launch>',
                              "main.launch": '<launch><include file="$(dirname)/child.launch"/></launch>'})
    (d,) = [d for d in diags if d.code == "undefined-arg"]
    assert d.severity == Severity.ERROR


def test_attributes_reading_an_arg_whose_default_failed_report_nothing():
    # roslaunch stops at the first default that reads the unset 'camera' (a warning: the command
    # line gives it); the remaps, names and params reading points_in / points_out / test_name
    # are never computed, so no check looks at them (tvl-lsp once called them invalid remaps)
    path = WS / "src" / "delta" / "launch" / "unset_arg_in_default.launch"
    diags = check_paths([str(path)], jobs=1)
    assert [d for d in diags if d.severity == Severity.ERROR] == []
    assert {d.code for d in diags} == {"unset-arg"}
    # with camera:=front, what roslaunch 1.15 loads (recorded from it)
    r = load_launch(str(path), {"camera": "front"}, packages=PK)
    assert r.error is None
    assert [(n["name"], n["remaps"]) for n in r.nodes] == [
        ("/front/points/flip", [["/front/points/halt", "/front_upright/points/halt"], ["~in", "/front/points"],
                               ["~out", "/front_upright/points"]])]
    assert r.params == {"/front/points/flip/topic": "/front_upright/points",
                        "/front/points/flip/front/points/frame": "front_link"}
    assert load_launch(str(path), {}, packages=PK).error is not None


def test_elements_under_a_group_whose_ns_reads_an_unset_arg_are_not_dead():
    # robot:=... comes from the command line: then both groups and all their nodes load (as
    # roslaunch 1.15 loads them, recorded below); --check once called the nodes in the first
    # group and the second group "never loaded whatever the file's args"
    path = WS / "src" / "delta" / "launch" / "unset_arg_group_ns.launch"
    diags = check_paths([str(path)], jobs=1)
    assert [d.code for d in diags] == ["unset-arg", "unset-arg"]
    assert all(d.severity == Severity.WARNING for d in diags)
    nodes = lambda **a: sorted(n["name"] for n in load_launch(str(path), a, packages=PK).nodes)  # noqa: E731
    assert nodes(robot="r1") == ["/r1/arm", "/r1/arm/gripper"]
    assert nodes(robot="r1", with_arm="false") == ["/r1/base"]
    assert load_launch(str(path), {}, packages=PK).error is not None


def test_one_error_names_every_unused_include_arg_as_roslaunch_does():
    # jsk_robot's lead_teleop.launch passes joy and port to a file that declares neither:
    # roslaunch 1.15 names both in one error, in the include's order; tvl-lsp launch named the
    # first only.  The oracle's messages, recorded:
    path = WS / "src" / "delta" / "launch" / "unused_include_args.launch"
    child = path.with_name("unused_include_args_child.launch")
    expected = {(): f"unused args [device, port, baud] for include of [{child}]",
                (("serial", "false"),): f"unused args [device, port] for include of [{child}]"}
    for args, message in expected.items():
        lr = load_launch(str(path), dict(args), packages=PK)
        assert (lr.error, lr.error_code) == (message, "unused-include-arg")
    # --check keeps one diagnostic per unused arg, each on its own <arg>
    diags = check_paths([str(path)], jobs=1)
    assert [(d.code, d.span.start.line + 1) for d in diags] == [("unused-include-arg", n) for n in (7, 9, 10)]
    assert "unused args [baud]" in diags[2].message and "when serial" in diags[2].message


def test_an_arg_the_file_sets_with_value_in_some_case_is_not_free():
    # summit_xl_sim's summit_xls_complete.launch: <arg if="$(arg omni_drive)" name="X" value="true"/>
    # and <arg unless="$(arg omni_drive)" name="X" default="true"/>.  roslaunch with the file's
    # defaults loads it; --check took X as a free arg given on the command line in every product
    # and called the <arg value> an error ("cannot override arg").  The oracle's answers, recorded:
    path = WS / "src" / "delta" / "launch" / "conditional_value_arg.launch"
    expected = {(): (["/base", "/planar"], True),
                (("omni_drive", "false"),): (["/base"], False),
                (("omni_drive", "false"), ("planar_move", "true")): (["/base", "/planar"], True)}
    for args, (names, param) in expected.items():
        lr = load_launch(str(path), dict(args), packages=PK)
        assert lr.error is None, lr.error
        assert sorted(n["name"] for n in lr.nodes) == names
        assert lr.params["/base/planar_move"] is param
    lr = load_launch(str(path), {"planar_move": "true"}, packages=PK)
    assert lr.error == "Invalid <arg> tag: cannot override arg 'planar_move', which has already been set"
    assert not [d for d in check_paths([str(path)], jobs=1) if d.code == "arg-already-set"]
