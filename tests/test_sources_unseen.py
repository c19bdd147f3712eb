"""Extraction (issue #26): the classes of code an unseen pass on public repositories found
(docs/benchmarks/2026-11-27-sources-unseen.md), each on a small fixture of our own written here:
node handles passed through methods that share their name with other classes' methods, through
constructor overloads a program does not call, through base-class initialisers and global
pointers; helper libraries linked by a nodelet library; a project's own factory functions taking
the node first.  The expected endpoints were written by reading the fixtures."""

from __future__ import annotations

from pathlib import Path

from tvl_lsp.graph.sources import extract

PKG_XML = "<package><name>{}</name><buildtool_depend>{}</buildtool_depend></package>"


def _pkg(root: Path, name: str, cmake: str, files: dict[str, str], build: str = "catkin") -> None:
    pkg = root / "src" / name
    pkg.mkdir(parents=True)
    (pkg / "package.xml").write_text(PKG_XML.format(name, build))
    (pkg / "CMakeLists.txt").write_text(f"project({name})\n" + cmake)
    for rel, text in files.items():
        p = pkg / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)


def _rows(ex, exe: str) -> set:
    x = next((x for x in ex.executables if x.name == exe), None)
    assert x is not None, [x.name for x in ex.executables]
    return {(e.kind, e.name, e.type) for e in x.endpoints}


DRIVER_H = """#include <ros/ros.h>
#include <std_msgs/String.h>
class Odometry { public: void init(ros::NodeHandle& nh, const std::string& name); };
struct Settings { double rate; };
class Driver {
public:
  Driver(std::string& node_name) : name_(node_name) {}
  bool init(ros::NodeHandle& nh, ros::NodeHandle& nh_pub);
private:
  void advertiseTopics(ros::NodeHandle& nh);
  std::string name_;
  Odometry odometry;
  ros::Publisher pub_, state_;
};
"""

DRIVER_CPP = """#include "driver/driver.h"
void Odometry::init(ros::NodeHandle& nh, const std::string& name) {
  nh.param("odom_frame", frame_, std::string("odom"));
}
bool Driver::init(ros::NodeHandle& nh, ros::NodeHandle& nh_pub) {
  advertiseTopics(nh);
  Settings settings;
  odometry.init(nh, name_);          // another class's init: not a call of Driver::init
  nh.getParam("rate", settings.rate);     // the field's type
  std::string description;
  nh_pub.getParam("robot_description", description);
  return true;
}
void Driver::advertiseTopics(ros::NodeHandle& nh) {
  pub_ = nh.advertise<std_msgs::String>("events/button", 10);
}
"""

NODELET_CPP = """#include <nodelet/nodelet.h>
#include <boost/shared_ptr.hpp>
#include "driver/driver.h"
class Runner { public: void init(int rate); };
class DriverNodelet : public nodelet::Nodelet {
  void onInit() {
    std::string name = getName();
    driver_.reset(new Driver(name));
    runner_.init(5);                 // a same-named method of a third class
    driver_->init(this->getPrivateNodeHandle(), this->getNodeHandle());
  }
  boost::shared_ptr<Driver> driver_;
  Runner runner_;
};
"""


def test_a_handle_passed_to_a_method_that_shares_its_name_with_others(tmp_path):
    """``driver_->init(getPrivateNodeHandle(), getNodeHandle())`` in a nodelet library, the
    driver's code in a helper library that nodelet links: ``Odometry::init(nh, name)`` and
    ``Runner::init(5)`` are other functions of that name (by the receiver's type and by the
    argument that is no node handle); the helper library is read with the nodelet, not alone."""
    _pkg(tmp_path, "drv", "add_library(driver_ros src/driver.cpp)\n"
                          "add_library(driver_nodelet src/nodelet.cpp)\n"
                          "target_link_libraries(driver_nodelet driver_ros)\n",
         {"include/driver/driver.h": DRIVER_H, "src/driver.cpp": DRIVER_CPP, "src/nodelet.cpp": NODELET_CPP})
    ex = extract([str(tmp_path)], disk=False)
    assert [x.name for x in ex.executables] == ["driver_nodelet"]
    assert _rows(ex, "driver_nodelet") == {
        ("publish", "~events/button", "std_msgs/String"),
        ("param_read", "~odom_frame", "string"),
        ("param_read", "~rate", "double"),
        ("param_read", "robot_description", "string"),
    }


