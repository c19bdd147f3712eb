# An obsolete keyword (Dashing's node_executable): launch_ros refuses the file.
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        Node(package='py_bringup', node_executable='old_node', node_name='old'),
    ])
