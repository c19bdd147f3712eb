"""Which launch dialect a file is written in: ROS 1 (roslaunch) or ROS 2 (ros2/launch).

``.launch.yaml`` / ``.launch.yml`` / ``.launch.py`` files are ROS 2.  An XML file (``.launch``,
``.launch.xml``, ``.xml``) is decided, in this order, by

1. a marker comment: ``<!-- tvl-lsp: dialect=ros2 -->`` (or ``ros1``) forces it;
2. its content: ROS 2 writes ``$(var x)``, ``exec=``, ``<let>``, ``$(find-pkg-share p)``,
   ``namespace=``, ``<push_ros_namespace>`` ...; ROS 1 writes ``$(arg x)``, ``type=``,
   ``$(find p)``, ``ns=``, ``<rosparam>``, ``doc=`` ...; the side with more evidence wins;
3. its package: a ``package.xml`` with an ament build type is ROS 2, a catkin one ROS 1;
4. its name: ``.launch`` is ROS 1, ``.launch.xml`` ROS 2.

When the content does not decide (no evidence, or as much for both sides) the result says so
(``ambiguous``), with the reason, so that the editor can tell the user which reading it chose
and how to force the other one.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from typing import Optional

from ...base.files import read_head_text
from ..xml import strip_comments
from .ament import package_of

MARKER = re.compile(r"(?:<!--|#)\s*tvl-lsp\s*:[^\n>]*?\bdialect\s*=\s*(ros1|ros2)\b", re.I)

_ROS2 = [(re.compile(p), w) for p, w in (
    (r"\$\(var\s", 3), (r"<node\b[^>]{0,4000}\sexec\s*=", 3), (r"<let\b", 3), (r"\$\(find-pkg-(share|prefix)\s", 3),
    (r"<push[_-]ros[_-]namespace\b", 3), (r"<set_remap\b", 3), (r"<set_parameter\b", 3),
    (r"<executable\b", 2), (r"<node\b[^>]{0,4000}\snamespace\s*=", 2), (r"<arg\b[^>]{0,4000}\sdescription\s*=", 1),
    (r"<choice\b", 2), (r"\$\((not|and|or|equals|not-equals|filename)[\s)]", 2),
    (r"<include\b[^>]{0,4000}\sfile\s*=\s*[\"'][^\"']{0,4000}\.launch\.(py|yaml|yml)[\"']", 2),
    (r"<node_container\b", 3), (r"<composable_node\b", 3), (r"<set_env\b", 2), (r"<unset_env\b", 2),
    (r"<group\b[^>]{0,4000}\s(scoped|forwarding)\s*=", 3), (r"<keep\b", 3), (r"\$\(exec-in-pkg\s", 3),
    (r"<param\b[^>]{0,4000}\sfrom\s*=", 2))]
_ROS1 = [(re.compile(p), w) for p, w in (
    (r"\$\(arg\s", 3), (r"<node\b[^>]{0,4000}\stype\s*=", 3), (r"\$\(find\s", 3), (r"<rosparam\b", 3),
    (r"<(node|group|include)\b[^>]{0,4000}\sns\s*=", 2), (r"<arg\b[^>]{0,4000}\sdoc\s*=", 1), (r"<machine\b", 3),
    (r"<test\b", 2), (r"pass_all_args\s*=", 3), (r"\$\(optenv\s", 3), (r"<param\b[^>]{0,4000}\s(textfile|binfile|command)\s*=", 2),
    (r"clear_params\s*=", 2), (r"<master\b", 3),
    (r"<include\b[^>]{0,4000}\sfile\s*=\s*[\"'][^\"']{0,4000}\.launch[\"']", 1))]


@dataclass(frozen=True)
class Dialect:
    dialect: str                 # "ros1" | "ros2"
    reason: str                  # why (for the user)
    ambiguous: bool = False      # the content did not decide
    marker: Optional[tuple[int, int]] = None  # offsets of a dialect marker

    @property
    def ros2(self) -> bool:
        return self.dialect == "ros2"


def is_ros2_path(path: str) -> bool:
    """Files only ROS 2 has (YAML and Python launch files)."""
    return path.endswith((".launch.yaml", ".launch.yml", ".launch.py"))


MAX_SCORED = 200_000  # the content signals are read in the first 200 kB (a dialect shows early)


def _strip_comments(text: str) -> str:
    return strip_comments(text)


def content_scores(text: str) -> tuple[int, int]:
    body = _strip_comments(text[:MAX_SCORED])
    r2 = sum(w for rx, w in _ROS2 if rx.search(body))
    r1 = sum(w for rx, w in _ROS1 if rx.search(body))
    return r2, r1


def detect_dialect(path: str, text: Optional[str] = None, package_dialect: Optional[str] = "?") -> Dialect:
    """The dialect of the launch file at ``path`` (``text``: its content, read if None;
    ``package_dialect``: "ros1" / "ros2" / None when the caller knows the package, "?" to look
    for its package.xml)."""
    if path.endswith((".launch.yaml", ".launch.yml", ".yaml", ".yml")):
        return Dialect("ros2", "a YAML launch file (ROS 1 has none)")
    if path.endswith(".py"):
        return Dialect("ros2", "a Python launch file")
    if text is None:
        text = read_head_text(path, 2_000_000) or ""
    m = MARKER.search(text[:200_000])
    if m:
        d = m.group(1).lower()
        return Dialect(d, f"the marker comment says dialect={d}", marker=(m.start(1), m.end(1)))
    r2, r1 = content_scores(text[:2_000_000])
    if package_dialect == "?":
        pkg = package_of(path)
        package_dialect = pkg.dialect if pkg is not None else None
        pkg_name = pkg.name if pkg is not None else None
        build = pkg.build_type if pkg is not None else None
    else:
        pkg_name, build = None, package_dialect
    pkg_why = (f"its package {pkg_name} has build type {build}" if pkg_name else
               f"its package is {package_dialect}") if package_dialect else ""
    if r2 > r1:
        why = "it uses ROS 2 launch syntax ($(var), exec=, <let>, $(find-pkg-share) ...)"
        return Dialect("ros2", why, ambiguous=r1 > 0)
    if r1 > r2:
        why = "it uses ROS 1 launch syntax ($(arg), type=, $(find) ...)"
        return Dialect("ros1", why, ambiguous=r2 > 0)
    if package_dialect in ("ros1", "ros2"):
        return Dialect(package_dialect, pkg_why + ("; its content could be either" if r1 == r2 else ""),
                       ambiguous=True)
    if path.endswith(".launch"):
        return Dialect("ros1", "its name ends in .launch (ROS 1's convention); its content could be either",
                       ambiguous=True)
    return Dialect("ros2", f"its name ends in {os.path.splitext(path)[1] or 'nothing'} and it is in no catkin "
                   "package; its content could be either", ambiguous=True)
