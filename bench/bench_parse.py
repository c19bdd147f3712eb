"""Parse + check benchmark for the TVL front end (not a test).

    .venv/bin/python bench/bench_parse.py [--runs N] [--lines N]

Measures tvl_lsp.tvl.parse_model on the shared corpus's drupal3.tvl (1,099 features) and on a
generated model of about 100,000 lines (features with attributes, groups of every kind,
reopenings and constraints), after one warm-up run; prints min / median milliseconds.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tvl_lsp.tvl import parse_model  # noqa: E402

SHARED = Path(__file__).resolve().parents[1].parent / "shared"
DRUPAL3 = SHARED / "corpus/tvl/familiar-tests/drupal3.tvl"


def generate(lines: int) -> str:
    """A valid model of about ``lines`` lines."""
    out = ["// generated benchmark model", "const int lim 3;", "enum level in {low, mid, high};",
           "root Bench {", "  int total is sum(selectedChildren.cost);", "  group someOf {"]
    # each module: 1 group line + 12 lines of declaration below
    n = max(1, lines // 14)
    out += [f"    M{i}," for i in range(n - 1)] + [f"    M{n - 1}", "  }", "}"]
    for i in range(n):
        out += [
            f"M{i} {{",
            "  int cost in [0..100], ifIn: is 10, ifOut: is 0;",
            "  level lvl;",
            f"  group [1..lim] {{",
            f"    M{i}_a {{ bool on is true; }},",
            f"    opt M{i}_b,",
            f"    M{i}_c group oneOf {{ M{i}_c1, M{i}_c2 }}",
            "  }",
            f"  M{i}_a -> !M{i}_b || (cost > 5 && lvl == mid);",
            f"  ifIn: count(selectedChildren) <= 3;",
            "}",
            f"M{i}.M{i}_b {{ M{i}_c2 requires M{i}_a; }}",
        ]
    return "\n".join(out) + "\n"


def measure(text: str, path: str, runs: int) -> tuple[list[float], int, int]:
    res = parse_model(text, path)  # warm-up (grammar load, caches)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        res = parse_model(text, path)
        times.append((time.perf_counter() - t0) * 1000)
    errors = sum(1 for d in res.diagnostics if d.severity == 1)
    return times, len(res.model.features), errors


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--lines", type=int, default=100_000)
    a = ap.parse_args(argv)
    if DRUPAL3.is_file():
        t, nf, ne = measure(DRUPAL3.read_text(), str(DRUPAL3), a.runs)
        print(f"drupal3.tvl ({nf} features, {ne} errors): min {min(t):.1f} ms, median {statistics.median(t):.1f} ms")
    text = generate(a.lines)
    t, nf, ne = measure(text, "generated.tvl", max(1, a.runs // 3))
    print(f"generated ({text.count(chr(10))} lines, {nf} features, {ne} errors): "
          f"min {min(t):.0f} ms, median {statistics.median(t):.0f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
