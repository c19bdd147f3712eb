"""The ROS client library calls extraction recognises, with where their arguments are.

A *spec* says, for one call: ``api`` (roscpp, rclcpp, actionlib, ...), ``kind`` (see
:data:`.model.KINDS`), ``name`` (the index of the name argument), ``cb`` (the callback whose
signature gives the type when no template argument does), ``ctx`` (``msg`` / ``srv`` /
``action``: how the type is read), ``type_arg`` (an argument holding the type as a string),
``value`` (an argument whose type is a parameter's type), ``ros`` (1, 2, or 0: the package's).
"""

from __future__ import annotations

import re
from typing import Optional

# ---------------------------------------------------------------- C++

# method name -> spec (receiver: a node handle / node / image transport / filter)
_CPP_METHODS: dict[str, dict] = {
    # roscpp
    "advertise": {"api": "roscpp", "kind": "publish", "name": 0, "ros": 1},
    "subscribe": {"api": "roscpp", "kind": "subscribe", "name": 0, "cb": 2, "ros": 1},
    "advertiseService": {"api": "roscpp", "kind": "service", "name": 0, "cb": 1, "ctx": "srv", "ros": 1},
    "serviceClient": {"api": "roscpp", "kind": "client", "name": 0, "ctx": "srv", "ros": 1},
    "getParam": {"api": "roscpp", "kind": "param_read", "name": 0, "value": 1, "ros": 1},
    "getParamCached": {"api": "roscpp", "kind": "param_read", "name": 0, "value": 1, "ros": 1},
    "setParam": {"api": "roscpp", "kind": "param_write", "name": 0, "value": 1, "ros": 1},
    "deleteParam": {"api": "roscpp", "kind": "param_delete", "name": 0, "ros": 1},
    "searchParam": {"api": "roscpp", "kind": "param_search", "name": 0, "ros": 1},
    "advertiseCamera": {"api": "image_transport", "kind": "publish", "name": 0, "camera": True},
    "subscribeCamera": {"api": "image_transport", "kind": "subscribe", "name": 0, "camera": True},
    # rclcpp (and rclcpp_lifecycle)
    "create_publisher": {"api": "rclcpp", "kind": "publish", "name": 0, "ros": 2},
    "create_subscription": {"api": "rclcpp", "kind": "subscribe", "name": 0, "cb": 2, "ros": 2},
    "create_service": {"api": "rclcpp", "kind": "service", "name": 0, "cb": 1, "ctx": "srv", "ros": 2},
    "create_client": {"api": "rclcpp", "kind": "client", "name": 0, "ctx": "srv", "ros": 2},
    "create_generic_publisher": {"api": "rclcpp", "kind": "publish", "name": 0, "type_arg": 1, "ros": 2},
    "create_generic_subscription": {"api": "rclcpp", "kind": "subscribe", "name": 0, "type_arg": 1, "ros": 2},
    "declare_parameter": {"api": "rclcpp", "kind": "param_declare", "name": 0, "value": 1, "ros": 2},
    "get_parameter": {"api": "rclcpp", "kind": "param_read", "name": 0, "value": 1, "ros": 2},
    "get_parameter_or": {"api": "rclcpp", "kind": "param_read", "name": 0, "value": 1, "ros": 2},
    "undeclare_parameter": {"api": "rclcpp", "kind": "param_delete", "name": 0, "ros": 2},
}

