"""Extraction from the sources (issue #26): every API of roscpp, rospy, rclcpp, rclpy, actionlib,
rclcpp_action, image_transport and message_filters on the fixture workspace tests/data/sources/ws
(one package per ROS version and language), with the awkward cases: types only in callback
signatures, aliases and using, names from constants and #defines, members set in constructors,
child and private node handles, plugins registered as executables, several targets sharing
sources, a library the programs link, Python nodes spread over modules, Python 2, a half-edited
file.  The expected endpoints were written by reading the fixtures."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from tvl_lsp.graph.sources import extract

WS = Path(__file__).parent / "data" / "sources" / "ws"


@pytest.fixture(scope="module")
def ex():
    return extract([str(WS)], disk=False)


def _eps(ex, pkg, exe):
    x = next((x for x in ex.executables if x.package == pkg and x.name == exe), None)
    assert x is not None, f"no program {pkg}/{exe}: {[(x.package, x.name) for x in ex.executables]}"
    return {(e.kind, e.name, e.type) for e in x.endpoints}


def test_packages_and_ros_versions(ex):
    assert {(p.name, p.ros) for p in ex.packages} == {("ros1_cpp", 1), ("ros1_py", 1), ("ros2_cpp", 2), ("robot_bringup", 1),
                                                      ("ros2_py", 2)}


def test_roscpp_names_from_constants_members_and_handles(ex):
    got = _eps(ex, "ros1_cpp", "talker")
    assert got == {
        ("publish", "hello", "std_msgs/Empty"),                 # src/common.cpp: the library it links
        ("publish", "/diagnostics_agg", "std_msgs/String"),     # a constexpr of a header, a typedef
        ("publish", "chatter", "std_msgs/String"),              # a member set in the constructor
        ("publish", "status", "std_msgs/String"),               # a #define of a header
        ("publish", "~robot/count", "std_msgs/Int32"),          # private handle, constant + literal, using
        ("publish", "arm/joint", "std_msgs/Int32"),             # NodeHandle(nh, "arm")
        ("param_read", "~output", "string"),
        ("publish", "{out}", "std_msgs/String"),                # a parameter's value: dynamic
        ("param_read", "~rate", "int"),                         # the member's type
        ("param_write", "/talker_ready", "bool"),
        ("param_write", "last_talker", "string"),               # ros::param::set
        ("param_search", "frame", None),
        ("param_delete", "stale", None),
        ("param_read", "gain", "double"),                       # param(name, default)
    }
    dyn = next(e for x in ex.executables if x.name == "talker" for e in x.endpoints if e.name == "{out}")
    assert dyn.dynamic and dyn.expression == "out" and dyn.default == "out"
    status = next(e for x in ex.executables if x.name == "talker" for e in x.endpoints if e.name == "status")
    assert status.file.endswith("talker.cpp") and status.line == 15 and not status.dynamic


def test_roscpp_callback_types_and_shared_sources(ex):
    expected = {
        ("subscribe", "scan", "sensor_msgs/LaserScan"),         # &Listener::scanCallback, LaserScanConstPtr
        ("subscribe", "cmd_vel", "geometry_msgs/Twist"),        # boost::bind(&..., this, _1, 7)
        ("subscribe", "odom", "nav_msgs/Odometry"),
        ("subscribe", "chatter", "std_msgs/String"),            # a free function's parameter
    }
    assert _eps(ex, "ros1_cpp", "listener") == expected
    assert _eps(ex, "ros1_cpp", "listener_copy") == expected   # foreach(...) add_executable(${exe} ...)


def test_roscpp_services_actions_transport_filters(ex):
    assert _eps(ex, "ros1_cpp", "ros1_cpp_services") == {
        ("service", "reset", "ros1_cpp/Reset"), ("service", "trigger", "std_srvs/Trigger"),
        ("client", "/other/trigger", "std_srvs/Trigger"), ("client", "ping", "std_srvs/Trigger")}
    assert _eps(ex, "ros1_cpp", "dock_server") == {
        ("action_server", "dock", "ros1_cpp/Dock"), ("action_client", "move_base", "move_base_msgs/MoveBase")}
    assert _eps(ex, "ros1_cpp", "camera") == {
        ("subscribe", "imu/data", "sensor_msgs/Imu"), ("subscribe", "camera/info", "sensor_msgs/CameraInfo"),
        ("publish", "camera/image", "sensor_msgs/Image"), ("subscribe", "input/image", "sensor_msgs/Image"),
        ("publish", "stereo/left/image_raw", "sensor_msgs/Image"),
        ("publish", "stereo/left/camera_info", "sensor_msgs/CameraInfo")}


def test_rclcpp_components_and_actions(ex):
    assert _eps(ex, "ros2_cpp", "driver") == {
        ("param_declare", "frame_id", "string"), ("param_declare", "rate", "double"),
        ("publish", "imu/data_raw", "sensor_msgs/Imu"),          # a static constexpr member
        ("subscribe", "cmd_vel", "geometry_msgs/Twist"),        # a class alias
        ("service", "~set_mode", "ros2_cpp/SetMode"), ("client", "/reset", "std_srvs/Trigger"),
        ("param_read", "verbose", "bool"), ("param_write", "started", "bool")}
    driver = next(x for x in ex.executables if x.name == "driver")
    assert driver.aliases == ["ros2_cpp::Driver"]              # the plugin is started as driver
    assert _eps(ex, "ros2_cpp", "ros2_cpp::Filter") == {
        ("subscribe", "scan", "sensor_msgs/LaserScan"), ("publish", "scan_filtered", "sensor_msgs/LaserScan"),
        ("publish", "debug/image", "sensor_msgs/Image")}
    assert _eps(ex, "ros2_cpp", "minimal") == {
        ("publish", "chatter_out", "std_msgs/String"), ("subscribe", "chatter", "std_msgs/String"),
        ("publish", "raw", "std_msgs/UInt8")}
    assert _eps(ex, "ros2_cpp", "actions") == {
        ("action_server", "fibonacci", "example_interfaces/Fibonacci"),
        ("action_client", "navigate_to_pose", "nav2_msgs/NavigateToPose")}


def test_rospy_over_modules_and_python2(ex):
    got = _eps(ex, "ros1_py", "controller")
    assert {
        ("publish", "cmd_vel", "geometry_msgs/Twist"),          # driver.py, a constant of topics.py
        ("publish", "/robot/status", "ros1_py/Status"),
        ("publish", "arm/mode", "std_msgs/String"),             # '%s/mode' % self.prefix, Driver('arm')
        ("subscribe", "odom", "std_msgs/Float64"),
        ("param_read", "~rate", "double"), ("param_read", "frame_id", "string"),
        ("param_write", "/controller/ready", "bool"), ("param_delete", "~stale", None),
        ("param_search", "robot_name", None),
        ("service", "trigger", "std_srvs/Trigger"), ("client", "/reset", "std_srvs/Empty"),
        ("action_client", "move_base", "move_base_msgs/MoveBase"),
        ("subscribe", "camera/image", "sensor_msgs/Image"), ("subscribe", "camera/info", "sensor_msgs/CameraInfo"),
        ("param_read", "~input", "string"), ("subscribe", "{topic}", "sensor_msgs/Image"),
    } == got
    # Python 2, wildcard imports from two message modules
    assert _eps(ex, "ros1_py", "legacy.py") == {("subscribe", "chatter", "std_msgs/String"),
                                               ("publish", "status", "ros1_py/Status")}


def test_rclpy_console_scripts(ex):
    assert _eps(ex, "ros2_py", "talker") == {
        ("param_declare", "period", "double"), ("param_declare", "limits.max", "int"),
        ("param_declare", "limits.min", "int"),
        ("publish", "chatter", "std_msgs/String"),              # the constructor's default, from names.py
        ("subscribe", "echo", "std_msgs/String"), ("client", "add_two_ints", "example_interfaces/AddTwoInts"),
        ("param_read", "period", "double")}                     # the type it is declared with
    assert _eps(ex, "ros2_py", "server") == {
        ("service", "add_two_ints", "example_interfaces/AddTwoInts"),
        ("action_server", "fibonacci", "example_interfaces/Fibonacci"),
        ("action_client", "/other/fibonacci", "example_interfaces/Fibonacci")}
    # setup.cfg's entry point; a half-edited call does not hide what follows it
    got = _eps(ex, "ros2_py", "watcher")
    assert ("subscribe", "left/image", "sensor_msgs/Image") in got
    assert ("publish", "after", "sensor_msgs/Image") in got


def test_positions_point_at_the_call_and_the_name(ex):
    e = next(e for x in ex.executables if x.name == "minimal" for e in x.endpoints if e.name == "chatter")
    line = Path(e.file).read_text().splitlines()[e.line - 1]
    assert line[e.col:].startswith("create_subscription")
    assert e.name_line == e.line and line[e.name_col:e.name_end] == "TOPIC"


def test_no_false_endpoints_from_look_alike_calls(tmp_path):
    pkg = tmp_path / "src" / "p"
    (pkg / "src").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>p</name><buildtool_depend>catkin</buildtool_depend></package>")
    (pkg / "CMakeLists.txt").write_text("project(p)\nadd_executable(n src/n.cpp)\n")
    (pkg / "src" / "n.cpp").write_text(
        '#include <mqtt/client.h>\n'
        'int main() {\n'
        '  mqtt::client cli;\n'
        '  cli.subscribe("sensors", 1);\n'             # not a node handle
        '  auto params = std::make_shared<rclcpp::SyncParametersClient>(node);\n'
        '  parameters_client->set_parameters({rclcpp::Parameter("x", 1)});\n'   # another node's parameters
        '  // nh.advertise<std_msgs::String>("commented", 1);\n'
        '  const char* s = "nh.advertise<std_msgs::String>(\\"quoted\\", 1)";\n'
        '}\n')
    ex = extract([str(tmp_path)], disk=False)
    assert [e for x in ex.executables for e in x.endpoints] == []


def test_bad_sources_are_bounded_or_skipped_with_a_note(tmp_path, monkeypatch):
    from tvl_lsp.graph.sources import cache
    pkg = tmp_path / "ws" / "src" / "p"
    shutil.copytree(WS / "src" / "ros2_cpp", pkg)
    src = pkg / "src"
    (src / "binary.cpp").write_bytes(b"\x7fELF\0\0\0" + os.urandom(512))
    (src / "gen.cpp").write_text("// Generated by gencpp from file x.msg\n// DO NOT EDIT!\n"
                                 'void f() { nh.advertise<A>("gen", 1); }\n')
    (src / "latin1.cpp").write_bytes('// caf\xe9\nvoid f() { n.advertise<std_msgs::String>("caf\xe9", 1); }\n'
                                     .encode("latin-1"))
    monkeypatch.setattr(cache, "MAX_SOURCE_BYTES", 4096)
    (src / "huge.cpp").write_text("// " + "x" * 5000 + '\nvoid f() { n.advertise<std_msgs::String>("huge", 1); }\n')
    ex = extract([str(tmp_path / "ws")], disk=False)
    notes = "\n".join(ex.notes)
    assert "binary.cpp: binary: skipped" in notes
    assert "gen.cpp: generated: skipped" in notes
    assert "latin1.cpp: not UTF-8" in notes
    assert "huge.cpp: not read:" in notes and "larger than" in notes
    names = {e.name for x in ex.executables for e in x.endpoints}
    assert "gen" not in names and "huge" not in names and "caf\ufffd" in names
    assert "chatter_out" in names    # the good sources are read as before


def test_members_set_in_many_places_are_worked_out_once(tmp_path):
    """A member set in K methods from another member, 24 deep: followed along every path this is
    K^24 evaluations (it never ended); each reference is worked out once per program. The answer is
    the same as the one of a shallow twin (dynamic: the methods disagree)."""
    import subprocess
    import sys

    def program(n, k):
        lines = ['#include <ros/ros.h>', '#include <std_msgs/String.h>', 'class C {', 'public:',
                 '  C(ros::NodeHandle& nh) : nh_(nh) {}']
        for j in range(k):
            lines += [f'  void f{j}() {{', f'    t0_ = "a{j}";'] + [f'    t{i}_ = t{i - 1}_;' for i in range(1, n + 1)]
            lines.append('  }')
        lines += [f'  void go() {{ pub_ = nh_.advertise<std_msgs::String>(t{n}_, 1); }}',
                  '  ros::NodeHandle nh_; ros::Publisher pub_;',
                  '  std::string ' + ', '.join(f't{i}_' for i in range(n + 1)) + ';', '};',
                  'int main(int argc, char** argv) { ros::init(argc, argv, "n"); ros::NodeHandle nh; C c(nh); }']
        return "\n".join(lines) + "\n"

    got = []
    for n, k in ((3, 2), (30, 6)):
        ws = tmp_path / f"ws{n}"
        pkg = ws / "src" / "p"
        (pkg / "src").mkdir(parents=True)
        (pkg / "package.xml").write_text("<package><name>p</name><buildtool_depend>catkin</buildtool_depend></package>")
        (pkg / "CMakeLists.txt").write_text("project(p)\nadd_executable(n src/n.cpp)\n")
        (pkg / "src" / "n.cpp").write_text(program(n, k))
        code = ("from tvl_lsp.graph.sources import extract\n"
                f"ex = extract([{str(ws)!r}], disk=False)\n"
                "print(sorted((e.kind, e.dynamic) for x in ex.executables for e in x.endpoints))\n")
        p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
        assert p.returncode == 0, p.stderr[-2000:]
        got.append(p.stdout)
    assert got[0] == got[1] == "[('publish', True)]\n"
