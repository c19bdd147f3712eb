# OpaqueFunction(function=obj.method): launch calls the bound method with the context; the
# method keeps its nodes on the object (and a plain function its state in a global).  A LaunchConfiguration default that is a pathlib.Path
# is made text by str() (a Path is not iterable).
from pathlib import Path

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


class Bringup:
    def __init__(self, prefix):
        self.prefix = prefix
        self.nodes = []
        self.config = {name: LaunchConfiguration(name) for name in ('use_b', 'robot')}

    def declarations(self):
        return [DeclareLaunchArgument('use_b', default_value='false'),
                DeclareLaunchArgument('robot', default_value='r1'),
                DeclareLaunchArgument('bags', default_value=LaunchConfiguration('bags', default=Path('/tmp//bags/')))]

    def setup(self, context, *args, **kwargs):
        robot = self.config['robot'].perform(context)
        self.nodes.append(Node(package='py_bringup', executable='base', name=f'{self.prefix}_{robot}'))
        if self.config['use_b'].perform(context) == 'true':
            self.nodes.append(Node(package='py_bringup', executable='camera', name=f'{self.prefix}_b'))
        bags = LaunchConfiguration('bags').perform(context)
        self.nodes.append(Node(package='py_bringup', executable='lidar', name=f'bag{len(self.nodes)}',
                               remappings=[('bags', bags.strip('/').replace('/', '_'))]))
        return list(self.nodes)


SEEN = []


def plain(context, *args, **kwargs):
    """A plain function that keeps state in a global of the module."""
    if LaunchConfiguration('use_b').perform(context) == 'true':
        SEEN.append('b')
    SEEN.append('x')
    return [Node(package='py_bringup', executable='base', name=f'plain{len(SEEN)}')]


def generate_launch_description():
    b = Bringup('bound')
    return LaunchDescription(b.declarations() + [OpaqueFunction(function=b.setup), OpaqueFunction(function=plain)])
