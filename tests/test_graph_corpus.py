"""Opt-in (``pytest --corpus DIR``): the computation graph over the thesis workspace.

- every turtlerand pairing of the thesis (Listings 5.1, 5.2, 5.4, 5.5 with the models 4.1, 4.2,
  5.3), with the thesis's hints plus the turtlerand nodes' own: for every product, the
  projection equals the graph loaded directly; the three configurations of Figures 3, 5 and 7;
- lizi and turtlebot: the graph builds, every projection on a product is certain, and the DOT
  output renders with Graphviz.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from tvl_lsp.graph import graph_diagnostics, to_dot, to_json

from graph_helpers import TURTLERAND_HINTS, links_of, nodes_of, resources_of, setup
from test_graph_products import FIGURES

pytestmark = pytest.mark.corpus

ENV = {"TURTLEBOT_SIMULATION": "false", "TURTLEBOT_SERIAL_PORT": "/dev/ttyUSB0"}

TURTLERAND = [
    ("generic.launch", "generic.tvl"),
    ("generic_nested.launch", "generic.tvl"),
    ("generic_group_technique.launch", "generic.tvl"),
    ("generic.launch", "generic_split.tvl"),
    ("generic_nested.launch", "generic_split.tvl"),
    ("generic_alt.launch", "generic_alt.tvl"),
]


@pytest.fixture(scope="module")
def thesis_ws(corpus_dir, tmp_path_factory):
    src = corpus_dir / "thesis" / "ws"
    if not src.is_dir():
        pytest.skip(f"{src} not found")
    dst = tmp_path_factory.mktemp("thesis") / "ws"
    shutil.copytree(src, dst)
    pf = dst / "haros_turtlerand.yaml"
    text = pf.read_text()
    # the thesis hints the turtlesim nodes (Listing 5.6); add the turtlerand nodes' own
    extra = TURTLERAND_HINTS.split("  turtlerand/random_controller:", 1)[1]
    text = text.replace("rules:", "    turtlerand/random_controller:" + "\n".join(
        "  " + x if x.strip() else x for x in extra.splitlines()) + "\nrules:")
    pf.write_text(text)
    return dst


@pytest.mark.parametrize("launch,model", TURTLERAND, ids=[f"{a}+{b}" for a, b in TURTLERAND])
def test_turtlerand_every_product(thesis_ws, launch, model):
    d = thesis_ws / "src" / "turtlerand" / "launch"
    s = setup(d / launch, d / model, thesis_ws / "haros_turtlerand.yaml")
    try:
        assert s.hints.diagnostics == []
        assert {"turtlerand/random_controller", "turtlesim/turtlesim_node"} <= set(s.hints.by_type)
        products = s.products()
        assert len(products) == 4
        for p in products:
            direct = s.product_graph(p)
            proj = s.project(p)
            assert nodes_of(proj) == nodes_of(direct), p
            assert links_of(proj) == links_of(direct), p
            assert resources_of(proj) == resources_of(direct), p
            assert all(ln.condition is None for ln in proj.links.values())
        if launch in ("generic.launch", "generic_nested.launch", "generic_alt.launch"):
            for decisions, expected in FIGURES.values():
                assert links_of(s.project(decisions)) == expected
        graph_diagnostics(s.graph, s.logic, s.analysis)
    finally:
        s.logic.close()


@pytest.mark.parametrize("launch,model,products", [
    ("turtlebot_bringup/launch/generic.launch", "turtlebot/launch/turtlebot.tvl", 776),
    ("lizi/launch/generic.launch", "lizi/launch/generic.tvl", 2304)])
def test_lizi_and_turtlebot(thesis_ws, launch, model, products, monkeypatch):
    for k, v in ENV.items():
        monkeypatch.setenv(k, v)
    src = thesis_ws / "src"
    s = setup(src / launch, src / model, None)
    try:
        g = s.project(count=True)
        assert g.products == products
        assert g.nodes and all(not n.hinted and n.note for n in g.nodes.values())
        to_json(g)
        for decisions in ({}, next(iter(s.model.enumerate(limit=1)))):
            dot = to_dot(s.project(decisions))
            if shutil.which("dot"):
                r = subprocess.run(["dot", "-Tsvg"], input=dot, capture_output=True, text=True, timeout=60)
                assert r.returncode == 0 and "<svg" in r.stdout, r.stderr
        for p in s.model.enumerate(limit=40):
            proj = s.project(p)
            for el in list(proj.nodes.values()) + list(proj.resources.values()):
                assert el.condition is None, (p, el.id)
        assert graph_diagnostics(s.graph, s.logic, s.analysis) == []  # no hints: nothing to check
    finally:
        s.logic.close()


def test_thesis_hints_file_reads_cleanly(corpus_dir):
    from tvl_lsp.graph import parse_hints
    for name in ("haros_turtlerand.yaml", "haros_turtlerand_legacy.yaml", "haros_lizi.yaml", "haros_turtlebot.yaml"):
        p = Path(corpus_dir) / "thesis" / "ws" / name
        h = parse_hints(str(p), p.read_text())
        assert h.diagnostics == [], name
    legacy = Path(corpus_dir) / "thesis" / "ws" / "haros_turtlerand_legacy.yaml"
    h = parse_hints(str(legacy), legacy.read_text())
    assert set(h.by_config) == {"teleop_key", "random_controller", "multiplexer"}
