"""The Python launch-file front end beyond the oracle's answers: exact ranges into the .py text
(argument names, conditions, nodes), declines at the construct that stops the analysis, bad and
hostile input (never run, never a crash), the pairing with a model, includes across dialects."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest

from tvl_lsp.base.formula import Var, evaluate, variables
from tvl_lsp.launch import analyse_any, is_launch_path, load_any
from tvl_lsp.launch.ros2 import analyse_launch2, free_args2, load_launch2
from tvl_lsp.project.check import check_document

HERE = Path(__file__).resolve().parent
WS = HERE / "data" / "ros2py" / "ws"
BRINGUP = WS / "src" / "py_bringup" / "launch"
ENV = {"PATH": os.environ.get("PATH", "/usr/bin:/bin")}

HEAD = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, OpaqueFunction
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
"""


def _ws(tmp_path: Path, body: str, name: str = "t.launch.py") -> Path:
    pkg = tmp_path / "ws" / "src" / "demo_pkg"
    (pkg / "launch").mkdir(parents=True, exist_ok=True)
    (pkg / "package.xml").write_text(
        '<?xml version="1.0"?><package format="3"><name>demo_pkg</name><version>0.0.0</version>'
        '<description>d</description><maintainer email="a@b.c">a</maintainer><license>MIT</license>'
        '<export><build_type>ament_cmake</build_type></export></package>')
    p = pkg / "launch" / name
    p.write_text(body)
    return p


def _text_at(path: Path, span) -> str:
    lines = path.read_text().splitlines()
    assert span.start.line == span.end.line
    return lines[span.start.line][span.start.col:span.end.col]


def _analyse(p: Path, **kw):
    return analyse_launch2(p.read_text(), str(p), workspace_root=str(p.parents[3]), env=ENV, **kw)


# ------------------------------------------------------------------ names and ranges

def test_launch_py_files_are_launch_files():
    for name in ("robot.launch.py", "robot_launch.py", "bringup.launch.xml"):
        assert is_launch_path(name)
    assert not is_launch_path("setup.py")


def test_every_argument_name_has_its_exact_range(tmp_path):
    p = _ws(tmp_path, HEAD + """

def setup(context):
    name = context.launch_configurations['robot']
    rate = context.launch_configurations.get('rate', '5')
    return [Node(package='demo_pkg', executable='x', name=name)]


def generate_launch_description():
    use_cam = LaunchConfiguration('use_cam')
    return LaunchDescription([
        DeclareLaunchArgument('use_cam', default_value='false'),
        DeclareLaunchArgument('robot', default_value='r1'),
        Node(package='demo_pkg', executable='cam', name='cam', condition=IfCondition(use_cam)),
        Node(package='demo_pkg', executable='b', name='b', namespace=LaunchConfiguration('robot')),
        OpaqueFunction(function=setup),
    ])
""")
    la = _analyse(p)
    decls = {a.name: a for a in la.feature_args}
    assert set(decls) == {"use_cam", "robot"}
    for a in decls.values():
        assert _text_at(p, a.name_span) == a.name
    uses = [(s.args[0], s) for e in la.elements for s in e.substitutions if s.kind == "var"]
    names = sorted({n for n, _ in uses})
    assert names == ["rate", "robot", "use_cam"]
    for n, s in uses:
        assert s.name_span is not None and _text_at(p, s.name_span) == n
    # the facts' look-up finds them by name (what references / rename use)
    from tvl_lsp.project.facts import arg_name_span, arg_uses
    from tvl_lsp.base.text import LineIndex
    idx = LineIndex(p.read_text())
    got = {_text_at(p, arg_name_span(s, idx)) for _, s in arg_uses(la, str(p), "robot")}
    assert got == {"robot"} and len(arg_uses(la, str(p), "robot")) >= 2


def test_node_and_condition_ranges_point_into_the_python_text(tmp_path):
    p = _ws(tmp_path, HEAD + """
def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('use_cam', default_value='false'),
        Node(package='demo_pkg', executable='cam', name='cam',
             condition=IfCondition(LaunchConfiguration('use_cam'))),
    ])
""")
    la = _analyse(p)
    node = next(e for e in la.elements if e.tag == "node")
    assert _text_at(p, node.attrs["if"].value_span) == "IfCondition(LaunchConfiguration('use_cam'))"
    assert _text_at(p, node.attrs["name"].value_span) == "cam"
    assert _text_at(p, node.attrs["package"].value_span) == "'demo_pkg'"
    assert node.span.start.line == 9 and node.span.end.line == 10
    n = la.nodes[0]
    assert n.name == "/cam" and variables(n.condition) == {"use_cam"}


