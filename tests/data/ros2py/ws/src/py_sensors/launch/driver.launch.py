# Included by includes.launch.py (and by xml_to_py.launch.xml).
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('rate', default_value='5'),
        DeclareLaunchArgument('frame', default_value='laser'),
        Node(package='py_sensors', executable='driver', name='driver',
             parameters=[{'rate': LaunchConfiguration('rate'), 'frame_id': LaunchConfiguration('frame')}],
             remappings=[('data', [LaunchConfiguration('frame'), '/data'])]),
    ])