# qualified free functions: (prefix, name) -> spec
_CPP_FREE: dict[tuple[str, str], dict] = {
    ("ros::param", "get"): {"api": "roscpp", "kind": "param_read", "name": 0, "value": 1, "ros": 1},
    ("ros::param", "getCached"): {"api": "roscpp", "kind": "param_read", "name": 0, "value": 1, "ros": 1},
    ("ros::param", "param"): {"api": "roscpp", "kind": "param_read", "name": 0, "value": 1, "ros": 1},
    ("ros::param", "set"): {"api": "roscpp", "kind": "param_write", "name": 0, "value": 1, "ros": 1},
    ("ros::param", "del"): {"api": "roscpp", "kind": "param_delete", "name": 0, "ros": 1},
    ("ros::param", "search"): {"api": "roscpp", "kind": "param_search", "name": 0, "ros": 1},
    ("ros::service", "call"): {"api": "roscpp", "kind": "client", "name": 0, "ctx": "srv", "tvar": 1, "ros": 1},
    ("rclcpp_action", "create_server"): {"api": "rclcpp_action", "kind": "action_server", "name": 1, "ctx": "action",
                                         "ros": 2, "skip_nodes": True},
    ("rclcpp_action", "create_client"): {"api": "rclcpp_action", "kind": "action_client", "name": 1, "ctx": "action",
                                         "ros": 2, "skip_nodes": True},
    ("image_transport", "create_publisher"): {"api": "image_transport", "kind": "publish", "name": 1,
                                              "fixed": "sensor_msgs/Image", "ros": 2},
    ("image_transport", "create_subscription"): {"api": "image_transport", "kind": "subscribe", "name": 1,
                                                 "fixed": "sensor_msgs/Image", "ros": 2},
    ("image_transport", "create_camera_publisher"): {"api": "image_transport", "kind": "publish", "name": 1,
                                                     "fixed": "sensor_msgs/Image", "camera": True, "ros": 2},
    ("image_transport", "create_camera_subscription"): {"api": "image_transport", "kind": "subscribe", "name": 1,
                                                        "fixed": "sensor_msgs/Image", "camera": True, "ros": 2},
    ("rclcpp", "create_publisher"): {"api": "rclcpp", "kind": "publish", "name": 1, "ros": 2, "skip_nodes": True},
    ("rclcpp", "create_subscription"): {"api": "rclcpp", "kind": "subscribe", "name": 1, "cb": 3, "ros": 2,
                                        "skip_nodes": True},
    ("rclcpp", "create_client"): {"api": "rclcpp", "kind": "client", "name": 0, "ctx": "srv", "ros": 2,
                                  "skip_nodes": True},
    ("rclcpp", "create_service"): {"api": "rclcpp", "kind": "service", "name": 0, "ctx": "srv", "ros": 2,
                                   "skip_nodes": True},
    ("rclcpp", "create_generic_publisher"): {"api": "rclcpp", "kind": "publish", "name": 0, "ros": 2,
                                             "skip_nodes": True, "type_after_name": True},
    ("rclcpp", "create_generic_subscription"): {"api": "rclcpp", "kind": "subscribe", "name": 0, "ros": 2,
                                                "skip_nodes": True, "type_after_name": True},
    ("nav2_util", "declare_parameter_if_not_declared"): {"api": "rclcpp", "kind": "param_declare", "name": 1,
                                                         "value": 2, "ros": 2},
}
# the same, called unqualified (using-declarations, or inside the namespace)
_CPP_UNQUALIFIED: dict[str, tuple[str, str]] = {}
# helpers known by their name whatever their namespace (nav2_util::, nav2::, unqualified)
_ANY_PREFIX = {"declare_parameter_if_not_declared": {"api": "rclcpp", "kind": "param_declare", "name": 1,
                                                     "value": 2, "ros": 2},
               # nav2: node->declare_or_get_parameter(name, default) and
               # nav2::declare_or_get_parameter(node, name, default)
               "declare_or_get_parameter": {"api": "rclcpp", "kind": "param_declare", "name": 0, "ros": 2,
                                            "skip_nodes": True, "value_after_name": True}}

# calls whose result is a parameter's value
PARAM_VALUE_CALLS = {"param", "declare_parameter", "get_parameter", "get_parameter_or", "declare_parameter_if_not_declared",
                     "declare_or_get_parameter"}
# calls that write a parameter's value into an argument: method -> index of that argument
OUT_PARAM_CALLS = {"param": 1, "getParam": 1, "getParamCached": 1, "get_parameter": 1, "get_parameter_or": 1,
                   "get": 1}
NODE_FIRST = {"declare_parameter_if_not_declared"}
# where a parameter's default value is: the last argument, or the one after the name
DEFAULT_AT = {"param": "last", "get_parameter_or": "last", "declare_parameter": "next",
              "declare_parameter_if_not_declared": "next", "declare_or_get_parameter": "next"}
PARAM_METHODS = {"declare_parameter", "get_parameter", "get_parameter_or", "get_parameters", "set_parameter",
                 "set_parameters", "set_parameters_atomically", "undeclare_parameter", "declare_parameters",
                 "getParam", "setParam", "param", "deleteParam", "searchParam", "getParamCached",
                 "declare_or_get_parameter"}
NOT_USER_FUNCS = {"bind", "make_shared", "make_unique", "printf", "ROS_INFO", "ROS_WARN", "ROS_ERROR", "ROS_DEBUG",
                  "RCLCPP_INFO", "RCLCPP_WARN", "RCLCPP_ERROR", "RCLCPP_DEBUG", "c_str", "push_back", "size",
                  "emplace_back", "publish", "sleep", "ok", "spinOnce", "spin", "format", "str", "append", "find",
                  "count", "insert", "at", "get", "reset", "lock", "now", "Duration", "Rate", "to_string", "stod",
                  "stoi", "end", "begin", "empty", "fprintf", "sprintf", "snprintf", "memcpy", "max", "min", "abs",
                  "sqrt", "atan2", "cos", "sin", "fabs"}


