"""Recovery without cascades (issue 17), on models written for the purpose (tests/data/tvl_recovery,
the reference parser's verdicts recorded in expected.json): one error per mistake, at the mistake,
none elsewhere -- a declaration with a syntax error still declares its name, a misspelt 'group'
still declares the group's children, a ',' before '}' or a '}' missing before the next top-level
item costs one error, not the block around it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tvl_lsp.base.diagnostics import Severity
from tvl_lsp.tvl import parse_model

DATA = Path(__file__).parent / "data" / "tvl_recovery"
EXPECTED = json.loads((DATA / "expected.json").read_text())["files"]


def test_every_fixture_has_an_expectation():
    assert sorted(p.name for p in DATA.glob("*.tvl")) == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_one_error_per_mistake(name):
    exp = EXPECTED[name]
    res = parse_model((DATA / name).read_text(), str(DATA / name))
    errs = sorted((d for d in res.diagnostics if d.severity == Severity.ERROR),
                  key=lambda d: (d.span.start.line, d.span.start.col))
    # the reference's verdict
    assert (exp["reference"] == "accept") == (errs == []), [(str(d.span), d.message) for d in errs]
    # one error per mistake, where it is
    assert [(d.span.start.line + 1, d.span.start.col + 1, d.code) for d in errs] == \
        [(l, c, code) for l, c, code, _ in exp["errors"]], [(str(d.span.start), d.code, d.message) for d in errs]
    for d, (_, _, _, words) in zip(errs, exp["errors"]):
        assert words in d.message, d.message


def test_declaration_with_a_syntax_error_still_declares_its_name():
    res = parse_model((DATA / "attribute_syntax.tvl").read_text(), "/tmp/a.tvl")
    root = res.model.root
    assert "speed" in {a.name for a in root.attributes}


def test_misspelt_group_keeps_the_children():
    res = parse_model((DATA / "misspelt_group.tvl").read_text(), "/tmp/g.tvl")
    assert {f.name for f in res.model.features} >= {"Shop", "A", "B", "X", "Y"}
