"""Agreement with the real roslaunch (Debian's python3-roslaunch under /usr/bin/python3).

1. Every ``duplicate-node``, ``undefined-arg``, ``duplicate-arg`` (and ``unset-arg``) witness
   that ``tvl-lsp --check`` reports on the test workspace (tests/testenv.py) and on
   tests/data/pairs, passed to roslaunch as ``name:=true|false``, makes roslaunch raise that
   error for that name.
2. Over the products of the paired models (all of them for turtlerand; a fixed sample of the
   crawler's 584 and the scout's 1152 unless TVL_LSP_ALL_PRODUCTS=1), whenever roslaunch raises
   one of these errors, tvl-lsp reported it: a fact of that code and name whose condition holds
   in that product, and the diagnostic is in the ``--check`` output.

Both also run on the thesis's workspace in the corpus suite (``--corpus DIR``).

roslaunch stops at the first problem of any kind, and the files name packages that are not in
the workspace (``$(find xacro)``, ``scout_control``...) and files that do not exist.  So
roslaunch runs on a copy of the files in a sandbox where every ``$(find pkg)/path`` the files
name exists (an empty package, a launch file declaring the args its include passes, an empty
YAML), ``<param command=...>`` programs are not run, and the environment variables they read
are set: only the errors under test remain.
"""

from __future__ import annotations

import json
import os
import random
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from testenv import ROSLAUNCH_MISSING, SYS_PY, have_roslaunch, make_ws
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.base.formula import evaluate
from tvl_lsp.project.check import check_paths, free_top_args
from tvl_lsp.launch import analyse_launch
from tvl_lsp.tvl import parse_model

HERE = Path(__file__).resolve().parent
PAIRS = HERE / "data" / "pairs"

ENV = {"CRAWLER_SIMULATION": "false", "CRAWLER_SERIAL_PORT": "/dev/ttyUSB0", "ROBOT": "robot",
       "TURTLEBOT_SIMULATION": "false", "TURTLEBOT_SERIAL_PORT": "/dev/ttyUSB0"}

DRIVER = r'''
import io, json, os, sys
jobs = json.load(sys.stdin)
os.environ["ROS_PACKAGE_PATH"] = jobs["package_path"]
for k, v in jobs["env"].items():
    os.environ[k] = v
import rospkg
import roslaunch.loader
import roslaunch.substitution_args as sa
from roslaunch.config import ROSLaunchConfig
from roslaunch.xmlloader import XmlLoader
_orig = roslaunch.loader.Loader.param_value
def param_value(self, verbose, name, ptype, value, textfile, binfile, command):
    if command is not None:   # do not run programs: the value does not matter here
        return ""
    return _orig(self, verbose, name, ptype, value, textfile, binfile, command)
roslaunch.loader.Loader.param_value = param_value
out = []
for job in jobs["runs"]:
    sa._rospack = rospkg.RosPack()
    argv = ["roslaunch", job["file"]] + ["%s:=%s" % kv for kv in sorted(job["args"].items())]
    cfg = ROSLaunchConfig()
    so, se = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = io.StringIO(), io.StringIO()
    try:
        loader = XmlLoader()
        loader.ignore_unset_args = False   # as roslaunch's load_config_default sets it
        loader.load(job["file"], cfg, argv=argv, verbose=False)
        res = {"ok": True}
    except BaseException as e:
        res = {"ok": False, "error": type(e).__name__, "message": str(e)[:400]}
    finally:
        sys.stdout, sys.stderr = so, se
    out.append(res)
print(json.dumps(out))
'''


pytestmark = pytest.mark.skipif(not have_roslaunch(), reason=ROSLAUNCH_MISSING)

# the workspaces: ours, and the thesis's (corpus suite)
WORKSPACES = ["repo", pytest.param("thesis", marks=pytest.mark.corpus)]


@pytest.fixture(scope="module")
def ws(request, tmp_path_factory) -> Path:
    if request.param == "repo":
        return make_ws(tmp_path_factory.mktemp("repo") / "ws")
    return request.getfixturevalue("corpus_dir") / "thesis" / "ws"

FIND = re.compile(r"\$\(find ([^)\s]+)\)(/[^\s'\"<>]*)?")
INCLUDE = re.compile(r"<include\b[^>]*?file=\"([^\"]+)\"[^>]*?(/>|>(.*?)</include>)", re.S)
ARG_NAME = re.compile(r"<arg\s+name=\"([^\"]+)\"")


