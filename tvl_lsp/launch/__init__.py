"""Launch files: the dialect-independent model (``model``: elements with presence conditions,
facts, ``LaunchAnalysis`` / ``LoadResult``), secure XML with exact ranges (``xml``), package
discovery (``packages``), and the ROS 1 front end (``ros1/``: load-time rules, arg scopes,
substitution args, the symbolic load).  A second dialect gets its own sub-package beside
``ros1/`` producing the same model.  Pure: no LSP here.

Public API::

    analyse_launch(text, path, workspace_root=None, read_file=None, *, features=None, env=None,
                   packages=None) -> LaunchAnalysis      # symbolic: all assignments at once
    check_launch(analysis) -> list[Diagnostic]          # a launch file on its own (no model)
    load_launch(path, args, workspace_root=None, read_file=None, *, text=None, env=None,
                packages=None) -> LoadResult             # concrete: one assignment, like roslaunch
    parse_xml(text, path) -> XmlDoc                      # secure parse with exact ranges
    find_packages(workspace_root) -> {package: folder}

Both dialects (chosen by file kind and content, ``launch/ros2/dialect.py``)::

    analyse_any(text, path, ...) -> LaunchAnalysis      # ROS 1 or ROS 2 front end; .dialect says which
    load_any(path, args, ...) -> LoadResult | Launch2Result
    dialect_of(path, text) -> Dialect
    free_args_of_file(text, path) -> list[str]          # args checked as free booleans without a model
"""

from .ros1.loader import analyse_launch, check_launch, load_launch
from .model import (ArgDecl, Attr, Element, ErrorFact, IncludeFact, LaunchAnalysis, LoadResult, NodeFact,
                    ParamFact, RemapCase, Subst)
from .packages import find_packages, guess_workspace_root
from .xml import parse_xml
from .dialects import (ARG_KINDS, analyse_any, dialect_of, free_args_of_file, include_targets, is_launch_path,
                       load_any)

parse_launch = analyse_launch
launch_diagnostics = check_launch

__all__ = ["analyse_launch", "check_launch", "launch_diagnostics", "load_launch", "parse_launch", "parse_xml", "find_packages",
           "guess_workspace_root", "ArgDecl", "Attr", "Element", "ErrorFact", "IncludeFact", "LaunchAnalysis",
           "LoadResult", "NodeFact", "ParamFact", "RemapCase", "Subst", "ARG_KINDS", "analyse_any", "dialect_of",
           "free_args_of_file", "include_targets", "is_launch_path", "load_any"]
