"""The UVL front end: the model it builds (same objects as TVL's), its semantics (checked against a
brute-force enumeration written independently here), exact diagnostics and error recovery."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.project.check import check_document
from tvl_lsp.tvl import model as M
from tvl_lsp.uvl import parse_uvl

DATA = Path(__file__).parent / "data" / "uvl"


def parse(text: str, path: str = "/tmp/m.uvl", files: dict | None = None):
    return parse_uvl(text, path, read_file=(files or {}).get)


def parse_file(name: str):
    p = DATA / name
    return parse_uvl(p.read_text(), str(p))


def brute(names, ok) -> int:
    return sum(ok(dict(zip(names, bits))) for bits in itertools.product((False, True), repeat=len(names)))


def diags(res, code=None):
    return [(d.span.start.line + 1, d.span.start.col + 1, d.code, d.message) for d in res.diagnostics
            if code is None or d.code == code]


# ------------------------------------------------------------------ the model

def test_robot_model_objects_and_spans():
    res = parse_file("robot.uvl")
    assert res.errors == []
    m = res.model
    assert m.format == "uvl" and m.root.name == "Robot" and m.root.is_root
    names = [f.name for f in m.features]
    assert names == ["Robot", "Base", "Kobuki", "Create", "Sensor 3D", "Kinect", "Astra", "Teleop", "Keyboard",
                     "Joystick", "Tablet", "Arm"]
    robot = m.root
    assert [g.keyword for g in robot.groups] == ["mandatory", "optional"]
    assert [(c.feature.name, c.optional) for c in robot.group.children] == [("Base", False), ("Sensor 3D", False)]
    assert [(c.feature.name, c.optional) for c in robot.extra_groups[0].children] == [("Teleop", True), ("Arm", True)]
    base, s3d, teleop = m.feature("Base"), m.feature("Sensor 3D"), m.feature("Teleop")
    assert (base.group.kind, base.group.lo, base.group.hi) == ("oneOf", 1, 1)
    assert (s3d.group.kind, s3d.group.lo, s3d.group.hi) == ("someOf", 1, None)
    assert (teleop.group.kind, teleop.group.lo, teleop.group.hi, teleop.group.keyword) == ("card", 1, 2, "[1..2]")
    # exact spans: the quoted name (with its quotes), the keyword, the whole subtree
    assert str(s3d.name_span) == "15:4-15:15"  # (1-based lines and columns)
    assert str(teleop.group.keyword_span) == "21:5-21:11"
    assert (teleop.span.start.line + 1, teleop.span.end.line + 1) == (20, 24)
    # attributes are kept (not analysed); abstract is understood
    arm = m.feature("Arm")
    assert [(a.name, a.type) for a in arm.attributes] == [("weight", "Integer"), ("vendor", "String")]
    assert getattr(robot, "abstract", False) is True
    create = m.feature("Create")
    assert create.attributes[0].value.value == "an iRobot Create. Discontinued."
    # constraints resolved to features, with spans
    cons = robot.constraints
    assert [str(c.span) for c in cons] == ["28:2-28:15", "29:2-29:19", "30:2-30:42"]
    last = cons[2].expr
    assert last.op == "<->" and last.left.target is m.feature("Tablet")


def test_robot_count_matches_brute_force():
    res = parse_file("robot.uvl")
    names = ["Base", "Kobuki", "Create", "S3D", "Kinect", "Astra", "Teleop", "Keyboard", "Joystick", "Tablet", "Arm"]

    def ok(v):
        if not (v["Base"] and v["S3D"]):  # mandatory under the root
            return False
        if v["Kobuki"] + v["Create"] != 1:  # alternative
            return False
        if not (v["Kinect"] or v["Astra"]):  # or
            return False
        kids = v["Keyboard"] + v["Joystick"] + v["Tablet"]
        if v["Teleop"] and not 1 <= kids <= 2:
            return False
        if not v["Teleop"] and kids:
            return False
        if v["Arm"] and not v["Kobuki"]:
            return False
        if v["Kinect"] and v["Astra"]:
            return False
        if v["Tablet"] != ((v["Arm"] or v["S3D"]) and not v["Create"]):
            return False
        return True
    assert ModelAnalysis(res.model).count() == brute(names, ok) == 20


def test_multiple_groups_under_one_feature():
    res = parse_file("multigroups.uvl")
    assert res.errors == []
    drone = res.model.root
    assert [g.text for g in drone.groups] == ["mandatory", "optional", "alternative", "[2..3]", "or"]
    assert [f.name for f in drone.children] == ["Frame", "Camera", "Quad", "Hexa", "Gps", "Imu", "Baro",
                                                "Compass", "Wifi", "Radio"]
    names = ["Frame", "Camera", "Quad", "Hexa", "Gps", "Imu", "Baro", "Compass", "Wifi", "Radio"]

    def ok(v):
        return (v["Frame"] and v["Quad"] + v["Hexa"] == 1 and 2 <= v["Gps"] + v["Imu"] + v["Baro"] + v["Compass"] <= 3
                and (v["Wifi"] or v["Radio"]) and (not v["Hexa"] or v["Camera"]))
    a = ModelAnalysis(res.model)
    assert a.count() == brute(names, ok) == 90
    # the optional block's children are the optional ones (false-optional is about them only)
    assert [f.name for f in drone.children if f.optional] == ["Camera"]


def test_imports_nested_aliases_and_count():
    res = parse_file("imports/main.uvl")
    assert res.errors == [] and res.diagnostics == []
    m = res.model
    assert [f.name for f in m.features] == ["Rover", "Wheels", "Small", "Big", "Motors", "Weak", "Strong", "Sensors",
                                            "Lidar", "Sonar"]
    wheels = m.feature("Wheels")
    assert wheels.path.endswith("parts/wheels.uvl") and wheels.parent is m.root
    # the reference in the importing file is a declaration place too
    assert [(Path(p).name, str(s)) for p, s in wheels.decl_spans] == [("wheels.uvl", "4:2-4:8"), ("main.uvl", "7:4-7:12")]
    assert set(m.sources) == {str(DATA / "imports" / n) for n in ("main.uvl", "parts/wheels.uvl",
                                                                  "parts/motors.uvl", "sensors.uvl")}
    # Lidar => Big (main), Big => Strong (wheels): 6 with small wheels, 4 with big ones
    assert ModelAnalysis(m).count() == 10
    lidar_big = m.root.constraints[0].expr
    assert lidar_big.left.target is m.feature("Lidar") and lidar_big.right.target is m.feature("Big")


def test_missing_import_is_one_error_and_no_cascade():
    res = parse("imports\n\tparts.wheels as w\nfeatures\n\tR\n\t\tmandatory\n\t\t\tw.Wheels\n\t\t\tA\n"
                "constraints\n\tw.Big => A\n", "/nowhere/m.uvl")
    assert diags(res) == [(2, 2, "import-not-found",
                           "cannot read the imported model 'parts.wheels' (/nowhere/parts/wheels.uvl)")]
    assert [f.name for f in res.model.features] == ["R", "A"]


def test_import_cycle_and_unused_import():
    files = {"/w/a.uvl": "imports\n\tb\nfeatures\n\tA\n\t\toptional\n\t\t\tb.B\n",
             "/w/b.uvl": "imports\n\ta\nfeatures\n\tB\n"}
    res = parse(files["/w/a.uvl"], "/w/a.uvl", files)
    assert [(d.path, d.code) for d in res.diagnostics] == [("/w/b.uvl", "import-cycle")]
    assert ModelAnalysis(res.model).count() == 2
    res = parse("imports\n\tb\nfeatures\n\tA\n", "/w/a.uvl", {"/w/b.uvl": "features\n\tB\n"})
    assert [(d.code, str(d.span)) for d in res.diagnostics] == [("import-unused", "2:2-2:3")]


def test_not_analysed_parts_are_reported_once_each():
    res = parse_file("levels.uvl")
    got = diags(res)
    assert res.errors == []
    assert [(l, c, code) for l, c, code, _ in got] == [
        (4, 4, "not-analysed"), (5, 21, "not-analysed"), (7, 13, "not-analysed"), (7, 24, "not-analysed"),
        (11, 2, "not-analysed"), (12, 2, "not-analysed"), (13, 2, "not-analysed")]
    assert "typed feature" in got[0][3] and "feature cardinality [1..2]" in got[1][3]
    assert "attribute 'price' of Topping (and on 1 other feature)" in got[2][3]
    assert "compares values" in got[4][3]
    m = res.model
    # the boolean constraint is analysed, the others are kept for converters
    assert len(m.root.constraints) == 1
    assert [u.kind for u in m.unanalysed if u.kind != "attribute"] == ["feature-type", "feature-cardinality",
                                                                       "constraint", "constraint", "constraint"]
    assert ModelAnalysis(m).count() == 3  # Topping | Sauce


def test_check_reports_dead_and_false_optional_features_with_explanations():
    out = check_document(str(DATA / "anomalies.uvl"))
    got = [(d.span.start.line + 1, d.code, d.message) for d in out]
    assert got[0][:2] == (10, "dead-feature") and "Turbo is dead" in got[0][2]
    assert "group alternative of Engine: at most 1 of Petrol, Electric" in got[0][2]
    assert got[1][:2] == (11, "false-optional") and "Radio" in got[1][2]
    assert {r.path for d in out for r in d.related} == {str(DATA / "anomalies.uvl")}


# ------------------------------------------------------------------ diagnostics and recovery

def test_several_independent_mistakes_get_one_error_each():
    res = parse_file("errors/several.uvl")
    got = [(l, c, code) for l, c, code, _ in diags(res)]
    assert got == [(4, 9, "syntax-error"), (5, 4, "syntax-error"), (12, 3, "syntax-error"), (16, 18, "syntax-error"),
                   (17, 2, "unknown-name")]
    msgs = [d.message for d in res.diagnostics]
    assert msgs[0] == "this '{' is never closed on its line"
    assert msgs[1] == 'a feature name cannot begin with a digit: write it in double quotes ("12Wheels")'
    assert msgs[2] == "unexpected name alternativ: did you mean the group keyword 'alternative'?"
    assert msgs[4] == "no feature named 'Lidr'. Did you mean 'Lidar'?"
    # the rest is read: Base kept its name, the good constraint is analysed
    m = res.model
    assert m.feature("Base") is not None and m.feature("X") is None
    assert [c.span.start.line + 1 for c in m.root.constraints] == [18]
    assert ModelAnalysis(m).count() == 7


@pytest.mark.parametrize("text,expected", [
    # a group keyword at a feature's level
    ("features\n    A\n    mandatory\n            B\n",
     [(3, 5, "'mandatory' stands where a feature is expected: indent it under the feature whose children it groups")]),
    # a feature without a group keyword above it
    ("features\n\tA\n\t\tB\n", [(3, 3, "unexpected name B; expected a group keyword (mandatory, optional, or, "
                                        "alternative, [n..m])")]),
    # a dedent to a level that matches no block
    ("features\n\tA\n\t\toptional\n\t\t\tB\n\t  C\n",
     [(5, 1, "this line's indentation matches no enclosing level (check tabs and spaces)")]),
    # two features on one line
    ("features\n\tA\n\t\toptional\n\t\t\tB C\n",
     [(4, 6, "unexpected name C: one feature per line (a name with spaces is written in double quotes)")]),
    # an operator missing its operand; a dot in a quoted name
    ("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\tB =>\n",
     [(6, 6, "unexpected end of line; expected a feature name, '!' or '('")]),
    ('features\n\t"A.B"\n', [(2, 2, "a quoted feature name cannot contain '.' (it separates an import's name "
                                     "from its features)")]),
    # TVL / C habits in a constraint
    ("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\tA && B\n", [(6, 4, "UVL writes '&', not '&&'")]),
    ("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\tA || B\n", [(6, 4, "UVL writes '|', not '||'")]),
    ("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\tB -> A\n",
     [(6, 4, "UVL writes an implication '=>', not '->'")]),
    # types: a number where a constraint is expected
    ("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\tB & 3\n", [(6, 6, "a number is not a boolean")]),
    ("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\t(B & A) + 1 > 0\n",
     [(6, 2, "'&' gives a boolean, not a value")]),
    # cardinalities
    ("features\n\tA\n\t\t[3..1]\n\t\t\tB\n\t\t\tC\n\t\t\tD\n",
     [(3, 3, "the group cardinality [3..1] has its upper bound below its lower bound: no product can select A")]),
    ("features\n\tA\n\t\t[ 1 .. 2 ]\n\t\t\tB\n\t\t\tC\n", [(3, 3, "UVL writes a cardinality without spaces: [1..2]")]),
    # two roots, duplicate names, an unterminated string, an illegal character
    ("features\n\tA\n\tB\n", [(3, 2, "a UVL model has one root feature, 'A': 'B' and what is below it are not read "
                                     "(indent it under a feature)")]),
    ("features\n\tA\n\t\toptional\n\t\t\tB\n\t\t\tB\n",
     [(5, 4, "two features are named 'B': constraints cannot tell them apart (rename one)")]),
    ("features\n\tA {x 'abc}\n", [(2, 7, "this string is never closed on its line")]),
    ("features\n\tA\n\t\toptional\n\t\t\tB @\n", [(4, 6, "illegal character(s) '@' in a UVL model")]),
    ("features\n\tA \u00a0\n", [(2, 4, "illegal character(s) U+00A0 (no-break space) in a UVL model")]),
])
def test_exact_messages(text, expected):
    res = parse(text)
    got = [(l, c, m) for l, c, code, m in diags(res) if code != "not-analysed"]
    assert got == expected


def test_a_broken_feature_line_keeps_its_feature():
    res = parse("features\n\tA\n\t\toptional\n\t\t\tB {x 1,, y 2}\n\t\t\tC\nconstraints\n\tB => C\n")
    assert [(d.code, str(d.span)) for d in res.diagnostics] == [("syntax-error", "4:11-4:12")]
    assert [f.name for f in res.model.features] == ["A", "B", "C"]
    assert len(res.model.root.constraints) == 1


def test_dropped_features_do_not_cascade_into_constraints():
    # 'Arm' and what is below it are dropped with the bad line; constraints naming them are left
    # out silently (the syntax error explains)
    res = parse("features\n\tR\n\t\toptional\n\t\t\t1Arm\n\t\t\t\toptional\n\t\t\t\t\tGripper\n"
                "constraints\n\tGripper => R\n")
    assert [d.code for d in res.diagnostics] == ["syntax-error"]


def test_bad_input_never_raises():
    for text in ["", "\n\n", "features", "features\n", "constraints\n\t&&&\n", "\t\t\tfeatures\n", "{" * 500,
                 "features\n\tA\n" + "\t" * 300 + "B\n", "features\n\tA {" + "[" * 2000 + "\n",
                 "imports\n\t" + ".".join(["a"] * 100) + "\n", "features\n\tA\nconstraints\n\t" + "(" * 3000 + "A" + ")" * 3000,
                 "features\n\tA\n\t\toptional\n" + "".join(f"\t\t\tF{i}\n" for i in range(3000)),
                 "namespace\ninclude\n\tFoo\nimports\n\t.\n", "features\n\t\"\n", "/* never closed\nfeatures\n"]:
        res = parse(text)
        assert isinstance(res.model, M.Model)
        ModelAnalysis(res.model).count()


def test_deep_constraint_is_not_analysed_but_reported():
    deep = "(" * 400 + "B" + ")" * 400
    res = parse(f"features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\t{deep}\n")
    assert [d.code for d in res.diagnostics] == ["not-analysed"]
    assert "nested too deeply" in res.diagnostics[0].message


def test_long_chains_do_not_recurse():
    names = [f"F{i}" for i in range(5000)]
    text = ("features\n\tA\n\t\toptional\n" + "".join(f"\t\t\t{n}\n" for n in names)
            + "constraints\n\t" + " | ".join(names) + "\n\t" + " & ".join(f"!{n}" for n in names[:10]) + "\n")
    res = parse(text)
    assert res.errors == []
    a = ModelAnalysis(res.model)
    assert not a.is_void()
    assert sorted(len(c) for c in a.encoding.clauses())[-1] == 5000
    assert a.encoding.nvars == 5001  # no auxiliary variable


def test_windows_line_ends_and_spaces():
    text = "features\r\n    A\r\n        optional\r\n            B\r\nconstraints\r\n    B => A\r\n"
    res = parse(text)
    assert res.diagnostics == [] and ModelAnalysis(res.model).count() == 2
    assert str(res.model.feature("B").name_span) == "4:13-4:14"


def test_dimacs_first_class_in_check(tmp_path):
    p = tmp_path / "m.dimacs"
    p.write_text("c 1 A\nc 2 B\nc 3 C\np cnf 3 3\n1 0\n-1 -3 0\n-2 3 0\n")
    got = [(d.code, d.message, d.span.start.line) for d in check_document(str(p))]
    # B needs C, A excludes C, A is forced: B and C are dead (on their `c` lines), explained by clauses
    assert [(c, line) for c, _, line in got] == [("dead-feature", 1), ("dead-feature", 2)]
    assert "Because:" in got[0][1]
    # no false-optional in a flat CNF (all the core features would be)
    bad = tmp_path / "bad.dimacs"
    bad.write_text("p cnf 2 1\n1 x 0\nc 1 A\nc 2 A\n")
    got = [(d.code, str(d.span)) for d in check_document(str(bad))]
    assert ("syntax-error", "2:3-2:4") in got and ("duplicate-feature-name", "4:5-4:6") in got


def test_check_gives_one_error_per_mistake_and_none_elsewhere(tmp_path):
    """Through the whole --check pipeline (front end and analyses): five independent mistakes, five
    errors at their places; the impossible cardinality does not add a void-model error."""
    p = tmp_path / "shop.uvl"
    p.write_text(
        "namespace Shop\n\nfeatures\n    Shop {abstract}\n        mandatory\n            Catalog\n"
        "            Payment\n                [3..1]\n                    Card\n                    Cash\n"
        "        optional\n            Search {weight 2\n            Wishlist\n            \"Gift Card\"\n\n"
        "constraints\n    Search => Catalg\n    Wishlist => \"Gift Card\"\n    Card | => Cash\n"
        "    (Wishlist & Search\n")
    errs = [(d.code, str(d.span)) for d in check_document(str(p)) if d.severity == 1]
    assert errs == [("cardinality-bounds", "8:17-8:23"), ("syntax-error", "12:20-12:21"),
                    ("unknown-name", "17:15-17:21"), ("syntax-error", "19:12-19:14"),
                    ("syntax-error", "20:23-20:23")], errs