def cpp_spec(m: str, prefix: Optional[str], nargs: int) -> Optional[dict]:
    """The spec of a C++ call ``prefix::m(...)`` / ``x.m(...)`` (prefix None: a method call)."""
    if m in _ANY_PREFIX:
        return _ok(_ANY_PREFIX[m], nargs)
    if prefix:
        p = prefix.lstrip(":")
        spec = _CPP_FREE.get((p, m))
        if spec is None:
            tail = p.split("::")[-1]
            spec = _CPP_FREE.get((tail, m))
        if spec is None:
            if p.split("::")[0] in ("ros", "rclcpp", "rclcpp_action", "image_transport"):
                return None
            spec = _CPP_METHODS.get(m) if m not in ("get", "set", "call", "param") else None
            if spec is None:
                return None
            if spec["api"] == "rclcpp":
                # a project's factory, ns::create_subscription<T>(node, "topic", ...): the node first
                spec = dict(spec, skip_nodes=True)
        return _ok(spec, nargs)
    if prefix == "" and m in _CPP_UNQUALIFIED:
        return _ok(_CPP_FREE[_CPP_UNQUALIFIED[m]], nargs)
    spec = _CPP_METHODS.get(m)
    if prefix == "" and (spec is None or spec["api"] != "rclcpp"):
        # a plain call: a node's own method (rclcpp, in a Node subclass); roscpp's are node
        # handle methods, never called bare (a local lambda called getParam is not one)
        return None
    if spec is None:
        if m == "param":
            spec = {"api": "roscpp", "kind": "param_read", "name": 0, "value": 1 if nargs >= 3 else 1, "ros": 1}
        else:
            return None
    return _ok(spec, nargs)


def _ok(spec: dict, nargs: int) -> Optional[dict]:
    if nargs <= spec["name"]:
        return None
    return spec


# constructions that are endpoints: the class's last name component (and a namespace test)
def class_spec(base: str) -> Optional[dict]:
    """The spec of constructing ``base`` (a class name, template arguments removed, aliases
    expanded), or None."""
    parts = base.replace(" ", "").lstrip(":").split("::")
    last = parts[-1]
    ns = parts[-2] if len(parts) >= 2 else ""
    if last in ("SimpleActionServer", "ActionServer") and ns in ("actionlib", "nav2_util", "nav2", ""):
        return {"api": "actionlib" if ns in ("actionlib", "") else ns, "kind": "action_server", "ctx": "action",
                "ros": 1 if ns == "actionlib" else (2 if ns in ("nav2_util", "nav2") else 0)}
    if last in ("SimpleActionClient", "ActionClient") and ns in ("actionlib", ""):
        return {"api": "actionlib", "kind": "action_client", "ctx": "action", "ros": 1 if ns == "actionlib" else 0}
    if last == "Subscriber" and ns == "message_filters":
        return {"api": "message_filters", "kind": "subscribe", "ctx": "msg", "ros": 0}
    if last == "SubscriberFilter" and ns == "image_transport":
        return {"api": "image_transport", "kind": "subscribe", "fixed": "sensor_msgs/Image", "ros": 0}
    if last == "ServiceClient" and ns in ("nav2_util", "nav2"):
        return {"api": ns, "kind": "client", "ctx": "srv", "ros": 2}
    if last == "ServiceServer" and ns in ("nav2_util", "nav2"):
        return {"api": ns, "kind": "service", "ctx": "srv", "ros": 2}
    return None


def camera_info_topic(image: str) -> str:
    """``image_transport::getCameraInfoTopic``: the ``camera_info`` beside an image topic."""
    i = image.rstrip("/").rfind("/")
    if i < 0:
        return "camera_info"
    return image[: i + 1] + "camera_info"


# ---------------------------------------------------------------- Python

