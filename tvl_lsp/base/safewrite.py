"""Safe writing: atomic, never through a symbolic link, never outside the folder it is given.

Every file tvl-lsp writes on its own (configuration launch files from ``generate``, the
configurator and the editor command, ``--check --output``, ``graph --output``, ``convert``)
goes through :func:`write_files` or :func:`write_file`.  They promise:

- **atomic**: the text goes to a new temporary file in the same folder (created exclusively,
  never following a link), is flushed to the disk (``fsync``), then renamed over the target
  (``os.replace``).  A reader, a ``kill -TERM``, a full disk or a power cut sees the old file or
  the new one, never an empty or partial one; on an error the temporary file is removed;
- **never through a link**: a target that is a symbolic link (``configs/a.launch ->
  ../../.git/config``) is refused, and so is one that is not a regular file (a FIFO, a device,
  a folder).  The rename would replace a link planted after the check, not write through it;
- **inside its folder, with no race**: with ``within`` (the workspace roots), the output folder
  is opened once, component by component from the root with ``O_NOFOLLOW | O_DIRECTORY`` (a
  folder swapped for a link between a check and the write is refused, not followed), created
  where missing, and every file is written relative to that open folder (``dir_fd``);
- **one-line errors**: every failure is a :class:`WriteError` whose text says what could not
  be written and why ("the disk is full", "a name is too long", "is a symbolic link"), for
  the hosts to print (CLI, exit 2), answer (LSP error, HTTP 4xx/5xx) or show.

Temporary files are named ``.tvl-lsp-PID-RANDOM.tmp``; one left by a process that no longer
runs (killed with SIGKILL) is removed by the next write to that folder.
"""

from __future__ import annotations

import errno
import os
import secrets
import stat
from typing import Iterable, Mapping, Optional, Sequence, Union

_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_DIRECTORY = getattr(os, "O_DIRECTORY", 0)
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)
TMP_PREFIX = ".tvl-lsp-"
TMP_SUFFIX = ".tmp"
MISSING = "the folder does not exist"

_REASONS = {
    errno.ENOSPC: "the disk is full",
    errno.EDQUOT: "the disk quota is exceeded",
    errno.EFBIG: "the file is larger than this process may write (file size limit)",
    errno.ENAMETOOLONG: "a file or folder name is too long",
    errno.EROFS: "the file system is read-only",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.ENOTDIR: "a part of the path is not a folder",
    errno.EISDIR: "it is a folder",
    errno.ELOOP: "a part of the path is a symbolic link (generated files are never written through a link)",
    errno.EIO: "an input/output error",
    errno.ENOENT: "a part of the path does not exist",
    errno.EEXIST: "it already exists",
    errno.EMLINK: "too many links",
    errno.EXDEV: "it is on another file system",
}


class WriteError(OSError):
    """A file tvl-lsp did not write; ``str()`` is one line: "cannot write PATH: REASON"."""

    def __init__(self, path: str, reason: str, err: Optional[int] = None):
        super().__init__(err or 0, reason)
        self.path = path
        self.reason = reason
        self.written: list[str] = []  # (several files: those written, complete, before this one failed)

    def __str__(self) -> str:
        return f"cannot write {self.path}: {self.reason}"


def reason(exc: BaseException) -> str:
    """A short phrase for an ``OSError`` (the errno's meaning in plain words)."""
    if isinstance(exc, WriteError):
        return exc.reason
    if isinstance(exc, OSError):
        r = _REASONS.get(exc.errno or 0)
        if r:
            return r
        return (exc.strerror or str(exc) or type(exc).__name__).splitlines()[0]
    return f"{type(exc).__name__}: {exc}".splitlines()[0]


def _wrap(path: str, exc: OSError) -> WriteError:
    return exc if isinstance(exc, WriteError) else WriteError(path, reason(exc), exc.errno)


def _lexically_under(path: str, root: str) -> Optional[str]:
    """``path`` relative to ``root`` when it lies under it by its spelling ("" for the root
    itself), else None."""
    root = root.rstrip(os.sep) or os.sep
    if path == root:
        return ""
    prefix = root if root.endswith(os.sep) else root + os.sep
    return path[len(prefix):] if path.startswith(prefix) else None


