# What tvl-lsp cannot know statically: a branch on an environment variable (unknown unless set).
import os

from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    model = os.environ.get('PY_ROBOT_MODEL', 'burger')
    nodes = [Node(package='py_bringup', executable='base', name='base')]
    if model == 'waffle':
        nodes.append(Node(package='py_bringup', executable='camera', name='waffle_camera'))
    return LaunchDescription(nodes)
