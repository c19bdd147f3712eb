"""roslaunch load-time rules, arg scoping, namespaces, includes and presence conditions."""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_lsp.base.formula import FALSE, TRUE, Var, conj, evaluate, neg
from tvl_lsp.base import formula as fm
from tvl_lsp.base.diagnostics import CODES
from tvl_lsp.launch import analyse_launch, check_launch, load_launch

WS = Path(__file__).resolve().parent / "data" / "launch" / "ws"
A, B, C = Var("A"), Var("B"), Var("C")


def L(body: str, features=("A", "B", "C"), **kw):
    decl = "".join(f'<arg name="{f}"/>' for f in features)
    return analyse_launch(f"<launch>{decl}\n{body}\n</launch>", kw.pop("path", "/w/t.launch"),
                          features=list(features), packages=kw.pop("packages", {}), **kw)


def facts(a, code):
    return [f for f in a.facts if f.code == code]


def sat(f):
    import itertools
    vs = ["A", "B", "C"]
    return [dict(zip(vs, b)) for b in itertools.product([False, True], repeat=3) if evaluate(f, dict(zip(vs, b)))]


def equiv(f, g):
    return sat(f) == sat(g)


def error_codes(a):
    return sorted({d.code for d in check_launch(a) if d.severity == 1})


# ---------------------------------------------------------------- conditions

def test_presence_conditions_are_conjunctions_along_the_path():
    a = L('<group if="$(arg A)"><group unless="$(arg B)"><node pkg="p" type="t" name="n"/></group></group>'
          '<node pkg="p" type="t" name="m" if="true"/><node pkg="p" type="t" name="z" if="0"/>')
    node = {n.name: n for n in a.nodes}
    assert node["/n"].condition == conj([A, neg(B)])
    assert node["/m"].condition == TRUE
    assert "/z" not in node
    z = [e for e in a.elements if e.tag == "node" and e.attrs["name"].value == "z"][0]
    assert z.condition == FALSE


def test_eval_conditions_translate_to_formulas():
    a = L('<node pkg="p" type="t" name="n1" if="$(eval arg(\'A\') and not B)"/>'
          '<node pkg="p" type="t" name="n2" if="$(eval A == True or C != False)"/>'
          '<node pkg="p" type="t" name="n3" unless="$(eval arg(\'B\') == \'true\')"/>')
    node = {n.name: n.condition for n in a.nodes}
    assert equiv(node["/n1"], conj([A, neg(B)]))
    assert equiv(node["/n2"], A | C)
    assert node["/n3"] == TRUE  # arg('B') is the boolean True, never the string 'true'


def test_unanalysable_eval_is_an_information_not_a_guess():
    a = L('<node pkg="p" type="t" name="n" if="$(eval some.attribute)"/>'
          '<node pkg="p" type="t" name="n" unless="$(eval some.attribute)"/>')
    infos = facts(a, "condition-not-analysable")
    assert len(infos) == 2 and {f.severity for f in infos} == {3}   # one note on each value
    # the node's condition is an unknown (neither always nor never loaded), the same one for
    # both tags: if= and unless= of it exclude each other (no duplicate-node), no error
    (u,) = {str(n.condition).lstrip("!") for n in a.nodes}
    assert fm.is_unknown(u) and a.nodes[1].condition == neg(a.nodes[0].condition)
    assert [f for f in a.facts if f.severity == 1] == []


def test_invalid_condition_and_if_with_unless():
    a = L('<arg name="v" value="yes" if="$(arg A)"/><arg name="v" value="TRUE" unless="$(arg A)"/>'
          '<node pkg="p" type="t" name="n" if="$(arg v)"/>'
          '<node pkg="p" type="t" name="m" if="true" unless="false"/>')
    inv = facts(a, "invalid-condition")
    assert len(inv) == 1 and inv[0].condition == A and "yes is not a 'bool' type" in inv[0].message
    assert [n.condition for n in a.nodes if n.name == "/n"] == [neg(A)]
    assert facts(a, "if-and-unless")[0].condition == TRUE


