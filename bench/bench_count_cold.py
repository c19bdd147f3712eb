"""``tvl-lsp count`` cold against raw d4 on the same CNF, and a UVL model against its DIMACS twin
(issue #30, part 3), side by side in one run, each tool in a fresh process.

    .venv/bin/python bench/bench_count_cold.py [--models DIR] [--runs 3] [--only NAME]... [--twin NAME]...
    .venv/bin/python bench/bench_count_cold.py --raw-d4 FILE.dimacs     # raw d4 alone (prints the count)

``--models``: the folder holding ``dimacs/<name>.dimacs`` and ``uvl/<name>.uvl`` (default
``$TVL_LSP_MODELS`` or ``/work/shared/models``).  Raw d4 is the PyPI ``d4solver`` the project uses,
reading the DIMACS file itself and counting (``py_d4.Solver(path).count()``) in a fresh Python
process; ``tvl-lsp count FILE --json`` runs with an empty disk cache (cold: it parses, reduces,
compiles and stores the d-DNNF).  The runs are interleaved (d4, tvl, d4, tvl...), the figure is
the MEDIAN of ``--runs`` of each, in CPU seconds of the process and its children (user + system:
the machine is shared, CPU time moves less than wall time), wall seconds beside.  The counts
must agree.  Prints a Markdown table; the machine's load (``uptime``) first.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

DEFAULT_MODELS = os.environ.get("TVL_LSP_MODELS", "/work/shared/models")
NAMES = ["automotive01", "ecos-i386pc", "automotive2_1"]
TWINS = ["embtoolkit", "ecos-i386pc", "automotive01", "busybox-1.18.0", "uclinux-distribution"]
PY = sys.executable
TVL = str(Path(PY).with_name("tvl-lsp"))


def raw_d4(path: str) -> int:
    import py_d4
    saved = os.dup(1)
    os.dup2(os.open(os.devnull, os.O_WRONLY), 1)  # d4 prints statistics on fd 1
    n = py_d4.Solver(path).count().getIntResult()
    os.dup2(saved, 1)
    print(n)
    return 0


def measure(cmd: list[str], env=None, timeout: float = 600.0):
    """(CPU seconds, wall seconds, stdout) of a fresh process (None CPU on failure)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, timeout, ""
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return (cpu if p.returncode == 0 else None), wall, p.stdout


def d4_cmd(path: Path) -> list[str]:
    return [PY, __file__, "--raw-d4", str(path)]


def tvl_count(path: Path):
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, TVL_LSP_CACHE_DIR=cache)
        cpu, wall, out = measure([TVL, "count", str(path), "--json"], env)
    n = json.loads(out)["count"] if cpu is not None else None
    return cpu, wall, n


def plain_status(uvl: Path) -> str:
    """Does ``tvl-lsp count`` read the model by the plain path (tvl_lsp.uvl.plain), and is its
    CNF the full path's, clause for clause?"""
    from tvl_lsp.analysis.encode import encode
    from tvl_lsp.analysis.plaincnf import encode_plain
    from tvl_lsp.uvl import parse_uvl
    from tvl_lsp.uvl.plain import read_plain
    text = uvl.read_text()
    p = read_plain(text)
    if p is None:
        return "no (full path)"
    c = encode_plain(p)
    enc = encode(parse_uvl(text, str(uvl)).model)
    same = (c.n_features, c.nvars, c.clauses) == (enc.n_features, enc.nvars, enc.clauses())
    return "yes, same CNF" if same else "yes, CNF DIFFERS"


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fmt(cpu, wall):
    return "failed" if cpu is None else f"{cpu:.2f} ({wall:.2f})"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default=DEFAULT_MODELS)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--only", action="append", help="DIMACS models (default: %s)" % ", ".join(NAMES))
    ap.add_argument("--twin", action="append", help="UVL / DIMACS twins (default: %s)" % ", ".join(TWINS))
    ap.add_argument("--raw-d4", metavar="FILE", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.raw_d4:
        return raw_d4(args.raw_d4)
    models = Path(args.models)
    if not (models / "dimacs").is_dir():
        print(f"bench_count_cold: no models at {models}/dimacs (pass --models DIR); nothing measured")
        return 0
    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    print()
    print("| model | raw d4 CPU (wall) s | tvl-lsp count cold CPU (wall) s | ratio (CPU) | counts agree |")
    print("|---|---|---|---|---|")
    for name in args.only or NAMES:
        path = models / "dimacs" / f"{name}.dimacs"
        if not path.exists():
            continue
        d4c, d4w, tc, tw, agree = [], [], [], [], True
        for _ in range(args.runs):
            c, w, out = measure(d4_cmd(path))
            d4c.append(c)
            d4w.append(w)
            n_d4 = int(out.split()[0]) if c is not None else None
            c, w, n = tvl_count(path)
            tc.append(c)
            tw.append(w)
            agree = agree and n is not None and n == n_d4
        a, b = med(d4c), med(tc)
        ratio = f"{b / a:.2f}" if a and b else "-"
        print(f"| {name} | {fmt(a, med(d4w))} | {fmt(b, med(tw))} | {ratio} | {'yes' if agree else 'NO'} |",
              flush=True)
    print()
    print("| twin | raw d4 on .dimacs CPU (wall) s | tvl-lsp count .dimacs | tvl-lsp count .uvl | "
          ".uvl / .dimacs (CPU) | .uvl / raw d4 | counts agree | plain path |")
    print("|---|---|---|---|---|---|---|---|")
    for name in args.twin or TWINS:
        dim, uvl = models / "dimacs" / f"{name}.dimacs", models / "uvl" / f"{name}.uvl"
        if not (dim.exists() and uvl.exists()):
            continue
        rows = {"d4": ([], []), "dimacs": ([], []), "uvl": ([], [])}
        counts = set()
        for _ in range(args.runs):
            c, w, out = measure(d4_cmd(dim))
            rows["d4"][0].append(c)
            rows["d4"][1].append(w)
            counts.add(int(out.split()[0]) if c is not None else None)
            for key, p in (("dimacs", dim), ("uvl", uvl)):
                c, w, n = tvl_count(p)
                rows[key][0].append(c)
                rows[key][1].append(w)
                counts.add(n)
        m = {k: (med(v[0]), med(v[1])) for k, v in rows.items()}
        r1 = f"{m['uvl'][0] / m['dimacs'][0]:.2f}" if m["uvl"][0] and m["dimacs"][0] else "-"
        r2 = f"{m['uvl'][0] / m['d4'][0]:.2f}" if m["uvl"][0] and m["d4"][0] else "-"
        ok = len(counts) == 1 and None not in counts
        print(f"| {name} | {fmt(*m['d4'])} | {fmt(*m['dimacs'])} | {fmt(*m['uvl'])} | {r1} | {r2} | "
              f"{'yes' if ok else 'NO'} | {plain_status(uvl)} |", flush=True)
    print()
    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    return 0


if __name__ == "__main__":
    sys.exit(main())
