# Event handlers: their actions start only when a process starts or exits (listed apart).
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, LogInfo, RegisterEventHandler
from launch.event_handlers import OnProcessExit, OnProcessStart
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    spawner = Node(package='py_bringup', executable='spawner', name='spawner', arguments=['joint_state_broadcaster'])
    controller = Node(package='py_bringup', executable='spawner', name='controller_spawner',
                      arguments=[LaunchConfiguration('controller')])
    return LaunchDescription([
        DeclareLaunchArgument('controller', default_value='forward_controller'),
        spawner,
        RegisterEventHandler(OnProcessExit(target_action=spawner, on_exit=[controller])),
        RegisterEventHandler(event_handler=OnProcessStart(
            target_action=spawner, on_start=[LogInfo(msg='spawner started'),
                                             Node(package='py_bringup', executable='watcher', name='watcher')])),
        ExecuteProcess(cmd=['sleep', '1'], name='sleeper'),
    ])
