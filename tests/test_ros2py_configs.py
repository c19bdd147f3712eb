"""Configuration launch files of a generic Python launch file: ``tvl-lsp generate FILE.launch.py``
writes, per product of the model, an XML launch file that includes the generic ``.launch.py``
with the product's arguments.  The real ros2/launch loaded every one of them and started the
product's nodes: its answers on our fixture are recorded in
tests/data/ros2py_editor/golden/configs.json (scripts/ros2py_config_golden.py, ``--allow-python``
on our own ``clean.launch.py``); here the files are generated again and compared with the texts
the oracle saw, and the oracle's nodes with the product's nodes as tvl-lsp computes them (the
concrete load of the configuration, and the symbolic analysis of the generic file evaluated in
the product)."""

from __future__ import annotations

import contextlib
import io
import json
import re
import shutil
from pathlib import Path

import pytest

from tvl_lsp.base.formula import evaluate, variables
from tvl_lsp.cli.commands.generate import main as generate_main
from tvl_lsp.launch import analyse_any, load_any

DATA = Path(__file__).resolve().parent / "data" / "ros2py_editor"
GOLDEN = json.loads((DATA / "golden" / "configs.json").read_text())
GENERIC = "src/rover/launch/clean.launch.py"


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    ws = tmp_path_factory.mktemp("configs") / "ws"
    shutil.copytree(DATA / "ws", ws)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        rc = generate_main([str(ws / GENERIC), "--mode", "all", "--workspace", str(ws), "--out", "configs"])
    assert rc == 0
    files = sorted(Path(p) for p in out.getvalue().split())
    return ws, files


def _nodes(nodes) -> list:
    return sorted((n["name"], n["package"], n["executable"], [list(r) for r in n["remaps"]]) for n in nodes)


def test_the_generated_files_are_those_ros2_launch_loaded(generated):
    ws, files = generated
    assert [f.name for f in files] == [g["name"] for g in GOLDEN]
    for f, g in zip(files, GOLDEN):
        assert f.read_text() == g["text"], f.name
        assert f.parent == ws / "src" / "rover" / "configs"
        assert '<include file="$(find-pkg-share rover)/launch/clean.launch.py">' in g["text"]
    # every product of clean.tvl, each loaded by ros2 launch without an error
    assert len(GOLDEN) == 24 and all(g["exit_code"] == 0 and g["error"] is None for g in GOLDEN)


def _product(text: str) -> dict[str, bool]:
    return {k: v == "true" for k, v in re.findall(r'<arg name="([^"]+)" value="(true|false)"/>', text)}


@pytest.mark.parametrize("i", range(len(GOLDEN)), ids=[g["name"] for g in GOLDEN])
def test_ros2_launch_started_the_products_nodes(generated, i):
    ws, files = generated
    g = GOLDEN[i]
    want = _nodes(g["nodes"])
    product = _product(g["text"])
    # (every feature argument set as the product says; the include's own arguments leak into the
    # includer's launch configurations, as ros2 launch does)
    assert {k: g["launch_configurations"].get(k) for k in product} == {k: "true" if v else "false"
                                                                      for k, v in product.items()}
    # tvl-lsp's concrete load of the configuration file (XML including the Python file)
    res = load_any(str(files[i]), {}, workspace_root=str(ws))
    assert res.error is None, res.error
    assert _nodes(res.nodes) == want
    # the symbolic analysis of the generic file, in the product
    generic = ws / GENERIC
    la = analyse_any(generic.read_text(), str(generic), workspace_root=str(ws), features=sorted(product))

    def holds(c):
        return evaluate(c, {v: product.get(v, False) for v in variables(c)})
    got = sorted((n.name, n.pkg, n.type, [list(r) for r in n.remaps]) for n in la.nodes if holds(n.condition))
    assert got == want
