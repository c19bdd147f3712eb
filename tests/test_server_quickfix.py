"""Quick fixes for model anomalies in the editor (#30), end to end with both client profiles
(pytest-lsp): offered with their diagnostic, the edit names the document version, and applying it
removes the finding."""

from __future__ import annotations

import asyncio
import shutil

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import (CONFIG, PROFILES, apply_text_edits, codes, diagnostics, install_client_handlers,
                            start)
from testenv import DATA

pytestmark = pytest.mark.asyncio(loop_scope="module")

QF = DATA / "quickfix"


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("qfws")
    for p in QF.iterdir():
        shutil.copy(p, ws / p.name)
    lsp_client.ws = ws
    lsp_client.profile = request.param
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


def _open(client, name: str, text: str, version: int = 1) -> str:
    path = client.ws / name
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id=path.suffix[1:], version=version, text=text)))
    return uri


def _change(client, uri: str, text: str, version: int) -> None:
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))


async def _quickfixes(client, uri, diag, only=True, timeout=30.0):
    """The quick fixes at the diagnostic; asked again, as an editor does when the cursor moves,
    until some come (a request waits a bounded time for fixes being checked: under load the
    first may come back without them)."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while True:
        acts = await client.text_document_code_action_async(types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(uri=uri), range=diag.range,
            context=types.CodeActionContext(diagnostics=[diag],
                                            only=[types.CodeActionKind.QuickFix] if only else None)))
        out = [a for a in acts or [] if isinstance(a, types.CodeAction) and a.kind == types.CodeActionKind.QuickFix
               and a.edit is not None]
        if out or loop.time() > end:
            return out
        await asyncio.sleep(0.2)


def _edits(action, uri):
    """The text edits of an action's edit, and the version it names (None: unversioned)."""
    edit = action.edit
    if edit.document_changes:
        [dc] = edit.document_changes
        assert dc.text_document.uri == uri
        return list(dc.edits), dc.text_document.version
    return list(edit.changes[uri]), None


ANOMALIES = {"dead-feature", "false-optional", "redundant-constraint", "void-model", "always-false-constraint"}


@pytest.mark.parametrize("name,code,word", [
    ("dead.tvl", "dead-feature", "Lidar"),
    ("false_optional.uvl", "false-optional", "Logger"),
    ("redundant.uvl", "redundant-constraint", "Card | !Card"),
    ("void.tvl", "void-model", None),
])
async def test_fix_offered_with_its_diagnostic_and_applied(client: LanguageClient, name, code, word):
    text = (QF / name).read_text()
    uri = _open(client, name, text)
    diags = await diagnostics(client, uri, lambda ds: code in codes(ds))
    target = [d for d in diags if d.code == code and (word is None or word in d.message
                                                       or word in _at(text, d.range))]
    assert target, [(d.code, d.message) for d in diags]
    acts = await _quickfixes(client, uri, target[0])
    assert acts, f"no quick fix for {code}"
    for a in acts:
        assert a.diagnostics and a.diagnostics[0].code == code
        assert a.title[0].isupper()
    edits, version = _edits(acts[0], uri)
    if client.profile == "visual-studio-code":
        assert version == 1  # VS Code applies documentChanges: the edit is for version 1 only
    new = apply_text_edits(text, edits)
    _change(client, uri, new, 2)
    after = await diagnostics(client, uri, lambda ds: sum(1 for d in ds if d.code == code) < len(
        [d for d in diags if d.code == code]))
    assert sum(1 for d in after if d.code == code) < sum(1 for d in diags if d.code == code)
    # a fix adds no finding
    before_other = sorted((d.code, d.message) for d in diags if d.code in ANOMALIES)
    for d in after:
        if d.code in ANOMALIES:
            assert (d.code, d.message) in before_other or code == "void-model", (d.code, d.message)
    client.text_document_did_close(types.DidCloseTextDocumentParams(
        text_document=types.TextDocumentIdentifier(uri=uri)))


def _at(text: str, rng: types.Range) -> str:
    lines = text.split("\n")
    if rng.start.line != rng.end.line:
        return lines[rng.start.line][rng.start.character:]
    return lines[rng.start.line][rng.start.character:rng.end.character]


