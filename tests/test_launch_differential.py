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

from tvl_lsp.base.formula import evaluate
from tvl_lsp.launch import analyse_launch, find_packages, load_launch

HERE = Path(__file__).resolve().parent
SHARED = Path(__file__).resolve().parents[1].parent / "shared"
THESIS_WS = SHARED / "corpus" / "thesis" / "ws" / "src"
OWN_WS = HERE / "data" / "launch" / "ws" / "src"
ORACLE = HERE / "data" / "launch" / "roslaunch_oracle.py"
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


CASES = [(f, THESIS_WS, ()) for f in _files(THESIS_WS)]
# the turtlebot file reads two environment variables; also run it with them set
CASES += [(str(THESIS_WS / "turtlebot_bringup" / "launch" / "generic.launch"), THESIS_WS,
           (("TURTLEBOT_SIMULATION", "false"), ("TURTLEBOT_SERIAL_PORT", "/dev/ttyUSB0")))]
CASES += [(f, OWN_WS, ()) for f in _files(OWN_WS)]


def _prepare(path, ws, extra_env):
    env = {k: v for k, v in os.environ.items() if not k.startswith("TURTLEBOT_")}
    env.update(dict(extra_env))
    pk = find_packages(str(ws))
    analysis = analyse_launch(Path(path).read_text(), path, packages=pk, env=env)
    assigns = _assignments(analysis.free_args)
    jobs = [dict(file=path, args={k: str(v).lower() for k, v in a.items()}, package_path=str(ws),
                 env=dict(extra_env)) for a in assigns]
    return env, pk, analysis, assigns, jobs


@pytest.fixture(scope="module")
def oracle_results():
    """One roslaunch process for all files (its start-up dominates)."""
    all_jobs = []
    for case in CASES:
        all_jobs.extend(_prepare(*case)[4])
    results = iter(_oracle(all_jobs))
    return {case: [next(results) for _ in _prepare(*case)[4]] for case in CASES}


@pytest.mark.parametrize("path,ws,extra_env", CASES,
                         ids=[f"{Path(c[0]).parent.parent.name}/{Path(c[0]).name}{'+env' if c[2] else ''}"
                              for c in CASES])
def test_same_nodes_and_errors_as_roslaunch(path, ws, extra_env, oracle_results):
    env, pk, analysis, assigns, jobs = _prepare(path, ws, extra_env)
    results = oracle_results[(path, ws, extra_env)]
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
            assert sorted(lr.params) == sorted(o["params"]), where
            assert not sym_errs, (where, [(f.code, f.message) for f in sym_errs])
        else:
            checked_err += 1
            assert lr.error is not None, (where, o)
            if o["error"] != "ResourceNotFound":
                # a reason inside the workspace: the symbolic analysis predicts it too
                assert sym_errs, (where, o)
    assert checked_ok + checked_err == len(assigns)


# ---------------------------------------------------------------- launch files nobody has seen

FEATS = ["A", "B", "C"]

def _cond(r):
    k = r.random()
    f = r.choice(FEATS)
    if k < 0.35: return f' if="$(arg {f})"'
    if k < 0.55: return f' unless="$(arg {f})"'
    if k < 0.62: g = r.choice(FEATS); return f' if="$(eval arg(\'{f}\') and not {g})"'
    if k < 0.66: return f' if="$(eval {f} or {r.choice(FEATS)})"'
    if k < 0.68: return ' if="$(arg mode)"'
    return ""

