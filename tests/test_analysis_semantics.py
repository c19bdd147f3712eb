"""TVL semantics of the encoder (issue 4): counts against the reference's, by hand."""

import pytest

from testenv import DATA, EXAMPLE_WS, OVERLAY_WS
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.tvl import parse_model



def analysis(text: str) -> ModelAnalysis:
    res = parse_model(text, "/tmp/m.tvl")
    assert not res.errors, [d.message for d in res.errors]
    return ModelAnalysis(res.model)


def count(text: str, **kw) -> int:
    return analysis(text).count(**kw)


def products(text: str) -> set[frozenset]:
    a = analysis(text)
    return {frozenset(k for k, v in p.items() if v) for p in a.enumerate(limit=None)}


def test_oneof_with_optional_child_has_4_products():
    text = "root R { group oneOf { A, opt B, C } }"
    assert count(text) == 4
    assert products(text) == {frozenset({"R"}), frozenset({"R", "A"}), frozenset({"R", "B"}),
                              frozenset({"R", "C"})}


def test_card_group_optional_children_win_over_the_lower_bound():
    assert count("root R { group [2..*] { A, opt B, C } }") == 6
    # |S| <= j still applies to optional children
    assert count("root R { group [0..1] { opt A, opt B, opt C } }") == 4


def test_allof_someof():
    assert count("root R { group allOf { A, B, opt C } }") == 2
    assert count("root R { group someOf { A, B, C } }") == 7
    assert count("root R { group someOf { A, opt B } }") == 4  # optional: [1..*] never bites
    assert count("root R { group oneOf { A, B, C } }") == 3


def test_group_applies_only_when_parent_selected():
    text = "root R { group allOf { opt P { group oneOf { A, B } } } }"
    assert count(text) == 3  # {R}, {R,P,A}, {R,P,B}
    assert products(text) == {frozenset({"R"}), frozenset({"R", "P", "A"}), frozenset({"R", "P", "B"})}


def test_constraints_are_global_even_inside_optional_features():
    text = """root R { group allOf { opt P { A || B; }, opt A, opt B } }"""
    # A || B holds in every product, whether P is selected or not
    assert count(text) == 6


def test_ifin_ifout():
    base = "root R { group allOf { opt P { %s }, opt A } }"
    assert count(base % "ifIn: A;") == 3   # P -> A : {}, {A}, {P,A}
    assert count(base % "ifOut: A;") == 3  # !P -> A : {A}, {P}, {P,A}


def test_shared_feature_implies_one_of_its_parents():
    text = """root R { group someOf { X { group allOf { opt S } }, Y { group allOf { opt shared S } } } }"""
    a = analysis(text)
    for p in a.enumerate(limit=None):
        if p["S"]:
            assert p["X"] or p["Y"]
    # X,Y someOf: 3 ways; S possible whenever one of them: 3 * 2
    assert a.count() == 6


def test_bool_attributes_and_aggregates_of_the_coffee_machine():
    p = DATA / "models" / "coffee.tvl"
    a = ModelAnalysis(parse_model(p.read_text(), str(p)).model)
    assert a.count() == 46
    assert a.dead_features() == ["Decaf"]
    # Heater.quick = or(selectedChildren.fast): only Thermoblock is fast, and quick excludes Jug
    assert a.count(include=["Thermoblock", "Jug"]) == 0
    assert a.count(include=["Jug"]) == 10


@pytest.mark.corpus
def test_bool_attributes_and_aggregates_of_listing_4_3(corpus_dir):
    p = corpus_dir / "thesis" / "models" / "example_4_3.tvl"
    a = ModelAnalysis(parse_model(p.read_text(), str(p)).model)
    assert a.count() == 20
    assert a.dead_features() == ["J"]


def test_bool_attribute_values_constrain_features():
    text = """root R {
      group allOf { opt A { bool x is true; }, opt B { bool x is false; } }
      bool y is or(selectedChildren.x);
      y;
    }"""
    assert count(text) == 2  # A must be selected: {A}, {A,B}


def test_enum_attribute_one_hot():
    text = """root R {
      enum color in {red, green, blue};
      group allOf { opt A, opt B }
      A -> color == red;
      B -> color != red;
    }"""
    # A and B can not both hold; {} {A} {B}: products are projected on features
    assert count(text) == 3


def test_int_attributes_sum_of_selected_children():
    text = """root Car {
      int price is sum(selectedChildren.price);
      group someOf { Focus { int price is 12000; }, Saxo { int price is 13500; }, Mini { int price is 9000; } }
      price <= 22000;
    }"""
    # subsets with sum <= 22000: F, S, M, F+M (21000); S+M = 22500 no
    assert count(text) == 4


def test_int_attribute_domain():
    text = """root R {
      group allOf { opt A { int n in [1..3]; }, opt B }
      B -> A.n > 2;
      A -> A.n < 2;
    }"""
    # B needs n=3, A needs n=1 (when A selected): {} {A} {B}; {A,B} impossible
    assert count(text) == 3


