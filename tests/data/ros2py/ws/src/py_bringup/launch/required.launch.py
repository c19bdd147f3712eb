# An argument without a default: ros2 launch needs map:=...
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('map', description='The map file'),
        Node(package='py_bringup', executable='map_server', name='map_server',
             parameters=[{'yaml_filename': LaunchConfiguration('map')}]),
    ])
