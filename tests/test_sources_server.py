"""The sources in the language server (issue #26, pytest-lsp, both client profiles): editing a
node's C++ source updates the graph findings of the launch file that starts it (unsaved text),
and a hover on a topic name in the source says in which products the node runs and who is on
the other end."""

from __future__ import annotations

import asyncio
import shutil
import time
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, PROFILES, diagnostics, install_client_handlers, open_doc, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

WS = Path(__file__).parent / "data" / "sources" / "ws"


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("sources") / "ws"
    shutil.copytree(WS, ws)
    lsp_client.ws = ws
    lsp_client.profile = request.param
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


def _paths(client):
    ws = client.ws
    return (ws / "src" / "robot_bringup" / "launch" / "robot.launch",
            ws / "src" / "ros1_cpp" / "src" / "listener.cpp")


def _open_source(client, path: Path, text: str | None = None) -> str:
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id="cpp", version=1, text=path.read_text() if text is None else text)))
    return uri


async def _hover(client, uri, line, col, want: str):
    """Hover until the answer is there (the first builds the graph; under load it may say "hover
    again"), for up to 60 s."""
    deadline = time.monotonic() + 60
    while True:
        h = await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=line, character=col)))
        if h is not None and want in h.contents.value or time.monotonic() > deadline:
            return h
        await asyncio.sleep(0.5)


def _topic_findings(diags):
    return {d.message.split(" ")[1] for d in diags if str(d.code) == "topic-without-publisher"}


async def test_hover_on_a_topic_name_in_a_source(client: LanguageClient):
    launch, listener = _paths(client)
    uri = _open_source(client, listener)
    lines = listener.read_text().splitlines()
    line = next(i for i, t in enumerate(lines) if '"chatter"' in t)
    col = lines[line].index('"chatter"') + 3
    h = await _hover(client, uri, line, col, "robot.launch")
    assert h is not None, "no hover"
    md = h.contents.value
    assert "subscribes to** `chatter` [`std_msgs/String`]" in md and "`ros1_cpp/listener`" in md
    assert "runs as `/robot/listener` when `Listener` (4 of 8 products)" in md
    assert "`/robot/chatter`: published by `/robot/talker` (when `Talker`), `/robot/legacy` (when `Legacy`)" in md
    assert h.range is not None and h.range.start.line == line
    assert lines[line][h.range.start.character:h.range.end.character] == '"chatter"'
    # elsewhere in the source: nothing
    assert await client.text_document_hover_async(types.HoverParams(
        text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=0, character=2))) is None


async def test_editing_a_source_updates_the_findings(client: LanguageClient):
    launch, listener = _paths(client)
    luri = open_doc(client, launch)
    diags = await diagnostics(client, luri, lambda ds: "/robot/odom" in _topic_findings(ds), timeout=60)
    assert "/robot/odom" in _topic_findings(diags)
    # an unsaved edit of the listener: it now listens on "wheel_odom"
    uri = listener.as_uri()
    text = listener.read_text().replace('"odom"', '"wheel_odom"')
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))
    diags = await diagnostics(client, luri, lambda ds: "/robot/wheel_odom" in _topic_findings(ds), timeout=60)
    found = _topic_findings(diags)
    assert "/robot/wheel_odom" in found and "/robot/odom" not in found
    d = next(d for d in diags if "/robot/wheel_odom" in d.message)
    assert any(r.location.uri.endswith("listener.cpp") for r in d.related_information or [])
