"""Exact projected model counting with pyganak (the fallback engine), with a time budget,
cancellation and a cache.

Small CNFs are counted in-process (a few milliseconds); bigger ones in a child process
(``python -m tvl_lsp.analysis.counting.projected``) that is killed on timeout or cancellation, so a request
never hangs the caller.  Results are cached by the logical content of the query: a hash of
the clauses, the projection and the assumptions -- the model's layout, comments and
whitespace do not enter it.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import threading
from collections import OrderedDict
from typing import Iterable, Optional, Sequence

from .clock import Budget
from .errors import CancelLike, CountCancelled, CountTimeout
from .errors import is_cancelled as _is_cancelled

# in-process below these sizes (pyganak cannot be interrupted inside a call)
INPROCESS_MAX_VARS = 600
INPROCESS_MAX_CLAUSES = 4000

class _LRU:
    def __init__(self, size: int = 4096):
        self.size = size
        self.data: OrderedDict[str, int] = OrderedDict()
        self.lock = threading.Lock()

    def get(self, key: str) -> Optional[int]:
        with self.lock:
            v = self.data.get(key)
            if v is not None:
                self.data.move_to_end(key)
            return v

    def put(self, key: str, value: int) -> None:
        with self.lock:
            self.data[key] = value
            self.data.move_to_end(key)
            while len(self.data) > self.size:
                self.data.popitem(last=False)


CACHE = _LRU()


def query_key(base_key: str, projection_all: bool, assumptions: Iterable[int],
              extra: Sequence[Sequence[int]] = ()) -> str:
    h = hashlib.sha256(base_key.encode())
    h.update(b"P" if projection_all else b"p")
    h.update((" ".join(map(str, sorted(set(assumptions))))).encode())
    for c in extra:
        h.update((" ".join(map(str, c)) + ";").encode())
    return h.hexdigest()


def _count_inprocess(nvars: int, clauses: Sequence[Sequence[int]], projection: Optional[Sequence[int]]) -> int:
    import pyganak
    from ..sat import BoundedSolver as Solver
    # pyganak writes "c o intermediate count: 0" on stdout for an unsatisfiable CNF; stdout is
    # the language server's channel, so settle that case with a SAT call first
    with Solver(name="minisat22", bootstrap_with=[c for c in clauses if c]) as s:
        if any(not c for c in clauses) or not s.solve():
            return 0
    c = pyganak.Counter()
    if nvars:
        c.new_vars(nvars)
    for cl in clauses:
        if not cl:
            return 0
        c.add_clause(cl)
    if projection is not None:
        if not projection:
            # nothing to count: 1 if satisfiable, 0 otherwise
            c.set_sampling_set([1])
            return 1 if c.count() > 0 else 0
        c.set_sampling_set(list(projection))
    return int(c.count())


def _dimacs(nvars: int, clauses: Iterable[Sequence[int]], projection: Optional[Sequence[int]]) -> bytes:
    parts = []
    cls = list(clauses)
    parts.append(f"p cnf {nvars} {len(cls)}\n")
    if projection is not None:
        parts.append("c p show " + " ".join(map(str, projection)) + " 0\n")
    for c in cls:
        parts.append(" ".join(map(str, c)) + " 0\n")
    return "".join(parts).encode()


def _count_subprocess(nvars, clauses, projection, timeout: Optional[float], cancel: CancelLike) -> int:
    data = _dimacs(nvars, clauses, projection)
    from ...base import children  # (its own process group; it dies with this process)
    proc = children.popen([sys.executable, "-m", "tvl_lsp.analysis.counting.projected"], stdin=subprocess.PIPE,
                          stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    out: list[bytes] = []

    def feed():
        try:
            proc.stdin.write(data)
            proc.stdin.close()
        except (BrokenPipeError, OSError):
            pass

    def read():
        try:
            out.append(proc.stdout.read())
        except (OSError, ValueError):
            pass

    tw = threading.Thread(target=feed, daemon=True)
    tr = threading.Thread(target=read, daemon=True)
    tw.start()
    tr.start()
    budget = Budget(proc.pid, timeout) if timeout is not None else None  # (see clock.py)
    try:
        while True:
            try:
                proc.wait(timeout=0.02)
                break
            except subprocess.TimeoutExpired:
                pass
            if _is_cancelled(cancel):
                raise CountCancelled()
            if budget is not None and budget.spent():
                raise CountTimeout(f"no answer within {timeout:g} s")
    finally:
        children.kill(proc)
    tr.join(5)
    text = (out[0] if out else b"").decode().strip()
    if proc.returncode != 0 or not text:
        raise RuntimeError(f"the counter failed (exit code {proc.returncode})")
    return int(text.split()[-1], 16)  # (hexadecimal: a count can have more digits than int() reads)


def simplify(nvars: int, clauses: Sequence[Sequence[int]], projection: Optional[Sequence[int]]):
    """Unit propagation, then renumbering of what is left to 1..k.

    Returns (k, clauses, projection or None for all) with the same projected count, or None
    when propagation finds a conflict (count 0).  Fixed variables are determined, so they
    leave both the clauses and the projection; a projected variable that no clause mentions
    any more stays (it doubles the count)."""
    value: dict[int, bool] = {}
    occ: dict[int, list[int]] = {}
    cls = [list(c) for c in clauses]
    queue = []
    for i, c in enumerate(cls):
        if not c:
            return None
        if len(c) == 1:
            queue.append(c[0])
        for x in c:
            occ.setdefault(x, []).append(i)
    sat = [False] * len(cls)
    while queue:
        x = queue.pop()
        v = abs(x)
        if v in value:
            if value[v] != (x > 0):
                return None
            continue
        value[v] = x > 0
        for i in occ.get(x, ()):
            sat[i] = True
        for i in occ.get(-x, ()):
            if sat[i]:
                continue
            rest = []
            for y in cls[i]:
                w = value.get(abs(y))
                if w is None:
                    rest.append(y)
                elif w == (y > 0):
                    sat[i] = True
                    break
            if sat[i]:
                continue
            if not rest:
                return None
            cls[i] = rest
            if len(rest) == 1:
                queue.append(rest[0])
    out = []
    used: set[int] = set()
    for i, c in enumerate(cls):
        if sat[i]:
            continue
        c = [y for y in c if abs(y) not in value]  # (every literal left is unassigned or false)
        if not c:
            return None
        out.append(c)
        used.update(abs(y) for y in c)
    proj = set(range(1, nvars + 1)) if projection is None else set(projection)
    proj -= set(value)
    keep = sorted(used | proj)
    ren = {v: i + 1 for i, v in enumerate(keep)}
    out = [[ren[abs(y)] if y > 0 else -ren[abs(y)] for y in c] for c in out]
    newproj = sorted(ren[v] for v in proj)
    return len(keep), out, (None if len(newproj) == len(keep) else newproj)


def count_cnf(nvars: int, clauses: Sequence[Sequence[int]], projection: Optional[Sequence[int]] = None,
              timeout: Optional[float] = None, cancel: CancelLike = None, key: Optional[str] = None,
              inprocess: Optional[bool] = None) -> int:
    """Number of assignments of ``projection`` (None: all variables) that extend to a model.

    Raises :class:`CountTimeout` / :class:`CountCancelled`."""
    if key is not None:
        got = CACHE.get(key)
        if got is not None:
            return got
    if _is_cancelled(cancel):
        raise CountCancelled()
    simple = simplify(nvars, clauses, projection)
    if simple is None:
        if key is not None:
            CACHE.put(key, 0)
        return 0
    nvars, clauses, projection = simple
    if nvars == 0:
        n = 1
        if key is not None:
            CACHE.put(key, n)
        return n
    if inprocess is None:
        inprocess = nvars <= INPROCESS_MAX_VARS and len(clauses) <= INPROCESS_MAX_CLAUSES
    if inprocess:
        n = _count_inprocess(nvars, clauses, projection)
    else:
        n = _count_subprocess(nvars, clauses, projection, timeout, cancel)
    if key is not None:
        CACHE.put(key, n)
    return n


def _worker_main() -> int:
    """Read a DIMACS CNF (``c p show ... 0`` for the projection) on stdin, print the count (in
    hexadecimal)."""
    from ...base.children import die_with_parent
    die_with_parent()
    nvars = 0
    clauses: list[list[int]] = []
    projection = None
    cur: list[int] = []
    for line in sys.stdin.buffer.read().decode().splitlines():
        if not line or line[0] == "c":
            if line.startswith("c p show"):
                projection = [int(x) for x in line.split()[3:] if x != "0"]
            continue
        if line[0] == "p":
            nvars = int(line.split()[2])
            continue
        for tok in line.split():
            x = int(tok)
            if x == 0:
                clauses.append(cur)
                cur = []
            else:
                cur.append(x)
    n = _count_inprocess(nvars, clauses, projection)
    sys.stdout.write(f"{n:x}\n")
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    code = _worker_main()
    sys.stdout.flush()
    os._exit(code)
