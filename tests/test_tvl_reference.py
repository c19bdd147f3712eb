"""Acceptance versus the TVL reference parser (TVLParser v20100804) on our own fixtures.

tests/data/tvl/reference/*.tvl each exercise one thing the reference accepts or rejects;
tests/data/tvl_reference_fixtures.json records what the reference answered on each
(scripts/record_tvl_reference.py runs it: its jars are third-party, not in the repository) and,
by hand, the error tvl-lsp must report on a rejected file.  tvl-lsp must report no error where the
reference accepts, and that error where it rejects, except on the few files recorded as
deliberate divergences, where tvl-lsp's own answer is recorded and checked instead.
tests/test_tvl_corpus.py does the same over the corpus (corpus suite).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from testenv import DATA
from tvl_lsp.base.diagnostics import Severity
from tvl_lsp.tvl import parse_model

FIXTURES = DATA / "tvl" / "reference"
RECORD = json.loads((DATA / "tvl_reference_fixtures.json").read_text())["models"]


def _errors(path: Path):
    res = parse_model(path.read_text(encoding="utf-8"), str(path))
    return res, [d for d in res.diagnostics if d.severity == Severity.ERROR]


def test_the_record_covers_every_fixture():
    assert {p.name for p in FIXTURES.glob("*.tvl")} == set(RECORD)
    # both verdicts, and a rejection for most of the codes of the corpus's table
    assert {e["reference"] for e in RECORD.values()} == {"accept", "reject"}
    assert len({e["code"] for e in RECORD.values() if "code" in e}) >= 15


@pytest.mark.parametrize("name", sorted(RECORD))
def test_acceptance_matches_the_reference(name):
    exp = RECORD[name]
    res, errs = _errors(FIXTURES / name)
    verdict = exp.get("tvl_lsp", exp["reference"])
    if verdict == "accept":
        assert errs == [], [f"{d.span} {d.code}: {d.message}" for d in errs]
        assert res.model.root is not None
    else:
        assert errs, f"the reference rejects {name}: {exp['message']}"
        first = min(errs, key=lambda d: (d.span.start.line, d.span.start.col))
        assert (first.code, first.span.start.line + 1) == (exp["code"], exp["line"]), \
            [(d.code, d.span.start.line + 1, d.message) for d in errs]
        if "at" in exp:   # a syntax error: on the line the reference names, or where tvl-lsp
            # says the missing separator goes (the end of the line before, recorded by hand)
            at = exp.get("tvl_lsp_at", exp["at"])
            assert (first.span.start.line + 1, first.span.start.col + 1) == tuple(at) if "tvl_lsp_at" in exp \
                else first.span.start.line + 1 == at[0]


@pytest.mark.parametrize("name", sorted(n for n, e in RECORD.items() if "divergence" in e))
def test_divergences_are_recorded_with_a_reason(name):
    exp = RECORD[name]
    assert exp["reference"] != exp["tvl_lsp"] and len(exp["divergence"]) > 40
    # the fixture says so too, in its header comment
    header = "\n".join((FIXTURES / name).read_text().splitlines()[:3])
    assert "the reference" in header and "tvl-lsp" in header


def test_included_fragment_is_read_through_its_includer():
    res, errs = _errors(FIXTURES / "accept_include.tvl")
    assert errs == [] and {f.name for f in res.model.features} >= {"Thermometer", "Barometer", "Anemometer"}
    assert len(res.model.includes) == 1 and res.model.includes[0].resolved
