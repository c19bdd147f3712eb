"""Navigation, rename, completion, structure, formatting, code lens, settings and position
encodings, end to end with the Neovim and VS Code client profiles (pytest-lsp)."""

from __future__ import annotations

import asyncio

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import (CONFIG, PROFILES, apply_text_edits, codes, copy_ws, diagnostics, edits_by_uri,
                            install_client_handlers, open_doc, position_of, start)

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = copy_ws(tmp_path_factory.mktemp("ws"))
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    lsp_client.scout_tvl = ws / "src/scout/launch/generic.tvl"
    lsp_client.scout_launch = ws / "src/scout/launch/generic.launch"
    lsp_client.tvl_uri = open_doc(lsp_client, lsp_client.scout_tvl)
    lsp_client.launch_uri = open_doc(lsp_client, lsp_client.scout_launch)
    yield
    await lsp_client.shutdown_session()


def tdi(uri):
    return types.TextDocumentIdentifier(uri=uri)


async def hover_text(client, uri, pos, want=None):
    for _ in range(100):
        h = await client.text_document_hover_async(types.HoverParams(text_document=tdi(uri), position=pos))
        v = h.contents.value if h else ""
        if want is None or want in v:
            return v
        await asyncio.sleep(0.1)
    return v


async def test_definition_from_launch_arg_use_goes_to_the_feature(client: LanguageClient):
    text = client.scout_launch.read_text()
    pos = position_of(text, "$(arg Simulation)", offset=7)
    locs = await client.text_document_definition_async(types.DefinitionParams(
        text_document=tdi(client.launch_uri), position=pos))
    assert locs and locs[0].uri == client.tvl_uri
    model = client.scout_tvl.read_text()
    assert locs[0].range.start == position_of(model, "Simulation")


async def test_declaration_of_a_launch_arg_is_its_arg_tag(client: LanguageClient):
    text = client.scout_launch.read_text()
    pos = position_of(text, "$(arg Simulation)", offset=7)
    locs = await client.text_document_declaration_async(types.DeclarationParams(
        text_document=tdi(client.launch_uri), position=pos))
    assert locs and locs[0].uri == client.launch_uri
    assert locs[0].range.start == position_of(text, '<arg name="Simulation"', offset=11)


async def test_references_span_model_and_launch_file(client: LanguageClient):
    model = client.scout_tvl.read_text()
    pos = position_of(model, "Laser", offset=1)
    refs = await client.text_document_references_async(types.ReferenceParams(
        text_document=tdi(client.tvl_uri), position=pos,
        context=types.ReferenceContext(include_declaration=True)))
    uris = [r.uri for r in refs]
    launch_text = client.scout_launch.read_text()
    assert uris.count(client.tvl_uri) == model.count("Laser") == 3
    assert uris.count(client.launch_uri) == launch_text.count("Laser") == 2


async def test_rename_feature_updates_model_and_launch_file(client: LanguageClient):
    model = client.scout_tvl.read_text()
    pos = position_of(model, "Laser", offset=2)
    prep = await client.text_document_prepare_rename_async(types.PrepareRenameParams(
        text_document=tdi(client.tvl_uri), position=pos))
    assert prep is not None
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=tdi(client.tvl_uri), position=pos, new_name="Lidar"))
    new_model = apply_text_edits(model, edits_by_uri(edit)[client.tvl_uri])
    launch = client.scout_launch.read_text()
    new_launch = apply_text_edits(launch, edits_by_uri(edit)[client.launch_uri])
    assert "Laser" not in new_model and new_model.count("Lidar") == model.count("Laser")
    assert "Laser" not in new_launch and '<arg name="Lidar"/>' in new_launch and "$(arg Lidar)" in new_launch


@pytest.mark.parametrize("bad", ["lidar", "Webcam", "group", "Two words"])
async def test_rename_refuses_invalid_or_clashing_names(client: LanguageClient, bad):
    model = client.scout_tvl.read_text()
    pos = position_of(model, "Laser", offset=2)
    with pytest.raises(Exception):
        await client.text_document_rename_async(types.RenameParams(
            text_document=tdi(client.tvl_uri), position=pos, new_name=bad))


async def completion_labels(client, uri, pos):
    res = await client.text_document_completion_async(types.CompletionParams(
        text_document=tdi(uri), position=pos))
    items = res.items if isinstance(res, types.CompletionList) else res
    return {i.label for i in items}


async def test_completion_in_tvl(client: LanguageClient):
    model = client.scout_tvl.read_text()
    labels = await completion_labels(client, client.tvl_uri, position_of(model, "Slam ->"))
    assert {"group", "oneOf", "opt", "Laser", "Planner"} <= labels


async def test_completion_in_launch(client: LanguageClient, tmp_path):
    path = client.ws / "src/scout/launch/scratch.launch"
    text = '<launch>\n  <arg name="Mine"/>\n  <node pkg="a" type="b" name="c" if="$(arg \n  <include file="$(find \n  <\n  <node \n</launch>\n'
    uri = open_doc(client, path, text)
    assert "Mine" in await completion_labels(client, uri, position_of(text, "$(arg ", offset=6))
    assert {"scout", "crawler_bringup", "turtlerand"} <= await completion_labels(client, uri, position_of(text, "$(find ", offset=7))
    assert {"node", "group", "include"} <= await completion_labels(client, uri, position_of(text, "  <\n", offset=3))
    assert {"pkg", "type", "name", "if"} <= await completion_labels(client, uri, position_of(text, "<node \n", offset=6))


