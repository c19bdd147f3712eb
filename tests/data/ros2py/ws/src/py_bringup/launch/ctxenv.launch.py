# context.environment in an OpaqueFunction: the process's environment (R2_ROBOT=burger in the
# runs) with the launch's SetEnvironmentVariable changes in scope.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, OpaqueFunction, SetEnvironmentVariable
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def setup(context, *args, **kwargs):
    env = context.environment
    nodes = []
    if env.get('R2_ROBOT') == 'burger':
        nodes.append(Node(package='py_bringup', executable='base', name='env_base'))
    if 'PY_CTX_MODE' in env:
        nodes.append(Node(package='py_bringup', executable='camera', name='cam_' + env['PY_CTX_MODE']))
    return nodes


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('mode', default_value='fast'),
        GroupAction([SetEnvironmentVariable('PY_CTX_MODE', 'scoped'), OpaqueFunction(function=setup)]),
        SetEnvironmentVariable('PY_CTX_MODE', LaunchConfiguration('mode')),
        OpaqueFunction(function=setup),
    ])
