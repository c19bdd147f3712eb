# Includes across dialects: Python -> Python, XML and YAML; launch_arguments as tuples and dict items.
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, IncludeLaunchDescription
from launch.conditions import IfCondition, UnlessCondition
from launch.launch_description_sources import (AnyLaunchDescriptionSource, PythonLaunchDescriptionSource)
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution, TextSubstitution
from launch_ros.actions import PushRosNamespace
from launch_ros.substitutions import FindPackageShare
from launch_xml.launch_description_sources import XMLLaunchDescriptionSource
from launch_yaml.launch_description_sources import YAMLLaunchDescriptionSource


def generate_launch_description():
    sensors = get_package_share_directory('py_sensors')
    driver_args = {'rate': LaunchConfiguration('rate'), 'frame': 'base_laser'}
    return LaunchDescription([
        DeclareLaunchArgument('rate', default_value='15'),
        DeclareLaunchArgument('use_xml', default_value='true'),
        DeclareLaunchArgument('use_yaml', default_value='false'),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(os.path.join(sensors, 'launch', 'driver.launch.py')),
            launch_arguments=driver_args.items(),
        ),
        GroupAction([
            PushRosNamespace('front'),
            IncludeLaunchDescription(
                XMLLaunchDescriptionSource(
                    PathJoinSubstitution([FindPackageShare('py_sensors'), 'launch', 'lidar.launch.xml'])),
                launch_arguments=[('rate', '40'), ('frame', TextSubstitution(text='front_laser'))],
                condition=IfCondition(LaunchConfiguration('use_xml')),
            ),
        ]),
        IncludeLaunchDescription(
            YAMLLaunchDescriptionSource([FindPackageShare('py_sensors'), '/launch/cam.launch.yaml']),
            condition=IfCondition(LaunchConfiguration('use_yaml')),
        ),
        IncludeLaunchDescription(
            AnyLaunchDescriptionSource(os.path.join(sensors, 'launch', 'lidar.launch.xml')),
            launch_arguments={'frame': 'rear_laser'}.items(),
            condition=UnlessCondition(LaunchConfiguration('use_xml')),
        ),
    ])
