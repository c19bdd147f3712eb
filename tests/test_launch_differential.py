"""Differential test against the real roslaunch (Debian's python3-roslaunch, /usr/bin/python3).

For the thesis's generic launch files and our own fixtures, and every assignment of the
feature args (a fixed sample when there are many), the nodes tvl-lsp says are loaded
(both the concrete loader and the symbolic analysis evaluated at the assignment) equal
what roslaunch loads, and where roslaunch raises a load error tvl-lsp predicts one.
"""

from __future__ import annotations

import itertools
import json
import os
import random
import re
import subprocess
from pathlib import Path

import pytest

from tvl_lsp.analysis.formula import evaluate
from tvl_lsp.launch import analyse_launch, find_packages, load_launch

HERE = Path(__file__).resolve().parent
SHARED = Path(__file__).resolve().parents[1].parent / "shared"
THESIS_WS = SHARED / "corpus" / "thesis" / "ws" / "src"
OWN_WS = HERE / "data" / "launch" / "ws" / "src"
ORACLE = HERE / "launch_oracle.py"
SYS_PY = "/usr/bin/python3"


def _have_roslaunch() -> bool:
    if not os.path.exists(SYS_PY):
        return False
    r = subprocess.run([SYS_PY, "-c", "import roslaunch.xmlloader, roslaunch.config"], capture_output=True)
    return r.returncode == 0


pytestmark = pytest.mark.skipif(not _have_roslaunch(), reason="/usr/bin/python3 cannot import roslaunch")

ANON = re.compile(r"_anon\d+")


def _norm(names):
    return sorted(ANON.sub("_anon", n) for n in names)


def _oracle(jobs):
    r = subprocess.run([SYS_PY, str(ORACLE)], input=json.dumps(jobs), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def _assignments(free, limit=24, seed=7):
    if len(free) <= 5:
        return [dict(zip(free, bits)) for bits in itertools.product([False, True], repeat=len(free))]
    rnd = random.Random(seed)
    out = [dict.fromkeys(free, True), dict.fromkeys(free, False)]
    out += [{f: rnd.random() < 0.5 for f in free} for _ in range(limit - 2)]
    return out


def _files(ws: Path):
    return sorted(str(p) for p in ws.glob("*/launch/*.launch"))


CASES = [(f, THESIS_WS, {}) for f in _files(THESIS_WS)]
# the turtlebot file reads two environment variables; also run it with them set
CASES += [(str(THESIS_WS / "turtlebot_bringup" / "launch" / "generic.launch"), THESIS_WS,
           {"TURTLEBOT_SIMULATION": "false", "TURTLEBOT_SERIAL_PORT": "/dev/ttyUSB0"})]
CASES += [(f, OWN_WS, {}) for f in _files(OWN_WS)]


@pytest.mark.parametrize("path,ws,extra_env", CASES,
                         ids=[f"{Path(c[0]).parent.parent.name}/{Path(c[0]).name}{'+env' if c[2] else ''}"
                              for c in CASES])
def test_same_nodes_and_errors_as_roslaunch(path, ws, extra_env):
    env = {k: v for k, v in os.environ.items() if not k.startswith("TURTLEBOT_")}
    env.update(extra_env)
    pk = find_packages(str(ws))
    text = Path(path).read_text()
    analysis = analyse_launch(text, path, packages=pk, env=env)
    assigns = _assignments(analysis.free_args)
    jobs = [dict(file=path, args={k: str(v).lower() for k, v in a.items()}, package_path=str(ws),
                 env=extra_env) for a in assigns]
    results = _oracle(jobs)
    checked_ok = checked_err = 0
    for a, job, o in zip(assigns, jobs, results):
        lr = load_launch(path, job["args"], packages=pk, env=env)
        sym_nodes = _norm(n.name for n in analysis.nodes if not n.is_test and evaluate(n.condition, a))
        sym_errs = [f for f in analysis.facts if f.severity == 1 and evaluate(f.condition, a)]
        where = f"{path} {job['args']}"
        if o["ok"]:
            checked_ok += 1
            assert lr.error is None, (where, lr.error)
            assert _norm(n["name"] for n in lr.nodes) == _norm(o["nodes"]), where
            assert sym_nodes == _norm(o["nodes"]), where
            assert not sym_errs, (where, [(f.code, f.message) for f in sym_errs])
        else:
            checked_err += 1
            assert lr.error is not None, (where, o)
            if o["error"] != "ResourceNotFound":
                # a reason inside the workspace: the symbolic analysis predicts it too
                assert sym_errs, (where, o)
    assert checked_ok + checked_err == len(assigns)
