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
one JSON line (``{"ok": true, "seconds": ..., "nodes": ..., "edges": ..., "count": "..."}``) on its stdout.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
from typing import Callable, Optional, Sequence

from .clock import Budget
from .errors import CancelLike, CountCancelled, CountTimeout, EngineFailed, is_cancelled

Progress = Optional[Callable[[str], None]]

_FD_LOCK = threading.Lock()


def dimacs_bytes(nvars: int, clauses: Sequence[Sequence[int]]) -> bytes:
    parts = [f"p cnf {nvars} {len(clauses)}\n"]
    for c in clauses:
        parts.append(" ".join(map(str, c)) + " 0\n")
    return "".join(parts).encode()


def _d4_options(options: Optional[dict]):
    if not options:
        return None
    import py_d4
    return py_d4.load_options_from_dict(options)


def compile_inprocess(nvars: int, clauses: Sequence[Sequence[int]], options: Optional[dict] = None,
                      interruptible: bool = False) -> tuple[str, int]:
    """(NNF text, model count over variables 1..nvars) of the CNF (d4 in this process; fd 1
    silenced meanwhile).  ``interruptible`` (main thread of a command-line process only): Ctrl-C
    ends the process during the compilation (d4 does not return to Python to see it)."""
    if nvars == 0:  # d4 dies of a floating point exception on a CNF without variables
        return _no_vars(clauses)
    import py_d4
    import signal
    old = None
    if interruptible and threading.current_thread() is threading.main_thread():
        old = signal.signal(signal.SIGINT, signal.SIG_DFL)
    try:
        return _compile_inprocess(py_d4, nvars, clauses, options)
    finally:
        if old is not None:
            signal.signal(signal.SIGINT, old)


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
            s = py_d4.Solver([list(c) for c in clauses], nvars) if cfg is None else \
                py_d4.Solver([list(c) for c in clauses], nvars, cfg)
            r = s.compile()
            return r.getNNFString(), int(r.count([]))
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
    if nvars == 0:  # d4 dies of a floating point exception on a CNF without variables
        text, count = _no_vars(clauses)
        with open(out_path, "w") as fh:
            fh.write(text)
        return {"ok": True, "seconds": 0.0, "nodes": 1, "edges": 0, "count": count}
    cnf_path = out_path + ".cnf"
    with open(cnf_path, "wb") as fh:
        fh.write(dimacs_bytes(nvars, clauses))
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

    def pre():
        if nice:
            try:
                os.nice(nice)
            except OSError:
                pass

    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=pre if (nice and os.name == "posix") else None)
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
        if proc.poll() is None:
            proc.kill()
            proc.wait()
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
        why = (report or {}).get("error") or (err[0] if err else b"").decode(errors="replace").strip()[-300:]
        raise EngineFailed(f"d4 failed (exit code {proc.returncode}): {why or 'no output'}")
    report["count"] = int(report["count"])
    return report


def compile_file(cnf_path: str, out_path: str, timeout: Optional[float] = None, cancel: CancelLike = None,
                 progress: Progress = None, options: Optional[dict] = None, nice: int = 0) -> dict:
    """Compile a DIMACS file (d4 reads it itself) in a child process; see :func:`compile_cnf`."""
    return _run_child(cnf_path, out_path, timeout, cancel, progress, options, nice)


def _die_with_parent() -> None:
    """Linux: this compilation ends when the process that asked for it dies (a worker process
    of the language server killed with SIGKILL leaves no d4 running)."""
    parent = os.getppid()
    try:
        import ctypes
        import signal
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except Exception:  # noqa: BLE001 (elsewhere: the parent's kill on cancel still ends it)
        return
    if parent == 1 or os.getppid() != parent:
        os._exit(1)


def _worker_main(argv: list[str]) -> int:
    cnf_path, out_path = argv[0], argv[1]
    options = json.loads(argv[2]) if len(argv) > 2 else None
    _die_with_parent()
    # d4 prints statistics on fd 1: keep our report channel apart and send d4's chatter away
    report_fd = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    report = os.fdopen(report_fd, "w")
    try:
        import py_d4
        t0 = time.perf_counter()
        cfg = _d4_options(options)
        s = py_d4.Solver(cnf_path) if cfg is None else py_d4.Solver(cnf_path, cfg)
        r = s.compile()
        nnf = r.getNNFString()
        tmp = f"{out_path}.{os.getpid()}.tmp"
        with open(tmp, "w") as fh:
            fh.write(nnf)
        os.replace(tmp, out_path)
        count = str(r.count([]))  # a decimal string: the count can have thousands of digits
        report.write(json.dumps({"ok": True, "seconds": time.perf_counter() - t0, "nodes": r.getNbNodes(),
                                 "edges": r.getNbEdges(), "count": count}) + "\n")
        report.flush()
        return 0
    except Exception as e:  # reported to the parent, which falls back on another engine
        report.write(json.dumps({"ok": False, "error": f"{type(e).__name__}: {e}"}) + "\n")
        report.flush()
        return 1


if __name__ == "__main__":
    sys.exit(_worker_main(sys.argv[1:]))
