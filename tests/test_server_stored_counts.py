"""Reopening a model counted before (issue #15): a fresh server answers the first hover on a
feature with its count from the facts stored on disk by content -- no parse, encoding or
circuit in a worker process first -- never with a stale count for an edited text, and a
damaged or foreign stored file is ignored (the count is computed again, exactly)."""

from __future__ import annotations

import asyncio
import os
import sys
from pathlib import Path

import pytest
from lsprotocol import types
from pytest_lsp import ClientServerConfig

from server_helpers import diagnostics, open_doc, position_of, start
from testenv import REPO

pytestmark = pytest.mark.asyncio

ROBOT_UVL = """features
\tRobot
\t\tmandatory
\t\t\tBase
\t\t\t\talternative
\t\t\t\t\tKobuki
\t\t\t\t\tCreate
\t\toptional
\t\t\tCamera
\t\t\tArm
constraints
\tArm => Kobuki
"""


def _config(cache: Path) -> ClientServerConfig:
    env = {"PYTHONPATH": str(REPO), "TVL_LSP_CACHE_DIR": str(cache), "PATH": os.environ.get("PATH", "")}
    return ClientServerConfig(server_command=[sys.executable, "-m", "tvl_lsp"], server_env=env)


async def _server(cache: Path, ws: Path):
    client = await _config(cache).start()
    await start(client, "neovim", ws)
    return client


async def _hover(client, uri: str, pos) -> str:
    h = await client.text_document_hover_async(types.HoverParams(
        text_document=types.TextDocumentIdentifier(uri=uri), position=pos))
    return h.contents.value if h else ""


async def _first_feature_hover(client, uri: str, pos) -> str:
    """The first hover that names the feature (before the model's parse, a hover is empty)."""
    for _ in range(200):
        value = await _hover(client, uri, pos)
        if "**feature**" in value:
            return value
        await asyncio.sleep(0.05)
    return value


async def _counted_hover(client, uri: str, pos, want: str) -> str:
    value = ""
    for _ in range(300):
        value = await _hover(client, uri, pos)
        if want in value:
            break
        await asyncio.sleep(0.1)
    return value


def _facts_files(cache: Path) -> list[Path]:
    return sorted(cache.glob("*.facts"))


async def _robot_counted_once(tmp_path: Path):
    """A workspace with robot.uvl, counted (and its facts stored) by a first server that has
    stopped since: (workspace, model, cache folder, position of Kobuki)."""
    ws = tmp_path / "ws"
    ws.mkdir()
    model = ws / "robot.uvl"
    model.write_text(ROBOT_UVL)
    cache = tmp_path / "cache"
    pos = position_of(ROBOT_UVL, "Kobuki", offset=1)
    first = await _server(cache, ws)
    try:
        uri = open_doc(first, model)
        assert "in **4 of 6 products**" in await _counted_hover(first, uri, pos, "of 6 products")
    finally:
        await first.shutdown_session()
    assert _facts_files(cache), "the counted facts were not stored"
    return ws, model, cache, pos


async def test_reopened_model_hover_is_counted_at_once_and_edits_are_never_stale(tmp_path):
    ws, model, cache, pos = await _robot_counted_once(tmp_path)
    # a fresh server: the very first hover that finds the feature has its count
    again = await _server(cache, ws)
    try:
        uri = open_doc(again, model)
        value = await _first_feature_hover(again, uri, pos)
        assert "in **4 of 6 products**" in value, value
        # (answered from the stored facts, maybe before the server's parse: the same text)
        await diagnostics(again, uri)
        assert await _hover(again, uri, pos) == value
        assert "**root feature** `Robot`" in await _hover(again, uri, position_of(ROBOT_UVL, "Robot", offset=1))
        # an edit (the constraint removed) is a new content: its own exact count, never the
        # stored one of the old text
        edited = ROBOT_UVL.replace("constraints\n\tArm => Kobuki\n", "")
        again.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=edited)]))
        value = await _counted_hover(again, uri, pos, "of 8 products")
        assert "in **4 of 8 products**" in value, value
    finally:
        await again.shutdown_session()


async def test_a_stored_file_of_another_text_is_not_used(tmp_path):
    """The model opened with a text that differs from the stored one (edited on disk while
    no server ran): counted for its own text."""
    ws, model, cache, pos = await _robot_counted_once(tmp_path)
    edited = ROBOT_UVL.replace("Arm => Kobuki", "Camera => Create")
    model.write_text(edited)
    second = await _server(cache, ws)
    try:
        uri = open_doc(second, model)
        value = await _counted_hover(second, uri, position_of(edited, "Kobuki", offset=1), "products**")
        # Kobuki x {no camera} x {arm or not} = 2; Create x {camera or not} x {arm or not} = 4
        assert "in **2 of 6 products**" in value, value
    finally:
        await second.shutdown_session()


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
@pytest.mark.parametrize("damage", ["garbage", "truncated", "foreign"])
async def test_damaged_or_foreign_stored_facts_are_ignored(tmp_path, damage):
    ws = tmp_path / "ws"
    ws.mkdir()
    model = ws / "robot.uvl"
    model.write_text(ROBOT_UVL)
    other = ws / "other.uvl"
    other.write_text("features\n\tOther\n\t\toptional\n\t\t\tX\n\t\t\tKobuki\n")
    cache = tmp_path / "cache"
    pos = position_of(ROBOT_UVL, "Kobuki", offset=1)
    first = await _server(cache, ws)
    try:
        uri = open_doc(first, model)
        assert "of 6 products" in await _counted_hover(first, uri, pos, "of 6 products")
        before = set(_facts_files(cache))
        if damage == "foreign":  # another model's (sound) facts file
            ouri = open_doc(first, other)
            opos = position_of(other.read_text(), "Kobuki", offset=1)
            assert "of 4 products" in await _counted_hover(first, ouri, opos, "of 4 products")
    finally:
        await first.shutdown_session()
    (mine,) = before
    if damage == "garbage":
        mine.write_bytes(b"\x00\xff not a facts file \xfe" * 50)
    elif damage == "truncated":
        mine.write_bytes(mine.read_bytes()[: len(mine.read_bytes()) // 2])
    else:
        (theirs,) = set(_facts_files(cache)) - before
        mine.write_bytes(theirs.read_bytes())
    second = await _server(cache, ws)
    try:
        uri = open_doc(second, model)
        value = await _counted_hover(second, uri, pos, "products**")
        assert "in **4 of 6 products**" in value, value
    finally:
        await second.shutdown_session()
