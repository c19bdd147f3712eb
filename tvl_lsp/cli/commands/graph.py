"""``tvl-lsp graph LAUNCH [--include F]... [--exclude F]... [--format json|dot|mermaid]``

The variability-aware computation graph of a generic launch file: its ROS nodes, topics,
services, parameters and links in every product of its model at once, each with its presence
condition; ``--include`` / ``--exclude`` restrict it to the products with / without features
(certain elements then have no condition, impossible ones are gone).  What each node uses is
read from its package's sources in the workspace (C++ and Python, ``tvl-lsp extract`` shows it)
and from the node hints of the HAROS project file (``nodes:``).  See docs/graph.md.

Exit status: 0; 1 when no product satisfies the decisions; 2 on usage errors (unknown feature,
unreadable file).
"""

from __future__ import annotations

import argparse
import json
import os
import sys


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(
        prog="tvl-lsp graph",
        description="The computation graph (nodes, topics, services, parameters) of a generic launch file "
                    "in all products of its model at once, or in the products left by some decisions.")
    ap.add_argument("launch", help="the generic launch file")
    ap.add_argument("--include", "-i", action="append", default=[], metavar="F",
                    help="only products with feature F (repeatable)")
    ap.add_argument("--exclude", "-x", action="append", default=[], metavar="F",
                    help="only products without feature F (repeatable)")
    ap.add_argument("--format", "-f", choices=("json", "dot", "mermaid"), default="json")
    ap.add_argument("--count", action="store_true",
                    help="count the products that have each element (and the products left)")
    ap.add_argument("--model", metavar="FILE", help="the TVL model (default: the launch file's pairing)")
    ap.add_argument("--project", action="append", default=None, metavar="FILE",
                    help="HAROS project file(s) with the node hints (default: those naming the launch file)")
    ap.add_argument("--workspace", metavar="DIR", help="the workspace folder (default: found from LAUNCH)")
    ap.add_argument("--no-params", action="store_true", help="leave parameters out")
    ap.add_argument("--no-services", action="store_true", help="leave services out")
    ap.add_argument("--no-actions", action="store_true", help="leave actions out")
    ap.add_argument("--no-leaf-topics", action="store_true",
                    help="leave out topics only published or only subscribed to (rqt_graph's \"hide leaf topics\")")
    ap.add_argument("--no-sources", action="store_true",
                    help="do not read what the nodes use from their packages' sources (hints only)")
    ap.add_argument("--output", "-o", metavar="FILE", help="write to FILE instead of standard output")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    from ...graph import NoProducts, UnknownFeature, to_dot, to_json, to_mermaid, view
    from ...project.graph import GraphError, load_graph

    path = os.path.abspath(args.launch)
    if not os.path.isfile(path):
        print(f"tvl-lsp graph: no such file: {args.launch}", file=sys.stderr)
        return 2
    both = set(args.include) & set(args.exclude)
    if both:
        print(f"tvl-lsp graph: {', '.join(sorted(both))} both included and excluded", file=sys.stderr)
        return 2
    decisions = {**{f: True for f in args.include}, **{f: False for f in args.exclude}}
    try:
        ctx = load_graph(path, roots=[args.workspace] if args.workspace else None, model=args.model,
                         project_files=args.project, sources=not args.no_sources)
    except GraphError as ex:
        print(f"tvl-lsp graph: {ex}", file=sys.stderr)
        return 2
    try:
        for d in ctx.hints.diagnostics:
            print(f"{d.path}:{d.span.start}: warning: {d.message} [{d.code}]", file=sys.stderr)
        errors = [d for d in ctx.analysis.diagnostics if d.severity == 1]
        for d in errors[:5]:
            print(f"{d.path}:{d.span.start}: error: {d.message} [{d.code}]", file=sys.stderr)
        if errors:
            print(f"tvl-lsp graph: {os.path.basename(path)} has errors; the graph shows what could be read",
                  file=sys.stderr)
        try:
            g = ctx.project(decisions, count=args.count)
        except UnknownFeature as ex:
            where = os.path.basename(ctx.model_path) if ctx.model_path else "the launch file's args"
            print(f"tvl-lsp graph: {ex} (in {where})", file=sys.stderr)
            return 2
        except NoProducts as ex:
            print(f"tvl-lsp graph: {ex}", file=sys.stderr)
            return 1
    finally:
        ctx.close()
    if ctx.extraction is not None:
        for n in sorted(set(ctx.extraction.notes))[:20]:
            print(f"tvl-lsp graph: note: {n}", file=sys.stderr)
    g = view(g, services=not args.no_services, actions=not args.no_actions, parameters=not args.no_params,
             leaf_topics=not args.no_leaf_topics)
    if args.format == "json":
        out = json.dumps(to_json(g), indent=2) + "\n"
    elif args.format == "dot":
        out = to_dot(g, parameters=not args.no_params)
    else:
        out = to_mermaid(g, parameters=not args.no_params)
    if args.output:
        from ...base.safewrite import write_output
        try:  # atomic, never through a link
            write_output(args.output, out)
        except OSError as ex:
            print(f"tvl-lsp graph: {ex}", file=sys.stderr)
            return 2
    else:
        sys.stdout.write(out)
    return 0
