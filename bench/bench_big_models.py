"""Benchmark ``tvl-lsp --check`` on very big models: CPU time and peak memory per file.

    .venv/bin/python bench/bench_big_models.py [--models DIR] [--only NAME ...] [--runs N]

Generates four synthetic models beyond any real one into a temporary folder (a flat TVL group
of 200,000 features; ``bench_parse.generate(200000)``, 212,000 lines in the corpus's style with
79,501 features; a flat UVL group of 300,000 features; a random 2-CNF of 100,000 variables and
600,000 clauses), and adds every ``*.uvl`` / ``*.dimacs`` of ``--models`` (default
../shared/models/{uvl,dimacs}: the industrial models; skipped with a note when absent).

Each file is checked alone by the real command line in a fresh process; the figures are the
child's user+system CPU time and maximum resident set size (``resource.getrusage``), the median
over ``--runs``.  Issue 12 asks for every hostile file in under 5 s CPU and 1 GB.
"""

from __future__ import annotations

import argparse
import os
import random
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_MODELS = ROOT.parent / "shared" / "models"
sys.path.insert(0, str(ROOT / "bench"))


def synthetic(folder: Path) -> list[Path]:
    from bench_parse import generate
    out = []
    p = folder / "flat200k.tvl"
    p.write_text("root R {\n  group someOf {\n" + ",\n".join(f"    F{i}" for i in range(200_000)) + "\n  }\n}\n")
    out.append(p)
    p = folder / "layered212k.tvl"
    p.write_text(generate(200_000))
    out.append(p)
    p = folder / "flat300k.uvl"
    p.write_text("features\n    R\n        optional\n" + "".join(f"            F{i}\n" for i in range(300_000)))
    out.append(p)
    rng = random.Random(1)
    n, m = 100_000, 600_000
    lines = [f"p cnf {n} {m}"]
    for _ in range(m):
        lines.append(" ".join(str(v if rng.random() < 0.5 else -v) for v in rng.sample(range(1, n + 1), 2)) + " 0")
    p = folder / "random600k.dimacs"
    p.write_text("\n".join(lines) + "\n")
    out.append(p)
    return out


def measure(path: Path) -> tuple[float, float, str]:
    """(CPU seconds, max RSS in MB, the summary line) of one ``--check`` in a fresh process."""
    exe = ROOT / ".venv" / "bin" / "tvl-lsp"
    cmd = [str(exe) if exe.exists() else "tvl-lsp", "--check", str(path)]
    with tempfile.TemporaryFile("w+") as out:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=out)
        _, _, ru = os.wait4(proc.pid, 0)  # this child's own rusage
        proc.returncode = 0
        out.seek(0)
        last = next((x for x in reversed(out.read().splitlines()) if "checked" in x), "")
    return ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024, last


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", default=str(DEFAULT_MODELS), help="folder with uvl/ and dimacs/ (industrial models)")
    ap.add_argument("--only", nargs="*", help="file names to run (default: all)")
    ap.add_argument("--runs", type=int, default=1)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        files = synthetic(Path(tmp))
        models = Path(args.models)
        if models.is_dir():
            files += sorted(models.glob("uvl/*.uvl")) + sorted(models.glob("dimacs/*.dimacs"))
        else:
            print(f"note: {models} not found: industrial models skipped (pass --models DIR with uvl/ and dimacs/)")
        if args.only:
            files = [f for f in files if f.name in args.only]
        print(f"{'file':28} {'MB':>6} {'CPU s':>7} {'max RSS MB':>11}  summary")
        for f in files:
            runs = [measure(f) for _ in range(args.runs)]
            cpu = statistics.median(r[0] for r in runs)
            rss = statistics.median(r[1] for r in runs)
            print(f"{f.name:28} {f.stat().st_size / 1e6:6.1f} {cpu:7.2f} {rss:11.0f}  {runs[-1][2]}", flush=True)
        print(f"load average: {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
