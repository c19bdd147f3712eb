"""Compiling a CNF into a d-DNNF with d4 (PyPI ``d4solver``, module ``py_d4``).

d4 cannot be interrupted inside a call and prints ``c ...`` statistics on file descriptor 1
(the language server's channel), so:

- :func:`compile_cnf` runs it in a child process (``python -m tvl_lsp.analysis.counting.d4``)
  whose stdout is a pipe we read nothing from but the result line; the parent polls, reports
  progress, and kills the child on timeout or cancellation;
- :func:`compile_inprocess` (small CNFs only, where spawning a process would cost more than
  the compilation) points fd 1 at ``/dev/null`` for the duration of the call, under a lock.
  Never call it from a process whose fd 1 another thread is writing to (the language
  server's main process): the server counts in its worker processes.

The child reads the CNF from a DIMACS file (d4's own reader), writes the NNF to the path it is given and prints
one JSON line (``{"ok": true, "seconds": ..., "nodes": ..., "edges": ..., "count": "...", "nnf": [size,
sha256]}``) on its stdout.

Memory: d4 reserves address space up front -- about 1.8 GB it always needs, plus its cache's
first page (4 GB by default): ~6 GB for a two-variable formula.  Under a limit on address space
or data (``ulimit -v``, ``RLIMIT_DATA``: the check budget) an allocation d4 cannot make ends in a
``std::bad_alloc`` or a segmentation fault.  So (:func:`memory_plan`): with no limit d4 runs as
before; under a limit it never runs in the calling process -- the child raises its own soft
limits to the hard ones (its limits are its own, not the caller's budget), sizes the cache's
pages to the room left, and a crash is an :class:`EngineFailed` (the service then counts with
pyganak); when even the hard limit leaves d4 no room, it is not started and the reason says
so ("d4 needs about 2.1 GB of address space; this process may use 1.0 GB (ulimit -v)").

The child dies with its parent (:mod:`tvl_lsp.base.children`: its own process group,
``PR_SET_PDEATHSIG``); the parent kills its group on timeout or cancellation.
"""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import threading
import time
from typing import Callable, Optional, Sequence

from .clock import Budget
from .errors import CancelLike, CountCancelled, CountTimeout, EngineFailed, is_cancelled

Progress = Optional[Callable[[str], None]]

_FD_LOCK = threading.Lock()

MB = 1024 * 1024
D4_FIXED = 1800 * MB       # address space d4 reserves whatever the cache's size (measured: 1.8 GB)
D4_MARGIN = 256 * MB       # for the formula, the circuit and the interpreter around it
D4_DEFAULT_PAGE = 4096 * MB  # d4's cache: its first page by default
D4_MIN_PAGE = 16 * MB


def address_limit(hard: bool = False) -> Optional[int]:
    """The smaller of this process's address-space and data limits (soft, or ``hard``), in
    bytes; None when there is none."""
    try:
        import resource
    except ImportError:
        return None
    out = None
    for which in ("RLIMIT_AS", "RLIMIT_DATA"):
        r = getattr(resource, which, None)
        if r is None:
            continue
        try:
            v = resource.getrlimit(r)[1 if hard else 0]
        except (OSError, ValueError):
            continue
        if v != resource.RLIM_INFINITY and v >= 0:
            out = v if out is None else min(out, v)
    return out


def _in_use() -> int:
    """This process's address space now (bytes)."""
    try:
        from ...base.files import read_head
        raw = read_head("/proc/self/statm", 256)
        return int((raw or b"0").split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, IndexError, OSError):
        return 0


def _gb(n: int) -> str:
    return f"{n / (1024 * MB):.1f} GB"


