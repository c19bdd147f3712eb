"""Nested equivalences are distributed once per node and polarity, not once per enclosing
equivalence: an equivalence distributes both its sides in both polarities, so without
remembering them the work grew as 4^depth (a random 700-character constraint of mixed ``<=>``
and ``=>`` took 5 s to encode).  Counted in distribution steps, not timed."""

from __future__ import annotations

import pytest

from tvl_lsp.analysis import encode as E
from tvl_lsp.analysis import plaincnf
from tvl_lsp.uvl import parse_uvl
from tvl_lsp.uvl.plain import read_plain

NAMES = ["A", "B", "C", "D", "E", "F"]


def _nested(depth: int) -> str:
    e = "A"
    for i in range(depth):
        a, b = NAMES[i % 6], NAMES[(i + 3) % 6]
        e = f"({a} & {b} | !{a}) <=> ({e}) => {b}" if i % 2 else f"{a} <=> ({e} | {b})"
    return e


def _model(depth: int) -> str:
    return ("features\n\tR\n\t\toptional\n" + "".join(f"\t\t\t{x}\n" for x in NAMES)
            + "constraints\n\t" + _nested(depth) + "\n")


@pytest.mark.parametrize("depth", [12, 16])
def test_full_path_distributes_each_equivalence_once(depth, monkeypatch):
    calls = [0]
    real = E.Encoding._product

    def counted(self, *a):
        calls[0] += 1
        return real(self, *a)

    monkeypatch.setattr(E.Encoding, "_product", counted)
    enc = E.encode(parse_uvl(_model(depth), "m.uvl").model)
    assert enc.clauses()
    assert calls[0] <= 10 * depth  # (4^depth before: 15,697 steps at depth 12)


@pytest.mark.parametrize("depth", [12, 16])
def test_plain_path_distributes_each_equivalence_once(depth, monkeypatch):
    calls = [0]
    real = plaincnf._Enc.product

    def counted(self, *a):
        calls[0] += 1
        return real(self, *a)

    monkeypatch.setattr(plaincnf._Enc, "product", counted)
    text = _model(depth)
    c = plaincnf.encode_plain(read_plain(text))
    assert calls[0] <= 10 * depth
    enc = E.encode(parse_uvl(text, "m.uvl").model)
    assert (c.nvars, c.clauses) == (enc.nvars, enc.clauses())
