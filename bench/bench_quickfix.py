"""Quick fixes for model anomalies (#30): what a fix costs.

    .venv/bin/python bench/bench_quickfix.py MODEL... [--findings N] [--budget S] [--json]

For each model (.tvl / .uvl):
- the editor's case: the checked fixes of one finding at a time (``fixes_for(keys=[k])``, as a
  code action asks for the findings under the cursor), for the first N findings: CPU seconds per
  finding (median, max), fixes offered, re-checks;
- ``tvl-lsp --check --fix``'s case: ``fix_file`` on the whole model: fixes applied, findings left,
  re-checks, CPU and wall seconds;
- and every fix of those N findings checked independently: applied to the text, the model checked
  again by the ``--check`` pipeline (the finding gone, nothing new).

CPU seconds are this process's (``resource.getrusage``): the machine is shared, note ``uptime``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import sys
import time
from collections import Counter


def cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def bench(path: str, n: int, budget: float) -> dict:
    from tvl_lsp.base.files import read_text
    from tvl_lsp.project import fixes as F
    from tvl_lsp.project import models
    from tvl_lsp.project.check import check_model
    text = read_text(path)
    out: dict = {"model": os.path.basename(path)}
    t = cpu()
    diags = check_model(path, text)
    out["check_cpu"] = round(cpu() - t, 3)
    findings = [d for d in diags if d.code in F.ANOMALY_CODES]
    out["findings"] = dict(Counter(d.code for d in findings))
    per, offered, checks, bad, nofix = [], 0, 0, 0, 0
    before = Counter(F.finding_key(d, text) for d in diags)
    for d in findings[:n]:
        k = F.finding_key(d, text)
        F._CACHE.clear()
        t = cpu()
        r = F.fixes_for(path, text, keys=[k], budget=budget)
        per.append(cpu() - t)
        fixes = r.fixes.get(k) or []
        nofix += not fixes
        offered += len(fixes)
        checks += r.checks
        for fx in fixes:
            new = F.apply_edits(text, fx.edits)
            after = Counter(F.finding_key(x, new) for x in check_model(path, new))
            if after[k] >= before[k] or (d.code not in (F.VOID, F.ALWAYS_FALSE) and after - (before - Counter([k]))):
                bad += 1
            models.clear()
    if per:
        out["editor"] = {"findings": len(per), "cpu_median": round(statistics.median(per), 3),
                         "cpu_max": round(max(per), 3), "fixes": offered, "rechecks": checks,
                         "without_fix": nofix,
                         "failed_independent_check": bad}
    F._CACHE.clear()
    t, w = cpu(), time.monotonic()
    run = F.fix_file(path, text, budget=budget)
    out["fix_file"] = {"applied": len(run.applied), "no_fix": len(run.unfixed), "not_reached": len(run.left),
                       "rechecks": run.checks, "cpu": round(cpu() - t, 2), "wall": round(time.monotonic() - w, 2)}
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("models", nargs="+")
    ap.add_argument("--findings", type=int, default=10, help="findings timed one by one (default 10)")
    ap.add_argument("--budget", type=float, default=300.0)
    ap.add_argument("--json", action="store_true")
    ns = ap.parse_args(argv)
    print(f"# {os.uname().nodename}: load {os.getloadavg()[0]:.1f}", file=sys.stderr)
    rows = [bench(m, ns.findings, ns.budget) for m in ns.models]
    if ns.json:
        print(json.dumps(rows, indent=1))
    else:
        for r in rows:
            print(json.dumps(r))
    return 0


if __name__ == "__main__":
    sys.exit(main())
