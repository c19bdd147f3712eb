# A Python launch file: tvl-lsp interprets it (never runs it); the oracle runs it with --allow-python.
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package='r2_sensors', executable='driver', name='driver')])
