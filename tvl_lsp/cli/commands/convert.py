"""``tvl-lsp convert IN OUT [--verify] [--force]``

Converts a feature model between formats, chosen by the files' extensions: ``.tvl``, ``.uvl``,
``.dimacs`` (or ``.cnf``) -- TVL -> UVL, UVL -> TVL, TVL / UVL -> DIMACS (with FeatureIDE's
``c <var> <Feature>`` lines), and DIMACS -> TVL / UVL.  ``OUT`` may be ``-`` (standard output;
give the format with ``--to``).  The number of products is preserved (see
:mod:`tvl_lsp.analysis.convert`); ``--verify`` counts both models and says whether they agree.
What the target format cannot hold is kept as comments and listed as notes on standard error.

Exit status: 0 converted (and, with ``--verify``, the counts agree); 1 the input has errors (not
converted unless ``--force``), the conversion is not exact, or the counts differ; 2 usage or
unreadable input.
"""

from __future__ import annotations

import argparse
import sys


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp convert",
                                 description="Convert a feature model between TVL, UVL and DIMACS "
                                             "(formats from the extensions).")
    ap.add_argument("input", help="a .tvl, .uvl or .dimacs model")
    ap.add_argument("output", help="the file to write (.tvl, .uvl, .dimacs); '-' for standard output")
    ap.add_argument("--to", choices=["tvl", "uvl", "dimacs"], help="the output format (default: from OUT's extension)")
    ap.add_argument("--verify", action="store_true", help="count the products of both models and compare")
    ap.add_argument("--force", action="store_true", help="convert even if the input has errors")
    ap.add_argument("--timeout", type=float, default=None, metavar="S", help="for --verify: give up counting after S s")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    from ...analysis.convert import ConvertError, convert_model
    from ...analysis.formats import model_format, parse_any_model
    src_fmt = model_format(args.input)
    dst_fmt = args.to or (model_format(args.output) if args.output != "-" else None)
    if src_fmt is None:
        print(f"tvl-lsp convert: {args.input}: unknown format (use .tvl, .uvl or .dimacs)", file=sys.stderr)
        return 2
    if dst_fmt is None:
        print(f"tvl-lsp convert: {args.output}: unknown format (use .tvl, .uvl or .dimacs, or --to)", file=sys.stderr)
        return 2
    if src_fmt == dst_fmt:
        print(f"tvl-lsp convert: {args.input} is already {src_fmt.upper()}", file=sys.stderr)
        return 2
    try:
        from ...base.files import read_text  # regular files only, within the size cap
        text = read_text(args.input)
    except OSError as ex:
        print(f"tvl-lsp convert: cannot read {args.input}: {getattr(ex, 'reason', None) or ex.strerror}", file=sys.stderr)
        return 2
    res = parse_any_model(text, args.input)
    if res.errors:
        for d in res.errors[:20]:
            print(f"{d.path}:{d.span.start}: error: {d.message} [{d.code}]", file=sys.stderr)
        if not args.force:
            print(f"tvl-lsp convert: {args.input} has errors: not converted (--force converts what could be read)",
                  file=sys.stderr)
            return 1
    try:
        conv = convert_model(res.model, dst_fmt)
    except ConvertError as ex:
        print(f"tvl-lsp convert: {ex}", file=sys.stderr)
        return 1
    for n in conv.notes:
        print(f"tvl-lsp convert: note: {n}", file=sys.stderr)
    if args.output == "-":
        sys.stdout.write(conv.text)
    else:
        from ...base.safewrite import write_output
        try:  # atomic, never through a link
            write_output(args.output, conv.text)
        except OSError as ex:
            print(f"tvl-lsp convert: {ex}", file=sys.stderr)
            return 2
    status = 0 if conv.exact else 1
    if args.verify:
        from ...analysis.counting import CountTimeout
        from ...analysis.engine import ModelAnalysis
        try:
            a = ModelAnalysis(res.model).count(timeout=args.timeout)
            out = parse_any_model(conv.text, args.output if args.output != "-" else f"out.{dst_fmt}",
                                  fmt=dst_fmt, read_file=lambda p: None)
            b = ModelAnalysis(out.model).count(timeout=args.timeout)
        except CountTimeout:
            print("tvl-lsp convert: --verify: no count within the time limit", file=sys.stderr)
            return 1
        if out.errors:
            print(f"tvl-lsp convert: --verify: the converted model has errors: {out.errors[0].message}",
                  file=sys.stderr)
            return 1
        same = a == b
        print(f"tvl-lsp convert: products: {a} ({src_fmt}), {b} ({dst_fmt}): {'same' if same else 'DIFFERENT'}",
              file=sys.stderr)
        if not same:
            status = 1
    return status
