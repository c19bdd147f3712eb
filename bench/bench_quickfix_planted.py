"""Quick fixes (#30), the judging line: generated models with planted anomalies (TVL and UVL),
every finding fixable, each fix removing its finding and adding none.

    .venv/bin/python bench/bench_quickfix_planted.py [--seeds N] [--first S]

For seeds S..S+N-1 and both formats, ``tests/quickfix_gen.planted_model`` writes a model with
planted anomalies (see there); every finding of its ``--check`` gets ``fixes_for``'s fixes, each
applied to the text and the model checked again by the ``--check`` pipeline
(``project.check.check_model``), independently of the code that offered it: the finding must be
gone, no finding new (a void model: none the model without its conflict lacks; with several
conflicts, no new error) and no error new (a void model with two conflicts stays void when
an always-false constraint of one goes).  ``fix_file`` (``--check --fix``) must leave no
finding.  Prints the counts and every failure; exit status 1 when there is one.  CPU seconds are
the process's (``resource.getrusage``): note ``uptime``.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=300)
    ap.add_argument("--first", type=int, default=0)
    a = ap.parse_args(argv)
    from quickfix_gen import planted_model
    from tvl_lsp.analysis.fixes import source_text
    from tvl_lsp.project.check import check_model
    from tvl_lsp.project.fixes import ANOMALY_CODES, apply_edits, finding_key, fix_file, fixes_for

    def keys(path, text):
        ds = check_model(path, text)
        return Counter(finding_key(d, text) for d in ds), ds
    tmp = tempfile.mkdtemp(prefix="qf-planted-")
    st: Counter = Counter()
    fails = []
    for seed in range(a.first, a.first + a.seeds):
        for fmt in ("tvl", "uvl"):
            text, planted, _, without = planted_model(seed, fmt)
            path = os.path.join(tmp, f"m{seed}.{fmt}")
            Path(path).write_text(text)
            before, diags = keys(path, text)
            st["models"] += 1
            st["planted"] += len(planted)
            if planted - set(before):
                fails.append((seed, fmt, "planted, not reported", planted - set(before)))
            hidden, several = Counter(), False
            void = next((d for d in diags if d.code == "void-model"), None)
            if void is not None:
                st["void models"] += 1
                hidden, _ = keys(path, without([source_text(text, r.span) for r in void.related if r.path == path]))
                several = hidden[("void-model",)] > 0
                st["void models with several conflicts"] += several
            rep = fixes_for(path, text, budget=60)
            for d in diags:
                if d.code not in ANOMALY_CODES:
                    continue
                k = finding_key(d, text)
                st["findings"] += 1
                st[f"findings: {d.code}"] += 1
                fx = rep.fixes.get(k) or []
                if not fx:
                    fails.append((seed, fmt, "no fix", k))
                    continue
                st["findings with a fix"] += 1
                st["planted findings with a fix"] += k in planted
                for f in fx:
                    new = apply_edits(text, f.edits)
                    after, ad = keys(path, new)
                    added = after - ((before - Counter([k])) | hidden)
                    errs = [x for x in ad if x.severity == 1 and finding_key(x, new) not in before]
                    lenient = several and d.code in ("void-model", "always-false-constraint")
                    st["fixes"] += 1
                    if after[k] < before[k] and (lenient or not added) and not errs:
                        st["fixes verified"] += 1
                    else:
                        fails.append((seed, fmt, "bad fix", k, f.title, dict(added), [e.message for e in errs]))
            run = fix_file(path, text)
            _, d2 = keys(path, run.text)
            st["--fix runs"] += 1
            left = [(d.code, d.message[:60]) for d in d2 if d.code in ANOMALY_CODES or d.severity == 1]
            if left:
                fails.append((seed, fmt, "--fix left", left))
    r = resource.getrusage(resource.RUSAGE_SELF)
    for k in sorted(st):
        print(f"{k}: {st[k]}")
    print(f"cpu seconds: {r.ru_utime + r.ru_stime:.1f}")
    for f in fails:
        print("FAIL", f)
    print(f"{len(fails)} failure(s)")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
