"""The LSP generate command and the code-action resolve (issue 12): colliding names are
refused, and nothing is written outside the client's workspace folders (pytest-lsp)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, install_client_handlers, open_doc, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

DATA = Path(__file__).parent / "data/robustness/case_collision"


@pytest_lsp.fixture(config=CONFIG, scope="module")
async def client(lsp_client: LanguageClient, tmp_path_factory):
    base = tmp_path_factory.mktemp("gen")
    ws = base / "ws"
    shutil.copytree(DATA, ws)
    outside = base / "outside"
    shutil.copytree(DATA, outside)
    lsp_client.ws, lsp_client.outside = ws, outside
    install_client_handlers(lsp_client)
    await start(lsp_client, "visual-studio-code", ws)
    yield
    await lsp_client.shutdown_session()


async def _generate(client, path: Path, **opts):
    return await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.generateConfigurations", arguments=[{"uri": path.as_uri(), "mode": "all", **opts}]))


async def test_colliding_names_are_refused(client: LanguageClient):
    launch = client.ws / "src/cc/launch/cc.launch"
    open_doc(client, launch)
    with pytest.raises(Exception, match="differ only in case"):
        await _generate(client, launch)
    assert not (client.ws / "src/cc/configs").exists()


async def test_a_file_outside_the_workspace_folders_gets_nothing_written(client: LanguageClient):
    launch = client.outside / "src/cc/launch/cc.launch"
    (client.outside / "src/cc/launch/cc.tvl").write_text("root Cc {\n  group someOf { Ab, Other }\n}\n")
    launch.write_text(launch.read_text().replace('"AB"', '"Other"').replace("arg AB", "arg Other"))
    open_doc(client, launch)
    with pytest.raises(Exception, match="outside the workspace"):
        await _generate(client, launch)
    action = types.CodeAction(title="generate", data={"tvl-lsp.generate": {"uri": launch.as_uri(), "mode": "all"}})
    with pytest.raises(Exception, match="outside the workspace"):
        await client.code_action_resolve_async(action)
    assert not (client.outside / "src/cc/configs").exists()
    assert not client.applied_edits
