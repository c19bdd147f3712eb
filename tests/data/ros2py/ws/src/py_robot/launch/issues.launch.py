# generic.launch.py with planted problems (for the cross-check with generic.tvl):
# 'Sonar' is no feature, 'Teleop' has no argument, 'ghost' runs in no product (Fusion without
# Lidar is impossible), two nodes named 'drive' run together when Diff and Camera do, and the
# condition of 'base_monitor' holds in every product (Base is mandatory).
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('Robot', default_value='true'),
        DeclareLaunchArgument('Base', default_value='true'),
        DeclareLaunchArgument('Diff', default_value='true'),
        DeclareLaunchArgument('Omni', default_value='false'),
        DeclareLaunchArgument('Lidar', default_value='false'),
        DeclareLaunchArgument('Camera', default_value='false'),
        DeclareLaunchArgument('Fusion', default_value='false'),
        DeclareLaunchArgument('Sonar', default_value='false'),
        Node(package='py_robot', executable='diff_drive', name='drive',
             condition=IfCondition(LaunchConfiguration('Diff'))),
        Node(package='py_robot', executable='camera_drive', name='drive',
             condition=IfCondition(LaunchConfiguration('Camera'))),
        Node(package='py_robot', executable='ghost', name='ghost',
             condition=IfCondition(PythonExpression(["'", LaunchConfiguration('Fusion'), "' == 'true' and '",
                                                     LaunchConfiguration('Lidar'), "' == 'false'"]))),
        Node(package='py_robot', executable='sonar', name='sonar',
             condition=IfCondition(LaunchConfiguration('Sonar'))),
        Node(package='py_robot', executable='base_monitor', name='base_monitor',
             condition=IfCondition(LaunchConfiguration('Base'))),
    ])
