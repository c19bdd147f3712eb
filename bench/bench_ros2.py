#!/usr/bin/env python3
"""ROS 2 launch files of a workspace: how fast tvl-lsp analyses them, and (with the oracle) how
often its answers equal the real ros2/launch's.

    .venv/bin/python bench/bench_ros2.py --workspace WS                 # timing only
    ROS2_ORACLE=.../ros2-launch-oracle ROS2_ORACLE_VENV=... \\
        .venv/bin/python bench/bench_ros2.py --workspace WS --oracle    # + comparison

For every ``*.launch.xml`` / ``*.launch.yaml`` / ``*_launch.xml`` under ``WS/src``: the symbolic
analysis (all boolean args at once, as ``--check`` runs it) and the concrete load with the
defaults.  With ``--oracle``, each file also runs through the oracle (``--stub-missing-packages``,
under ``env -i``) with up to three argument sets -- the defaults (args without a default get
``dummy``, or ``true`` for ``use_``/``enable``/``launch_`` names), every boolean default flipped,
and half of them flipped -- and the nodes (full name, package, executable), remaps and error of
``load_launch2`` are compared with the oracle's.  With ``--symbolic``, the symbolic analysis
(what ``--check`` reasons on) is also evaluated at each run's args (see ``symbolic_agrees``).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tvl_lsp.launch.ros2 import actions as A  # noqa: E402
from tvl_lsp.launch.ros2 import analyse_launch2, load_launch2  # noqa: E402
from tvl_lsp.launch.ros2.frontend import parse_launch_file  # noqa: E402

SUFFIXES = (".launch.xml", ".launch.yaml", ".launch.yml", "_launch.xml", "_launch.yaml")
ENV = {"PATH": "/usr/bin:/bin", "HOME": "/tmp"}
FLIP = {"true": "false", "false": "true", "True": "False", "False": "True"}


def launch_files(ws: Path, any_name: bool = False) -> list[Path]:
    """The ROS 2 launch files of a workspace by name; with ``any_name``, also every ``.xml`` /
    ``.yaml`` / ``.launch`` file in a ``launch`` folder that tvl-lsp reads as ROS 2 launch
    (``*_launch_all_hw.xml``, mavros's ``*.launch`` ...)."""
    from tvl_lsp.launch import dialect_of
    base = ws / "src" if (ws / "src").is_dir() else ws
    out = []
    for d, dn, fn in os.walk(base):
        dn[:] = sorted(x for x in dn if not x.startswith(".") and x not in ("build", "install", "log"))
        for f in sorted(fn):
            p = Path(d) / f
            if f.endswith(SUFFIXES):
                out.append(p)
            elif any_name and "launch" in p.parts and f.endswith((".xml", ".yaml", ".launch")) \
                    and f != "package.xml":
                try:
                    text = p.read_text(errors="replace")
                except OSError:
                    continue
                if ("<launch" in text or text.lstrip().startswith("launch:")) and dialect_of(str(p), text).ros2:
                    out.append(p)
    return out


def arg_sets(path: Path, rnd: random.Random) -> list[dict]:
    try:
        doc = parse_launch_file(path.read_text(errors="replace"), str(path))
        acts, _ = A.parse_description(doc.root, str(path)) if doc.root is not None else ([], [])
    except Exception:
        acts = []
    tops = [a for a in acts if isinstance(a, A.ArgA)]
    base = {}
    for a in tops:
        if a.default is None and a.cond is None:
            base[a.name] = a.choices[0] if a.choices else (
                "true" if any(k in a.name for k in ("use_", "enable", "launch_", "with_", "is_")) else "dummy")
    out = [dict(base)]
    bools = [a for a in tops if a.default is not None and a.default.text in FLIP]
    if bools:
        out.append({**base, **{a.name: FLIP[a.default.text] for a in bools}})
        half = {**base, **{a.name: FLIP[a.default.text] for a in bools if rnd.random() < 0.5}}
        if half not in out:
            out.append(half)
    return out


def run_oracle(ws: Path, tasks: list[dict]) -> list[dict]:
    oracle = os.environ.get("ROS2_ORACLE", "ros2-launch-oracle")
    env = dict(ENV, TMPDIR=tempfile.gettempdir())
    if os.environ.get("ROS2_ORACLE_VENV"):
        env["ROS2_ORACLE_VENV"] = os.environ["ROS2_ORACLE_VENV"]
    with tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False) as fh:
        for t in tasks:
            fh.write(json.dumps(t) + "\n")
    try:
        r = subprocess.run([oracle, "--workspace", str(ws), "--stub-missing-packages", "--batch", fh.name],
                           env=env, capture_output=True, text=True)
    finally:
        os.unlink(fh.name)
    if r.returncode != 0:
        raise SystemExit(f"oracle failed: {r.stderr.strip()[:500]}")
    return [json.loads(x) for x in r.stdout.splitlines() if x.strip()]


BOOL_WORDS = ("true", "false", "1", "0")