# module-qualified callables (after import resolution) -> spec; the name and type arguments
# may also be given by keyword (the second element of each pair)
PY_CALLS: dict[str, dict] = {
    "rospy.Publisher": {"api": "rospy", "kind": "publish", "name": (0, "name"), "type": (1, "data_class"), "ros": 1},
    "rospy.Subscriber": {"api": "rospy", "kind": "subscribe", "name": (0, "name"), "type": (1, "data_class"), "ros": 1},
    "rospy.Service": {"api": "rospy", "kind": "service", "name": (0, "name"), "type": (1, "service_class"),
                      "ctx": "srv", "ros": 1},
    "rospy.ServiceProxy": {"api": "rospy", "kind": "client", "name": (0, "name"), "type": (1, "service_class"),
                           "ctx": "srv", "ros": 1},
    "rospy.get_param": {"api": "rospy", "kind": "param_read", "name": (0, "param_name"), "value": (1, "default"),
                        "ros": 1},
    "rospy.get_param_cached": {"api": "rospy", "kind": "param_read", "name": (0, "param_name"),
                               "value": (1, "default"), "ros": 1},
    "rospy.set_param": {"api": "rospy", "kind": "param_write", "name": (0, "param_name"),
                        "value": (1, "param_value"), "ros": 1},
    "rospy.delete_param": {"api": "rospy", "kind": "param_delete", "name": (0, "param_name"), "ros": 1},
    "rospy.search_param": {"api": "rospy", "kind": "param_search", "name": (0, "param_name"), "ros": 1},
    "actionlib.SimpleActionServer": {"api": "actionlib", "kind": "action_server", "name": (0, "name"),
                                     "type": (1, "ActionSpec"), "ctx": "action", "ros": 1},
    "actionlib.ActionServer": {"api": "actionlib", "kind": "action_server", "name": (0, "ns"),
                               "type": (1, "ActionSpec"), "ctx": "action", "ros": 1},
    "actionlib.SimpleActionClient": {"api": "actionlib", "kind": "action_client", "name": (0, "ns"),
                                     "type": (1, "ActionSpec"), "ctx": "action", "ros": 1},
    "actionlib.ActionClient": {"api": "actionlib", "kind": "action_client", "name": (0, "ns"),
                               "type": (1, "ActionSpec"), "ctx": "action", "ros": 1},
    "rclpy.action.ActionServer": {"api": "rclpy", "kind": "action_server", "name": (2, "action_name"),
                                  "type": (1, "action_type"), "ctx": "action", "ros": 2},
    "rclpy.action.ActionClient": {"api": "rclpy", "kind": "action_client", "name": (2, "action_name"),
                                  "type": (1, "action_type"), "ctx": "action", "ros": 2},
    "message_filters.Subscriber": {"api": "message_filters", "kind": "subscribe", "name": (None, "topic"),
                                   "type": (None, "msg_type"), "mf": True, "ros": 0},
}
# aliases of modules the calls live in
PY_MODULE_ALIASES = {"rclpy.action.server.ActionServer": "rclpy.action.ActionServer",
                     "rclpy.action.client.ActionClient": "rclpy.action.ActionClient",
                     "actionlib.simple_action_server.SimpleActionServer": "actionlib.SimpleActionServer",
                     "actionlib.simple_action_client.SimpleActionClient": "actionlib.SimpleActionClient",
                     "actionlib.action_server.ActionServer": "actionlib.ActionServer",
                     "actionlib.action_client.ActionClient": "actionlib.ActionClient",
                     "rospy.topics.Publisher": "rospy.Publisher", "rospy.topics.Subscriber": "rospy.Subscriber",
                     "rospy.impl.tcpros_service.ServiceProxy": "rospy.ServiceProxy",
                     "rospy.impl.tcpros_service.Service": "rospy.Service"}

# rclpy node methods (any receiver)
PY_METHODS: dict[str, dict] = {
    "create_publisher": {"api": "rclpy", "kind": "publish", "name": (1, "topic"), "type": (0, "msg_type"), "ros": 2},
    "create_subscription": {"api": "rclpy", "kind": "subscribe", "name": (1, "topic"), "type": (0, "msg_type"),
                            "ros": 2},
    "create_service": {"api": "rclpy", "kind": "service", "name": (1, "srv_name"), "type": (0, "srv_type"),
                       "ctx": "srv", "ros": 2},
    "create_client": {"api": "rclpy", "kind": "client", "name": (1, "srv_name"), "type": (0, "srv_type"),
                      "ctx": "srv", "ros": 2},
    "declare_parameter": {"api": "rclpy", "kind": "param_declare", "name": (0, "name"), "value": (1, "value"), "ros": 2},
    "get_parameter": {"api": "rclpy", "kind": "param_read", "name": (0, "name"), "ros": 2},
    "get_parameter_or": {"api": "rclpy", "kind": "param_read", "name": (0, "name"), "value": (1, "alternative_value"),
                         "ros": 2},
    "undeclare_parameter": {"api": "rclpy", "kind": "param_delete", "name": (0, "name"), "ros": 2},
}

_PY_NAME_OK = re.compile(r"^[\w.]+$")


def py_value_type(kind: str, text: str) -> Optional[str]:
    """A Python literal's parameter type."""
    if kind == "integer":
        return "int"
    if kind == "float":
        return "double"
    if kind in ("true", "false"):
        return "bool"
    if kind in ("string", "concatenated_string"):
        return "string"
    if kind == "binary_operator":
        nums = re.findall(r"\d+(\.\d*)?(?:[eE][-+]?\d+)?", text)
        if nums and re.fullmatch(r"[\d.eE+\-*/() ]+", text):
            return "double" if any(n for n in nums) or "." in text or "/" in text else "int"
        return None
    if kind == "list":
        return "list"
    if kind == "dictionary":
        return "dict"
    return None
