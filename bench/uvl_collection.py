"""Real UVL files as unseen input (issue 17): read every ``*.uvl`` under the given folders with
tvl-lsp's UVL front end and report how many it reads without an error, the errors on the rest,
the constructs read but not analysed, and the parse time.

    .venv/bin/python bench/uvl_collection.py DIR [DIR ...] [--check] [--verdicts FILE.json] [--list]

The public collection is github.com/Universal-Variability-Language/uvl-models (feature models,
decision models, OVM models and the parser's test resources); uvl-parser's ``test_models`` are the
grammar's own test files (its ``faulty/`` folder must be rejected).  Neither is bundled: fetch them
and pass their folders.  ``--check`` also runs the analyses (void, dead, false-optional,
redundant) as ``tvl-lsp --check`` does, with a 20 s budget per model.  ``--verdicts`` takes a JSON
object {path: "accept"|"reject"} of another parser's verdicts (uvlparser) and prints where ours
differ.
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

SYNTAX = {"syntax-error", "illegal-character", "unterminated-comment", "unterminated-string", "multiple-roots"}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--verdicts")
    ap.add_argument("--list", action="store_true", help="print every file's result")
    args = ap.parse_args(argv)
    from tvl_lsp.analysis.engine import ModelAnalysis
    from tvl_lsp.uvl import parse_uvl

    files = sorted(p for d in args.dirs for p in Path(d).rglob("*.uvl"))
    other = json.loads(Path(args.verdicts).read_text()) if args.verdicts else {}
    stats: collections.Counter = collections.Counter()
    codes: collections.Counter = collections.Counter()
    times = []
    for f in files:
        text = f.read_text(encoding="utf-8", errors="replace")
        t0 = time.process_time()
        try:
            res = parse_uvl(text, str(f))
        except Exception as e:  # a crash is a bug: count it and go on
            stats["crash"] += 1
            print(f"CRASH {f}: {e!r}")
            continue
        dt = time.process_time() - t0
        times.append((dt, f))
        errs = res.errors
        stats["files"] += 1
        stats["read"] += not errs
        stats["not_analysed"] += any(d.code == "not-analysed" for d in res.diagnostics)
        for d in errs:
            codes[d.code] += 1
        anomalies = []
        if args.check and not errs:
            try:
                anomalies = ModelAnalysis(res.model).anomalies(time_budget=20)
            except Exception as e:
                stats["check_crash"] += 1
                print(f"CHECK CRASH {f}: {e!r}")
            stats["void"] += any(d.code == "void-model" for d in anomalies)
            stats["with_dead"] += any(d.code == "dead-feature" for d in anomalies)
        ours = "reject" if any(d.code in SYNTAX for d in errs) else "accept"
        theirs = other.get(str(f))
        if theirs is not None:
            stats["compared"] += 1
            if theirs != ours:
                stats["differ"] += 1
                print(f"DIFFERENT {f}: other {theirs}, tvl-lsp {ours}")
        if errs:
            d = errs[0]
            print(f"ERRORS {f}: {len(errs)}; first {d.span} {d.code}: {d.message[:140]}")
        elif args.list:
            print(f"OK {f} ({len(res.model.features)} features, {dt:.2f} s)")
    times.sort(key=lambda x: x[0])
    total = sum(t for t, _ in times)
    print(json.dumps({**stats, "error_codes": dict(codes), "parse_cpu_s_total": round(total, 1),
                      "parse_cpu_s_median": round(times[len(times) // 2][0], 3) if times else None,
                      "slowest": [f"{t:.2f} s {p.name}" for t, p in times[-3:]]}, indent=1))
    return 1 if stats["crash"] else 0


if __name__ == "__main__":
    sys.exit(main())
