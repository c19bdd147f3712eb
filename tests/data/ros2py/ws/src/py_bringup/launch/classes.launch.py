# Classes of the file: a configuration helper (methods, a property, a class attribute, super()) and a
# Substitution subclass performed when launching, which reads an argument's value.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch.substitution import Substitution
from launch_ros.actions import Node


class Base:
    prefix = 'robot'

    def __init__(self, name):
        self.name = name

    def full(self, suffix):
        return f'{self.prefix}_{self.name}_{suffix}'


class Sensor(Base):
    prefix = 'sensor'

    def __init__(self, name, enabled=True):
        super().__init__(name)
        self.enabled = enabled

    @property
    def executable(self):
        return self.name + '_node'

    def node(self):
        return Node(package='py_sensors', executable=self.executable, name=self.full('driver'),
                    condition=IfCondition(LaunchConfiguration('use_' + self.name)))


class ConditionalText(Substitution):
    def __init__(self, text_if, text_else, flag):
        super().__init__()
        self.text_if = text_if
        self.text_else = text_else
        self.flag = flag

    def perform(self, context):
        if LaunchConfiguration(self.flag).perform(context) == 'true':
            return self.text_if
        return self.text_else


def generate_launch_description():
    sensors = [Sensor('lidar'), Sensor('camera', enabled=False)]
    return LaunchDescription(
        [DeclareLaunchArgument('use_' + s.name, default_value='true' if s.enabled else 'false') for s in sensors]
        + [DeclareLaunchArgument('fast', default_value='false')]
        + [s.node() for s in sensors]
        + [Node(package='py_bringup', executable='selector', name=ConditionalText('fast_mode', 'slow_mode', 'fast'),
                remappings=[('out', ConditionalText('fast_out', 'slow_out', 'fast'))])])
