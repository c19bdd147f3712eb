"""``tvl-lsp launch FILE [name:=value ...] [--json] [--workspace DIR] [--dialect ros1|ros2] [--strict-packages]``

Prints what roslaunch (ROS 1) or ros2 launch (ROS 2: .launch.xml / .launch.yaml / .launch.py)
would start from FILE under these args, without starting anything: the resolved nodes (full
name, package, executable, namespace, remaps, params), the include tree, or the error launch
would raise (exit status 1).

ROS 2: ``$(find-pkg-share pkg)`` of a workspace package is its source folder; a package that is
neither in the workspace nor in ``AMENT_PREFIX_PATH`` counts as installed with an empty share
folder (``--strict-packages``: launch's "package not found" error instead).  Python launch
files are interpreted, never executed; where one needs what cannot be known without running
it (a branch on an environment variable that is not set, a call tvl-lsp does not model), the
answer is "not analysable" with the file and line that stop it (exit status 1), never a guess.
The actions of event handlers (``RegisterEventHandler(OnProcessExit(...))``) start only when a
process starts or exits: they are listed apart, under "events" (``--json``: ``events``).  The
dialect of a ``.launch.xml`` file is detected (``--dialect`` forces it).

ROS 1: ``$(find pkg)`` finds what roslaunch finds, the packages of the workspace (the one
``--check`` uses for FILE, unless ``--workspace`` names it) and of ``ROS_PACKAGE_PATH``, with
roslaunch's precedence (:func:`tvl_lsp.launch.packages.ros_packages`).

ROS 1 with --json: "params" maps each parameter to the value roslaunch sets (typed as roslaunch
types it: numbers, booleans, strings, YAML lists and maps), except those in "param_sources"
(textfile / binfile / command), given by path or command line.
"""

from __future__ import annotations

import json
import os
import sys

from ...launch import dialect_of, load_launch
from ...launch.model import json_value


def main(argv: list[str]) -> int:
    as_json = False
    workspace = None
    dialect = None
    strict = False
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
        elif a == "--dialect" and i + 1 < len(argv) and argv[i + 1] in ("ros1", "ros2"):
            i += 1
            dialect = argv[i]
        elif a.startswith("--dialect=") and a.split("=", 1)[1] in ("ros1", "ros2"):
            dialect = a.split("=", 1)[1]
        elif a == "--strict-packages":
            strict = True
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
        print("usage: tvl-lsp launch FILE [name:=value ...] [--json] [--workspace DIR] [--dialect ros1|ros2] "
              "[--strict-packages]", file=sys.stderr)
        return 2
    path = os.path.abspath(path)
    if dialect is None:
        dialect = dialect_of(path).dialect
    if dialect == "ros2":
        return _ros2(path, args, workspace, as_json, strict)
    if workspace is None:  # the workspace --check finds for this file: one package resolver for both
        from ...project.workspace import find_workspace_root
        workspace = find_workspace_root(path)
    res = load_launch(path, args, workspace_root=workspace)
    if as_json:
        out = {"file": path, "args": args, "nodes": res.nodes,
               "params": {k: json_value(v) for k, v in res.params.items()},
               "param_sources": res.param_sources, "remaps": res.remaps,
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
            for k in sorted(res.params):
                src = res.param_sources.get(k)
                print(f"  {k} = {res.param_text.get(k, res.params[k])}" + (f"  ({src})" if src else ""))
        if res.includes:
            print("includes:")

            def show(incs, depth):
                for inc in incs:
                    state = "" if inc["followed"] else ("  (not read: outside the workspace)" if inc.get("outside")
                                                        else "  (not followed)")
                    print("  " + "  " * depth + f"{inc['file']} [ns {inc['namespace']}]{state}")
                    show(inc["includes"], depth + 1)
            show(res.includes, 0)
        for wmsg in res.warnings:
            print(f"warning: {wmsg}")
    return 1 if res.error is not None else 0


def _ros2(path: str, args: dict, workspace, as_json: bool, strict: bool) -> int:
    from ...launch.ros2 import load_launch2
    res = load_launch2(path, args, workspace_root=workspace, stub_packages=not strict)
    if as_json:
        print(json.dumps(res.to_json(), indent=2, sort_keys=False, default=str))
        return 1 if res.error is not None else 0
    print("nodes:")
    for n in res.nodes:
        what = f"{n['package']}/{n['executable']}" if n["executable"] else f"{n['package']} (composable)"
        ns = n["namespace"] or "/"
        print(f"  {n['name'] or '(named by the executable)'}  ({what}, ns {ns})")
        for f_, t_ in n["remaps"]:
            print(f"      remap {f_} -> {t_}")
        for k, v in n["params"].items():
            print(f"      param {k} = {v!r}")
        for f_ in n["param_files"]:
            print(f"      params from {f_}")
    if res.executables:
        print("executables:")
        for e in res.executables:
            print(f"  {e['process_name']}: {' '.join(e['cmd'])}")
    if res.includes:
        print("includes:")

        def show(incs, depth):
            for inc in incs:
                state = "" if inc["followed"] else ("  (not read: outside the workspace)" if inc.get("outside")
                                                    else "  (not followed)")
                print("  " + "  " * depth + f"{inc['file']}{state}")
                show(inc["includes"], depth + 1)
        show(res.includes, 0)
    if res.events:
        print("events (their actions start only when a process starts / exits at run time):")
        for ev in res.events:
            target = f" of {ev['target']}" if ev["target"] else ""
            print(f"  {ev['event']}{target} (line {ev['line']}):")
            for n in ev["nodes"]:
                print(f"    {n['name'] or '(named by the executable)'}  ({n['package']}/{n['executable']})")
            if ev["not_analysed"]:
                print(f"    not analysed: {ev['not_analysed']}")
    for wmsg in res.warnings:
        print(f"warning: {wmsg}")
    if res.error is not None:
        where = f" ({os.path.relpath(res.error_path)}:{res.error_line})" if res.error_path else ""
        if res.error_type == "NotAnalysed":
            print(f"not analysable{where}: {res.error} -- what ros2 launch starts from here on is not known "
                  f"[{res.error_code}]")
        else:
            print(f"error: {res.error} [{res.error_code}]{where}")
    return 1 if res.error is not None else 0
