"""The graph's two ways of answering (a product table, the SAT service) give the same answers:
the same projections, conditions, counts, findings and witnesses."""

from __future__ import annotations

import pytest

from tvl_lsp.graph import GraphLogic, graph_diagnostics, project, to_json
from tvl_lsp.graph.logic import SatOracle, TableOracle

from graph_helpers import ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT, setup, turtlerand_ws

MODES = {"table": dict(), "projected": dict(full_table=False), "sat": dict(table_limit=0)}
DECISIONS = [{}, {"Nav": True}, {"Camera": True, "Compress": False}, {"Omni": True, "Teleop": True},
             {"Robot": True, "Base": True, "Diff": True, "Omni": False, "Camera": True, "Compress": True,
              "Teleop": False, "Nav": True}]


def _logic(s, mode):
    enc = s.model.encoding
    return GraphLogic(enc, s.features, s.model, **MODES[mode])


def _diag_key(d):
    return (d.code, d.path, d.span, d.message, tuple(sorted(d.witness.items())), tuple(d.related))


@pytest.fixture(scope="module")
def robot():
    s = setup(ROBOT_LAUNCH, ROBOT_MODEL, ROBOT_PROJECT)
    yield s
    s.logic.close()


def test_oracle_kinds(robot):
    for mode, kind in (("table", TableOracle), ("projected", TableOracle), ("sat", SatOracle)):
        with _logic(robot, mode) as lg:
            o = lg.oracle({"Nav", "Camera"})
            assert isinstance(o, kind), mode
            if mode == "table":
                assert o.t.full and o.t.n == 18
            if mode == "projected":
                assert not o.t.full and o.t.names == ["Camera", "Nav"] and o.t.n == 4


@pytest.mark.parametrize("decisions", DECISIONS, ids=[str(sorted(d.items())) for d in DECISIONS])
def test_same_projection_and_counts_in_every_mode(robot, decisions):
    outs = {}
    for mode in MODES:
        with _logic(robot, mode) as lg:
            outs[mode] = to_json(project(robot.graph, lg, decisions, count=True))
    assert outs["table"] == outs["projected"] == outs["sat"]


def test_same_findings_and_witnesses_in_every_mode(robot):
    outs = {}
    for mode in MODES:
        with _logic(robot, mode) as lg:
            outs[mode] = [_diag_key(d) for d in graph_diagnostics(robot.graph, lg, robot.analysis)]
    assert outs["table"] == outs["projected"] == outs["sat"]
    assert len(outs["table"]) == 8


def test_turtlerand_same_in_every_mode(tmp_path):
    ws = turtlerand_ws(tmp_path)
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    s = setup(launch, launch.with_suffix(".tvl"), ws / "haros.yaml")
    try:
        outs = {}
        for mode in MODES:
            with _logic(s, mode) as lg:
                outs[mode] = (to_json(project(s.graph, lg, {}, count=True)),
                              [_diag_key(d) for d in graph_diagnostics(s.graph, lg, s.analysis)])
        assert outs["table"] == outs["projected"] == outs["sat"]
    finally:
        s.logic.close()


def test_table_limit_falls_back_to_sat(robot):
    with GraphLogic(robot.model.encoding, robot.features, robot.model, table_limit=10) as lg:
        assert isinstance(lg.oracle(set(robot.features)), SatOracle)
        assert isinstance(lg.oracle({"Nav"}), TableOracle)  # 2 rows: a table of just Nav


def test_unpaired_free_args_table():
    with GraphLogic(None, ["a", "b", "c"]) as lg:
        o = lg.oracle({"a"})
        assert isinstance(o, TableOracle) and o.t.n == 8
        from tvl_lsp.base.formula import Var, conj, neg
        f = conj([Var("a"), neg(Var("b"))])
        assert o.count(o.term(f), f) == 2
        assert o.witness(o.term(f), f) == {"a": True, "b": False, "c": False}
