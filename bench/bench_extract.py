"""Extraction benchmark (issue #26: a 300-source repository in at most 2 s cold, at most 0.2 s
when nothing changed).  Not a test.

    .venv/bin/python bench/bench_extract.py PATH [--runs N] [--edit]

PATH: a repository, workspace or package (e.g. a checkout of ros-planning/navigation).  Each
run measures, in fresh child processes (so that no memory cache survives):

- ``cold``: an empty on-disk cache, nothing in memory: every source parsed;
- ``disk``: a new process over the cache the cold run wrote (what a second ``tvl-lsp extract``
  or a restarted server pays);
- ``warm``: in the same process, once more with nothing changed (what the editor pays when the
  graph is asked again);
- ``edit`` (with --edit): after one source file is touched (a comment appended in a copy): only it
  is parsed again.

Figures are wall-clock and CPU (user+system) seconds of ``extract()`` itself (imports excluded),
min / median over the runs, with the number of sources read and parsed.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, os, resource, sys, time
sys.path.insert(0, sys.argv[1])
from tvl_lsp.graph.sources import extract, cache
def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime
path, mode = sys.argv[2], sys.argv[3]
out = {}
t0, c0 = time.perf_counter(), cpu()
ex = extract([path])
out["first"] = [time.perf_counter() - t0, cpu() - c0, ex.files_read, ex.files_parsed,
                sum(len(x.endpoints) for x in ex.executables)]
if mode == "warm":
    t0, c0 = time.perf_counter(), cpu()
    ex = extract([path])
    out["warm"] = [time.perf_counter() - t0, cpu() - c0, ex.files_read, ex.files_parsed,
                   sum(len(x.endpoints) for x in ex.executables)]
if mode == "edit":
    victim = sys.argv[4]
    with open(victim, "a", encoding="utf-8") as fh:
        fh.write("\n// touched by bench_extract\n")
    t0, c0 = time.perf_counter(), cpu()
    ex = extract([path])
    out["edit"] = [time.perf_counter() - t0, cpu() - c0, ex.files_read, ex.files_parsed,
                   sum(len(x.endpoints) for x in ex.executables)]
print(json.dumps(out))
"""


def child(path: str, mode: str, cache_dir: str, extra: list[str] = ()) -> dict:
    env = dict(os.environ, TVL_LSP_CACHE_DIR=cache_dir)
    r = subprocess.run([sys.executable, "-c", CHILD, str(ROOT), path, mode, *extra], capture_output=True,
                       text=True, env=env, timeout=600)
    if r.returncode != 0:
        raise SystemExit(r.stderr[-3000:])
    return json.loads(r.stdout.strip().splitlines()[-1])


def fmt(rows: list[list]) -> str:
    wall = [r[0] for r in rows]
    cpu = [r[1] for r in rows]
    return (f"wall min {min(wall):.3f} s, median {statistics.median(wall):.3f} s; "
            f"CPU min {min(cpu):.3f} s, median {statistics.median(cpu):.3f} s "
            f"({rows[0][2]} sources read, {rows[0][3]} parsed, {rows[0][4]} endpoints)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("path")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--edit", action="store_true", help="also measure one touched source (on a copy)")
    a = ap.parse_args()
    path = str(Path(a.path).resolve())
    cold, disk, warm, edit = [], [], [], []
    for _ in range(a.runs):
        with tempfile.TemporaryDirectory(prefix="bench-extract-") as d:
            cache_dir = os.path.join(d, "cache")
            r = child(path, "warm", cache_dir)
            cold.append(r["first"])
            warm.append(r["warm"])
            disk.append(child(path, "once", cache_dir)["first"])
            if a.edit:
                copy = os.path.join(d, "copy")
                shutil.copytree(path, copy, symlinks=True)
                victim = next(str(p) for p in sorted(Path(copy).rglob("*.cpp")))
                child(copy, "once", cache_dir)
                edit.append(child(copy, "edit", cache_dir, [victim])["edit"])
    print(f"path: {path}")
    print(f"cold (empty caches):          {fmt(cold)}")
    print(f"disk (new process, cached):   {fmt(disk)}")
    print(f"warm (same process, no edit): {fmt(warm)}")
    if edit:
        print(f"edit (one source touched):    {fmt(edit)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