# ------------------------------------------------------------------ declines

def test_a_branch_on_an_environment_variable_declines_there_and_never_guesses(tmp_path):
    p = _ws(tmp_path, HEAD + """import os


def generate_launch_description():
    nodes = [Node(package='demo_pkg', executable='a', name='a')]
    if os.environ.get('TVL_TEST_UNSET_VARIABLE') == 'x':
        nodes.append(Node(package='demo_pkg', executable='b', name='b'))
    return LaunchDescription(nodes)
""")
    la = _analyse(p)
    notes = [d for d in la.diagnostics if d.code == "launch-not-analysable"]
    assert len(notes) == 1 and notes[0].span.start.line == 10
    assert "TVL_TEST_UNSET_VARIABLE" in notes[0].message
    assert not la.nodes and not [d for d in la.diagnostics if d.severity == 1]
    # the concrete load knows its environment: not set, so no branch
    assert [n["name"] for n in load_launch2(str(p), {}, env=ENV).nodes] == ["/a"]
    # set: known, and the branch taken
    res = load_launch2(str(p), {}, env={**ENV, "TVL_TEST_UNSET_VARIABLE": "x"})
    assert [n["name"] for n in res.nodes] == ["/a", "/b"]


def test_an_unknown_action_declines_at_its_line_and_makes_later_configurations_unknown(tmp_path):
    p = _ws(tmp_path, HEAD + """from some_vendor.launch import make_magic


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('flag', default_value='true'),
        make_magic(),
        Node(package='demo_pkg', executable='a', name='a', condition=IfCondition(LaunchConfiguration('flag'))),
    ])
""")
    la = _analyse(p)
    notes = [f for f in la.facts if f.code == "launch-not-analysable"]
    assert notes and notes[0].span.start.line == 11
    assert not [f for f in la.facts if f.severity == 1]
    # the concrete load declines at the import (ros2 launch needs the module installed)
    res = load_launch2(str(p), {}, env=ENV)
    assert res.error_type == "NotAnalysed" and res.error_line == 6


def test_opaque_function_reads_each_case_of_the_arguments(tmp_path):
    p = _ws(tmp_path, HEAD + """

def setup(context):
    if context.launch_configurations['mode'] == 'true':
        return [Node(package='demo_pkg', executable='a', name='fast')]
    return [Node(package='demo_pkg', executable='b', name='slow'), Node(package='demo_pkg', executable='c', name='x')]


def generate_launch_description():
    return LaunchDescription([DeclareLaunchArgument('mode', default_value='false'), OpaqueFunction(function=setup)])
""")
    la = _analyse(p, features=["mode"])
    by = {n.name: n.condition for n in la.nodes}
    assert set(by) == {"/fast", "/slow", "/x"}
    assert evaluate(by["/fast"], {"mode": True}) and not evaluate(by["/fast"], {"mode": False})
    assert evaluate(by["/slow"], {"mode": False}) and not evaluate(by["/slow"], {"mode": True})
    assert [n["name"] for n in load_launch2(str(p), {"mode": "true"}, env=ENV).nodes] == ["/fast"]


def test_opaque_function_raising_on_a_missing_configuration_is_an_error_where_it_happens(tmp_path):
    p = _ws(tmp_path, HEAD + """

def setup(context):
    return [Node(package='demo_pkg', executable='a', name=context.launch_configurations['robot'])]


def generate_launch_description():
    return LaunchDescription([OpaqueFunction(function=setup)])
""")
    la = _analyse(p)
    errs = [f for f in la.facts if f.code == "python-error"]
    assert errs and "KeyError" in errs[0].message
    res = load_launch2(str(p), {}, env=ENV)
    assert res.error_type == "KeyError"
    assert not load_launch2(str(p), {"robot": "r1"}, env=ENV).error


# ------------------------------------------------------------------ bad and hostile input

