"""What ros2/launch and launch_ros accept in XML / YAML launch files: tags, their attributes
(required first) and sub-entities, and the substitution names.  For completion and hovers; the
parser (:mod:`.actions`) is what enforces them."""

from __future__ import annotations

_COND = ["if", "unless"]
_PROCESS = ["output", "respawn", "respawn_delay", "respawn_max_retries", "cwd", "launch-prefix", "on_exit",
            "emulate_tty", "sigterm_timeout", "sigkill_timeout", "shell"]

TAG_ATTRS: dict[str, list[str]] = {
    "launch": ["deprecated"],
    "arg": ["name", "default", "description"] + _COND,
    "choice": ["value"],
    "let": ["name", "value"] + _COND,
    "group": ["scoped", "forwarding"] + _COND,
    "keep": ["name", "value"],
    "include": ["file"] + _COND,
    "node": ["pkg", "exec", "name", "namespace", "args", "ros_args", "exec_name"] + _PROCESS + _COND,
    "executable": ["cmd", "name"] + _PROCESS + _COND,
    "param": ["name", "value", "type", "from", "allow_substs"],
    "remap": ["from", "to"],
    "env": ["name", "value"],
    "push_ros_namespace": ["namespace"] + _COND,
    "set_remap": ["from", "to"] + _COND,
    "set_parameter": ["name", "value"] + _COND,
    "set_parameters_from_file": ["filename"] + _COND,
    "set_env": ["name", "value"] + _COND,
    "unset_env": ["name"] + _COND,
    "append_env": ["name", "value", "prepend", "separator"] + _COND,
    "log": ["message"] + _COND,
    "timer": ["period", "cancel_on_shutdown"] + _COND,
    "node_container": ["pkg", "exec", "name", "namespace", "args", "ros_args"] + _PROCESS + _COND,
    "composable_node": ["pkg", "plugin", "name", "namespace"] + _COND,
    "load_composable_node": ["target"] + _COND,
    "extra_arg": ["name", "value"],
    "shutdown": ["reason"] + _COND,
    "reset": _COND,
    "set_use_sim_time": ["value"] + _COND,
}

ACTIONS = ["arg", "let", "node", "include", "group", "executable", "push_ros_namespace", "set_remap",
           "set_parameter", "set_parameters_from_file", "set_env", "unset_env", "append_env", "log", "timer",
           "node_container", "load_composable_node", "shutdown", "reset", "set_use_sim_time"]

CHILD_TAGS: dict[str, list[str]] = {
    "launch": ACTIONS,
    "group": ["keep"] + ACTIONS,
    "timer": ACTIONS,
    "arg": ["choice"],
    "include": ["arg"],
    "node": ["remap", "param", "env"],
    "executable": ["env"],
    "param": ["param"],
    "node_container": ["composable_node", "remap", "param", "env"],
    "composable_node": ["remap", "param", "extra_arg"],
    "load_composable_node": ["composable_node"],
    "reset": ["keep"],
}

SUBSTITUTIONS = ["var", "find-pkg-share", "find-pkg-prefix", "env", "eval", "not", "and", "or", "any", "all",
                 "equals", "not-equals", "if", "dirname", "filename", "anon", "command", "find-exec",
                 "exec-in-pkg", "file-content", "param", "launch_log_dir"]
