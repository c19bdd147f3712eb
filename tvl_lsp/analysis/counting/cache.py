"""Where compiled d-DNNFs are kept: in memory (the last few circuits) and on disk.

The disk cache lives in ``$TVL_LSP_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/tvl-lsp/ddnnf``,
else ``~/.cache/tvl-lsp/ddnnf``.  One file per compiled CNF, named by the SHA-256 of the CNF
(and of the compiler's version), so two models that differ only in layout or comments
share it.  Small results derived from a compilation are kept beside them as blobs
(:meth:`DiskCache.put_blob`: a model's facts by content, :mod:`tvl_lsp.project.factstore`).
It is bounded: after a write, the least recently used files go until the folder holds at most
``$TVL_LSP_CACHE_MAX_MB`` megabytes (default 512).  Safe under concurrent writers (several
editors, CI jobs): every file is written under a unique temporary name and renamed into place
atomically (:mod:`tvl_lsp.base.safewrite`), readers that find a damaged file delete it and
recompile, and a file that disappears under a reader (evicted by another process) is a miss.

The folder is not trusted (``TVL_LSP_CACHE_DIR`` may be a shared folder, a copied one, one
another user can write to):

- every entry is read through the bounded reader, without following links
  (:func:`tvl_lsp.base.files.read_bytes`): a FIFO, a link to ``/dev/zero`` or a huge file is a
  miss, never a hang or an unbounded read;
- every entry is *sealed*: a header line with an HMAC-SHA256 of its name (which holds its content
  key) and its bytes, under a secret that is not in the folder (``$TVL_LSP_CACHE_KEY_FILE``, else
  ``$XDG_CONFIG_HOME/tvl-lsp/cache.key``, else ``~/.config/tvl-lsp/cache.key``: 32 random bytes
  created on first use, mode 0600, refused unless it is a regular file of ours that only we can
  read; when it cannot be used, a secret of this process alone).  A d-DNNF's entry (``KEY.count``)
  holds the model count and the size and SHA-256 of the d-DNNF file (``KEY.nnf``, d4's own
  format) checked when it is read.  A forged count, an entry copied from another key, a
  file edited and re-checksummed: the seal does not match, the entry is ignored and the count is
  computed again;
- eviction deletes only the files the cache names (its entry names and its temporary files)
  *and* recognises (a sealed header, or d4's format for a ``.nnf``), regular files only.
"""

from __future__ import annotations

import hashlib
import hmac
import json
import os
import re
import stat
import threading
import time
from collections import OrderedDict
from pathlib import Path
from typing import Iterable, Optional, Sequence

from ...base import files, safewrite
from ...base.envvars import megabytes

FORMAT = "tvl-lsp-ddnnf-1"
ENTRY = "tvl-lsp-entry-2"
DEFAULT_MAX_MB = 512
NNF_MAX_BYTES = 1 << 30   # a d-DNNF file bigger than this is not read back (compiled again)
BLOB_MAX_BYTES = 64 * 1024 * 1024  # a stored blob bigger than this is not read (nor written)
HEADER_MAX = 4096


def compiler_version() -> str:
    v = _dist_info_version()
    if v is not None:
        return "d4solver-" + v
    try:
        from importlib.metadata import version
        return "d4solver-" + version("d4solver")
    except Exception:
        return "d4solver-unknown"


def _dist_info_version() -> Optional[str]:
    """d4solver's version from the name of its ``.dist-info`` folder beside ``py_d4`` (what
    ``importlib.metadata.version`` answers, without importing it and reading every
    distribution's metadata: 0.015 s of every cold count); None when that folder is not the
    only one there."""
    try:
        import importlib.util
        spec = importlib.util.find_spec("py_d4")
        if spec is None or not spec.origin:
            return None
        site = os.path.dirname(os.path.dirname(spec.origin))
        found = [e.name for e in os.scandir(site) if e.name.startswith("d4solver-") and e.name.endswith(".dist-info")]
    except (OSError, ImportError, ValueError):
        return None
    if len(found) != 1:
        return None
    v = found[0][len("d4solver-"):-len(".dist-info")]
    return v or None


