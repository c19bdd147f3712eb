"""``tvl-lsp sample MODEL (--t 1|2|3 | --uniform N) [--seed S] [--include F]... [--exclude F]...
[--budget S] [--iterations K] [--jobs J] [--format text|json|github-matrix]``

Products of a model to test with:

- ``--t 2``: a pairwise covering sample -- every valid pair of feature literals (A with B, A
  without B, ...) occurs in some configuration; ``--t 3``: every valid triple; ``--t 1``: every
  feature both selected and left out, where the model allows it.  Usually far fewer
  configurations than products (docs/sampling.md: how, and figures on industrial models).
- ``--uniform N``: N products drawn uniformly at random (with replacement) from all of them.

Every configuration is a product of the model (within ``--include`` / ``--exclude``).  The
same ``--seed`` (default 0) gives the same sample, whatever ``--jobs``.  ``--budget S``: stop
after S seconds (wall clock) with what is there: a t-wise sample cut short is printed all the
same, with a warning saying the coverage reached and the interactions left, and the exit code is
1.  ``--iterations K``: K independent runs (other seeds), the smallest sample kept (default: as
many as are cheap -- 32 for a robot's model, 4 for busybox, 1 for automotive01); ``--jobs J``
runs them in J processes.

Output (``--format``): ``text`` one line per configuration, its selected features; ``json`` one
object ``{"configurations": [{feature: bool, ...}, ...], "complete": ..., "coverage": ...}``
(``--json`` is short for it); ``github-matrix`` one line of JSON usable as a GitHub Actions
``strategy.matrix``: ``{"include": [{"config": "c01", "args": "A:=true B:=false ...",
"A": true, "B": false, ...}, ...]}`` (README: an example workflow).

Exit code: 0 a sample, 1 no product matches or the sample is incomplete (budget), 2 usage or
a model that cannot be read.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

GITHUB_MATRIX_MAX = 256  # GitHub Actions runs at most this many jobs of one matrix


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp sample", description="Sample the products of a feature model.")
    ap.add_argument("model", help="a .tvl or .uvl model, or a .dimacs CNF")
    how = ap.add_mutually_exclusive_group(required=True)
    how.add_argument("--t", type=int, choices=[1, 2, 3], help="t-wise covering sample (1, 2 or 3)")
    how.add_argument("--uniform", type=int, metavar="N", help="N products uniformly at random")
    ap.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    ap.add_argument("--include", "-i", action="append", default=[], metavar="F", help="only products with F")
    ap.add_argument("--exclude", "-x", action="append", default=[], metavar="F", help="only products without F")
    ap.add_argument("--format", choices=["text", "json", "github-matrix"], default="text",
                    help="output format (default text)")
    ap.add_argument("--json", action="store_true", help="same as --format json")
    ap.add_argument("--budget", "--timeout", dest="budget", type=float, default=None, metavar="S",
                    help="stop after S seconds with the sample so far (t-wise: partial, exit code 1)")
    ap.add_argument("--iterations", type=int, default=None, metavar="K",
                    help="t-wise: K runs with other seeds, the smallest sample kept (default: as many as "
                         "are cheap for the model, 1 to 32)")
    ap.add_argument("--jobs", "-j", type=int, default=1, metavar="J",
                    help="t-wise: run the iterations in J processes (the sample does not depend on it)")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    if args.json:
        args.format = "json"
    if args.uniform is not None and args.uniform < 0:
        print("tvl-lsp sample: --uniform needs a number >= 0", file=sys.stderr)
        return 2
    if args.budget is not None and args.budget <= 0:
        print("tvl-lsp sample: --budget needs a number of seconds > 0", file=sys.stderr)
        return 2
    if (args.iterations is not None and args.iterations < 1) or args.jobs < 1:
        print("tvl-lsp sample: --iterations and --jobs need a number >= 1", file=sys.stderr)
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
    result = None
    try:
        if args.uniform is not None:
            configs, engine = a.sample(uniform=args.uniform, seed=args.seed, include=args.include,
                                       exclude=args.exclude, timeout=args.budget)
        else:
            configs, result = a.twise_sample(args.t, seed=args.seed, include=args.include, exclude=args.exclude,
                                             budget=args.budget, iterations=args.iterations, jobs=args.jobs)
            engine = "sat"
    except CountTimeout:
        print(f"tvl-lsp sample: no sample within {args.budget:g} s", file=sys.stderr)
        return 2
    except ValueError as ex:
        print(f"tvl-lsp sample: {ex}", file=sys.stderr)
        return 2
    complete = result is None or result.complete
    if not configs:
        print("tvl-lsp sample: no product matches" if complete else
              f"tvl-lsp sample: stopped by the budget ({args.budget:g} s) before the first configuration",
              file=sys.stderr)
    elif not complete:
        print(f"tvl-lsp sample: stopped by the budget ({args.budget:g} s): {len(configs)} configurations cover "
              f"{100 * result.coverage:.2f}% of the {_what(args.t)} ({result.left} not covered yet, none of them "
              "known to be invalid); a larger --budget completes it", file=sys.stderr)
    if args.format == "json":
        out = {"model": args.model, "configurations": configs, "size": len(configs),
               "engine": engine, "t": args.t, "uniform": args.uniform, "seed": args.seed,
               "include": args.include, "exclude": args.exclude,
               "seconds": round(time.monotonic() - t0, 3)}
        if result is not None:
            out.update(_stats(result))
        print(json.dumps(out))
    elif args.format == "github-matrix":
        if len(configs) > GITHUB_MATRIX_MAX:
            print(f"tvl-lsp sample: {len(configs)} configurations: a GitHub Actions matrix runs at most "
                  f"{GITHUB_MATRIX_MAX} jobs (split it, or decide some features with --include/--exclude)",
                  file=sys.stderr)
        print(json.dumps(github_matrix(configs), separators=(",", ":")))
    else:
        for c in configs:
            print(" ".join(k for k, v in c.items() if v))
    return 0 if configs and complete else 1


def _what(t) -> str:
    return {1: "feature literals", 2: "pairs", 3: "triples"}.get(t, "interactions")


def _stats(r) -> dict:
    return {"complete": r.complete, "coverage": r.coverage,
            "interactions": {"covered": r.covered, "left": r.left, "invalid": r.invalid,
                             "over": "representative features (equivalent features counted once)"},
            "features": r.features, "open_features": r.open_features, "representatives": r.representatives,
            "iterations": r.iterations, "stopped": r.stopped, "sat_calls": r.sat_calls}


def github_matrix(configs: list[dict[str, bool]]) -> dict:
    """``{"include": [...]}``: one entry per configuration with every feature's value, a short
    name (``config``: c01, c02, ...) and the launch arguments (``args``: ``A:=true B:=false``,
    for ``roslaunch`` / ``ros2 launch``).  A feature called ``config`` or ``args`` keeps its name;
    the extra key then becomes ``tvl_config`` / ``tvl_args``."""
    width = len(str(len(configs)))
    out = []
    for k, c in enumerate(configs, 1):
        entry: dict = {}
        name_key = "config" if "config" not in c else "tvl_config"
        args_key = "args" if "args" not in c else "tvl_args"
        entry[name_key] = f"c{k:0{width}d}"
        entry.update(c)
        entry[args_key] = " ".join(f"{f}:={'true' if v else 'false'}" for f, v in c.items())
        out.append(entry)
    return {"include": out}
