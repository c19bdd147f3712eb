# tvl-lsp: model=camera.tvl
# The camera's arguments declared from a list: a rename of a feature cannot tell that the list's
# strings are argument names (it says so).
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

FEATURES = ['Camera', 'Cam']


def generate_launch_description():
    return LaunchDescription([DeclareLaunchArgument(f, default_value='false') for f in FEATURES] + [
        Node(package='rover', executable='camera', name='camera',
             condition=IfCondition(LaunchConfiguration('Camera'))),
    ])