def cnf_key(nvars: int, clauses: Iterable[Sequence[int]], extra: str = "") -> str:
    h = hashlib.sha256()
    h.update(f"{FORMAT} {compiler_version()} {extra}\np cnf {nvars}\n".encode())
    # (the same bytes as one update per clause, in chunks: a 240,000-clause CNF hashes in a
    # third of the time)
    chunk: list[str] = []
    for c in clauses:
        chunk.append(" ".join(map(str, c)))
        if len(chunk) >= 4096:
            h.update((" 0\n".join(chunk) + " 0\n").encode())
            chunk = []
    if chunk:
        h.update((" 0\n".join(chunk) + " 0\n").encode())
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
    """``TVL_LSP_CACHE_MAX_MB`` in bytes (a finite number of megabytes; a bad value is
    explained on stderr and the default used)."""
    return megabytes("TVL_LSP_CACHE_MAX_MB", DEFAULT_MAX_MB)


def _safe_name(name: str) -> bool:
    return bool(name) and len(name) <= 200 and not name.startswith(".") \
        and all(c.isascii() and (c.isalnum() or c in "._-") for c in name)


def _touch(p: Path) -> None:
    """Mark a cache file used now: the least recently *used* files are evicted first."""
    try:
        os.utime(p, follow_symlinks=False)
    except (OSError, NotImplementedError):
        pass


# ------------------------------------------------------------------ the secret behind the seals

_SECRET: list = []
_SECRET_LOCK = threading.Lock()


def key_file() -> Path:
    env = os.environ.get("TVL_LSP_CACHE_KEY_FILE")
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CONFIG_HOME")
    base = Path(xdg) if xdg else Path.home() / ".config"
    return base / "tvl-lsp" / "cache.key"


def _own_secret(path: Path) -> Optional[bytes]:
    """The secret in ``path`` when it is a regular file of this user that nobody else can read
    or write, holding 64 hexadecimal digits; else None."""
    try:
        st = os.lstat(path)
    except OSError:
        return None
    if not stat.S_ISREG(st.st_mode) or (hasattr(os, "getuid") and st.st_uid != os.getuid()) \
            or st.st_mode & 0o077:
        return None
    raw = files.read_head(str(path), 128, follow=False)
    text = (raw or b"").strip()
    if len(text) != 64 or not re.fullmatch(rb"[0-9a-f]{64}", text):
        return None
    return bytes.fromhex(text.decode())


def secret() -> bytes:
    """The key of the cache's seals (see the module's docstring), read or created once per
    process."""
    with _SECRET_LOCK:
        if _SECRET:
            return _SECRET[0]
        path = key_file()
        got = _own_secret(path)
        if got is None and not os.path.lexists(path):
            try:
                os.makedirs(path.parent, mode=0o700, exist_ok=True)
                safewrite.create_exclusive(str(path), os.urandom(32).hex().encode() + b"\n", 0o600)
            except OSError:
                pass
            got = _own_secret(path)
        if got is None:  # unusable: entries written by this process only are trusted
            got = os.urandom(32)
        _SECRET.append(got)
        return got


def _mac(name: str, payload: bytes) -> str:
    m = hmac.new(secret(), digestmod=hashlib.sha256)
    m.update(f"{ENTRY}\0{name}\0{len(payload)}\0".encode())
    m.update(payload)
    return m.hexdigest()


def seal(name: str, payload: bytes) -> bytes:
    """An entry's bytes: a header line (format, size, HMAC of the name and payload), then the
    payload."""
    head = json.dumps({"tvl-lsp": ENTRY, "size": len(payload), "mac": _mac(name, payload)},
                      separators=(",", ":")).encode()
    return head + b"\n" + payload


def unseal(name: str, data: bytes) -> Optional[bytes]:
    """The payload of a sealed entry named ``name``, or None (not an entry, damaged, forged,
    another name's)."""
    nl = data.find(b"\n", 0, HEADER_MAX)
    if nl < 0:
        return None
    try:
        head = json.loads(data[:nl].decode("ascii"))
    except (ValueError, UnicodeDecodeError, RecursionError):
        return None
    payload = data[nl + 1:]
    if not isinstance(head, dict) or head.get("tvl-lsp") != ENTRY or head.get("size") != len(payload):
        return None
    mac = head.get("mac")
    if not isinstance(mac, str) or not hmac.compare_digest(mac, _mac(name, payload)):
        return None
    return payload


