# Corner cases of names and namespaces, substitution lists, pushes, containers without namespace.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction
from launch.substitutions import LaunchConfiguration, TextSubstitution, ThisLaunchFileDir
from launch_ros.actions import ComposableNodeContainer, Node, PushRosNamespace
from launch_ros.descriptions import ComposableNode


def generate_launch_description():
    ns = LaunchConfiguration('ns')
    return LaunchDescription([
        DeclareLaunchArgument('ns', default_value=''),
        DeclareLaunchArgument('prefix', default_value='robot'),
        Node(package='py_bringup', executable='empty_ns', name='empty_ns', namespace=''),
        Node(package='py_bringup', executable='root_ns', name='root_ns', namespace='/'),
        Node(package='py_bringup', executable='arg_ns', name='arg_ns', namespace=ns),
        Node(package='py_bringup', executable='listed', name=[LaunchConfiguration('prefix'), '_listed'],
             namespace=['/', LaunchConfiguration('prefix')]),
        Node(package='py_bringup', executable='unnamed'),
        Node(package='py_bringup', executable='exec_named', exec_name='custom_exec'),
        Node(package='py_bringup', executable='text_sub', name=TextSubstitution(text='text_sub'),
             remappings=[(['in_', LaunchConfiguration('prefix')], 'out'), ('a', TextSubstitution(text='b'))]),
        GroupAction([
            PushRosNamespace(''),
            Node(package='py_bringup', executable='pushed_empty', name='pushed_empty'),
        ]),
        GroupAction([
            PushRosNamespace(LaunchConfiguration('prefix')),
            PushRosNamespace('inner'),
            Node(package='py_bringup', executable='two_pushes', name='two_pushes', namespace='rel'),
            Node(package='py_bringup', executable='abs', name='abs', namespace='/abs'),
        ]),
        ComposableNodeContainer(
            name='container', namespace='', package='rclcpp_components', executable='component_container',
            composable_node_descriptions=[
                ComposableNode(package='py_bringup', plugin='py_bringup::A', name='comp_a'),
                ComposableNode(package='py_bringup', plugin='py_bringup::B', name='comp_b', namespace='ns_b'),
                ComposableNode(package='py_bringup', plugin='py_bringup::C'),
            ]),
        Node(package='py_bringup', executable='dir_param', name='dir_param',
             parameters=[{'dir': ThisLaunchFileDir()}]),
    ])