async def test_document_symbols(client: LanguageClient):
    syms = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=tdi(client.tvl_uri)))
    root = [s for s in syms if s.name == "Scout"][0]
    assert {"Sensors", "Navigation", "Simulation"} <= {c.name for c in root.children}
    syms = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=tdi(client.launch_uri)))
    assert syms[0].name.startswith("<launch>")
    assert any(c.name == "<arg> Simulation" for c in syms[0].children)


async def test_folding_ranges(client: LanguageClient):
    root_line = position_of(client.scout_tvl.read_text(), "root Scout").line
    fr = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=tdi(client.tvl_uri)))
    assert any(r.start_line == root_line for r in fr)
    fr = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=tdi(client.launch_uri)))
    assert any(r.start_line == 0 for r in fr) and len(fr) > 5


async def test_semantic_tokens(client: LanguageClient):
    res = await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=tdi(client.tvl_uri)))
    data = res.data
    assert data and len(data) % 5 == 0
    # absolute (line, column, length, type, modifiers) of each token
    toks, line, col = [], 0, 0
    for i in range(0, len(data), 5):
        dl, dc, n, t, m = data[i:i + 5]
        line, col = line + dl, (col + dc if dl == 0 else dc)
        toks.append((line, col, n, t, m))
    root = position_of(client.scout_tvl.read_text(), "root Scout")
    assert toks[0][:2] == (0, 0) and toks[0][3] == 6  # the header comment
    k = [t[:2] for t in toks].index((root.line, 0))
    # `root` (keyword) then `Scout` (class, declaration)
    assert toks[k] == (root.line, 0, 4, 0, 0)
    assert toks[k + 1] == (root.line, 5, 5, 1, 1)


async def test_formatting_is_idempotent(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/messy.tvl"
    text = "root Turtlerand {group allOf {Turtlesim group allOf {opt Teleop,\n opt Random}}}\n"
    uri = open_doc(client, path, text)
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=tdi(uri), options=types.FormattingOptions(tab_size=2, insert_spaces=True)))
    assert edits
    once = apply_text_edits(text, edits)
    assert once != text
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=once)]))
    again = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=tdi(uri), options=types.FormattingOptions(tab_size=2, insert_spaces=True)))
    assert not again


async def test_hover_on_launch_arg_and_element(client: LanguageClient):
    text = client.scout_launch.read_text()
    v = await hover_text(client, client.launch_uri, position_of(text, '<arg name="Simulation"', offset=12), "of 1152")
    assert "run the scout in the gazebo simulator" in v and "384 of 1152 products" in v
    v = await hover_text(client, client.launch_uri, position_of(text, '<group if="$(arg State_publisher)">', offset=2),
                         "of 1152")
    assert "State_publisher" in v and "576 of 1152 products" in v


async def test_hover_on_arg_says_where_it_is_set(client: LanguageClient):
    # generic.launch is included by configs/teleop.launch, which sets its args
    path = client.ws / "src/turtlerand/launch/generic.launch"
    text = path.read_text()
    uri = open_doc(client, path, text, version=50)
    v = await hover_text(client, uri, position_of(text, '<arg name="Teleop"', offset=12), "set by")
    assert "configs/teleop.launch" in v and "$(arg Teleop)" in v


async def test_hover_on_feature_shows_its_facts(client: LanguageClient):
    model = client.scout_tvl.read_text()
    v = await hover_text(client, client.tvl_uri, position_of(model, "Slam", offset=1), "of 1152")
    assert "parent: `Navigation`" in v and "of 1152 products" in v


async def test_code_lens_on_root(client: LanguageClient):
    for _ in range(100):
        lenses = await client.text_document_code_lens_async(types.CodeLensParams(text_document=tdi(client.tvl_uri)))
        if lenses and "1152" in lenses[0].command.title:
            break
        await asyncio.sleep(0.1)
    root = position_of(client.scout_tvl.read_text(), "root Scout")
    assert lenses[0].command.title.startswith("1152 products") and lenses[0].range.start.line == root.line


async def test_settings_turn_a_code_off_and_change_severity(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic.launch"
    text = path.read_text().replace('  <arg name="Random"/>\n', "")
    uri = open_doc(client, path, text)
    ds = await diagnostics(client, uri, lambda ds: "missing-arg" in codes(ds))
    assert [d.severity for d in ds if d.code == "missing-arg"] == [types.DiagnosticSeverity.Warning]
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"tvl-lsp": {"diagnostics": {"missing-arg": "hint"}}}))
    ds = await diagnostics(client, uri, lambda ds: any(d.severity == types.DiagnosticSeverity.Hint for d in ds))
    assert [d.severity for d in ds if d.code == "missing-arg"] == [types.DiagnosticSeverity.Hint]
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"tvl-lsp": {"diagnostics": {"missing-arg": "off"}}}))
    ds = await diagnostics(client, uri, lambda ds: "missing-arg" not in codes(ds))
    assert "missing-arg" not in codes(ds)
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"tvl-lsp": {"diagnostics": {}}}))


