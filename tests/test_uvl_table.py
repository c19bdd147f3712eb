"""The UVL parser's stored LALR table (tvl_lsp/uvl/_uvl_table.py) is the one lark computes from
grammars/uvl.lark today, and reading UVL does not import lark (the cold-start cost it saves)."""

import subprocess
import sys

from tvl_lsp.uvl import _uvl_table, parser


def test_stored_table_is_the_grammars_table():
    rows, start, end = parser._lark_table()
    assert _uvl_table.GRAMMAR_SHA256 == parser._grammar_digest(), \
        "grammars/uvl.lark changed: regenerate with `python -m tvl_lsp.uvl.parser`"
    assert parser._stored_table() == (rows, start, end)
    assert parser.table_module_text() == open(_uvl_table.__file__, encoding="utf-8").read()


def test_stale_table_falls_back_to_lark(monkeypatch):
    stored = parser._TABLES
    monkeypatch.setattr(_uvl_table, "GRAMMAR_SHA256", "0" * 64)
    monkeypatch.setattr(parser, "_TABLES", None)
    assert parser._stored_table() is None
    rows, start, end = parser._tables()
    assert (start, end) == (_uvl_table.START, _uvl_table.END)
    assert len(rows) == len(_uvl_table.ROWS)
    parser._TABLES = stored


def test_uvl_parse_and_encode_do_not_import_lark():
    code = ("import sys\n"
            "from tvl_lsp.analysis.formats import parse_any_model\n"
            "from tvl_lsp.analysis.engine import ModelAnalysis\n"
            "r = parse_any_model('features\\n  A\\n    optional\\n      B\\nconstraints\\n  B => A\\n', 'm.uvl')\n"
            "assert not r.errors, r.errors\n"
            "ModelAnalysis(r.model).encoding\n"
            "print(sorted(m for m in sys.modules if m == 'lark' or m.startswith('lark.')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
