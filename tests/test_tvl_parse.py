"""TVL front end: grammar coverage, the model it builds, exact ranges."""

from tvl_lsp.base.text import Pos, Span
from tvl_lsp.tvl import parse_model
from tvl_lsp.tvl import model as m


def parse(text, path="/m/model.tvl", files=None):
    files = files or {}
    return parse_model(text, path, read_file=lambda p: files.get(p))


def errors(res):
    return [d for d in res.diagnostics if d.severity == 1]


FULL = """// every construct of the reference grammar
int price in [0..100];
real weight;
enum color in {red, green};
bool flag;
struct size { real w; real h in [0..10]; }
const int two 2;
const real half 0.5;
const bool yes true;
root Car {
  data { "k" "v"; "k2" "v2" }
  int cost is 3, ifIn: is 4, ifOut: is 0;
  real r in [1.5..*];
  enum e in {a, b}, ifin: in {a};
  price p;
  size s { w in [1..2]; h is 3; }
  group [1..two] {
    opt Engine { group oneof { Petrol, Diesel } },
    Wheels group allOf { Front, Back },
    opt shared Petrol
  }
  ifIn: cost > 1;
  ifOut: !Engine;
  Engine requires Wheels;
  Diesel excludes Petrol;
  cost + 1 * 2 >= 3 ? true : false;
  this.cost == abs(-3) <- Engine -> Wheels <-> true;
  sum(children.cost) == 0 || count(selectedChildren) < 2 && max(1, 2, 3) <= 4;
  and(Engine, Wheels) || or(Front) || xor(Back, Front);
  e in {a, b};
  root.Engine.Petrol -> parent.cost == 1 || this.s.w > 1.5;
}
Engine { int cost is 1; parent.cost > 0; }
Car.Engine.Petrol { int cost is 2; }
root Car { bool extra; }
"""


def test_full_grammar_parses_without_errors():
    res = parse(FULL.replace("parent.cost == 1 ||", "Engine.cost == 1 ||"))
    # 'parent' is refused in a shared feature (Petrol is shared by Car)
    assert [d.code for d in errors(parse(FULL + "Petrol { parent.cost > 0; }"))][-1:] == ["parent-in-shared"]
    assert errors(res) == [], [str(d.span) + d.message for d in errors(res)]
    mdl = res.model
    assert mdl.root.name == "Car" and mdl.root.is_root
    assert [t.name for t in mdl.types] == ["price", "weight", "color", "flag", "size"]
    assert [c.name for c in mdl.constants] == ["two", "half", "yes"]
    g = mdl.root.group
    assert g.kind == "card" and (g.lo, g.hi) == (1, 2)
    assert g.hi_expr.target is mdl.constants[0]
    kids = {c.feature.name: c for c in g.children}
    assert kids["Engine"].optional and not kids["Engine"].shared
    assert kids["Petrol"].shared and kids["Petrol"].optional
    petrol = mdl.feature("Car.Engine.Petrol")
    assert mdl.root in petrol.shared_parents and petrol.parent.name == "Engine"
    assert mdl.feature("Wheels").group.kind == "allOf" and (mdl.feature("Wheels").group.lo, mdl.feature("Wheels").group.hi) == (2, 2)
    assert mdl.feature("Engine").group.kind == "oneOf"
    assert [a.name for a in mdl.root.attributes] == ["cost", "r", "e", "p", "s", "extra"]
    cost = mdl.root.attributes[0]
    assert isinstance(cost.value, m.IntLit) and cost.if_in_value.value == 4 and cost.if_out_value.value == 0
    s = mdl.root.attributes[4]
    assert s.type_decl.base == "struct" and set(s.field_refinements) == {"w", "h"}
    assert [d.key for d in mdl.root.data] == ["k", "k2"]
    kinds = [c.kind for c in mdl.root.constraints]
    assert kinds[:2] == ["ifIn", "ifOut"] and all(c.expr.type == "bool" for c in mdl.root.constraints)
    # reopenings: 'Engine {', 'Car.Engine.Petrol {' and a later 'root Car'
    assert len(mdl.feature("Car.Engine").decl_spans) == 2
    assert len(mdl.root.decl_spans) == 2


