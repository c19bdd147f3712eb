"""Shared helpers for the language server's end-to-end tests (pytest-lsp)."""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path

from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

from testenv import REPO, make_ws

PROFILES = ["neovim", "visual-studio-code"]

CONFIG = ClientServerConfig(server_command=[sys.executable, "-m", "tvl_lsp"],
                            server_env={"PYTHONPATH": str(REPO)})


def copy_ws(tmp_path: Path) -> Path:
    """A scratch copy of the test workspace (examples/ws + tests/data/ws) in ``tmp_path``."""
    return make_ws(tmp_path / "ws")


def capabilities(profile: str) -> types.ClientCapabilities:
    return client_capabilities(profile)


async def start(client: LanguageClient, profile: str, root: Path, options: dict | None = None):
    opts = {"debounce": 0.05, "count": {"timeBudget": 20}}
    opts.update(options or {})
    client.set_configuration({"tvl-lsp": opts})
    client.init_result = await client.initialize_session(types.InitializeParams(
        capabilities=capabilities(profile),
        root_uri=root.as_uri(),
        workspace_folders=[types.WorkspaceFolder(uri=root.as_uri(), name=root.name)],
        initialization_options=opts,
    ))


def open_doc(client: LanguageClient, path: Path, text: str | None = None, version: int = 1) -> str:
    uri = path.as_uri()
    lang = "tvl" if path.suffix == ".tvl" else "xml"
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id=lang, version=version, text=path.read_text() if text is None else text)))
    return uri


def uses_pull(client: LanguageClient) -> bool:
    """The server offered pull diagnostics to this client (only to those that accept refreshes)."""
    res = getattr(client, "init_result", None)
    return res is not None and res.capabilities.diagnostic_provider is not None


async def diagnostics(client: LanguageClient, uri: str, predicate=None, timeout: float = 30.0):
    """The document's diagnostics (pulled when the client supports pull, else the last
    pushed), waiting until ``predicate(diags)`` holds (or time runs out)."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    diags = []
    while loop.time() < end:
        if uses_pull(client):
            rep = await client.text_document_diagnostic_async(types.DocumentDiagnosticParams(
                text_document=types.TextDocumentIdentifier(uri=uri)))
            diags = list(rep.items)
        else:
            diags = list(client.diagnostics.get(uri, []))
        if (predicate is None and (uri in client.diagnostics or uses_pull(client))) or (
                predicate is not None and predicate(diags)):
            return diags
        await asyncio.sleep(0.1)
    return diags


def codes(diags) -> list[str]:
    return sorted(str(d.code) for d in diags)


def position_of(text: str, needle: str, nth: int = 0, offset: int = 0) -> types.Position:
    """LSP position (UTF-16 == code points for ASCII lines) of the nth occurrence of needle."""
    i = -1
    for _ in range(nth + 1):
        i = text.index(needle, i + 1)
    i += offset
    line = text.count("\n", 0, i)
    col = i - (text.rfind("\n", 0, i) + 1)
    return types.Position(line=line, character=col)


def apply_text_edits(text: str, edits) -> str:
    """Apply LSP TextEdits (ASCII text: characters == UTF-16 units) to ``text``."""
    lines = text.split("\n")
    starts = [0]
    for ln in lines[:-1]:
        starts.append(starts[-1] + len(ln) + 1)

    def off(p):
        if p.line >= len(lines):
            return len(text)
        return starts[p.line] + min(p.character, len(lines[p.line]))
    for e in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character), reverse=True):
        a, b = off(e.range.start), off(e.range.end)
        text = text[:a] + e.new_text + text[b:]
    return text


def edits_by_uri(edit: types.WorkspaceEdit) -> dict[str, list]:
    """The text edits of a WorkspaceEdit by document URI (``changes`` or, for clients that
    support it, versioned ``documentChanges``)."""
    out: dict[str, list] = {}
    for uri, es in (edit.changes or {}).items():
        out.setdefault(uri, []).extend(es)
    for ch in edit.document_changes or []:
        if isinstance(ch, types.TextDocumentEdit):
            out.setdefault(ch.text_document.uri, []).extend(ch.edits)
    return out


def install_client_handlers(client: LanguageClient) -> None:
    """What a real editor does and the bare test client does not: accept dynamic
    registrations, and apply workspace edits (CreateFile + text edits) to disk."""
    client.applied_edits = []

    @client.feature(types.CLIENT_REGISTER_CAPABILITY)
    def register_capability(params: types.RegistrationParams):
        return None

    @client.feature(types.WORKSPACE_CODE_LENS_REFRESH)
    def code_lens_refresh(params):
        return None

    @client.feature(types.WORKSPACE_APPLY_EDIT)
    def apply_edit(params: types.ApplyWorkspaceEditParams):
        client.applied_edits.append(params.edit)
        apply_workspace_edit(params.edit)
        return types.ApplyWorkspaceEditResult(applied=True)


def apply_workspace_edit(edit: types.WorkspaceEdit) -> list[Path]:
    """Apply a WorkspaceEdit to disk as an editor would; returns the files touched."""
    from tvl_lsp.lsp.convert import uri_to_path
    touched = []
    for ch in edit.document_changes or []:
        if isinstance(ch, types.CreateFile):
            p = Path(uri_to_path(ch.uri))
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_text("")
        elif isinstance(ch, types.TextDocumentEdit):
            p = Path(uri_to_path(ch.text_document.uri))
            p.write_text(apply_text_edits(p.read_text() if p.exists() else "", ch.edits))
            touched.append(p)
    for uri, edits in (edit.changes or {}).items():
        p = Path(uri_to_path(uri))
        p.write_text(apply_text_edits(p.read_text(), edits))
        touched.append(p)
    return touched