def test_if_unless_on_launch():
    a = analyse_launch('<launch if="false"><node pkg="p" type="t" name="n"/></launch>', "/w/l.launch")
    f = facts(a, "launch-if-unless")
    assert f and f[0].severity == 2
    assert [n.name for n in a.nodes] == ["/n"]  # roslaunch ignores it
    a = analyse_launch('<launch if="$(arg x)"><arg name="x" default="true"/></launch>', "/w/l.launch")
    assert facts(a, "launch-if-unless")[0].severity == 1  # roslaunch crashes


# ---------------------------------------------------------------- args

def test_paired_if_unless_declaration_is_legal_but_plain_redeclaration_is_not():
    a = L('<arg name="r" value="1" if="$(arg A)"/><arg name="r" value="2" unless="$(arg A)"/>'
          '<node pkg="p" type="t" name="n" args="$(arg r)"/>')
    assert not facts(a, "duplicate-arg") and not facts(a, "undefined-arg")
    assert [str(n.condition) for n in a.nodes] == ["true"]
    r = load_launch("/w/t.launch", {"A": "false"}, text='<launch><arg name="A"/>\n'
                    '<arg name="r" value="1" if="$(arg A)"/><arg name="r" value="2" unless="$(arg A)"/>'
                    '<node pkg="p" type="t" name="n" args="$(arg r)"/></launch>', packages={})
    assert r.error is None and r.nodes[0]["args"] == "2"
    a = L('<arg name="r" default="1"/><arg name="r" default="2" if="$(arg B)"/>')
    d = facts(a, "duplicate-arg")
    assert d[0].condition == B and "arg 'r' has already been declared" in d[0].message


def test_value_and_default_together():
    a = L('<arg name="r" value="1" default="2"/>')
    assert facts(a, "arg-value-and-default")[0].message == "<arg> tag must have one and only one of value/default."


def test_group_scope_drops_group_local_args():
    a = L('<group><arg name="g" default="1"/><node pkg="p" type="t" name="in" args="$(arg g)"/></group>'
          '<node pkg="p" type="t" name="out" args="$(arg g)"/>')
    und = facts(a, "undefined-arg")
    assert len(und) == 1 and und[0].span.start.col > 0 and und[0].condition == TRUE
    assert "requires the 'g' arg to be set" in und[0].message


def test_a_failing_arg_value_is_reported_once_not_at_every_use():
    a = L('<arg name="sim" default="$(env TVL_LSP_SURELY_UNSET)"/><param name="p" value="$(arg sim)"/>'
          '<node pkg="p" type="t" name="n" if="$(arg sim)"/>')
    assert [f.code for f in a.facts if f.severity == 1] == ["env-not-set"]


def test_unset_required_arg_is_reported_where_used():
    a = L('<group if="$(arg A)"><arg name="map"/><node pkg="p" type="t" name="m" args="$(arg map)"/></group>')
    u = facts(a, "unset-arg")
    assert len(u) == 1 and u[0].condition == A
    assert not facts(a, "undefined-arg")


def test_top_level_arg_used_as_string_is_not_a_feature():
    a = analyse_launch('<launch><arg name="foo"/><param name="p" value="$(arg foo)"/></launch>', "/w/x.launch")
    assert a.free_args == [] and [x.name for x in a.feature_args] == ["foo"]
    # the command line can give it: a warning (roslaunch run without it fails)
    assert error_codes(a) == [] and [d.code for d in check_launch(a) if d.severity == 2] == ["unset-arg"]
    a = analyse_launch('<launch><arg name="F"/><node pkg="p" type="t" name="n" if="$(arg F)"/></launch>', "/w/x.launch")
    assert a.free_args == ["F"] and error_codes(a) == [] and a.required_args == ["F"]


def test_feature_args_are_only_direct_children_of_launch():
    a = L('<group><arg name="NotAFeature" default="0.5"/></group>', features=("A",))
    assert [x.name for x in a.feature_args] == ["A"]
    assert a.feature_args[0].default is None


# ---------------------------------------------------------------- nodes and namespaces

