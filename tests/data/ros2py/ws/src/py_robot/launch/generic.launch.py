# The generic launch file of py_robot: one DeclareLaunchArgument per feature of generic.tvl.
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, IncludeLaunchDescription
from launch.conditions import IfCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import Node

FEATURES = ['Robot', 'Base', 'Diff', 'Omni', 'Lidar', 'Camera', 'Fusion', 'Teleop']
ON = {'Robot', 'Base', 'Diff'}


def feature(name):
    return IfCondition(LaunchConfiguration(name))


def generate_launch_description():
    sensors = get_package_share_directory('py_sensors')
    args = [DeclareLaunchArgument(f, default_value='true' if f in ON else 'false') for f in FEATURES]
    return LaunchDescription(args + [
        Node(package='py_robot', executable='diff_drive', name='base', condition=feature('Diff')),
        Node(package='py_robot', executable='omni_drive', name='base', condition=feature('Omni')),
        GroupAction([
            IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(sensors, 'launch', 'driver.launch.py')),
                                     launch_arguments=[('rate', '15')]),
        ], condition=feature('Lidar')),
        Node(package='py_robot', executable='camera_driver', name='camera', condition=feature('Camera'),
             remappings=[('image_raw', 'camera/image')]),
        Node(package='py_robot', executable='fusion', name='fusion',
             condition=IfCondition(PythonExpression(["'", LaunchConfiguration('Lidar'), "' == 'true' and '",
                                                     LaunchConfiguration('Camera'), "' == 'true'"]))),
        Node(package='py_robot', executable='teleop_twist_keyboard', name='teleop', condition=feature('Teleop'),
             remappings=[('cmd_vel', 'base/cmd_vel')]),
    ])
