"""The diagnostics catalogue (tvl_lsp/data/diagnostics.md, package data) documents every registered
code, `tvl-lsp --explain` prints it, and the
complete examples (```tvl / ```xml blocks) really get their code."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tvl_lsp.project.check import check_document
from tvl_lsp.main import main
from tvl_lsp.cli.commands.explain import doc_text, load_codes, sections

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "tvl_lsp" / "data" / "diagnostics.md"
CODES = load_codes()
SECTIONS = sections(DOC.read_text(encoding="utf-8"))
FENCE = re.compile(r"```(tvl|uvl|xml|text)\n(.*?)```", re.S)


def test_every_registered_code_has_a_section():
    missing = sorted(set(CODES) - set(SECTIONS))
    assert missing == [], f"codes without a section in tvl_lsp/data/diagnostics.md: {missing}"


@pytest.mark.parametrize("code", sorted(SECTIONS))
def test_section_is_complete_and_matches_the_registry(code):
    sec = SECTIONS[code]
    assert code in CODES, f"tvl_lsp/data/diagnostics.md documents `{code}`, which no module registers"
    sev = CODES[code].severity.label
    assert f"**Severity:** {sev}" in sec
    assert FENCE.search(sec), "a minimal example"
    assert "**Fix:**" in sec


@pytest.mark.parametrize("code", sorted(CODES))
def test_explain_prints_the_section(code, capsys):
    assert main(["--explain", code]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"## `{code}`")
    assert out == SECTIONS[code]


def test_explain_unknown_code_and_listing(capsys):
    assert main(["--explain", "dead-elemnt"]) == 2
    assert "dead-element" in capsys.readouterr().err
    assert main(["--explain"]) == 0
    listing = capsys.readouterr().out
    rows = listing.splitlines()
    head, table = rows[0], [r for r in rows[1:] if r and not r.startswith(" ")][:-1]
    assert head.split() == ["CODE", "SEVERITY", "SUMMARY"]
    assert [r.split()[0] for r in table] == sorted(CODES)
    sev_col, sum_col = head.index("SEVERITY"), head.index("SUMMARY")
    for r in table:  # one aligned table: every severity and summary starts in its column
        code = r.split()[0]
        assert r[sev_col:].startswith(CODES[code].severity.label + " ") and r[sev_col - 1] == " ", r
        assert r[sum_col:] == CODES[code].summary and r[sum_col - 1] == " ", r
    assert rows[-1].startswith(f"{len(CODES)} codes.")


def test_listing_wraps_under_its_column_on_a_terminal():
    from tvl_lsp.cli.commands.explain import listing
    text = listing(CODES, width=80)
    col = text.splitlines()[0].index("SUMMARY")
    assert all(len(r) <= 80 for r in text.splitlines()[:-1])
    cont = [r for r in text.splitlines() if r.startswith(" ")]
    assert cont and all(r[:col].strip() == "" and r[col] != " " for r in cont)


@pytest.mark.parametrize("code", sorted(CODES))
def test_summaries_are_sentences(code):
    """--explain's list, the SARIF rules and the VS Code picker show the registered summaries: one
    style, a sentence that begins with a capital letter and ends with a full stop."""
    s = CODES[code].summary
    assert s[:1].isupper() and s.endswith(".") and "\n" not in s and "  " not in s, s


EXAMPLES = [(code, m.group(1), m.group(2)) for code, sec in sorted(SECTIONS.items())
            for m in [FENCE.search(sec)] if m and m.group(1) in ("tvl", "uvl", "xml")]


@pytest.mark.parametrize("code,lang,text", EXAMPLES, ids=[e[0] for e in EXAMPLES])
def test_complete_examples_get_their_code(code, lang, text, tmp_path):
    path = tmp_path / {"tvl": "example.tvl", "uvl": "example.uvl"}.get(lang, "example.launch")
    path.write_text(text)
    got = {d.code for d in check_document(str(path))}
    assert code in got, f"{code}: the example gets {sorted(got)}"