_ENTRY_HEAD = b'{"tvl-lsp":"tvl-lsp-entry-'
_NNF_HEAD = re.compile(rb"[otfa] [0-9]+[ \n]")
_TEMP = re.compile(r"\.[A-Za-z0-9._-]+\.[0-9]+\.[0-9]+\.(?:tmp|part|ctmp)(?:\.cnf)?")


def _recognised(name: str, path: str) -> bool:
    """A file this cache wrote: a sealed entry, or a d-DNNF in d4's format under its name."""
    head = files.read_head(path, 64, follow=False)
    if head is None:
        return False
    if head.startswith(_ENTRY_HEAD):
        return True
    return name.endswith(".nnf") and _NNF_HEAD.match(head) is not None


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
        return None if d is None or not _safe_name(key) else d / f"{key}.nnf"

    # -------------------------------------------------------------- sealed entries
    def _read_entry(self, name: str, cap: int) -> Optional[bytes]:
        d = self.folder
        if d is None or not _safe_name(name):
            return None
        p = d / name
        try:
            data = files.read_bytes(str(p), cap + HEADER_MAX, follow=False)
        except (OSError, ValueError):
            if os.path.lexists(p) and not os.path.isdir(p):
                self._unlink(name)  # a link, a FIFO, a device, too big: not ours
            return None
        payload = unseal(name, data)
        if payload is None:
            self._unlink(name)  # damaged, forged, foreign: computed again
            return None
        _touch(p)
        return payload

    def _write_entry(self, name: str, payload: bytes) -> Optional[Path]:
        d = self.folder
        if d is None or not _safe_name(name):
            return None
        try:
            d.mkdir(parents=True, exist_ok=True)
            safewrite.write_file(str(d / name), seal(name, payload), replace=True)
        except (OSError, ValueError):
            return None
        return d / name

    def _unlink(self, name: str) -> None:
        d = self.folder
        if d is not None and _safe_name(name):
            try:
                os.unlink(d / name)
            except OSError:
                pass

    def _manifest(self, key: str) -> Optional[dict]:
        """The entry of a compiled CNF: {"count": int, "nnf": (size, sha256) | None}."""
        payload = self._read_entry(f"{key}.count", 1 << 20)
        if payload is None:
            return None
        try:
            m = json.loads(payload.decode("ascii"))
            if not isinstance(m, dict) or m.get("key") != key:
                raise ValueError("another key's entry")
            c = m.get("count")
            if not isinstance(c, str) or not re.fullmatch(r"[0-9a-f]+", c):
                raise ValueError("not a count")
            nnf = m.get("nnf")
            if nnf is not None and not (isinstance(nnf, list) and len(nnf) == 2 and type(nnf[0]) is int
                                        and isinstance(nnf[1], str)):
                raise ValueError("not a digest")
            return {"count": int(c, 16), "nnf": tuple(nnf) if nnf else None}
        except (ValueError, UnicodeDecodeError, RecursionError):
            self._unlink(f"{key}.count")
            return None

    def _put_manifest(self, key: str, count: Optional[int], nnf: Optional[tuple[int, str]]) -> None:
        if count is None or count < 0:
            return
        payload = json.dumps({"key": key, "count": format(count, "x"), "nnf": list(nnf) if nnf else None},
                             separators=(",", ":")).encode()
        self._write_entry(f"{key}.count", payload)

    # -------------------------------------------------------------- d-DNNFs
    def has(self, key: str) -> bool:
        """Is a d-DNNF listed for ``key`` (read back by :meth:`get`, which checks it)?"""
        p = self.path(key)
        if p is None:
            return False
        m = self._manifest(key)
        try:
            return m is not None and m["nnf"] is not None and stat.S_ISREG(os.lstat(p).st_mode)
        except OSError:
            return False

    def get_count(self, key: str) -> Optional[int]:
        """The model count stored for ``key`` (counting it needs no parse), when its entry is
        sound and sealed by us."""
        m = self._manifest(key)
        return None if m is None else m["count"]

    def get(self, key: str) -> Optional[str]:
        """The d-DNNF of ``key`` when its entry lists it and the file matches its size and
        SHA-256; else None (and the file is discarded)."""
        p = self.path(key)
        if p is None:
            return None
        m = self._manifest(key)
        if m is None or m["nnf"] is None:
            return None
        size, digest = m["nnf"]
        try:
            data = files.read_bytes(str(p), min(NNF_MAX_BYTES, max(size, 0)), follow=False)
        except (OSError, ValueError):
            self.discard(key)
            return None
        if len(data) != size or not hmac.compare_digest(hashlib.sha256(data).hexdigest(), digest):
            self.discard(key)
            return None
        _touch(p)
        return data.decode("ascii", errors="replace")

    def put(self, key: str, text: str, count: Optional[int] = None) -> Optional[Path]:
        p = self.path(key)
        if p is None:
            return None
        data = text.encode("ascii", errors="replace")
        try:
            p.parent.mkdir(parents=True, exist_ok=True)
            safewrite.write_file(str(p), data, replace=True)
        except (OSError, ValueError):
            return None
        self._put_manifest(key, count, (len(data), hashlib.sha256(data).hexdigest()))
        self.evict()
        return p

    def adopt(self, key: str, file: str, count: Optional[int] = None,
              digest: Optional[tuple[int, str]] = None) -> Optional[Path]:
        """Move a finished NNF file (written by the compiler process, which reported its size
        and SHA-256 as ``digest``) into the cache."""
        p = self.path(key)
        if p is None:
            return None
        try:
            if not stat.S_ISREG(os.lstat(file).st_mode):
                return None
            if digest is None:
                data = files.read_bytes(file, NNF_MAX_BYTES, follow=False)
                digest = (len(data), hashlib.sha256(data).hexdigest())
            p.parent.mkdir(parents=True, exist_ok=True)
            os.replace(file, p)
        except (OSError, ValueError):
            return None
        self._put_manifest(key, count, digest)
        self.evict()
        return p

    def discard(self, key: str) -> None:
        if self.path(key) is not None:
            for name in (f"{key}.nnf", f"{key}.count"):
                self._unlink(name)

    # -------------------------------------------------------------- blobs
    def get_blob(self, name: str) -> Optional[bytes]:
        """The bytes stored under ``name`` (a file name of letters, digits, '.', '-' and '_'
        written by :meth:`put_blob`), or None (absent, unreadable, not sealed by us, no cache)."""
        return self._read_entry(name, BLOB_MAX_BYTES)

    def put_blob(self, name: str, data: bytes, evict: bool = True) -> Optional[Path]:
        """Store ``data`` under ``name``, sealed and atomically (a unique temporary file renamed
        into place: a reader sees the old file, the new one or none, never a part), then keep
        the folder within its bound.  Never raises on a disk error (the cache is an
        optimisation) and leaves no temporary file behind."""
        if len(data) > BLOB_MAX_BYTES:
            return None
        p = self._write_entry(name, data)
        if p is not None and evict:  # (a caller writing many calls evict() once at the end)
            self.evict()
        return p

    def discard_blob(self, name: str) -> None:
        self._unlink(name)

    def tmp_path(self, key: str) -> str:
        """A fresh path, in the cache folder when there is one (so that adopting it is a rename)."""
        d = self.folder
        if d is not None and _safe_name(key):
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
        """Keep the folder's entries within the bound, least recently used first out; remove
        temporary files of writers that died.  Only this cache's files are touched: names it
        gives, regular files, with contents it recognises."""
        d = self.folder
        if d is None:
            return
        entries = []
        total = 0
        now = time.time()
        try:
            with os.scandir(d) as it:
                for e in it:
                    try:
                        if not e.is_file(follow_symlinks=False):
                            continue
                        st = e.stat(follow_symlinks=False)
                    except OSError:
                        continue
                    name = e.name
                    if _TEMP.fullmatch(name) or (name.startswith(safewrite.TMP_PREFIX)
                                                 and name.endswith(safewrite.TMP_SUFFIX)):
                        if now - st.st_mtime > 24 * 3600:  # a writer that died long ago
                            try:
                                os.unlink(e.path)
                            except OSError:
                                pass
                        continue
                    if _safe_name(name) and _recognised(name, e.path):
                        entries.append((st.st_mtime, st.st_size, e.path))
                        total += st.st_size
        except OSError:
            return
        limit = self.limit
        if total <= limit:
            return
        for _, size, path in sorted(entries):
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
