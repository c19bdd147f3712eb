"""The reference's semantic checks, one by one, and the grammar departures with their fixes."""


import pytest

from testenv import OVERLAY_WS
from tvl_lsp.base.diagnostics import CODES, Severity
from tvl_lsp.base.text import Pos, Span
from tvl_lsp.tvl import parse_model



def diags(text, files=None):
    files = files or {}
    return parse_model(text, "/m/a.tvl", read_file=lambda p: files.get(p)).diagnostics


def codes(text, **kw):
    return [d.code for d in diags(text, **kw) if d.severity == Severity.ERROR]


def warn_codes(text):
    return [d.code for d in diags(text) if d.severity == Severity.WARNING]


G = "group allOf { B, C }"


@pytest.mark.parametrize("text,code", [
    ("A { group allOf { B } }", "first-not-root"),
    ("root A.B { }", "root-long-name"),
    ("root A { group allOf { B.C } }", "long-name-in-group"),
    ("root A { group allOf { A } }", "root-name-reused"),
    ("root A { group allOf { B } } B { group allOf { C } } B { group allOf { D } }", "multiple-groups"),
    ("root A { group allOf { B } } X { }", "unknown-name"),
    ("root A { group allOf { B { group allOf { X } }, C { group allOf { X } } } } X { }", "ambiguous-name"),
    ("root A { group [2..1] { B, C } }", "cardinality-bounds"),
    ("root A { group [0..k] { B, C } }", "cardinality-bounds"),
    ("root A { group [3..3] { B, C } }", "cardinality-exceeds-children"),
    ("root A { group allOf { B } int x; x; }", "type-error"),
    ("root A { group allOf { B } B && 3; }", "type-error"),
    ("root A { int x is true; }", "type-error"),
    ("root A { int Price; }", "naming-convention"),
    ("int Money; root A { }", "naming-convention"),
    ("root a { }", "naming-convention"),
    ("root A { int x; int x; }", "duplicate-attribute"),
    ("root A { ghost g; }", "unknown-type"),
    ("int t; root A { int t; }", "name-conflict"),
    ("enum c in {B}; root A { group allOf { B } }", "name-conflict"),
    ("int t in [12.5..20]; root A { }", "invalid-domain"),
    ("real t in [3..2]; root A { }", "invalid-domain"),
    ("int t in {1, 2, 1}; root A { }", "invalid-domain"),
    ("int t in {1, 5 - 2}; root A { }", "invalid-domain"),
    ("root A { int x in [0..10], ifIn: is 11; }", "value-out-of-domain"),
    ("root A { enum e in {a, b}; e == c; }", "value-out-of-domain"),
    ("root A { group allOf { B, C { group allOf { D { group allOf { shared C } } } } } }", "shared-cycle"),
    ("root A { group allOf { B, C } } C { parent; } B { group allOf { shared C } }", "parent-in-shared"),
    ("int t; root A { t; }", "type-as-value"),
    ("struct s { int a; } root A { s v { b is 1; } }", "unknown-field"),
    ("root A { int v { b is 1; } }", "not-a-struct"),
    ("root A { group allOf { B, C } B.D; }", "unknown-name"),
    ("root A { group allOf { B } Q; }", "unknown-name"),
])
def test_each_check(text, code):
    assert code in codes(text), diags(text)


def test_codes_are_registered_and_kebab_case():
    for d in diags("root A { int X; group [3..1] { B } Q; ghost g; }"):
        assert d.code in CODES
        assert d.code == d.code.lower() and " " not in d.code and "_" not in d.code


def test_reference_leniencies_are_warnings():
    # lower-case children are not rejected, an upper bound above the number of children is a
    # printed WARNING; duplicate children are rejected (TVLParser v20100804: "Type error : the
    # feature A has many children features with an identical ID.", also for oneOf and deeper)
    assert codes("root A { group allOf { B, B } }") == ["duplicate-feature"]
    assert codes("root A { group oneOf { B, C } }\nB { group allOf { D, D } }") == ["duplicate-feature"]
    assert codes("root A { group allOf { b } }") == []
    assert "naming-convention" in warn_codes("root A { group allOf { b } }")
    assert codes("root A { group [1..5] { B, C } }") == []
    assert "cardinality-upper-unreachable" in warn_codes("root A { group [1..5] { B, C } }")


def test_unknown_name_suggests_close_names():
    d = [x for x in diags("root A { group allOf { Engine } } Engin { }") if x.code == "unknown-name"][0]
    assert "Engine" in d.message and d.span == Span(Pos(0, 34), Pos(0, 39))


def test_ambiguous_name_lists_the_paths_that_resolve_it():
    text = "root A { group allOf { B { group allOf { X } }, C { group allOf { X } } } X; }"
    d = [x for x in diags(text) if x.code == "ambiguous-name"][0]
    assert "'B.X'" in d.message and "'C.X'" in d.message
    assert d.data["candidates"] == ["B.X", "C.X"]
    assert d.span == Span(Pos(0, 74), Pos(0, 75))
    assert codes(text.replace("X; }", "B.X -> !C.X; }")) == []


def test_reopening_only_sees_features_declared_before_it():
    assert "unknown-name" in codes("root A { group allOf { B } } C { } B { group allOf { C } }")
    assert codes("root A { group allOf { B } } B { group allOf { C } } C { }") == []


def test_group_bounds_from_constants_and_star():
    res = parse_model("const int two 2; root A { group [two..*] { B, C, D } }", "/m/a.tvl")
    g = res.model.root.group
    assert (g.lo, g.hi) == (2, None) and res.diagnostics == []