def _relative_to_roots(folder: str, within: Iterable[str]) -> Optional[tuple[str, str]]:
    """(the real root, the folder relative to it) for the first root that holds ``folder``,
    by spelling or once the root's own links are resolved; None when no root holds it."""
    folder = os.path.normpath(os.path.abspath(folder))
    for r in within:
        try:
            lexical = os.path.normpath(os.path.abspath(r))
            real = os.path.realpath(r)
        except (OSError, ValueError):
            continue
        for base in (lexical, real):
            rel = _lexically_under(folder, base)
            if rel is not None:
                return real, rel
    return None


class Folder:
    """An output folder opened once (a file descriptor); files are written relative to it.

    Use :func:`open_folder`; close it (or use it as a context manager) when done."""

    def __init__(self, path: str, fd: int):
        self.path = path
        self.fd = fd

    def __enter__(self) -> "Folder":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self.fd >= 0:
            try:
                os.close(self.fd)
            finally:
                self.fd = -1

    def _target(self, name: str) -> str:
        return os.path.join(self.path, name)

    def check(self, name: str, replace: bool = False) -> Optional[os.stat_result]:
        """Refuse a target that is a link or not a regular file (``replace``: only a folder; a
        link or a special file is then replaced by the rename, never written through); its
        stat when it is a regular file."""
        _check_name(self._target(name), name)
        try:
            st = os.stat(name, dir_fd=self.fd, follow_symlinks=False)
        except FileNotFoundError:
            return None
        except OSError as exc:
            raise _wrap(self._target(name), exc) from None
        if replace and not stat.S_ISDIR(st.st_mode):
            return st if stat.S_ISREG(st.st_mode) else None
        _refuse_kind(self._target(name), st.st_mode)
        return st

    def write(self, name: str, data: Union[str, bytes], replace: bool = False, mode: Optional[int] = None) -> str:
        """Write ``data`` to ``name`` in this folder atomically; its path.  ``replace``: a link
        or special file of that name is replaced (a cache's own entries), not refused.
        ``mode``: the new file's permissions (default: the old file's, else 0o666 - umask)."""
        target = self._target(name)
        raw = data.encode("utf-8") if isinstance(data, str) else bytes(data)
        old = self.check(name, replace)
        if mode is None:
            mode = stat.S_IMODE(old.st_mode) if old is not None else 0o666  # (umask applies to a new file)
        tmp = f"{TMP_PREFIX}{os.getpid()}-{secrets.token_hex(6)}{TMP_SUFFIX}"
        # (True from before the open: a signal handler's exception can come between the open and
        # the next statement; unlinking a name that does not exist, or no longer, is harmless --
        # the random part makes it this call's own)
        created = True
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW | _CLOEXEC, mode, dir_fd=self.fd)
            try:
                if old is not None or mode != 0o666:
                    try:
                        os.fchmod(fd, mode)
                    except OSError:
                        pass
                view = memoryview(raw)
                while view:
                    n = os.write(fd, view)
                    view = view[n:]
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(tmp, name, src_dir_fd=self.fd, dst_dir_fd=self.fd)
            created = False
        except FileExistsError as exc:  # (the random name taken: not this call's file)
            created = False
            raise _wrap(target, exc) from None
        except OSError as exc:
            raise _wrap(target, exc) from None
        finally:
            if created:  # an error, or an exception raised by a signal handler (SIGTERM, Ctrl-C)
                try:
                    os.unlink(tmp, dir_fd=self.fd)
                except OSError:
                    pass
        try:
            os.fsync(self.fd)  # the rename itself on the disk
        except OSError:
            pass
        return target

    def sweep(self) -> None:
        """Remove the temporary files of writers that no longer run (killed with SIGKILL)."""
        try:
            names = os.listdir(self.fd)
        except OSError:
            return
        for n in names:
            if not (n.startswith(TMP_PREFIX) and n.endswith(TMP_SUFFIX)):
                continue
            pid = n[len(TMP_PREFIX):].split("-", 1)[0]
            if not pid.isdigit() or int(pid) == os.getpid() or _alive(int(pid)):
                continue
            try:
                os.unlink(n, dir_fd=self.fd)
            except OSError:
                pass


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _check_name(target: str, name: str) -> None:
    if not name or name in (".", "..") or "/" in name or "\0" in name or (os.altsep and os.altsep in name):
        raise WriteError(target, "not a plain file name")


