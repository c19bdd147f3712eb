"""ROS 2 launch files (``.launch.xml``, ``.launch.yaml``): the same analyses as for ROS 1.

Pure: no LSP here.  Public API::

    analyse_launch2(text, path, workspace_root=None, read_file=None, *, features=None, env=None,
                    packages=None, choices=None) -> LaunchAnalysis   # symbolic: all args at once
    load_launch2(path, args, workspace_root=None, read_file=None, *, text=None, env=None,
                 packages=None, stub_packages=True) -> Launch2Result  # concrete: what ros2 launch does
    free_args2(text, path) -> list[str]          # top-level args used only as booleans
    detect_dialect(path, text, ...) -> Dialect    # ROS 1 or ROS 2, and why

The analysis results are the shared model of :mod:`tvl_lsp.launch.model` (elements with
presence conditions and exact ranges, nodes, error facts, includes), so that every check,
hover, navigation and code action works on ROS 2 files unchanged.
"""

from .api import Launch2Result, analyse_launch2, choice_args, free_args2, load_launch2
from .dialect import Dialect, detect_dialect, is_ros2_path

__all__ = ["analyse_launch2", "choice_args", "load_launch2", "free_args2", "Launch2Result", "Dialect", "detect_dialect",
           "is_ros2_path"]