SLAM_H = """#include <ros/ros.h>
#include <std_msgs/String.h>
class Slam {
public:
  Slam();
  Slam(ros::NodeHandle& nh, ros::NodeHandle& pnh);
  Slam(unsigned long seed, unsigned long buffer);
  void init();
private:
  ros::NodeHandle node_;
  ros::NodeHandle private_nh_;
  ros::Publisher map_pub_;
  int iterations_;
};
"""

SLAM_CPP = """#include "slam/slam.h"
Slam::Slam() : private_nh_("~") { init(); }
Slam::Slam(ros::NodeHandle& nh, ros::NodeHandle& pnh) : node_(nh), private_nh_(pnh) { init(); }
Slam::Slam(unsigned long seed, unsigned long buffer) : private_nh_("~") { init(); }
void Slam::init() {
  private_nh_.getParam("iterations", iterations_);
  map_pub_ = node_.advertise<std_msgs::String>("map", 1, true);
}
"""


def test_members_set_by_constructor_overloads_the_program_does_not_call(tmp_path):
    """Three constructors set ``private_nh_`` ("~", a parameter, "~") and ``node_``; each program
    calls one of them: the others' initialisers are not the program's (a call whose arguments
    are no node handles is not one of the handle-taking overload)."""
    main_cpp = '#include "slam/slam.h"\nint main(int c, char** v) { ros::init(c, v, "slam"); Slam s; ros::spin(); }\n'
    replay_cpp = ('#include "slam/slam.h"\nint main(int c, char** v) { ros::init(c, v, "replay");\n'
                  '  unsigned long seed = 1; unsigned long buffer = 2;\n  Slam s(seed, buffer);\n}\n')
    nodelet_cpp = ('#include <nodelet/nodelet.h>\n#include "slam/slam.h"\n'
                   'class SlamNodelet : public nodelet::Nodelet {\n'
                   '  void onInit() { slam_.reset(new Slam(getNodeHandle(), getPrivateNodeHandle())); }\n'
                   '  boost::shared_ptr<Slam> slam_;\n};\n')
    _pkg(tmp_path, "slam", "add_executable(slam src/slam.cpp src/main.cpp)\n"
                           "add_executable(replay src/slam.cpp src/replay.cpp)\n"
                           "add_library(slam_nodelet src/slam.cpp src/nodelet.cpp)\n",
         {"include/slam/slam.h": SLAM_H, "src/slam.cpp": SLAM_CPP, "src/main.cpp": main_cpp,
          "src/replay.cpp": replay_cpp, "src/nodelet.cpp": nodelet_cpp})
    ex = extract([str(tmp_path)], disk=False)
    want = {("param_read", "~iterations", "int"), ("publish", "map", "std_msgs/String")}
    for exe in ("slam", "replay", "slam_nodelet"):
        assert _rows(ex, exe) == want, exe


