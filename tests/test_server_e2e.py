"""End-to-end sessions on a copy of the test workspace (tests/testenv.py), with the Neovim and the VS Code
client capability profiles (pytest-lsp)."""

from __future__ import annotations

import sys

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import (REPO, CONFIG, PROFILES, codes, copy_ws, diagnostics,
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


async def test_scout_launch_shows_its_real_problems(client: LanguageClient):
    path = client.ws / "src/scout/launch/generic.launch"
    uri = open_doc(client, path)
    diags = await diagnostics(client, uri, lambda ds: "undefined-arg" in codes(ds))
    und = [d for d in diags if d.code == "undefined-arg"]
    assert und, codes(diags)
    text = path.read_text()
    # the range is exactly the $(arg stereo_cam) substitution
    line = text.split("\n")[und[0].range.start.line]
    assert line[und[0].range.start.character: und[0].range.end.character] == "$(arg stereo_cam)"


async def test_server_and_check_cli_agree_on_every_workspace_file(client: LanguageClient):
    """The server runs the same pipeline as ``tvl-lsp --check``: same diagnostics."""
    from tvl_lsp.project.check import check_document
    rels = ["src/scout/launch/generic.launch", "src/scout/launch/generic.tvl",
            "src/crawler_bringup/launch/generic.launch", "src/crawler/models/crawler.tvl",
            "src/turtlerand/launch/generic_alt.launch", "src/turtlerand/launch/generic_alt.tvl",
            "src/turtlerand/launch/generic_nested.launch"]
    for rel in rels:
        path = client.ws / rel
        want = sorted((d.code, d.span.start.line, d.span.start.col, d.message)
                      for d in check_document(str(path), path.read_text(), roots=[str(client.ws)]))
        uri = open_doc(client, path)

        def same(ds):
            return sorted((d.code, d.range.start.line, d.range.start.character, d.message) for d in ds) == want
        diags = await diagnostics(client, uri, same, timeout=20)
        got = sorted((d.code, d.range.start.line, d.range.start.character, d.message) for d in diags)
        assert got == want, rel
        assert want or rel.endswith(("generic_nested.launch", "scout/launch/generic.tvl",
                                     "crawler.tvl")), rel  # the others have something to report


async def test_hover_on_scout_root_shows_1152(client: LanguageClient):
    path = client.ws / "src/scout/launch/generic.tvl"
    uri = open_doc(client, path)
    text = path.read_text()
    pos = position_of(text, "root Scout", offset=6)
    value = ""
    for _ in range(100):
        h = await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri), position=pos))
        assert h is not None
        value = h.contents.value
        if "1152" in value:
            break
        import asyncio
        await asyncio.sleep(0.1)
    assert "1152" in value, value
    # the count ran with $/progress (both profiles support work done progress)
    reports = [r for rs in client.progress_reports.values() for r in rs]
    assert any(isinstance(r, types.WorkDoneProgressBegin) and "scout" not in r.title.lower() or
               isinstance(r, types.WorkDoneProgressBegin) for r in reports)
    assert any(isinstance(r, types.WorkDoneProgressEnd) for r in reports)


async def test_main_rejects_bad_arguments(capsys):
    from tvl_lsp.server import main, serve
    assert main(["--tcp", "localhost:notaport"]) == 2
    assert main(["--bogus"]) == 2
    assert serve(tcp="localhost:notaport") == 2




async def test_counting_starts_when_the_model_is_checked(client: LanguageClient):
    """Counting starts in the background once a model is checked, not when it is first
    hovered: a user who opens a model whose count takes seconds and hovers its root a while
    later sees the total at once, not "counting…"."""
    import asyncio
    sys.path.insert(0, str(REPO / "bench"))
    from gen_model import generate_model
    path = client.ws / "src" / "big.tvl"
    path.write_text(generate_model(800))
    uri = open_doc(client, path)
    await diagnostics(client, uri, lambda ds: True)
    # wait, without hovering, until the background count reports its end through $/progress
    # (it never starts without the prefetch); a loaded machine only makes this slower
    loop = asyncio.get_running_loop()
    end = loop.time() + 90

    def count_done():  # a progress bar "Counting the products of big.tvl" that has ended
        return any(any(isinstance(r, types.WorkDoneProgressBegin) and "big.tvl" in r.title for r in rs)
                   and any(isinstance(r, types.WorkDoneProgressEnd) for r in rs)
                   for rs in client.progress_reports.values())
    while not count_done() and loop.time() < end:
        await asyncio.sleep(0.2)
    assert count_done(), "no background count ran after the model was checked"
    h = await client.text_document_hover_async(types.HoverParams(
        text_document=types.TextDocumentIdentifier(uri=uri), position=position_of(path.read_text(), "Root", offset=1)))
    assert h is not None
    assert "products** in total" in h.contents.value, h.contents.value
