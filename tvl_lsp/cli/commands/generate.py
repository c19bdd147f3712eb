"""``tvl-lsp generate LAUNCH [--model MODEL] [--out DIR] [--mode all|completions|one|sample] [--t 2]
[--seed S] [--budget S] [--limit N] [--include F]... [--exclude F]... [--format auto|xml|python] [--dry-run]``

Writes configuration launch files (the thesis's Listing 6.1) for the products of the model
paired with a generic launch file: each sets the feature args to true/false and includes the
generic file through ``$(find pkg)``.  The same pure functions as the language server's
"generate configuration launch files" action (``tvl_lsp.project.generate``).  Files are named after
the selected features, written under ``--out`` (default: ``configs`` in the launch file's
package), never outside the workspace.  Prints one written path per line.

``--mode sample --t 2`` writes a pairwise covering sample: every valid pair of features (A
with B, A without B, ...) is in some file -- the test matrix a robot's CI can afford when all
products are millions (``--t 1``: every feature on and off; ``--t 3``: every valid triple).
``--limit`` does not apply to a sample unless given (cutting a sample short loses coverage: a
warning says so); ``--budget S`` stops the sampler after S seconds and writes what it has, with
a warning and exit code 1.

``--format``: the launch format of the files: ``auto`` (default) and ``xml``: the generic file's
dialect's XML -- roslaunch XML, or ros2 XML, also for a ``.launch.py`` generic file (an XML file
that includes it with the product's arguments) --, or ``python`` (ROS 2: a ``.launch.py`` that
includes the generic file, XML, YAML or Python, with the args set).
"""

from __future__ import annotations

import argparse
import os
import sys


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp generate",
                                 description="Write configuration launch files for the products of a model.")
    ap.add_argument("launch", help="the generic launch file")
    ap.add_argument("--model", help="the model (default: the one paired with the launch file)")
    ap.add_argument("--out", help="output folder (absolute, or relative to the launch file's package)")
    ap.add_argument("--mode", choices=["all", "completions", "one", "sample"], default="completions",
                    help="all products, every completion of --include/--exclude (default), one, "
                         "or a t-wise sample")
    ap.add_argument("--t", type=int, choices=[1, 2, 3], default=2, help="with --mode sample: 1, 2 (default) or 3")
    ap.add_argument("--seed", type=int, default=0, help="with --mode sample: random seed (default 0)")
    ap.add_argument("--budget", type=float, default=None, metavar="S",
                    help="with --mode sample: stop sampling after S seconds (partial sample, exit code 1)")
    ap.add_argument("--format", choices=["auto", "xml", "python"], default="auto",
                    help="launch format of the files (default: XML of the generic file's dialect)")
    ap.add_argument("--limit", type=int, default=None,
                    help="at most this many files (default 100; no limit for a sample)")
    ap.add_argument("--include", "-i", action="append", default=[], metavar="F")
    ap.add_argument("--exclude", "-x", action="append", default=[], metavar="F")
    ap.add_argument("--workspace", help="workspace root (default: found from the launch file)")
    ap.add_argument("--dry-run", action="store_true", help="print the files instead of writing them")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0

    from ...project.facts import generation_products
    from ...project.generate import GenerateError, plan_configurations, resolve_folder, writer_for
    from ...launch import analyse_any
    from ...project.generate import ros2_choices
    from ...analysis.formats import parse_any_model as parse_model
    from ...project.workspace import find_workspace_root, load_workspace, norm

    launch = norm(args.launch)
    if not os.path.isfile(launch):
        print(f"tvl-lsp generate: cannot read {args.launch}", file=sys.stderr)
        return 2
    root = norm(args.workspace) if args.workspace else find_workspace_root(launch)
    ws = load_workspace([root])
    model = norm(args.model) if args.model else None
    if model is None:
        pairings, _ = ws.pair(launch)
        models = [p.model for p in pairings if p.model]
        if not models:
            print(f"tvl-lsp generate: {args.launch} is paired with no model; pass --model", file=sys.stderr)
            return 2
        model = models[0]
    try:
        from ...base.files import read_text  # regular files only, within the size cap
        mtext = read_text(model)
        ltext = read_text(launch)
    except OSError as ex:
        print(f"tvl-lsp generate: {ex}", file=sys.stderr)
        return 2
    res = parse_model(mtext, model)
    if res.model is None or res.model.root is None:
        print(f"tvl-lsp generate: {model} has no root feature", file=sys.stderr)
        return 1
    sources = dict(res.model.sources or {})
    sources[model] = mtext
    decisions = {f: True for f in args.include}
    decisions.update({f: False for f in args.exclude})
    limit = args.limit if args.limit is not None else (None if args.mode == "sample" else 100)
    partial = None
    try:
        if args.mode == "sample":
            from ...project.facts import sample_products
            products, partial = sample_products(model, sources, decisions, t=args.t, seed=args.seed,
                                                budget=args.budget)
        else:
            products = generation_products(model, sources, decisions, args.mode, max(1, limit or 1),
                                           t=args.t, seed=args.seed)
    except KeyError as ex:
        print(f"tvl-lsp generate: {ex.args[0] if ex.args else ex}", file=sys.stderr)
        return 2
    if partial is not None:
        print(f"tvl-lsp generate: sampling stopped by the budget ({args.budget:g} s): {len(products)} "
              f"configurations cover {100 * partial.coverage:.2f}% of the interactions ({partial.left} not covered "
              "yet, none of them known to be invalid); a larger --budget completes it", file=sys.stderr)
    analysis = analyse_any(ltext, launch, workspace_root=root)
    names = {f.name for f in res.model.features} | {f.long_name for f in res.model.features}
    features = [a.name for a in analysis.feature_args if a.name in names and getattr(a, "value", None) is None]
    package = ws.package_of(launch)
    try:
        out_dir = resolve_folder(args.out, launch, [root])
        if args.mode == "sample" and limit is not None and len(products) > limit:
            print(f"tvl-lsp generate: the {args.t}-wise sample has {len(products)} configurations; writing "
                  f"the first {limit} only (--limit), so some pairs are not covered", file=sys.stderr)
        files = plan_configurations(products, features, launch, out_dir, [root], package,
                                    ws.packages.get(package) if package else None,
                                    limit=limit if args.mode == "sample" else None,
                                    omit=[res.model.root.name], dialect=analysis.dialect,
                                    choices=ros2_choices(analysis, res.model),
                                    writer=writer_for(analysis.dialect, launch, args.format))
    except GenerateError as ex:
        print(f"tvl-lsp generate: {ex}", file=sys.stderr)
        return 2
    if not files:
        print("tvl-lsp generate: no product matches", file=sys.stderr)
        return 1
    if args.dry_run:
        for f in files:
            print(f"==> {f.path}")
            print(f.text)
        return 1 if partial is not None else 0
    from ...project.generate import write_configurations
    try:  # atomic, never through a link, inside the workspace (tvl_lsp.base.safewrite)
        written = write_configurations(files, [root])
    except OSError as ex:
        from ...base.safewrite import WriteError, summary
        for p in getattr(ex, "written", []):
            print(p)
        print(f"tvl-lsp generate: {summary(ex, len(files)) if isinstance(ex, WriteError) else ex}", file=sys.stderr)
        return 2
    for p in written:
        print(p)
    return 1 if partial is not None else 0
