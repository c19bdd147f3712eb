# Groups (scoped, forwarding, launch_configurations), namespaces, global remaps and parameters, timers.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, SetLaunchConfiguration, TimerAction
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node, PushRosNamespace, PushROSNamespace, SetParameter, SetRemap


def generate_launch_description():
    ns = LaunchConfiguration('ns')
    return LaunchDescription([
        DeclareLaunchArgument('ns', default_value='robot1'),
        DeclareLaunchArgument('use_group', default_value='true'),
        DeclareLaunchArgument('color', default_value='red'),
        SetParameter(name='use_sim_time', value=True),
        GroupAction([
            PushRosNamespace(ns),
            SetRemap(src='cmd_vel', dst='cmd_vel_safe'),
            SetLaunchConfiguration('color', 'blue'),
            Node(package='py_bringup', executable='controller', name='controller',
                 parameters=[{'color': LaunchConfiguration('color')}]),
            GroupAction([
                PushROSNamespace('sensors'),
                Node(package='py_sensors', executable='imu_node', name='imu', remappings=[('imu', 'imu/data')]),
            ]),
        ], condition=IfCondition(LaunchConfiguration('use_group'))),
        Node(package='py_bringup', executable='monitor', name='monitor',
             parameters=[{'color': LaunchConfiguration('color')}]),
        GroupAction([
            SetLaunchConfiguration('color', 'green'),
            Node(package='py_bringup', executable='painter', name='painter_unscoped',
                 parameters=[{'color': LaunchConfiguration('color')}]),
        ], scoped=False),
        Node(package='py_bringup', executable='monitor', name='monitor_after',
             parameters=[{'color': LaunchConfiguration('color')}]),
        GroupAction([
            Node(package='py_bringup', executable='painter', name='painter_forward',
                 parameters=[{'shade': LaunchConfiguration('shade')}]),
        ], forwarding=False, launch_configurations={'shade': 'dark'}),
        TimerAction(period=2.0, actions=[
            Node(package='py_bringup', executable='late', name='late_node', namespace=ns),
        ]),
    ])
