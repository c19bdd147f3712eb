"""Benchmark ``tvl-lsp --check`` on a whole tree.

    .venv/bin/python bench/bench_check.py [PATH] [--runs N] [--jobs N ...]

PATH defaults to ../shared/corpus (the team's shared corpus: 95 models, 330 launch files);
any folder will do (``examples``, a ROS workspace).

Runs the real command line (a fresh process each time, as CI does: imports, discovery,
pairing, parsing, SAT, output) and prints wall-clock times per ``--jobs`` setting, with the
number of files and diagnostics.  The goal for the whole ``shared/corpus`` is <= 30 s.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT = ROOT.parent / "shared" / "corpus"


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("path", nargs="?", default=str(DEFAULT))
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--jobs", type=int, action="append", default=None,
                    help="--jobs values to compare (default: 1 and automatic)")
    ns = ap.parse_args()
    if not os.path.exists(ns.path):
        print(f"bench_check.py: {ns.path} not found (the default is the team's shared corpus, ../shared/corpus); "
              "pass the tree to check: bench/bench_check.py PATH (e.g. examples)", file=sys.stderr)
        return 2
    sys.path.insert(0, str(ROOT))
    from tvl_lsp.project.workspace import discover_files
    files = discover_files([ns.path])
    print(f"tree: {ns.path}")
    print(f"files: {len(files.models)} models, {len(files.launches)} launch files, "
          f"{len(files.yamls)} YAML files, {len(files.manifests)} packages; {os.cpu_count()} CPUs")
    settings = ns.jobs or [1, 0]
    for jobs in settings:
        cmd = [sys.executable, "-m", "tvl_lsp", "--check", ns.path, "--format", "json", "-q"]
        if jobs:
            cmd += ["--jobs", str(jobs)]
        times = []
        ndiag = None
        for _ in range(ns.runs):
            t = time.perf_counter()
            r = subprocess.run(cmd, capture_output=True, text=True, cwd=str(ROOT))
            times.append(time.perf_counter() - t)
            if r.returncode not in (0, 1):
                print(r.stderr, file=sys.stderr)
                return 2
            ndiag = len(json.loads(r.stdout))
        label = f"--jobs {jobs}" if jobs else "--jobs auto"
        print(f"{label:12} min {min(times):6.2f} s  median {statistics.median(times):6.2f} s  "
              f"max {max(times):6.2f} s  ({ns.runs} runs, {ndiag} diagnostics)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
