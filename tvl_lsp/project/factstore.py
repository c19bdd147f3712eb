"""A model's facts (total, every feature's count, core / dead / false-optional features) kept on
disk by content, beside the compiled d-DNNFs (:mod:`tvl_lsp.analysis.counting.cache`), so that
reopening a model counted before answers from one small file instead of parsing, encoding and
reading the circuit back (issue #15: the first counted hover within 2 s of opening).

    key(path, sources)             -> hex digest of everything the facts depend on
    load(path, sources)            -> the stored fields, or None
    store(path, sources, fields)   -> written atomically (or silently not, on a disk error)

The key is the SHA-256 of the model's path and *text*, the path and text of every file its
parse read (its includes / imports: ``sources``), the store's format, the compiler's version
and a fingerprint of the analysis code (the installed files' names, sizes and modification
times): the same key means the same parse, the same encoding and so the same exact counts.
Any edit of the model or an include is a new key (never a stale count); a layout-only edit
misses here and is counted from the d-DNNF, which is cached by the CNF's logical content.

A file is trusted only when it parses, names this store's format and this very key, carries a
matching checksum of its fields and its counts are consistent (0 <= count <= total); anything
else (truncated, damaged, another model's file, another version's) is deleted and ignored --
the facts are then computed as if nothing was stored.  Counts are stored as hexadecimal
strings (JSON integers of thousands of digits hit Python's int/str conversion limit).

Pure with respect to LSP; only complete, exact facts are stored (the caller decides).
"""

from __future__ import annotations

import hashlib
import json
import os
import threading
from pathlib import Path
from typing import Optional

from ..analysis.counting import cache as C

FORMAT = "tvl-lsp-facts-1"
SUFFIX = ".facts"

_FINGERPRINT: list[Optional[str]] = [None]
_FP_LOCK = threading.Lock()


def code_fingerprint() -> str:
    """A digest of the package's source and grammar files (name, size, mtime): facts stored
    by other code (an upgrade, an edited checkout) are never read back."""
    with _FP_LOCK:
        if _FINGERPRINT[0] is None:
            root = Path(__file__).resolve().parents[1]
            h = hashlib.sha256()
            entries = []
            for dirpath, dirnames, filenames in os.walk(root, followlinks=True):
                dirnames[:] = sorted(d for d in dirnames if d not in ("__pycache__", "static"))
                for fn in filenames:
                    if fn.endswith((".py", ".lark")):
                        p = os.path.join(dirpath, fn)
                        try:
                            st = os.stat(p)
                        except OSError:
                            continue
                        entries.append(f"{os.path.relpath(p, root)}\0{st.st_size}\0{st.st_mtime_ns}")
            for e in sorted(entries):
                h.update(e.encode("utf-8", "surrogatepass") + b"\n")
            _FINGERPRINT[0] = h.hexdigest()
        return _FINGERPRINT[0]


def _norm(p: str) -> str:
    return os.path.normpath(os.path.abspath(p))


def key(path: str, sources: dict[str, str]) -> str:
    h = hashlib.sha256()
    h.update(f"{FORMAT}\n{C.compiler_version()}\n{code_fingerprint()}\n".encode())
    h.update(_norm(path).encode("utf-8", "surrogatepass") + b"\0\0")
    for p, t in sorted((_norm(p), t) for p, t in sources.items()):
        h.update(p.encode("utf-8", "surrogatepass") + b"\0")
        h.update(("" if t is None else t).encode("utf-8", "surrogatepass") + b"\0")
    return h.hexdigest()


def encode(k: str, fields: dict) -> bytes:
    """The file's bytes for ``fields``: total (int), per_feature (name -> int, in order), core,
    dead, false_optional (sets of names), hover (None, or rows: ``[line, col, end line, end
    col, markdown]`` of the feature declarations).  A header line (format, key, the payload's size and
    SHA-256), then the payload (JSON)."""
    plain = {
        "total": format(fields["total"], "x"),
        "per_feature": [[n, format(v, "x")] for n, v in fields["per_feature"].items()],
        "core": sorted(fields["core"]),
        "dead": sorted(fields["dead"]),
        "false_optional": sorted(fields["false_optional"]),
    }
    if fields.get("hover") is not None:
        plain["hover"] = fields["hover"]
    payload = json.dumps(plain, separators=(",", ":")).encode()
    header = json.dumps({"format": FORMAT, "key": k, "size": len(payload),
                         "sha256": hashlib.sha256(payload).hexdigest()}, separators=(",", ":")).encode()
    return header + b"\n" + payload


def _hex(x) -> int:
    if not isinstance(x, str) or not (x.isascii() and x.isalnum()):  # (int() takes "-1", " 1", "1_0")
        raise ValueError("not a count")
    return int(x, 16)


def _names(x) -> set[str]:
    if not isinstance(x, list) or not all(isinstance(n, str) for n in x):
        raise ValueError("not a list of names")
    return set(x)


def _rows(x) -> Optional[list]:
    """Hover rows: ``[line, col, end line, end col, markdown]`` (None when absent)."""
    if x is None:
        return None
    if not isinstance(x, list):
        raise ValueError("not a list of rows")
    for r in x:
        if not (isinstance(r, list) and len(r) == 5 and isinstance(r[4], str)
                and all(type(v) is int and v >= 0 for v in r[:4]) and (r[0], r[1]) <= (r[2], r[3])):
            raise ValueError("not a hover row")
    return x


def decode(k: str, data: bytes) -> Optional[dict]:
    """The fields stored in ``data`` when it is a sound file for the key ``k``, else None."""
    try:
        nl = data.find(b"\n")
        if nl < 0 or nl > 4096:
            return None
        head = json.loads(data[:nl].decode("utf-8"))
        payload = data[nl + 1:]
        if not isinstance(head, dict) or head.get("format") != FORMAT or head.get("key") != k \
                or head.get("size") != len(payload) or head.get("sha256") != hashlib.sha256(payload).hexdigest():
            return None
        plain = json.loads(payload.decode("utf-8"))
        if not isinstance(plain, dict):
            return None
        total = _hex(plain["total"])
        rows = plain["per_feature"]
        if not isinstance(rows, list):
            return None
        per_feature: dict[str, int] = {}
        for row in rows:
            if not (isinstance(row, list) and len(row) == 2 and isinstance(row[0], str)):
                return None
            n = _hex(row[1])
            if n > total or row[0] in per_feature:
                return None
            per_feature[row[0]] = n
        return {"total": total, "per_feature": per_feature, "core": _names(plain["core"]),
                "dead": _names(plain["dead"]), "false_optional": _names(plain["false_optional"]),
                "hover": _rows(plain.get("hover"))}
    except (ValueError, KeyError, TypeError, UnicodeDecodeError, RecursionError):
        return None


def file_name(k: str) -> str:
    return k + SUFFIX


def load(path: str, sources: dict[str, str]) -> Optional[dict]:
    """The facts stored for this content, or None (none stored, or a file that is not sound:
    it is deleted)."""
    k = key(path, sources)
    disk = C.DiskCache()
    data = disk.get_blob(file_name(k))
    if data is None:
        return None
    fields = decode(k, data)
    if fields is None:
        disk.discard_blob(file_name(k))
    return fields


def store(path: str, sources: dict[str, str], fields: dict) -> bool:
    """Keep complete, exact facts for this content (atomically; False when not written)."""
    k = key(path, sources)
    try:
        data = encode(k, fields)
    except (ValueError, KeyError, TypeError):
        return False
    return C.DiskCache().put_blob(file_name(k), data) is not None
