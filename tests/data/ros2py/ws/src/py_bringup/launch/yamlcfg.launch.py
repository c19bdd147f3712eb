# A workspace YAML file drives the nodes (read and parsed, never anything else).
import os

import yaml
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def load_robots():
    path = os.path.join(get_package_share_directory('py_sensors'), 'config', 'robots.yaml')
    with open(path, 'r') as f:
        return yaml.safe_load(f)


def generate_launch_description():
    cfg = load_robots()
    ld = LaunchDescription()
    for r in cfg['robots']:
        ld.add_action(Node(package='py_sensors', executable=r['sensor'] + '_node', name=r['name'] + '_' + r['sensor'],
                           namespace=r['name'], parameters=[{'rate': cfg['settings']['rate']}]))
    return ld
