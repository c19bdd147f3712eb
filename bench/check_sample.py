"""``tvl-lsp sample --t 2`` checked by enumeration (issue #15).

    .venv/bin/python bench/check_sample.py MODEL.tvl [MODEL ...]

For each model: runs ``tvl-lsp sample MODEL --t 2 --json`` in a fresh process, enumerates every
product of the model (small models only: SAT enumeration), and reports whether every sampled
configuration is a product, whether every valid pair of feature literals (A with / without B,
over all products) occurs in some configuration, and whether the sample is smaller than the
product set -- with the smallest pairwise cover found by brute force when there are at most 12
products (a model whose every product is needed to cover its pairs cannot do better).
"""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
import time
from pathlib import Path

from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.formats import parse_any_model

TVL = str(Path(sys.executable).with_name("tvl-lsp"))


def pairs(p: dict, names: list[str]) -> set:
    return set(itertools.combinations([(n, p[n]) for n in names], 2))


def check(path: str) -> bool:
    t = time.perf_counter()
    out = subprocess.run([TVL, "sample", path, "--t", "2", "--json"], capture_output=True, text=True)
    dt = time.perf_counter() - t
    if out.returncode != 0:
        print(f"{path}: tvl-lsp sample failed: {out.stderr.strip()}")
        return False
    confs = json.loads(out.stdout)["configurations"]
    a = ModelAnalysis(parse_any_model(Path(path).read_text(), path).model)
    prods = list(a.enumerate(limit=None))
    names = sorted(prods[0]) if prods else []
    keys = {tuple(p[n] for n in names) for p in prods}
    valid = all(set(c) == set(names) and tuple(c[n] for n in names) in keys for c in confs)
    per = [pairs(p, names) for p in prods]
    need = set().union(*per) if per else set()
    got = set().union(*[pairs(c, names) for c in confs]) if confs else set()
    smallest = ""
    if len(prods) <= 12:
        k = next(k for k in range(1, len(prods) + 1)
                 if any(set().union(*c) >= need for c in itertools.combinations(per, k)))
        smallest = f", smallest cover {k}"
    print(f"{path}: {len(names)} features, {len(prods)} products, sample of {len(confs)} in {dt:.2f} s"
          f"{smallest}; every configuration a product: {valid}; valid pairs {len(need)}, "
          f"covered {len(need & got)}; fewer than products: {len(confs) < len(prods)}")
    return valid and need <= got


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__)
        return 2
    return 0 if all([check(p) for p in argv]) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
