"""The language server on a Python launch file, end to end (pytest-lsp): the diagnostics of
--check with exact ranges into the .py text, and the other requests answer without failing."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, PROFILES, diagnostics, install_client_handlers, open_doc, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

WS = Path(__file__).resolve().parent / "data" / "ros2py" / "ws"


@pytest_lsp.fixture(config=CONFIG, params=PROFILES[:1], scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("r2py") / "ws"
    shutil.copytree(WS, ws)
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    lsp_client.py = ws / "src" / "py_robot" / "launch" / "issues.launch.py"
    lsp_client.py_uri = open_doc(lsp_client, lsp_client.py)
    yield
    await lsp_client.shutdown_session()


def _text_at(text: str, rng: types.Range) -> str:
    line = text.split("\n")[rng.start.line]
    return line[rng.start.character:rng.end.character] if rng.start.line == rng.end.line else line


async def test_diagnostics_of_a_python_generic_file(client: LanguageClient):
    diags = await diagnostics(client, client.py_uri, lambda ds: any(str(d.code) == "duplicate-node" for d in ds))
    text = client.py.read_text()
    by = {}
    for d in diags:
        by.setdefault(str(d.code), []).append(_text_at(text, d.range))
    assert by["unmatched-arg"] == ["Sonar"]
    assert "missing-arg" in by and "dead-element" in by
    assert by["duplicate-node"] and all("drive" in t for t in by["duplicate-node"])


async def test_other_requests_answer_on_a_python_file(client: LanguageClient):
    pos = types.Position(line=21, character=40)
    tdi = types.TextDocumentIdentifier(uri=client.py_uri)
    await client.text_document_hover_async(types.HoverParams(text_document=tdi, position=pos))
    await client.text_document_completion_async(types.CompletionParams(text_document=tdi, position=pos))
    await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=tdi))
    await client.text_document_code_action_async(types.CodeActionParams(
        text_document=tdi, range=types.Range(start=pos, end=pos), context=types.CodeActionContext(diagnostics=[])))
