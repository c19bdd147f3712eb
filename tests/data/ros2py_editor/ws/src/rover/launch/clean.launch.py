# The rover's generic launch file, as it should be: one DeclareLaunchArgument per feature of clean.tvl.
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.conditions import IfCondition, UnlessCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import Node


def generate_launch_description():
    sensors = get_package_share_directory('rover_sensors')
    return LaunchDescription([
        DeclareLaunchArgument('Rover', default_value='true'),
        DeclareLaunchArgument('Base', default_value='true'),
        DeclareLaunchArgument('Diff', default_value='true'),
        DeclareLaunchArgument('Ackermann', default_value='false'),
        DeclareLaunchArgument('Lidar', default_value='false'),
        DeclareLaunchArgument('Camera', default_value='false'),
        DeclareLaunchArgument('Teleop', default_value='false'),
        DeclareLaunchArgument('Nav', default_value='false'),
        Node(package='rover', executable='diff_drive', name='drive',
             condition=IfCondition(LaunchConfiguration('Diff'))),
        Node(package='rover', executable='ackermann_drive', name='drive',
             condition=UnlessCondition(LaunchConfiguration('Diff'))),
        Node(package='rover', executable='camera', name='camera',
             parameters=[{'label': 'Kamera 📷 groß'}], condition=IfCondition(LaunchConfiguration('Camera'))),
        Node(package='rover', executable='lidar', name='lidar',
             condition=IfCondition(LaunchConfiguration('Lidar'))),
        Node(package='rover', executable='planner', name='planner',
             condition=IfCondition(PythonExpression(["'", LaunchConfiguration('Nav'), "' == 'true' and '",
                                                     LaunchConfiguration('Lidar'), "' == 'true'"]))),
        Node(package='rover', executable='teleop', name='teleop',
             condition=IfCondition(LaunchConfiguration('Teleop'))),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(os.path.join(sensors, 'launch', 'sonar.launch.py')),
            launch_arguments={'rate': '10', 'frame': 'sonar_link'}.items(),
            condition=IfCondition(LaunchConfiguration('Lidar'))),
    ])