def test_resolved_names_with_group_node_and_absolute_namespaces():
    a = L('<group ns="g"><node pkg="p" type="t" name="a"/><node pkg="p" type="t" name="b" ns="sub"/>'
          '<node pkg="p" type="t" name="c" ns="/abs"/><group ns="/top"><node pkg="p" type="t" name="d"/></group>'
          '</group><node pkg="p" type="t" name="$(anon x)"/><node pkg="p" type="t" name="$(anon y)"/>')
    names = sorted(n.name for n in a.nodes)
    assert names[:4] == ["/abs/c", "/g/a", "/g/sub/b", "/top/d"]
    assert names[4].startswith("/x_") and names[5].startswith("/y_")
    assert not facts(a, "duplicate-node")


def test_node_name_depending_on_an_arg_splits_into_cases():
    a = L('<arg name="side" value="left" if="$(arg A)"/><arg name="side" value="right" unless="$(arg A)"/>'
          '<group ns="$(arg side)"><node pkg="p" type="t" name="drv_$(arg side)"/></group>')
    assert sorted((n.name, str(n.condition)) for n in a.nodes) == [("/left/drv_left", "A"), ("/right/drv_right", "!A")]


def test_duplicate_nodes_condition_is_the_conjunction():
    a = L('<node pkg="p" type="t" name="w" if="$(arg A)"/><group if="$(arg B)"><node pkg="p" type="t" name="w"/></group>'
          '<node pkg="p" type="t" name="v" if="$(arg C)"/><node pkg="p" type="t" name="v" unless="$(arg C)"/>')
    d = facts(a, "duplicate-node")
    assert len(d) == 1 and d[0].condition == conj([A, B])
    assert "multiple nodes named [/w]" in d[0].message and d[0].related


@pytest.mark.parametrize("body,code,cond", [
    ('<node pkg="p" type="t" name="ns/foo"/>', "node-name-namespace", TRUE),
    ('<node pkg="p" type="t" name="n" ns=""/>', "empty-ns", TRUE),
    ('<group ns="" if="$(arg B)"/>', "empty-ns", B),
    ('<node pkg="p" type="t" name="n" respawn="true" required="$(arg A)"/>', "respawn-and-required", A),
    ('<node pkg="p" type="t" name="n" respawn="maybe"/>', "invalid-attribute-value", TRUE),
    ('<node pkg="p" type="t"/>', "missing-attribute", TRUE),
    ('<node pkg="" type="t" name="n"/>', "invalid-attribute-value", TRUE),
    ('<node pkg="p" type="t" name="n" output="foo"/>', "invalid-attribute-value", TRUE),
    ('<param name="x"/>', "param-value-count", TRUE),
    ('<param name="x" value="1" command="ls" if="$(arg C)"/>', "param-value-count", C),
    ('<param name="x" type="int" value="abc"/>', "invalid-param", TRUE),
    ('<param name="x" command="surely_not_a_command_tvl"/>', "command-not-found", TRUE),
    ('<rosparam command="bad"/>', "invalid-param", TRUE),
    ('<rosparam>1</rosparam>', "invalid-param", TRUE),
    ('<remap from="a"/>', "invalid-remap", TRUE),
    ('<remap from="a b" to="c"/>', "invalid-remap", TRUE),
    ('<env name="" value="x"/>', "invalid-env", TRUE),
    ('<machine name="m"/>', "missing-attribute", TRUE),
    ('<machine name="m" address="a" timeout="-1"/>', "invalid-machine", TRUE),
    ('<machine name="m" address="a" ros-root="/x"/>', "invalid-machine", TRUE),
    ('<test test-name="t" pkg="p" type="t" respawn="true"/>', "invalid-test", TRUE),
    ('<param name="x" value="$(foo bar)"/>', "unknown-substitution", TRUE),
    ('<param name="x" value="$(arg)"/>', "substitution-arity", TRUE),
    ('<param name="x" value="$(arg $(arg A))"/>', "substitution-syntax", TRUE),
    ('<param name="x" value="a $(eval 1+1)"/>', "unknown-substitution", TRUE),
    ('<param name="x" value="$(env TVL_LSP_SURELY_UNSET)"/>', "env-not-set", TRUE),
    ('<param name="x" value="$(eval 1/0)"/>', "eval-error", TRUE),
])
def test_load_time_rules(body, code, cond):
    a = L(body)
    got = facts(a, code)
    assert got, [(f.code, f.message) for f in a.facts]
    assert got[0].condition == cond
    assert code in CODES


