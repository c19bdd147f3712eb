"""Workspace discovery, packages and the three pairing rules (HAROS project, marker, same stem)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from testenv import make_ws
from tvl_lsp.base.text import Pos, Span
from tvl_lsp.project.workspace import (RULE_MARKER, RULE_NONE, RULE_PROJECT, RULE_STEM, discover_files, find_marker,
                               find_workspace_root, launch_stem, load_workspace, parse_project)

HERE = Path(__file__).resolve().parent
PAIRS = HERE / "data" / "pairs"


@pytest.fixture(scope="module")
def wsdir(tmp_path_factory) -> Path:
    """The test workspace: examples/ws + tests/data/ws (tests/testenv.py)."""
    return make_ws(tmp_path_factory.mktemp("pairing") / "ws")


def test_pairings_follow_the_project_files_then_the_stem(wsdir):
    ws = load_workspace([str(wsdir)])
    assert sorted(ws.packages) == ["crawler", "crawler_bringup", "scout", "turtlerand"]
    assert ws.diagnostics == []
    src = wsdir / "src"

    def pair(rel):
        ps, ds = ws.pair(str(src / rel))
        assert ds == []
        return [(os.path.relpath(p.model, src) if p.model else None, p.rule) for p in ps]

    assert pair("turtlerand/launch/generic.launch") == [("turtlerand/launch/generic.tvl", RULE_PROJECT)]
    assert pair("crawler_bringup/launch/generic.launch") == [("crawler/models/crawler.tvl", RULE_PROJECT)]
    assert pair("scout/launch/generic.launch") == [("scout/launch/generic.tvl", RULE_PROJECT)]
    assert pair("turtlerand/launch/generic_alt.launch") == [("turtlerand/launch/generic_alt.tvl", RULE_STEM)]
    # the legacy (plain HAROS) project names first.launch but pairs no model
    assert pair("turtlerand/launch/first.launch") == [(None, RULE_NONE)]
    assert pair("turtlerand/launch/generic_nested.launch") == [(None, RULE_NONE)]
    # a configuration launch file sets the args of the generic one it includes: no model of its own
    assert pair("turtlerand/configs/teleop.launch") == [(None, RULE_NONE)]


def test_project_pairing_records_where_it_is_written(wsdir):
    ws = load_workspace([str(wsdir)])
    (p,), _ = ws.pair(str(wsdir / "src/crawler_bringup/launch/generic.launch"))
    assert p.source_path == str(wsdir / "haros_crawler.yaml")
    # {lf: crawler_bringup/launch/generic.launch, ...}: the lf value on line 4 (0-based 3)
    line = (wsdir / "haros_crawler.yaml").read_text().splitlines()[3]
    col = line.index("crawler_bringup/")
    assert p.source_span == Span(Pos(3, col), Pos(3, col + len("crawler_bringup/launch/generic.launch")))
    assert f"haros_crawler.yaml:4:{col + 1}" in p.describe(str(wsdir))
    # the scout's project writes lf / tvl directly under configurations, on their own lines
    (q,), _ = ws.pair(str(wsdir / "src/scout/launch/generic.launch"))
    assert q.source_span.start == Pos(4, 8)


def test_discovery_and_workspace_root(wsdir):
    files = discover_files([str(wsdir)])
    names = {os.path.basename(p) for p in files.launches}
    assert {"generic_nested.launch", "teleop.launch", "first.launch", "tracks.launch.xml"} <= names
    assert len(files.models) == 5 and len(files.manifests) == 4
    assert {os.path.basename(y) for y in files.yamls} >= {"haros_scout.yaml", "haros_crawler.yaml", "haros.yaml"}
    # from a file deep in the tree, the root is the folder holding the project files
    assert find_workspace_root(str(wsdir / "src/scout/launch/generic.launch")) == str(wsdir)


def test_discovery_skips_build_folders(tmp_path):
    for d in ("src/p/launch", "build/x", "devel/y", "install/z", "node_modules/w", ".git/v", ".venv/u"):
        (tmp_path / d).mkdir(parents=True)
    (tmp_path / "src/p/launch/a.launch").write_text("<launch/>")
    (tmp_path / "src/p/launch/b.launch.xml").write_text("<launch/>")
    for d in ("build/x", "devel/y", "install/z", "node_modules/w", ".git/v", ".venv/u"):
        (tmp_path / d / "c.launch").write_text("<launch/>")
        (tmp_path / d / "m.tvl").write_text("root R {}")
    f = discover_files([str(tmp_path)])
    assert [os.path.basename(p) for p in f.launches] == ["a.launch", "b.launch.xml"]
    assert f.models == []
    assert launch_stem("x/robot.launch.xml") == "robot" and launch_stem("robot.launch") == "robot"


def test_marker_pairing_and_its_errors():
    ws = load_workspace([str(PAIRS)])
    (p,), ds = ws.pair(str(PAIRS / "marker/bringup.launch"))
    assert (p.model, p.rule) == (str(PAIRS / "clean/clean.tvl"), RULE_MARKER)
    line = (PAIRS / "marker/bringup.launch").read_text().splitlines()[1]
    col = line.index("../clean")
    assert p.source_span == Span(Pos(1, col), Pos(1, col + len("../clean/clean.tvl")))
    (q,), ds = ws.pair(str(PAIRS / "marker/broken_marker.launch"))
    assert q.rule == RULE_NONE and q.model is None
    assert [d.code for d in ds] == ["marker-model-not-found"]
    line = (PAIRS / "marker/broken_marker.launch").read_text().splitlines()[1]
    col = line.index("../nowhere")
    assert ds[0].span == Span(Pos(1, col), Pos(1, col + len("../nowhere/missing.tvl")))


def test_marker_syntax_variants_and_opt_out(tmp_path):
    assert find_marker('<!-- tvl-lsp: model="a b.tvl" -->')[0] == "a b.tvl"
    assert find_marker("<!--tvl-lsp:model=m.tvl-->")[0] == "m.tvl"
    assert find_marker("<!-- nothing here -->") is None
    (tmp_path / "r.tvl").write_text("root R {}")
    (tmp_path / "r.launch").write_text("<launch><!-- tvl-lsp: model=none --></launch>")
    (tmp_path / "s.launch").write_text("<launch/>")
    (tmp_path / "s.tvl").write_text("root S {}")
    ws = load_workspace([str(tmp_path)])
    (p,), _ = ws.pair(str(tmp_path / "r.launch"))
    assert p.model is None and p.rule == RULE_MARKER     # explicitly alone, despite r.tvl
    (q,), _ = ws.pair(str(tmp_path / "s.launch"))
    assert q.rule == RULE_STEM and q.model == str(tmp_path / "s.tvl")
    # the text passed in (an unsaved buffer) wins over the file on disk
    (r,), _ = ws.pair(str(tmp_path / "s.launch"), "<launch><!-- tvl-lsp: model=r.tvl --></launch>")
    assert r.rule == RULE_MARKER and r.model == str(tmp_path / "r.tvl")


def test_project_in_a_workspace_with_two_packages_of_one_name():
    # pairs/ws and pairs/badws both hold a package `bot`: each project file means its own
    ws = load_workspace([str(PAIRS)])
    (p,), _ = ws.pair(str(PAIRS / "ws/src/bot/launch/generic.launch"))
    assert p.rule == RULE_PROJECT and p.model == str(PAIRS / "ws/src/bot/models/rover.tvl")
    (q,), _ = ws.pair(str(PAIRS / "badws/src/bot/launch/generic.launch"))
    assert q.rule == RULE_NONE


def test_broken_project_files_get_exact_diagnostics():
    ws = load_workspace([str(PAIRS / "badws")])
    by_file = {os.path.basename(d.path): d for d in ws.diagnostics}
    assert set(by_file) == {"haros_broken.yaml", "haros_missing.yaml", "haros_typo.yaml"}
    d = by_file["haros_missing.yaml"]
    assert d.code == "project-file-not-found"
    line = (PAIRS / "badws/haros_missing.yaml").read_text().splitlines()[d.span.start.line]
    assert line[d.span.start.col:d.span.end.col] == "bot/launch/nothere.tvl"
    d = by_file["haros_broken.yaml"]
    assert d.code == "invalid-project" and "not valid YAML" in d.message
    d = by_file["haros_typo.yaml"]
    assert d.code == "invalid-project" and "`tv1`" in d.message


@pytest.mark.parametrize("text", [
    "configurations: [",
    "configurations:\n  - 3\n",
    "configurations:\n  x: [1, 2]\n",
    "configurations:\n  {lf: [a, {b: c}], tvl: [x, y]}\n",
    "configurations: &a\n  x: *a\n",
    "configurations:\n" + "  - " * 200 + "x\n",
    "configurations: !!python/object:os.system ls\n",
])
def test_malformed_projects_never_crash(text):
    pf = parse_project("/tmp/p.yaml", text, {})
    assert pf is not None
    assert all(d.code in ("invalid-project", "project-file-not-found") for d in pf.diagnostics)
    assert pf.diagnostics, text


def test_yaml_without_configurations_is_not_a_project():
    assert parse_project("/tmp/p.yaml", "foo: 1\n", {}) is None
    assert parse_project("/tmp/p.yaml", "- a\n- b\n", {}) is None
    assert parse_project("/tmp/p.yaml", "a: [\n", {}) is None  # broken, but not a project file


def test_two_project_files_pair_one_launch_file_with_two_models(tmp_path):
    from tvl_lsp.project.check import check_paths
    pkg = tmp_path / "src" / "bot"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>bot</name></package>")
    (pkg / "launch" / "g.launch").write_text('<launch>\n  <arg name="R"/>\n  <arg name="A"/>\n</launch>\n')
    (pkg / "a.tvl").write_text("root R { group allOf { opt A } }\n")
    (pkg / "b.tvl").write_text("root R { group allOf { opt A, opt B } }\n")
    (tmp_path / "p1.yaml").write_text("configurations:\n  {lf: bot/launch/g.launch, tvl: bot/a.tvl}\n")
    (tmp_path / "p2.yaml").write_text("configurations:\n  - {lf: bot/launch/g.launch, tvl: bot/b.tvl}\n")
    ws = load_workspace([str(tmp_path)])
    ps, _ = ws.pair(str(pkg / "launch" / "g.launch"))
    assert [(os.path.basename(p.model), os.path.basename(p.source_path)) for p in ps] == \
        [("a.tvl", "p1.yaml"), ("b.tvl", "p2.yaml")]
    diags = check_paths([str(tmp_path)], jobs=1)
    (miss,) = [d for d in diags if d.code == "missing-arg"]
    assert "`B` of b.tvl" in miss.message
    # the diagnostic says which pairing it comes from
    assert any(r.path.endswith("p2.yaml") for r in miss.related)
    assert not any(r.path.endswith("p1.yaml") for r in miss.related)
