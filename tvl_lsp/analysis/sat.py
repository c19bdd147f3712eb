"""SAT calls that a CPU-time limit can stop.

Python's CPU-time budget (``project/budget.py``, a ``SIGPROF`` timer) interrupts Python code
only: a solver call runs in C and ignores it, so one hard instance (a pigeonhole formula of 132
variables in a 1 KB DIMACS file) kept ``--check`` busy for hours.  Every solver the analyses
create is a :class:`BoundedSolver`.  While a :func:`cpu_limit` block is active on the thread,
its ``solve`` calls are *limited* calls that a watchdog thread interrupts once the process has
used the block's CPU time; the interrupted call raises :class:`SolverInterrupted` (the budget's
caller turns it into ``analysis-budget-exceeded``).  Outside such a block ``solve`` is pysat's
own, unchanged.
"""

from __future__ import annotations

import threading
import time
from contextlib import contextmanager
from typing import Optional

from pysat.solvers import Solver

_local = threading.local()
POLL_SECONDS = 0.05  # how often the watchdog looks at the CPU clock
# Glucose looks at an interrupt only between two restarts, which grow apart on a hard instance
# (a 1 s limit stopped a pigeonhole formula after 2 s; MiniSat stops at once): the solvers are
# interrupted this long before the block's CPU time is spent, so that the block ends within it
SOLVER_LATENCY = 1.0


class SolverInterrupted(BaseException):  # like the CPU budget's exception: no "except Exception" swallows it
    def __init__(self, seconds: float):
        self.what = f"more than {seconds:g} s of CPU time"
        super().__init__(self.what)
        self.seconds = seconds


class _Watch:
    """Interrupts the registered solver once ``time.process_time()`` passes ``cpu_deadline``."""

    def __init__(self, seconds: float):
        self.seconds = seconds
        self.cpu_deadline = time.process_time() + seconds
        self.fired = False
        self.current: Optional[Solver] = None
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="tvl-lsp-sat-watch", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        at = self.cpu_deadline - min(SOLVER_LATENCY, self.seconds / 4)
        while not self._stop.wait(POLL_SECONDS):
            if time.process_time() >= at:
                with self._lock:
                    self.fired = True
                    if self.current is not None:
                        self.current.interrupt()
                return

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()

    def solve(self, s: "BoundedSolver", assumptions) -> bool:
        with self._lock:
            if self.fired:
                raise SolverInterrupted(self.seconds)
            self.current = s
        try:
            r = Solver.solve_limited(s, assumptions=assumptions, expect_interrupt=True)
        finally:
            with self._lock:
                self.current = None
        if r is None:  # interrupted (the watchdog, or SIGINT)
            s.clear_interrupt()
            raise SolverInterrupted(self.seconds)
        return r


class BoundedSolver(Solver):
    """pysat's :class:`Solver` whose ``solve`` honours the thread's :func:`cpu_limit`."""

    def solve(self, assumptions=[]):  # noqa: B006 (pysat's signature)
        w = getattr(_local, "watch", None)
        if w is None:
            return Solver.solve(self, assumptions=assumptions)
        return w.solve(self, assumptions)


def remaining() -> Optional[float]:
    """CPU seconds left in this thread's :func:`cpu_limit` block (None outside one)."""
    w = getattr(_local, "watch", None)
    return None if w is None else max(0.0, w.cpu_deadline - time.process_time())


@contextmanager
def cpu_limit(seconds: Optional[float]):
    """While the block runs on this thread, solver calls stop (raising
    :class:`SolverInterrupted`) once the process has used ``seconds`` more CPU time.
    ``None`` or ``<= 0``: no limit.  Nested blocks keep the tighter limit."""
    outer = getattr(_local, "watch", None)
    if seconds is None or seconds <= 0 or (
            outer is not None and outer.cpu_deadline <= time.process_time() + seconds):
        yield
        return
    w = _Watch(seconds)
    _local.watch = w
    try:
        yield
    finally:
        _local.watch = outer
        w.stop()