def test_real_constraint_left_out_and_reported_once():
    text = """root R {
      real w in [0.5..2.5];
      group allOf { opt A, opt B }
      A -> w > 1.5;
    }"""
    a = analysis(text)
    assert a.count() == 4
    diags = [d for d in a.anomalies() if d.code == "constraint-not-encoded"]
    assert len(diags) == 1 and diags[0].span.start.line == 3  # 0-based: the `A -> w > 1.5` line


REPO_MODELS = [  # the repository's models and their counts (tests/data/ws/README.md)
    (EXAMPLE_WS / "src/turtlerand/launch/generic.tvl", 4),
    (OVERLAY_WS / "src/turtlerand/launch/generic_split.tvl", 4),
    # generic_alt.tvl writes `and` / `or` (errors), read as && / ||: Multiplexer only with Teleop
    # and Random (5 of the 8 choices of the three), Logger only with one of them (4 of those 5)
    (OVERLAY_WS / "src/turtlerand/launch/generic_alt.tvl", 9),
    (OVERLAY_WS / "src/crawler/models/crawler.tvl", 584),
    (OVERLAY_WS / "src/scout/launch/generic.tvl", 1152),
    (DATA / "models" / "coffee.tvl", 46),
]


@pytest.mark.parametrize("p,expected", REPO_MODELS, ids=[p.name if p.parent.name != "launch" else
                                                         f"{p.parents[1].name}/{p.name}" for p, _ in REPO_MODELS])
def test_repository_model_counts(p, expected):
    a = ModelAnalysis(parse_model(p.read_text(), str(p)).model)
    assert a.count() == expected
    assert sum(1 for _ in a.enumerate(limit=None)) == expected


@pytest.mark.corpus
@pytest.mark.parametrize("rel,expected", [
    ("thesis/ws/src/turtlerand/launch/generic.tvl", 4),
    ("thesis/ws/src/turtlerand/launch/generic_split.tvl", 4),
    ("thesis/ws/src/turtlerand/launch/generic_alt.tvl", 4),
    ("thesis/ws/src/turtlebot/launch/turtlebot.tvl", 776),
    ("thesis/ws/src/lizi/launch/generic.tvl", 2304),
    ("thesis/models/example_4_3.tvl", 20),
])
def test_thesis_counts(rel, expected, corpus_dir):
    p = corpus_dir / rel
    a = ModelAnalysis(parse_model(p.read_text(), str(p)).model)
    assert a.count() == expected
    assert sum(1 for _ in a.enumerate(limit=None)) == expected


def test_layout_does_not_change_the_cache_key():
    a = analysis("root R { group oneOf { A, B } }")
    b = analysis("// comment\nroot   R {\n  group oneOf {\n    A,\n    B\n  }\n}\n")
    assert a.encoding.logical_key() == b.encoding.logical_key()
    c = analysis("root R { group someOf { A, B } }")
    assert c.encoding.logical_key() != a.encoding.logical_key()


@pytest.mark.parametrize("text,expected", [
    ("root R { group someOf { A, B, C } count(selectedChildren) == 2; }", 3),
    ("root R { group someOf { A, B, C } count(selectedChildren) <= 1; }", 3),
    # sums: A 3, B -2, C 5; |sum| < 4 for A, B, AB (1), BC (3)
    ("root R { int p is sum(selectedChildren.v); group someOf { A { int v is 3; }, B { int v is -2; }, "
     "C { int v is 5; } } abs(p) < 4; }", 4),
    ("root R { int m is max(selectedChildren.v); group someOf { A { int v is 3; }, B { int v is 1; }, "
     "C { int v is 5; } } m < 5; }", 3),
    ("root R { int m is min(selectedChildren.v); group someOf { A { int v is 3; }, B { int v is 1; }, "
     "C { int v is 5; } } m > 2; }", 3),
    ("root R { group allOf { opt A, opt B } (A ? B : !B); }", 2),
    ("root R { bool b; group allOf { opt A, opt B } b -> A; !b -> B; }", 3),
    ("root R { enum c in {x, y, z}; group allOf { opt A, opt B } A -> c in {x, y}; B -> c == z; }", 3),
    ("root R { int n in [0..10]; group allOf { opt A, opt B } A -> n * 2 > 15; B -> n + 3 < 5; }", 3),
    ("root R { group allOf { opt A { int w in {1, 2}; }, opt B { int w in {3}; } } A.w + B.w == 4; }", 4),
    ("root R { group allOf { opt A, opt B } and(A, B) || xor(A, B); }", 3),
    # an ifIn value outside the attribute's domain makes its feature dead
    ("root R { group allOf { opt A { int n in [1..3], ifIn: is 2; }, opt B } }", 4),
    ("root R { group allOf { opt A { int n, ifIn: is 2, ifOut: is 7; }, opt B } B -> A.n > 5; }", 3),
])
def test_expressions_and_attributes(text, expected):
    assert count(text) == expected


def test_attribute_value_outside_its_domain_kills_its_feature():
    text = "root R { group allOf { opt A { int n in [1..3], ifIn: is 5; }, opt B } }"
    a = ModelAnalysis(parse_model(text, "x.tvl").model)  # the checker reports the value too
    assert a.count() == 2 and a.dead_features() == ["A"]
