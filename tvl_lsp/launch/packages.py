"""Catkin packages of a workspace: ``package.xml`` ``<name>`` -> package folder."""

from __future__ import annotations

import os
import re
from functools import lru_cache

from ..base.files import read_head
from .xml import strip_comments

_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_SKIP = {".git", "build", "devel", "install", "node_modules", ".venv", "__pycache__", "log", ".hg"}
MAX_DIRS = 20000


_METAPACKAGE = re.compile(r"<export\b[^>]*>(?:(?!</export>).)*?<metapackage\b", re.S)
_COMMENT = re.compile(r"<!--.*?-->", re.S)


def _scan(root: str) -> dict[str, str]:
    """rospkg's crawl (``rospkg.rospack.list_by_path``, what ``$(find pkg)`` uses): symbolic
    links followed, ``CATKIN_IGNORE`` and ``rospack_nosubdirs`` end a branch, a folder with a
    ``package.xml`` is a package (a metapackage is none: ``$(find)`` cannot find it) and so is
    one with a rosbuild ``manifest.xml`` (named after the folder); packages do not nest; of
    two packages with one name the first crawled wins (rospkg walks folders in the file
    system's order, and so does this)."""
    out: dict[str, str] = {}
    count = 0
    seen: set[str] = set()
    for dirpath, dirnames, filenames in os.walk(root, followlinks=True):
        count += 1
        if count > MAX_DIRS:
            break
        try:
            real = os.path.realpath(dirpath)
        except OSError:
            real = dirpath
        if real in seen:  # a link back up the tree
            dirnames[:] = []
            continue
        seen.add(real)
        dirnames[:] = [d for d in dirnames if d not in _SKIP and not d.startswith(".")]
        if "CATKIN_IGNORE" in filenames:
            dirnames[:] = []
            continue
        if "package.xml" in filenames:
            dirnames[:] = []  # packages do not nest
            head = read_head(os.path.join(dirpath, "package.xml"), 200_000)  # regular files only
            if head is None:
                continue
            text = strip_comments(head.decode("utf-8", "replace"))
            if _METAPACKAGE.search(text):
                continue
            m = _NAME.search(text)
            out.setdefault(m.group(1) if m else os.path.basename(dirpath), dirpath)
            continue
        if "manifest.xml" in filenames:
            dirnames[:] = []
            out.setdefault(os.path.basename(dirpath), dirpath)
            continue
        if "rospack_nosubdirs" in filenames:
            dirnames[:] = []
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
