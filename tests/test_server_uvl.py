"""The language server on UVL and DIMACS models: diagnostics with exact ranges, hover counts, the
configurator, and a generic launch file paired with a .uvl model by a HAROS project file."""

from __future__ import annotations

import asyncio

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, codes, diagnostics, install_client_handlers, open_doc, position_of, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

ROBOT_UVL = """features
\tRobot
\t\tmandatory
\t\t\tBase
\t\t\t\talternative
\t\t\t\t\tKobuki
\t\t\t\t\tCreate
\t\toptional
\t\t\tCamera {resolution 1080}
\t\t\tArm
constraints
\tArm => Kobuki
"""

LAUNCH = """<launch>
  <arg name="Robot"/>
  <arg name="Base"/>
  <arg name="Kobuki"/>
  <arg name="Create"/>
  <arg name="Camera"/>
  <arg name="Armm"/>
  <node if="$(arg Camera)" pkg="usb_cam" type="usb_cam_node" name="camera"/>
</launch>
"""


@pytest_lsp.fixture(config=CONFIG, scope="module")
async def client(lsp_client: LanguageClient, tmp_path_factory):
    ws = tmp_path_factory.mktemp("ws")
    pkg = ws / "src" / "robot"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>robot</name></package>\n")
    (pkg / "robot.uvl").write_text(ROBOT_UVL)
    (pkg / "launch" / "generic.launch").write_text(LAUNCH)
    (ws / "haros.yaml").write_text("configurations:\n  {lf: robot/launch/generic.launch, tvl: robot/robot.uvl}\n")
    (ws / ".catkin_workspace").write_text("")
    (ws / "model.dimacs").write_text("c 1 A\nc 2 B\nc 3 C\np cnf 3 3\n1 0\n-1 -3 0\n-2 3 0\n")
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, "neovim", ws)
    yield
    await lsp_client.shutdown_session()


async def hover_text(client, uri, pos, want: str) -> str:
    value = ""
    for _ in range(150):
        h = await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri), position=pos))
        value = h.contents.value if h else ""
        if want in value:
            break
        await asyncio.sleep(0.1)
    return value


async def test_uvl_hover_counts_and_groups(client: LanguageClient):
    path = client.ws / "src/robot/robot.uvl"
    uri = open_doc(client, path)
    text = path.read_text()
    value = await hover_text(client, uri, position_of(text, "Robot", offset=1), "6 products")
    assert "**6 products** in total" in value
    value = await hover_text(client, uri, position_of(text, "Kobuki", offset=1), "of 6 products")
    assert "in the group `alternative` of `Base`: counted by the group's cardinality" in value
    assert "in **4 of 6 products**" in value
    value = await hover_text(client, uri, position_of(text, "Camera", offset=1), "of 6 products")
    assert "in the group `optional` of `Robot`: optional" in value
    assert "- attribute `resolution 1080` (not analysed)" in value


async def test_uvl_diagnostics_have_exact_ranges(client: LanguageClient):
    path = client.ws / "src/robot/broken.uvl"
    text = ROBOT_UVL.replace("Arm => Kobuki", "Arm => Kobuk")
    path.write_text(text)
    uri = open_doc(client, path)
    diags = await diagnostics(client, uri, lambda ds: "unknown-name" in codes(ds))
    bad = [d for d in diags if d.code == "unknown-name"][0]
    line = text.split("\n")[bad.range.start.line]
    assert line[bad.range.start.character:bad.range.end.character] == "Kobuk"
    assert "Did you mean 'Kobuki'?" in bad.message


async def test_launch_paired_with_uvl_model_by_project_file(client: LanguageClient):
    path = client.ws / "src/robot/launch/generic.launch"
    uri = open_doc(client, path)
    diags = await diagnostics(client, uri, lambda ds: "unmatched-arg" in codes(ds) and "missing-arg" in codes(ds))
    assert "unmatched-arg" in codes(diags) and "missing-arg" in codes(diags)
    unmatched = [d for d in diags if d.code == "unmatched-arg"][0]
    assert "Arm" in unmatched.message


async def test_configurator_on_uvl(client: LanguageClient):
    uri = (client.ws / "src/robot/robot.uvl").as_uri()
    res = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.include", arguments=[uri, "Arm"]))
    assert res["remaining"] == 2  # Arm forces Kobuki; Camera free
    res = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.reset", arguments=[uri]))


async def test_dimacs_model_gets_its_dead_features(client: LanguageClient):
    path = client.ws / "model.dimacs"
    uri = open_doc(client, path)
    diags = await diagnostics(client, uri, lambda ds: codes(ds).count("dead-feature") == 2)
    assert codes(diags) == ["dead-feature", "dead-feature"]
    assert sorted(d.range.start.line for d in diags) == [1, 2]  # the `c 2 B` and `c 3 C` lines