def test_base_class_initialisers_global_pointers_and_same_named_overloads(tmp_path):
    """``Socket(nh) : Input(nh, 1)`` constructs the base with the handle; ``setup(private_nh)``
    of one class beside ``Base::setup(msg)`` and ``container->setup(msg)`` of others; a global
    ``ros::NodeHandle* g_n = NULL`` set in main."""
    src = """#include <ros/ros.h>
#include <std_msgs/String.h>
#include <sensor_msgs/LaserScan.h>
class Input { public: Input(ros::NodeHandle private_nh, int port); };
class Socket : public Input { public: Socket(ros::NodeHandle private_nh); };
class Raw { public: void setup(ros::NodeHandle private_nh); struct { std::string model; int npackets; } config_; };
class Container { public: void setup(const sensor_msgs::LaserScan::ConstPtr& msg); };
class Cloud : public Container { public: void setup(const sensor_msgs::LaserScan::ConstPtr& msg); };
Input::Input(ros::NodeHandle private_nh, int port) {
  std::string ip;
  private_nh.param("device_ip", ip, std::string(""));
}
Socket::Socket(ros::NodeHandle private_nh) : Input(private_nh, 2368) {}
void Raw::setup(ros::NodeHandle private_nh) {
  private_nh.getParam("model", config_.model);
  private_nh.getParam("npackets", config_.npackets);
}
void Cloud::setup(const sensor_msgs::LaserScan::ConstPtr& msg) { Container::setup(msg); }
class Transform {
public:
  Transform(ros::NodeHandle node, ros::NodeHandle private_nh) : data_(new Raw) {
    data_->setup(private_nh);
    sub_ = node.subscribe("scan", 10, &Transform::cb, this);
  }
  void cb(const sensor_msgs::LaserScan::ConstPtr& msg) { container_->setup(msg); }
  boost::shared_ptr<Raw> data_;
  boost::shared_ptr<Container> container_;
  ros::Subscriber sub_;
};
ros::NodeHandle* g_n = NULL;
void listen() { ros::Publisher p = g_n->advertise<std_msgs::String>("status", 1); }
int main(int argc, char** argv) {
  ros::init(argc, argv, "transform");
  g_n = new ros::NodeHandle();
  Transform t(ros::NodeHandle(), ros::NodeHandle("~"));
  Socket s(ros::NodeHandle("~"));
  listen();
}
"""
    _pkg(tmp_path, "velo", "add_executable(transform src/t.cpp)\n", {"src/t.cpp": src})
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "transform") == {
        ("param_read", "~device_ip", "string"),
        ("param_read", "~model", "string"),
        ("param_read", "~npackets", "int"),
        ("subscribe", "scan", "sensor_msgs/LaserScan"),
        ("publish", "status", "std_msgs/String"),
    }


def test_a_project_factory_taking_the_node_first(tmp_path):
    """``nav2::interfaces::create_subscription<T>(parent, topic_name_, ...)``: a project's free
    function named like the API, with the node first: the topic is the second argument."""
    src = """#include <rclcpp/rclcpp.hpp>
#include <nav_msgs/msg/odometry.hpp>
class OdomSmoother {
public:
  template<typename NodeT>
  OdomSmoother(const NodeT & parent, const std::string & odom_topic = "odom") {
    sub_ = my_project::interfaces::create_subscription<nav_msgs::msg::Odometry>(
      parent, odom_topic, std::bind(&OdomSmoother::cb, this, std::placeholders::_1));
  }
  void cb(nav_msgs::msg::Odometry::SharedPtr msg) {}
  rclcpp::Subscription<nav_msgs::msg::Odometry>::SharedPtr sub_;
};
int main(int argc, char** argv) {
  rclcpp::init(argc, argv);
  auto node = std::make_shared<rclcpp::Node>("smoother");
  OdomSmoother s(node, "wheel/odom");
}
"""
    _pkg(tmp_path, "sm", "add_executable(smoother src/s.cpp)\n", {"src/s.cpp": src}, build="ament_cmake")
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "smoother") == {("subscribe", "wheel/odom", "nav_msgs/Odometry")}


def test_rclcpp_parameter_types_from_type_enums_and_arithmetic(tmp_path):
    """``declare_parameter(name, rclcpp::PARAMETER_STRING)`` declares a type without a value
    (also under a name built at run time, and its read into an ``rclcpp::Parameter`` has it);
    ``1.0 / frequency_`` is a double; ``2 * count_`` cannot be told (count_ could be anything)."""
    src = """#include <rclcpp/rclcpp.hpp>
class Filter : public rclcpp::Node {
public:
  Filter() : Node("filter") {
    frequency_ = this->declare_parameter("frequency", 30.0);
    this->declare_parameter("sensor_timeout", 1.0 / frequency_);
    this->declare_parameter("window", 2 * count_);
    this->declare_parameter("gains", rclcpp::ParameterType::PARAMETER_DOUBLE_ARRAY);
    for (int i = 0; i < 3; ++i) {
      std::stringstream ss;
      ss << "odom" << i;
      std::string topic_name = ss.str();
      this->declare_parameter(topic_name, rclcpp::PARAMETER_STRING);
      rclcpp::Parameter parameter;
      this->get_parameter(topic_name, parameter);
    }
  }
  double frequency_;
  int count_;
};
int main(int argc, char** argv) { rclcpp::init(argc, argv); rclcpp::spin(std::make_shared<Filter>()); }
"""
    _pkg(tmp_path, "flt", "add_executable(filter src/f.cpp)\n", {"src/f.cpp": src}, build="ament_cmake")
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "filter") == {
        ("param_declare", "frequency", "double"),
        ("param_declare", "sensor_timeout", "double"),
        ("param_declare", "window", None),
        ("param_declare", "gains", "double[]"),
        ("param_declare", "{ss.str()}", "string"),
        ("param_read", "{ss.str()}", "string"),
    }


