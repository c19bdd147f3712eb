"""Bounded reading of files: only regular files, up to a size cap, never blocking.

Every file tvl-lsp reads on its own, in every host (``--check``, the language server and its
worker processes, the configurator, the caches): models, included models and launch files,
rosparam and ``textfile`` files, package manifests, project files, cache entries, its own
static assets -- goes through :func:`read_text`, :func:`read_bytes` or :func:`read_head`
(``tests/test_architecture.py`` refuses a plain ``open()`` for reading anywhere else).  They refuse, with a reason a user can act on, what must never be read:

- anything that is not a regular file: character and block devices (``/dev/zero``,
  ``/dev/stdin``), FIFOs (opening one for reading would block until a writer comes), sockets
  and folders; a symbolic link counts as what it points to;
- a regular file larger than the cap (``MAX_BYTES`` by default, per call otherwise).

The file is stat-ed before it is opened (a device is never opened), opened non-blocking, and
stat-ed again through the open descriptor (a file swapped for a FIFO in between is still
refused); at most ``cap + 1`` bytes are read, so a file that grows while it is read cannot
exhaust memory either.

:func:`inside` tells whether a path lies inside one of some folders (symbolic links resolved):
the check pipeline uses it to refuse to read and quote files outside the workspace.
"""

from __future__ import annotations

import os
import stat
from typing import Callable, Iterable, Optional

MAX_BYTES = 25 * 1024 * 1024  # the largest text file tvl-lsp reads (a 400,000-line model is ~10 MB)

_KINDS = (
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISDIR, "a folder"),
)


class Unreadable(OSError):
    """A file tvl-lsp refuses to read; ``reason`` completes "cannot read PATH: ..." """

    def __init__(self, path: str, reason: str):
        super().__init__(f"{path}: {reason}")
        self.path = path
        self.reason = reason


def _kind(mode: int) -> Optional[str]:
    if stat.S_ISREG(mode):
        return None
    for test, name in _KINDS:
        if test(mode):
            return name
    return "not a regular file"


def _mb(n: int) -> str:
    return f"{n / (1024 * 1024):.0f} MB" if n >= 1024 * 1024 else f"{n:,} bytes"


def _check(path: str, st: os.stat_result, cap: Optional[int]) -> None:
    """Refuse what is not a regular file, and (``cap`` not None) a file larger than ``cap``."""
    kind = _kind(st.st_mode)
    if kind is not None:
        raise Unreadable(path, f"it is {kind}, not a regular file; only regular files are read")
    if cap is not None and st.st_size > cap:
        raise Unreadable(path, f"it is {_mb(st.st_size)}; files larger than {_mb(cap)} are not read")


def read_bytes(path: str, cap: int = MAX_BYTES, *, head: bool = False, follow: bool = True) -> bytes:
    """The bytes of the regular file at ``path`` (its first ``cap`` bytes when ``head``).
    ``follow=False``: a symbolic link is refused too, not followed (a cache's own files).

    Raises :class:`Unreadable` for what is not a regular file or (unless ``head``) is larger
    than ``cap``, and ``OSError`` when the file cannot be opened."""
    size_cap = None if head else cap
    st = os.stat(path) if follow else os.lstat(path)
    if not follow and stat.S_ISLNK(st.st_mode):
        raise Unreadable(path, "it is a symbolic link, which is not followed here")
    _check(path, st, size_cap)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    if not follow:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, flags)
    try:
        _check(path, os.fstat(fd), size_cap)
        chunks: list[bytes] = []
        left = cap if head else cap + 1
        while left > 0:
            b = os.read(fd, min(left, 1 << 20))
            if not b:
                break
            chunks.append(b)
            left -= len(b)
    finally:
        os.close(fd)
    data = b"".join(chunks)
    if not head and len(data) > cap:
        raise Unreadable(path, f"it grew past {_mb(cap)} while it was read; files larger than that are not read")
    return data


def read_text(path: str, cap: int = MAX_BYTES) -> str:
    """The text of the regular file at ``path`` (UTF-8, undecodable bytes replaced).

    Raises :class:`Unreadable` or ``OSError`` (see :func:`read_bytes`)."""
    return read_bytes(path, cap).decode("utf-8", errors="replace")


