"""Environment variables tvl-lsp reads, validated: a bad value is explained once on stderr
(one line: the variable, the value, what is expected, what is used instead) and never stops a
command or the server.

- ``TVL_LSP_LOG``: the log level, any case (``debug``, ``INFO``, ``Warning``...) or a number;
- ``TVL_LSP_CACHE_MAX_MB``: the disk cache's bound, a finite number of megabytes (0 keeps
  nothing; ``inf``, ``nan``, ``1e400``, negative numbers and words are refused).
"""

from __future__ import annotations

import logging
import math
import os
import sys
import threading
from typing import Optional

_WARNED: set[str] = set()
_LOCK = threading.Lock()

LEVELS = ("CRITICAL", "ERROR", "WARNING", "INFO", "DEBUG")


def warn_once(name: str, value: str, expected: str, used: str) -> None:
    """Say on stderr, once per variable and value, that ``name=value`` is not valid."""
    key = f"{name}={value}"
    with _LOCK:
        if key in _WARNED:
            return
        _WARNED.add(key)
    shown = value if len(value) <= 40 else value[:37] + "..."
    try:
        sys.stderr.write(f"tvl-lsp: {name}={shown!r} is not valid ({expected}); using {used}\n")
        sys.stderr.flush()
    except (OSError, ValueError, AttributeError):
        pass


def log_level(value: Optional[str] = None, default: int = logging.WARNING) -> int:
    """The logging level named by ``TVL_LSP_LOG`` (or ``value``): a level name in any case, or
    a number from 0 to 50."""
    raw = os.environ.get("TVL_LSP_LOG") if value is None else value
    if raw is None or not raw.strip():
        return default
    text = raw.strip()
    if text.upper() in LEVELS:
        return getattr(logging, text.upper())
    if text.isdigit() and int(text) <= 50:
        return int(text)
    warn_once("TVL_LSP_LOG", raw, "one of " + ", ".join(n.lower() for n in LEVELS),
              logging.getLevelName(default).lower())
    return default


def megabytes(name: str, default: float, maximum: float = 1 << 30) -> int:
    """A size in bytes from a variable holding megabytes: a finite number from 0 to
    ``maximum``; anything else is explained and ``default`` is used."""
    raw = os.environ.get(name)
    if raw is None or not raw.strip():
        return int(default * 1024 * 1024)
    try:
        mb = float(raw.strip())
    except ValueError:
        mb = math.nan
    if not math.isfinite(mb) or mb < 0 or mb > maximum:
        warn_once(name, raw, f"a number of megabytes from 0 to {maximum:g}", f"{default:g} MB")
        mb = default
    return int(mb * 1024 * 1024)