@pytest.mark.parametrize("body,code", [
    ("def generate_launch_description(:\n    pass\n", "python-syntax"),
    ("x = (" * 300 + ")" * 300 + "\n", "python-syntax"),
    ("\x00\n", "python-syntax"),
])
def test_syntax_errors_get_pythons_message_at_its_range(tmp_path, body, code):
    p = _ws(tmp_path, body)
    diags = check_document(str(p))
    got = [d for d in diags if d.code == code]
    assert got and got[0].severity == 1, [(d.code, d.message) for d in diags]


def test_syntax_error_range_is_exact(tmp_path):
    p = _ws(tmp_path, HEAD + "def generate_launch_description():\n    return LaunchDescription([Node(a=1 b=2)])\n")
    d = next(d for d in check_document(str(p)) if d.code == "python-syntax")
    assert d.span.start.line == 6 and "SyntaxError" in d.message
    assert _text_at(p, d.span) in ("1 b", "1", "b", "=1 b")


@pytest.mark.parametrize("body", [
    # never run: exec / eval / __import__ / subprocess / writing files / an endless loop
    "import os\ndef generate_launch_description():\n    exec('import os; os.remove(\"/x\")')\n",
    "def generate_launch_description():\n    return eval('1+1')\n",
    "def generate_launch_description():\n    m = __import__('os')\n    return m\n",
    "import subprocess\ndef generate_launch_description():\n    subprocess.run(['touch', '/tmp/tvl_lsp_pwned'])\n"
    "    return LaunchDescription([])\nfrom launch import LaunchDescription\n",
    "def generate_launch_description():\n    open('/tmp/tvl_lsp_pwned', 'w').write('x')\n",
    "def generate_launch_description():\n    while True:\n        pass\n",
    "def f(n):\n    return f(n + 1)\ndef generate_launch_description():\n    return f(0)\n",
    "def generate_launch_description():\n    return 'x' * 10 ** 12\n",
    "def generate_launch_description():\n    x = []\n    for i in range(10 ** 9):\n        x.append(i)\n",
    "X = 2 ** 10 ** 10\ndef generate_launch_description():\n    pass\n",
    "def generate_launch_description():\n    return [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]\n",
])
def test_hostile_code_is_never_run_and_is_bounded(tmp_path, body):
    marker = Path("/tmp/tvl_lsp_pwned")
    if marker.exists():
        marker.unlink()
    p = _ws(tmp_path, body)
    t0 = time.process_time()
    diags = check_document(str(p))
    res = load_launch2(str(p), {}, env=ENV)
    assert time.process_time() - t0 < 8
    assert not marker.exists()
    assert not [d for d in diags if d.code == "internal-error"]
    assert res.error is not None or not res.nodes   # declined or refused, never a node list made up


def test_a_huge_literal_is_bounded(tmp_path):
    p = _ws(tmp_path, "X = [" + "1," * 200_000 + "]\ndef generate_launch_description():\n    return X\n")
    t0 = time.process_time()
    check_document(str(p))
    assert time.process_time() - t0 < 8


# ------------------------------------------------------------------ dialects and pairing

def test_dialect_entry_points_take_python_files():
    p = BRINGUP / "basic.launch.py"
    la = analyse_any(p.read_text(), str(p), workspace_root=str(WS), env=ENV)
    assert la.dialect == "ros2" and la.nodes
    res = load_any(str(p), {"use_camera": "true"}, workspace_root=str(WS), env=ENV)
    assert {n["name"] for n in res.nodes} >= {"/r1/lidar", "/camera"}


def test_free_args_of_a_python_file_are_its_boolean_arguments():
    p = BRINGUP / "basic.launch.py"
    assert set(free_args2(p.read_text(), str(p))) == {"use_lidar", "use_camera"}
    p = BRINGUP / "opaque.launch.py"
    # read as strings inside the OpaqueFunction: not free booleans
    assert free_args2(p.read_text(), str(p)) == []


def test_xml_includes_python_and_python_includes_xml_and_yaml():
    p = BRINGUP / "xml_to_py.launch.xml"
    la = analyse_launch2(p.read_text(), str(p), workspace_root=str(WS), env=ENV)
    drv = [n for n in la.nodes if n.name == "/driver"]
    assert drv and drv[0].condition == Var("use_driver")
    assert drv[0].element.path.endswith("driver.launch.py")
    p = BRINGUP / "includes.launch.py"
    la = analyse_launch2(p.read_text(), str(p), workspace_root=str(WS), env=ENV, features=["use_xml", "use_yaml"])
    srcs = {os.path.basename(n.element.path) for n in la.nodes}
    assert srcs == {"driver.launch.py", "lidar.launch.xml", "cam.launch.yaml"}