def _refuse_kind(target: str, mode: int) -> None:
    if stat.S_ISLNK(mode):
        raise WriteError(target, "it is a symbolic link; tvl-lsp never writes through a link "
                                 "(remove the link or choose another folder)")
    if stat.S_ISDIR(mode):
        raise WriteError(target, "it is a folder")
    if not stat.S_ISREG(mode):
        raise WriteError(target, "it exists and is not a regular file (a FIFO, a socket or a device)")


def open_folder(folder: str, within: Optional[Sequence[str]] = None, create: bool = True) -> Folder:
    """Open ``folder`` for writing (creating it and its parents when ``create``).

    With ``within`` (workspace roots): the folder must lie inside one of them, and every part
    of its path below the root must be a real folder (not a symbolic link), checked and opened
    in one pass with ``O_NOFOLLOW`` (no check-then-use race).  Without it the path is opened as
    given (the user named it on the command line).  Raises :class:`WriteError`."""
    folder = os.path.normpath(os.path.abspath(folder))
    if within is None:
        parts = [p for p in folder.split(os.sep) if p]
        start, follow = os.sep, True
    else:
        found = _relative_to_roots(folder, within)
        if found is None:
            raise WriteError(folder, "it is outside the workspace; choose a folder inside it")
        start, rel = found
        parts = [p for p in rel.split(os.sep) if p]
        follow = False
    try:
        fd = os.open(start, os.O_RDONLY | _DIRECTORY | _CLOEXEC)
    except OSError as exc:
        raise _wrap(start, exc) from None
    here = start
    try:
        for part in parts:
            here = os.path.join(here, part)
            flags = os.O_RDONLY | _DIRECTORY | _CLOEXEC | (0 if follow else _NOFOLLOW)
            try:
                nfd = os.open(part, flags, dir_fd=fd)
            except FileNotFoundError:
                if not create:
                    raise WriteError(here, MISSING) from None
                try:
                    os.mkdir(part, 0o777, dir_fd=fd)
                except FileExistsError:
                    pass
                except OSError as exc:
                    raise _wrap(here, exc) from None
                try:
                    nfd = os.open(part, flags, dir_fd=fd)
                except OSError as exc:
                    raise _folder_error(here, part, fd, exc) from None
            except OSError as exc:
                raise _folder_error(here, part, fd, exc) from None
            os.close(fd)
            fd = nfd
    except BaseException:
        os.close(fd)
        raise
    return Folder(folder, fd)


def _folder_error(here: str, part: str, parent_fd: int, exc: OSError) -> WriteError:
    """Why ``part`` (in the folder open as ``parent_fd``) cannot be opened as a folder."""
    try:
        st = os.stat(part, dir_fd=parent_fd, follow_symlinks=False)
    except OSError:
        return _wrap(here, exc)
    if stat.S_ISLNK(st.st_mode):
        return WriteError(here, "it is a symbolic link; generated files are never written through a link "
                                "(choose a folder that is not a link)")
    if not stat.S_ISDIR(st.st_mode):
        return WriteError(here, "it exists and is not a folder")
    return _wrap(here, exc)


def write_files(folder: str, files: Mapping[str, Union[str, bytes]],
                within: Optional[Sequence[str]] = None) -> list[str]:
    """Write ``files`` (file name -> text) into ``folder`` (see :func:`open_folder` for
    ``within``), each atomically; every target is checked before the first is written (a
    link among them: nothing is written).  Returns the paths written.  Raises WriteError."""
    with open_folder(folder, within) as d:
        for name in files:
            d.check(name)
        d.sweep()
        done: list[str] = []
        try:
            for name, data in files.items():
                done.append(d.write(name, data))
        except WriteError as exc:
            exc.written = done
            raise
        return done


def write_paths(paths: Mapping[str, Union[str, bytes]], within: Optional[Sequence[str]] = None) -> list[str]:
    """:func:`write_files` for full paths (grouped by folder, in the given order)."""
    by_folder: dict[str, dict[str, Union[str, bytes]]] = {}
    for p, data in paths.items():
        full = os.path.normpath(os.path.abspath(p))
        by_folder.setdefault(os.path.dirname(full), {})[os.path.basename(full)] = data
    # every target of every folder is checked before anything is written
    for folder, files in by_folder.items():
        check_paths([os.path.join(folder, n) for n in files], within)
    out: list[str] = []
    for folder, files in by_folder.items():
        try:
            out.extend(write_files(folder, files, within))
        except WriteError as exc:
            exc.written = out + exc.written
            raise
    return out


