"""The ROS 2 launch front end against the real ros2/launch (its answers recorded in
tests/data/ros2/golden by scripts/ros2_golden.py), plus its parts: the substitution grammar,
exact ranges in XML and YAML, dialect detection, ament workspaces and robustness."""

from __future__ import annotations

import json
import os
import random
from pathlib import Path

import pytest

from tvl_lsp.base.formula import evaluate, variables
from tvl_lsp.launch.ros2 import analyse_launch2, detect_dialect, free_args2, load_launch2
from tvl_lsp.launch.ros2 import actions as A
from tvl_lsp.launch.ros2 import subst as S
from tvl_lsp.launch.ros2.ament import find_ament_packages, guess_ament_root
from tvl_lsp.launch.ros2.frontend import parse_launch_file

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "ros2"
WS = DATA / "ws"
GOLDEN = sorted((DATA / "golden").glob("*.json"))
ENV = {"R2_ROBOT": "burger", "PATH": os.environ.get("PATH", "/usr/bin:/bin")}


def _golden(p: Path) -> dict:
    return json.loads(p.read_text())


def _ws(s):
    return s.replace(str(WS), "$WS") if isinstance(s, str) else s


def _nodes(nodes, key_name="name"):
    return [(n[key_name], n["package"], n["executable"], [list(r) for r in n["remaps"]]) for n in nodes]


# ------------------------------------------------------------------ the oracle's answers

# where tvl-lsp's message cannot be the oracle's: the oracle's own prefix path in "searching:",
# its refusal of Python files, lark's and expat's own error texts for malformed files
KNOWN_MESSAGE_DIFFERENCES = {"errors_missing_pkg", "composable_no_stub", "bad_subst", "bad_not_xml"}


@pytest.mark.parametrize("golden", GOLDEN, ids=[p.stem for p in GOLDEN])
def test_concrete_load_equals_ros2_launch(golden):
    """nodes (full name, package, executable), remaps and the error of `tvl-lsp launch` equal
    the real ros2/launch's."""
    d = _golden(golden)
    case, want = d["case"], d["result"]
    res = load_launch2(str(WS / "src" / case["file"]), case["args"], workspace_root=str(WS), env=ENV,
                       stub_packages="--stub-missing-packages" in case["options"])
    assert _nodes(res.nodes) == _nodes(want["nodes"])
    assert (res.error is None) == (want["error"] is None), (res.error, want["error"])
    if want["error"] is not None and golden.stem not in KNOWN_MESSAGE_DIFFERENCES:
        assert _ws(res.error) == want["error"]
        assert res.error_type == want["error_type"]
    # what the root file declared, and the launch configurations at the end
    if want["error"] is None:
        assert {k: _ws(v) for k, v in res.declared.items()} == want["args"]
        want_conf = {k: v for k, v in want["launch_configurations"].items() if k != "ros_namespace"}
        got_conf = {k: _ws(v) for k, v in res.configurations.items() if k in want_conf or k != "ros_namespace"}
        assert {k: got_conf.get(k) for k in want_conf} == want_conf


def _params_equal(got: dict, want: dict) -> bool:
    return {k: (_ws(v) if isinstance(v, str) else v) for k, v in got.items()} == want


@pytest.mark.parametrize("name", ["nodes_defaults", "nodes_r2", "nodes_yaml_defaults", "substitutions_defaults",
                                  "includes_defaults"])
def test_inline_params_equal_ros2_launch(name):
    """Inline <param> values (typed by YAML, nested names flattened) as launch passes them."""
    d = _golden(DATA / "golden" / f"{name}.json")
    res = load_launch2(str(WS / "src" / d["case"]["file"]), d["case"]["args"], workspace_root=str(WS), env=ENV)
    for got, want in zip(res.nodes, d["result"]["nodes"]):
        inline = {k: v for k, v in want["params"].items() if k in got["params"]}
        assert _params_equal(got["params"], inline), (got["name"], got["params"], want["params"])