def test_generic_python_file_paired_with_its_model_finds_the_planted_problems():
    p = WS / "src" / "py_robot" / "launch" / "issues.launch.py"
    diags = check_document(str(p))
    codes = {(d.code, _text_at(p, d.span) if d.span.start.line == d.span.end.line else "") for d in diags}
    assert ("unmatched-arg", "Sonar") in codes
    assert any(c == "missing-arg" for c, _ in codes)
    assert any(c == "dead-element" for c, _ in codes)
    assert ("constant-condition", "IfCondition(LaunchConfiguration('Base'))") in codes
    dup = next(d for d in diags if d.code == "duplicate-node")
    assert dup.witness is not None and dup.witness.get("Camera") and dup.witness.get("Diff")
    assert not [d for d in diags if d.severity == 1]


def test_the_clean_generic_python_file_gets_nothing():
    p = WS / "src" / "py_robot" / "launch" / "generic.launch.py"
    diags = check_document(str(p))
    assert [d for d in diags if d.severity <= 2] == [], [(d.code, d.message) for d in diags]


# ------------------------------------------------------------------ the command line

def test_cli_lists_event_handlers_apart(capsys):
    from tvl_lsp.main import main
    f = str(BRINGUP / "events.launch.py")
    assert main(["launch", f, "--workspace", str(WS), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [n["name"] for n in out["nodes"]] == ["/spawner"]
    ev = {e["event"]: [n["name"] for n in e["nodes"]] for e in out["events"]}
    assert ev == {"OnProcessExit": ["/controller_spawner"], "OnProcessStart": ["/watcher"]}
    assert main(["launch", f, "--workspace", str(WS)]) == 0
    text = capsys.readouterr().out
    assert "events (" in text and "OnProcessExit of Node(spawner)" in text and "/controller_spawner" in text


def test_cli_says_which_line_stops_the_analysis(capsys, tmp_path):
    from tvl_lsp.main import main
    p = _ws(tmp_path, HEAD + """import sys


def generate_launch_description():
    nodes = []
    for a in sys.argv:
        nodes.append(Node(package='demo_pkg', executable='x', name='n'))
    return LaunchDescription(nodes)
""")
    assert main(["launch", str(p)]) == 1
    out = capsys.readouterr().out
    assert "not analysable" in out and "t.launch.py:11" in out and "sys.argv" in out
    assert main(["launch", str(p), "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["error_type"] == "NotAnalysed" and d["error_line"] == 11 and d["nodes"] == []


def test_cli_obsolete_keyword_is_launchs_error(capsys):
    from tvl_lsp.main import main
    assert main(["launch", str(BRINGUP / "obsolete.launch.py"), "--workspace", str(WS), "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert "TypeError" in d["error"] and d["error_line"] == 8


def test_an_include_that_is_not_followed_still_sets_its_args_and_leaks_unknowns(tmp_path):
    """launch sets an include's args before loading the file, and an include does not scope:
    after an include tvl-lsp cannot follow (a package outside the workspace), a configuration
    nobody here declares is unknown, not an error."""
    p = _ws(tmp_path, HEAD + """from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([
        IncludeLaunchDescription(PythonLaunchDescriptionSource(
            PathJoinSubstitution([FindPackageShare('other_pkg'), 'launch', 'x.launch.py'])),
            launch_arguments={'passed': 'p1'}.items()),
        Node(package='demo_pkg', executable='a', name='a',
             parameters=[{'p': LaunchConfiguration('passed'), 'q': LaunchConfiguration('from_include')}]),
    ])
""")
    la = _analyse(p)
    assert not [f for f in la.facts if f.code == "undefined-arg"], [(f.code, f.message) for f in la.facts]
    x = p.parent / "x.launch.xml"
    x.write_text('<launch>\n  <include file="$(find-pkg-share other_pkg)/launch/y.launch.xml">\n'
                 '    <arg name="passed" value="p1"/>\n  </include>\n'
                 '  <node pkg="demo_pkg" exec="a" name="a">\n    <param name="p" value="$(var passed)"/>\n'
                 '    <param name="q" value="$(var from_include)"/>\n  </node>\n</launch>\n')
    la = analyse_launch2(x.read_text(), str(x), workspace_root=str(p.parents[3]), env=ENV)
    assert not [f for f in la.facts if f.code == "undefined-arg"], [(f.code, f.message) for f in la.facts]


def test_a_launch_testing_file_is_declined_not_an_error(tmp_path):
    p = _ws(tmp_path, "import launch\nimport launch_testing\n\n\ndef generate_test_description():\n"
                      "    return launch.LaunchDescription([])\n", name="test_x_launch.py")
    diags = check_document(str(p))
    assert [d.code for d in diags] == ["launch-not-analysable"] and "launch_testing" in diags[0].message


def test_an_undeclared_configuration_with_a_default_is_not_a_constant(tmp_path):
    """LaunchConfiguration('log', default='true') that no DeclareLaunchArgument declares: ros2 launch
    sets log:=false from the command line all the same, so its condition is not always true."""
    p = _ws(tmp_path, HEAD + """
def generate_launch_description():
    log = LaunchConfiguration('log', default='true')
    return LaunchDescription([Node(package='demo_pkg', executable='a', name='a', condition=IfCondition(log))])
""")
    diags = check_document(str(p))
    assert not [d for d in diags if d.code in ("constant-condition", "dead-element")], [d.message for d in diags]


def test_a_newer_launch_name_is_unknown_in_the_analysis_and_declined_by_the_load(tmp_path):
    """PathSubstitution is not in launch 3.7.1 (the modelled version, where importing it fails): the
    concrete load declines at the import; the symbolic analysis goes on with an unknown value."""
    p = _ws(tmp_path, HEAD + """from launch.substitutions import PathSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    cfg = PathSubstitution(FindPackageShare('demo_pkg')) / 'config' / 'a.yaml'
    return LaunchDescription([Node(package='demo_pkg', executable='a', name='a', parameters=[cfg])])
""")
    res = load_launch2(str(p), {}, env=ENV)
    assert res.error_type == "NotAnalysed" and "PathSubstitution" in res.error and res.error_line == 6
    la = _analyse(p)
    assert [n.name for n in la.nodes] == ["/a"]
    assert not [f for f in la.facts if f.severity == 1]


def test_xacro_and_programs_are_never_run(tmp_path):
    p = _ws(tmp_path, HEAD + """import subprocess
import xacro


def generate_launch_description():
    desc = xacro.process_file('/nonexistent/robot.urdf.xacro').toxml()
    rev = subprocess.check_output(['git', 'rev-parse', 'HEAD'])
    return LaunchDescription([Node(package='demo_pkg', executable='rsp', name='rsp',
                                   parameters=[{'robot_description': desc, 'rev': rev}])])
""")
    res = load_launch2(str(p), {}, env=ENV)
    assert res.error_type == "NotAnalysed" and "xacro" in res.error and res.error_line == 11
    la = _analyse(p)
    assert [n.name for n in la.nodes] == ["/rsp"] and not [f for f in la.facts if f.severity == 1]


def test_a_declined_generic_file_does_not_call_every_feature_missing(tmp_path):
    """Where the analysis declines, a declaration may be hidden: no missing-arg then."""
    p = _ws(tmp_path, HEAD + """import os


def generate_launch_description():
    args = [DeclareLaunchArgument('A', default_value='false')]
    if os.environ.get('TVL_TEST_UNSET_VARIABLE'):
        args.append(DeclareLaunchArgument('B', default_value='false'))
    return LaunchDescription(args)
""", name="gen.launch.py")
    (p.parent / "gen.tvl").write_text("root R { group allOf { opt A, opt B } }\n")
    diags = check_document(str(p))
    assert "launch-not-analysable" in {d.code for d in diags}
    assert not [d for d in diags if d.code == "missing-arg"], [d.message for d in diags]


def test_a_pytest_file_without_generate_launch_description_is_declined_not_an_error(tmp_path):
    """``test_x_launch.py`` of launch_pytest (or plain pytest) matches ``*_launch.py`` but pytest runs
    it: no "missing generate_launch_description" error; a plain module without one still gets it."""
    p = _ws(tmp_path, "import launch\nimport launch_pytest\nimport pytest\n\n\n@launch_pytest.fixture\n"
                      "def launch_description():\n    return launch.LaunchDescription([])\n", name="test_x_launch.py")
    diags = check_document(str(p))
    assert [d.code for d in diags] == ["launch-not-analysable"] and "launch_pytest" in diags[0].message
    q = _ws(tmp_path, "import launch\n\n\ndef launch_description():\n    return launch.LaunchDescription([])\n",
            name="plain_launch.py")
    assert [d.code for d in check_document(str(q))] == ["invalid-launch-file"]


def test_a_required_arg_declared_after_an_include_that_passes_it_is_no_undefined_arg(tmp_path):
    """launch's look-ahead keeps the include's declaration of 'mm' (which the include passes from
    LaunchConfiguration('mm')) and not the file's own later DeclareLaunchArgument('mm'): the command
    line must still give mm (the oracle resolves the file with mm:=x, fails without): a warning that
    it is required, never an undefined-arg error in every product."""
    inc = _ws(tmp_path, HEAD + """
def generate_launch_description():
    return LaunchDescription([DeclareLaunchArgument('mm'), Node(package='demo_pkg', executable='b', name='b',
                              parameters=[{'mm': LaunchConfiguration('mm')}])])
""", name="inc.launch.py")
    p = _ws(tmp_path, HEAD + """
import os
from ament_index_python.packages import get_package_share_directory
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource


def generate_launch_description():
    inc = IncludeLaunchDescription(PythonLaunchDescriptionSource(
        os.path.join(get_package_share_directory('demo_pkg'), 'launch', 'inc.launch.py')),
        launch_arguments={'mm': LaunchConfiguration('mm')}.items())
    return LaunchDescription([inc, DeclareLaunchArgument(name='mm')])
""")
    assert inc.exists()
    diags = check_document(str(p))
    assert [d.code for d in diags if d.severity == 1] == [], [(d.code, d.message) for d in diags]
    unset = [d for d in diags if d.code == "unset-arg"]
    assert len(unset) == 1 and _text_at(p, unset[0].span) == "mm", [(d.code, d.message) for d in diags]


def test_a_node_whose_executable_is_a_path_is_declined_by_the_concrete_load(tmp_path):
    """Node(executable='/dev/null') (a LaunchConfiguration default that must be overridden):
    launch_ros' which() looks at that path, not in the package -- whether it runs depends on the
    machine (the oracle: SubstitutionFailure for /dev/null).  Declined at the executable, never a
    node list; a plain executable name still loads."""
    p = _ws(tmp_path, HEAD + """
def generate_launch_description():
    exe = LaunchConfiguration('scenario', default='/dev/null')
    return LaunchDescription([Node(package='demo_pkg', executable=exe, name='s'),
                              Node(package='demo_pkg', executable='a', name='a')])
""")
    res = load_launch2(str(p), {}, workspace_root=str(tmp_path / "ws"), env=ENV, stub_packages=True)
    assert res.error_type == "NotAnalysed" and "executable of this node is a path" in res.error, res.error
    assert res.error_line == 9   # the executable= value
    res = load_launch2(str(p), {"scenario": "runner"}, workspace_root=str(tmp_path / "ws"), env=ENV,
                       stub_packages=True)
    assert res.error is None and sorted(n["executable"] for n in res.nodes) == ["a", "runner"]


def test_a_failing_python_expression_is_told_in_python_terms(tmp_path):
    """PythonExpression over bare true / false fails in launch (NameError): the error names the
    PythonExpression and says how to write it in Python, not in XML's $(eval) terms."""
    p = _ws(tmp_path, HEAD + """from launch.substitutions import PythonExpression


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('A', default_value='false'),
        DeclareLaunchArgument('B', default_value='false'),
        Node(package='demo_pkg', executable='a', name='a',
             condition=IfCondition(PythonExpression([LaunchConfiguration('A'), ' and ', LaunchConfiguration('B')]))),
    ])
""")
    from tvl_lsp.project.check import check_paths
    diags = check_paths([str(p)])
    errs = [d for d in diags if d.code == "eval-error"]
    assert errs, [d.message for d in diags]
    assert all(d.message.startswith("PythonExpression('") and "$(eval" not in d.message
               and "LaunchConfiguration('x')" in d.message for d in errs), [d.message for d in errs]
    assert _text_at(p, errs[0].span).startswith("PythonExpression(")