def _classify(message: str):
    """roslaunch's message -> (kind, name) for the errors under test."""
    m = re.search(r"multiple nodes named \[([^\]]+)\]", message)
    if m:
        return "duplicate-node", m.group(1)
    m = re.search(r"arg '([^']+)' has already been declared", message)
    if m:
        return "duplicate-arg", m.group(1)
    m = re.search(r"requires the '([^']+)' arg to be set|arg '([^']+)' is not defined", message)
    if m:
        return "arg-not-set", m.group(1) or m.group(2)
    return None, None


KIND = {"duplicate-node": "duplicate-node", "duplicate-arg": "duplicate-arg",
        "undefined-arg": "arg-not-set", "unset-arg": "arg-not-set"}


@pytest.fixture(scope="module")
def sandbox(ws, tmp_path_factory):
    """A copy of the workspace and of tests/data/pairs where every $(find) resolves."""
    root = tmp_path_factory.mktemp("rosws")
    shutil.copytree(ws / "src", root / "src")
    shutil.copytree(PAIRS, root / "pairs")
    stubs = root / "stubs"
    stubs.mkdir()
    pkgs = {p.parent.name: p.parent for p in (root / "src").glob("*/package.xml")}
    launches = list((root / "src").rglob("*.launch")) + list((root / "pairs").rglob("*.launch"))
    for lf in launches:
        text = lf.read_text()
        passed: dict[str, set[str]] = {}
        for m in INCLUDE.finditer(text):
            passed.setdefault(m.group(1), set()).update(ARG_NAME.findall(m.group(3) or ""))
        for m in FIND.finditer(text):
            pkg, rest = m.group(1), (m.group(2) or "").lstrip("/")
            folder = pkgs.get(pkg)
            if folder is None:
                folder = stubs / pkg
                folder.mkdir(exist_ok=True)
                (folder / "package.xml").write_text(
                    f"<package format='2'><name>{pkg}</name><version>0.0.0</version>"
                    "<description>stub</description><maintainer email='a@b.c'>a</maintainer>"
                    "<license>BSD</license></package>")
                pkgs[pkg] = folder
            if not rest or "$(" in rest:
                continue
            target = folder / rest
            if target.exists():
                continue
            target.parent.mkdir(parents=True, exist_ok=True)
            if rest.endswith((".launch", ".xml")):
                args = set()
                for inc, names in passed.items():
                    if inc.startswith(m.group(0)) or inc == m.group(0):
                        args |= names
                body = "".join(f'  <arg name="{a}" default=""/>\n' for a in sorted(args))
                target.write_text(f"<launch>\n{body}</launch>\n")
            elif rest.endswith((".yaml", ".yml")):
                target.write_text("{}\n")
            else:
                target.write_text("")
    return root


def _roslaunch(sandbox: Path, runs: list[dict]) -> list[dict]:
    payload = {"package_path": f"{sandbox / 'src'}:{sandbox / 'stubs'}", "env": ENV, "runs": runs}
    r = subprocess.run([SYS_PY, "-c", DRIVER], input=json.dumps(payload), capture_output=True, text=True,
                       timeout=600, env={**os.environ, "ROS_PACKAGE_PATH": payload["package_path"], **ENV})
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout)


def _in_sandbox(sandbox: Path, ws: Path, path: str) -> str:
    p = Path(path)
    try:
        return str(sandbox / "src" / p.relative_to(ws / "src"))
    except ValueError:
        return str(sandbox / "pairs" / p.relative_to(PAIRS))


def _args(witness: dict) -> dict:
    return {k: "true" if v else "false" for k, v in witness.items()}


def _name_of(d) -> str:
    if d.data and d.data.get("arg"):
        return d.data["arg"]
    if d.code == "duplicate-node":
        return re.search(r"named \[([^\]]+)\]", d.message).group(1)
    return re.search(r"'([^']+)'", d.message.split("]", 1)[-1] if d.message.startswith("[") else d.message).group(1)


@pytest.fixture(scope="module")
def reported(ws):
    diags = check_paths([str(ws), str(PAIRS / "robot"), str(PAIRS / "alone"), str(PAIRS / "clean"),
                         str(PAIRS / "nav")], jobs=1)
    return [d for d in diags if d.code in KIND and d.witness is not None]