def test_unknown_tags_and_attributes_warn():
    a = L('<nod pkg="p"/><node pkg="p" type="t" name="n" colour="red"><foo/></node>')
    codes = [(d.code, d.severity) for d in a.diagnostics]
    assert ("unknown-tag", 2) in codes and ("unknown-attribute", 2) in codes
    assert len([c for c in codes if c[0] == "unknown-tag"]) == 2


# ---------------------------------------------------------------- includes

def _ws():
    from tvl_lsp.launch import find_packages
    return find_packages(str(WS))


def test_find_resolves_package_name_not_folder_name():
    pk = _ws()
    assert pk["alpha_pkg"].endswith("/src/alpha") and "alpha" not in pk


def test_include_with_args_scoping_and_namespaces():
    pk = _ws()
    path = str(WS / "src" / "alpha" / "launch" / "generic_ns.launch")
    a = analyse_launch(Path(path).read_text(), path, packages=pk)
    assert a.free_args == ["A", "B", "C"]
    names = {(n.name, str(n.condition)) for n in a.nodes}
    assert ("/left/r1/driver", "true") in names
    assert ("/left/r1/boost", "C") in names
    assert any(n.name == "/r2/driver" and equiv(n.condition, conj([neg(conj([A, neg(B)])), C])) for n in a.nodes)
    assert ("/passed_b", "B") in names  # pass_all_args
    drv = [n for n in a.nodes if n.name == "/left/r1/driver"][0]
    assert drv.path.endswith("part.launch") and drv.element.include_depth == 1
    for val, rate in (("true", "10"), ("false", "5")):
        r = load_launch(path, {"A": val, "B": "true", "C": "true"}, packages=pk)
        assert r.error is None
        assert [n["args"] for n in r.nodes if n["name"] == "/left/r1/driver"] == [f"--rate {rate}"]
    assert not [f for f in a.facts if f.severity == 1]


def test_unused_include_arg_and_conflicts():
    pk = _ws()
    path = str(WS / "src" / "alpha" / "launch" / "conflicts.launch")
    a = analyse_launch(Path(path).read_text(), path, packages=pk)
    unused = facts(a, "unused-include-arg")
    assert len(unused) == 1 and equiv(unused[0].condition, conj([B, A])) and "unused args [colour]" in unused[0].message
    assert equiv(facts(a, "duplicate-node")[0].condition, conj([A, B]))
    assert equiv(facts(a, "unset-arg")[0].condition, conj([neg(A), B]))


def test_include_cycle_is_detected():
    pk = _ws()
    path = str(WS / "src" / "alpha" / "launch" / "cycle_b.launch")
    a = analyse_launch(Path(path).read_text(), path, packages=pk)
    cyc = facts(a, "include-cycle")
    assert cyc and cyc[0].condition == TRUE
    res = load_launch(path, {}, packages=pk)
    assert res.error_code == "include-cycle"


def test_include_outside_workspace_is_not_an_error():
    a = L('<include file="$(find somewhere_else)/launch/x.launch"><arg name="a" value="1"/></include>')
    assert error_codes(a) == []
    inc = [e for e in a.elements if e.tag == "include"][0]
    assert inc.unresolved and a.includes[0].package == "somewhere_else"


def test_missing_include_inside_workspace_is_an_error():
    a = L('<include file="$(find alpha_pkg)/launch/nope.launch" if="$(arg A)"/>', packages=_ws())
    f = facts(a, "include-not-found")
    assert f and f[0].condition == A