def symbolic_agrees(ws: Path, run: dict, cache: dict) -> bool | None:
    """The symbolic analysis (what --check reasons on: the file's boolean args free) evaluated at
    the run's args has the oracle's nodes, and an error holds there iff launch failed.  None
    (not compared): a run that gives a non-boolean arg (the analysis has no value for it), or one
    the oracle fails on a Python include or on a file of a package outside the workspace (the
    analysis notes these rather than reporting an error)."""
    from tvl_lsp.base.formula import evaluate, variables
    from tvl_lsp.launch.ros2.api import free_args2
    want, path, given = run["result"], run["file"], run["args"]
    e = want["error"] or ""
    if "Python launch file" in e or f"{ws}/install/share/" in e:
        return None  # (a file of a package the oracle stubs, outside the workspace: --check notes it)
    if "not found on the PATH" in e:
        return None  # $(find-exec X) of a program the oracle's machine lacks: --check cannot know
    if any(v.strip().lower() not in BOOL_WORDS for v in given.values()):
        return None
    text = Path(path).read_text(errors="replace")
    doc = parse_launch_file(text, path)
    acts = A.parse_description(doc.root, path)[0] if doc.root is not None else []
    free = set(free_args2(text, path)) | set(given)
    assign = {a.name: given.get(a.name, a.default.text if a.default is not None else "false").strip().lower()
              in ("true", "1") for a in acts if isinstance(a, A.ArgA) and a.name in free}
    feats = tuple(sorted(assign))
    if (path, feats) not in cache:
        cache[(path, feats)] = analyse_launch2(text, path, workspace_root=str(ws), env=ENV, features=list(feats))
    la = cache[(path, feats)]

    def holds(c):
        return evaluate(c, {v: assign.get(v, False) for v in variables(c)})
    got = [(n.name or None, n.package, n.executable or None) for n in la.nodes if holds(n.condition)]
    exp = [(n["name"], n["package"], n["executable"]) for n in want["nodes"]]
    errors = [f for f in la.facts if (f.severity == 1 or f.code == "unset-arg") and holds(f.condition)]
    errors += [x for x in la.diagnostics if x.severity == 1]
    if want["error"] is None:
        return got == exp and not errors
    return bool(errors) and got[:len(exp)] == exp


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", required=True, help="a ROS 2 workspace (packages under src/)")
    ap.add_argument("--oracle", action="store_true", help="also compare with ros2-launch-oracle")
    ap.add_argument("--any-name", action="store_true",
                    help="also files in launch/ folders with other names that tvl-lsp reads as ROS 2 launch")
    ap.add_argument("--symbolic", action="store_true",
                    help="with --oracle: also evaluate the symbolic analysis at each run's args (slower)")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every disagreement")
    ns = ap.parse_args(argv)
    ws = Path(ns.workspace).resolve()
    files = launch_files(ws, ns.any_name)
    if not files:
        print(f"no ROS 2 launch files under {ws}", file=sys.stderr)
        return 2
    sym, conc = [], []
    for f in files:
        text = f.read_text(errors="replace")
        t = time.perf_counter()
        analyse_launch2(text, str(f), workspace_root=str(ws), env=ENV, lenient=True)
        sym.append((time.perf_counter() - t, f))
        t = time.perf_counter()
        load_launch2(str(f), {}, workspace_root=str(ws), env=ENV, text=text)
        conc.append((time.perf_counter() - t, f))
    for label, xs in (("symbolic analysis", sym), ("concrete load", conc)):
        ts = sorted(x for x, _ in xs)
        print(f"{label}: {len(ts)} files, total {sum(ts):.1f} s, median {ts[len(ts) // 2] * 1000:.0f} ms, "
              f"max {ts[-1]:.2f} s ({max(xs)[1].relative_to(ws)})")
    if not ns.oracle:
        return 0
    rnd = random.Random(5)
    tasks = [{"file": str(f), "args": a} for f in files for a in arg_sets(f, rnd)]
    stats = {"runs": 0, "nodes": 0, "remaps": 0, "error": 0, "message": 0, "sym_runs": 0, "sym_equal": 0}
    cache: dict = {}
    for d in run_oracle(ws, tasks):
        agrees = symbolic_agrees(ws, d, cache) if ns.symbolic else None
        if agrees is not None:
            stats["sym_runs"] += 1
            stats["sym_equal"] += agrees
            if ns.verbose and not agrees:
                print("SYMBOLIC DIFFERS", os.path.relpath(d["file"], ws), d["args"], d["result"]["error"])
        r = d["result"]
        res = load_launch2(d["file"], d["args"], workspace_root=str(ws), env=ENV)
        want = [(n["name"], n["package"], n["executable"]) for n in r["nodes"]]
        got = [(n["name"], n["package"], n["executable"]) for n in res.nodes]
        rm_ok = [n["remaps"] for n in r["nodes"]] == [[list(x) for x in n["remaps"]] for n in res.nodes]
        stats["runs"] += 1
        stats["nodes"] += want == got
        stats["remaps"] += want == got and rm_ok
        stats["error"] += (r["error"] is None) == (res.error is None)
        stats["message"] += r["error"] == res.error
        if ns.verbose and (want != got or not rm_ok or (r["error"] is None) != (res.error is None)):
            print("DIFFERS", os.path.relpath(d["file"], ws), d["args"], r["error"], res.error)
    n = stats["runs"]
    print(f"oracle: {n} runs; equal nodes {stats['nodes']}, remaps {stats['remaps']}, error or not "
          f"{stats['error']}, error message {stats['message']} (the oracle's refusal of Python files reads "
          "differently)")
    if ns.symbolic:
        print(f"symbolic analysis at the runs' args (runs with boolean args only): {stats['sym_runs']} runs; "
              f"nodes and error-or-not equal {stats['sym_equal']}")
    return 0 if stats["nodes"] == stats["remaps"] == stats["error"] == n else 1


if __name__ == "__main__":
    sys.exit(main())