def test_a_python_type_imported_under_one_name_from_two_places_is_unknown(tmp_path):
    """``CmdVelMsg`` is ``Twist`` or ``TwistStamped`` by an environment variable read at run
    time: no type (never one of the two guessed); a plain import keeps its type."""
    node = """import os
import rclpy
from rclpy.node import Node
from nav_msgs.msg import Odometry
if os.environ.get('ROS_DISTRO', 'humble') == 'humble':
    from geometry_msgs.msg import Twist as CmdVelMsg
else:
    from geometry_msgs.msg import TwistStamped as CmdVelMsg


class Mover(Node):
    def __init__(self):
        super().__init__('mover')
        self.pub = self.create_publisher(CmdVelMsg, 'cmd_vel', 10)
        self.sub = self.create_subscription(Odometry, 'odom', self.cb, 10)

    def cb(self, msg):
        pass


def main():
    rclpy.init()
    rclpy.spin(Mover())
"""
    pkg = tmp_path / "src" / "mover"
    (pkg / "mover").mkdir(parents=True)
    (pkg / "package.xml").write_text(PKG_XML.format("mover", "ament_python"))
    (pkg / "setup.py").write_text("from setuptools import setup\nsetup(name='mover', entry_points={"
                                  "'console_scripts': ['mover = mover.mover:main']})\n")
    (pkg / "mover" / "__init__.py").write_text("")
    (pkg / "mover" / "mover.py").write_text(node)
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "mover") == {("publish", "cmd_vel", None), ("subscribe", "odom", "nav_msgs/Odometry")}


def test_names_written_into_c_strings_by_sprintf(tmp_path):
    """``char topicname[] = "analog_input00"; snprintf(topicname, ..., "analog_input%02d", i)``:
    the name is the format's (never the array's first value); ``%s`` of a known string is
    read; ``strcpy`` leaves a run-time value."""
    src = """#include <ros/ros.h>
#include <std_msgs/Float64.h>
#include <cstdio>
int main(int argc, char** argv) {
  ros::init(argc, argv, "inputs");
  ros::NodeHandle nh, pnh("~");
  std::vector<ros::Publisher> pubs;
  for (int i = 0; i < 4; i++) {
    char topicname[] = "analog_input00";
    snprintf(topicname, sizeof(topicname), "analog_input%02d", i);
    pubs.push_back(nh.advertise<std_msgs::Float64>(topicname, 1));
    char param[100];
    sprintf(param, "%s/gain", "calibration");
    double gain;
    pnh.getParam(param, gain);
  }
  char label[32] = "label";
  strcpy(label, argv[1]);
  std::string value;
  pnh.getParam(label, value);
}
"""
    _pkg(tmp_path, "io", "add_executable(inputs src/i.cpp)\n", {"src/i.cpp": src})
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "inputs") == {
        ("publish", "analog_input{i}", "std_msgs/Float64"),
        ("param_read", "~calibration/gain", "double"),
        ("param_read", "~{label}", "string"),
    }


