"""UVL twins vs DIMACS twins (issue 17): do ``tvl-lsp count`` of a UVL model and of its DIMACS
export agree, and do the two describe the same variables?

    .venv/bin/python bench/compare_uvl_dimacs.py [--models DIR] [--timeout 600] [--only a,b]

For each ``uvl/NAME.uvl`` with a ``dimacs/NAME.dimacs`` under ``--models`` (default
``../shared/models``), in a fresh ``tvl-lsp count --json`` process each (the real command, with
its timeout):

- the variables: the UVL model's feature names against the DIMACS ``c <var> <name>`` names
  (same set? how many only on one side?);
- the clauses: the DIMACS CNF against our encoding of the UVL model -- both directions are
  checked clause by clause with a SAT solver (the UVL encoding implies every DIMACS clause,
  and the DIMACS CNF implies every clause of the UVL encoding restricted to the features),
  within a time budget, when the variables are the same;
- the two counts and the time each took.

Prints a Markdown table (and, with ``--json FILE``, the raw results).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

DEFAULT_MODELS = ROOT.parent / "shared" / "models"
TVL_LSP = [sys.executable, "-m", "tvl_lsp"]


def count(path: Path, timeout: float) -> dict:
    t = time.monotonic()
    try:
        p = subprocess.run(TVL_LSP + ["count", str(path), "--json", "--timeout", str(timeout)],
                           capture_output=True, text=True, timeout=timeout + 120, cwd=ROOT)
    except subprocess.TimeoutExpired:
        return {"count": None, "error": "timeout", "seconds": time.monotonic() - t}
    out = {"seconds": round(time.monotonic() - t, 2), "exit": p.returncode}
    try:
        out.update(json.loads(p.stdout.strip().splitlines()[-1]))
    except Exception:
        out["error"] = (p.stderr.strip().splitlines() or ["no output"])[-1][:200]
    return out


def compare_vars(upath: Path, dpath: Path) -> dict:
    from tvl_lsp.analysis.dimacs import parse_dimacs
    from tvl_lsp.uvl import parse_uvl
    res = parse_uvl(upath.read_text(encoding="utf-8"), str(upath))
    unames = [f.name for f in res.model.features]
    nv, clauses, names, _ = parse_dimacs(dpath.read_text(encoding="utf-8"))
    dnames = [names.get(i, f"_{i}") for i in range(1, nv + 1)]
    su, sd = set(unames), set(dnames)
    return {"uvl_features": len(unames), "dimacs_vars": nv, "dimacs_clauses": len(clauses),
            "uvl_constraints": len(res.model.constraints),
            "uvl_errors": len(res.errors), "not_analysed": sum(d.code == "not-analysed" for d in res.diagnostics),
            "only_uvl": sorted(su - sd)[:5], "n_only_uvl": len(su - sd),
            "only_dimacs": sorted(sd - su)[:5], "n_only_dimacs": len(sd - su),
            "same_vars": su == sd and len(unames) == len(su) and len(dnames) == len(sd)}


def compare_clauses(upath: Path, dpath: Path, budget: float) -> dict:
    """Check both implications clause by clause (within ``budget`` seconds)."""
    from pysat.solvers import Solver
    from tvl_lsp.analysis.dimacs import parse_dimacs
    from tvl_lsp.analysis.encode import encode
    from tvl_lsp.uvl import parse_uvl
    res = parse_uvl(upath.read_text(encoding="utf-8"), str(upath))
    enc = encode(res.model)
    nv, dclauses, names, _ = parse_dimacs(dpath.read_text(encoding="utf-8"))
    # DIMACS variable -> our variable
    to_ours = {}
    for i in range(1, nv + 1):
        f = enc.feature_by_name(names.get(i, ""))
        if f is None:
            return {"clauses": "variables differ"}
        to_ours[i] = enc.var_of_feature[f]
    mapped = [[(1 if x > 0 else -1) * to_ours[abs(x)] for x in c] for c in dclauses]
    deadline = time.monotonic() + budget
    out = {}
    with Solver(name="cadical153", bootstrap_with=enc.clauses()) as s:
        bad = 0
        done = 0
        for c in mapped:
            if time.monotonic() > deadline:
                break
            done += 1
            if s.solve(assumptions=[-x for x in c]):
                bad += 1
        out["dimacs_clauses_implied_by_uvl"] = f"{done - bad}/{len(mapped)}" + ("" if done == len(mapped) else " (budget)")
    ours = [c for c in enc.clauses() if all(abs(x) <= enc.n_features for x in c)]
    with Solver(name="cadical153", bootstrap_with=mapped) as s:
        bad = 0
        done = 0
        for c in ours:
            if time.monotonic() > deadline:
                break
            done += 1
            if s.solve(assumptions=[-x for x in c]):
                bad += 1
        out["uvl_clauses_implied_by_dimacs"] = f"{done - bad}/{len(ours)}" + ("" if done == len(ours) else " (budget)")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default=str(DEFAULT_MODELS))
    ap.add_argument("--timeout", type=float, default=600.0, help="per count (s)")
    ap.add_argument("--clause-budget", type=float, default=60.0, help="per model, for the clause check (s)")
    ap.add_argument("--only", default="")
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    base = Path(args.models)
    names = sorted(p.stem for p in (base / "uvl").glob("*.uvl") if (base / "dimacs" / f"{p.stem}.dimacs").exists())
    if args.only:
        names = [n for n in names if n in args.only.split(",")]
    results = {}
    for name in names:
        up, dp = base / "uvl" / f"{name}.uvl", base / "dimacs" / f"{name}.dimacs"
        r = compare_vars(up, dp)
        if r["same_vars"]:
            r.update(compare_clauses(up, dp, args.clause_budget))
        r["uvl"] = count(up, args.timeout)
        r["dimacs"] = count(dp, args.timeout)
        results[name] = r
        print(name, json.dumps(r), file=sys.stderr, flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))
    print("| model | UVL features / DIMACS vars | same variables | UVL count (s) | DIMACS count (s) | equal | "
          "DIMACS clauses implied by UVL | UVL clauses implied by DIMACS |")
    print("|---|---|---|---|---|---|---|---|")
    for name, r in results.items():
        def c(d):
            if d.get("count") is None:
                return f"{d.get('error', 'no answer')} ({d['seconds']:.0f} s)"
            s = str(d["count"])
            s = s if len(s) <= 12 else f"{s[:6]}…({len(s)} digits)"
            return f"{s} ({d['seconds']:.1f} s)"
        uc, dc = r["uvl"].get("count"), r["dimacs"].get("count")
        eq = "—" if uc is None or dc is None else ("yes" if uc == dc else "NO")
        same = "yes" if r["same_vars"] else f"no ({r['n_only_uvl']} only in UVL, {r['n_only_dimacs']} only in DIMACS)"
        print(f"| {name} | {r['uvl_features']} / {r['dimacs_vars']} | {same} | {c(r['uvl'])} | {c(r['dimacs'])} | "
              f"{eq} | {r.get('dimacs_clauses_implied_by_uvl', '—')} | {r.get('uvl_clauses_implied_by_dimacs', '—')} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
