"""The editor on a generic ROS 2 launch file and its ROS 1 twin (pytest-lsp): the server
publishes, for each, exactly the problems `--check` reports (code and range), and the two
twins get the same findings."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, PROFILES, diagnostics, install_client_handlers, open_doc, start
from tvl_lsp.project.check import check_document

pytestmark = pytest.mark.asyncio(loop_scope="module")

TWINS = Path(__file__).resolve().parent / "data" / "ros2" / "twins"
TWIN_CODES = {"undefined-arg", "unmatched-arg", "missing-arg", "dead-element", "duplicate-node",
              "constant-condition", "invalid-condition"}


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    root = tmp_path_factory.mktemp("twins") / "twins"
    shutil.copytree(TWINS, root)
    lsp_client.root = root
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, root)
    yield
    await lsp_client.shutdown_session()


def _lsp_keys(diags) -> list:
    return sorted((str(d.code), d.range.start.line, d.range.start.character, d.range.end.line,
                   d.range.end.character) for d in diags)


def _check_keys(path: Path) -> list:
    return sorted((d.code, d.span.start.line, d.span.start.col, d.span.end.line, d.span.end.col)
                  for d in check_document(str(path)))


async def _published(client: LanguageClient, path: Path) -> list:
    uri = open_doc(client, path)
    want = len(_check_keys(path))
    diags = await diagnostics(client, uri, lambda ds: len(ds) >= want and
                              any(str(d.code) == "dead-element" for d in ds))
    client.text_document_did_close(types.DidCloseTextDocumentParams(
        text_document=types.TextDocumentIdentifier(uri=uri)))
    return diags


@pytest.mark.parametrize("name", ["courier", "twin_robot"])
async def test_the_editor_shows_what_check_reports_and_the_twins_agree(client: LanguageClient, name):
    stem = "robot" if name == "twin_robot" else name
    ros1 = client.root / "ros1" / "src" / name / "launch" / f"{stem}.launch"
    ros2 = client.root / "ros2" / "src" / name / "launch" / f"{stem}.launch.xml"
    got1 = _lsp_keys(await _published(client, ros1))
    got2 = _lsp_keys(await _published(client, ros2))
    assert got1 == _check_keys(ros1)
    assert got2 == _check_keys(ros2)
    assert [k for k in got1 if k[0] in TWIN_CODES] == [k for k in got2 if k[0] in TWIN_CODES]
    assert {k[0] for k in got2} >= {"missing-arg", "unmatched-arg", "duplicate-node", "dead-element",
                                    "constant-condition", "undefined-arg"}