def test_exact_name_spans_and_decl_spans():
    text = "root Car {\n  group allOf {\n    opt Engine,\n    Wheels\n  }\n}\nEngine { }\n"
    res = parse(text)
    eng = res.model.feature("Engine")
    assert eng.name_span == Span(Pos(2, 8), Pos(2, 14))
    assert eng.decl_spans == [("/m/model.tvl", Span(Pos(2, 8), Pos(2, 14))), ("/m/model.tvl", Span(Pos(6, 0), Pos(6, 6)))]
    assert res.model.root.name_span == Span(Pos(0, 5), Pos(0, 8))
    assert res.model.root.group.keyword_span == Span(Pos(1, 8), Pos(1, 13))


def test_expression_precedence_and_types():
    text = "root A { int x; group allOf { B } 1 + 2 * 3 == 7 && B || !B -> B; x > 1 ? B : !B; }"
    res = parse(text)
    assert errors(res) == []
    c1, c2 = res.model.root.constraints
    e = c1.expr
    # -> is the lowest here: ((... && B) || !B) -> B
    assert isinstance(e, m.Binary) and e.op == "->"
    assert e.left.op == "||" and e.left.left.op == "&&"
    eq = e.left.left.left
    assert eq.op == "==" and eq.left.op == "+" and eq.left.right.op == "*"
    assert eq.left.type == "int" and eq.type == "bool"
    assert isinstance(c2.expr, m.Ternary) and c2.expr.type == "bool"


def test_right_assoc_implication_and_ternary():
    res = parse("root A { group allOf { B, C, D } B <- C <- D; B ? C : D ? B : C; }")
    assert errors(res) == []
    e = res.model.root.constraints[0].expr
    assert e.op == "<-" and isinstance(e.right, m.Binary) and e.right.op == "<-"
    t = res.model.root.constraints[1].expr
    assert isinstance(t.other, m.Ternary)


def test_nonassoc_comparison_is_a_syntax_error():
    res = parse("root A { int x; group allOf { B } 1 < x < 3; }")
    assert [d.code for d in errors(res)] == ["syntax-error"]


def test_lowercase_aliases_and_selected_children():
    res = parse("root A { int p is sum(selectedchildren.p); group someof { B { int p is 1; }, C { int p is 2; } } "
                "ifin: B; ifout: !C; }")
    assert errors(res) == []
    agg = res.model.root.attributes[0].value
    assert agg.over == "selectedChildren" and agg.attr == "p" and agg.owner is res.model.root and agg.type == "int"


def test_names_resolve_to_targets():
    text = ("const int k 3;\nenum col in {red, blue};\nroot A { col c; int n is k; group allOf { B { int q; } }\n"
            "B.q > k; c == red; this.n == root.B.q; }\n")
    res = parse(text)
    assert errors(res) == []
    mdl = res.model
    cons = mdl.root.constraints
    bq = cons[0].expr.left
    assert bq.target is mdl.feature("B").attributes[0] and bq.feature is mdl.feature("B")
    assert bq.part_targets == [mdl.feature("B"), mdl.feature("B").attributes[0]]
    assert cons[0].expr.right.target is mdl.constants[0]
    red = cons[1].expr.right
    assert isinstance(red.target, m.EnumValue) and red.target.name == "red"
    assert cons[1].expr.left.type.startswith("enum")


def test_include_is_textual_and_relative_to_the_including_file():
    files = {"/m/sub/b.tvl": "B { int x is 1; }\ninclude(c.tvl);\n", "/m/sub/c.tvl": "C { }\n"}
    res = parse("root A { group allOf { B, C } }\ninclude(sub/b.tvl);\n", files=files)
    assert errors(res) == []
    b = res.model.feature("B")
    assert b.attributes[0].path == "/m/sub/b.tvl"
    assert ("/m/sub/b.tvl", Span(Pos(0, 0), Pos(0, 1))) in b.decl_spans
    assert ("/m/sub/c.tvl", Span(Pos(0, 0), Pos(0, 1))) in res.model.feature("C").decl_spans
    assert [i.resolved for i in res.model.includes] == ["/m/sub/b.tvl", "/m/sub/c.tvl"]
    assert set(res.model.sources) == {"/m/model.tvl", "/m/sub/b.tvl", "/m/sub/c.tvl"}


def test_comments_are_ignored():
    res = parse("/* head */ root A { // line\n group allOf { B /* in */ } }\n")
    assert errors(res) == [] and res.model.feature("B") is not None
