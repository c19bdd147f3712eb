"""The language server facing special files and unwritable targets (issue #28, defects 1, 2
and 7), end to end (pytest-lsp):

- a FIFO named ``*.launch`` and a ``*.launch`` link to ``/dev/zero`` in the workspace: the
  server's check process read the workspace's other launch files with a plain read, so every
  check blocked until the 40 s backstop (the FIFO) or read gigabytes (``/dev/zero``); now their
  diagnostics come as usual;
- ``tvl-lsp.generateConfigurations`` with a link among the targets: an LSP error whose message
  says why (it answered ``null``), nothing written through the link, whether the server writes
  the files itself or the editor does (``workspace/applyEdit``).
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, capabilities, codes, copy_ws, diagnostics, install_client_handlers, open_doc

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=CONFIG, scope="module", params=["server-writes", "editor-writes"])
async def client(lsp_client: LanguageClient, tmp_path_factory, request):
    ws = copy_ws(tmp_path_factory.mktemp("special"))
    launch_dir = ws / "src" / "turtlerand" / "launch"
    os.mkfifo(launch_dir / "blocked.launch")               # opening it for reading would block
    os.symlink("/dev/zero", launch_dir / "endless.launch")  # reading it would never end
    (ws / ".git").mkdir(exist_ok=True)
    (ws / ".git" / "config").write_text("[core]\n")
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    caps = capabilities("neovim")
    if request.param == "server-writes":
        caps.workspace.workspace_edit.resource_operations = []
    opts = {"debounce": 0.05, "count": {"timeBudget": 20}}
    lsp_client.set_configuration({"tvl-lsp": opts})
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=caps, root_uri=ws.as_uri(), initialization_options=opts,
        workspace_folders=[types.WorkspaceFolder(uri=ws.as_uri(), name=ws.name)]))
    yield
    await lsp_client.shutdown_session()


async def test_special_files_in_the_workspace_do_not_block_the_checks(client: LanguageClient):
    launch = client.ws / "src" / "turtlerand" / "launch" / "generic.launch"
    t0 = time.monotonic()
    uri = open_doc(client, launch)
    diags = await diagnostics(client, uri, lambda ds: "constant-condition" in codes(ds), timeout=25)
    assert "constant-condition" in codes(diags), diags
    assert time.monotonic() - t0 < 25  # (the backstop was 40 s)


async def test_generate_refuses_a_link_with_an_error_message(client: LanguageClient):
    launch = client.ws / "src" / "turtlerand" / "launch" / "generic.launch"
    open_doc(client, launch)
    configs = client.ws / "src" / "turtlerand" / "configs"
    configs.mkdir(exist_ok=True)
    victim = configs / "generic_turtlesim.launch"
    if not victim.is_symlink():
        victim.symlink_to(Path("../../../.git/config"))
    before = (client.ws / ".git" / "config").read_text()
    listing = sorted(p.name for p in configs.iterdir())
    n_edits = len(client.applied_edits)
    with pytest.raises(Exception, match="symbolic link") as e:
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.generateConfigurations", arguments=[{"uri": launch.as_uri(), "mode": "all"}]))
    assert "\n" not in str(e.value).strip()
    assert (client.ws / ".git" / "config").read_text() == before
    assert len(client.applied_edits) == n_edits
    assert sorted(p.name for p in configs.iterdir()) == listing  # nothing written


async def test_the_generate_code_action_refuses_a_link_too(client: LanguageClient):
    launch = client.ws / "src" / "turtlerand" / "launch" / "generic.launch"
    configs = client.ws / "src" / "turtlerand" / "configs"
    configs.mkdir(exist_ok=True)
    victim = configs / "generic_turtlesim.launch"
    if not victim.is_symlink():
        victim.symlink_to(Path("../../../.git/config"))
    action = types.CodeAction(title="generate", data={"tvl-lsp.generate": {"uri": launch.as_uri(), "mode": "all"}})
    with pytest.raises(Exception, match="symbolic link"):
        await client.code_action_resolve_async(action)
