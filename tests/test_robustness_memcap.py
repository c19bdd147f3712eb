"""``--check --memory N``: a file whose check reaches the memory limit ends with
``analysis-budget-exceeded`` and the other files are checked -- never a hang or a crash.

At the limit itself two things happen that no code in the process recovers from (see
:mod:`tvl_lsp.project.supervise`): CPython 3.11 spins for ever when an allocation fails while
it unwinds an exception to a ``with`` handler past offset 256 of a function (``models.load``'s
``with lk:``: ``--check --memory 150 --budget 0`` of a big DIMACS model hung about one run in
six), and the C++ solvers abort.  :func:`grow` makes the first happen at will, at
``models.load``'s own ``with`` block; ``os.abort()`` stands for the second.  Every case runs in a
child process with a timeout (killed at its end), so a regression fails instead of hanging the
suite.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

# The parse of every model named big*.tvl grows a chain of tuples (that outlives it) until an
# allocation fails, inside a `with` block far enough into its function (past offset 256) for
# the interpreter to need a new int to unwind to it: at a bare limit CPython 3.11 spins there
# every time (like models.load's `with lk:` now and then).  Anything else is parsed as usual.
GROW_IN_WITH = ("def grow_in_with(cell):\n"
                + "    a = 1; b = 2; c = a + b; d = c * 2; e = d - 1; f = e + a; g = f * b; h = g - c\n" * 10
                + "    lk = threading.Lock()\n"
                  "    with lk:\n"
                  "        i = 1000\n"
                  "        while True:\n"
                  "            cell[0] = (cell[0], i)\n"
                  "            i += 1\n")
PRELUDE = textwrap.dedent('''
    import json, os, resource, sys, threading
    from tvl_lsp.analysis import formats
    from tvl_lsp.project import supervise
    real_parse = formats.parse_any_model
    KEPT = [None]
    exec(GROW_IN_WITH)

    def grow(text, path, **kw):
        if not os.path.basename(path).startswith("big"):
            return real_parse(text, path, **kw)
        grow_in_with(KEPT)
    formats.parse_any_model = grow
''').replace("exec(GROW_IN_WITH)", "exec(" + repr(GROW_IN_WITH) + ")")


def _run(code: str, timeout: float = 90) -> subprocess.CompletedProcess:
    """``code`` in a child (killed after ``timeout`` s, the test then fails), with a CPU limit."""
    import resource

    def limits():
        resource.setrlimit(resource.RLIMIT_CPU, (60, 60))
    try:
        return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                              preexec_fn=limits)
    except subprocess.TimeoutExpired as exc:  # (subprocess.run kills the child first)
        pytest.fail(f"hung: no answer in {timeout} s\n{(exc.stderr or b'')[-2000:]!r}")


def _workspace(tmp_path):
    (tmp_path / "big.tvl").write_text("root Big { group allOf { A, B } }\n")
    (tmp_path / "ok.tvl").write_text("root Ok { group allOf { C, lower } }\n")  # a naming warning
    return tmp_path


def test_a_check_that_hits_the_memory_limit_is_reported_and_the_rest_is_checked(tmp_path):
    """The --check command itself (cap_memory, its supervised workers): the spinning file gets the
    budget error, the other its warning, exit code 1.  Without the supervisor this hangs."""
    ws = _workspace(tmp_path)
    p = _run(PRELUDE + textwrap.dedent(f'''
        from tvl_lsp.main import main
        code = main(["--check", "--format", "json", "--memory", "64", "--budget", "0", "--jobs", "1", {str(ws)!r}])
        print(json.dumps({{"exit": code, "stats": supervise.STATS}}), file=sys.stderr)
    '''))
    assert p.returncode == 0, p.stderr[-3000:]
    got = json.loads(p.stderr.strip().splitlines()[-1])
    diags = json.loads(p.stdout[:p.stdout.rindex("]") + 1])
    assert got["exit"] == 1, (got, diags)
    codes = sorted((d["path"].rsplit("/", 1)[-1], d["code"]) for d in diags)
    assert codes == [("big.tvl", "analysis-budget-exceeded"), ("ok.tvl", "naming-convention")], codes
    big = next(d for d in diags if d["path"].endswith("big.tvl"))
    assert "more memory than it may use" in big["message"]
    if sys.version_info[:2] == (3, 11):  # the interpreter spun, and the supervisor got it out
        assert got["stats"]["rescued"] == 1 and got["stats"]["killed"] == 0, got


def test_a_worker_that_cannot_be_rescued_is_killed(tmp_path):
    """No room to raise the limit into (the hard limit is the soft one): the worker is killed
    after STUCK_SECONDS, its file gets the budget error, the next unit a fresh worker."""
    ws = _workspace(tmp_path)
    p = _run(PRELUDE + textwrap.dedent(f'''
        from tvl_lsp.project import budget, check
        supervise.raise_limit = lambda pid, n: False
        with budget.cap_memory(64 * 1024 * 1024):
            diags = check.check_paths([{str(ws)!r}], jobs=1, cpu_budget=0, supervise=True)
        print(json.dumps({{"codes": sorted((os.path.basename(d.path), d.code) for d in diags),
                          "messages": [d.message for d in diags], "stats": supervise.STATS}}))
    '''))
    assert p.returncode == 0, p.stderr[-3000:]
    got = json.loads(p.stdout)
    assert got["codes"] == [["big.tvl", "analysis-budget-exceeded"], ["ok.tvl", "naming-convention"]], got
    assert any("more memory than it may use" in m for m in got["messages"]), got
    if sys.version_info[:2] == (3, 11):
        assert got["stats"]["killed"] == 1 and got["stats"]["workers"] == 2, got


ABORTING = textwrap.dedent('''
    import json, os, resource, sys
    from tvl_lsp.analysis import formats
    from tvl_lsp.project import budget, check, supervise
    real_parse = formats.parse_any_model

    def parse(text, path, **kw):
        name = os.path.basename(path)
        if name.startswith("near"):   # a C library aborting at the memory limit (Glucose's OutOfMemoryException)
            room = resource.getrlimit(resource.RLIMIT_DATA)[0] - int(open("/proc/self/statm").read().split()[5]) * 4096
            hold = bytearray(max(0, room - 8 * 1024 * 1024))  # (touched: it is there for the supervisor to see)
            import time
            time.sleep(0.5)
            os.abort()
        if name.startswith("crash"):  # the same far from the limit: a bug
            os.abort()
        return real_parse(text, path, **kw)
    formats.parse_any_model = parse
''')


def test_a_worker_that_dies_is_reported_and_the_rest_is_checked(tmp_path):
    """A worker that dies near its memory limit: the budget error; far from it: an internal
    error that names the signal.  The other files are checked (by new workers)."""
    for name in ("near.tvl", "crash.tvl"):
        (tmp_path / name).write_text("root M { group allOf { A, B } }\n")
    (tmp_path / "ok.tvl").write_text("root Ok { group allOf { C, lower } }\n")
    p = _run(ABORTING + textwrap.dedent(f'''
        with budget.cap_memory(96 * 1024 * 1024):
            diags = check.check_paths([{str(tmp_path)!r}], jobs=2, cpu_budget=0, supervise=True)
        print(json.dumps({{"diags": sorted((os.path.basename(d.path), d.code, d.message) for d in diags),
                          "stats": supervise.STATS}}))
    '''))
    assert p.returncode == 0, p.stderr[-3000:]
    got = json.loads(p.stdout)
    codes = [d[:2] for d in got["diags"]]
    assert codes == [["crash.tvl", "internal-error"], ["near.tvl", "analysis-budget-exceeded"],
                     ["ok.tvl", "naming-convention"]], got
    assert "SIGABRT" in got["diags"][0][2] and "more memory than it may use" in got["diags"][1][2], got
    assert got["stats"]["died"] == 2, got


def test_no_worker_is_left_behind(tmp_path):
    for i in range(4):
        (tmp_path / f"m{i}.tvl").write_text(f"root M{i} {{ group allOf {{ A, lower }} }}\n")
    p = _run(textwrap.dedent(f'''
        import json, multiprocessing
        from tvl_lsp.project import check, supervise
        diags = check.check_paths([{str(tmp_path)!r}], jobs=2, cpu_budget=0, supervise=True)
        print(json.dumps({{"n": len(diags), "codes": sorted({{d.code for d in diags}}),
                          "children": len(multiprocessing.active_children()), "stats": supervise.STATS}}))
    '''))
    assert p.returncode == 0, p.stderr[-3000:]
    got = json.loads(p.stdout)
    assert got["n"] == 4 and got["codes"] == ["naming-convention"] and got["children"] == 0, got
    assert got["stats"]["workers"] == 2 and got["stats"]["died"] == 0, got


def test_the_systemerror_of_a_lost_memoryerror_is_the_memory_budget(monkeypatch):
    """Out of memory, CPython can fail to create the MemoryError and raise "SystemError: <f>
    returned NULL without setting an exception" instead (seen in --check --memory 240 of a big
    DIMACS model): at the memory limit that is the budget, not an internal error."""
    import resource
    from tvl_lsp.project import budget
    lost = SystemError("<function ModelAnalysis.encoding> returned NULL without setting an exception")
    limit = 1 << 30
    monkeypatch.setattr(resource, "getrlimit", lambda which: (limit, resource.RLIM_INFINITY))
    monkeypatch.setattr(budget, "_data_in_use", lambda: limit - 1024 * 1024)
    assert budget.out_of_memory(lost) and budget.out_of_memory(MemoryError())
    assert not budget.out_of_memory(SystemError("error return without exception set, elsewhere"))
    assert not budget.out_of_memory(ValueError("returned NULL without setting an exception"))
    monkeypatch.setattr(budget, "_data_in_use", lambda: limit // 2)  # far from the limit: a bug
    assert not budget.out_of_memory(lost)
    monkeypatch.setattr(resource, "getrlimit", lambda which: (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
    assert not budget.out_of_memory(lost)


def test_check_fix_at_the_memory_limit_ends_with_its_error(tmp_path):
    """``--check --fix`` runs the fixes under ``--memory`` too: a model whose analysis spins at the
    limit ends the command with the memory error (exit 2), not a hang; the worker that spun was
    rescued or killed by the watcher."""
    ws = _workspace(tmp_path)
    p = _run(PRELUDE + textwrap.dedent(f'''
        from tvl_lsp.main import main
        code = main(["--check", "--fix", "--memory", "64", "--budget", "0", {str(ws)!r}])
        print(json.dumps({{"exit": code, "stats": supervise.STATS}}), file=sys.stderr)
    '''))
    assert p.returncode == 0, p.stderr[-3000:]
    got = json.loads(p.stderr.strip().splitlines()[-1])
    assert got["exit"] == 2
    assert "needed more memory than --memory allows" in p.stderr
    assert got["stats"]["rescued"] + got["stats"]["killed"] >= 1
    assert "Traceback" not in p.stderr
