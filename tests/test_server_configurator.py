"""The language server's ``tvl-lsp.configurator`` command (what the VS Code webview calls):
the same answers as ``tvl-lsp ui``, decisions shared with tvl-lsp.include / exclude / reset."""

from __future__ import annotations

import asyncio
import shutil
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, PROFILES, install_client_handlers, open_doc, start

REPO = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("cfg") / "ws"
    shutil.copytree(REPO / "examples" / "ws", ws)
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


async def test_configurator_view_requests(client: LanguageClient):
    launch = client.ws / "src/turtlerand/launch/generic.launch"
    uri = open_doc(client, launch)

    async def view(op, params=None):
        return await asyncio.wait_for(client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.configurator", arguments=[uri, op, params or {}])), 120)

    async def run(cmd, *args):
        return await asyncio.wait_for(client.workspace_execute_command_async(types.ExecuteCommandParams(
            command=cmd, arguments=[uri, *args])), 120)

    await run("tvl-lsp.reset")
    m = await view("model")
    assert m["tree"]["id"] == "Turtlerand" and m["launch"] == str(launch)
    g = await view("graph")
    assert any(e["id"] == "node:/Random" for e in g["elements"]) and g["status"]["node:/Random"] == "possible"
    assert (await view("counts"))["remaining"] == "4"
    r = await view("decide", {"feature": "Random", "value": True})
    assert r["ok"] and r["state"]["decisions"] == {"Random": True}
    assert r["state"]["graph"]["node:/Random"] == "certain" and "Teleop" in r["state"]["open"]
    assert (await view("counts"))["remaining"] == "2"
    # the palette commands see the same decisions, and the view sees theirs
    assert (await run("tvl-lsp.count"))["remaining"] == 2
    await run("tvl-lsp.exclude", "Teleop")
    st = await view("state")
    assert st["decisions"] == {"Random": True, "Teleop": False}
    r = await view("decide", {"feature": "Vel", "value": False})
    assert not r["ok"] and r["refused"]["conflictsWith"] == {"Random": True}
    assert "Vel is mandatory in Random" in r["refused"]["message"]
    p = await view("problems")
    # the graph's finding (a product with turtlesim alone: nothing publishes /turtle1/cmd_vel) is
    # excluded once Random is decided; the constant condition stays
    assert [x["code"] for x in p["problems"]] == ["topic-without-publisher", "constant-condition"]
    assert p["status"][p["problems"][0]["id"]] == "excluded"
    r = await view("decide", {"feature": "Multiplexer", "value": False})
    assert r["state"]["complete"]
    g = await view("generate", {"mode": "current"})
    assert len(g["written"]) == 1
    out = Path(g["written"][0])
    assert out.is_file() and client.ws in out.parents and '<arg name="Random" value="true"/>' in out.read_text()
    x = await view("excerpt", {"path": str(launch), "line": 21})
    assert "random_controller" in x["lines"][21 - x["start"]]
    with pytest.raises(Exception, match="unknown feature"):
        await view("decide", {"feature": "Nope", "value": True})
    r = await view("reset")
    assert r["state"]["decisions"] == {} and (await run("tvl-lsp.count"))["remaining"] == 4


async def test_configurator_view_configurations(client: LanguageClient):
    """The requests added for issue 29 through the server: why a feature is implied, decisions
    replaced and completed, a configuration saved next to the model (written by the editor or the
    server) and loaded back, the launch files a model could configure, the panel closed."""
    model = client.ws / "src/turtlerand/launch/generic.tvl"
    uri = open_doc(client, model)

    async def view(op, params=None):
        return await asyncio.wait_for(client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.configurator", arguments=[uri, op, params or {}])), 120)

    await view("reset")
    x = await view("explain", {"feature": "Turtlesim"})
    assert x["implied"] and "Turtlesim is mandatory in Turtlerand" in x["text"]
    r = await view("set", {"decisions": {"Random": True}})
    assert r["ok"] and r["state"]["decisions"] == {"Random": True}
    x = await view("explain", {"feature": "Vel"})
    assert x["text"] == "included because you included Random: Vel is mandatory in Random"
    saved = await view("save", {"name": "lab", "format": "json"})
    path = Path(saved["written"][0])
    assert path == model.parent / "lab.config.json" and '"Random": true' in path.read_text()
    r = await view("complete", {"how": "minimal"})
    assert r["state"]["complete"] and r["added"] == {"Teleop": False, "Multiplexer": False}
    r = await view("load", {"path": str(path)})
    assert r["state"]["decisions"] == {"Random": True}
    assert [f["name"] for f in (await view("configs"))["files"]] == ["lab.config.json"]
    got = await view("launches")
    assert got["candidates"][0]["relative"] == "src/turtlerand/launch/generic.launch"
    assert (await view("close"))["stopped"] >= 0
    await view("reset")
