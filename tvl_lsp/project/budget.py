"""The per-file analysis budget: CPU time and memory one file's check may use.

Every bound in the front ends (file sizes, element counts, ``$(eval)`` values, YAML aliases,
SAT time budgets) keeps ordinary and hostile files fast; this is the backstop behind them.
:func:`limited` runs one file's check under a CPU-time budget (the process's CPU time, timed
by ``ITIMER_PROF``; the check is interrupted the next time Python code runs) and turns a
``MemoryError`` into the same outcome: the file gets one ``analysis-budget-exceeded`` error and
the rest of the workspace is still checked.

The budget needs the main thread (signals are delivered there); elsewhere the check runs
without it.  :func:`cap_memory` sets the process's data-segment limit (``RLIMIT_DATA``) so that
an allocation past it raises ``MemoryError`` instead of exhausting the machine; the
``--check`` command and the server's check workers call it once.
"""

from __future__ import annotations

import gc
import os
import signal
import threading
from contextlib import contextmanager
from typing import Callable, Optional, TypeVar

from ..base.diagnostics import Diagnostic, Severity, register
from ..base.text import Pos, Span

BUDGET_EXCEEDED = register(
    "analysis-budget-exceeded", Severity.ERROR,
    "a file's check used more CPU time or memory than its budget; it was stopped, the rest was checked",
    "workspace")

CPU_SECONDS = 30.0            # per file, CPU time (the SAT analyses have their own, smaller budgets)
MEMORY_BYTES = 3 * 1024 ** 3  # per process, data segment

T = TypeVar("T")


class BudgetExceeded(BaseException):  # not an Exception: no "except Exception" in the analysis swallows it
    def __init__(self, what: str):
        super().__init__(what)
        self.what = what


def _data_in_use() -> int:
    try:
        with open("/proc/self/statm", "rb") as fh:  # size resident shared text lib data dt (pages)
            return int(fh.read().split()[5]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


@contextmanager
def cap_memory(allowance: int = MEMORY_BYTES):
    """While the block runs, the process's data segment may grow by at most ``allowance``
    (``RLIMIT_DATA``, never raised above an existing limit); the previous limit is restored
    after it.  Past it an allocation raises ``MemoryError``: that file's check ends with
    ``analysis-budget-exceeded`` (see :func:`limited`); worker processes inherit the limit."""
    try:
        import resource
        old = resource.getrlimit(resource.RLIMIT_DATA)
        soft, hard = old
        want = _data_in_use() + allowance
        if hard != resource.RLIM_INFINITY:
            want = min(want, hard)
        if soft == resource.RLIM_INFINITY or soft > want:
            resource.setrlimit(resource.RLIMIT_DATA, (want, hard))
    except (ImportError, ValueError, OSError):  # not on this platform
        old = None
    try:
        yield
    finally:
        if old is not None:
            try:
                resource.setrlimit(resource.RLIMIT_DATA, old)
            except (ValueError, OSError):
                pass


@contextmanager
def _cpu_budget(seconds: Optional[float]):
    usable = (seconds is not None and seconds > 0 and hasattr(signal, "setitimer")
              and threading.current_thread() is threading.main_thread())
    if not usable:
        yield
        return

    def on_prof(signum, frame):
        raise BudgetExceeded(f"more than {seconds:g} s of CPU time")

    old = signal.signal(signal.SIGPROF, on_prof)
    prev = signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, old)
        if prev and prev[0]:
            signal.setitimer(signal.ITIMER_PROF, *prev)


def exceeded(path: str, what: str) -> Diagnostic:
    return Diagnostic(BUDGET_EXCEEDED, Severity.ERROR, path, Span(Pos(0, 0), Pos(0, 0)),
                      f"{os.path.basename(path)} was not fully checked: its analysis needed {what}, more than "
                      "its budget; the other files were checked (simplify or split it, or report it if it is small)")


def limited(path: str, run: Callable[[], list], seconds: Optional[float] = CPU_SECONDS) -> list:
    """``run()`` (one file's check, a list of diagnostics) within the budget, or a list with one
    ``analysis-budget-exceeded`` diagnostic for ``path``."""
    # the cyclic garbage collector is paused for the file (the front ends and the encoder build
    # millions of small objects and few cycles: on a 200,000-feature model its rescans of the
    # growing heap cost more than the analysis); what a check leaves is collected after it
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        with _cpu_budget(seconds):
            return run()
    except BudgetExceeded as exc:
        return [exceeded(path, exc.what)]
    except MemoryError:
        return [exceeded(path, "more memory than it may use")]
    finally:
        if was_enabled:
            gc.enable()
