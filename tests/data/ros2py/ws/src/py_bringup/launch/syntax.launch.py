from launch import LaunchDescription


def generate_launch_description():
    return LaunchDescription([
        Node(package='py_bringup', executable='x' name='broken'),
    ])
