"""End-to-end sessions on a copy of the thesis workspace, with the Neovim and the VS Code
client capability profiles (pytest-lsp)."""

from __future__ import annotations

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import (CONFIG, PROFILES, apply_text_edits, codes, copy_ws, diagnostics,
                            install_client_handlers, open_doc, position_of, start)

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = copy_ws(tmp_path_factory.mktemp("ws"))
    lsp_client.ws = ws
    lsp_client.profile = request.param
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


async def test_lizi_launch_shows_its_real_problems(client: LanguageClient):
    path = client.ws / "src/lizi/launch/generic.launch"
    uri = open_doc(client, path)
    diags = await diagnostics(client, uri, lambda ds: "undefined-arg" in codes(ds))
    und = [d for d in diags if d.code == "undefined-arg"]
    assert und, codes(diags)
    text = path.read_text()
    # the range is exactly the $(arg depth_cam) substitution
    line = text.split("\n")[und[0].range.start.line]
    assert "depth_cam" in line[und[0].range.start.character: und[0].range.end.character]


async def test_hover_on_lizi_root_shows_2304(client: LanguageClient):
    path = client.ws / "src/lizi/launch/generic.tvl"
    uri = open_doc(client, path)
    text = path.read_text()
    pos = position_of(text, "Lizi", offset=1)
    value = ""
    for _ in range(100):
        h = await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri), position=pos))
        assert h is not None
        value = h.contents.value
        if "2304" in value:
            break
        import asyncio
        await asyncio.sleep(0.1)
    assert "2304" in value, value