def read_text_or_none(path: str, cap: int = MAX_BYTES) -> Optional[str]:
    """:func:`read_text`, or None for anything that cannot or must not be read."""
    try:
        return read_text(path, cap)
    except (OSError, ValueError):
        return None


def read_head(path: str, n: int, follow: bool = True) -> Optional[bytes]:
    """The first ``n`` bytes of a regular file of any size, or None (not a regular file, or
    it cannot be opened)."""
    try:
        return read_bytes(path, n, head=True, follow=follow)
    except (OSError, ValueError):
        return None


def unreadable_reason(path: str, cap: int = MAX_BYTES) -> Optional[str]:
    """Why the file at ``path`` cannot be read (the text after "cannot read PATH: "), or None
    when it is a regular file within the cap."""
    try:
        _check(path, os.stat(path), cap)
    except Unreadable as exc:
        return exc.reason
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


def is_regular(path: str) -> bool:
    """A regular file (symbolic links followed)."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def inside(path: str, folders: Iterable[str]) -> bool:
    """Whether ``path`` lies in one of ``folders`` (or is one), symbolic links resolved."""
    try:
        p = os.path.realpath(path)
    except (OSError, ValueError):
        return False
    for f in folders:
        try:
            r = os.path.realpath(f)
        except (OSError, ValueError):
            continue
        if p == r or p.startswith(r.rstrip(os.sep) + os.sep):
            return True
    return False


ROOT_MARKERS = (".catkin_workspace", ".catkin_tools", ".git", ".tvl-lsp")


def model_workspace(path: str, max_up: int = 12) -> str:
    """The folder a model's includes and imports must stay inside: the nearest ancestor of the
    model holding a workspace marker (``.git``, ``.catkin_workspace``, ``.catkin_tools``,
    ``.tvl-lsp``), else the parent of the innermost ``src`` folder above it, else the model's
    own folder.  Includes outside it are refused (never read, never quoted in a diagnostic)."""
    return find_root(os.path.dirname(os.path.abspath(path)), lambda cur, names: False, max_up)


def find_root(folder: str, is_root: Callable[[str, list[str]], bool], max_up: int = 12) -> str:
    """The nearest ancestor of ``folder`` (itself included, at most ``max_up`` levels) that holds
    a workspace marker (``ROOT_MARKERS``) or for which ``is_root(path, its file names)`` holds;
    else :func:`src_parent` of ``folder``."""
    cur = folder
    for _ in range(max_up):
        try:
            names = os.listdir(cur)
        except OSError:
            names = []
        if any(m in names for m in ROOT_MARKERS) or is_root(cur, names):
            return cur
        parent = os.path.dirname(cur)
        if parent == cur:
            break
        cur = parent
    return src_parent(folder)


def src_parent(folder: str) -> str:
    """The parent of the innermost ``src`` folder above ``folder`` (a catkin / colcon
    workspace's root), else ``folder`` itself."""
    parts = folder.split(os.sep)
    if "src" in parts:
        i = len(parts) - 1 - parts[::-1].index("src")
        return os.sep.join(parts[:i]) or os.sep
    return folder


def package_text(*parts: str) -> str:
    """The text of a file shipped in the package (``package_text("grammars", "tvl.lark")``),
    through the bounded reader; from the source tree first (``grammars`` is a link there)."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # tvl_lsp/
    for cand in (os.path.join(here, *parts), os.path.join(os.path.dirname(here), *parts)):
        if is_regular(cand):
            return read_text(cand)
    from importlib import resources  # an installed wheel without the link materialised
    ref = resources.files("tvl_lsp")
    for part in parts:
        ref = ref / part
    with resources.as_file(ref) as p:
        return read_text(str(p))


def read_head_text(path: str, n: int) -> Optional[str]:
    """:func:`read_head` decoded as UTF-8 (undecodable bytes replaced), or None."""
    b = read_head(path, n)
    return None if b is None else b.decode("utf-8", errors="replace")
