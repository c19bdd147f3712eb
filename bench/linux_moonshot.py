"""The Linux kernel moonshot (issue #15): attempts at an exact count of linux-2.6.33.3.dimacs.

    nice .venv/bin/python bench/linux_moonshot.py [--models DIR] [--budget S] [--attempt NAME]...

Attempts (each bounded by ``--budget`` seconds, default 300, run one at a time except the
cube trial, which uses a pool of 2 processes):

- ``simplify``: backbone (python-sat, literal by literal with the solver's models as filter),
  unit propagation, equivalent-literal substitution (strongly connected components of the
  binary implication graph), dropping satisfied clauses; reports the reduced CNF.  Exact:
  fixed and substituted variables are functions of the rest, so the count is unchanged.
- ``d4``: d4 (counting mode) on the reduced CNF, default options and a small partitioning
  budget;
- ``pyganak``: pyganak on the reduced CNF;
- ``cubes``: split on the 2 variables occurring most often, count the 4 cubes with d4 in a
  pool of 2 processes, sum.

Prints one line per attempt (what, seconds, answer or "no answer"); the figures are in
docs/benchmarks/2026-11-23-linux-kernel-count.md.  ``--models`` default: ``/work/shared/models`` (``$TVL_LSP_MODELS`` overrides).
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

DEFAULT_MODELS = os.environ.get("TVL_LSP_MODELS", "/work/shared/models")
PY = sys.executable

D4_COUNT = r"""
import os, sys, json, time
import py_d4
opts = json.loads(sys.argv[2]) if len(sys.argv) > 2 else None
saved = os.dup(1); os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
if opts:
    base = py_d4.dump_options_to_dict(py_d4.Solver([[1]], 1).getOptions())
    def merge(a, b):
        for k, v in b.items():
            if isinstance(v, dict): merge(a[k], v)
            else: a[k] = v
    merge(base, opts)
    s = py_d4.Solver(sys.argv[1], py_d4.load_options_from_dict(base))
else:
    s = py_d4.Solver(sys.argv[1])
n = s.count().getIntResult()
os.dup2(saved, 1)
print(n)
"""

GANAK_COUNT = r"""
import os, sys, pyganak
from pysat.formula import CNF
f = CNF(from_file=sys.argv[1])
c = pyganak.Counter(); c.new_vars(f.nv)
for cl in f.clauses: c.add_clause(cl)
saved = os.dup(1); os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
n = c.count()
os.dup2(saved, 1)
print(n)
"""


def read_cnf(path):
    from tvl_lsp.analysis.dimacs import parse_dimacs
    nv, cls, _, _ = parse_dimacs(Path(path).read_text())
    return nv, cls


def write_cnf(path, nv, cls):
    with open(path, "w") as fh:
        fh.write(f"p cnf {nv} {len(cls)}\n")
        for c in cls:
            fh.write(" ".join(map(str, c)) + " 0\n")


def simplify(nv, cls, budget):
    """Backbone + equivalences; returns (nv', clauses', factor) with count = factor * count'."""
    from pysat.solvers import Solver
    t0 = time.perf_counter()
    s = Solver(name="cadical153", bootstrap_with=cls)
    assert s.solve(), "unsatisfiable"
    model = s.get_model()
    cand = {abs(x): x for x in model}
    backbone = {}
    for v in range(1, nv + 1):
        if time.perf_counter() - t0 > budget:
            break
        x = cand.get(v)
        if x is None:
            continue
        if s.solve(assumptions=[-x]):
            m = s.get_model()
            for y in m:  # literals that flip in this model are not backbone
                if cand.get(abs(y)) == -y:
                    cand.pop(abs(y), None)
        else:
            backbone[v] = x
            s.add_clause([x])
    s.delete()
    t_bb = time.perf_counter() - t0
    # unit propagation with the backbone
    val = {v: x > 0 for v, x in backbone.items()}
    out = []
    for c in cls:
        if any(val.get(abs(x)) == (x > 0) for x in c):
            continue
        r = [x for x in c if abs(x) not in val]
        out.append(r)
    # equivalences: SCCs of the binary implication graph (iterative Tarjan)
    graph: dict[int, list[int]] = {}
    for c in out:
        if len(c) == 2:
            a, b = c
            graph.setdefault(-a, []).append(b)
            graph.setdefault(-b, []).append(a)
    index, low, onstack, stack, comps = {}, {}, set(), [], []
    counter = [0]
    for root in list(graph):
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            node, i = work.pop()
            if i == 0:
                index[node] = low[node] = counter[0]
                counter[0] += 1
                stack.append(node)
                onstack.add(node)
            succ = graph.get(node, [])
            if i < len(succ):
                work.append((node, i + 1))
                w = succ[i]
                if w not in index:
                    work.append((w, 0))
                elif w in onstack:
                    low[node] = min(low[node], index[w])
                continue
            if low[node] == index[node]:
                comp = []
                while True:
                    w = stack.pop()
                    onstack.discard(w)
                    comp.append(w)
                    if w == node:
                        break
                comps.append(comp)
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
    rep = {}
    for comp in comps:
        if len(comp) > 1:
            r = min(comp, key=abs)
            for x in comp:
                if x != r:
                    rep[x] = r
    sub = {}
    for x, r in rep.items():
        sub[x] = r
    out2 = []
    for c in out:
        c2 = sorted({sub.get(x, x) for x in c})
        if any(-x in c2 for x in c2):
            continue
        out2.append(c2)
    eliminated = {abs(x) for x in rep}
    # renumber what is left; variables in no clause stay (each doubles the count)
    keep = [v for v in range(1, nv + 1) if v not in val and v not in eliminated]
    ren = {v: i + 1 for i, v in enumerate(keep)}
    out3 = [[ren[abs(x)] * (1 if x > 0 else -1) for x in c] for c in out2]
    out3 = [list(c) for c in {tuple(c) for c in out3}]
    return len(keep), out3, {"backbone": len(backbone), "equivalent": len(eliminated),
                             "seconds_backbone": round(t_bb, 1), "seconds": round(time.perf_counter() - t0, 1)}