def _gen(r, depth=0, names=None, inc_ok=True):
    out = []
    for _ in range(r.randint(1, 4)):
        k = r.random()
        if k < 0.35:
            nm = r.choice(["a", "b", "c", "d", "$(arg side)", "x_$(arg side)", "$(anon q)"])
            ns = r.choice(["", "", ' ns="n1"', ' ns="/abs"', ' ns="$(arg side)"', ' ns=""'])
            extra = r.choice(["", "", ' respawn="true"', ' required="$(arg A)"', ' respawn="$(arg B)"'])
            out.append(f'<node pkg="alpha_pkg" type="t" name="{nm}"{ns}{extra}{_cond(r)}/>')
        elif k < 0.55 and depth < 3:
            ns = r.choice(["", "", ' ns="g1"', ' ns="$(arg side)"'])
            out.append(f'<group{ns}{_cond(r)}>' + "".join(_gen(r, depth + 1, names, inc_ok)) + '</group>')
        elif k < 0.68:
            nm = r.choice(["side", "mode", "extra", "v"])
            kind = r.choice(["value", "default", "value"])
            val = r.choice(["left", "right", "true", "false", "maybe", "$(arg A)", "$(arg extra)"])
            out.append(f'<arg name="{nm}" {kind}="{val}"{_cond(r)}/>')
        elif k < 0.78 and inc_ok:
            args = ""
            for a in r.sample(["robot", "rate", "fast", "bogus"], r.randint(0, 3)):
                v = r.choice(["r1", "$(arg side)", "true", "$(arg C)", "2"])
                args += f'<arg name="{a}" value="{v}"{_cond(r) if r.random() < .3 else ""}/>'
            pa = ' pass_all_args="true"' if r.random() < 0.15 else ""
            target = r.choice(["part.launch", "part.launch", "all_args.launch"])
            out.append(f'<include file="$(find beta)/launch/{target}"{pa}{r.choice(["", _cond(r)])}>{args}</include>')
        elif k < 0.81:
            out.append(r.choice([
                f'<rosparam{_cond(r)}>{{k: 1, m: {{n: 2}}}}</rosparam>',
                f'<rosparam param="lst"{_cond(r)}>[1, 2]</rosparam>',
                f'<rosparam{_cond(r)}>3</rosparam>',
                f'<env name="E" value="$(optenv HOME x)"{_cond(r)}/>',
                f'<test test-name="t{r.randint(0, 3)}" pkg="alpha_pkg" type="t"{_cond(r)}/>',
                f'<node pkg="alpha_pkg" type="t" name="$(eval \'e\' + str(arg(\'A\')))"{_cond(r)}/>',
                f'<group ns="cp" clear_params="true"{_cond(r)}><node pkg="alpha_pkg" type="t" name="cp"/></group>',
                f'<node pkg="alpha_pkg" type="t" name="w" clear_params="true"{_cond(r)}><param name="z" value="1"/></node>',
                f'<machine name="m1" address="localhost"{_cond(r)}/>',
                f'<arg name="dflt" default="$(arg nope)"{_cond(r)}/>',
                f'<node pkg="alpha_pkg" type="t" name="o" output="$(arg side)"{_cond(r)}/>',
            ]))
        elif k < 0.88:
            out.append(f'<param name="{r.choice(["p", "~q", "/r"])}" value="{r.choice(["1", "$(arg side)", "x"])}"{_cond(r)}/>')
        else:
            out.append(f'<remap from="a" to="{r.choice(["b", "$(arg side)"])}"{_cond(r)}/>')
    return out

def _make(seed):
    r = random.Random(seed)
    head = "".join(f'<arg name="{f}"/>' for f in FEATS)
    pre = '<arg name="side" value="left" if="$(arg A)"/><arg name="side" value="right" unless="$(arg A)"/>' if r.random() < 0.7 else ""
    return f"<launch>{head}{pre}" + "".join(_gen(r)) + "</launch>\n"



def test_random_generic_launch_files_against_roslaunch(tmp_path):
    """Random generic launch files (groups, namespaces, conditional and paired args, includes
    with args and pass_all_args, evals, anon names, params, rosparam, tests, ...) under all 8
    assignments of their three features: same nodes and params as roslaunch, and a predicted
    error wherever roslaunch fails."""
    pk = find_packages(str(OWN_WS))
    jobs, meta = [], []
    for seed in range(40):
        p = str(tmp_path / f"g{seed}.launch")
        Path(p).write_text(_make(seed))
        for bits in itertools.product([False, True], repeat=3):
            a = dict(zip(FEATS, bits))
            jobs.append(dict(file=p, args={k: str(v).lower() for k, v in a.items()}, package_path=str(OWN_WS)))
            meta.append((p, a))
    results = _oracle(jobs)
    analyses = {}
    n_ok = 0
    for (p, a), job, o in zip(meta, jobs, results):
        if p not in analyses:
            analyses[p] = analyse_launch(Path(p).read_text(), p, packages=pk, features=FEATS)
        an = analyses[p]
        lr = load_launch(p, job["args"], packages=pk)
        sym_nodes = _norm(x.name for x in an.nodes if evaluate(x.condition, a) and not x.is_test)
        sym_errs = [x for x in an.facts if x.severity == 1 and evaluate(x.condition, a)]
        where = (Path(p).read_text(), a, o)
        if o["ok"]:
            n_ok += 1
            assert lr.error is None and not sym_errs, (where, lr.error, [x.message for x in sym_errs])
            assert _norm(x["name"] for x in lr.nodes) == _norm(o["nodes"]) == sym_nodes, where
            assert sorted(lr.params) == sorted(o["params"]), where
        else:
            assert lr.error is not None and sym_errs, where
    assert 0 < n_ok < len(jobs)  # both outcomes are exercised
