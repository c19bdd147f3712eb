# context.environment.get of a variable that is not set: its default when launching here (the
# symbolic analysis cannot know whether it is set when launching: declined).
from launch import LaunchDescription
from launch.actions import OpaqueFunction
from launch_ros.actions import Node


def setup(context, *args, **kwargs):
    level = 'info'
    if context.environment.get('PY_CTX_DEBUG', '0') == '1':
        level = 'debug'
    return [Node(package='py_bringup', executable='base', name='base_' + level)]


def generate_launch_description():
    return LaunchDescription([OpaqueFunction(function=setup)])
