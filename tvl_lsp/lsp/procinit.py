"""What the server's worker processes (checks, counts) run first: their priority, die with the
server, import the core.  A module of its own that imports nothing heavy: a worker process
imports the initializer's module before running it -- with :mod:`.workers` (lsprotocol: 0.4 s
of CPU) the two workers' start-up competed with the server's first parse of the document being
opened.

Priorities: the check and count processes do what the user is waiting for (diagnostics, the
counts of a hover) and keep the server's priority: niced, they lost to every other process of
a busy machine (a build), and the first counted hover of automotive01.uvl came 153 s after
opening at load 12 (issue #28).  Only speculative work -- a count that ran out of its budget,
retried with a longer one -- runs in a niced process (:data:`BACKGROUND_NICE`).  A niced
process cannot lower its nice value again, so the two kinds of work never share a process.
"""

from __future__ import annotations

import os
import sys
import threading
import time

M_MMAP_THRESHOLD = -3  # glibc's mallopt parameter


def bound_heap(threshold: int = 128 * 1024) -> bool:
    """Large blocks (a document's text, its line index, a big parse's arrays) are mapped
    and unmapped, so memory goes back to the system once a big document is gone.

    glibc raises its mmap threshold each time a mapped block is freed (up to 32 MB): after a
    few big texts every large block comes from the heap, which fragments and never shrinks
    (the server fuzz campaign: +50 % RSS after a thousand edits with no object kept).  A
    fixed threshold turns that adjustment off.  False where there is no glibc ``mallopt``."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes
        return bool(ctypes.CDLL(None).mallopt(M_MMAP_THRESHOLD, threshold))
    except (OSError, AttributeError, TypeError):
        return False


BACKGROUND_NICE = 10  # the background process's nice increment (retried counts)


def _worker_init(nice: int = 0) -> None:
    """Worker processes die with the server (an editor may kill it without a ``shutdown``);
    ``nice``: lower this process's priority by that much (the background process only)."""
    bound_heap()
    if os.environ.get("TVL_LSP_LOGFILE"):  # the server's log, with this process's id
        import logging
        logging.basicConfig(level=os.environ.get("TVL_LSP_LOG", "WARNING").upper(),
                            filename=os.environ["TVL_LSP_LOGFILE"],
                            format=f"%(asctime)s %(levelname)s %(name)s [worker {os.getpid()}]: %(message)s")
    # counts run in the background while the user works on: their budgets are CPU time, so a
    # busy machine slows them down without turning them into timeouts (analysis/counting/clock.py)
    os.environ["TVL_LSP_COUNT_CLOCK"] = "cpu"
    if nice:
        try:
            os.nice(nice)
        except (OSError, AttributeError):
            pass
    parent = os.getppid()
    try:  # Linux: SIGKILL when the parent dies
        import ctypes
        import signal
        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except Exception:
        pass

    def orphan_watch():  # elsewhere (or if the parent died before prctl): poll
        while True:
            time.sleep(1.0)
            if os.getppid() != parent:
                os._exit(0)
    threading.Thread(target=orphan_watch, daemon=True).start()
    threading.Thread(target=_idle_trimmer, daemon=True, name="tvl-idle-trim").start()


IDLE_SECONDS = 1.0   # a worker that used (almost) no CPU for this long is idle ...
TRIM_AFTER_CPU = 0.5  # ... and gives its freed memory back if it worked this much since it last did


def _cpu() -> float:
    t = os.times()
    return t.user + t.system


def _idle_trimmer() -> None:
    """When the worker goes idle after some work, collect its garbage cycles (a parse's trees
    have parent links: they wait for a full collection) and give the free heap back to the
    system (``malloc_trim``): an idle worker's memory is what its caches hold, not the peak of
    its last check (issue #28: 1.87 GB after 12 edit cycles of a big model)."""
    import gc
    trim = None
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            trim = ctypes.CDLL(None).malloc_trim
        except (OSError, AttributeError):
            trim = None
    when = IdleTrim(_cpu())
    while True:
        time.sleep(IDLE_SECONDS)
        if not when.due(_cpu()):
            continue
        gc.collect()
        if trim is not None:
            try:
                trim(0)
            except Exception:  # noqa: BLE001 (an optimisation)
                pass
        when.done(_cpu())


class IdleTrim:
    """When to trim (:func:`_idle_trimmer`), from the process's CPU time read every
    :data:`IDLE_SECONDS`: once it is idle (almost no CPU used since the last reading) after
    at least :data:`TRIM_AFTER_CPU` seconds of work since the last trim -- never while it
    works, never twice for one piece of work."""

    def __init__(self, cpu: float):
        self.last = self.trimmed = cpu

    def due(self, cpu: float) -> bool:
        busy, self.last = cpu - self.last > 0.05 * IDLE_SECONDS, cpu
        return not busy and cpu - self.trimmed >= TRIM_AFTER_CPU

    def done(self, cpu: float) -> None:
        self.trimmed = self.last = cpu


def _warm() -> None:
    try:
        from ..project import facts as _facts  # noqa: F401
        from ..analysis import engine  # noqa: F401
        from ..tvl import parse_model  # noqa: F401
    except Exception:
        pass