@pytest.mark.parametrize("ws", WORKSPACES, indirect=True)
def test_every_witness_makes_roslaunch_raise_that_error(ws, sandbox, reported):
    assert {d.code for d in reported} >= {"duplicate-node", "undefined-arg", "duplicate-arg", "unset-arg"}
    relevant = [d for d in reported if d.code != "unset-arg" or "battery" in d.message]
    runs = [{"file": _in_sandbox(sandbox, ws, d.path), "args": _args(d.witness)} for d in relevant]
    results = _roslaunch(sandbox, runs)
    for d, res in zip(relevant, results):
        assert not res["ok"], (d.path, d.code, d.witness)
        kind, name = _classify(res["message"])
        assert kind == KIND[d.code], (d.message, res["message"])
        # a later undeclared arg of a value is its own problem, but roslaunch stops at the
        # first one of that value (the problem's data and related information say which)
        assert name == (d.data or {}).get("stops_at", _name_of(d)), (d.message, res["message"])


def _paired(ws_name, lf, mf, sample):
    return pytest.param(ws_name, lf, mf, sample, id=f"{ws_name}:{lf}",
                        marks=[pytest.mark.corpus] if ws_name == "thesis" else [])


PAIRED = [  # (workspace, launch file, model, sample size or None for every product); "pairs/": tests/data/pairs
    _paired("repo", "src/turtlerand/launch/generic.launch", "src/turtlerand/launch/generic.tvl", None),
    _paired("repo", "src/turtlerand/launch/generic_alt.launch", "src/turtlerand/launch/generic_alt.tvl", None),
    _paired("repo", "src/crawler_bringup/launch/generic.launch", "src/crawler/models/crawler.tvl", 40),
    _paired("repo", "src/scout/launch/generic.launch", "src/scout/launch/generic.tvl", 40),
    _paired("repo", "pairs/robot/robot.launch", "pairs/robot/robot.tvl", None),
    _paired("repo", "pairs/nav/nav.launch", "pairs/nav/nav.tvl", None),
    _paired("thesis", "src/turtlerand/launch/generic.launch", "src/turtlerand/launch/generic.tvl", None),
    _paired("thesis", "src/turtlerand/launch/generic_alt.launch", "src/turtlerand/launch/generic_alt.tvl", None),
    _paired("thesis", "src/turtlebot_bringup/launch/generic.launch", "src/turtlebot/launch/turtlebot.tvl", 40),
    _paired("thesis", "src/lizi/launch/generic.launch", "src/lizi/launch/generic.tvl", 40),
]


@pytest.mark.parametrize("ws,lf,mf,sample", PAIRED, indirect=["ws"])
def test_roslaunch_raises_nothing_tvl_lsp_did_not_report(ws, sandbox, reported, lf, mf, sample):
    lf, mf = ((PAIRS.parent / p if p.startswith("pairs/") else ws / p) for p in (lf, mf))
    launch = str(lf)
    res = parse_model(mf.read_text(), str(mf))
    ma = ModelAnalysis(res.model)
    products = list(ma.enumerate(limit=None))
    if sample is not None and os.environ.get("TVL_LSP_ALL_PRODUCTS") != "1" and len(products) > sample:
        products = random.Random(5).sample(products, sample)
    text = lf.read_text()
    enc = ma.encoding
    features = [enc.name_of(f) for f in enc.features]
    features += [n for n in free_top_args(text, str(lf)) if enc.feature_by_name(n) is None]
    la = analyse_launch(text, str(lf), features=features)
    runs = [{"file": _in_sandbox(sandbox, ws, str(lf)), "args": _args(p)} for p in products]
    results = _roslaunch(sandbox, runs)
    here = [d for d in reported if d.path == str(lf)]
    raised = 0
    for product, res in zip(products, results):
        if res["ok"]:
            continue
        kind, name = _classify(res["message"])
        if kind is None:
            continue
        raised += 1
        facts = [f for f in la.facts if KIND.get(f.code) == kind and evaluate(f.condition, product)
                 and (f"'{name}'" in f.message or f"[{name}]" in f.message)]
        assert facts, (launch, product, res["message"])
        assert any(KIND[d.code] == kind and _name_of(d) == name for d in here), (launch, res["message"])
    if "lizi" in launch or "scout" in launch or "pairs" in launch:
        assert raised > 0   # scout: the products with Simulation stop on stereo_cam (lizi: Gazebo, depth_cam)