def test_a_name_set_in_a_local_structs_field(tmp_path):
    """``desc.name = "min_neighbors"; declare_parameter(desc.name, ...)``: the field's value;
    set again in a branch, it is known only at run time."""
    src = """#include <rclcpp/rclcpp.hpp>
class Outliers : public rclcpp::Node {
public:
  explicit Outliers(const rclcpp::NodeOptions & options) : Node("outliers", options) {
    rcl_interfaces::msg::ParameterDescriptor desc;
    desc.name = "min_neighbors";
    desc.description = "neighbours of an inlier";
    declare_parameter(desc.name, rclcpp::ParameterValue(5), desc);
    rcl_interfaces::msg::ParameterDescriptor other;
    other.name = "radius";
    if (options.use_intra_process_comms()) {
      other.name = "radius_intra";
    }
    declare_parameter(other.name, rclcpp::ParameterValue(0.1), other);
  }
};
#include <rclcpp_components/register_node_macro.hpp>
RCLCPP_COMPONENTS_REGISTER_NODE(Outliers)
"""
    _pkg(tmp_path, "pcl", "add_library(outliers SHARED src/o.cpp)\n"
                          "rclcpp_components_register_node(outliers PLUGIN \"Outliers\" EXECUTABLE outliers_node)\n",
         {"src/o.cpp": src}, build="ament_cmake")
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "outliers_node") == {("param_declare", "min_neighbors", "int"),
                                          ("param_declare", "{other.name}", "double")}


def test_string_macros_written_side_by_side(tmp_path):
    """``#define SCALE "angular_scale"`` and ``#define X "/x"``: ``declare_parameter<double>(SCALE X,
    1)`` is ``angular_scale/x`` (tree-sitter reads the pair as ``SCALE::X`` or as an argument and
    an error, by context); a macro beside a literal too."""
    src = """#include <rclcpp/rclcpp.hpp>
#include <std_msgs/msg/string.hpp>
#define SCALE_S "angular_scale"
#define X_S "/x"
#define Y_S "/y"
#define NS_S "spacenav"
class Nav : public rclcpp::Node {
public:
  Nav() : Node("nav") {
    this->declare_parameter<double>(
      SCALE_S X_S, 1);
    pub_ = create_publisher<std_msgs::msg::String>(NS_S "/twist", 10);
  }
  rclcpp::Publisher<std_msgs::msg::String>::SharedPtr pub_;
};
void read(rclcpp::Node* node) { double v; node->get_parameter<double>(SCALE_S Y_S, v); }
int main(int argc, char** argv) { rclcpp::init(argc, argv); auto n = std::make_shared<Nav>(); read(n.get()); }
"""
    _pkg(tmp_path, "nav", "add_executable(nav src/n.cpp)\n", {"src/n.cpp": src}, build="ament_cmake")
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "nav") == {("param_declare", "angular_scale/x", "double"),
                                ("param_read", "angular_scale/y", "double"),
                                ("publish", "spacenav/twist", "std_msgs/String")}


def test_defaults_of_a_constructor_declared_in_a_header(tmp_path):
    """``Robot(const std::string& state = "robot_state", const std::string& markers = "markers")``
    in the header, the definition without defaults: ``Robot robot;`` and ``Robot r("x/state")``
    take the header's defaults for what they leave out."""
    header = """#include <ros/ros.h>
#include <std_msgs/String.h>
class Robot {
public:
  Robot(const std::string& state_topic = "robot_state", const std::string& marker_topic = "markers");
private:
  ros::NodeHandle nh_;
  ros::Publisher state_pub_, marker_pub_;
};
"""
    robot = """#include "robot/robot.h"
Robot::Robot(const std::string& state_topic, const std::string& marker_topic)
  : nh_(), state_pub_(nh_.advertise<std_msgs::String>(state_topic, 1)),
    marker_pub_(nh_.advertise<std_msgs::String>(marker_topic, 1)) {}
"""
    plain = '#include "robot/robot.h"\nint main(int c, char** v) { ros::init(c, v, "plain"); Robot robot; ros::spin(); }\n'
    named = ('#include "robot/robot.h"\nint main(int c, char** v) { ros::init(c, v, "named");\n'
             '  Robot r("tutorial/robot_state"); ros::spin(); }\n')
    _pkg(tmp_path, "robot", "add_executable(plain src/robot.cpp src/plain.cpp)\n"
                            "add_executable(named src/robot.cpp src/named.cpp)\n",
         {"include/robot/robot.h": header, "src/robot.cpp": robot, "src/plain.cpp": plain, "src/named.cpp": named})
    ex = extract([str(tmp_path)], disk=False)
    assert _rows(ex, "plain") == {("publish", "robot_state", "std_msgs/String"), ("publish", "markers", "std_msgs/String")}
    assert _rows(ex, "named") == {("publish", "tutorial/robot_state", "std_msgs/String"),
                                  ("publish", "markers", "std_msgs/String")}
