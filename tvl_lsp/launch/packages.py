"""ROS 1 packages: ``package.xml`` ``<name>`` -> package folder.

    find_packages(folder)               the packages under one folder, crawled as rospkg does
    ros_packages(workspace_root, env)   what ``$(find pkg)`` finds: the workspace and the folders of
                                        ``ROS_PACKAGE_PATH``, with roslaunch's precedence (the one
                                        resolver of ``--check``, the editor and ``tvl-lsp launch``)
"""

from __future__ import annotations

import os
import re
from functools import lru_cache
from typing import Mapping, Optional

from ..base.files import read_head
from .xml import strip_comments

_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_SKIP = {".git", "build", "devel", "install", "node_modules", ".venv", "__pycache__", "log", ".hg"}
_VCS = {".git", ".hg", ".svn", "__pycache__"}  # what rospkg crawls too, but never holds a package
MAX_DIRS = 20000


_METAPACKAGE = re.compile(r"<export\b[^>]*>(?:(?!</export>).)*?<metapackage\b", re.S)
_COMMENT = re.compile(r"<!--.*?-->", re.S)


def _scan(root: str, every: Optional[dict[str, list[str]]] = None, exact: bool = False) -> dict[str, str]:
    """rospkg's crawl (``rospkg.rospack.list_by_path``, what ``$(find pkg)`` uses): symbolic
    links followed, ``CATKIN_IGNORE`` and ``rospack_nosubdirs`` end a branch, a folder with a
    ``package.xml`` is a package (a metapackage is none: ``$(find)`` cannot find it) and so is
    one with a rosbuild ``manifest.xml`` (named after the folder); packages do not nest; of
    two packages with one name the first crawled wins (rospkg walks folders in the file
    system's order, and so does this).  ``exact``: a folder of ``ROS_PACKAGE_PATH``, crawled as
    rospkg does (build, install, hidden folders too); else a workspace's own folder, whose build
    and install spaces and hidden folders are not looked into."""
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
        dirnames[:] = ([d for d in dirnames if d not in _VCS] if exact else
                       [d for d in dirnames if d not in _SKIP and not d.startswith(".")])
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
            name = m.group(1) if m else os.path.basename(dirpath)
            out.setdefault(name, dirpath)
            if every is not None:
                every.setdefault(name, []).append(dirpath)
            continue
        if "manifest.xml" in filenames:
            dirnames[:] = []
            out.setdefault(os.path.basename(dirpath), dirpath)
            if every is not None:
                every.setdefault(os.path.basename(dirpath), []).append(dirpath)
            continue
        if "rospack_nosubdirs" in filenames:
            dirnames[:] = []
    return out


@lru_cache(maxsize=16)
def _cached(root: str, mtime: float, exact: bool = False) -> tuple[dict[str, str], dict[str, list[str]]]:
    every: dict[str, list[str]] = {}
    return _scan(root, every, exact), every


def _crawl(folder: str, exact: bool = False) -> tuple[dict[str, str], dict[str, list[str]]]:
    root = os.path.abspath(folder)
    try:
        mtime = os.stat(root).st_mtime
    except OSError:
        return {}, {}
    return _cached(root, mtime, exact)


def find_packages(workspace_root: str | None) -> dict[str, str]:
    """Package name -> absolute folder, for every package.xml under ``workspace_root``."""
    if not workspace_root:
        return {}
    return dict(_crawl(workspace_root)[0])


class Packages(dict):
    """Package name -> folder, as ``$(find)`` resolves it; ``ambiguous``: name -> every folder
    holding a package of that name, for the names found in more than one (the first is the one
    used)."""

    def __init__(self, *args, ambiguous: Optional[dict[str, list[str]]] = None, **kw):
        super().__init__(*args, **kw)
        self.ambiguous: dict[str, list[str]] = dict(ambiguous or {})


SYSTEM_SHARE = "/usr/share"  # Debian's rospkg searches it last, one level deep (its ROS packages)


def package_path(env: Mapping[str, str]) -> list[str]:
    """The folders rospkg searches, first wins: ``ROS_ROOT``, then ``ROS_PACKAGE_PATH`` in order
    (and, last, ``/usr/share``: see :func:`ros_packages`)."""
    out = []
    if env.get("ROS_ROOT"):
        out.append(os.path.normpath(env["ROS_ROOT"]))
    out += [x for x in env.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if x.strip()]
    return out


@lru_cache(maxsize=4)
def _system_share(root: str, mtime: float) -> dict[str, str]:
    """The packages directly under ``/usr/share`` (Debian's rospkg appends it to
    ``ROS_PACKAGE_PATH`` and crawls it one level deep): roslaunch, rosparam, rosout ... when
    Debian's ROS packages are installed; nothing on other systems."""
    out: dict[str, str] = {}
    try:
        names = sorted(os.listdir(root))
    except OSError:
        return out
    for name in names[:MAX_DIRS]:
        d = os.path.join(root, name)
        head = read_head(os.path.join(d, "package.xml"), 200_000)
        if head is None:
            continue
        text = strip_comments(head.decode("utf-8", "replace"))
        if _METAPACKAGE.search(text):
            continue
        m = _NAME.search(text)
        out.setdefault(m.group(1) if m else name, d)
    return out


def _within(a: str, b: str) -> bool:
    """``a`` is ``b`` or inside it."""
    return a == b or a.startswith(b.rstrip(os.sep) + os.sep)


def ros_packages(workspace_root: Optional[str], env: Optional[Mapping[str, str]] = None) -> Packages:
    """What roslaunch's ``$(find pkg)`` finds (rospkg): the folders of ``ROS_ROOT`` and
    ``ROS_PACKAGE_PATH`` crawled in order, the first folder holding a package of that name wins
    (in one folder, the first crawled).  The workspace counts where ``ROS_PACKAGE_PATH`` lists it
    (or a folder of it); a workspace it does not list comes first, as it would once its setup
    file is sourced.  Last, as Debian's rospkg (the roslaunch of Debian and Ubuntu's ROS packages)
    does, the packages directly under ``/usr/share``.  Names held by several folders are in
    ``ambiguous``."""
    env = os.environ if env is None else env
    ws = os.path.abspath(workspace_root) if workspace_root else None
    entries = [(os.path.abspath(e), True) for e in package_path(env)]
    if ws is not None:
        real = {e: os.path.realpath(e) for e, _ in entries}
        rws = os.path.realpath(ws)
        if not any(_within(real[e], rws) or _within(rws, real[e]) for e, _ in entries):
            entries.insert(0, (ws, False))
        elif not any(_within(rws, real[e]) for e, _ in entries):
            entries.append((ws, False))  # only folders inside it are listed: the rest of it last
    out: dict[str, str] = {}
    every: dict[str, list[str]] = {}
    for e, exact in dict.fromkeys(entries):
        first, all_ = _crawl(e, exact)
        for name, folder in first.items():
            out.setdefault(name, folder)
        for name, folders in all_.items():
            have = every.setdefault(name, [])
            have += [f for f in folders if f not in have]
    try:
        for name, folder in _system_share(SYSTEM_SHARE, os.stat(SYSTEM_SHARE).st_mtime).items():
            out.setdefault(name, folder)
    except OSError:
        pass
    return Packages(out, ambiguous={n: [out[n]] + [f for f in fs if f != out[n]]
                                    for n, fs in every.items() if len(fs) > 1})


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