def test_unsaved_editor_text_wins_over_disk():
    pk = _ws()
    inc = str(WS / "src" / "beta" / "launch" / "all_args.launch")
    edited = '<launch><arg name="A"/><arg name="B" default="false"/><node pkg="b" type="t" name="edited"/></launch>'
    a = L('<include file="$(find beta)/launch/all_args.launch" pass_all_args="true"/>', features=("A",),
          packages=pk, read_file=lambda p: edited if p == inc else None)
    assert [n.name for n in a.nodes] == ["/edited"]


# ---------------------------------------------------------------- concrete loader

def test_load_launch_one_assignment():
    pk = _ws()
    path = str(WS / "src" / "alpha" / "launch" / "conflicts.launch")
    r = load_launch(path, {"A": "true", "B": "false"}, packages=pk)
    assert r.error is None and [n["name"] for n in r.nodes] == ["/worker"]
    r = load_launch(path, {"A": "true", "B": "true"}, packages=pk)
    assert r.error_code == "duplicate-node" and "multiple nodes named [/worker]" in r.error
    r = load_launch(path, {"A": "false"}, packages=pk)
    assert r.error_code in ("undefined-arg", "unset-arg") and "'B'" in r.error


# ---------------------------------------------------------------- unknowns (issue 27)

def test_forall_unknowns_keeps_only_what_holds_whatever_they_are():
    u, v = fm.unknown("1:x"), fm.unknown("2:y")
    a = Var("a")
    assert fm.forall_unknowns(conj([a, u])) == FALSE                 # only when the unknown is true
    assert fm.forall_unknowns(fm.disj([conj([a, u]), conj([a, neg(u)])])) == a   # either way: certain
    assert fm.forall_unknowns(conj([u, neg(u)])) == FALSE
    assert fm.forall_unknowns(a) == a
    many = fm.disj([fm.unknown(str(i)) for i in range(fm.MAX_UNKNOWNS + 1)] + [conj([a, v])])
    assert fm.forall_unknowns(many) == FALSE                         # too many: never certain


def test_variables_and_substitute_visit_a_shared_subformula_once():
    """Conditions built by the walkers share subterms: a tree walk of 24 levels of sharing visits
    2 ** 24 nodes (autoware's behavior_planning.launch.xml took 25 s before)."""
    import time
    f = Var("x0")
    for i in range(1, 25):
        f = fm.disj([conj([f, Var(f"x{i}")]), conj([f, neg(Var(f"x{i}"))])]) if i % 2 else \
            conj([fm.disj([f, Var(f"x{i}")]), fm.disj([f, Var("u")])])
    t = time.process_time()
    assert len(fm.variables(f)) == 26
    g = fm.substitute(f, {"u": TRUE})
    assert "u" not in fm.variables(g)
    assert time.process_time() - t < 2


def test_eval_methods_are_bounded_and_sets_of_strings_are_sorted():
    from tvl_lsp.launch import evalguard as guard
    from tvl_lsp.launch.ros1 import subst as S
    with pytest.raises(guard.TooBig):
        guard.call_method("ab", "replace", ["a", "x" * 10 ** 5])
    with pytest.raises(guard.NotAllowed):
        guard.call_method([1], "append", [2])
    with pytest.raises(AttributeError):
        guard.call_method({}, "nope", [])
    with pytest.raises(guard.Unordered):
        guard.ordered([{"a", "b"}])
    assert guard.ordered({1, 2}) == {1, 2}
    run = lambda e, **args: S.run_eval(S.parse_eval(e), args, {})  # noqa: E731
    assert run("{'iron': False}.get(arg('robot'), True)", robot="iron") == "False"
    assert run("'a_b'.split('_')") == "['a', 'b']"
    assert run("len(set(['a', 'b']))") == "2"
    # a set of strings has no fixed order in Python: one, sorted, every run (what roslaunch gives
    # in some runs; 'a' in ..., len(...) are what it gives in all)
    assert run("list(set(['b', 'a']))") == "['a', 'b']" == run("list({'b', 'a'})")
    assert run("str(set(['b', 'a'])) + ','.join(frozenset('ba'))") == "{'a', 'b'}a,b"
    with pytest.raises(S.SubstError):
        run("[1, 2].index(3)")             # ValueError, as roslaunch raises
