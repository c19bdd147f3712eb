"""Acceptance versus the reference TVLParser over every .tvl of the corpus (corpus suite:
``--corpus DIR``; tests/test_tvl_reference.py is the default suite's counterpart on our own
fixtures).

tests/data/tvl_reference_expectations.json records, for each model, whether the reference
accepts it and why (from reading its sources); tvl-lsp must report no error on the accepted ones
and at least one (with the expected code) on the rejected ones.
"""

import json
from pathlib import Path

import pytest

from tvl_lsp.base.diagnostics import Severity
from tvl_lsp.tvl import parse_model

TABLE = json.loads((Path(__file__).parent / "data" / "tvl_reference_expectations.json").read_text())["models"]

pytestmark = pytest.mark.corpus


def _errors(path: Path):
    res = parse_model(path.read_text(encoding="utf-8", errors="replace"), str(path))
    return res, [d for d in res.diagnostics if d.severity == Severity.ERROR]


def test_table_covers_the_whole_corpus(corpus_dir):
    found = {str(p.relative_to(corpus_dir)) for p in corpus_dir.rglob("*.tvl")}
    assert found == set(TABLE)


@pytest.mark.parametrize("rel", sorted(TABLE))
def test_acceptance_matches_reference(rel, corpus_dir):
    exp = TABLE[rel]
    res, errs = _errors(corpus_dir / rel)
    if exp["expect"] == "accept":
        assert errs == [], [f"{d.span} {d.code}: {d.message}" for d in errs]
        assert res.model.root is not None
    else:
        assert errs, f"the reference rejects {rel}: {exp['reason']}"
        assert exp["code"] in {d.code for d in errs}
        assert any(d.span.start.line + 1 == exp["line"] for d in errs if d.code == exp["code"])


THESIS = ["thesis/ws/src/turtlerand/launch/generic.tvl", "thesis/ws/src/turtlerand/launch/generic_split.tvl",
          "thesis/ws/src/turtlebot/launch/turtlebot.tvl", "thesis/ws/src/lizi/launch/generic.tvl",
          "thesis/models/example_4_3.tvl"]


@pytest.mark.parametrize("rel", THESIS)
def test_thesis_models_have_no_diagnostics_at_all(rel, corpus_dir):
    res = parse_model((corpus_dir / rel).read_text(), str(corpus_dir / rel))
    assert res.diagnostics == []


def test_example_4_3_structure(corpus_dir):
    res = parse_model((corpus_dir / THESIS[-1]).read_text(), "x.tvl")
    mdl = res.model
    assert [f.long_name for f in mdl.features][:5] == ["A", "A.B", "A.E", "A.J", "A.K"]
    assert mdl.feature("K").group.kind == "card" and (mdl.feature("K").group.lo, mdl.feature("K").group.hi) == (1, None)
    assert mdl.feature("E").group.kind == "someOf" and mdl.feature("E").group.lo == 1
    y = mdl.feature("B").attributes[0]
    assert y.value.func == "or" and y.value.over == "selectedChildren" and y.value.type == "bool"
    assert [c.optional for c in mdl.root.group.children] == [False, False, True, True]


def test_root_tvl_includes_the_sheet_fragments(corpus_dir):
    root = corpus_dir / "tvl/familiar-tests/root.tvl"
    res = parse_model(root.read_text(), str(root))
    assert len(res.model.includes) == 5 and all(i.resolved for i in res.model.includes)
    sheet = res.model.feature("Sheet")
    assert sheet.path.endswith("root.tvl") and any(p.endswith("sheet.tvl") for p, _ in sheet.decl_spans)
