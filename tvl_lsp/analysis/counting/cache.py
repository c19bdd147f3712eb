"""Where compiled d-DNNFs are kept: in memory (the last few circuits) and on disk.

The disk cache lives in ``$TVL_LSP_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/tvl-lsp/ddnnf``,
else ``~/.cache/tvl-lsp/ddnnf``.  One file per compiled CNF, named by the SHA-256 of the CNF
(and of the compiler's version), so two models that differ only in layout or comments
share it.  Small results derived from a compilation are kept beside them as blobs
(:meth:`DiskCache.put_blob`: a model's facts by content, :mod:`tvl_lsp.project.factstore`).
It is bounded: after a write, the least recently used files go until the folder holds at most
``$TVL_LSP_CACHE_MAX_MB`` megabytes (default 512).  Safe under concurrent writers (several
editors, CI jobs): every file is written under a unique temporary name and renamed into place
atomically, readers that find a damaged file delete it and recompile, and
a file that disappears under a reader (evicted by another process) is a miss.
"""

from __future__ import annotations

import hashlib
import os
import threading
from collections import OrderedDict
from pathlib import Path
from typing import Iterable, Optional, Sequence

FORMAT = "tvl-lsp-ddnnf-1"
DEFAULT_MAX_MB = 512


def compiler_version() -> str:
    try:
        from importlib.metadata import version
        return "d4solver-" + version("d4solver")
    except Exception:
        return "d4solver-unknown"


def cnf_key(nvars: int, clauses: Iterable[Sequence[int]], extra: str = "") -> str:
    h = hashlib.sha256()
    h.update(f"{FORMAT} {compiler_version()} {extra}\np cnf {nvars}\n".encode())
    for c in clauses:
        h.update((" ".join(map(str, c)) + " 0\n").encode())
    return h.hexdigest()


def cache_dir() -> Optional[Path]:
    """The disk cache folder (None when disabled with ``TVL_LSP_CACHE_DIR=""``)."""
    env = os.environ.get("TVL_LSP_CACHE_DIR")
    if env is not None:
        return Path(env) if env else None
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg) if xdg else Path.home() / ".cache"
    return base / "tvl-lsp" / "ddnnf"


def max_bytes() -> int:
    try:
        return int(float(os.environ.get("TVL_LSP_CACHE_MAX_MB", DEFAULT_MAX_MB)) * 1024 * 1024)
    except ValueError:
        return DEFAULT_MAX_MB * 1024 * 1024


BLOB_MAX_BYTES = 64 * 1024 * 1024  # a stored blob bigger than this is not read (nor written)


def _safe_name(name: str) -> bool:
    return bool(name) and not name.startswith(".") and all(c.isalnum() or c in "._-" for c in name)



def _touch(p: Path) -> None:
    """Mark a cache file used now: the least recently *used* files are evicted first."""
    try:
        os.utime(p)
    except OSError:
        pass

