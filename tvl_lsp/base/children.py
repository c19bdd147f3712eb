"""Child processes that die with their parent (issue #28: no orphaned counting processes).

Two kinds of children:

- **one-shot programs** (d4's compilation, pyganak's count: ``python -m ...``), started with
  :func:`popen`: each runs in a process group of its own (so a kill reaches anything it
  starts), is told its parent's process id (``TVL_LSP_PARENT_PID``), and calls
  :func:`die_with_parent` first: Linux's ``PR_SET_PDEATHSIG`` (SIGKILL when the thread that
  started it ends -- that thread waits for it, so when the process that asked dies), then a
  check that the parent is still the one that started it (it may have died before the
  ``prctl``).  :func:`kill` ends one (its whole group); :func:`kill_all` every live one (a
  host that stops on SIGTERM);
- **pool workers** (``ProcessPoolExecutor``: the configurator's check process, ``--check -j``):
  their initializer calls :func:`watch_parent`, a thread that ends the worker once its parent is
  gone (a pool may be started from a short-lived thread, so the thread-bound ``prctl`` would
  end it too early).

A host that stops on SIGTERM calls :func:`kill_all` (``tvl-lsp ui``, the CLI through
:func:`terminate_on_sigterm`); a parent killed with SIGKILL takes its one-shot children with
it (``prctl``), and its pool workers follow within ``WATCH_SECONDS``.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
import weakref
from typing import Optional

ENV_PARENT = "TVL_LSP_PARENT_PID"
WATCH_SECONDS = 0.5
PR_SET_PDEATHSIG = 1

_LIVE: "weakref.WeakSet[subprocess.Popen]" = weakref.WeakSet()
_LIVE_LOCK = threading.Lock()


def popen(cmd: list[str], **kwargs) -> subprocess.Popen:
    """``subprocess.Popen`` for a one-shot child: its own process group, its parent's id in
    its environment, remembered until it ends (:func:`kill_all`)."""
    env = dict(kwargs.pop("env", None) or os.environ)
    env[ENV_PARENT] = str(os.getpid())
    if os.name == "posix":
        kwargs.setdefault("start_new_session", True)
    proc = subprocess.Popen(cmd, env=env, **kwargs)
    with _LIVE_LOCK:
        _LIVE.add(proc)
    return proc


def kill(proc: subprocess.Popen, wait: bool = True) -> None:
    """End ``proc`` and its process group now (SIGKILL), and reap it."""
    if proc.poll() is None:
        try:
            if os.name == "posix":
                os.killpg(proc.pid, signal.SIGKILL)
            else:
                proc.kill()
        except (ProcessLookupError, PermissionError, OSError):
            try:
                proc.kill()
            except OSError:
                pass
    if wait:
        try:
            proc.wait(5)
        except (subprocess.TimeoutExpired, OSError):
            pass
    with _LIVE_LOCK:
        _LIVE.discard(proc)


def kill_all() -> int:
    """Kill every one-shot child of this process that is still running; how many."""
    with _LIVE_LOCK:
        procs = [p for p in _LIVE if p.poll() is None]
    for p in procs:
        kill(p, wait=False)
    for p in procs:
        try:
            p.wait(2)
        except (subprocess.TimeoutExpired, OSError):
            pass
    return len(procs)


def _prctl_pdeathsig(sig: int) -> bool:
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_PDEATHSIG, int(sig), 0, 0, 0) == 0
    except (OSError, AttributeError, TypeError):
        return False


def die_with_parent() -> None:
    """First thing a one-shot child does: be killed when its parent goes, and exit at once if
    it is already gone."""
    expected = os.environ.get(ENV_PARENT, "")
    _prctl_pdeathsig(signal.SIGKILL)
    parent = int(expected) if expected.isdigit() else None
    if parent is not None and os.getppid() != parent:
        os._exit(1)
    if parent is None or not sys.platform.startswith("linux"):
        watch_parent()


def watch_parent(interval: float = WATCH_SECONDS) -> None:
    """A daemon thread that ends this process once its parent is gone (pool workers)."""
    parent = os.getppid()

    def watch() -> None:
        while True:
            time.sleep(interval)
            if os.getppid() != parent:
                os._exit(1)
    threading.Thread(target=watch, name="tvl-parent-watch", daemon=True).start()


class Terminated(SystemExit):
    """Raised in the main thread by SIGTERM (:func:`terminate_on_sigterm`): ``finally`` blocks
    run (temporary files removed, children killed) and the process exits with 143."""

    def __init__(self):
        super().__init__(128 + signal.SIGTERM)


def terminate_on_sigterm() -> Optional[object]:
    """Make SIGTERM end a command the way Ctrl-C does (its ``finally`` blocks run, no
    traceback), killing its one-shot children first.  Main thread only; the previous handler."""
    if threading.current_thread() is not threading.main_thread():
        return None

    def on_term(signum, frame):
        kill_all()
        raise Terminated()
    try:
        return signal.signal(signal.SIGTERM, on_term)
    except (ValueError, OSError):
        return None
