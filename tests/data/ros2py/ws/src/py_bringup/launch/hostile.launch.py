# Code tvl-lsp never runs: exec, subprocess, a loop that does not end (declined, never executed).
import subprocess

from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    out = subprocess.check_output(['hostname'])
    n = 0
    while True:
        n += 1
    return LaunchDescription([Node(package='py_bringup', executable='x', name=str(out))])