async def test_editing_the_model_rechecks_the_paired_launch_file(client: LanguageClient):
    lpath = client.ws / "src/turtlerand/launch/generic.launch"
    luri = open_doc(client, lpath, version=10)
    mpath = client.ws / "src/turtlerand/launch/generic.tvl"
    mtext = mpath.read_text()
    muri = open_doc(client, mpath, mtext)
    ds = await diagnostics(client, luri, lambda ds: "missing-arg" not in codes(ds))
    assert "missing-arg" not in codes(ds)
    # add a feature to the unsaved model: the launch file now lacks its arg
    new = mtext.replace("opt Random", "opt Random,\n      opt Extra")
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=muri, version=2),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=new)]))
    ds = await diagnostics(client, luri, lambda ds: "missing-arg" in codes(ds))
    assert any("Extra" in d.message for d in ds if d.code == "missing-arg")
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=muri, version=3),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=mtext)]))
    ds = await diagnostics(client, luri, lambda ds: "missing-arg" not in codes(ds))
    assert "missing-arg" not in codes(ds)


async def test_positions_follow_the_negotiated_encoding(client: LanguageClient):
    enc = client.init_result.capabilities.position_encoding or "utf-16"
    path = client.ws / "src/turtlerand/launch/unicode.tvl"
    prefix = "/* é😀 */ "
    text = prefix + "root Ünicode { group allOf { Böse } }\n"
    uri = open_doc(client, path, text)

    def units(s):
        if enc == "utf-8":
            return len(s.encode("utf-8"))
        if enc == "utf-32":
            return len(s)
        return len(s.encode("utf-16-le")) // 2
    col = units(text[: text.index("Böse")])
    locs = await client.text_document_definition_async(types.DefinitionParams(
        text_document=tdi(uri), position=types.Position(line=0, character=col + 1)))
    assert locs[0].range.start.character == col
    assert locs[0].range.end.character == col + units("Böse")


async def test_watched_model_change_on_disk_rechecks_the_open_launch_file(client: LanguageClient):
    lpath = client.ws / "src/turtlerand/launch/generic_alt.launch"
    mpath = client.ws / "src/turtlerand/launch/generic_alt.tvl"
    luri = open_doc(client, lpath)
    ds = await diagnostics(client, luri, lambda ds: "missing-arg" not in codes(ds))
    assert "missing-arg" not in codes(ds)
    original = mpath.read_text()
    mpath.write_text(original.replace("opt Multiplexer", "opt Multiplexer,\n    opt Brand_new"))
    try:
        client.workspace_did_change_watched_files(types.DidChangeWatchedFilesParams(changes=[
            types.FileEvent(uri=mpath.as_uri(), type=types.FileChangeType.Changed)]))
        ds = await diagnostics(client, luri, lambda ds: any("Brand_new" in d.message for d in ds))
        assert any("Brand_new" in d.message for d in ds), [d.message for d in ds]
    finally:
        mpath.write_text(original)
        client.workspace_did_change_watched_files(types.DidChangeWatchedFilesParams(changes=[
            types.FileEvent(uri=mpath.as_uri(), type=types.FileChangeType.Changed)]))


async def test_hover_on_a_diagnostic_shows_its_codes_page(client: LanguageClient):
    """The hover inside a diagnostic's range carries its code's page from the catalogue the
    package ships (what --explain prints), and tvl-lsp.explain returns a page or the list."""
    from tvl_lsp.base.catalogue import section
    path = client.ws / "src/turtlerand/launch/explain_probe.launch"
    text = '<launch>\n  <node pkg="p" type="t" name="n" if="true" unless="false"/>\n</launch>\n'
    path.write_text(text)
    uri = open_doc(client, path, text)
    ds = await diagnostics(client, uri, lambda ds: "if-and-unless" in codes(ds))
    (d,) = [d for d in ds if d.code == "if-and-unless"]
    v = await hover_text(client, uri, d.range.start, "if-and-unless")
    assert "**`if-and-unless`** (error)" in v
    assert "cannot set both 'if' and 'unless' on the same tag" in v and "**Fix:**" in v
    # outside every diagnostic's range: no page
    h = await client.text_document_hover_async(types.HoverParams(
        text_document=tdi(uri), position=types.Position(line=2, character=2)))
    assert h is None or "**Fix:**" not in h.contents.value
    page = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.explain", arguments=["if-and-unless"]))
    assert page["markdown"] == section("if-and-unless") and page["severity"] == "error"
    listing = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.explain", arguments=[]))
    assert {"code": "if-and-unless", "severity": "error"}.items() <= next(
        c for c in listing["codes"] if c["code"] == "if-and-unless").items()
    with pytest.raises(Exception, match="unknown diagnostic code"):
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.explain", arguments=["if-and-unles"]))
