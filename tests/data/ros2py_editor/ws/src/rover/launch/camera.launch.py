# The rover's camera, configured when launching: an OpaqueFunction reads the arguments.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def camera_nodes(context):
    if context.launch_configurations['Camera'] != 'true':
        return []
    fps = LaunchConfiguration('fps').perform(context)
    return [Node(package='rover', executable='camera', name='camera', parameters=[{'fps': int(fps)}])]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('Cam', default_value='true'),
        DeclareLaunchArgument('Camera', default_value='false'),
        DeclareLaunchArgument('fps', default_value='30'),
        OpaqueFunction(function=camera_nodes),
    ])
