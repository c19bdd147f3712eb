"""The computation graph in the language server (pytest-lsp, both client profiles): the graph
checks as diagnostics with related locations, hover on a <node> listing its topics with their
conditions, and the ``tvl-lsp.graph`` command returning the JSON of docs/graph.md."""

from __future__ import annotations

import shutil

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from graph_helpers import GRAPH_WS
from server_helpers import CONFIG, PROFILES, diagnostics, install_client_handlers, open_doc, start

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("graph") / "ws"
    shutil.copytree(GRAPH_WS, ws)
    lsp_client.ws = ws
    lsp_client.profile = request.param
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


def _launch(client):
    return client.ws / "src" / "robot" / "launch" / "robot.launch"


def _line_of(path, needle: str) -> tuple[int, int]:
    for i, line in enumerate(path.read_text().splitlines()):
        if needle in line:
            return i, line.index(needle)
    raise AssertionError(needle)


async def test_graph_findings_are_diagnostics(client: LanguageClient):
    launch = _launch(client)
    uri = open_doc(client, launch)
    diags = await diagnostics(client, uri, lambda ds: any(str(d.code) == "topic-without-publisher" for d in ds))
    graph = [d for d in diags if str(d.code) in ("topic-without-publisher", "topic-without-subscriber",
                                                 "topic-type-mismatch", "remap-unused")]
    assert len(graph) == 8
    d = next(d for d in graph if "/base/cmd_vel " in d.message)
    line, col = _line_of(launch, '<node pkg="robot_drivers" type="diff_drive"')
    assert (d.range.start.line, d.range.start.character) == (line, col)
    assert d.severity == types.DiagnosticSeverity.Warning
    assert any(r.location.uri.endswith("haros.yaml") for r in d.related_information or [])
    mm = next(d for d in graph if str(d.code) == "topic-type-mismatch")
    assert any(r.location.uri.endswith("camera.launch") for r in mm.related_information or [])


async def _node_hover(client, uri, line, col):
    """Hover on a node; under load the graph may still be building ("computing…, hover again"):
    hover again, as a user would, for up to 60 s."""
    import asyncio, time
    deadline = time.monotonic() + 60
    while True:
        h = await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=line, character=col)))
        if h is None or "computing…" not in h.contents.value or time.monotonic() > deadline:
            return h
        await asyncio.sleep(0.5)


async def test_hover_on_node_lists_its_topics(client: LanguageClient):
    launch = _launch(client)
    uri = open_doc(client, launch)
    line, col = _line_of(launch, 'type="omni_drive"')
    h = await _node_hover(client, uri, line, col + 3)
    assert h is not None
    md = h.contents.value
    assert "robot_drivers/omni_drive" in md
    assert "subscribes to `/base/cmd_vel_omni`" in md and "when `Nav`" in md
    assert "`/robot/odom`" in md and "provides `/base/set_mode`" in md
    line, col = _line_of(launch, 'type="mapper"')
    h = await _node_hover(client, uri, line, col + 3)
    assert h is not None and "no hints for nav/mapper" in h.contents.value


async def test_graph_command(client: LanguageClient):
    launch = _launch(client)
    uri = open_doc(client, launch)

    async def run(*args):
        return await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.graph", arguments=[uri, *args]))
    doc = await run({"Nav": True}, {"count": True})
    assert doc["products"] == 6 and doc["decisions"] == {"Nav": True}
    assert any(x["node"] == "/planner" and x["topic"] == "/cmd_vel_safe" and x["condition"] is None
               for x in doc["links"])
    doc = await run({"include": ["Nav"], "exclude": ["Omni"]})
    assert doc["decisions"] == {"Nav": True, "Omni": False} and "products" not in doc
    bad = await run({"Nav": True, "Teleop": True})
    assert "no product" in bad["error"] and sorted(bad["conflict"]) == ["Nav", "Teleop"]
    # without decisions: the configurator's current ones for this model
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.include", arguments=[uri, "Camera"]))
    doc = await run()
    assert doc["decisions"] == {"Camera": True}
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.reset", arguments=[uri]))


async def test_graph_command_uses_unsaved_text(client: LanguageClient):
    launch = _launch(client)
    uri = launch.as_uri()
    text = launch.read_text().replace('name="planner"', 'name="route_planner"')
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=50),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))
    doc = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.graph", arguments=[uri, {}]))
    names = {n["name"] for n in doc["nodes"]}
    assert "/route_planner" in names and "/planner" not in names
