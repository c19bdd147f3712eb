"""ament workspaces: packages, their build type, and where ``$(find-pkg-share pkg)`` points.

A ROS 2 workspace keeps its packages under ``src/`` (colcon's rules: the search stops at a
``package.xml``; ``COLCON_IGNORE`` / ``AMENT_IGNORE`` / ``CATKIN_IGNORE`` hide a folder; the
``build``, ``install`` and ``log`` folders colcon writes are skipped).  ``$(find-pkg-share
pkg)`` of a workspace package is its *source* folder: ``colcon build`` installs ``launch/``,
``config/`` ... from there into ``install/pkg/share/pkg``, so an installed file maps back to
the source file of the same relative path.  Packages installed elsewhere are found through
``AMENT_PREFIX_PATH`` (``share/ament_index/resource_index/packages/<pkg>``).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Mapping, Optional

from ...base.files import read_head_text
from ..xml import strip_comments

SKIP = {".git", "build", "install", "log", "devel", "node_modules", ".venv", "__pycache__", ".hg"}
IGNORE_MARKERS = ("COLCON_IGNORE", "AMENT_IGNORE", "CATKIN_IGNORE")
MAX_DIRS = 20000

_COMMENT = re.compile(r"<!--.*?-->", re.S)
_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_BUILD_TYPE = re.compile(r"<build_type(?:\s[^>]*)?>\s*([^<\s]+)\s*</build_type>")
_BUILDTOOL = re.compile(r"<buildtool_depend(?:\s[^>]*)?>\s*([^<\s]+)\s*</buildtool_depend>")

AMENT_TYPES = ("ament_cmake", "ament_python", "ament_cargo", "ament_cmake_python")


@dataclass(frozen=True)
class Package:
    name: str
    folder: str
    build_type: Optional[str]    # ament_cmake, ament_python, catkin, cmake, ... (None: not said)

    @property
    def dialect(self) -> Optional[str]:
        """"ros2" for ament packages, "ros1" for catkin ones, None when the manifest does not say."""
        bt = self.build_type or ""
        if bt.startswith("ament") or bt in ("cmake", "colcon"):
            return "ros2" if bt.startswith("ament") else None
        if bt == "catkin":
            return "ros1"
        return None


def read_manifest(text: str, folder: str) -> Package:
    text = strip_comments(text)
    m = _NAME.search(text)
    name = m.group(1) if m else os.path.basename(folder)
    bt = _BUILD_TYPE.search(text)
    build_type = bt.group(1) if bt else None
    if build_type is None:
        tools = _BUILDTOOL.findall(text)
        if any(t.startswith("ament") for t in tools):
            build_type = next(t for t in tools if t.startswith("ament"))
        elif "catkin" in tools:
            build_type = "catkin"
    return Package(name, folder, build_type)


def _scan(root: str) -> dict[str, Package]:
    out: dict[str, Package] = {}
    count = 0
    base = os.path.join(root, "src") if os.path.isdir(os.path.join(root, "src")) else root
    for dirpath, dirnames, filenames in os.walk(base):
        count += 1
        if count > MAX_DIRS:
            break
        dirnames[:] = sorted(d for d in dirnames if d not in SKIP and not d.startswith("."))
        if any(m in filenames for m in IGNORE_MARKERS):
            dirnames[:] = []
            continue
        if "package.xml" in filenames:
            dirnames[:] = []
            head = read_head_text(os.path.join(dirpath, "package.xml"), 200_000)
            if head is None:
                continue
            pkg = read_manifest(head, dirpath)
            out.setdefault(pkg.name, pkg)
    return out


@lru_cache(maxsize=16)
def _cached(root: str, mtime: float) -> dict[str, Package]:
    return _scan(root)


def find_ament_packages(workspace_root: Optional[str]) -> dict[str, Package]:
    """Package name -> Package for every package.xml of the workspace (under ``src/`` when it
    has one)."""
    if not workspace_root:
        return {}
    root = os.path.abspath(workspace_root)
    try:
        mtime = os.stat(root).st_mtime
        src = os.path.join(root, "src")
        if os.path.isdir(src):
            mtime = max(mtime, os.stat(src).st_mtime)
    except OSError:
        return {}
    return dict(_cached(root, mtime))


def installed_packages(env: Mapping[str, str]) -> dict[str, str]:
    """Packages of the ament prefixes in ``AMENT_PREFIX_PATH``: name -> share folder."""
    out: dict[str, str] = {}
    for prefix in (env.get("AMENT_PREFIX_PATH") or "").split(os.pathsep):
        if not prefix:
            continue
        idx = os.path.join(prefix, "share", "ament_index", "resource_index", "packages")
        try:
            names = os.listdir(idx)
        except OSError:
            continue
        for n in names:
            out.setdefault(n, os.path.join(prefix, "share", n))
    return out


def package_of(path: str) -> Optional[Package]:
    """The package whose folder holds ``path`` (the nearest package.xml upwards)."""
    d = os.path.dirname(os.path.abspath(path))
    for _ in range(40):
        m = os.path.join(d, "package.xml")
        if os.path.isfile(m):
            head = read_head_text(m, 200_000)
            return read_manifest(head, d) if head is not None else None
        nd = os.path.dirname(d)
        if nd == d:
            return None
        d = nd
    return None


def guess_ament_root(path: str) -> Optional[str]:
    """The workspace of a file: the nearest ancestor with a ``src`` folder holding packages
    (not counting a ``src`` folder inside a package), else the folder above the package."""
    d = os.path.dirname(os.path.abspath(path))
    pkg_parent = None
    for _ in range(40):
        if os.path.basename(d) != "src" and os.path.isdir(os.path.join(d, "src")) and \
                not os.path.isfile(os.path.join(d, "package.xml")):
            return d
        if pkg_parent is None and os.path.isfile(os.path.join(d, "package.xml")):
            pkg_parent = os.path.dirname(d)
            if os.path.basename(pkg_parent) == "src":
                return os.path.dirname(pkg_parent)
        nd = os.path.dirname(d)
        if nd == d:
            break
        d = nd
    return pkg_parent


# ------------------------------------------------------------------ launch extensions

# A Python package extends the launch front end with tags (``@expose_action('trace')``) and
# substitutions (``@expose_substitution('name')``) through the entry point group
# ``launch.frontend.launch_extension`` (tracetools_launch's <trace>, ...): ros2 launch loads
# them when the package is installed.  Found statically: nothing is imported or run.
EXTENSION_GROUP = "launch.frontend.launch_extension"
_EXPOSE = re.compile(r"expose_(action|substitution)\(\s*['\"]([A-Za-z_][\w-]*)['\"]")
_SECTION = re.compile(r"^\s*\[([^\]]+)\]\s*$")
MAX_EXTENSION_FILES = 400


def _exposed(folder: str) -> dict[str, str]:
    """tag or substitution name -> "action" / "substitution" exposed by the Python files under
    ``folder`` (tests and build folders skipped; bounded)."""
    out: dict[str, str] = {}
    seen = 0
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames[:] = sorted(d for d in dirnames if d not in SKIP and not d.startswith(".") and d != "test")
        for f in sorted(filenames):
            if not f.endswith(".py"):
                continue
            seen += 1
            if seen > MAX_EXTENSION_FILES:
                return out
            text = read_head_text(os.path.join(dirpath, f), 1_000_000)
            if text is None:
                continue
            if "expose_" in text:
                for kind, name in _EXPOSE.findall(text):
                    out.setdefault(name, kind)
    return out


def _entry_modules(text: str) -> list[str]:
    """The modules of the launch-extension entry points in an ``entry_points.txt``."""
    out, on = [], False
    for line in text.splitlines():
        m = _SECTION.match(line)
        if m:
            on = m.group(1).strip() == EXTENSION_GROUP
        elif on and "=" in line:
            out.append(line.split("=", 1)[1].split(":", 1)[0].strip())
    return out


@lru_cache(maxsize=64)
def _workspace_extension(folder: str, stamp: float) -> dict[str, str]:
    for name in ("setup.py", "setup.cfg", "pyproject.toml"):
        head = read_head_text(os.path.join(folder, name), 200_000)
        if head is not None and EXTENSION_GROUP in head:
            return _exposed(folder)
    return {}


@lru_cache(maxsize=16)
def _installed_extensions(prefixes: str) -> dict[str, tuple[str, str]]:
    out: dict[str, tuple[str, str]] = {}
    for prefix in prefixes.split(os.pathsep):
        lib = os.path.join(prefix, "lib") if prefix else ""
        try:
            pys = sorted(d for d in os.listdir(lib) if d.startswith("python")) if lib else []
        except OSError:
            continue
        for py in pys:
            for sub in ("site-packages", "dist-packages"):
                site = os.path.join(lib, py, sub)
                try:
                    metas = sorted(d for d in os.listdir(site) if d.endswith((".egg-info", ".dist-info")))
                except OSError:
                    continue
                for meta in metas:
                    # (the head of a regular file only: never a FIFO or a device)
                    head = read_head_text(os.path.join(site, meta, "entry_points.txt"), 100_000)
                    if head is None:
                        continue
                    mods = _entry_modules(head)
                    dist = meta.split("-", 1)[0]
                    for mod in mods:
                        for name, kind in _exposed(os.path.join(site, *mod.split("."))).items():
                            out.setdefault(name, (kind, dist))
    return out


def launch_extensions(packages: Mapping[str, str], env: Mapping[str, str]) -> dict[str, tuple[str, str]]:
    """Name -> ("action" | "substitution", package) of what the launch extensions of the
    workspace's packages (``packages``: name -> folder) and of the ament prefixes in
    ``AMENT_PREFIX_PATH`` add to the launch front end."""
    out: dict[str, tuple[str, str]] = {}
    for pkg, folder in sorted(packages.items()):
        try:
            stamp = max(os.stat(os.path.join(folder, n)).st_mtime for n in ("setup.py", "setup.cfg")
                        if os.path.exists(os.path.join(folder, n)))
        except ValueError:
            continue  # not a Python package
        except OSError:
            continue
        for name, kind in _workspace_extension(folder, stamp).items():
            out.setdefault(name, (kind, pkg))
    for name, v in _installed_extensions(env.get("AMENT_PREFIX_PATH") or "").items():
        out.setdefault(name, v)
    return out
