# No generate_launch_description(): not a launch file ros2 launch can load.
from launch import LaunchDescription


def make_description():
    return LaunchDescription([])
