# Composable nodes: a container with components, and components loaded into it.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import ComposableNodeContainer, LoadComposableNodes
from launch_ros.descriptions import ComposableNode


def generate_launch_description():
    container = ComposableNodeContainer(
        name='image_container',
        namespace='camera',
        package='rclcpp_components',
        executable='component_container',
        composable_node_descriptions=[
            ComposableNode(package='py_sensors', plugin='py_sensors::Rectify', name='rectify',
                           parameters=[{'queue_size': 5}], remappings=[('image', 'image_raw')]),
            ComposableNode(package='py_sensors', plugin='py_sensors::Debayer', name='debayer',
                           condition=IfCondition(LaunchConfiguration('debayer'))),
        ],
    )
    load = LoadComposableNodes(
        target_container='camera/image_container',
        composable_node_descriptions=[
            ComposableNode(package='py_sensors', plugin='py_sensors::Resize', name='resize', namespace='camera',
                           parameters=[{'scale': 0.5}]),
        ],
    )
    return LaunchDescription([
        DeclareLaunchArgument('debayer', default_value='true'),
        container,
        load,
    ])
