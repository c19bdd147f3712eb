# Load-time errors of ros2 launch, one flag each.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.conditions import IfCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('use_undefined', default_value='false'),
        DeclareLaunchArgument('use_missing', default_value='false'),
        DeclareLaunchArgument('cond_value', default_value='true'),
        DeclareLaunchArgument('bad_ns', default_value='false'),
        Node(package='py_bringup', executable='reader', name='reader',
             parameters=[{'x': LaunchConfiguration('not_declared')}],
             condition=IfCondition(LaunchConfiguration('use_undefined'))),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(PathJoinSubstitution([FindPackageShare('py_sensors'), 'launch',
                                                                'missing.launch.py'])),
            condition=IfCondition(LaunchConfiguration('use_missing'))),
        Node(package='py_bringup', executable='conditional', name='conditional',
             condition=IfCondition(LaunchConfiguration('cond_value'))),
        Node(package='py_bringup', executable='spaced', name='spaced', namespace='bad ns',
             condition=IfCondition(LaunchConfiguration('bad_ns'))),
    ])
