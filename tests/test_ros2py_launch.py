"""The Python launch-file front end (``.launch.py``) against the real ros2/launch: its answers
on our own fixtures (``tests/data/ros2py``, recorded by ``scripts/ros2_golden.py --data
tests/data/ros2py`` with ``--allow-python``) compared with tvl-lsp's concrete load and its
symbolic analysis; plus what the oracle cannot say: ranges, declines, bad input."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from tvl_lsp.base.formula import evaluate, variables
from tvl_lsp.launch.ros2 import analyse_launch2, free_args2, load_launch2

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "ros2py"
WS = DATA / "ws"
GOLDEN = sorted((DATA / "golden").glob("*.json"))
ENV = {"R2_ROBOT": "burger", "PATH": os.environ.get("PATH", "/usr/bin:/bin")}


def _golden(p: Path) -> dict:
    return json.loads(p.read_text())


def _ws(s):
    if isinstance(s, str):
        return s.replace(str(WS), "$WS")
    if isinstance(s, list):
        return [_ws(x) for x in s]
    if isinstance(s, dict):
        return {k: _ws(v) for k, v in s.items()}
    return s


def _nodes(nodes):
    return [(n["name"], n["package"], n["executable"], [list(r) for r in n["remaps"]]) for n in nodes]


def _load(case: dict):
    return load_launch2(str(WS / "src" / case["file"]), case["args"], workspace_root=str(WS), env=ENV,
                        stub_packages="--stub-missing-packages" in case["options"])


@pytest.mark.parametrize("golden", GOLDEN, ids=[p.stem for p in GOLDEN])
def test_concrete_load_equals_ros2_launch(golden):
    """Nodes (full name, package, executable, remaps), whether launch fails, the declared
    arguments and the launch configurations equal the real ros2/launch's."""
    d = _golden(golden)
    case, want = d["case"], d["result"]
    res = _load(case)
    assert res.error_type != "NotAnalysed", res.error
    assert _nodes(res.nodes) == _nodes(want["nodes"])
    assert (res.error is None) == (want["error"] is None), (res.error, want["error"])
    if want["error"] is None:
        assert {k: _ws(v) for k, v in res.declared.items()} == want["args"]
        want_conf = {k: v for k, v in want["launch_configurations"].items() if k != "ros_namespace"}
        got_conf = {k: _ws(v) for k, v in res.configurations.items()}
        assert {k: got_conf.get(k) for k in want_conf} == want_conf
    elif want.get("error_type") not in ("InvalidLaunchFileError",):
        # the Python-specific load failures are wrapped by launch; the others read the same
        assert res.error_type == want["error_type"], (res.error, want["error"])


@pytest.mark.parametrize("golden", [g for g in GOLDEN if _golden(g)["result"]["error"] is None],
                         ids=[p.stem for p in GOLDEN if _golden(p)["result"]["error"] is None])
def test_parameters_equal_ros2_launch(golden):
    """Inline parameters (dicts, typed as launch_ros types them) and parameter files."""
    d = _golden(golden)
    res = _load(d["case"])
    for got, want in zip(res.nodes, d["result"]["nodes"]):
        if "params_error" in want:
            continue   # the oracle could not read launch_ros' parameter file (it writes tuples)
        inline = {k: v for k, v in want["params"].items() if k in got["params"]}
        assert _ws(got["params"]) == inline, (got["name"], got["params"], want["params"])
        assert _ws(got["param_files"]) == want["param_files"], got["name"]


def _features(path: Path, case: dict) -> dict[str, bool]:
    free = set(free_args2(path.read_text(), str(path))) | {k for k, v in case["args"].items() if v in ("true", "false")}
    return {k: v for k, v in [(k, case["args"].get(k)) for k in free]}


SYMBOLIC = [g for g in GOLDEN if all(v in ("true", "false") for v in _golden(g)["case"]["args"].values())
            and _golden(g)["case"]["file"].endswith(".py")]


@pytest.mark.parametrize("golden", SYMBOLIC, ids=[p.stem for p in SYMBOLIC])
def test_symbolic_analysis_equals_ros2_launch(golden):
    """The symbolic analysis (every value of the boolean arguments at once), evaluated at the
    run's arguments, has the oracle's nodes; where launch fails, an error holds there."""
    d = _golden(golden)
    case, want = d["case"], d["result"]
    path = WS / "src" / case["file"]
    text = path.read_text()
    free = set(free_args2(text, str(path))) | set(case["args"])
    la = analyse_launch2(text, str(path), workspace_root=str(WS), env=ENV, features=sorted(free))
    decl = {a.name: a.default for a in la.feature_args}
    assign = {}
    for n in free:
        v = case["args"].get(n, decl.get(n) or "false")
        assign[n] = v.strip().lower() in ("true", "1")

    def holds(c):
        return evaluate(c, {v: assign.get(v, False) for v in variables(c)})
    got = [(n.name or None, n.pkg, n.type or None, [list(r) for r in n.remaps])
           for n in la.nodes if holds(n.condition) and not getattr(n, "event", None)]
    errors = [f for f in la.facts if (f.severity == 1 or f.code == "unset-arg") and holds(f.condition)]
    errors += [x for x in la.diagnostics if x.severity == 1]
    if want["error"] is None:
        assert not errors, [(f.code, f.message) for f in errors]
        if golden.stem.startswith("decline_"):
            assert any(x.code == "launch-not-analysable" for x in la.diagnostics + la.facts)
            return
        assert sorted(got, key=str) == sorted(_nodes(want["nodes"]), key=str)
    else:
        assert errors, want["error"]


def test_golden_files_cover_the_issue():
    names = {p.stem for p in GOLDEN}
    for must in ("basic_defaults", "groups_defaults", "includes_defaults", "xml_to_py_defaults", "exprs_both",
                 "opaque_r2", "events_defaults", "composable_defaults", "yamlcfg_defaults", "wsmodule_defaults",
                 "obsolete_defaults", "nogen_defaults", "syntax_defaults", "errors_undefined", "required_missing",
                 "generic_00"):
        assert must in names
    assert len([n for n in names if n.startswith("generic_")]) >= 12
