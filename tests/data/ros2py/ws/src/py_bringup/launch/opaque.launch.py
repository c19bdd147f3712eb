# OpaqueFunction: the function reads the arguments' values and returns actions.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription, OpaqueFunction
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def launch_setup(context, *args, **kwargs):
    robot = context.launch_configurations['robot']
    use_extra = LaunchConfiguration('use_extra').perform(context)
    count = int(context.launch_configurations.get('count', '1'))
    actions = []
    for i in range(count):
        actions.append(Node(package='py_bringup', executable='worker', name=f'{robot}_worker_{i}'))
    if use_extra.lower() == 'true':
        actions.append(Node(package='py_bringup', executable='extra', name='extra', namespace=robot))
    if robot == 'r2':
        actions.append(IncludeLaunchDescription(PythonLaunchDescriptionSource(
            PathJoinSubstitution([FindPackageShare('py_sensors'), 'launch', 'driver.launch.py'])),
            launch_arguments={'frame': robot + '_frame'}.items()))
    return actions


def tagged(context, tag):
    return [Node(package='py_bringup', executable='tagger', name='tagger_' + tag,
                 parameters=[{'robot': context.launch_configurations['robot']}])]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('robot', default_value='r1'),
        DeclareLaunchArgument('use_extra', default_value='false'),
        DeclareLaunchArgument('count', default_value='2'),
        OpaqueFunction(function=launch_setup),
        OpaqueFunction(function=tagged, args=['x']),
    ])
