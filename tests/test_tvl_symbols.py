"""name_at / references: what a position designates and where a declaration is used."""

from tvl_lsp.base.text import Pos, Span
from tvl_lsp.tvl import parse_model
from tvl_lsp.tvl.symbols import name_at, references

TEXT = """enum col in {red, blue};
const int k 2;
root Car {
  col c;
  group [1..k] {
    Engine { int power; },
    opt Wheels
  }
  Engine.power > k;
  c == red;
}
Engine {
  power > 3 -> root.Wheels;
}
"""
P = "/m/car.tvl"


def setup_module():
    global RES
    RES = parse_model(TEXT, P)
    assert RES.diagnostics == []


def test_name_at_declaration_and_uses():
    mdl = RES.model
    eng = mdl.feature("Engine")
    assert name_at(mdl, P, Pos(5, 6)) == (eng, Span(Pos(5, 4), Pos(5, 10)))
    tgt, sp = name_at(mdl, P, Pos(8, 3))
    assert tgt is eng and sp == Span(Pos(8, 2), Pos(8, 8))
    tgt, sp = name_at(mdl, P, Pos(8, 10))
    assert tgt is eng.attributes[0] and sp == Span(Pos(8, 9), Pos(8, 14))
    tgt, _ = name_at(mdl, P, Pos(8, 17))
    assert tgt is mdl.constants[0]
    tgt, _ = name_at(mdl, P, Pos(9, 8))
    assert tgt.name == "red" and tgt.enum_of is mdl.types[0]
    tgt, _ = name_at(mdl, P, Pos(3, 3))
    assert tgt is mdl.types[0]  # the type name in 'col c;'
    tgt, _ = name_at(mdl, P, Pos(12, 22))
    assert tgt is mdl.feature("Wheels")
    assert name_at(mdl, P, Pos(2, 11)) is None  # on '{'


def test_references_cover_declarations_reopenings_and_uses():
    mdl = RES.model
    eng = mdl.feature("Engine")
    assert references(mdl, eng) == [(P, Span(Pos(5, 4), Pos(5, 10))), (P, Span(Pos(8, 2), Pos(8, 8))),
                                    (P, Span(Pos(11, 0), Pos(11, 6)))]
    power = eng.attributes[0]
    assert [sp.start.line for _, sp in references(mdl, power)] == [5, 8, 12]
    assert [sp.start.line for _, sp in references(mdl, power, include_declarations=False)] == [8, 12]
    k = mdl.constants[0]
    assert [sp.start.line for _, sp in references(mdl, k)] == [1, 4, 8]
