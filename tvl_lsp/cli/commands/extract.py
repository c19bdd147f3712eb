"""``tvl-lsp extract PATH... [--json]``

What the sources of the ROS packages under the paths make each program use: its publishers,
subscriptions, service servers and clients, action servers and clients, and the parameters it
declares, reads, writes, deletes or searches, with their types and where the code asks for them
(read with tree-sitter; see docs/graph.md, "Where the topics come from").  Names are as the code
asks for them (before the launch file's namespace and remaps); a name the code computes at run
time is *dynamic*: ``{expression}`` stands for each part that is not known before.  Output is
sorted and stable, for CI and for people checking what was read.

Exit status: 0; 2 on usage errors (a path that does not exist, or holds no package and no ROS source).
"""

from __future__ import annotations

import argparse
import json
import os
import sys

ALWAYS = ("package", "executable", "kind", "name", "type", "file", "line", "dynamic")
FIELDS = ("package", "executable", "kind", "name", "type", "file", "line", "col", "end_line", "end_col", "dynamic",
          "expression", "api", "ros", "default", "type_expression", "executable_kind")


def rows(ex) -> list[dict]:
    out = []
    for x in ex.executables:
        for e in x.endpoints:
            d = e.row()
            d["executable_kind"] = x.kind
            out.append({k: d.get(k) for k in FIELDS if k in d or k in ALWAYS})
    out.sort(key=lambda r: (r["package"], r["executable"], r["file"], r["line"], r["col"], r["kind"], r["name"]))
    return out


def to_json(ex) -> dict:
    return {
        "version": 1,
        "packages": [{"name": p.name, "folder": p.folder, "build_type": p.build_type, "ros": p.ros}
                     for p in ex.packages],
        "executables": [{"package": x.package, "executable": x.name, "kind": x.kind, "language": x.language,
                         "aliases": list(x.aliases), "sources": sorted(x.sources), "endpoints": len(x.endpoints)}
                        for x in ex.executables],
        "endpoints": rows(ex),
        "notes": sorted(set(ex.notes)),
    }


def _rel(p: str) -> str:
    try:
        r = os.path.relpath(p)
    except ValueError:
        return p
    return p if r.startswith("..") else r


def to_text(ex) -> str:
    lines = []
    for x in ex.executables:
        if not x.endpoints and x.kind in ("library", "source", "test"):
            continue
        lang = "C++" if x.language == "cpp" else "Python"
        extra = f"; also started as {', '.join(x.aliases)}" if x.aliases else ""
        lines.append(f"{x.package}/{x.name}  ({x.kind}, {lang}, {len(x.sources)} source(s){extra})")
        if not x.endpoints:
            lines.append("  (no endpoints found)")
        width = max([len(e.name) for e in x.endpoints] + [10])
        for e in x.endpoints:
            t = e.type or ("?" if e.type_expression is None else f"? ({e.type_expression})")
            dyn = f"  dynamic: {e.expression}" if e.dynamic else ""
            dflt = f"  default: {e.default}" if e.default is not None and e.kind.startswith("param") else ""
            lines.append(f"  {e.kind:<13} {e.name:<{min(width, 48)}}  {t:<28} {_rel(e.file)}:{e.line}{dyn}{dflt}")
    for n in sorted(set(ex.notes)):
        lines.append(f"note: {n}")
    return "\n".join(lines) + ("\n" if lines else "")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(
        prog="tvl-lsp extract",
        description="The topics, services, actions and parameters each program of the ROS packages under PATH uses, "
                    "read from its C++ and Python sources.")
    ap.add_argument("paths", nargs="+", metavar="PATH", help="a workspace, a folder of packages, or a package")
    ap.add_argument("--json", action="store_true", help="JSON (every endpoint with its package, executable, kind, "
                                                        "name, type, file, line, dynamic)")
    ap.add_argument("--no-cache", action="store_true", help="do not read or write the on-disk cache")
    ap.add_argument("--output", "-o", metavar="FILE", help="write to FILE instead of standard output")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    missing = [p for p in args.paths if not os.path.exists(p)]
    if missing:
        print(f"tvl-lsp extract: no such file or folder: {', '.join(missing)}", file=sys.stderr)
        return 2
    from ...graph.sources import extract
    ex = extract(args.paths, disk=not args.no_cache)
    if not ex.executables:
        print(f"tvl-lsp extract: no ROS package (a folder with a package.xml) and no ROS sources in or around "
              f"{', '.join(args.paths)}", file=sys.stderr)
        return 2
    out = json.dumps(to_json(ex), indent=1, sort_keys=False) + "\n" if args.json else to_text(ex)
    if args.output:
        from ...base.safewrite import write_output
        try:  # atomic, never through a link
            write_output(args.output, out)
        except OSError as ex:
            print(f"tvl-lsp extract: {ex}", file=sys.stderr)
            return 2
    else:
        sys.stdout.write(out)
    return 0