async def test_fixes_follow_the_text(client: LanguageClient):
    """Fixes are for the text the document has: after an edit the old ones are not offered, the
    new ones name the new version."""
    name = "several.uvl"
    text = (QF / name).read_text()
    uri = _open(client, name, text)
    diags = await diagnostics(client, uri, lambda ds: "false-optional" in codes(ds))
    fo = [d for d in diags if d.code == "false-optional"][0]
    first = await _quickfixes(client, uri, fo)
    assert any("Make Gps mandatory" in a.title for a in first)
    # a comment line added on top: every position moves by one line
    moved = "// edited\n" + text
    _change(client, uri, moved, 2)
    diags2 = await diagnostics(client, uri, lambda ds: any(d.code == "false-optional" and d.range.start.line
                                                           == fo.range.start.line + 1 for d in ds))
    fo2 = [d for d in diags2 if d.code == "false-optional"][0]
    second = await _quickfixes(client, uri, fo2)
    mand = [a for a in second if "Make Gps mandatory" in a.title]
    assert mand
    edits, version = _edits(mand[0], uri)
    if client.profile == "visual-studio-code":
        assert version == 2
    new = apply_text_edits(moved, edits)
    assert new.startswith("// edited\n") and "                mandatory\n                    Gps\n" in new
    client.text_document_did_close(types.DidCloseTextDocumentParams(
        text_document=types.TextDocumentIdentifier(uri=uri)))


async def test_only_other_kinds_skips_the_fixes(client: LanguageClient):
    name = "dead.uvl"
    text = (QF / name).read_text()
    uri = _open(client, name, text)
    diags = await diagnostics(client, uri, lambda ds: "dead-feature" in codes(ds))
    d = [x for x in diags if x.code == "dead-feature"][0]
    acts = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=types.TextDocumentIdentifier(uri=uri), range=d.range,
        context=types.CodeActionContext(diagnostics=[d], only=[types.CodeActionKind.Source])))
    assert not [a for a in acts or [] if getattr(a, "kind", None) == types.CodeActionKind.QuickFix]
    client.text_document_did_close(types.DidCloseTextDocumentParams(
        text_document=types.TextDocumentIdentifier(uri=uri)))


def _apply_as_editor(action, uri: str, text: str, version: int):
    """What an editor does with a code action's edit on its document at ``version``: a
    versioned edit (``documentChanges``) for another version is refused (None); else the new
    text."""
    edit = action.edit
    if edit.document_changes:
        [dc] = edit.document_changes
        if dc.text_document.uri != uri or (dc.text_document.version is not None
                                           and dc.text_document.version != version):
            return None
        return apply_text_edits(text, list(dc.edits))
    return apply_text_edits(text, list(edit.changes[uri]))


async def test_a_fix_for_a_stale_version_is_refused_and_the_current_one_applies(client: LanguageClient):
    """A fix computed for version 1 names version 1: once the document is at version 2 the
    editor refuses it; asked again, the fixes name version 2, apply and remove the finding."""
    name = "dead.tvl"
    text = (QF / name).read_text()
    uri = _open(client, name, text, version=1)
    diags = await diagnostics(client, uri, lambda ds: "dead-feature" in codes(ds))
    lidar = [d for d in diags if d.code == "dead-feature" and "Lidar" in _at(text, d.range)][0]
    old = await _quickfixes(client, uri, lidar)
    assert old
    assert _apply_as_editor(old[0], uri, text, 1) is not None  # the right version: applies
    moved = "// a line on top: every position moves\n" + text
    _change(client, uri, moved, 2)
    if client.profile == "visual-studio-code":
        assert _edits(old[0], uri)[1] == 1
        assert _apply_as_editor(old[0], uri, moved, 2) is None  # stale: refused
    diags2 = await diagnostics(client, uri, lambda ds: any(
        d.code == "dead-feature" and d.range.start.line == lidar.range.start.line + 1 for d in ds))
    lidar2 = [d for d in diags2 if d.code == "dead-feature" and "Lidar" in _at(moved, d.range)][0]
    new = await _quickfixes(client, uri, lidar2)
    assert [a.title for a in new] == [a.title for a in old]
    if client.profile == "visual-studio-code":
        assert _edits(new[0], uri)[1] == 2
    fixed = _apply_as_editor(new[0], uri, moved, 2)
    assert fixed is not None and fixed.startswith("// a line on top")
    _change(client, uri, fixed, 3)
    after = await diagnostics(client, uri, lambda ds: not any(
        d.code == "dead-feature" and "Lidar" in _at(fixed, d.range) for d in ds))
    assert not any(d.code == "dead-feature" and "Lidar" in _at(fixed, d.range) for d in after)
    assert not [d for d in after if d.code in ANOMALIES and (d.code, d.message) not in
                {(x.code, x.message) for x in diags}]
    client.text_document_did_close(types.DidCloseTextDocumentParams(
        text_document=types.TextDocumentIdentifier(uri=uri)))