def run(cmd, budget):
    t = time.perf_counter()
    try:
        p = subprocess.run(["nice", "-n", "10"] + cmd, capture_output=True, text=True, timeout=budget)
        dt = time.perf_counter() - t
        if p.returncode == 0 and p.stdout.strip():
            return p.stdout.split()[-1], dt
        return f"failed ({p.returncode}: {p.stderr.strip()[-200:]})", dt
    except subprocess.TimeoutExpired:
        return None, time.perf_counter() - t


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default=DEFAULT_MODELS)
    ap.add_argument("--budget", type=float, default=300)
    ap.add_argument("--attempt", action="append", help="simplify, d4, d4-budget, pyganak, cubes (default: all)")
    args = ap.parse_args(argv)
    path = Path(args.models) / "dimacs" / "linux-2.6.33.3.dimacs"
    if not path.exists():
        print(f"linux_moonshot: no {path} (pass --models DIR); nothing tried")
        return 0
    todo = args.attempt or ["simplify", "d4", "d4-budget", "pyganak", "cubes"]
    nv, cls = read_cnf(path)
    print(json.dumps({"model": path.name, "vars": nv, "clauses": len(cls)}), flush=True)
    tmp = Path(tempfile.mkdtemp(prefix="linux-"))
    red = tmp / "reduced.cnf"
    nv2, cls2, info = simplify(nv, cls, args.budget)
    write_cnf(red, nv2, cls2)
    info.update({"attempt": "simplify", "vars": nv2, "clauses": len(cls2)})
    print(json.dumps(info), flush=True)
    if "d4" in todo:
        ans, dt = run([PY, "-c", D4_COUNT, str(red)], args.budget)
        print(json.dumps({"attempt": "d4 (default options) on the reduced CNF", "seconds": round(dt, 1),
                          "answer": ans or f"no answer in {args.budget:g} s"}), flush=True)
    if "d4-budget" in todo:
        opts = json.dumps({"branching": {"partialOrder": {"budget": 1}}})
        ans, dt = run([PY, "-c", D4_COUNT, str(red), opts], args.budget)
        print(json.dumps({"attempt": "d4 (partitioning budget 1) on the reduced CNF", "seconds": round(dt, 1),
                          "answer": ans or f"no answer in {args.budget:g} s"}), flush=True)
    if "pyganak" in todo:
        ans, dt = run([PY, "-c", GANAK_COUNT, str(red)], args.budget)
        print(json.dumps({"attempt": "pyganak on the reduced CNF", "seconds": round(dt, 1),
                          "answer": ans or f"no answer in {args.budget:g} s"}), flush=True)
    if "cubes" in todo:
        occ = Counter(abs(x) for c in cls2 for x in c)
        split = [v for v, _ in occ.most_common(2)]
        cubes = [[a * split[0], b * split[1]] for a in (1, -1) for b in (1, -1)]
        files = []
        for i, cube in enumerate(cubes):
            f = tmp / f"cube{i}.cnf"
            write_cnf(f, nv2, cls2 + [[x] for x in cube])
            files.append(f)
        t = time.perf_counter()
        with cf.ThreadPoolExecutor(2) as pool:
            results = list(pool.map(lambda f: run([PY, "-c", D4_COUNT, str(f)], args.budget), files))
        dt = time.perf_counter() - t
        answers = [r[0] for r in results]
        total = sum(int(a) for a in answers) if all(a and a.isdigit() for a in answers) else None
        print(json.dumps({"attempt": f"4 cubes on variables {split}, d4, 2 processes", "seconds": round(dt, 1),
                          "cubes": [a or "no answer" for a in answers],
                          "answer": str(total) if total is not None else "incomplete"}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