def test_infix_and_or_have_a_quick_fix():
    ds = diags("root A { group allOf { B, C } B and C; B or C; }")
    infix = [d for d in ds if d.code == "infix-and-or"]
    assert [d.span for d in infix] == [Span(Pos(0, 32), Pos(0, 35)), Span(Pos(0, 41), Pos(0, 43))]
    assert [d.fixes[0].edits[0].new_text for d in infix] == ["&&", "||"]
    assert all(d.fixes[0].edits[0].span == d.span for d in infix)
    # the rest is still understood: the constraints are built and typed
    res = parse_model("root A { group allOf { B, C } B and C; }", "/m/a.tvl")
    assert res.model.root.constraints[0].expr.op == "&&"
    assert [d.code for d in res.diagnostics] == ["infix-and-or"]


def test_aggregate_and_or_are_not_flagged():
    assert codes("root A { group allOf { B, C } and(B, C) || or(B); }") == []


def test_constant_keyword_has_a_quick_fix():
    ds = diags("constant int k 2; root A { group [1..k] { B, C } }")
    assert [d.code for d in ds] == ["constant-keyword"]
    assert ds[0].fixes[0].edits[0].new_text == "const" and ds[0].span == Span(Pos(0, 0), Pos(0, 8))


def test_generic_alt_errors_are_at_its_infix_and_or():
    p = OVERLAY_WS / "src/turtlerand/launch/generic_alt.tvl"
    text = p.read_text()
    res = parse_model(text, str(p))
    errs = [d for d in res.diagnostics if d.severity == Severity.ERROR]
    assert {d.code for d in errs} == {"infix-and-or"}
    lines = text.splitlines()
    assert [lines[d.span.start.line][d.span.start.col:d.span.end.col] for d in errs] == ["and", "or"]
    # the rest of the model is still read
    assert sorted(f.name for f in res.model.features) == ["Logger", "Multiplexer", "Random", "Teleop",
                                                            "Turtlerand", "Turtlesim"]


def test_include_missing_and_cycle():
    ds = diags("root A { group allOf { B } }\ninclude(nope.tvl);\n")
    assert [d.code for d in ds] == ["include-missing"] and ds[0].span.start == Pos(1, 0)
    files = {"/m/b.tvl": "include(c.tvl);\nB { }\n", "/m/c.tvl": "include(b.tvl);\n"}
    ds = diags("root A { group allOf { B } }\ninclude(b.tvl);\n", files=files)
    cyc = [d for d in ds if d.code == "include-cycle"]
    assert len(cyc) == 1 and cyc[0].path == "/m/c.tvl" and "b.tvl -> c.tvl -> b.tvl" in cyc[0].message
    assert [d.code for d in ds if d.severity == Severity.ERROR] == ["include-cycle"]


def test_several_independent_errors_are_all_reported_and_the_rest_built():
    text = ("root A {\n  group allOf { B, C, D }\n  B -> ;\n}\n"
            "B { int x is ; }\n"
            "C { group allOf { E F } }\n"
            "D { int y is 2; D -> B; }\n")
    res = parse_model(text, "/m/a.tvl")
    syn = [d for d in res.diagnostics if d.code == "syntax-error"]
    assert [d.span.start.line for d in syn] == [2, 4, 5]
    d = res.model.feature("D")
    assert d is not None and d.attributes[0].name == "y" and len(d.constraints) == 1
    assert [f.name for f in res.model.root.children] == ["B", "C", "D"]


def test_missing_closing_brace_is_reported_at_the_end():
    res = parse_model("root A {\n  group allOf { B }\n", "/m/a.tvl")
    assert [d.code for d in res.diagnostics] == ["syntax-error"]
    assert "missing 1 '}'" in res.diagnostics[0].message
    assert res.model.feature("B") is not None


def test_signed_number_glued_to_minus_is_explained():
    ds = diags("root A { int x; x-1 > 0; }")
    assert ds[0].code == "syntax-error" and "space after '-'" in ds[0].message
    assert codes("root A { int x; x == -1; }") == []
    # the reference compares a computed number only with an attribute: "x - 1 > 0 is not valid,
    # you cannot compare two numerical values" (TVLParser v20100804); tvl-lsp counts it and warns
    assert codes("root A { int x; x - 1 > 0; }") == []
    assert "reference-rejects" in warn_codes("root A { int x; x - 1 > 0; }")


def test_did_you_mean_comes_with_a_fix():
    ds = diags("root A { group allOf { Engine } int power; } A { Engin -> Engine; powr > 1; }")
    unk = [d for d in ds if d.code == "unknown-name"]
    assert [d.fixes[0].edits[0].new_text for d in unk] == ["Engine", "power"]
    assert all(d.fixes[0].edits[0].span == d.span and d.fixes[0].preferred for d in unk)
    assert [d.data["suggestions"] for d in unk] == [["Engine"], ["power"]]


def test_enum_values_of_attributes_only_conflict_with_features_declared_before():
    # the reference checks an attribute's enum values when the attribute is processed
    # (attributes before the group): test2IDConflicts.tvl is accepted, test1IDConflicts.tvl not
    assert codes("root A { enum e in {B}; group allOf { B } }") == []
    assert "name-conflict" in codes("root A { group allOf { B } } B { enum e in {B}; }")


def test_infix_and_before_a_parenthesis():
    ds = diags("root A { group allOf { B, C } B and (C or B); and(B, C); B && or(C); }")
    assert [(d.code, d.span.start.col) for d in ds] == [("infix-and-or", 32), ("infix-and-or", 39)]