def summary(exc: WriteError, total: int) -> str:
    """The error's line, with how many of ``total`` files were written before it."""
    done = len(getattr(exc, "written", []) or [])
    if total <= 1:
        return str(exc)
    return f"{exc} ({done} of {total} files were written, each complete; the others were not)" if done else \
        f"{exc} (none of the {total} files was written)"


def check_paths(paths: Iterable[str], within: Optional[Sequence[str]] = None) -> None:
    """Raise :class:`WriteError` when one of ``paths`` could not be written safely (outside
    ``within``, through a link, over something that is not a regular file); creates nothing.
    For a host that lets another program write (an editor applying a WorkspaceEdit)."""
    for p in paths:
        full = os.path.normpath(os.path.abspath(p))
        try:
            d = open_folder(os.path.dirname(full), within, create=False)
        except WriteError as exc:
            if exc.reason == MISSING:  # (the parts before the missing one were checked)
                continue
            raise
        with d:
            d.check(os.path.basename(full))


def write_file(path: str, data: Union[str, bytes], within: Optional[Sequence[str]] = None,
               replace: bool = False, mode: Optional[int] = None) -> str:
    """Write one file atomically (see :func:`write_files`); its path.  ``replace``: a link or
    special file there is replaced, not refused (a cache's own entry names).  Raises WriteError."""
    full = os.path.normpath(os.path.abspath(path))
    with open_folder(os.path.dirname(full), within) as d:
        return d.write(os.path.basename(full), data, replace, mode)


def write_output(path: str, text: str) -> str:
    """A command's ``--output FILE``: a stream the user named (a terminal, a pipe: ``/dev/stdout``,
    ``/dev/fd/N``, ``/dev/null``) is written as it is; a file is written atomically, never
    through a link (:func:`write_file`).  Raises WriteError."""
    full = os.path.normpath(os.path.abspath(path))
    try:
        st = os.stat(full)
    except OSError:
        st = None
    if st is not None and (stat.S_ISCHR(st.st_mode) or stat.S_ISFIFO(st.st_mode)):
        try:
            with open(full, "w", encoding="utf-8", newline="\n") as fh:  # noqa: raw-write (a stream)
                fh.write(text)
        except OSError as exc:
            raise _wrap(full, exc) from None
        return full
    return write_file(full, text.encode("utf-8"))


def create_exclusive(path: str, data: bytes, mode: int = 0o600) -> bool:
    """Create ``path`` with ``data`` unless something is there already, atomically (a complete
    temporary file hard-linked into place: a reader never sees it half written).  True when
    this call created it.  Raises WriteError."""
    full = os.path.normpath(os.path.abspath(path))
    name = os.path.basename(full)
    with open_folder(os.path.dirname(full)) as d:
        _check_name(full, name)
        tmp = f"{TMP_PREFIX}{os.getpid()}-{secrets.token_hex(6)}{TMP_SUFFIX}"
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW | _CLOEXEC, mode, dir_fd=d.fd)
            try:
                os.fchmod(fd, mode)
                os.write(fd, data)
                os.fsync(fd)
            finally:
                os.close(fd)
            try:
                os.link(tmp, name, src_dir_fd=d.fd, dst_dir_fd=d.fd, follow_symlinks=False)
                return True
            except FileExistsError:
                return False
        except OSError as exc:
            raise _wrap(full, exc) from None
        finally:
            try:
                os.unlink(tmp, dir_fd=d.fd)
            except OSError:
                pass


def open_append(path: str):
    """A text file opened for appending (a log): created if missing, refused (WriteError) when
    it is a FIFO, a socket or a folder (opening a FIFO would block until a reader comes)."""
    full = os.path.normpath(os.path.abspath(path))
    try:
        fd = os.open(full, os.O_WRONLY | os.O_APPEND | os.O_CREAT | getattr(os, "O_NONBLOCK", 0) | _CLOEXEC, 0o644)
    except OSError as exc:
        raise _wrap(full, exc) from None
    try:
        st = os.fstat(fd)
        if not (stat.S_ISREG(st.st_mode) or stat.S_ISCHR(st.st_mode)):
            raise WriteError(full, "it is not a regular file")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "a", encoding="utf-8", errors="replace")
    except BaseException:
        os.close(fd)
        raise
