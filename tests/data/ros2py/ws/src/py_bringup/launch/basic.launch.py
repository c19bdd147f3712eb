# Arguments, nodes, conditions, parameters (dicts and files), remappings, a process and a log.
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, LogInfo, SetEnvironmentVariable
from launch.conditions import IfCondition, UnlessCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    use_sim_time = LaunchConfiguration('use_sim_time')
    robot = LaunchConfiguration('robot')
    params = os.path.join(get_package_share_directory('py_bringup'), 'config', 'basic.yaml')
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use the simulation clock'),
        DeclareLaunchArgument('use_lidar', default_value='true'),
        DeclareLaunchArgument('use_camera', default_value='false'),
        DeclareLaunchArgument('robot', default_value='r1', description='Robot name'),
        DeclareLaunchArgument('mode', default_value='sim', choices=['sim', 'real']),
        SetEnvironmentVariable('RCUTILS_COLORIZED_OUTPUT', '1'),
        LogInfo(msg=['Starting robot ', robot]),
        Node(
            package='py_sensors',
            executable='lidar_node',
            name='lidar',
            namespace=robot,
            parameters=[params, {'use_sim_time': use_sim_time, 'rate': 10, 'frame': 'laser',
                                 'limits': {'min': 0.1, 'max': 30.0}}],
            remappings=[('scan', 'scan_raw'), ('/tf', 'tf')],
            condition=IfCondition(LaunchConfiguration('use_lidar')),
        ),
        Node(
            package='py_sensors',
            executable='camera_node',
            name='camera',
            condition=IfCondition(LaunchConfiguration('use_camera')),
            parameters=[{'robot': robot, 'fps': '30'}],
        ),
        Node(
            package='py_sensors',
            executable='fake_camera',
            name='camera',
            condition=UnlessCondition(LaunchConfiguration('use_camera')),
            arguments=['--ros-args', '--log-level', 'warn'],
        ),
        Node(package='py_bringup', executable='mode_reporter', output='screen',
             parameters=[{'mode': LaunchConfiguration('mode')}]),
        ExecuteProcess(cmd=['echo', 'hello', robot], name='greeter', output='screen'),
        # (launch_ros writes list parameters as Python tuples, which the oracle's YAML reader refuses:
        # the oracle shows this node's parameters as an error)
        Node(package='py_bringup', executable='lister', name='lister',
             parameters=[{'ids': [1, 2, 3], 'names': ['a', 'b'], 'gains': [1, 2.5]}]),
    ])
