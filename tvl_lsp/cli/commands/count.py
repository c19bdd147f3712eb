"""``tvl-lsp count MODEL [--include F]... [--exclude F]... [--json] [--timeout S]``

Prints the exact number of products of a TVL model (``.tvl``) or of a DIMACS CNF
(``.dimacs`` / ``.cnf``, imported as a flat model, names from ``c <index> <name>``
comments) on its last line.  Exit code 0 on success, 2 on usage errors, unreadable
input or timeout.
"""

from __future__ import annotations

import argparse
import json
import sys
import time


def _load(path: str):
    from ...analysis.engine import ModelAnalysis
    with open(path, encoding="utf-8", errors="replace") as fh:
        text = fh.read()
    if path.endswith((".dimacs", ".cnf")):
        return ModelAnalysis.from_dimacs(text, path), []
    from ...tvl import parse_model
    res = parse_model(text, path)
    return ModelAnalysis(res.model), res.errors


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp count", description="Exact number of products of a feature model.")
    ap.add_argument("model", help="a .tvl model or a .dimacs CNF")
    ap.add_argument("--include", "-i", action="append", default=[], metavar="F", help="count only products with F")
    ap.add_argument("--exclude", "-x", action="append", default=[], metavar="F", help="count only products without F")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--timeout", type=float, default=None, metavar="S", help="give up after S seconds")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    from ...analysis.count import CountTimeout
    t0 = time.monotonic()
    try:
        an, errors = _load(args.model)
    except OSError as ex:
        print(f"tvl-lsp count: cannot read {args.model}: {ex.strerror}", file=sys.stderr)
        return 2
    except ValueError as ex:
        print(f"tvl-lsp count: {args.model}: {ex}", file=sys.stderr)
        return 2
    if errors:
        for d in errors:
            print(f"{d.path}:{d.span.start}: error: {d.message} [{d.code}]", file=sys.stderr)
        print(f"tvl-lsp count: {args.model} has errors; the count below is for what could be read",
              file=sys.stderr)
    enc = an.encoding
    for name in args.include + args.exclude:
        if enc.feature_by_name(name) is None:
            print(f"tvl-lsp count: no feature named {name!r} in {args.model}", file=sys.stderr)
            return 2
    for d in enc.diagnostics():
        print(f"{d.path}:{d.span.start}: info: {d.message} [{d.code}]", file=sys.stderr)
    try:
        n = an.count(include=args.include, exclude=args.exclude, timeout=args.timeout)
    except CountTimeout:
        if args.json:
            print(json.dumps({"model": args.model, "count": None, "timeout": True}))
        print(f"tvl-lsp count: no answer within {args.timeout:g} s", file=sys.stderr)
        return 2
    dt = time.monotonic() - t0
    if args.json:
        print(json.dumps({"model": args.model, "count": n, "count_text": str(n), "digits": len(str(n)),
                          "include": args.include, "exclude": args.exclude,
                          "features": enc.n_features, "seconds": round(dt, 3)}))
    else:
        print(n)
    return 0
