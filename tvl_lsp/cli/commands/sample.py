"""``tvl-lsp sample MODEL (--t 2 | --uniform N) [--seed S] [--include F]... [--exclude F]...
[--json] [--timeout S]``

Products of a model to test with:

- ``--t 2``: a pairwise covering sample -- every valid pair of feature literals (A with B, A
  without B, ...) occurs in some configuration; ``--t 1``: every feature both selected and
  left out, where the model allows it.  Usually far fewer configurations than products.
- ``--uniform N``: N products drawn uniformly at random (with replacement) from all of them.

Every configuration is a product of the model (within ``--include`` / ``--exclude``).  The
same ``--seed`` (default 0) gives the same sample.  Text output: one line per configuration,
its selected features; ``--json``: ``{"configurations": [{feature: bool, ...}, ...],
"engine": ...}``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp sample", description="Sample the products of a feature model.")
    ap.add_argument("model", help="a .tvl or .uvl model, or a .dimacs CNF")
    how = ap.add_mutually_exclusive_group(required=True)
    how.add_argument("--t", type=int, choices=[1, 2], help="t-wise covering sample (1 or 2)")
    how.add_argument("--uniform", type=int, metavar="N", help="N products uniformly at random")
    ap.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    ap.add_argument("--include", "-i", action="append", default=[], metavar="F", help="only products with F")
    ap.add_argument("--exclude", "-x", action="append", default=[], metavar="F", help="only products without F")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--timeout", type=float, default=None, metavar="S", help="give up after S seconds")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    if args.uniform is not None and args.uniform < 0:
        print("tvl-lsp sample: --uniform needs a number >= 0", file=sys.stderr)
        return 2
    from ...analysis.counting import CountTimeout
    from ...analysis.engine import ModelAnalysis
    from .count import report_errors
    t0 = time.monotonic()
    try:
        from ...base.files import read_text  # regular files only, within the size cap
        text = read_text(args.model)
        if args.model.endswith((".dimacs", ".cnf")):
            a, errors = ModelAnalysis.from_dimacs(text, args.model), []
        else:
            from ...analysis.formats import parse_any_model
            res = parse_any_model(text, args.model)  # TVL or UVL
            if res.model is None:
                raise ValueError("no model could be read")
            a, errors = ModelAnalysis(res.model), res.errors
    except OSError as ex:
        print(f"tvl-lsp sample: cannot read {args.model}: {getattr(ex, 'reason', None) or ex.strerror}", file=sys.stderr)
        return 2
    except ValueError as ex:
        print(f"tvl-lsp sample: {args.model}: {ex}", file=sys.stderr)
        return 2
    from .count import _TvlModel
    report_errors("tvl-lsp sample", args.model, _TvlModel(a), errors)
    enc = a.encoding
    for name in args.include + args.exclude:
        if enc.feature_by_name(name) is None:
            print(f"tvl-lsp sample: no feature named {name!r} in {args.model}", file=sys.stderr)
            return 2
    try:
        configs, engine = a.sample(t=args.t, uniform=args.uniform, seed=args.seed, include=args.include,
                                   exclude=args.exclude, timeout=args.timeout)
    except CountTimeout:
        print(f"tvl-lsp sample: no sample within {args.timeout:g} s", file=sys.stderr)
        return 2
    except ValueError as ex:
        print(f"tvl-lsp sample: {ex}", file=sys.stderr)
        return 2
    if not configs:
        print("tvl-lsp sample: no product matches", file=sys.stderr)
    if args.json:
        print(json.dumps({"model": args.model, "configurations": configs, "size": len(configs),
                          "engine": engine, "t": args.t, "uniform": args.uniform, "seed": args.seed,
                          "include": args.include, "exclude": args.exclude,
                          "seconds": round(time.monotonic() - t0, 3)}))
    else:
        for c in configs:
            print(" ".join(k for k, v in c.items() if v))
    return 0 if configs else 1
