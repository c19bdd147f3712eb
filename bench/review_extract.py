"""Hand-checking helper for extraction (issue #26; docs/benchmarks/2026-11-27-sources.md).  Not a test.

    .venv/bin/python bench/review_extract.py ROOT N SEED [--tally]

Shuffles the source files of ROOT that contain an API-looking call with random.Random(SEED),
takes the first N and prints, for each, its API-looking lines and the rows `tvl-lsp extract
--json` gives for it, side by side, to be read and judged by a person; ``--tally`` prints only
the counts (files, call sites, rows, untyped and dynamic rows).
"""

from __future__ import annotations

import json
import os
import random
import re
import subprocess
import sys
from pathlib import Path

PAT = re.compile(r"\b(advertise\w*|subscribe\w*|serviceClient|getParam\w*|setParam|deleteParam|searchParam|param|"
                 r"create_publisher|create_subscription|create_service|create_client|create_server|"
                 r"declare_parameters?|get_parameters?|get_parameter_or|set_parameters?|Publisher|Subscriber|Service|"
                 r"ServiceProxy|get_param|set_param|delete_param|search_param|\w*ActionServer|\w*ActionClient|"
                 r"declare_parameter_if_not_declared|declare_or_get_parameter|SubscriberFilter|call)\s*(<[^;]*?>)?\s*\(")
EXE = str(Path(sys.executable).with_name("tvl-lsp"))


def sample(root: str, n: int, seed: int) -> list[str]:
    files = []
    for dp, dn, fn in os.walk(root):
        dn[:] = sorted(x for x in dn if not x.startswith("."))
        for f in sorted(fn):
            p = os.path.join(dp, f)
            if f.endswith((".cpp", ".cc", ".h", ".hpp", ".py")) or (os.access(p, os.X_OK) and "." not in f):
                try:
                    t = open(p, encoding="utf-8", errors="replace").read()
                except OSError:
                    continue
                if PAT.search(t):
                    files.append(p)
    random.Random(seed).shuffle(files)
    return files[:n]


def main() -> int:
    root, n, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    doc = json.loads(subprocess.run([EXE, "extract", root, "--json"], capture_output=True, text=True).stdout)
    rows: dict[str, dict] = {}
    for r in doc["endpoints"]:
        rows.setdefault(r["file"], {})[(r["line"], r["kind"], r["name"], r["type"], r["dynamic"])] = r
    files = sample(root, n, seed)
    if "--tally" in sys.argv:
        rs = [k for f in files for k in rows.get(f, {})]
        sites = {(f, k[0], k[1]) for f in files for k in rows.get(f, {})}
        print(f"{root}: {len(files)} files, {len(sites)} call sites, {len(rs)} rows, "
              f"untyped {sum(1 for k in rs if k[3] is None)}, dynamic {sum(1 for k in rs if k[4])}")
        return 0
    for p in files:
        print("=" * 100)
        print("FILE", os.path.relpath(p, root))
        for i, line in enumerate(open(p, encoding="utf-8", errors="replace").read().split("\n"), 1):
            if PAT.search(line) and not line.strip().startswith(("//", "#", "*")):
                print(f"  {i:5d}: {line.strip()[:140]}")
        print("  -- extracted:")
        for k in sorted(rows.get(p, {})):
            print(f"     {k[0]:5d} {k[1]:13s} {k[2]:40s} {k[3]} {'DYN' if k[4] else ''}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
