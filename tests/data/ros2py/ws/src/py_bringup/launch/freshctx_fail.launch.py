# A LaunchContext() the file makes holds no launch configuration: performing one without a
# default raises SubstitutionFailure, and ros2 launch cannot load the file.
from launch import LaunchContext, LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    lc = LaunchContext()
    name = LaunchConfiguration('robot').perform(lc)
    return LaunchDescription([DeclareLaunchArgument('robot', default_value='r1'),
                              Node(package='py_bringup', executable='base', name=name)])
