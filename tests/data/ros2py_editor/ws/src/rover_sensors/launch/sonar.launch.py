# A sonar driver, included by the rover's launch files with launch_arguments.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('rate', default_value='5'),
        DeclareLaunchArgument('frame', default_value='sonar'),
        Node(package='rover_sensors', executable='sonar', name='sonar',
             parameters=[{'rate': LaunchConfiguration('rate'), 'frame_id': LaunchConfiguration('frame')}]),
    ])
