"""``tvl-lsp launch FILE [name:=value ...] [--json] [--workspace DIR]``

Prints what roslaunch would load from FILE under these args: the resolved nodes (name,
pkg, type, namespace), params, remaps and the include tree, or the load error roslaunch
would raise (exit status 1).
"""

from __future__ import annotations

import json
import os
import sys

from ...launch import load_launch


def main(argv: list[str]) -> int:
    as_json = False
    workspace = None
    path = None
    args: dict[str, str] = {}
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print(__doc__)
            return 0
        if a == "--json":
            as_json = True
        elif a == "--workspace" and i + 1 < len(argv):
            i += 1
            workspace = argv[i]
        elif a.startswith("--workspace="):
            workspace = a.split("=", 1)[1]
        elif ":=" in a and path is not None:
            k, v = a.split(":=", 1)
            args[k] = v
        elif path is None:
            path = a
        else:
            print(f"tvl-lsp launch: unexpected argument {a!r} (args are name:=value)", file=sys.stderr)
            return 2
        i += 1
    if path is None:
        print("usage: tvl-lsp launch FILE [name:=value ...] [--json] [--workspace DIR]", file=sys.stderr)
        return 2
    path = os.path.abspath(path)
    res = load_launch(path, args, workspace_root=workspace)
    if as_json:
        out = {"file": path, "args": args, "nodes": res.nodes, "params": res.params, "remaps": res.remaps,
               "includes": res.includes, "warnings": res.warnings}
        if res.error is not None:
            out["error"] = res.error
            out["error_code"] = res.error_code
        print(json.dumps(out, indent=2, sort_keys=False))
    else:
        if res.error is not None:
            print(f"error: {res.error} [{res.error_code}]")
        print("nodes:")
        for n in res.nodes:
            extra = f" args={n['args']!r}" if n["args"] else ""
            print(f"  {n['name']}  ({n['pkg']}/{n['type']}, ns {n['namespace']}){extra}")
            for f_, t_ in n["remaps"]:
                print(f"      remap {f_} -> {t_}")
        if res.params:
            print("params:")
            for k, v in sorted(res.params.items()):
                print(f"  {k} = {v}")
        if res.includes:
            print("includes:")

            def show(incs, depth):
                for inc in incs:
                    state = "" if inc["followed"] else "  (not followed: outside the workspace)"
                    print("  " + "  " * depth + f"{inc['file']} [ns {inc['namespace']}]{state}")
                    show(inc["includes"], depth + 1)
            show(res.includes, 0)
        for wmsg in res.warnings:
            print(f"warning: {wmsg}")
    return 1 if res.error is not None else 0
