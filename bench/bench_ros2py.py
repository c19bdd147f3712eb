#!/usr/bin/env python3
"""Python launch files (``.launch.py`` / ``*_launch.py``) of real repositories: tvl-lsp's static
answers against the real ros2/launch, which runs them.

    ROS2_ORACLE=.../ros2-launch-oracle ROS2_ORACLE_VENV=... \\
        .venv/bin/python bench/bench_ros2py.py REPO [REPO ...] [--json OUT] [--details]
    .venv/bin/python bench/bench_ros2py.py REPO ... --no-oracle          # tvl-lsp only (timing, declines)

Each REPO is a folder (a workspace: its packages are found under it).  Every launch file runs with
its defaults, with every boolean default flipped, with half of them flipped, and with a string
variant (the first argument whose default is a plain word gets ``tvl_variant``); an argument
without a default gets ``true`` (``use_*`` / ``enable*`` ...) or ``dummy``.  The oracle runs with
``--allow-python --stub-missing-packages`` under ``env -i`` (it executes the files: run it only on
repositories you trust); tvl-lsp's ``load_launch2`` with the same environment.

A run is:
- ``equal``: both resolve with the same node set (full name, package, executable, remaps), or both
  fail;
- ``declined``: tvl-lsp says it cannot know (``NotAnalysed``, with the construct's line);
- ``wrong``: both resolve with different nodes, or tvl-lsp resolves what the oracle rejects;
- ``false-error``: the oracle resolves, tvl-lsp reports an error;
- ``crash``: tvl-lsp raised.
Targets (issue #25): no wrong, no false error, no crash, and ``equal`` >= 75 % of the runs the
oracle resolves.  Third-party files are read here, never committed.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tvl_lsp.launch.ros2 import load_launch2  # noqa: E402

ENV = {"PATH": "/usr/bin:/bin", "HOME": "/tmp"}
FLIP = {"true": "false", "false": "true", "True": "False", "False": "True"}
SKIP_DIRS = {"build", "install", "log", ".git", "__pycache__"}
_DECL = re.compile(r"DeclareLaunchArgument\(\s*(?:name\s*=\s*)?['\"]([A-Za-z_][\w]*)['\"]"
                   r"(?:(?:(?!DeclareLaunchArgument).){0,600}?default_value\s*=\s*(?:['\"]([^'\"]*)['\"]|()))?", re.S)


def launch_files(repo: Path) -> list[Path]:
    out = []
    for d, dn, fn in os.walk(repo):
        dn[:] = sorted(x for x in dn if x not in SKIP_DIRS and not x.startswith("."))
        for f in sorted(fn):
            if f.endswith((".launch.py", "_launch.py")):
                out.append(Path(d) / f)
    return out


def declared(text: str) -> list[tuple[str, str | None]]:
    """(name, literal default | "" for a computed one | None for none) of each DeclareLaunchArgument."""
    seen = {}
    for m in _DECL.finditer(text):
        d = m.group(2) if m.group(2) is not None else ("" if m.group(3) is not None else None)
        seen.setdefault(m.group(1), d)
    return list(seen.items())


def arg_sets(text: str) -> list[tuple[str, dict]]:
    decl = declared(text)
    base = {}
    for n, d in decl:
        if d is None:
            base[n] = "true" if re.match(r"(use|enable|launch|with|start|run)_?", n, re.I) else "dummy"
    bools = [(n, d) for n, d in decl if d in FLIP]
    out = [("defaults", dict(base))]
    if bools:
        out.append(("flip_all", {**base, **{n: FLIP[d] for n, d in bools}}))
        if len(bools) > 1:
            out.append(("flip_half", {**base, **{n: FLIP[d] for n, d in bools[::2]}}))
    words = [(n, d) for n, d in decl if d and d not in FLIP and re.fullmatch(r"[A-Za-z][\w]*", d)]
    if words:
        out.append(("string", {**base, words[0][0]: "tvl_variant"}))
    return out


def run_oracle(repo: Path, tasks: list[dict], timeout: float) -> list[dict]:
    """One oracle process per chunk of tasks; a chunk that times out is run task by task."""
    oracle = os.environ.get("ROS2_ORACLE") or "ros2-launch-oracle"
    env = {"PATH": "/usr/bin:/bin", "HOME": "/tmp", "TMPDIR": tempfile.gettempdir()}
    if os.environ.get("ROS2_ORACLE_VENV"):
        env["ROS2_ORACLE_VENV"] = os.environ["ROS2_ORACLE_VENV"]

    def batch(chunk, tmo):
        with tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False) as fh:
            for t in chunk:
                fh.write(json.dumps({"file": t["file"], "args": t["args"]}) + "\n")
            name = fh.name
        try:
            r = subprocess.run([oracle, "--workspace", str(repo), "--allow-python", "--stub-missing-packages",
                                "--batch", name], env=env, capture_output=True, text=True, timeout=tmo,
                               stdin=subprocess.DEVNULL)
            lines = [json.loads(x) for x in r.stdout.splitlines() if x.strip().startswith("{")]
            if len(lines) != len(chunk):
                raise RuntimeError(f"oracle gave {len(lines)} answers for {len(chunk)} tasks: {r.stderr[-500:]}")
            return lines
        finally:
            os.unlink(name)
    out = []
    for i in range(0, len(tasks), 20):
        chunk = tasks[i:i + 20]
        try:
            out += batch(chunk, timeout * len(chunk))
        except (subprocess.TimeoutExpired, RuntimeError):
            for t in chunk:
                try:
                    out += batch([t], timeout)
                except (subprocess.TimeoutExpired, RuntimeError) as ex:
                    out.append({"exit_code": -1, "result": {"error": f"oracle: {type(ex).__name__}",
                                                            "error_type": "OracleTimeout", "nodes": []}})
    return out


def key(nodes: list[dict]) -> list:
    return sorted((n.get("name") or "", n.get("package") or "", n.get("executable") or "",
                   tuple(tuple(r) for r in n.get("remaps") or [])) for n in nodes)


def classify(ours, oracle: dict) -> str:
    if isinstance(ours, Exception):
        return "crash"
    res = oracle["result"]
    resolved = oracle["exit_code"] == 0
    if ours.error_type == "NotAnalysed":
        return "declined"
    if not resolved:
        return "equal" if ours.error is not None else "wrong"
    if ours.error is not None:
        return "false-error"
    return "equal" if key(ours.nodes) == key(res["nodes"]) else "wrong"


def tvl_nodes(ours) -> list:
    return [{"name": n["name"], "package": n["package"], "executable": n["executable"], "remaps": n["remaps"]}
            for n in ours.nodes]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("repos", nargs="+")
    ap.add_argument("--no-oracle", action="store_true")
    ap.add_argument("--json", help="write every run's classification here")
    ap.add_argument("--details", action="store_true", help="print every wrong / false-error / crash run")
    ap.add_argument("--timeout", type=float, default=30.0, help="oracle seconds per run")
    ap.add_argument("--check", action="store_true",
                    help="also run tvl-lsp --check over each repository: errors on a Python launch file the oracle "
                         "resolves with its defaults are false errors")
    ns = ap.parse_args(argv)
    total = collections.Counter()
    all_runs = []
    reasons = collections.Counter()
    print(f"{'repository':42} {'files':>5} {'runs':>5} {'resolved':>8} {'equal':>6} {'eq%':>6} {'declined':>8} "
          f"{'wrong':>5} {'f-err':>5} {'crash':>5} {'ms/run':>7}")
    for repo in ns.repos:
        repo = Path(repo).resolve()
        files = launch_files(repo)
        tasks = []
        for f in files:
            text = f.read_text(errors="replace")
            for label, args in arg_sets(text):
                tasks.append({"file": str(f), "args": args, "label": label})
        ours = []
        t0 = time.process_time()
        for t in tasks:
            try:
                ours.append(load_launch2(t["file"], t["args"], workspace_root=str(repo), env=ENV, stub_packages=True))
            except Exception as ex:  # a crash is a finding
                ex.tb = traceback.format_exc()
                ours.append(ex)
        cpu = time.process_time() - t0
        oracle = run_oracle(repo, tasks, ns.timeout) if not ns.no_oracle else [None] * len(tasks)
        c = collections.Counter()
        for t, o, r in zip(tasks, ours, oracle):
            if r is None:
                cls = "crash" if isinstance(o, Exception) else ("declined" if o.error_type == "NotAnalysed" else
                                                                "error" if o.error else "resolved")
            else:
                cls = classify(o, r)
                if r["exit_code"] == 0:
                    c["resolved"] += 1
                    if cls == "equal":
                        c["equal_resolved"] += 1
            c[cls] += 1
            if cls == "declined":
                why = re.sub(r"'[^']*'|\"[^\"]*\"|\d+", "_", o.error.split(": ", 1)[-1])[:110]
                reasons[why] += 1
            run = {"repo": repo.name, "file": str(Path(t["file"]).relative_to(repo)), "label": t["label"],
                   "args": t["args"], "class": cls}
            if isinstance(o, Exception):
                run["crash"] = o.tb
            else:
                run.update(tvl_error=o.error, tvl_error_type=o.error_type, tvl_line=o.error_line,
                           tvl_nodes=tvl_nodes(o))
            if r is not None:
                run.update(oracle_exit=r["exit_code"], oracle_error=r["result"].get("error"),
                           oracle_error_type=r["result"].get("error_type"),
                           oracle_nodes=[{k: n.get(k) for k in ("name", "package", "executable", "remaps")}
                                         for n in r["result"].get("nodes", [])])
            all_runs.append(run)
            if ns.details and cls in ("wrong", "false-error", "crash"):
                print(json.dumps(run, indent=1)[:4000])
        if ns.check:
            from tvl_lsp.project.check import check_paths
            t1 = time.time()
            diags = check_paths([str(repo)], jobs=1)
            resolved_defaults = {str(Path(t["file"])) for t, r in zip(tasks, oracle)
                                 if t["label"] == "defaults" and r is not None and r["exit_code"] == 0}
            errs = [d for d in diags if d.severity == 1 and d.path.endswith(".py")]
            bad = [d for d in errs if d.path in resolved_defaults]
            c["check_errors"] = len(errs)
            c["check_false"] = len(bad)
            print(f"  --check: {len(diags)} diagnostics, {len(errs)} errors on .py files, {len(bad)} on files the "
                  f"oracle resolves with defaults ({time.time() - t1:.1f} s)")
            for d in bad:
                print(f"    FALSE ERROR {d.path}:{d.span.start.line + 1}: [{d.code}] {d.message[:200]}")
            if ns.details:
                for d in errs:
                    if d not in bad:
                        print(f"    error {d.path}:{d.span.start.line + 1}: [{d.code}] {d.message[:160]}")
        total.update(c)
        res = c["resolved"]
        eq = c["equal_resolved"]
        pct = f"{100 * eq / res:5.1f}" if res else "  -  "
        print(f"{repo.name[:42]:42} {len(files):5} {len(tasks):5} {res:8} {c['equal']:6} {pct:>6} {c['declined']:8} "
              f"{c['wrong']:5} {c['false-error']:5} {c['crash']:5} {1000 * cpu / max(len(tasks), 1):7.1f}")
    res = total["resolved"]
    pct = f"{100 * total['equal_resolved'] / res:5.1f}" if res else "  -  "
    print(f"{'TOTAL':42} {'':5} {sum(total[k] for k in ('equal', 'declined', 'wrong', 'false-error', 'crash', 'resolved', 'error') if k != 'resolved'):5} "
          f"{res:8} {total['equal']:6} {pct:>6} {total['declined']:8} {total['wrong']:5} {total['false-error']:5} "
          f"{total['crash']:5}")
    if reasons:
        print("\ndeclined, by reason:")
        for why, n in reasons.most_common(40):
            print(f"  {n:4}  {why}")
    if ns.json:
        Path(ns.json).write_text(json.dumps(all_runs, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
