#!/usr/bin/env python3
"""Record (or check) what the real ros2/launch says about the configuration launch files tvl-lsp
generates for a generic Python launch file: tests/data/ros2py_editor/golden/configs.json.

    ROS2_ORACLE=/path/to/ros2-launch-oracle ROS2_ORACLE_VENV=/path/to/venv \\
        python scripts/ros2py_config_golden.py [--check]

``tvl-lsp generate`` writes one configuration per product of ``clean.tvl`` for
``clean.launch.py`` (an XML file that includes the generic Python file with the product's
arguments) into a scratch copy of the fixture workspace; the oracle (``--allow-python``: it runs
``clean.launch.py``, which is ours) resolves each of them, and the golden file keeps, per
configuration, its name, its text, the product and the oracle's answer (nodes, error).
``tests/test_ros2py_configs.py`` regenerates the files and compares them with these texts, and
the oracle's nodes with the product's nodes as tvl-lsp computes them.  The oracle never runs in
the tests (nor in CI).  ``--check`` compares instead of writing (exit 1 on a difference).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "ros2py_editor"
GOLDEN = DATA / "golden" / "configs.json"
GENERIC = "src/rover/launch/clean.launch.py"


def generate(ws: Path) -> list[Path]:
    """The configurations of every product, as ``tvl-lsp generate`` writes them (in ws)."""
    out = subprocess.run([sys.executable, "-m", "tvl_lsp", "generate", str(ws / GENERIC), "--mode", "all",
                          "--workspace", str(ws), "--out", "configs"], capture_output=True, text=True,
                         cwd=ROOT, check=True)
    return [Path(x) for x in out.stdout.split()]


def run_oracle(ws: Path, files: list[Path], oracle: str) -> list[dict]:
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": os.environ.get("HOME", "/tmp"),
           "TMPDIR": tempfile.gettempdir()}
    if os.environ.get("ROS2_ORACLE_VENV"):
        env["ROS2_ORACLE_VENV"] = os.environ["ROS2_ORACLE_VENV"]
    with tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False) as fh:
        for f in files:
            fh.write(json.dumps({"file": str(f), "args": {}}) + "\n")
        tasks = fh.name
    try:
        r = subprocess.run([oracle, "--workspace", str(ws), "--relative-paths", "--allow-python",
                            "--stub-missing-packages", "--batch", tasks], env=env, capture_output=True, text=True,
                           timeout=3600)
    finally:
        os.unlink(tasks)
    if r.returncode != 0:
        raise SystemExit(f"oracle failed ({r.returncode}): {r.stderr}")
    return [json.loads(x) for x in r.stdout.splitlines() if x.strip()]


def record(oracle: str) -> list[dict]:
    with tempfile.TemporaryDirectory() as tmp:
        ws = Path(tmp) / "ws"
        shutil.copytree(DATA / "ws", ws)
        files = sorted(generate(ws))
        answers = run_oracle(ws, files, oracle)
        out = []
        for f, a in zip(files, answers):
            res = a["result"]
            out.append({"name": f.name, "text": f.read_text(), "exit_code": a["exit_code"],
                        "launch_configurations": res.get("launch_configurations"),
                        "nodes": [{k: n[k] for k in ("name", "package", "executable", "namespace", "remaps", "params")}
                                  for n in res.get("nodes", [])],
                        "error": res.get("error")})
        return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="compare with the golden file instead of writing it")
    ns = ap.parse_args(argv)
    got = record(os.environ.get("ROS2_ORACLE") or "ros2-launch-oracle")
    if ns.check:
        same = GOLDEN.exists() and json.loads(GOLDEN.read_text()) == got
        print("equal" if same else "DIFFERS")
        return 0 if same else 1
    GOLDEN.parent.mkdir(exist_ok=True)
    GOLDEN.write_text(json.dumps(got, indent=1, ensure_ascii=False) + "\n")
    print(f"wrote {len(got)} configurations to {GOLDEN.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
