"""Secure XML parsing with exact ranges, and bad input (never a crash or a hang)."""

from __future__ import annotations

import time

from tvl_lsp.launch import analyse_launch, check_launch, parse_xml
from tvl_lsp.base.text import Pos, Span


def S(l1, c1, l2, c2):
    return Span(Pos(l1, c1), Pos(l2, c2))


TEXT = (
    '<launch>\n'
    '  <arg name="A"/>\n'
    '  <node pkg="p" type="t"\n'
    '        name="n_$(arg A)" if="$(arg A)"/>\n'
    '  <param name="é" value="x &amp; $(env HOME) &lt;$(optenv NOPE d)"/>\n'
    '</launch>\n'
)


def test_element_and_attribute_spans_are_exact():
    a = analyse_launch(TEXT, "/w/x.launch", features=["A"])
    els = {e.tag: e for e in a.elements}
    node = els["node"]
    assert node.span == S(2, 2, 3, 41)                    # '<node' .. '/>'
    assert node.tag_span == S(2, 3, 2, 7)
    assert node.attrs["name"].name_span == S(3, 8, 3, 12)
    assert node.attrs["name"].value_span == S(3, 14, 3, 24)
    assert node.attrs["name"].value == "n_$(arg A)"
    sub = [s for s in node.substitutions if s.attr == "name"][0]
    assert (sub.kind, sub.args, sub.span) == ("arg", ("A",), S(3, 16, 3, 24))
    # decoded entity references and non-ASCII names keep exact code-point columns
    param = els["param"]
    assert param.attrs["name"].value_span == S(4, 15, 4, 16)
    subs = {s.kind: s.span for s in param.substitutions}
    line = TEXT.splitlines()[4]
    assert subs["env"] == S(4, line.index("$(env"), 4, line.index("$(env") + len("$(env HOME)"))
    assert subs["optenv"] == S(4, line.index("$(optenv"), 4, line.index("$(optenv") + len("$(optenv NOPE d)"))
    fa = a.feature_args[0]
    assert (fa.name, fa.name_span) == ("A", S(1, 13, 1, 14))


def test_malformed_xml_reports_lxml_position_and_recovers():
    text = '<launch>\n  <node pkg="p" type="t" name="a"/>\n  <node pkg="p" type="t" name="b"\n</launch>\n'
    a = analyse_launch(text, "/w/bad.launch")
    errs = [d for d in a.diagnostics if d.code == "xml-syntax"]
    assert len(errs) == 1
    assert errs[0].span.start.line == 3 and errs[0].span.start.col == 0
    # what is well formed is still analysed
    assert "/a" in [n.name for n in a.nodes]


def test_no_launch_root():
    a = analyse_launch("<robot><node/></robot>", "/w/x.xml")
    assert [d.code for d in check_launch(a)] == ["no-launch-root"]


def test_external_entity_is_refused_and_nothing_is_read(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    text = (f'<!DOCTYPE launch [<!ENTITY e SYSTEM "file://{secret}">]>\n'
            '<launch><param name="p" value="&e;"/></launch>')
    reads = []
    a = analyse_launch(text, str(tmp_path / "x.launch"), read_file=lambda p: reads.append(p))
    d = check_launch(a)
    assert [x.code for x in d] == ["xml-entity-declaration"]
    assert d[0].span.start == Pos(0, 18)
    assert reads == []
    assert "TOP-SECRET" not in repr(a)
    doc = parse_xml(text, "x")
    assert doc.refused and doc.root is None


def test_entity_bomb_is_refused_quickly():
    decl = '<!ENTITY a0 "lol">' + "".join(f'<!ENTITY a{i} "{("&a%d;" % (i - 1)) * 10}">' for i in range(1, 10))
    text = f'<?xml version="1.0"?>\n<!DOCTYPE launch [{decl}]>\n<launch><param name="x" value="&a9;"/></launch>'
    t = time.time()
    a = analyse_launch(text, "/w/bomb.launch")
    assert time.time() - t < 2
    assert [d.code for d in check_launch(a)] == ["xml-entity-declaration"]


def test_undeclared_entity_reference_is_a_syntax_error():
    a = analyse_launch('<launch><param name="x" value="&e;"/></launch>', "/w/x.launch")
    assert [d.code for d in a.diagnostics] == ["xml-syntax"]


def test_deep_nesting_gives_a_diagnostic_not_a_crash():
    n = 10_000
    text = "<launch>" + "<group>" * n + '<node pkg="p" type="t" name="deep"/>' + "</group>" * n + "</launch>"
    t = time.time()
    a = analyse_launch(text, "/w/deep.launch")
    assert time.time() - t < 10
    codes = {d.code for d in check_launch(a)}
    assert codes & {"xml-syntax", "launch-too-deep"}


def test_huge_file_is_analysed_in_bounded_time():
    n = 5_000
    body = "\n".join(f'  <node pkg="p" type="t" name="n{i}" if="$(arg A)"/>' for i in range(n))
    text = f'<launch>\n  <arg name="A"/>\n{body}\n  <node pkg="p" type="t" name="n7"/>\n</launch>\n'
    t = time.time()
    a = analyse_launch(text, "/w/huge.launch")
    assert time.time() - t < 20
    assert len(a.nodes) == n + 1
    dup = [f for f in a.facts if f.code == "duplicate-node"]
    assert len(dup) == 1 and str(dup[0].condition) == "A"


def test_too_large_file_is_refused():
    text = "<launch>" + " " * 20_000_001 + "</launch>"
    a = analyse_launch(text, "/w/big.launch")
    assert [d.code for d in a.diagnostics] == ["launch-file-too-large"]


def test_binary_garbage_does_not_crash():
    for text in ["\x00\x01<launch", "<launch><node name='$(' pkg='x' type='y'/></launch>", "", "<", "<launch>&#0;</launch>",
                 "<launch><node pkg='a' type='b' name='c' if='$(eval __import__(\"os\"))'/></launch>"]:
        a = analyse_launch(text, "/w/g.launch")
        check_launch(a)


def test_deep_groups_inside_nested_includes_do_not_overflow(tmp_path):
    ws = tmp_path / "ws" / "src" / "deep"
    (ws / "launch").mkdir(parents=True)
    (ws / "package.xml").write_text("<package><name>deep</name></package>")
    for i in range(15):
        nxt = f'<include file="$(find deep)/launch/f{i + 1}.launch"/>' if i < 14 else ""
        body = "<group>" * 95 + f'<node pkg="p" type="t" name="n{i}"/>{nxt}' + "</group>" * 95
        (ws / "launch" / f"f{i}.launch").write_text(f"<launch>{body}</launch>")
    p = ws / "launch" / "f0.launch"
    from tvl_lsp.launch import find_packages
    a = analyse_launch(p.read_text(), str(p), packages=find_packages(str(tmp_path / "ws")))
    assert a.nodes and a.nodes[0].name == "/n0"
    assert {f.code for f in a.facts} & {"launch-analysis-budget", "include-too-deep"}
