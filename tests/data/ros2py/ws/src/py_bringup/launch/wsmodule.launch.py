# A helper module of the workspace (py_common), put on sys.path the way some files do.
import os
import sys

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription

sys.path.insert(0, get_package_share_directory('py_common'))
from py_common.launch_utils import declare_common, make_node  # noqa: E402


def generate_launch_description():
    return LaunchDescription(declare_common() + [
        make_node('planner', 'planner_node', horizon=5),
        make_node('tracker', 'tracker_node'),
    ])
