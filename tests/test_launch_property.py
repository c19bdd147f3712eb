"""Property test against the real roslaunch (Debian's python3-roslaunch): random launch trees.

Hypothesis generates small workspaces -- a main launch file and the files it includes -- with
groups and namespaces, args passed to includes (by ``<arg>`` and by ``pass_all_args``), ``~params``
and ``<param>`` / ``<rosparam>`` inside nodes, ``<rosparam>`` with ``subst_value``, YAML tags
(``!degrees``, ``deg()``), typed ``<param>`` values and if/unless on two free args.  For every
assignment of the free args, tvl-lsp's concrete load (``tvl-lsp launch``) and its symbolic
analysis evaluated at the assignment must agree with roslaunch: the same error / no error, the
same nodes, and the same parameter tree (names and values).

The default run uses a fixed seed (``derandomize``) and ``TVL_LSP_PROPERTY_EXAMPLES`` examples
(default 60); set it higher to search longer, and ``TVL_LSP_PROPERTY_RANDOM=1`` for a new seed.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

from tvl_lsp.base.formula import evaluate  # noqa: E402
from tvl_lsp.launch import analyse_launch, find_packages, load_launch  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from testenv import ROSLAUNCH_MISSING, SYS_PY, have_roslaunch  # noqa: E402
from test_launch_differential import ORACLE, _norm, param_diff, symbolic_load  # noqa: E402

pytestmark = pytest.mark.skipif(not have_roslaunch(), reason=ROSLAUNCH_MISSING)

EXAMPLES = int(os.environ.get("TVL_LSP_PROPERTY_EXAMPLES", "60"))
STATS = {"loads": 0, "fails": 0, "params": 0}
FREE = ("A", "B")
PKG = """<?xml version="1.0"?><package format="2"><name>hyp</name><version>0.0.1</version>
<description>generated</description><maintainer email="x@example.com">x</maintainer><license>MIT</license></package>
"""


class Oracle:
    """One long-lived roslaunch process (``roslaunch_oracle.py --serve``)."""

    def __init__(self):
        self.p = subprocess.Popen([SYS_PY, str(ORACLE), "--serve"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  text=True, cwd="/tmp")

    def __call__(self, jobs: list[dict]) -> list[dict]:
        self.p.stdin.write(json.dumps(jobs) + "\n")
        self.p.stdin.flush()
        return json.loads(self.p.stdout.readline())

    def close(self):
        self.p.stdin.close()
        self.p.wait(timeout=30)


@pytest.fixture(scope="module")
def oracle():
    o = Oracle()
    yield o
    o.close()


# ---------------------------------------------------------------- strategies

COND = st.sampled_from(["", "", "", ' if="$(arg A)"', ' unless="$(arg A)"', ' if="$(arg B)"',
                        ' unless="$(arg B)"', ' if="$(eval arg(\'A\') and not arg(\'B\'))"'])
NS = st.sampled_from(["", "", ' ns="g1"', ' ns="g2/sub"', ' ns="/top"', ' ns="$(arg label)"'])
PNAME = st.sampled_from(["p", "p", "~q", "~q", "/abs", "a/b", " sp ", "rate", "$(arg label)_x"])
PVALUE = st.sampled_from(["1", "2.5", "true", "False", " padded ", "x y", "1_0", "1e3", "$(arg label)",
                          "$(arg num)", "[1, 2]", "{k: v}", "$(eval arg('num') + '0')",
                          "$(eval 2 * int(arg('num')))", "$(arg label)/$(arg num)"])
PTYPE = st.sampled_from(["", "", "", ' type="int"', ' type="double"', ' type="str"', ' type="bool"',
                         ' type="yaml"'])
YAML = st.sampled_from([
    "{k: 1, m: {n: two}}",
    "angle: !degrees 90\nlist: [deg(180), rad(pi/2), 3]",
    "{label: $(arg label), count: $(arg num)}",
    "nested: {deep: {deeper: $(arg label)}}",
    "[a, b]",
    "7",
    "'$(arg num)'",
])


@st.composite
def params(draw, in_node: bool) -> str:
    out = []
    for _ in range(draw(st.integers(0 if in_node else 1, 4))):
        if draw(st.booleans()):
            out.append(f'<param name="{draw(PNAME)}" value="{draw(PVALUE)}"{draw(PTYPE)}{draw(COND)}/>')
        else:
            attrs = ""
            if draw(st.booleans()):
                attrs += f' param="{draw(st.sampled_from(["lst", "~priv", "/gl", "x/y"]))}"'
            if draw(st.integers(0, 3)) == 0:
                attrs += f' ns="{draw(st.sampled_from(["ns1", "/gns", "~pns"]))}"'
            if draw(st.booleans()):
                attrs += ' subst_value="true"'
            out.append(f"<rosparam{attrs}{draw(COND)}>{draw(YAML)}</rosparam>")
    return "".join(out)


@st.composite
def elements(draw, depth: int, files: dict, counter: list) -> str:
    out = []
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["node", "node", "group", "param", "include", "arg"]))
        if kind == "node":
            counter[0] += 1
            name = draw(st.sampled_from([f"n{counter[0]}", f"n{counter[0]}", "dup", "n_$(arg label)"]))
            out.append(f'<node pkg="hyp" type="t" name="{name}"{draw(NS)}{draw(COND)}>'
                       f"{draw(params(True))}</node>")
        elif kind == "group" and depth < 3:
            out.append(f"<group{draw(NS)}{draw(COND)}>{draw(elements(depth + 1, files, counter))}</group>")
        elif kind == "param":
            out.append(draw(params(False)))
        elif kind == "arg":
            out.append(draw(st.sampled_from([
                '<arg name="local" value="$(arg label)_l"/>',
                '<arg name="num" value="9"/>',                     # may override: arg-already-set
                '<arg name="label" value="right" if="$(arg B)"/>',
                '<arg name="mode" default="m_$(arg label)"/>',
                '<rosparam command="delete" param="p"/>',
            ])))
        elif kind == "include" and depth < 2 and len(files) < 4:
            child = f"c{len(files)}.launch"
            files[child] = ""  # reserve the name
            files[child] = child_file(draw, depth + 1, files, counter)
            where = draw(st.sampled_from(["$(dirname)", "$(find hyp)/launch"]))
            pa = draw(st.sampled_from(["", "", ' pass_all_args="true"']))
            inc_args = ""
            for a in draw(st.lists(st.sampled_from(["label", "num", "mode", "extra"]), max_size=2, unique=True)):
                v = draw(st.sampled_from(["$(arg label)", "5", "$(arg A)", "z"]))
                inc_args += f'<arg name="{a}" value="{v}"/>'
            out.append(f'<include file="{where}/{child}"{draw(NS)}{pa}{draw(COND)}>{inc_args}</include>')
        else:
            out.append(f'<param name="simple{counter[0]}" value="{draw(PVALUE)}"/>')
    return "".join(out)


def child_file(draw, depth: int, files: dict, counter: list) -> str:
    decls = ""
    for a in ("label", "num", "mode"):
        form = draw(st.sampled_from(["default", "default", "default", "default", "none", "absent"]))
        if form == "default":
            decls += f'<arg name="{a}" default="d_{a}"/>'
        elif form == "none":
            decls += f'<arg name="{a}"/>'
    if draw(st.booleans()):
        decls += '<arg name="A" default="false"/><arg name="B" default="true"/>'
    return f"<launch>{decls}{draw(elements(depth, files, counter))}</launch>\n"


@st.composite
def workspaces(draw) -> dict:
    files: dict[str, str] = {}
    counter = [0]
    head = ('<arg name="A"/><arg name="B"/><arg name="label" default="left"/><arg name="num" default="3"/>')
    files["main.launch"] = f"<launch>{head}{draw(elements(0, files, counter))}</launch>\n"
    return files


# ---------------------------------------------------------------- the property

@settings(max_examples=EXAMPLES, deadline=None, derandomize=not os.environ.get("TVL_LSP_PROPERTY_RANDOM"),
          database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                 HealthCheck.data_too_large])
@given(files=workspaces())
def test_random_launch_trees_load_as_roslaunch_loads_them(files, oracle, tmp_path_factory):
    ws = tmp_path_factory.mktemp("ws")
    pkg = ws / "hyp"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text(PKG)
    for name, text in files.items():
        (pkg / "launch" / name).write_text(text)
    main = str(pkg / "launch" / "main.launch")
    text = files["main.launch"]
    pk = find_packages(str(ws))
    analysis = analyse_launch(text, main, packages=pk, features=list(FREE))
    assigns = [dict(A=a, B=b) for a in (False, True) for b in (False, True)]
    jobs = [dict(file=main, args={k: str(v).lower() for k, v in a.items()}, package_path=str(ws)) for a in assigns]
    results = oracle(jobs)
    for a, job, o in zip(assigns, jobs, results):
        lr = load_launch(main, job["args"], packages=pk)
        sym_errs = [f for f in analysis.facts if (f.severity == 1 or f.code == "unset-arg")
                    and evaluate(f.condition, a)]
        where = (files, job["args"], o.get("message"))
        STATS["loads" if o["ok"] else "fails"] += 1
        if o["ok"]:
            STATS["params"] += len(o["values"])
            assert lr.error is None, (where, lr.error)
            assert not sym_errs, (where, [(f.code, f.message) for f in sym_errs])
            nodes = _norm(o["nodes"])
            assert _norm(n["name"] for n in lr.nodes) == nodes, where
            assert _norm(n.name for n in analysis.nodes if not n.is_test and evaluate(n.condition, a)) == nodes, where
            assert param_diff(lr, o["values"]) == [], where
            assert param_diff(symbolic_load(analysis, a), o["values"]) == [], where
        else:
            assert lr.error is not None, where
            assert sym_errs, where


def test_the_random_trees_exercise_both_outcomes():
    """Guard: the generated trees are not all rejected (or all loaded) by roslaunch."""
    if STATS["loads"] + STATS["fails"] == 0:
        return  # the property test was not selected (-k): nothing to check
    print(STATS)
    assert STATS["loads"] >= STATS["fails"] / 4 and STATS["fails"] > 0 and STATS["params"] > 50
