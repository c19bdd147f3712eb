"""Benchmark the variability-aware computation graph (``tvl-lsp graph``) on a workspace.

    .venv/bin/python bench/bench_graph.py --workspace ../shared/corpus/thesis/ws [--launch FILE] [--runs N]

Picks the largest launch file of the workspace that a model configures (or ``--launch``), then
measures, ``--runs`` times each:

- the real command line in a fresh process (``tvl-lsp graph FILE --format dot`` and
  ``--format json --count``): wall-clock and CPU time (imports included);
- in process, cold caches: pairing, model parse, symbolic load, hints, graph, projection with
  counts, JSON + DOT, and the graph checks.

Goal: under 1 s for the largest thesis launch file.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _fmt(xs: list[float]) -> str:
    return f"min {min(xs) * 1000:7.1f} ms  median {statistics.median(xs) * 1000:7.1f} ms  max {max(xs) * 1000:7.1f} ms"


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workspace", required=True, help="a workspace folder (e.g. ../shared/corpus/thesis/ws)")
    ap.add_argument("--launch", help="the launch file (default: the largest one a model configures)")
    ap.add_argument("--runs", type=int, default=5)
    ns = ap.parse_args()
    if not os.path.isdir(ns.workspace):
        print(f"bench_graph.py: no workspace at {ns.workspace} (the thesis's is in the team's shared corpus, "
              "../shared/corpus/thesis/ws); pass --workspace DIR, e.g. examples/ws", file=sys.stderr)
        return 2
    sys.path.insert(0, str(ROOT))
    from tvl_lsp.project.workspace import load_workspace

    ws = load_workspace([ns.workspace])
    if ns.launch:
        launch = os.path.abspath(ns.launch)
    else:
        paired = [lf for lf in ws.files.launches if any(p.model for p in ws.pair(lf)[0])]
        if not paired:
            print(f"no launch file of {ns.workspace} is paired with a model", file=sys.stderr)
            return 2
        launch = max(paired, key=lambda p: (os.path.getsize(p), p))
    print(f"launch file: {launch} ({sum(1 for _ in open(launch))} lines); {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.1f}")

    for fmt in (["--format", "dot"], ["--format", "json", "--count"]):
        walls, cpus = [], []
        for _ in range(ns.runs):
            c0 = _cpu_children()
            t = time.perf_counter()
            r = subprocess.run([sys.executable, "-m", "tvl_lsp", "graph", launch, *fmt], capture_output=True,
                               text=True, cwd=str(ROOT))
            walls.append(time.perf_counter() - t)
            cpus.append(_cpu_children() - c0)
            if r.returncode != 0:
                print(r.stderr, file=sys.stderr)
                return 2
        print(f"CLI {' '.join(fmt):24} wall {_fmt(walls)}")
        print(f"{'':28} CPU  {_fmt(cpus)}")

    from tvl_lsp.analysis.counting.projected import CACHE
    from tvl_lsp.analysis.counting.service import MEMORY
    from tvl_lsp.graph import to_dot, to_json
    from tvl_lsp.project.graph import load_graph
    steps: dict[str, list[float]] = {}
    sizes = None
    for _ in range(ns.runs):
        CACHE.data.clear()
        MEMORY.clear()
        t0 = time.perf_counter()
        ctx = load_graph(launch)
        t1 = time.perf_counter()
        g = ctx.project(count=True)
        t2 = time.perf_counter()
        to_json(g)
        to_dot(g)
        t3 = time.perf_counter()
        diags = ctx.diagnostics()
        t4 = time.perf_counter()
        ctx.close()
        for k, v in (("load (pair, model, launch, hints, graph)", t1 - t0), ("projection with counts", t2 - t1),
                     ("JSON + DOT", t3 - t2), ("checks", t4 - t3), ("total", t4 - t0)):
            steps.setdefault(k, []).append(v)
        sizes = (len(g.nodes), len(g.topics()), len(g.services()), len(g.parameters()), len(g.links), len(diags),
                 g.products)
    print("in process (cold caches): nodes %d, topics %d, services %d, parameters %d, links %d, findings %d, "
          "products %s" % sizes)
    for k, v in steps.items():
        print(f"  {k:42} {_fmt(v)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