def _symbolic_cases():
    """Runs whose args are all free booleans of the file (the symbolic analysis's variables)."""
    out = []
    for p in GOLDEN:
        d = _golden(p)
        case = d["case"]
        if case["options"] or d["result"].get("error_type") == "PackageNotFoundError":
            continue
        if any(v not in ("true", "false") for v in case["args"].values()):
            continue
        path = WS / "src" / case["file"]
        free = set(free_args2(path.read_text(), str(path)))
        if path.parent.name == "launch" and path.parent.parent.name == "r2_robot":
            free = set(free) | set(case["args"])  # the generic files: every feature is free
        if all(k in free for k in case["args"]):
            out.append(p)
    return out


SYMBOLIC = _symbolic_cases()


@pytest.mark.parametrize("golden", SYMBOLIC, ids=[p.stem for p in SYMBOLIC])
def test_symbolic_analysis_equals_ros2_launch(golden):
    """The symbolic analysis (all values of the boolean args at once), evaluated at the run's
    args, has the oracle's nodes; where launch fails, an error fact holds there."""
    d = _golden(golden)
    case, want = d["case"], d["result"]
    path = WS / "src" / case["file"]
    text = path.read_text()
    doc = parse_launch_file(text, str(path))
    acts, _ = A.parse_description(doc.root, str(path))
    free = set(free_args2(text, str(path))) | set(case["args"])
    assign = {}
    for a in acts:
        if not isinstance(a, A.ArgA):
            continue
        if a.choices is not None:
            val = case["args"].get(a.name, a.default.text if a.default else None)
            assign.update({f"{a.name}={c}": c == val for c in a.choices})
        elif a.name in free:
            v = case["args"].get(a.name, a.default.text if a.default is not None else "false")
            assign[a.name] = v.strip().lower() in ("true", "1")
    feats = [n for n in free if n in assign]
    la = analyse_launch2(text, str(path), workspace_root=str(WS), env=ENV, features=feats)

    def holds(c):
        return evaluate(c, {v: assign.get(v, False) for v in variables(c)})
    got = [(n.name or None, n.package, n.executable or None, [list(r) for r in n.remaps])
           for n in la.nodes if holds(n.condition)]
    errors = [f for f in la.facts if (f.severity == 1 or f.code == "unset-arg") and holds(f.condition)]
    errors += [x for x in la.diagnostics if x.severity == 1]
    if want["error"] is None:
        assert got == _nodes(want["nodes"]) and not errors, [(f.code, f.message) for f in errors]
    else:
        assert errors, want["error"]
        assert got[:len(want["nodes"])] == _nodes(want["nodes"])


def test_golden_files_cover_the_issue():
    """The recorded runs exercise every semantic the oracle README lists."""
    names = {p.stem for p in GOLDEN}
    for must in ("args_bad_choice", "scopes_defaults", "global_scope", "conditions_yes", "errors_eval_bool",
                 "errors_undefined", "errors_missing", "required_cond", "dirname_leak", "includes_python",
                 "nodes_yaml_defaults", "all_yaml_bad_choice", "generic_00", "generic_yaml_00", "issues_00"):
        assert must in names
    assert len([n for n in names if n.startswith("generic_")]) >= 20


# ------------------------------------------------------------------ the substitution grammar

@pytest.mark.parametrize("text,expected", [
    ("abc", [("T", "abc")]),
    ("a$(var x)b", [("T", "a"), ("S", "var", [[("T", "x")]]), ("T", "b")]),
    ("$(var x default)", [("S", "var", [[("T", "x")], [("T", "default")]])]),
    ("$(env X 'a b')", [("S", "env", [[("T", "X")], [("T", "a b")]])]),
    ("\\$(var x)", [("T", "$(var x)")]),
    ("$(and $(var a) $(var b))", [("S", "and", [[("S", "var", [[("T", "a")]])], [("S", "var", [[("T", "b")]])]])]),
    ("$(eval '\"$(var m)\" == \"r\"')",
     [("S", "eval", [[("T", '"'), ("S", "var", [[("T", "m")]]), ("T", '" == "r"')]])]),
    ("x $ y", [("T", "x $ y")]),
])
def test_substitution_grammar(text, expected):
    def conv(parts):
        out = []
        for p in parts:
            if isinstance(p, S.Text):
                out.append(("T", p.text))
            else:
                out.append(("S", p.name, [conv(a) for a in p.args]))
        return out
    assert conv(S.parse(text)) == expected


