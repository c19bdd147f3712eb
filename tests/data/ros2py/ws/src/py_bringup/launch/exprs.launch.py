# Python computations and substitution expressions: PythonExpression over several arguments,
# Equals/And/Or/Not, LaunchConfigurationEquals/NotEquals, environment variables, Command,
# f-strings, % and format, comprehensions, loops, helper functions, dict methods.
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition, LaunchConfigurationEquals, LaunchConfigurationNotEquals, UnlessCondition
from launch.substitutions import (AndSubstitution, Command, EnvironmentVariable, EqualsSubstitution,
                                  LaunchConfiguration, NotSubstitution, OrSubstitution, PythonExpression)
from launch_ros.actions import Node

ROBOTS = ['alpha', 'beta']
DEFAULTS = {'rate': 10, 'frame': 'odom'}


def robot_node(name, index, extra=None):
    params = dict(DEFAULTS)
    params.update(extra or {})
    params['index'] = index
    return Node(package='py_bringup', executable='robot_driver', name=f'{name}_driver', namespace=name,
                parameters=[params], remappings=[('odom', '/%s/odom_raw' % name)])


def generate_launch_description():
    a = LaunchConfiguration('a')
    b = LaunchConfiguration('b')
    mode = LaunchConfiguration('mode')
    declared = [DeclareLaunchArgument(n, default_value=v) for n, v in (('a', 'true'), ('b', 'false'))]
    declared.append(DeclareLaunchArgument('mode', default_value='fast'))
    declared.append(DeclareLaunchArgument('count', default_value='2'))
    nodes = []
    for i, r in enumerate(ROBOTS):
        nodes.append(robot_node(r, i, {'frame': '{}_odom'.format(r)} if i else None))
    extra = [Node(package='py_bringup', executable='helper', name='helper_' + str(k)) for k in range(3) if k != 1]
    nodes.extend(extra)
    if DEFAULTS.get('rate', 0) > 5:
        nodes.append(Node(package='py_bringup', executable='fast_logger', name='fast_logger'))
    else:
        nodes.append(Node(package='py_bringup', executable='slow_logger', name='slow_logger'))
    return LaunchDescription(declared + [
        Node(package='py_bringup', executable='both', name='both',
             condition=IfCondition(PythonExpression(["'", a, "' == 'true' and '", b, "' == 'true'"]))),
        Node(package='py_bringup', executable='either', name='either',
             condition=IfCondition(PythonExpression(["'", a, "' == 'true' or '", b, "' == 'true'"]))),
        Node(package='py_bringup', executable='and_node', name='and_node',
             condition=IfCondition(AndSubstitution(a, NotSubstitution(b)))),
        Node(package='py_bringup', executable='or_node', name='or_node',
             condition=UnlessCondition(OrSubstitution(a, b))),
        Node(package='py_bringup', executable='eq_node', name='eq_node',
             condition=IfCondition(EqualsSubstitution(mode, 'fast'))),
        Node(package='py_bringup', executable='mode_fast', name='mode_fast',
             condition=LaunchConfigurationEquals('mode', 'fast')),
        Node(package='py_bringup', executable='mode_other', name='mode_other',
             condition=LaunchConfigurationNotEquals('mode', 'fast')),
        Node(package='py_bringup', executable='counter', name='counter',
             condition=IfCondition(PythonExpression([LaunchConfiguration('count'), ' > 1']))),
        Node(package='py_bringup', executable='env_reader', name='env_reader',
             parameters=[{'home': EnvironmentVariable('PY_ROBOT', default_value='none'),
                          'desc': Command(['echo ', mode])}]),
    ] + nodes)
