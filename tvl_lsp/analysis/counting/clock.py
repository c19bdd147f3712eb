"""The clock of a counting child process's time budget (d4's compilation, pyganak's count).

By default the wall clock: ``count --timeout 5`` answers within about 5 s.  A host whose counts
run in the background while the user goes on working -- the language server's worker
processes -- sets ``TVL_LSP_COUNT_CLOCK=cpu``: the budget is then the child's CPU time, so a
machine busy with a build slows a count down but does not turn it into a timeout (a two-second
compilation of automotive01.uvl gave no answer within the 10 s budget at load 12, issue #28).
The wall clock still stops the child after :data:`WALL_FACTOR` times its budget.
"""

from __future__ import annotations

import os
import time

ENV = "TVL_LSP_COUNT_CLOCK"
WALL_FACTOR = 10.0

try:
    _TICKS = os.sysconf("SC_CLK_TCK")
except (AttributeError, ValueError, OSError):
    _TICKS = 100


def cpu_budgets() -> bool:
    return os.environ.get(ENV, "").lower() == "cpu"


def cpu_seconds(pid: int) -> float | None:
    """The CPU time (user + system) process ``pid`` has used, or None where /proc says nothing."""
    from ...base.files import read_head
    try:
        data = read_head(f"/proc/{pid}/stat", 4096)  # (the bounded reader: one line)
        if not data:
            return None
        fields = data[data.rindex(b")") + 2:].split()
        return (int(fields[11]) + int(fields[12])) / _TICKS  # utime, stime (fields 14, 15)
    except (OSError, ValueError, IndexError):
        return None


class Budget:
    """``spent()``: has the child ``pid``, started at ``start`` (time.monotonic), used up its
    ``seconds``?"""

    def __init__(self, pid: int, seconds: float, start: float | None = None):
        self.pid = pid
        self.seconds = seconds
        self.start = time.monotonic() if start is None else start
        self.cpu = cpu_budgets() and cpu_seconds(pid) is not None
        self._next = 0.0

    def spent(self) -> bool:
        wall = time.monotonic() - self.start
        if not self.cpu:
            return wall > self.seconds
        if wall > self.seconds * WALL_FACTOR:
            return True
        if wall < self._next:  # (/proc is read at most every 0.1 s)
            return False
        self._next = wall + 0.1
        used = cpu_seconds(self.pid)
        return used is not None and used > self.seconds
