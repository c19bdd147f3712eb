"""Counting benchmark (issue #15): raw d4 and raw pyganak on the same CNF vs ``tvl-lsp count``,
per-feature counts, and a configurator click (a decision -> every feature's count).

    .venv/bin/python bench/bench_counting.py [--models DIR] [--pyganak-timeout S] [--only NAME]

``--models`` is the folder holding ``dimacs/<name>.dimacs`` (default: ``/work/shared/models``,
our machines' copy of the shared models; ``$TVL_LSP_MODELS`` overrides the default).  Every
figure is wall-clock time of a fresh process (what a user waits for), the minimum of ``--runs``
interleaved runs, except the click, which is measured in one process after compilation (what
the configurator does: a decision, then every feature's count under all decisions so far).  "cold" runs use an
empty disk cache, "warm" ones the cache the cold run filled.  Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

DEFAULT_MODELS = os.environ.get("TVL_LSP_MODELS", "/work/shared/models")
NAMES = ["automotive01", "ecos-i386pc", "busybox-1.18.0", "automotive2_1"]
REPO = Path(__file__).resolve().parents[1]
PY = sys.executable
TVL = str(Path(PY).with_name("tvl-lsp"))

RAW_D4 = r"""
import os, sys, time
import py_d4
saved = os.dup(1); os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
t = time.perf_counter()
n = py_d4.Solver(sys.argv[1]).count().getIntResult()
dt = time.perf_counter() - t
os.dup2(saved, 1)
print(n); print(dt)
"""

RAW_GANAK = r"""
import os, sys, time
import pyganak
from tvl_lsp.analysis.dimacs import parse_dimacs
nv, cls, _, _ = parse_dimacs(open(sys.argv[1]).read())
c = pyganak.Counter(); c.new_vars(nv); c.add_clauses(cls)
saved = os.dup(1); os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
t = time.perf_counter()
n = c.count()
dt = time.perf_counter() - t
os.dup2(saved, 1)
print(n); print(dt)
"""


def run(cmd, timeout, env=None):
    t = time.perf_counter()
    try:
        p = subprocess.run(["nice", "-n", "5"] + cmd, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return None, timeout, ""
    return p, time.perf_counter() - t, p.stdout


def fresh_env(cache):
    env = dict(os.environ)
    env["TVL_LSP_CACHE_DIR"] = cache
    return env


def click_bench(path, cache, decisions=20, seed=1):
    """In this process: compile (or load) once, then time decision -> all per-feature counts."""
    os.environ["TVL_LSP_CACHE_DIR"] = cache
    from tvl_lsp.analysis.counting import CNFCounter
    from tvl_lsp.analysis.dimacs import parse_dimacs
    nv, cls, _, _ = parse_dimacs(Path(path).read_text())
    svc = CNFCounter(nv, cls, nv)
    t = time.perf_counter()
    svc.circuit()
    load = time.perf_counter() - t
    t = time.perf_counter()
    base = svc.feature_counts()
    first = time.perf_counter() - t
    rng = random.Random(seed)
    open_vars = [v for v in range(1, nv + 1) if 0 < base.counts[v] < base.total]
    times = []
    lits: list[int] = []
    for _ in range(decisions):
        v = rng.choice(open_vars)
        lit = v if rng.random() < 0.5 else -v
        t = time.perf_counter()
        r = svc.feature_counts(lits + [lit])
        times.append(time.perf_counter() - t)
        if r.total:
            lits.append(lit)  # a click keeps the earlier decisions
    # spot checks: per-feature counts equal --include counts
    for v in rng.sample(open_vars, min(10, len(open_vars))):
        assert base.counts[v] == svc.count([v]).value, v
    return load, first, times


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default=DEFAULT_MODELS, help=f"models folder (default {DEFAULT_MODELS})")
    ap.add_argument("--pyganak-timeout", type=float, default=120.0)
    ap.add_argument("--timeout", type=float, default=300.0, help="per d4 / tvl-lsp run")
    ap.add_argument("--only", action="append", help="only these models (repeatable)")
    ap.add_argument("--runs", type=int, default=3, help="runs of each measurement, interleaved; the minimum is "
                                                       "reported (the machine is shared: the minimum is the "
                                                       "least disturbed run)")
    args = ap.parse_args(argv)
    folder = Path(args.models) / "dimacs"
    if not folder.is_dir():
        print(f"bench_counting: no models at {folder} (pass --models DIR); nothing measured")
        return 0
    rows = []
    for name in args.only or NAMES:
        path = folder / f"{name}.dimacs"
        if not path.exists():
            print(f"bench_counting: {path} missing; skipped", file=sys.stderr)
            continue
        row = {"model": name}
        best: dict[str, float] = {}
        d4n = gn = n = None
        pf = None
        click = None

        def keep(key, dt):
            best[key] = min(best.get(key, dt), dt)
        for _ in range(args.runs):
            p, dt, out = run([PY, "-c", RAW_D4, str(path)], args.timeout)
            if p is not None and p.returncode == 0:
                d4n = int(out.split()[0])
                keep("d4", dt)
            if gn is None and "pyganak" not in best:
                p, dt, out = run([PY, "-c", RAW_GANAK, str(path)], args.pyganak_timeout)
                if p is not None and p.returncode == 0:
                    gn = int(out.split()[0])
                    keep("pyganak", dt)
                else:
                    best["pyganak"] = float("inf")
            with tempfile.TemporaryDirectory() as cache:
                env = fresh_env(cache)
                p, dt, out = run([TVL, "count", str(path), "--json"], args.timeout, env)
                if p is not None and p.returncode == 0:
                    data = json.loads(out)
                    n = data["count"]
                    row["engine"] = data["engine"]
                    keep("count cold", dt)
                p, dt, out = run([TVL, "count", str(path), "--json"], args.timeout, env)
                if p is not None and p.returncode == 0:
                    keep("count warm", dt)
            with tempfile.TemporaryDirectory() as cache:
                env = fresh_env(cache)
                p, dt, out = run([TVL, "count", str(path), "--per-feature", "--json"], args.timeout, env)
                if p is not None and p.returncode == 0:
                    pf = json.loads(out)
                    keep("per-feature cold", dt)
                p, dt, out = run([TVL, "count", str(path), "--per-feature", "--json"], args.timeout, env)
                if p is not None and p.returncode == 0:
                    keep("per-feature warm", dt)
                if click is None:
                    click = click_bench(str(path), cache)
        for key in ("d4", "pyganak", "count cold", "count warm", "per-feature cold", "per-feature warm"):
            v = best.get(key)
            limit = args.pyganak_timeout if key == "pyganak" else args.timeout
            row[key] = f"{v:.2f} s" if v is not None and v != float("inf") else f"no answer in {limit:g} s"
        if "d4" in best and "count cold" in best:
            row["cold / d4"] = f"{best['count cold'] / best['d4']:.2f}"
        if "count cold" in best and "per-feature cold" in best:
            row["per-feature / count"] = f"{best['per-feature cold'] / best['count cold']:.2f}"
        load, first, times = click
        row["click (median / max)"] = f"{statistics.median(times) * 1000:.0f} / {max(times) * 1000:.0f} ms"
        row["load circuit"] = f"{load:.2f} s"
        same = n is not None and (d4n is None or n == d4n) and (gn is None or n == gn) and \
            pf is not None and pf["count"] == n
        row["digits"] = str(len(str(n))) if n is not None else "-"
        row["agree"] = "yes" if same else "NO"
        rows.append(row)
        print(json.dumps(row), file=sys.stderr, flush=True)
    if not rows:
        return 0
    cols = list(rows[0])
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        print("| " + " | ".join(r.get(c, "") for c in cols) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
