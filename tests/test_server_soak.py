"""Soak: thousands of random incremental edits (invalid positions, non-ASCII and astral
characters, CR/LF mixes) leave the server alive, its text equal to the client's, and its
memory bounded.  The fast variant runs by default; ``-m slow`` runs the long one."""

from __future__ import annotations

import asyncio
import random
import re

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, PROFILES, copy_ws, install_client_handlers, open_doc, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

PIECES = ["", "a", "Feature", "é", "😀", "𝔘x", "\n", "\r\n", "\r", "{", "}", "<node ", "$(arg ", "  ",
          "中文", "\t", "group oneOf {", "opt ", ";", "&&", "\"", "<!--", "-->", "/*", "*/", "\u2028"]


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = copy_ws(tmp_path_factory.mktemp("ws"))
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


# ---------------------------------------------------------------- an independent reference

def _width(ch: str, enc: str) -> int:
    if enc == "utf-8":
        return len(ch.encode("utf-8"))
    if enc == "utf-32":
        return 1
    return 2 if ord(ch) > 0xFFFF else 1


def _lines(text: str):
    """(start, end-of-content) of every line, LSP line terminators."""
    out, start = [], 0
    for m in re.finditer(r"\r\n|\r|\n", text):
        out.append((start, m.start()))
        start = m.end()
    out.append((start, len(text)))
    return out


def ref_offset(text: str, pos: types.Position, enc: str) -> int:
    lines = _lines(text)
    if pos.line >= len(lines):
        return len(text)
    a, b = lines[pos.line]
    units = 0
    for i in range(a, b):
        if units >= pos.character:
            return i
        units += _width(text[i], enc)
    return b


def position_at(text: str, offset: int, enc: str) -> types.Position:
    lines = _lines(text)
    for n, (a, b) in enumerate(lines):
        if a <= offset <= b:
            return types.Position(line=n, character=sum(_width(c, enc) for c in text[a:offset]))
    return types.Position(line=len(lines) - 1, character=0)


def random_position(rng: random.Random, text: str, enc: str) -> types.Position:
    r = rng.random()
    if r < 0.08:  # past the end of the document
        return types.Position(line=len(_lines(text)) + rng.randint(0, 5), character=rng.randint(0, 50))
    if r < 0.16:  # past the end of a line
        lines = _lines(text)
        n = rng.randrange(len(lines))
        a, b = lines[n]
        return types.Position(line=n, character=sum(_width(c, enc) for c in text[a:b]) + rng.randint(1, 40))
    off = rng.randint(0, len(text))
    # only code point boundaries that are not inside a CR LF pair
    if 0 < off < len(text) and text[off - 1] == "\r" and text[off] == "\n":
        off -= 1
    return position_at(text, off, enc)


async def soak(client: LanguageClient, edits: int, seed: int):
    enc = client.init_result.capabilities.position_encoding or "utf-16"
    rng = random.Random(seed)
    docs = {}
    for rel in ("src/scout/launch/generic.tvl", "src/scout/launch/generic.launch"):
        p = client.ws / rel
        text = p.read_text()
        docs[open_doc(client, p, text)] = [text, 1]

    async def state(uri):
        return await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.documentState", arguments=[uri]))
    await asyncio.sleep(0.5)
    rss0 = (await state(next(iter(docs))))["rss"]
    uris = list(docs)
    for i in range(edits):
        uri = rng.choice(uris)
        text, version = docs[uri]
        p1 = random_position(rng, text, enc)
        p2 = random_position(rng, text, enc)
        a, b = ref_offset(text, p1, enc), ref_offset(text, p2, enc)
        if b < a:
            p1, p2, a, b = p2, p1, b, a
        if len(text) > 6000:  # keep the documents from growing without bound
            p2 = position_at(text, min(len(text), a + 200), enc)
            b = ref_offset(text, p2, enc)
        new = "".join(rng.choice(PIECES) for _ in range(rng.randint(0, 3)))
        text = text[:a] + new + text[b:]
        version += 1
        docs[uri] = [text, version]
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[types.TextDocumentContentChangePartial(range=types.Range(start=p1, end=p2), text=new)]))
        if i % 97 == 0:
            # requests keep being answered while edits stream in
            await client.text_document_hover_async(types.HoverParams(
                text_document=types.TextDocumentIdentifier(uri=uri), position=random_position(rng, text, enc)))
            await client.text_document_completion_async(types.CompletionParams(
                text_document=types.TextDocumentIdentifier(uri=uri), position=random_position(rng, text, enc)))
            tdi = types.TextDocumentIdentifier(uri=uri)
            await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=tdi))
            await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=tdi))
            await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=tdi))
            p = random_position(rng, text, enc)
            await client.text_document_code_action_async(types.CodeActionParams(
                text_document=tdi, range=types.Range(start=p, end=p),
                context=types.CodeActionContext(diagnostics=[])))
            await client.text_document_definition_async(types.DefinitionParams(
                text_document=tdi, position=random_position(rng, text, enc)))
        if i % 500 == 499:
            for u in uris:
                st = await state(u)
                assert st["text"] == docs[u][0], f"diverged after {i + 1} edits"
    for u in uris:
        st = await state(u)
        assert st["text"] == docs[u][0] and st["version"] == docs[u][1]
    # still analysing: diagnostics for the final text arrive
    await asyncio.sleep(0.5)
    st = await state(uris[0])
    assert st["rss"] is None or rss0 is None or st["rss"] - rss0 < 150 * 2**20, (rss0, st["rss"])
    assert st["cache"] <= 600


async def test_soak_fast(client: LanguageClient):
    await soak(client, 1000, seed=7)


@pytest.mark.slow
async def test_soak_long(client: LanguageClient):
    await soak(client, 6000, seed=11)