class DiskCache:
    def __init__(self, folder: Optional[Path] = None, limit: Optional[int] = None):
        self._folder = folder
        self._limit = limit

    @property
    def folder(self) -> Optional[Path]:
        return self._folder if self._folder is not None else cache_dir()

    @property
    def limit(self) -> int:
        return self._limit if self._limit is not None else max_bytes()

    def path(self, key: str) -> Optional[Path]:
        d = self.folder
        return None if d is None else d / f"{key}.nnf"

    def has(self, key: str) -> bool:
        p = self.path(key)
        return p is not None and p.is_file()

    def get_count(self, key: str) -> Optional[int]:
        """The model count stored beside the d-DNNF (counting it needs no parse)."""
        p = self.path(key)
        if p is None:
            return None
        try:
            text = p.with_suffix(".count").read_text().strip()
            return int(text) if text.isdigit() else None
        except (OSError, ValueError):
            return None

    def _put_count(self, key: str, count: Optional[int]) -> None:
        p = self.path(key)
        if p is None or count is None:
            return
        try:
            tmp = p.parent / f".{key}.{os.getpid()}.{threading.get_ident()}.ctmp"
            tmp.write_text(f"{count}\n")
            os.replace(tmp, p.with_suffix(".count"))
        except OSError:
            pass

    def get(self, key: str) -> Optional[str]:
        p = self.path(key)
        if p is None:
            return None
        try:
            text = p.read_text()
        except (OSError, UnicodeDecodeError):
            return None
        _touch(p)
        return text

    def put(self, key: str, text: str, count: Optional[int] = None) -> Optional[Path]:
        p = self.path(key)
        if p is None:
            return None
        try:
            p.parent.mkdir(parents=True, exist_ok=True)
            tmp = p.parent / f".{key}.{os.getpid()}.{threading.get_ident()}.tmp"
            tmp.write_text(text)
            os.replace(tmp, p)
        except OSError:
            return None
        self._put_count(key, count)
        self.evict()
        return p

    def adopt(self, key: str, file: str, count: Optional[int] = None) -> Optional[Path]:
        """Move a finished NNF file (written by the compiler process) into the cache."""
        p = self.path(key)
        if p is None:
            return None
        try:
            p.parent.mkdir(parents=True, exist_ok=True)
            os.replace(file, p)
        except OSError:
            return None
        self._put_count(key, count)
        self.evict()
        return p

    def get_blob(self, name: str) -> Optional[bytes]:
        """The bytes stored under ``name`` (a file name of letters, digits, '.', '-' and '_'
        written by :meth:`put_blob`), or None (absent, unreadable, no cache)."""
        d = self.folder
        if d is None or not _safe_name(name):
            return None
        p = d / name
        try:
            with open(p, "rb") as fh:
                data = fh.read(BLOB_MAX_BYTES + 1)
        except OSError:
            return None
        if len(data) > BLOB_MAX_BYTES:
            return None
        _touch(p)
        return data

    def put_blob(self, name: str, data: bytes) -> Optional[Path]:
        """Store ``data`` under ``name``, atomically (a unique temporary file renamed into
        place: a reader sees the old file, the new one or none, never a part), then keep the
        folder within its bound.  Never raises on a disk error (the cache is an optimisation)."""
        d = self.folder
        if d is None or not _safe_name(name) or len(data) > BLOB_MAX_BYTES:
            return None
        p = d / name
        tmp = d / f".{name}.{os.getpid()}.{threading.get_ident()}.tmp"
        try:
            d.mkdir(parents=True, exist_ok=True)
            with open(tmp, "wb") as fh:
                fh.write(data)
            os.replace(tmp, p)
        except OSError:
            try:
                tmp.unlink()
            except OSError:
                pass
            return None
        self.evict()
        return p

    def discard_blob(self, name: str) -> None:
        d = self.folder
        if d is not None and _safe_name(name):
            try:
                (d / name).unlink()
            except OSError:
                pass

    def discard(self, key: str) -> None:
        p = self.path(key)
        if p is not None:
            for q in (p, p.with_suffix(".count")):
                try:
                    q.unlink()
                except OSError:
                    pass

    def tmp_path(self, key: str) -> str:
        """A fresh path, in the cache folder when there is one (so that adopting it is a rename)."""
        d = self.folder
        if d is not None:
            try:
                d.mkdir(parents=True, exist_ok=True)
                return str(d / f".{key}.{os.getpid()}.{threading.get_ident()}.part")
            except OSError:
                pass
        import tempfile
        fd, name = tempfile.mkstemp(suffix=".nnf", prefix="tvl-lsp-")
        os.close(fd)
        return name

    def evict(self) -> None:
        d = self.folder
        if d is None:
            return
        files = []
        total = 0
        try:
            for e in os.scandir(d):
                if not e.is_file():
                    continue
                try:
                    st = e.stat()
                except OSError:
                    continue
                if e.name.endswith((".tmp", ".part", ".ctmp", ".cnf")):
                    # a temporary file of a writer that died long ago
                    import time
                    if time.time() - st.st_mtime > 24 * 3600:
                        try:
                            os.unlink(e.path)
                        except OSError:
                            pass
                    continue
                files.append((st.st_mtime, st.st_size, e.path))
                total += st.st_size
        except OSError:
            return
        limit = self.limit
        if total <= limit:
            return
        for _, size, path in sorted(files):
            try:
                os.unlink(path)
            except OSError:
                continue
            total -= size
            if total <= limit:
                break


class MemoryCache:
    """The last few parsed circuits (they can be large), least recently used first out: at most
    ``size`` of them and ``max_weight`` in all (each put with its weight; the latest is always
    kept)."""

    def __init__(self, size: int = 8, max_weight: Optional[int] = None):
        self.size = size
        self.max_weight = max_weight
        self.data: OrderedDict[str, object] = OrderedDict()
        self.weights: dict[str, int] = {}
        self.lock = threading.Lock()

    def get(self, key: str):
        with self.lock:
            v = self.data.get(key)
            if v is not None:
                self.data.move_to_end(key)
            return v

    def put(self, key: str, value, weight: int = 0) -> None:
        with self.lock:
            self.data[key] = value
            self.data.move_to_end(key)
            self.weights[key] = weight
            total = sum(self.weights.values())
            while len(self.data) > 1 and (len(self.data) > self.size or
                                          (self.max_weight is not None and total > self.max_weight)):
                old, _ = self.data.popitem(last=False)
                total -= self.weights.pop(old, 0)

    def clear(self) -> None:
        with self.lock:
            self.data.clear()
            self.weights.clear()