def memory_plan(limit: Optional[int], in_use: int) -> Optional[dict]:
    """d4's cache options for a process that may use ``limit`` bytes of address space (None:
    no limit) and uses ``in_use`` now: None for d4's defaults, else smaller pages.  Raises
    EngineFailed when d4 has no room at all."""
    if limit is None:
        return None
    room = limit - in_use - D4_FIXED - D4_MARGIN
    if room >= D4_DEFAULT_PAGE + D4_DEFAULT_PAGE // 8:
        return None
    if room < D4_MIN_PAGE:
        raise EngineFailed(f"d4 needs about {_gb(D4_FIXED + D4_MARGIN + D4_MIN_PAGE + in_use)} of address space; "
                           f"this process may use {_gb(limit)} (ulimit -v / the memory budget)")
    first = max(D4_MIN_PAGE, min(D4_DEFAULT_PAGE, room // 2))
    return {"cache": {"bucket": {"sizeFirstPage": str(first), "sizeAdditionalPage": str(max(MB, first // 8))}}}


def inprocess_plan(tiny: bool = False) -> tuple[bool, Optional[dict]]:
    """May d4 run in this process, and with which cache options?  With room for its defaults
    (no limit, or a generous one): yes.  Under a tighter limit only a ``tiny`` CNF (its cache
    never outgrows a small first page), with pages sized to the room; otherwise no: a failed
    allocation inside d4 is a crash, not an exception (a child process is used)."""
    limit = address_limit()
    if limit is None:
        return True, None
    try:
        plan = memory_plan(limit, _in_use())
    except EngineFailed:
        return False, None
    return (True, None) if plan is None else (tiny, plan if tiny else None)


def inprocess_ok(tiny: bool = False) -> bool:
    return inprocess_plan(tiny)[0]


def check_room() -> None:
    """Raise EngineFailed, with the reason, when not even a child process (which raises its
    soft limits to the hard ones) has room for d4."""
    limit = address_limit(hard=True)
    if limit is not None:
        memory_plan(limit, 64 * MB)


def _merge(options: Optional[dict], extra: Optional[dict]) -> Optional[dict]:
    if not extra:
        return options
    out = json.loads(json.dumps(options or {}))
    for k, v in extra.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = _merge(out[k], v)
        else:
            out[k] = v
    return out


def dimacs_bytes(nvars: int, clauses: Sequence[Sequence[int]]) -> bytes:
    parts = [f"p cnf {nvars} {len(clauses)}\n"]
    for c in clauses:
        parts.append(" ".join(map(str, c)) + " 0\n")
    return "".join(parts).encode()


def decimal_int(value) -> int:
    """d4's count (a decimal string) as an int, however many digits it has."""
    from ...base.bignum import parse_decimal
    return value if isinstance(value, int) else parse_decimal(str(value))


def _d4_options(options: Optional[dict]):
    if not options:
        return None
    import py_d4
    return py_d4.load_options_from_dict(options)


def _raise_own_limits() -> None:
    """A child's limits are its own: its soft address-space and data limits go up to the hard
    ones (the caller's budget, e.g. ``--check``'s, was for the caller's work)."""
    try:
        import resource
    except ImportError:
        return
    for which in ("RLIMIT_AS", "RLIMIT_DATA"):
        r = getattr(resource, which, None)
        if r is None:
            continue
        try:
            soft, hard = resource.getrlimit(r)
            if soft != hard:
                resource.setrlimit(r, (hard, hard))
        except (OSError, ValueError):
            pass


def compile_inprocess(nvars: int, clauses: Sequence[Sequence[int]], options: Optional[dict] = None,
                      interruptible: bool = False, tiny: bool = False) -> tuple[str, int]:
    """(NNF text, model count over variables 1..nvars) of the CNF (d4 in this process; fd 1
    silenced meanwhile).  ``interruptible`` (main thread of a command-line process only): Ctrl-C
    ends the process during the compilation (d4 does not return to Python to see it)."""
    if nvars == 0:  # d4 dies of a floating point exception on a CNF without variables
        return _no_vars(clauses)
    ok, plan = inprocess_plan(tiny)
    if not ok:
        raise EngineFailed("d4 does not run in a process with a tight memory limit (use a child process)")
    options = _merge(options, plan)
    import py_d4
    import signal
    old = None
    if threading.current_thread() is threading.main_thread():
        # SIGTERM (and, ``interruptible``, Ctrl-C) ends the process during the compilation: d4
        # does not return to Python for a handler to run (and there is nothing to clean up)
        old = (signal.signal(signal.SIGINT, signal.SIG_DFL) if interruptible else None,
               signal.signal(signal.SIGTERM, signal.SIG_DFL))
    try:
        return _compile_inprocess(py_d4, nvars, clauses, options)
    finally:
        if old is not None:
            if old[0] is not None:
                signal.signal(signal.SIGINT, old[0])
            signal.signal(signal.SIGTERM, old[1])


def _no_vars(clauses) -> tuple[str, int]:
    """The d-DNNF of a CNF over no variable: true (one model, the empty one) unless a clause
    is empty."""
    return ("f 1 0\n", 0) if any(not c for c in clauses) else ("t 1 0\n", 1)


def _compile_inprocess(py_d4, nvars, clauses, options) -> tuple[str, int]:
    with _FD_LOCK:
        sys.stdout.flush()
        saved = os.dup(1)
        devnull = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(devnull, 1)
            cfg = _d4_options(options)
            if type(clauses) is not list or not all(type(c) is list for c in clauses):
                clauses = [list(c) for c in clauses]  # (py_d4 takes lists of lists)
            s = py_d4.Solver(clauses, nvars) if cfg is None else py_d4.Solver(clauses, nvars, cfg)
            try:
                r = s.compile()
                return r.getNNFString(), decimal_int(r.count([]))
            except MemoryError as e:  # (std::bad_alloc)
                raise EngineFailed(f"d4 ran out of memory ({e})") from None
            finally:
                del s
        finally:
            os.dup2(saved, 1)
            os.close(saved)
            os.close(devnull)


def compile_cnf(nvars: int, clauses: Sequence[Sequence[int]], out_path: str, timeout: Optional[float] = None,
                cancel: CancelLike = None, progress: Progress = None, options: Optional[dict] = None,
                nice: int = 0) -> dict:
    """Compile in a child process; the NNF lands in ``out_path``.  Returns the child's report
    (its ``count`` is the model count over variables 1..nvars, as an int).
    Raises CountTimeout / CountCancelled / EngineFailed."""
    from ...base.safewrite import write_file
    if nvars == 0:  # d4 dies of a floating point exception on a CNF without variables
        text, count = _no_vars(clauses)
        data = text.encode()
        write_file(out_path, data, replace=True)
        return {"ok": True, "seconds": 0.0, "nodes": 1, "edges": 0, "count": count,
                "nnf": [len(data), hashlib.sha256(data).hexdigest()]}
    check_room()
    cnf_path = out_path + ".cnf"
    write_file(cnf_path, dimacs_bytes(nvars, clauses), replace=True)
    try:
        return _run_child(cnf_path, out_path, timeout, cancel, progress, options, nice)
    finally:
        try:
            os.unlink(cnf_path)
        except OSError:
            pass


def _run_child(cnf_path: str, out_path: str, timeout, cancel, progress, options, nice) -> dict:
    cmd = [sys.executable, "-m", "tvl_lsp.analysis.counting.d4", cnf_path, out_path]
    if options:
        cmd.append(json.dumps(options))

    from ...base import children
    proc = children.popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if nice:
        try:
            os.setpriority(os.PRIO_PROCESS, proc.pid, min(19, os.getpriority(os.PRIO_PROCESS, 0) + nice))
        except (OSError, AttributeError):
            pass
    out: list[bytes] = []
    err: list[bytes] = []

    def read(stream, into):
        try:
            into.append(stream.read())
        except (OSError, ValueError):
            pass

    threads = [threading.Thread(target=read, args=(proc.stdout, out), daemon=True),
               threading.Thread(target=read, args=(proc.stderr, err), daemon=True)]
    for t in threads:
        t.start()
    start = time.monotonic()
    last_report = start
    budget = Budget(proc.pid, timeout, start) if timeout is not None else None  # (see clock.py)
    try:
        while True:
            try:
                proc.wait(timeout=0.01)
                break
            except subprocess.TimeoutExpired:
                pass
            now = time.monotonic()
            if is_cancelled(cancel):
                raise CountCancelled()
            if budget is not None and budget.spent():
                raise CountTimeout(f"d4 gave no answer within {timeout:g} s")
            if progress is not None and now - last_report >= 1.0:
                last_report = now
                progress(f"compiling with d4: {now - start:.0f} s")
    finally:
        children.kill(proc)  # (its process group; a no-op once it has ended)
        for t in threads:
            t.join(5)
    text = (out[0] if out else b"").decode(errors="replace")
    report = None
    for line in reversed(text.splitlines()):
        if line.startswith("{"):
            try:
                report = json.loads(line)
            except ValueError:
                pass
            break
    if proc.returncode != 0 or not report or not report.get("ok"):
        why = (report or {}).get("error") or _last_line((err[0] if err else b"").decode(errors="replace"))
        if proc.returncode is not None and proc.returncode < 0:
            try:
                name = signal.Signals(-proc.returncode).name
            except ValueError:
                name = f"signal {-proc.returncode}"
            what = f"d4 crashed ({name})" + (": it may have run out of memory" if address_limit(True) else "")
        else:
            what = f"d4 failed (exit code {proc.returncode})"
        raise EngineFailed(f"{what}: {why}" if why else what)
    try:
        report["count"] = int(report["count"], 16)
    except (KeyError, TypeError, ValueError):
        raise EngineFailed("d4's child process gave no count") from None
    return report


def _last_line(text: str) -> str:
    """The last meaningful line of a child's stderr (a Python traceback's last line), short."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1][-300:] if lines else ""


def compile_file(cnf_path: str, out_path: str, timeout: Optional[float] = None, cancel: CancelLike = None,
                 progress: Progress = None, options: Optional[dict] = None, nice: int = 0) -> dict:
    """Compile a DIMACS file (d4 reads it itself) in a child process; see :func:`compile_cnf`."""
    return _run_child(cnf_path, out_path, timeout, cancel, progress, options, nice)


def _worker_main(argv: list[str]) -> int:
    from ...base.children import die_with_parent
    die_with_parent()
    cnf_path, out_path = argv[0], argv[1]
    options = json.loads(argv[2]) if len(argv) > 2 else None
    # d4 prints statistics on fd 1: keep our report channel apart and send d4's chatter away
    report_fd = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    report = os.fdopen(report_fd, "w")
    try:
        _raise_own_limits()
        options = _merge(options, memory_plan(address_limit(), _in_use()))
        import py_d4
        from ...base.safewrite import write_file
        t0 = time.perf_counter()
        cfg = _d4_options(options)
        s = py_d4.Solver(cnf_path) if cfg is None else py_d4.Solver(cnf_path, cfg)
        r = s.compile()
        nnf = r.getNNFString().encode("ascii", errors="replace")
        write_file(out_path, nnf, replace=True)  # (atomic: a temporary file renamed into place)
        count = format(decimal_int(r.count([])), "x")  # hexadecimal: the count can have thousands of digits
        report.write(json.dumps({"ok": True, "seconds": time.perf_counter() - t0, "nodes": r.getNbNodes(),
                                 "edges": r.getNbEdges(), "count": count,
                                 "nnf": [len(nnf), hashlib.sha256(nnf).hexdigest()]}) + "\n")
        report.flush()
        return 0
    except MemoryError as e:  # std::bad_alloc
        report.write(json.dumps({"ok": False, "error": f"d4 ran out of memory ({e})"}) + "\n")
    except Exception as e:  # reported to the parent, which falls back on another engine
        report.write(json.dumps({"ok": False, "error": f"{type(e).__name__}: {e}"}) + "\n")
    report.flush()
    return 1


if __name__ == "__main__":
    code = _worker_main(sys.argv[1:])
    sys.stdout.flush()
    os._exit(code)  # (no interpreter teardown: nothing is left to save)
