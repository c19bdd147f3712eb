# tvl-lsp: model=rover.tvl
# The rover's teleoperation, built with ld.add_action (a *_launch.py file paired by its marker):
# it declares no argument yet.
from launch import LaunchDescription
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    ld = LaunchDescription()
    ld.add_action(Node(package='rover', executable='teleop', name='teleop',
                       condition=IfCondition(LaunchConfiguration('Teleop'))))
    ld.add_action(Node(package='rover', executable='joy', name='joy'))
    return ld
