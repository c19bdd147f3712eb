"""Catkin packages of a workspace: ``package.xml`` ``<name>`` -> package folder."""

from __future__ import annotations

import os
import re
from functools import lru_cache

_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_SKIP = {".git", "build", "devel", "install", "node_modules", ".venv", "__pycache__", "log", ".hg"}
MAX_DIRS = 20000


def _scan(root: str) -> dict[str, str]:
    out: dict[str, str] = {}
    count = 0
    for dirpath, dirnames, filenames in os.walk(root):
        count += 1
        if count > MAX_DIRS:
            break
        dirnames[:] = sorted(d for d in dirnames if d not in _SKIP and not d.startswith("."))
        if "CATKIN_IGNORE" in filenames or "COLCON_IGNORE" in filenames:
            dirnames[:] = []
            continue
        if "package.xml" in filenames:
            try:
                with open(os.path.join(dirpath, "package.xml"), encoding="utf-8", errors="replace") as f:
                    m = _NAME.search(f.read(200_000))
            except OSError:
                m = None
            name = m.group(1) if m else os.path.basename(dirpath)
            out.setdefault(name, dirpath)
            dirnames[:] = []  # packages do not nest
    return out


@lru_cache(maxsize=16)
def _cached(root: str, mtime: float) -> dict[str, str]:
    return _scan(root)


def find_packages(workspace_root: str | None) -> dict[str, str]:
    """Package name -> absolute folder, for every package.xml under ``workspace_root``."""
    if not workspace_root:
        return {}
    root = os.path.abspath(workspace_root)
    try:
        mtime = os.stat(root).st_mtime
    except OSError:
        return {}
    return dict(_cached(root, mtime))


def guess_workspace_root(path: str) -> str | None:
    """The nearest ancestor holding a ``src`` folder (catkin) or, failing that, the folder
    above the nearest package.xml."""
    d = os.path.dirname(os.path.abspath(path))
    pkg_parent = None
    while True:
        if os.path.isdir(os.path.join(d, "src")) and os.path.basename(d) != "src":
            if any(os.path.isfile(os.path.join(d, "src", x, "package.xml"))
                   for x in _listdir(os.path.join(d, "src"))):
                return d
        if pkg_parent is None and os.path.isfile(os.path.join(d, "package.xml")):
            pkg_parent = os.path.dirname(d)
        nd = os.path.dirname(d)
        if nd == d:
            return pkg_parent
        d = nd


def _listdir(d: str) -> list[str]:
    try:
        return os.listdir(d)
    except OSError:
        return []
