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
    assert all(c in listing for c in CODES)


EXAMPLES = [(code, m.group(1), m.group(2)) for code, sec in sorted(SECTIONS.items())
            for m in [FENCE.search(sec)] if m and m.group(1) in ("tvl", "uvl", "xml")]


@pytest.mark.parametrize("code,lang,text", EXAMPLES, ids=[e[0] for e in EXAMPLES])
def test_complete_examples_get_their_code(code, lang, text, tmp_path):
    path = tmp_path / {"tvl": "example.tvl", "uvl": "example.uvl"}.get(lang, "example.launch")
    path.write_text(text)
    got = {d.code for d in check_document(str(path))}
    assert code in got, f"{code}: the example gets {sorted(got)}"
