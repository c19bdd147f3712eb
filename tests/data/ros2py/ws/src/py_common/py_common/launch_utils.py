"""Helpers shared by launch files (a workspace module: tvl-lsp interprets it, never imports it)."""
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

COMMON_ARGS = {'use_sim_time': 'false', 'log_level': 'info'}


def declare_common():
    return [DeclareLaunchArgument(k, default_value=v) for k, v in COMMON_ARGS.items()]


def make_node(name, executable, **params):
    params.setdefault('use_sim_time', LaunchConfiguration('use_sim_time'))
    return Node(package='py_bringup', executable=executable, name=name, parameters=[params],
                arguments=['--ros-args', '--log-level', LaunchConfiguration('log_level')])
