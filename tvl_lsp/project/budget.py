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
``--check`` command calls it once, and runs the checks in worker processes it watches
(:mod:`.supervise`): at the limit itself CPython 3.11 can spin for ever and the C++ solvers
abort, which no code in the process can recover from.
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
    "A file's check used more CPU time or memory than its budget; it was stopped, the rest was checked.",
    "workspace")

CPU_SECONDS = 30.0            # per file, CPU time (the SAT analyses have their own, smaller budgets)
MEMORY_BYTES = 3 * 1024 ** 3  # per process, data segment
# ``--check`` (a CI job, one process): every file is done in seconds and well under 1 GB, the
# biggest industrial models included (automotive2_1: 2.4 s, 320 MB); a hostile or
# pathological file (a hard SAT instance, a model far beyond any real one) stops there
CHECK_CPU_SECONDS = 4.0
CHECK_MEMORY_BYTES = 880 * 1024 ** 2
MEMORY_WHAT = "more memory than it may use"  # (the ``what`` of the memory budget's error)

T = TypeVar("T")


class BudgetExceeded(BaseException):  # not an Exception: no "except Exception" in the analysis swallows it
    def __init__(self, what: str):
        super().__init__(what)
        self.what = what


def _data_in_use() -> int:
    from ..base.files import read_head
    try:  # size resident shared text lib data dt (pages)
        return int((read_head("/proc/self/statm", 256) or b"").split()[5]) * os.sysconf("SC_PAGE_SIZE")
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


def exceeded(path: str, what: str, done: Optional[str] = None, rest: Optional[str] = None) -> Diagnostic:
    """The ``analysis-budget-exceeded`` error of ``path``; ``done``: what was completed and is
    reported all the same (e.g. "its syntax and type checks"), ``rest``: what was stopped."""
    if done:
        tail = (f"; {done} are complete and reported, {rest or 'the rest'} was stopped (`--budget SECONDS` "
                "raises the budget of `--check`)")
    else:
        tail = ("; the other files were checked (simplify or split it, or raise the budget: "
                "`--budget SECONDS` for `--check`)")
    return Diagnostic(BUDGET_EXCEEDED, Severity.ERROR, path, Span(Pos(0, 0), Pos(0, 0)),
                      f"{os.path.basename(path)} was not fully checked: its analysis needed {what}, more than "
                      f"its budget{tail}")


class Progress:
    """What a check has finished before its budget ran out: ``diagnostics`` are final and are
    reported with the ``analysis-budget-exceeded`` error, ``done`` says what they cover."""
    __slots__ = ("diagnostics", "done", "rest")

    def __init__(self):
        self.diagnostics: list[Diagnostic] = []
        self.done: Optional[str] = None   # what the diagnostics cover ("its syntax and type checks")
        self.rest: Optional[str] = None   # what comes after it ("the search for anomalies (...)")


RESERVE_BYTES = 32 * 1024 * 1024  # address space held back for the handling of a MemoryError


def _reserve():
    """An untouched private mapping of ``RESERVE_BYTES`` (it counts towards ``RLIMIT_DATA`` but
    not towards the resident memory): released when an allocation fails, it leaves room to
    unwind and report.  Without it Python had no memory left to handle the ``MemoryError`` and
    aborted ("Fatal Python error") in one run out of two."""
    try:
        import mmap
        return mmap.mmap(-1, RESERVE_BYTES, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    except (ImportError, OSError, ValueError, AttributeError):
        return None


def out_of_memory(exc: BaseException) -> bool:
    """Whether ``exc`` is this process running out of its memory budget: a ``MemoryError``, or
    the ``SystemError`` CPython raises in its place ("returned NULL without setting an
    exception") when it had no memory left to create the ``MemoryError``, while the data segment
    is within :data:`RESERVE_BYTES` (plus as much again) of its limit."""
    if isinstance(exc, MemoryError):
        return True
    if not isinstance(exc, SystemError) or "without setting an exception" not in str(exc):
        return False
    try:
        import resource
        soft = resource.getrlimit(resource.RLIMIT_DATA)[0]
    except (ImportError, ValueError, OSError):
        return False
    return soft != resource.RLIM_INFINITY and soft - _data_in_use() < 2 * RESERVE_BYTES


def remaining() -> Optional[float]:
    """CPU seconds left to the current :func:`limited` block on this thread (None: no limit)."""
    from ..analysis.sat import remaining as _remaining
    return _remaining()


def limited(path: str, run: Callable[[], list], seconds: Optional[float] = CPU_SECONDS,
            progress: Optional[Progress] = None, keep: Optional[list] = None) -> list:
    """``run()`` (one file's check, a list of diagnostics) within the budget, or, past it, the
    diagnostics ``progress`` collected and one ``analysis-budget-exceeded`` error for ``path``.
    Solver calls (C code, which the CPU timer cannot interrupt) are stopped at the same budget
    (:func:`tvl_lsp.analysis.sat.cpu_limit`).  ``keep``: a list the stopped check's exception
    (and so its frames' objects) is appended to, for a process that ends soon to drop at once."""
    from ..analysis.sat import SolverInterrupted, cpu_limit
    # the cyclic garbage collector is paused for the file (the front ends and the encoder build
    # millions of small objects and few cycles: on a 200,000-feature model its rescans of the
    # growing heap cost more than the analysis); what a check leaves is collected after it
    was_enabled = gc.isenabled()
    gc.disable()
    reserve = [_reserve()]

    def guarded() -> list:
        try:
            return run()
        except MemoryError:
            if reserve[0] is not None:  # room to unwind, before anything else allocates
                reserve[0].close()
                reserve[0] = None
            raise

    try:
        with cpu_limit(seconds if threading.current_thread() is threading.main_thread() else None), \
                _cpu_budget(seconds):
            return guarded()
    except (MemoryError, BudgetExceeded, SolverInterrupted) as exc:
        what = MEMORY_WHAT if isinstance(exc, MemoryError) else exc.what
        if keep is not None:
            keep.append(exc)
    finally:
        if reserve[0] is not None:
            reserve[0].close()
        if keep is not None:
            gc.freeze()  # what the check made is dropped at the end, not scanned by the collector first
        if was_enabled:
            gc.enable()
    if progress is None:
        return [exceeded(path, what)]
    return list(progress.diagnostics) + [exceeded(path, what, progress.done, progress.rest)]
