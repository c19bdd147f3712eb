# A LaunchContext() the file makes itself (outside any launch), its substitutions performed at
# once: environment variables that are not set take their defaults (known when launching only:
# the symbolic analysis declines).
import os

from launch import LaunchContext, LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import EnvironmentVariable, LaunchConfiguration, PathJoinSubstitution, \
    TextSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    lc = LaunchContext()
    ld = LaunchDescription([DeclareLaunchArgument('robot', default_value='r1')])

    robot = EnvironmentVariable('R2_ROBOT', default_value='none')
    lidar = EnvironmentVariable('PY_FRESH_LIDAR', default_value='false')
    model = EnvironmentVariable('PY_FRESH_MODEL', default_value=['ust', TextSubstitution(text='10')])
    # a configuration declared above is not in this new context: its default here is used
    mode = LaunchConfiguration('robot', default='fresh')

    if robot.perform(lc) == 'burger':
        ld.add_action(Node(package='py_bringup', executable='base', name='burger_base'))
    if lidar.perform(lc) == 'true':
        ld.add_action(Node(package='py_bringup', executable='lidar', name='lidar'))
    cfg = PathJoinSubstitution([FindPackageShare('py_sensors'), 'config', 'sensors.yaml']).perform(lc)
    ld.add_action(Node(package='py_bringup', executable='camera', name=model.perform(lc) + '_' + mode.perform(lc),
                       remappings=[('cfg', os.path.basename(cfg))]))
    return ld
