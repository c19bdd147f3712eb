"""The language server on ROS 2 launch files (XML and YAML), end to end (pytest-lsp): the
diagnostics of --check with exact ranges, navigation and rename across the model and the
launch files, hover, completion and the missing-arg quick fix."""

from __future__ import annotations

import asyncio
import shutil
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import (CONFIG, PROFILES, apply_text_edits, diagnostics, edits_by_uri, install_client_handlers,
                            open_doc, position_of, start)

pytestmark = pytest.mark.asyncio(loop_scope="module")

WS = Path(__file__).resolve().parent / "data" / "ros2" / "ws"


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("r2") / "ws"
    shutil.copytree(WS, ws)
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    d = ws / "src" / "r2_robot" / "launch"
    lsp_client.tvl = d / "generic.tvl"
    lsp_client.xml = d / "issues.launch.xml"
    lsp_client.yaml = d / "generic.launch.yaml"
    lsp_client.tvl_uri = open_doc(lsp_client, lsp_client.tvl)
    lsp_client.xml_uri = open_doc(lsp_client, lsp_client.xml)
    lsp_client.yaml_uri = open_doc(lsp_client, lsp_client.yaml)
    yield
    await lsp_client.shutdown_session()


def tdi(uri):
    return types.TextDocumentIdentifier(uri=uri)


def _text_at(text: str, rng: types.Range) -> str:
    lines = text.split("\n")
    if rng.start.line == rng.end.line:
        return lines[rng.start.line][rng.start.character:rng.end.character]
    return lines[rng.start.line][rng.start.character:]


async def test_diagnostics_of_a_ros2_generic_file(client: LanguageClient):
    diags = await diagnostics(client, client.xml_uri, lambda ds: any(str(d.code) == "undefined-arg" for d in ds)
                              and any(str(d.code) == "dead-element" for d in ds))
    text = client.xml.read_text()
    by = {}
    for d in diags:
        by.setdefault(str(d.code), []).append(_text_at(text, d.range))
    assert by["undefined-arg"] == ["$(var lidar_frame)"]
    assert by["duplicate-node"] == ["driver"]
    assert by["include-arg-leak"] == ["$(var rate)"]
    assert by["dead-element"][0].startswith("<node")


async def test_diagnostics_of_a_yaml_launch_file(client: LanguageClient):
    yaml_path = client.ws / "src" / "r2_bringup" / "launch" / "bad" / "bad.launch.yaml"
    uri = open_doc(client, yaml_path)
    diags = await diagnostics(client, uri, lambda ds: any(str(d.code) == "invalid-launch-file" for d in ds))
    d = next(d for d in diags if str(d.code) == "invalid-launch-file")
    assert _text_at(yaml_path.read_text(), d.range) == "5"


async def test_definition_from_var_goes_to_the_feature(client: LanguageClient):
    text = client.xml.read_text()
    pos = position_of(text, "$(var Camera)", offset=7)
    locs = await client.text_document_definition_async(types.DefinitionParams(
        text_document=tdi(client.xml_uri), position=pos))
    assert locs and locs[0].uri == client.tvl_uri
    assert locs[0].range.start == position_of(client.tvl.read_text(), "Camera")


async def test_declaration_of_a_var_is_its_arg(client: LanguageClient):
    text = client.yaml.read_text()
    pos = position_of(text, "$(var Lidar)", offset=7)
    locs = await client.text_document_declaration_async(types.DeclarationParams(
        text_document=tdi(client.yaml_uri), position=pos))
    assert locs and locs[0].uri == client.yaml_uri
    assert locs[0].range.start == position_of(text, "{name: Lidar", offset=7)


async def test_rename_feature_updates_xml_and_yaml_launch_files(client: LanguageClient):
    model = client.tvl.read_text()
    pos = position_of(model, "Teleop", offset=1)
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=tdi(client.tvl_uri), position=pos, new_name="Joystick"))
    yaml_new = apply_text_edits(client.yaml.read_text(), edits_by_uri(edit)[client.yaml_uri])
    assert "Teleop" not in yaml_new and "{name: Joystick," in yaml_new and "$(var Joystick)" in yaml_new
    xml_new = apply_text_edits(client.xml.read_text(), edits_by_uri(edit)[client.xml_uri])
    assert "$(var Teleop)" not in xml_new and '<arg name="Joystick" default="false"/>' in xml_new


async def test_hover_on_a_var_counts_products(client: LanguageClient):
    text = client.xml.read_text()
    pos = position_of(text, "$(var Camera)", offset=8)
    v = ""
    for _ in range(100):
        h = await client.text_document_hover_async(types.HoverParams(text_document=tdi(client.xml_uri), position=pos))
        v = h.contents.value if h else ""
        if "of 20 products" in v:
            break
        await asyncio.sleep(0.1)
    assert "Camera" in v and "of 20 products" in v


async def _labels(client, uri, pos):
    res = await client.text_document_completion_async(types.CompletionParams(text_document=tdi(uri), position=pos))
    items = res.items if isinstance(res, types.CompletionList) else res
    return {i.label for i in items}


async def test_completion_in_ros2_xml_and_yaml(client: LanguageClient):
    path = client.ws / "src" / "r2_robot" / "launch" / "scratch.launch.xml"
    text = '<launch>\n  <arg name="Lidar" default="false"/>\n  <node pkg="p" exec="e" if="$(var \n  <\n</launch>\n'
    path.write_text(text)
    uri = open_doc(client, path, text)
    labels = await _labels(client, uri, position_of(text, "$(var ", offset=6))
    assert "Lidar" in labels
    labels = await _labels(client, uri, types.Position(line=3, character=3))
    assert {"push_ros_namespace", "let", "set_remap"} <= labels and "rosparam" not in labels
    ypath = client.ws / "src" / "r2_robot" / "launch" / "scratch.launch.yaml"
    ytext = "launch:\n  - node:\n      pkg: p\n      \n  - \n"
    ypath.write_text(ytext)
    yuri = open_doc(client, ypath, ytext)
    assert {"exec", "namespace", "remap"} <= await _labels(client, yuri, types.Position(line=3, character=6))
    assert {"node", "include", "group"} <= await _labels(client, yuri, types.Position(line=4, character=4))


async def test_missing_arg_quick_fix_in_yaml(client: LanguageClient):
    path = client.ws / "src" / "r2_robot" / "launch" / "partial_args.launch.yaml"
    text = "# tvl-lsp: model=generic.tvl\nlaunch:\n  - arg: {name: Robot, default: \"true\"}\n"
    path.write_text(text)
    uri = open_doc(client, path, text)
    diags = await diagnostics(client, uri, lambda ds: any(str(d.code) == "missing-arg" for d in ds))
    d = next(d for d in diags if str(d.code) == "missing-arg")
    actions = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=tdi(uri), range=d.range, context=types.CodeActionContext(diagnostics=[d])))
    fix = next(a for a in actions if isinstance(a, types.CodeAction) and a.title.startswith("Add `- arg:"))
    new = apply_text_edits(text, fix.edit.changes[uri])
    assert new.count("- arg:") == 2 and new.endswith('default: "false"}\n')