@pytest.mark.parametrize("text", ["$(var  x)", "$(var x )", "$(1x)", "$(var a'b)", "$(var x", "$(eval 'x)"])
def test_substitution_grammar_errors(text):
    with pytest.raises(S.SubstSyntaxError):
        S.parse(text)


def test_substitution_positions():
    parts = S.parse("pre $(var name) $(find-pkg-share pkg)/x")
    subs = list(S.walk(parts))
    assert [(s.name, s.start, s.end) for s in subs] == [("var", 4, 15), ("find-pkg-share", 16, 37)]


# ------------------------------------------------------------------ exact ranges

def test_xml_ranges_of_elements_and_substitutions():
    path = WS / "src" / "r2_bringup" / "launch" / "args.launch.xml"
    text = path.read_text()
    la = analyse_launch2(text, str(path), workspace_root=str(WS), env=ENV)
    lines = text.splitlines()
    node = next(e for e in la.elements if e.tag == "node" and e.attrs.get("name") and e.attrs["name"].value == "lidar")
    sp = node.attrs["if"].value_span
    assert lines[sp.start.line][sp.start.col:sp.end.col] == "$(var use_lidar)"
    sub = next(s for s in node.substitutions if s.kind == "var")
    assert lines[sub.span.start.line][sub.span.start.col:sub.span.end.col] == "$(var use_lidar)"
    assert sub.args == ("use_lidar",)
    # the start tag
    assert lines[node.span.start.line][node.span.start.col:].startswith("<node")


def test_yaml_ranges_of_elements_and_substitutions():
    path = WS / "src" / "r2_bringup" / "launch" / "nodes.launch.yaml"
    text = path.read_text()
    la = analyse_launch2(text, str(path), workspace_root=str(WS), env=ENV)
    lines = text.splitlines()
    cam = next(e for e in la.elements if e.tag == "node" and e.attrs.get("name") and e.attrs["name"].value == "camera")
    assert lines[cam.tag_span.start.line][cam.tag_span.start.col:cam.tag_span.end.col] == "node"
    sp = cam.attrs["if"].value_span
    assert lines[sp.start.line][sp.start.col:sp.end.col] == "$(var use_camera)"
    remap = next(e for e in la.elements if e.tag == "remap")
    sub = next(s for s in remap.substitutions if s.kind == "var")
    assert lines[sub.span.start.line][sub.span.start.col:sub.span.end.col] == "$(var robot)"
    # the YAML arg declarations are the file's feature args
    assert [a.name for a in la.feature_args] == ["robot", "use_camera"]


def test_unknown_tag_and_attribute_are_errors_at_their_range(tmp_path):
    f = tmp_path / "bad.launch.xml"
    f.write_text('<launch>\n  <nod pkg="a" exec="b"/>\n  <node pkg="a" exec="b" colour="red"/>\n'
                 '  <node pkg="a" exec="b" name="$(vra x)"/>\n</launch>\n')
    la = analyse_launch2(f.read_text(), str(f), workspace_root=str(tmp_path), env=ENV)
    got = sorted((d.code, d.span.start.line, d.span.start.col) for d in la.diagnostics)
    assert got == [("unknown-attribute", 2, 25), ("unknown-substitution", 3, 31), ("unknown-tag", 1, 3)]
    res = load_launch2(str(f), {}, workspace_root=str(tmp_path), env=ENV)
    assert res.error.startswith("Caught multiple exceptions when trying to load file of format [xml]:\n"
                                " - RuntimeError: Unrecognized entity of the type: nod")
    assert res.nodes == []


# ------------------------------------------------------------------ semantics in the symbolic analysis

def _analyse(name: str, **kw):
    path = WS / "src" / name
    return analyse_launch2(path.read_text(), str(path), workspace_root=str(WS), env=ENV, **kw)


def test_invalid_condition_has_a_witness_condition():
    la = _analyse("r2_bringup/launch/errors.launch.xml")
    f = next(f for f in la.facts if f.code == "invalid-condition")
    assert "'maybe'" in f.message
    assert variables(f.condition) == {"bad_cond"}


