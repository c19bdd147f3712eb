"""Parse + check benchmark for the TVL front end (not a test).

    .venv/bin/python bench/bench_parse.py [--runs N] [--lines N] [--model FILE]

Measures tvl_lsp.tvl.parse_model (lex + parse + build + every check) on a real model, by
default the corpus's drupal3.tvl (1,099 features; at ../shared/corpus/tvl/familiar-tests/ on the
team's machines; ``--model FILE`` for another, ``--model none`` for none), and on two generated
models of about 100,000 lines (always there): one in the
style of the corpus's big models (~2.5 tokens per line) and a dense one (~6.8 tokens per line).
One warm-up run, then min / median milliseconds.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tvl_lsp.tvl import parse_model  # noqa: E402

DRUPAL3 = Path(__file__).resolve().parents[1].parent / "shared" / "corpus/tvl/familiar-tests/drupal3.tvl"


def generate(lines: int) -> str:
    """A valid model of about ``lines`` lines in the style of the corpus's big models (drupal*.tvl):
    a root with a long group, one feature per line in groups, reopenings with requires/excludes
    constraints, some attributes, cardinalities and optional children.  ~2.5 tokens per line,
    like drupal3.tvl (5,457 tokens on 2,262 lines)."""
    out = ["// generated benchmark model", "const int lim 2;", "root Bench {", "  group someOf {"]
    n = max(1, lines // 16)
    out += [f"    P{i}," for i in range(n - 1)] + [f"    P{n - 1}", "  }", "}"]
    for i in range(n):
        j = (i * 7 + 3) % n
        out += [
            f"P{i} {{",
            f"  group [1..lim] {{",
            f"    P{i}_a,",
            f"    opt P{i}_b,",
            f"    P{i}_c",
            "  }",
            f"  int cost is {i % 100};",
            f"  P{i} -> P{j};",
            "}",
            f"P{i}_c {{",
            "  group oneOf {",
            f"    P{i}_c1,",
            f"    P{i}_c2",
            "  }",
            f"  P{i}_c1 excludes P{j}_b;",
            "}",
        ]
    return "\n".join(out) + "\n"


def generate_dense(lines: int) -> str:
    """A denser model (~6.8 tokens per line): attributes with domains and ifIn/ifOut values,
    enum comparisons, aggregates and arithmetic in every module."""
    out = ["// generated dense benchmark model", "const int lim 3;", "enum level in {low, mid, high};",
           "root Bench {", "  int total is sum(selectedChildren.cost);", "  group someOf {"]
    n = max(1, lines // 14)
    out += [f"    M{i}," for i in range(n - 1)] + [f"    M{n - 1}", "  }", "}"]
    for i in range(n):
        out += [
            f"M{i} {{",
            "  int cost in [0..100], ifIn: is 10, ifOut: is 0;",
            "  level lvl;",
            "  group [1..lim] {",
            f"    M{i}_a {{ bool on is true; }},",
            f"    opt M{i}_b,",
            f"    M{i}_c group oneOf {{ M{i}_c1, M{i}_c2 }}",
            "  }",
            f"  M{i}_a -> !M{i}_b || (cost > 5 && lvl == mid);",
            "  ifIn: count(selectedChildren) <= 3;",
            "}",
            f"M{i}.M{i}_b {{ M{i}_c2 requires M{i}_a; }}",
        ]
    return "\n".join(out) + "\n"


def measure(text: str, path: str, runs: int) -> tuple[list[float], list[float], int, int]:
    res = parse_model(text, path)  # warm-up (grammar load, caches)
    times, cpu = [], []
    for _ in range(runs):
        t0, c0 = time.perf_counter(), time.process_time()
        res = parse_model(text, path)
        times.append((time.perf_counter() - t0) * 1000)
        cpu.append((time.process_time() - c0) * 1000)
    errors = sum(1 for d in res.diagnostics if d.severity == 1)
    return times, cpu, len(res.model.features), errors


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--lines", type=int, default=100_000)
    ap.add_argument("--model", default=str(DRUPAL3), metavar="FILE|none",
                    help="a real model to measure too (default: %(default)s)")
    a = ap.parse_args(argv)
    model = None if a.model == "none" else Path(a.model)
    if model is not None and not model.is_file():
        print(f"bench_parse.py: {model} not found (drupal3.tvl is in the team's shared corpus, "
              "../shared/corpus/tvl/familiar-tests/); pass --model FILE, or --model none for the generated "
              "models only", file=sys.stderr)
        return 2
    if model is not None:
        t, c, nf, ne = measure(model.read_text(), str(model), a.runs)
        print(f"{model.name} ({nf} features, {ne} errors): wall min {min(t):.1f} ms, median {statistics.median(t):.1f} ms; "
              f"CPU min {min(c):.1f} ms, median {statistics.median(c):.1f} ms")
    for name, gen in (("generated", generate), ("generated dense", generate_dense)):
        text = gen(a.lines)
        t, c, nf, ne = measure(text, "generated.tvl", max(1, a.runs // 3))
        print(f"{name} ({text.count(chr(10))} lines, {nf} features, {ne} errors): "
              f"wall min {min(t):.0f} ms, median {statistics.median(t):.0f} ms; "
              f"CPU min {min(c):.0f} ms, median {statistics.median(c):.0f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
