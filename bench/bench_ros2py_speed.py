#!/usr/bin/env python3
"""``--check`` of Python launch files against the same number of XML launch files (issue #25: within
2x the time).

    .venv/bin/python bench/bench_ros2py_speed.py --py DIR [DIR ...] --xml DIR [DIR ...] [-n 200] [--repeat 3]

Takes ``n`` ``.launch.py`` / ``*_launch.py`` files under the ``--py`` folders and ``n``
``.launch.xml`` files under the ``--xml`` folders (evenly spread over the sorted lists), and runs
``check_paths`` on each set (one process, one job, a fresh process per run), ``repeat`` times;
prints the CPU seconds of each run (``resource.getrusage``: the machine is shared) and the ratio
of the medians.  The folders are real repositories (fetched, never committed).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, resource, sys
sys.path.insert(0, %r)
from tvl_lsp.project.check import check_paths
files = json.loads(sys.argv[1])
r0 = resource.getrusage(resource.RUSAGE_SELF)
diags = check_paths(files, jobs=1)
r1 = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps({"cpu": (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), "diagnostics": len(diags),
                  "maxrss_mb": r1.ru_maxrss / 1024}))
"""


def collect(dirs: list[str], suffixes: tuple, n: int) -> list[str]:
    out = []
    for d in dirs:
        for base, dn, fn in os.walk(d):
            dn[:] = sorted(x for x in dn if not x.startswith(".") and x not in ("build", "install", "log"))
            out += [os.path.join(base, f) for f in sorted(fn) if f.endswith(suffixes)]
    out.sort()
    if len(out) <= n:
        return out
    step = len(out) / n
    return [out[int(i * step)] for i in range(n)]


def run(files: list[str]) -> dict:
    p = subprocess.run([sys.executable, "-c", CHILD % str(ROOT), json.dumps(files)], capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(p.stderr)
    return json.loads(p.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--py", nargs="+", required=True)
    ap.add_argument("--xml", nargs="+", required=True)
    ap.add_argument("-n", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=3)
    ns = ap.parse_args(argv)
    py = collect(ns.py, (".launch.py", "_launch.py"), ns.n)
    xml = collect(ns.xml, (".launch.xml",), ns.n)
    print(f"{len(py)} Python launch files, {len(xml)} XML launch files; load: {os.getloadavg()}")
    res: dict[str, list[float]] = {"py": [], "xml": []}
    for i in range(ns.repeat):
        for kind, files in (("xml", xml), ("py", py)):
            r = run(files)
            res[kind].append(r["cpu"])
            print(f"  run {i + 1} {kind:3}: {r['cpu']:6.2f} s CPU, {r['diagnostics']} diagnostics, "
                  f"{r['maxrss_mb']:.0f} MB")
    mp, mx = statistics.median(res["py"]), statistics.median(res["xml"])
    print(f"median CPU: Python {mp:.2f} s, XML {mx:.2f} s, ratio {mp / mx:.2f} (target <= 2)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