def test_python_include_is_followed_and_the_rest_checked():
    """An <include> of a .launch.py file is analysed by the Python front end (never run): its
    node is there under the include's condition, and nothing says it is not analysed."""
    la = _analyse("r2_bringup/launch/includes.launch.xml")
    assert not [f for f in la.facts if f.code in ("python-launch-include", "launch-not-analysable")]
    driver = [n for n in la.nodes if n.name.endswith("/driver")]
    assert driver and all(n.pkg == "r2_sensors" and n.element.path.endswith("driver.launch.py") for n in driver)
    assert any(n.name == "/sensors/last" for n in la.nodes)


def test_required_arg_of_an_include_is_an_error_on_the_include():
    la = _analyse("r2_bringup/launch/required_cond.launch.xml")
    f = next(f for f in la.facts if f.code == "unset-arg")
    assert "map_path" in f.message


FEATURES = ["Robot", "Base", "Diff", "Omni", "Lidar", "Camera", "Fusion", "Teleop"]


def test_include_arg_leak_that_changes_a_later_element():
    la = _analyse("r2_robot/launch/issues.launch.xml", features=FEATURES)
    leaks = [f for f in la.facts if f.code == "include-arg-leak"]
    assert len(leaks) == 1
    assert "'30'" in leaks[0].message and variables(leaks[0].condition) == {"Camera"}


def test_duplicate_node_names_with_their_condition():
    la = _analyse("r2_robot/launch/issues.launch.xml", features=FEATURES)
    dups = [f for f in la.facts if f.code == "duplicate-node"]
    assert {frozenset(variables(f.condition)) for f in dups} >= {frozenset({"Camera", "Teleop"}),
                                                                 frozenset({"Diff", "Omni"})}


# ------------------------------------------------------------------ dialects and workspaces

def test_dialect_detection(tmp_path):
    r2 = WS / "src" / "r2_bringup" / "launch" / "args.launch.xml"
    assert detect_dialect(str(r2)).dialect == "ros2" and not detect_dialect(str(r2)).ambiguous
    yaml_file = WS / "src" / "r2_bringup" / "launch" / "all.launch.yaml"
    assert detect_dialect(str(yaml_file)).dialect == "ros2"
    legacy = WS / "src" / "r2_legacy" / "launch" / "legacy.launch.xml"
    d = detect_dialect(str(legacy))
    assert d.dialect == "ros1" and "ROS 1" in d.reason
    plain = WS / "src" / "r2_legacy" / "launch" / "plain.launch.xml"
    d = detect_dialect(str(plain))
    assert d.dialect == "ros1" and d.ambiguous and "catkin" in d.reason
    plain2 = WS / "src" / "r2_bringup" / "launch" / "plain.launch.xml"
    d = detect_dialect(str(plain2))
    assert d.dialect == "ros2" and d.ambiguous and "ament_cmake" in d.reason
    forced = tmp_path / "x.launch.xml"
    forced.write_text('<launch>\n  <!-- tvl-lsp: dialect=ros1 -->\n  <arg name="a" default="$(var b)"/>\n</launch>\n')
    d = detect_dialect(str(forced))
    assert d.dialect == "ros1" and "marker" in d.reason


def test_ament_workspace_packages(tmp_path):
    pk = find_ament_packages(str(WS))
    assert set(pk) == {"r2_bringup", "r2_sensors", "r2_robot", "r2_legacy", "r2_ext"}
    assert pk["r2_bringup"].dialect == "ros2" and pk["r2_legacy"].dialect == "ros1"
    # build install log are skipped, COLCON_IGNORE is honoured
    for sub in ("build/x", "install/x", "log/x", "src/ignored"):
        d = tmp_path / "ws" / sub
        d.mkdir(parents=True)
        (d / "package.xml").write_text(f"<package><name>{sub.replace('/', '_')}</name></package>")
    (tmp_path / "ws" / "src" / "ignored" / "COLCON_IGNORE").write_text("")
    (tmp_path / "ws" / "src" / "good").mkdir()
    (tmp_path / "ws" / "src" / "good" / "package.xml").write_text("<package><name>good</name></package>")
    assert set(find_ament_packages(str(tmp_path / "ws"))) == {"good"}
    assert guess_ament_root(str(tmp_path / "ws" / "src" / "good" / "launch" / "a.launch.xml")) == \
        str(tmp_path / "ws")


