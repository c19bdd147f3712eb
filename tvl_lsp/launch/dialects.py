"""One entry point for both launch dialects: ROS 1 (roslaunch XML) and ROS 2 (ros2/launch XML
and YAML).  Pure: no LSP here.

    analyse_any(text, path, ...) -> LaunchAnalysis   # the front end of the file's dialect
    load_any(path, args, ...) -> LoadResult | Launch2Result
    dialect_of(path, text) -> Dialect               # see tvl_lsp.launch.ros2.dialect

Both front ends produce the shared model of :mod:`tvl_lsp.launch.model`; ``LaunchAnalysis.dialect``
says which one did.  A ``.launch.xml`` file whose dialect the content does not decide gets a
``launch-dialect`` information diagnostic on its root tag saying which reading was chosen and
why (and how to force the other).
"""

from __future__ import annotations

import re
from typing import Iterable, Mapping, Optional

from ..base.diagnostics import Diagnostic, Severity, register
from .model import LaunchAnalysis
from .ros2.dialect import Dialect, detect_dialect

# the substitutions that read a launch argument: roslaunch's $(arg X), ros2/launch's $(var X)
ARG_KINDS = ("arg", "var")

# launch file names: roslaunch's .launch (and .launch.xml, .test), ros2/launch's .launch.xml /
# .launch.yaml / .launch.py and the *_launch.xml / *_launch.yaml / *_launch.py of the ROS 2 tutorials
LAUNCH_SUFFIXES = (".launch", ".launch.xml", ".launch.yaml", ".launch.yml", ".launch.py", "_launch.xml",
                   "_launch.yaml", "_launch.yml", "_launch.py")


def is_launch_path(path: str) -> bool:
    return path.endswith(LAUNCH_SUFFIXES)


def launch_stem(path: str) -> str:
    """``robot`` for robot.launch, robot.launch.xml, robot.launch.yaml, robot_launch.xml ..."""
    import os
    base = os.path.basename(path)
    for suf in sorted(LAUNCH_SUFFIXES, key=len, reverse=True):
        if base.endswith(suf):
            return base[: -len(suf)]
    return os.path.splitext(base)[0]


LAUNCH_DIALECT = register("launch-dialect", Severity.INFORMATION,
                          "Which launch dialect (ROS 1 or ROS 2) tvl-lsp reads a file as, when its content does not say.", "launch")


def dialect_of(path: str, text: Optional[str] = None) -> Dialect:
    return detect_dialect(path, text)


def analyse_any(text: str, path: str, workspace_root: Optional[str] = None, read_file=None, *,
                features: Optional[Iterable[str]] = None, env: Optional[Mapping[str, str]] = None,
                packages: Optional[dict[str, str]] = None, choices=None,
                dialect: Optional[Dialect] = None, partial: bool = False, lenient: bool = False) -> LaunchAnalysis:
    """Analyse a launch file with the front end of its dialect (``choices``, ``partial``: see
    :func:`tvl_lsp.launch.ros2.analyse_launch2`; ROS 1 ignores them)."""
    d = dialect or detect_dialect(path, text)
    if d.ros2:
        from .ros2 import analyse_launch2
        la = analyse_launch2(text, path, workspace_root=workspace_root, read_file=read_file, features=features,
                             env=env, packages=None if packages is None else _ros2_packages(packages),
                             choices=choices, partial=partial, lenient=lenient)
    else:
        from .ros1.loader import analyse_launch
        la = analyse_launch(text, path, workspace_root=workspace_root, read_file=read_file, features=features,
                            env=env, packages=packages, alone=lenient)
    la.dialect = d.dialect
    if d.ambiguous and d.marker is None and path.endswith((".launch.xml", ".xml")) and la.root is not None:
        other = "ros1" if d.ros2 else "ros2"
        name = "ROS 2" if d.ros2 else "ROS 1"
        la.diagnostics.append(Diagnostic(
            LAUNCH_DIALECT, Severity.INFORMATION, la.path, la.root.tag_span or la.root.span,
            f"tvl-lsp reads this file as {name} launch XML: {d.reason}. Add <!-- tvl-lsp: dialect={other} --> "
            f"to read it as {'ROS 1' if other == 'ros1' else 'ROS 2'}"))
    return la


def _ros2_packages(packages: Mapping[str, str]) -> dict[str, str]:
    import os
    return {k: os.path.realpath(v) for k, v in packages.items()}


# a Python launch file's literal launch file names (PythonLaunchDescriptionSource(... 'x.launch.py'), os.path.join
# (..., 'launch', 'x_launch.py'), PathJoinSubstitution([..., 'x.launch.xml']) ...)
_INCLUDE_PY = re.compile(r"""["']([^"'\n]{0,300}?(?:[._]launch\.(?:py|xml|yaml|yml)|\.launch))["']""")
_INCLUDE_XML = re.compile(r"<include\b[^>]{0,4000}?\bfile\s*=\s*(?:\"([^\"]*)\"|'([^']*)')", re.S)
_INCLUDE_YAML = re.compile(r"^\s*-?\s*(?:include\s*:\s*\{[^}\n]*?\bfile\s*:|file\s*:)\s*[\"']?([^\"'\n,}]+)", re.M)


def include_targets(text: str) -> set[str]:
    """The base names of the launch files a launch file includes (as written: ``.../x.launch.xml``
    -> ``x.launch.xml``; names made by a substitution are left out)."""
    out: set[str] = set()
    if "LaunchDescription" in text[:5_000_000] and ("import" in text[:5_000_000]):
        # a Python launch file: the launch file names it writes as literals
        for m in _INCLUDE_PY.finditer(text[:5_000_000]):
            out.add(m.group(1).strip())
    for m in _INCLUDE_XML.finditer(text[:5_000_000]):
        out.add((m.group(1) if m.group(1) is not None else m.group(2)).strip())
    for m in _INCLUDE_YAML.finditer(text[:5_000_000]):
        out.add(m.group(1).strip())
    names = set()
    for v in out:
        base = v.rsplit("/", 1)[-1]
        if base and "$(" not in base and is_launch_path(base):
            names.add(base)
    return names


def free_args_of_file(text: str, path: str, dialect: Optional[Dialect] = None,
                      unused: bool = False) -> Optional[list[str]]:
    """ROS 2: the top-level args checked as free booleans without a model.  ROS 1: None (the
    project layer's ``free_top_args`` decides)."""
    d = dialect or detect_dialect(path, text)
    if not d.ros2:
        return None
    from .ros2 import free_args2
    return free_args2(text, path, unused)


def load_any(path: str, args: Mapping[str, str], workspace_root: Optional[str] = None, read_file=None, *,
             text: Optional[str] = None, env: Optional[Mapping[str, str]] = None, stub_packages: bool = True):
    """What roslaunch / ros2 launch loads from ``path`` for ``args``."""
    d = detect_dialect(path, text)
    if d.ros2:
        from .ros2 import load_launch2
        return load_launch2(path, args, workspace_root, read_file, text=text, env=env, stub_packages=stub_packages)
    from .ros1.loader import load_launch
    return load_launch(path, args, workspace_root, read_file, text=text, env=env)
