#!/usr/bin/env python3
"""Regenerate (or check) the ROS 2 golden files: what the real ros2/launch says about our fixtures.

    ROS2_ORACLE=/path/to/ros2-launch-oracle ROS2_ORACLE_VENV=/path/to/venv \\
        python scripts/ros2_golden.py [--data tests/data/ros2py] [--check] [--only NAME ...]

The oracle (``ros2-launch-oracle``, a driver for the real ros2/launch and launch_ros) is not part
of this repository and never runs in CI: it lives on the developers' machines (see
``tests/data/ros2/README.md``).  This script runs it on every case of
``tests/data/ros2/cases.txt`` and on every product of each generic launch file listed there,
and writes its JSON answers to ``tests/data/ros2/golden/<name>.json``; the tests compare
``tvl-lsp``'s ROS 2 front end with these files.  ``--check`` compares instead of writing
(exit 1 on a difference).  ``--data`` names another fixture folder of the same layout
(``tests/data/ros2py``: the Python launch files, whose cases run with ``--allow-python`` --
only ever on these fixtures, which are ours).

Runs happen under ``env -i`` with a fixed environment (``ORACLE_ENV`` below), so that
``$(env ...)`` resolves the same everywhere; the tests use the same environment.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "ros2"
WS = DATA / "ws"
GOLDEN = DATA / "golden"
CASES = DATA / "cases.txt"
# the environment of every oracle run (and of the tests that compare with it)
ORACLE_ENV = {"R2_ROBOT": "burger"}


def read_cases(path: Path = CASES) -> list[dict]:
    """``name | [--option ...] FILE [name:=value ...]`` lines; ``\\x20`` in a value is a blank.
    ``@products NAME FILE MODEL`` expands to one case per product of MODEL (features as
    ``name:=true|false``)."""
    out = []
    for line in path.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("@products"):
            words = line.split()
            options = [w for w in words if w.startswith("--")]
            _, name, file, model = [w for w in words if not w.startswith("--")]
            for i, product in enumerate(_products(WS / "src" / model)):
                out.append(dict(name=f"{name}_{i:02d}", options=options, file=file,
                                args={k: "true" if v else "false" for k, v in product.items()}))
            continue
        name, rest = (x.strip() for x in line.split("|", 1))
        words = rest.split()
        options = [w for w in words if w.startswith("--")]
        words = [w for w in words if not w.startswith("--")]
        args = {}
        for w in words[1:]:
            k, v = w.split(":=", 1)
            args[k] = v.replace("\\x20", " ")
        out.append(dict(name=name, options=options, file=words[0], args=args))
    return out


def _products(model: Path) -> list[dict[str, bool]]:
    sys.path.insert(0, str(ROOT))
    from tvl_lsp.project.facts import generation_products
    text = model.read_text()
    return generation_products(str(model), {str(model): text}, {}, "all", 1000)


def run_oracle(cases: list[dict], oracle: str) -> dict[str, dict]:
    """name -> {"exit_code", "result"} (one oracle process per set of options)."""
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": os.environ.get("HOME", "/tmp"),
           "TMPDIR": tempfile.gettempdir(), **ORACLE_ENV}
    if os.environ.get("ROS2_ORACLE_VENV"):
        env["ROS2_ORACLE_VENV"] = os.environ["ROS2_ORACLE_VENV"]
    groups: dict[tuple, list[dict]] = {}
    for c in cases:
        groups.setdefault(tuple(c["options"]), []).append(c)
    out = {}
    for options, group in groups.items():
        with tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False) as fh:
            for c in group:
                fh.write(json.dumps({"file": str(WS / "src" / c["file"]), "args": c["args"]}) + "\n")
            tasks = fh.name
        try:
            r = subprocess.run([oracle, "--workspace", str(WS), "--relative-paths", *options, "--batch", tasks],
                               env=env, capture_output=True, text=True, timeout=3600)
        finally:
            os.unlink(tasks)
        if r.returncode != 0:
            raise SystemExit(f"oracle failed ({r.returncode}): {r.stderr}")
        lines = [json.loads(x) for x in r.stdout.splitlines() if x.strip()]
        for c, line in zip(group, lines):
            out[c["name"]] = {"case": {"file": c["file"], "args": c["args"], "options": list(options)},
                              "exit_code": line["exit_code"], "result": line["result"]}
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="compare with golden/ instead of writing it")
    ap.add_argument("--only", nargs="*", help="only these case names (prefixes)")
    ap.add_argument("--data", help="the fixture folder (default tests/data/ros2)")
    ns = ap.parse_args(argv)
    if ns.data:
        global DATA, WS, GOLDEN, CASES
        DATA = Path(ns.data).resolve()
        WS, GOLDEN, CASES = DATA / "ws", DATA / "golden", DATA / "cases.txt"
    oracle = os.environ.get("ROS2_ORACLE") or "ros2-launch-oracle"
    cases = read_cases(CASES)
    if ns.only:
        cases = [c for c in cases if any(c["name"].startswith(p) for p in ns.only)]
    results = run_oracle(cases, oracle)
    GOLDEN.mkdir(exist_ok=True)
    bad = 0
    for name, got in results.items():
        path = GOLDEN / f"{name}.json"
        text = json.dumps(got, indent=1, sort_keys=False) + "\n"
        if ns.check:
            if not path.exists() or json.loads(path.read_text()) != got:
                bad += 1
                print(f"DIFFERS {name}")
        else:
            path.write_text(text)
    if not ns.check:
        wanted = {f"{n}.json" for n in results}
        if not ns.only:
            for p in GOLDEN.glob("*.json"):
                if p.name not in wanted:
                    p.unlink()
        print(f"wrote {len(results)} golden files to {GOLDEN.relative_to(ROOT)}")
    else:
        print(f"{len(results) - bad} equal, {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