def test_find_pkg_share_is_the_source_folder():
    res = load_launch2(str(WS / "src" / "r2_bringup" / "launch" / "substitutions.launch.xml"), {},
                       workspace_root=str(WS), env=ENV)
    quoted = next(n for n in res.nodes if n["name"] == "/quoted")
    assert quoted["params"]["share"] == str(WS / "src" / "r2_sensors" / "config" / "lidar.yaml")


# ------------------------------------------------------------------ robustness

def test_bad_input_never_crashes():
    rnd = random.Random(3)
    files = sorted(WS.glob("src/*/launch/**/*.launch.*"))
    for f in files:
        text = f.read_text()
        for _ in range(12):
            i = rnd.randrange(len(text))
            j = min(len(text), i + rnd.randrange(1, 40))
            junk = rnd.choice(["", "$(", ")", "<", ">", '"', "'", "\n- ", ": ", "$(var", "{", "]", "\\"])
            t = text[:i] + junk + text[j:]
            la = analyse_launch2(t, str(f), workspace_root=str(WS), env=ENV)
            assert la.path == str(f)
            load_launch2(str(f), {}, workspace_root=str(WS), env=ENV, text=t)


@pytest.mark.parametrize("text", ["", "launch:", "launch: 5", "- a\n- b", "launch:\n  - node: 3\n",
                                  "launch:\n  - group: {children: [1, 2]}\n", "a: 1\nb: 2\n",
                                  "launch:\n  - arg: {name: [1]}\n", "launch:\n  - node: {pkg: p, exec: e, name: 5}\n"])
def test_bad_yaml_never_crashes(tmp_path, text):
    f = tmp_path / "x.launch.yaml"
    la = analyse_launch2(text, str(f), workspace_root=str(tmp_path), env=ENV)
    res = load_launch2(str(f), {}, workspace_root=str(tmp_path), env=ENV, text=text)
    assert res.error is not None and res.nodes == []
    assert any(d.severity == 1 for d in la.diagnostics), la.diagnostics


@pytest.mark.corpus
def test_the_ros1_corpus_is_read_as_ros1(corpus_dir):
    """Every real ROS 1 launch file of the corpus (.launch and the .launch.xml of MoveIt
    configurations in catkin packages) is read as ROS 1."""
    files = sorted(corpus_dir.rglob("*.launch")) + sorted(corpus_dir.rglob("*.launch.xml"))
    assert len(files) > 100
    wrong = [str(f) for f in files if detect_dialect(str(f)).dialect != "ros1"]
    assert wrong == []


def test_the_parse_cache_keeps_two_versions_of_a_file_and_a_bounded_number_of_characters(tmp_path, monkeypatch):
    """Found by bench/bench_server_fuzz.py: every text of an edited launch file stayed parsed
    (up to 4,000 parses, each many times its text in memory: +40 MB in the server after a
    thousand edits).  Now: at most two versions of one path, and a bound in characters."""
    from tvl_lsp.launch.ros2 import walker as W
    from tvl_lsp.launch.ros2.api import analyse_launch2
    monkeypatch.setattr(W, "_PARSED", {})
    monkeypatch.setattr(W, "_PARSED_CHARS", [0])
    path = str(tmp_path / "a.launch.xml")
    for i in range(30):
        analyse_launch2(f'<launch>\n  <arg name="x{i}" default="true"/>\n</launch>\n', path)
    mine = [k for k in W._PARSED if k[0] == path]
    assert len(mine) == W.VERSIONS_PER_PATH, mine
    assert W._PARSED_CHARS[0] == sum(k[1] for k in W._PARSED)
    monkeypatch.setattr(W, "MAX_PARSED_CHARS", 5000)
    big = '<launch>\n' + '  <arg name="y" default="true"/>\n' * 100 + '</launch>\n'  # ~3,300 characters
    for i in range(5):
        analyse_launch2(big, str(tmp_path / f"b{i}.launch.xml"))
    assert W._PARSED_CHARS[0] <= 5000 and len(W._PARSED) >= 1
    assert W._PARSED_CHARS[0] == sum(k[1] for k in W._PARSED)
