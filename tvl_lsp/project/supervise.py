"""``--check``'s units of work in worker processes that the command watches: the backstop of
the memory budget, so that no file can hang or crash ``--check``.

Inside a worker a file's check that runs out of memory ends in :func:`.budget.limited` with
``analysis-budget-exceeded`` -- in most runs.  Two things a process cannot recover from by
itself happen at its memory limit, and only there:

- CPython 3.11 **spins for ever**: when an exception unwinds to a ``with`` (or ``finally``)
  handler past offset 256 of a function, the interpreter allocates the offset as an int; when
  that allocation fails it looks for the same handler again, and again (``ceval.c``'s
  ``exception_unwind``: ``PyLong_FromLong(frame_lasti)`` failing ``goto exception_unwind``),
  in C, holding the GIL: no signal handler, timer or other thread of the process runs again
  (``--check --memory 100`` of a 400,000-clause DIMACS model, at ``project/models.py``'s
  ``with lk:``);
- the C++ SAT solvers **abort** the process (``Glucose41::OutOfMemoryException``).

So the units (:func:`tvl_lsp.project.check.plan`) run in forked workers, each worker reports
every file as it starts and ends it, and the command's own process (which uses little memory)
watches them:

- a worker with less than :data:`STUCK_ROOM` left below its memory limit for
  :data:`STUCK_SECONDS` is stuck there: its soft limit is raised by :data:`RESCUE_BYTES`
  (``prlimit``), the failed allocation then succeeds, it unwinds and reports the file's budget
  error itself (with the findings made before it), and is replaced after its unit.  Still stuck
  :data:`GRACE` seconds later, it is killed and the file gets the budget error;
- a worker that dies (a solver's abort at the limit, a segfault, the system's OOM killer) is
  replaced; its file gets ``analysis-budget-exceeded`` if it was near its memory limit at the
  last look (:data:`NEAR_SHARE`, :data:`NEAR_MAX`), an ``internal-error`` otherwise.

The files of a unit not reached yet are checked in a new worker, and every other result stands.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import time
from collections import deque
from dataclasses import replace
from multiprocessing.connection import wait as wait_for
from typing import Any, Callable, Optional, Sequence

from ..base.diagnostics import Diagnostic, Severity
from ..base.text import Pos, Span
from . import budget

MB = 1024 * 1024
TICK = 0.05                # seconds between two looks at the workers
STUCK_ROOM = 2 * MB        # a worker with less room than this below its limit ...
STUCK_SECONDS = 0.5        # ... for this long is stuck there (a working process fails or frees sooner)
RESCUE_BYTES = 32 * MB     # how much its limit is raised by, to unwind
GRACE = 5.0                # seconds a rescued worker has to unwind before it is killed
NEAR_SHARE = 4             # a worker that dies with less than a quarter of the room it had at the
NEAR_MAX = 64 * MB         # unit's start left (64 MB at most) died of its memory limit

RunUnit = Callable[..., list]
STATS = {"workers": 0, "rescued": 0, "killed": 0, "died": 0}  # (this process's, for tests and benchmarks)


def available() -> bool:
    """Workers can be forked here (Linux and the like, with ``/proc``)."""
    return hasattr(os, "fork") and "fork" in mp.get_all_start_methods() and os.path.isdir("/proc/self")


def room_of(pid: int) -> Optional[int]:
    """Bytes the process ``pid`` (one of this user's) has left below the tighter of its soft
    memory limits (``RLIMIT_DATA`` against its data segment, ``RLIMIT_AS`` against its address
    space), or None: no limit, or the process is gone."""
    try:
        import resource
        from ..base.files import read_head
        status = (read_head(f"/proc/{pid}/status", 4096) or b"").decode("ascii", "replace")
        kb = {k: int(v.split()[0]) * 1024 for k, v in (ln.split(":", 1) for ln in status.splitlines() if ":" in ln)
              if k in ("VmData", "VmSize")}
        best: Optional[int] = None
        for which, used in ((resource.RLIMIT_DATA, kb.get("VmData")), (resource.RLIMIT_AS, kb.get("VmSize"))):
            soft = resource.prlimit(pid, which)[0]
            if used is None or soft == resource.RLIM_INFINITY or soft < 0:
                continue
            best = soft - used if best is None else min(best, soft - used)
        return best
    except (ImportError, AttributeError, ValueError, IndexError, OSError):
        return None


def raise_limit(pid: int, nbytes: int) -> bool:
    """Raise the soft memory limits of the process ``pid`` (``RLIMIT_DATA`` and ``RLIMIT_AS``,
    where set) by ``nbytes``, within their hard limits.  Whether a limit was raised."""
    try:
        import resource
    except ImportError:
        return False
    done = False
    for which in (resource.RLIMIT_DATA, resource.RLIMIT_AS):
        try:
            soft, hard = resource.prlimit(pid, which)
            if soft == resource.RLIM_INFINITY or soft < 0:
                continue
            new = soft + nbytes if hard == resource.RLIM_INFINITY else min(hard, soft + nbytes)
            if new > soft:
                resource.prlimit(pid, which, (new, hard))
                done = True
        except (ValueError, OSError, AttributeError):
            pass
    return done


def _serve(conn, run_unit: RunUnit) -> None:
    """A worker: run the units it is sent, reporting each file's start and end, then the
    unit's diagnostics."""
    from ..base.children import die_with_parent
    die_with_parent()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # (Ctrl-C reaches the command, which kills its workers)

    def send(msg) -> None:
        try:
            conn.send(msg)
        except (OSError, ValueError):  # the supervisor is gone
            os._exit(1)

    def on_file(path: str, diags: Optional[list]) -> None:
        send(("file", path, diags))
    while True:
        try:
            unit = conn.recv()
        except (EOFError, OSError):
            os._exit(0)
        if unit is None:
            os._exit(0)
        send(("unit", None, run_unit(unit, None, on_file)))


def _files(unit) -> list[str]:
    return ([unit.model] if unit.model is not None and unit.model_wanted else []) + [lf for lf, _, _ in unit.launches]


class _Watched:
    """What the command knows of a forked worker's memory (``self.proc``), and the look it takes
    at it every :data:`TICK`."""
    proc: Any
    room0: Optional[int] = None        # room below its limit when its work started
    room: Optional[int] = None         # ... at the last look
    stuck_since: Optional[float] = None
    rescued_at: Optional[float] = None  # when its limit was raised (then it is replaced after its work)

    def near_limit(self) -> bool:
        if self.rescued_at is not None or self.stuck_since is not None:
            return True
        if self.room is None or self.room0 is None:
            return False
        return self.room < min(NEAR_MAX, self.room0 // NEAR_SHARE)

    def look(self, now: float) -> bool:
        """Stuck at its memory limit for :data:`STUCK_SECONDS`: its limit is raised (once) so that
        it can unwind.  True when it must be killed: it cannot be rescued, or is stuck again
        :data:`GRACE` seconds after."""
        r = room_of(self.proc.pid)
        if r is not None:  # (None: no limit, or it died since: a zombie's size is not known)
            self.room = r
        if r is not None and r < STUCK_ROOM:
            self.stuck_since = self.stuck_since or now
        else:
            self.stuck_since = None
        if self.stuck_since is None or now - self.stuck_since < STUCK_SECONDS:
            return False
        if self.rescued_at is None and raise_limit(self.proc.pid, RESCUE_BYTES):
            self.rescued_at, self.stuck_since = now, None
            STATS["rescued"] += 1
            return False
        return self.rescued_at is None or now - self.rescued_at > GRACE


class _Worker(_Watched):
    def __init__(self, ctx, run_unit: RunUnit):
        mine, theirs = ctx.Pipe(duplex=True)
        self.proc = ctx.Process(target=_serve, args=(theirs, run_unit), name="tvl-lsp-check", daemon=True)
        self.proc.start()
        STATS["workers"] += 1
        theirs.close()
        self.conn = mine
        self.index: Optional[int] = None   # the unit it runs
        self.unit = None
        self.left: list[str] = []          # the unit's files not finished yet
        self.got: list[Diagnostic] = []    # the diagnostics of the unit's finished files
        self.current: Optional[str] = None

    def assign(self, index: int, unit) -> None:
        self.index, self.unit, self.left, self.got, self.current = index, unit, _files(unit), [], None
        self.stuck_since = None
        self.room0 = self.room = room_of(self.proc.pid)
        self.conn.send(unit)

    def kill(self) -> None:
        try:
            self.proc.kill()
        except (OSError, ValueError, AttributeError):
            pass
        self.proc.join(5)
        try:
            self.conn.close()
        except OSError:
            pass


def _died(path: str, exitcode: Optional[int], near_limit: bool) -> Diagnostic:
    sig = -exitcode if exitcode is not None and exitcode < 0 else None
    how = (f"was ended by {signal.Signals(sig).name}" if sig in signal.valid_signals() else
           f"exited with {exitcode}")
    if near_limit:
        return budget.exceeded(path, f"{budget.MEMORY_WHAT} (the process checking it {how} at its memory limit)")
    return Diagnostic("internal-error", Severity.ERROR, path, Span(Pos(0, 0), Pos(0, 0)),
                      f"the check of {os.path.basename(path)} stopped the process checking it (it {how}): "
                      "a bug in tvl-lsp or a library it uses (please report it); the other files were checked")


def run(units: Sequence, jobs: int, run_unit: RunUnit, order: Optional[Sequence[int]] = None) -> list[list[Diagnostic]]:
    """Each unit's diagnostics (in the order of ``units``), the units checked by ``jobs``
    watched workers, started in ``order`` (default: as given).  ``run_unit(unit, read_file,
    on_file)``: :func:`tvl_lsp.project.check._run_unit`."""
    ctx = mp.get_context("fork")
    pending = deque((i, units[i]) for i in (order if order is not None else range(len(units))))
    results: list[list[Diagnostic]] = [[] for _ in units]
    workers: list[_Worker] = []

    def fail(w: _Worker, diag: Callable[[str], Diagnostic]) -> None:
        """End ``w`` (killed): its finished files' diagnostics kept, its current file reported,
        its unit's other files queued again."""
        w.kill()
        workers.remove(w)
        results[w.index] += w.got
        path = w.current or (w.left[0] if w.left else None)
        if path is not None:
            results[w.index].append(diag(path))
        rest = [p for p in w.left if p != path]
        if rest:
            u = w.unit
            pending.appendleft((w.index, replace(u, model_wanted=u.model_wanted and u.model in rest,
                                                 launches=tuple(x for x in u.launches if x[0] in rest))))

    def drain(w: _Worker) -> bool:
        """Take ``w``'s messages; False when its pipe closed (the worker is gone)."""
        try:
            while w.index is not None and w.conn.poll():
                kind, path, diags = w.conn.recv()
                if kind == "unit":
                    results[w.index] += diags
                    w.index = w.unit = w.current = None
                    w.left, w.got = [], []
                elif diags is None:
                    w.current = path
                else:
                    w.got += diags
                    if path in w.left:
                        w.left.remove(path)
                    w.current = None
        except (EOFError, OSError):
            return False
        return True

    def watch(w: _Worker, now: float) -> None:
        """A busy worker stuck at its memory limit: rescued, then killed."""
        if w.look(now):
            STATS["killed"] += 1
            fail(w, lambda p: budget.exceeded(p, budget.MEMORY_WHAT))

    try:
        while pending or any(w.index is not None for w in workers):
            for w in [w for w in workers if w.index is None and (w.rescued_at is not None or not pending)]:
                workers.remove(w)
                try:
                    w.conn.send(None)
                except OSError:
                    pass
                w.kill()
            for w in [w for w in workers if w.index is None] + [None] * (jobs - len(workers)):
                if not pending:
                    break
                fresh = w is None
                if w is None:
                    w = _Worker(ctx, run_unit)
                    workers.append(w)
                job = pending.popleft()
                try:
                    w.assign(*job)
                except OSError:  # (it died idle: the OOM killer) the unit goes to a new worker
                    if fresh:
                        raise
                    w.index = None
                    pending.appendleft(job)
                    workers.remove(w)
                    w.kill()
            busy = [w for w in workers if w.index is not None]
            wait_for([w.conn for w in busy] + [w.proc.sentinel for w in busy], timeout=TICK)
            now = time.monotonic()
            for w in busy:
                alive = drain(w)
                if w.index is None:
                    continue
                if not alive or not w.proc.is_alive():
                    drain(w)
                    if w.index is None:
                        continue
                    w.proc.join(1)
                    code, near = w.proc.exitcode, w.near_limit()
                    STATS["died"] += 1
                    fail(w, lambda p: _died(p, code, near))
                    continue
                watch(w, now)
    finally:
        for w in workers:
            w.kill()
    return results


def call(fn: Callable, *args, **kw):
    """``fn(*args, **kw)`` in one forked worker watched as :func:`run` watches its workers (the
    other commands that run under ``--memory``: ``--check --fix``).  Its result (sent back
    pickled); ``MemoryError`` when the worker ran out of memory (stuck at its limit and rescued
    or killed, or dead near it, or its own ``MemoryError``); ``RuntimeError`` when it failed
    otherwise (with its traceback) or died of something else."""
    import traceback
    ctx = mp.get_context("fork")
    rd, wr = ctx.Pipe(duplex=False)

    def work() -> None:
        import io
        import sys
        rd.close()
        # what it prints goes back with its result (the parent's streams may be a test's or
        # a pipe's objects, which a forked child's writes would not reach)
        sys.stdout, sys.stderr = io.StringIO(), io.StringIO()
        try:
            res = ("ok", fn(*args, **kw))
        except MemoryError:
            res = ("memory", None)
        except BaseException as exc:  # (the parent re-raises it; nothing escapes a forked child)
            res = ("memory", None) if budget.out_of_memory(exc) else ("error", traceback.format_exc())
        try:
            wr.send(res + (sys.stdout.getvalue(), sys.stderr.getvalue()))
        except MemoryError:
            wr.send(("memory", None, "", ""))

    proc = ctx.Process(target=work, daemon=True)
    proc.start()
    wr.close()
    STATS["workers"] += 1
    w = _Watched()
    w.proc = proc
    w.room0 = w.room = room_of(proc.pid)
    res = None
    try:
        while True:
            if rd.poll(TICK):
                try:
                    res = rd.recv()
                except (EOFError, OSError):
                    res = None
                break
            if not proc.is_alive():
                break
            if w.look(time.monotonic()):
                STATS["killed"] += 1
                proc.kill()
                raise MemoryError()
    finally:
        proc.join(5)
        if proc.is_alive():
            proc.kill()
            proc.join(5)
        rd.close()
    if res is None:  # died without an answer
        STATS["died"] += 1
        if w.near_limit():
            raise MemoryError()
        raise RuntimeError(f"the worker died (exit code {proc.exitcode})")
    kind, value, out, err = res
    import sys
    sys.stdout.write(out)
    sys.stderr.write(err)
    if kind == "memory":
        raise MemoryError()
    if kind == "error":
        raise RuntimeError(value)
    return value
