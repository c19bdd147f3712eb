"""Configuration launch files (Listing 6.1): the pure functions and ``tvl-lsp generate``."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from testenv import make_ws
from tvl_lsp.main import main as cli_main
from tvl_lsp.project.generate import (GenerateError, configuration_name, find_package, inside,
                              normalise_product, plan_configurations, render_configuration,
                              resolve_folder)

FEATURES = ["Turtlerand", "Turtlesim", "Random", "Teleop"]


@pytest.fixture
def ws(tmp_path) -> Path:
    return make_ws(tmp_path / "ws")


def test_render_writes_the_args_then_includes_the_generic_file():
    """The shape of the thesis's Listing 6.1: every feature arg set, in the order given, then
    the generic launch file included with each arg passed on."""
    got = render_configuration({"Turtlerand": True, "Turtlesim": True, "Random": True},
                               ["Turtlerand", "Turtlesim", "Teleop", "Random"], "$(find turtlerand)/launch/generic.launch")
    assert got == """<launch>
  <arg name="Turtlerand" value="true"/>
  <arg name="Turtlesim" value="true"/>
  <arg name="Teleop" value="false"/>
  <arg name="Random" value="true"/>
  <include file="$(find turtlerand)/launch/generic.launch">
    <arg name="Turtlerand" value="$(arg Turtlerand)"/>
    <arg name="Turtlesim" value="$(arg Turtlesim)"/>
    <arg name="Teleop" value="$(arg Teleop)"/>
    <arg name="Random" value="$(arg Random)"/>
  </include>
</launch>
"""


@pytest.mark.corpus
def test_render_matches_the_thesis_listing_6_1(corpus_dir):
    want = (corpus_dir / "thesis/ws/src/turtlerand/configs/teleop.launch").read_text()
    got = render_configuration({"Turtlerand": True, "Turtlesim": True, "Random": False, "Teleop": True},
                               FEATURES, "$(find turtlerand)/launch/generic.launch")
    assert got == want


def test_products_in_any_shape_normalise_to_feature_args():
    assert normalise_product({"Turtlerand.Turtlesim": True, "Random": False}, ["Turtlesim", "Random"]) == \
        {"Turtlesim": True, "Random": False}
    assert normalise_product({"Teleop"}, ["Teleop", "Random"]) == {"Teleop": True, "Random": False}


def test_names_are_deterministic_and_bounded():
    p = {"Turtlerand": True, "Turtlesim": True, "Teleop": True}
    assert configuration_name(p, FEATURES, "generic", omit=["Turtlerand"]) == "generic_turtlesim-teleop.launch"
    assert configuration_name({}, FEATURES, "generic") == "generic_none.launch"
    many = [f"Feature_{i}" for i in range(40)]
    a = configuration_name({f: True for f in many}, many, "g")
    b = configuration_name({f: True for f in many[:-1]}, many, "g")
    assert len(a) < 100 and a != b


def test_attribute_values_are_escaped():
    text = render_configuration({'A"b': True}, ['A"b'], "$(find p)/x&y.launch")
    assert "&quot;" in text and "&amp;" in text


def test_inside_resolves_dot_dot_and_symlinks(tmp_path):
    ws = tmp_path / "ws"
    (ws / "a").mkdir(parents=True)
    outside = tmp_path / "out"
    outside.mkdir()
    os.symlink(outside, ws / "link")
    assert inside(str(ws / "a" / "x.launch"), [str(ws)])
    assert not inside(str(ws / ".." / "out" / "x.launch"), [str(ws)])
    assert not inside(str(ws / "link" / "x.launch"), [str(ws)])


def test_folders_outside_the_workspace_are_refused(ws):
    generic = ws / "src/turtlerand/launch/generic.launch"
    assert resolve_folder(None, str(generic), [str(ws)]) == str(ws / "src/turtlerand/configs")
    assert resolve_folder("gen/x", str(generic), [str(ws)]) == str(ws / "src/turtlerand/gen/x")
    with pytest.raises(GenerateError):
        resolve_folder("../../../elsewhere", str(generic), [str(ws)])
    with pytest.raises(GenerateError):
        resolve_folder("/etc", str(generic), [str(ws)])
    with pytest.raises(GenerateError):
        plan_configurations([{"Turtlerand": True}], FEATURES, str(generic), "/tmp", [str(ws)])


def test_package_discovery_reads_package_xml(ws):
    name, folder = find_package(str(ws / "src/scout/launch/generic.launch"))
    assert name == "scout" and folder == str(ws / "src/scout")
    # from a file deeper in the package
    name, folder = find_package(str(ws / "src/crawler_bringup/launch/includes/tracks.launch.xml"))
    assert name == "crawler_bringup" and folder == str(ws / "src/crawler_bringup")


def test_cli_generates_the_four_turtlerand_configurations(ws, capsys):
    generic = ws / "src/turtlerand/launch/generic.launch"
    assert cli_main(["generate", str(generic), "--mode", "all", "--out", "gen"]) == 0
    files = sorted((ws / "src/turtlerand/gen").glob("*.launch"))
    assert [f.name for f in files] == ["generic_turtlesim-random-vel.launch",
                                       "generic_turtlesim-teleop-random-vel-multiplexer.launch",
                                       "generic_turtlesim-teleop.launch", "generic_turtlesim.launch"]
    assert all("$(find turtlerand)/launch/generic.launch" in f.read_text() for f in files)
    # a partial configuration: only its completions
    assert cli_main(["generate", str(generic), "-i", "Teleop", "--out", "gen2"]) == 0
    assert len(list((ws / "src/turtlerand/gen2").glob("*.launch"))) == 2
    assert cli_main(["generate", str(generic), "--mode", "one", "-x", "Random", "--out", "gen3"]) == 0
    assert [f.name for f in (ws / "src/turtlerand/gen3").glob("*.launch")] == ["generic_turtlesim.launch"]
    assert cli_main(["generate", str(generic), "--out", "/tmp"]) == 2


def test_feature_names_differing_only_in_case_are_refused_not_overwritten(tmp_path, capsys):
    """Issue 12: `Ab` and `AB` gave one file name (3 products, 2 files, exit 0)."""
    import shutil
    ws = tmp_path / "cc"
    shutil.copytree(Path(__file__).parent / "data/robustness/case_collision", ws)
    generic = ws / "src/cc/launch/cc.launch"
    assert cli_main(["generate", str(generic), "--mode", "all", "--workspace", str(ws)]) == 2
    err = capsys.readouterr().err
    assert "`Ab` and `AB`" in err and "nothing was written" in err
    assert not (ws / "src/cc/configs").exists()
    with pytest.raises(GenerateError, match="differ only in case"):
        plan_configurations([{"Ab": True}, {"AB": True}], ["Ab", "AB"], str(generic), str(ws / "out"), [str(ws)])
