"""The language server on ROS 2 Python launch files (``.launch.py``, ``*_launch.py``), end to end
(pytest-lsp, Neovim and VS Code client profiles) on tests/data/ros2py_editor: a generic
``rover.launch.py`` paired with ``rover.tvl`` with four planted problems, its clean twin, an
``ld.add_action`` file, an XML file that includes the generic one and a Python file it includes.

Diagnostics equal ``--check``'s (code and range); hover, definition, references and rename of
an argument across the Python strings, the model and the including / included files (exact
ranges inside the literals, in the negotiated position encoding, after non-ASCII text);
completion of argument names; the quick fix that adds a missing ``DeclareLaunchArgument``;
generation, the graph and the configurator on a ``.launch.py``; ordinary Python left alone."""

from __future__ import annotations

import ast
import asyncio
import shutil
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import (CONFIG, PROFILES, diagnostics, edits_by_uri, install_client_handlers, open_doc,
                            start)
from tvl_lsp.project.check import check_document

pytestmark = pytest.mark.asyncio(loop_scope="module")

WS = Path(__file__).resolve().parent / "data" / "ros2py_editor" / "ws"
PLANTED = {"missing-arg", "unmatched-arg", "duplicate-node", "dead-element"}


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = tmp_path_factory.mktemp("r2py") / "ws"
    shutil.copytree(WS, ws)
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    d = ws / "src" / "rover" / "launch"
    lsp_client.launch_dir = d
    lsp_client.tvl = d / "rover.tvl"
    lsp_client.py = d / "rover.launch.py"
    lsp_client.tvl_uri = open_doc(lsp_client, lsp_client.tvl)
    lsp_client.py_uri = open_doc(lsp_client, lsp_client.py)
    lsp_client.enc = lsp_client.init_result.capabilities.position_encoding or "utf-16"
    yield
    await lsp_client.shutdown_session()


# ------------------------------------------------------------------ helpers

def tdi(uri):
    return types.TextDocumentIdentifier(uri=uri)


def units(s: str, enc: str) -> int:
    enc = str(getattr(enc, "value", enc))
    if enc == "utf-8":
        return len(s.encode("utf-8"))
    if enc == "utf-32":
        return len(s)
    return len(s.encode("utf-16-le")) // 2


def lsp_pos(text: str, offset: int, enc: str) -> types.Position:
    line = text.count("\n", 0, offset)
    start = text.rfind("\n", 0, offset) + 1
    return types.Position(line=line, character=units(text[start:offset], enc))


def offset_of(text: str, pos: types.Position, enc: str) -> int:
    starts = [0]
    for i, c in enumerate(text):
        if c == "\n":
            starts.append(i + 1)
    line_start = starts[pos.line]
    line_end = text.find("\n", line_start)
    line = text[line_start: len(text) if line_end < 0 else line_end]
    n = 0
    for i, c in enumerate(line):
        if n >= pos.character:
            return line_start + i
        n += units(c, enc)
    return line_start + len(line)


def text_at(text: str, rng: types.Range, enc: str) -> str:
    return text[offset_of(text, rng.start, enc):offset_of(text, rng.end, enc)]


def find(text: str, needle: str, enc: str, nth: int = 0, offset: int = 0) -> types.Position:
    i = -1
    for _ in range(nth + 1):
        i = text.index(needle, i + 1)
    return lsp_pos(text, i + offset, enc)


def apply(text: str, edits, enc: str) -> str:
    for e in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character), reverse=True):
        a, b = offset_of(text, e.range.start, enc), offset_of(text, e.range.end, enc)
        text = text[:a] + e.new_text + text[b:]
    return text


async def full_diagnostics(client: LanguageClient, uri: str, timeout: float = 60.0):
    """The document's diagnostics once the solver-backed check of its current text has landed."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while loop.time() < end:
        st = await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.documentState", arguments=[uri]))
        if st and st.get("phase") == "full" and st.get("resultVersion") == st.get("version"):
            return await diagnostics(client, uri, lambda ds: True)
        await asyncio.sleep(0.1)
    raise AssertionError(f"no full check of {uri} within {timeout} s")


def change(client: LanguageClient, uri: str, text: str, version: int) -> None:
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))


async def hover_text(client: LanguageClient, uri: str, pos: types.Position, until: str = "") -> tuple[str, object]:
    value, rng = "", None
    for _ in range(150):
        h = await client.text_document_hover_async(types.HoverParams(text_document=tdi(uri), position=pos))
        value, rng = (h.contents.value, h.range) if h else ("", None)
        if until in value:
            break
        await asyncio.sleep(0.1)
    return value, rng


def check_keys(path: Path) -> list:
    return sorted((d.code, d.span.start.line, d.span.start.col, d.span.end.line, d.span.end.col)
                  for d in check_document(str(path)))


def lsp_keys(diags, text: str, enc: str) -> list:
    """(code, range in code points): comparable with --check's."""
    out = []
    for d in diags:
        a, b = offset_of(text, d.range.start, enc), offset_of(text, d.range.end, enc)
        sa, sb = lsp_pos(text, a, "utf-32"), lsp_pos(text, b, "utf-32")
        out.append((str(d.code), sa.line, sa.character, sb.line, sb.character))
    return sorted(out)


# ------------------------------------------------------------------ diagnostics

async def test_planted_problems_found_with_their_ranges_as_check_reports_them(client: LanguageClient):
    text = client.py.read_text()
    enc = client.enc
    diags = await full_diagnostics(client, client.py_uri)
    assert lsp_keys(diags, text, enc) == check_keys(client.py)
    by = {}
    for d in diags:
        by.setdefault(str(d.code), []).append(text_at(text, d.range, enc))
    assert set(by) == PLANTED
    assert by["unmatched-arg"] == ["Sonar"]
    assert by["missing-arg"] == ["generate_launch_description"]
    assert by["duplicate-node"] == ["sensor"]
    assert by["dead-element"][0].startswith("Node(package='rover', executable='planner'")
    msgs = {str(d.code): d.message for d in diags}
    assert "DeclareLaunchArgument('Teleop')" in msgs["missing-arg"]
    assert "Camera && Lidar" in msgs["duplicate-node"]
    assert "Node(name='planner')" in msgs["dead-element"] and "Nav -> Lidar" in msgs["dead-element"]


async def test_the_clean_twin_gets_nothing(client: LanguageClient):
    path = client.launch_dir / "clean.launch.py"
    uri = open_doc(client, path)
    assert await full_diagnostics(client, uri) == []
    assert check_keys(path) == []


async def test_a_keystroke_updates_the_diagnostics(client: LanguageClient):
    path = client.launch_dir / "clean.launch.py"
    uri = path.as_uri()
    text = path.read_text()
    typed = text.replace("DeclareLaunchArgument('Nav', default_value='false'),",
                         "DeclareLaunchArgument('Nav', default_value='false'),\n"
                         "        DeclareLaunchArgument('Gps', default_value='false'),")
    change(client, uri, typed, 2)
    diags = await diagnostics(client, uri, lambda ds: any(str(d.code) == "unmatched-arg" for d in ds))
    d = next(d for d in diags if str(d.code) == "unmatched-arg")
    assert text_at(typed, d.range, client.enc) == "Gps"
    change(client, uri, text, 3)
    assert await full_diagnostics(client, uri) == []


async def test_ordinary_python_is_not_analysed(client: LanguageClient):
    """A Python module of the package is no launch file: not checked as one (its hover, if any,
    is about the node's source, never an argument's)."""
    path = client.ws / "src" / "rover" / "rover" / "util.py"
    uri = open_doc(client, path)
    h = await client.text_document_hover_async(types.HoverParams(text_document=tdi(uri),
                                                                 position=types.Position(line=4, character=6)))
    assert h is None or not any(w in h.contents.value for w in ("argument", "products", "**Node**"))
    st = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.documentState", arguments=[uri]))
    assert st["phase"] is None
    assert uri not in client.diagnostics


# ------------------------------------------------------------------ hover

async def test_hover_on_an_argument_declaration_and_use(client: LanguageClient):
    text = client.py.read_text()
    enc = client.enc
    value, rng = await hover_text(client, client.py_uri, find(text, "'Camera', default", enc, offset=3),
                                  "of 24 products")
    assert "**feature** `Rover.Camera`" in value and "in **12 of 24 products**" in value
    assert "DeclareLaunchArgument('Camera')" in value and "default `false`" in value
    assert "sim.launch.xml" in value  # set by the XML file that includes this one
    assert text_at(text, rng, enc) == "Camera"
    # a use on a line with non-ASCII text before it
    value, rng = await hover_text(client, client.py_uri, find(text, "LaunchConfiguration('Camera')", enc, offset=22),
                                  "of 24 products")
    assert "in **12 of 24 products**" in value
    assert text_at(text, rng, enc) == "LaunchConfiguration('Camera')"


async def test_hover_on_a_node_gives_its_presence_condition(client: LanguageClient):
    text = client.py.read_text()
    value, rng = await hover_text(client, client.py_uri,
                                  find(text, "Node(package='rover', executable='lidar'", client.enc, offset=1),
                                  "products) of")
    assert value.startswith("**Node** `sensor`")
    assert "loaded when `Lidar`" in value and "**16 of 24 products**" in value
    value, _ = await hover_text(client, client.py_uri,
                                find(text, "Node(package='rover', executable='planner'", client.enc, offset=1))
    assert "loaded when `Nav && !Lidar`" in value or "loaded in **no** product" in value or \
        "**0 of 24 products**" in value


async def test_hover_on_an_include_argument_describes_the_included_files(client: LanguageClient):
    text = client.py.read_text()
    value, rng = await hover_text(client, client.py_uri, find(text, "'rate': '10'", client.enc, offset=2), "sonar")
    assert "**argument** `rate` of src/rover_sensors/launch/sonar.launch.py" in value
    assert "DeclareLaunchArgument('rate')" in value and "default `5`" in value
    assert "passed to the included file: `10` when `Sonar`" in value
    assert text_at(text, rng, client.enc) == "rate"


# ------------------------------------------------------------------ navigation

async def _locations(client, method, uri, pos):
    if method == "definition":
        return await client.text_document_definition_async(types.DefinitionParams(text_document=tdi(uri), position=pos))
    if method == "declaration":
        return await client.text_document_declaration_async(types.DeclarationParams(text_document=tdi(uri),
                                                                                    position=pos))
    return await client.text_document_references_async(types.ReferenceParams(
        text_document=tdi(uri), position=pos, context=types.ReferenceContext(include_declaration=True)))


def _texts(client, locs) -> list[tuple[str, str]]:
    out = []
    for loc in locs:
        p = Path(loc.uri.replace("file://", ""))
        out.append((p.name, text_at(p.read_text(), loc.range, client.enc)))
    return sorted(out)


async def test_definition_declaration_and_references_of_a_feature_argument(client: LanguageClient):
    text = client.py.read_text()
    pos = find(text, "LaunchConfiguration('Camera')", client.enc, offset=22)
    locs = await _locations(client, "definition", client.py_uri, pos)
    assert locs and locs[0].uri == client.tvl_uri and _texts(client, locs) == [("rover.tvl", "Camera")]
    locs = await _locations(client, "declaration", client.py_uri, pos)
    assert [(loc.uri, loc.range.start) for loc in locs] == [(client.py_uri, find(text, "'Camera', default",
                                                                                 client.enc, offset=1))]
    locs = await _locations(client, "references", client.py_uri, pos)
    names = _texts(client, locs)
    assert names == [("rover.launch.py", "Camera")] * 2 + [("rover.tvl", "Camera"), ("sim.launch.xml", "Camera")]
    # the use after the emoji: its exact column in the negotiated encoding
    line = text.splitlines()[pos.line]
    col = units(line[: line.index("LaunchConfiguration('Camera')") + len("LaunchConfiguration('")], client.enc)
    assert any(loc.range.start == types.Position(line=pos.line, character=col) for loc in locs)


async def test_definition_of_an_include_argument_is_in_the_included_file(client: LanguageClient):
    text = client.py.read_text()
    locs = await _locations(client, "definition", client.py_uri, find(text, "'frame': 'sonar_link'", client.enc,
                                                                       offset=2))
    assert _texts(client, locs) == [("sonar.launch.py", "frame")]
    locs = await _locations(client, "references", client.py_uri, find(text, "'frame': 'sonar_link'", client.enc,
                                                                       offset=2))
    # its declaration and use in sonar.launch.py, and the keys of both files that include it
    assert _texts(client, locs) == [("clean.launch.py", "frame"), ("rover.launch.py", "frame"),
                                    ("sonar.launch.py", "frame"), ("sonar.launch.py", "frame")]


async def test_rename_a_feature_from_the_python_file(client: LanguageClient):
    text = client.py.read_text()
    enc = client.enc
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=tdi(client.py_uri), position=find(text, "LaunchConfiguration('Camera')", enc, offset=24),
        new_name="Kamera"))
    by = edits_by_uri(edit)
    sim = client.launch_dir / "sim.launch.xml"
    assert set(by) == {client.py_uri, client.tvl_uri, sim.as_uri()}
    new_py = apply(text, by[client.py_uri], enc)
    assert "DeclareLaunchArgument('Kamera', default_value='false')" in new_py
    assert "condition=IfCondition(LaunchConfiguration('Kamera'))" in new_py and "Camera" not in new_py
    ast.parse(new_py)
    assert "opt Kamera" in apply(client.tvl.read_text(), by[client.tvl_uri], enc)
    assert '<arg name="Kamera" value="true"/>' in apply(sim.read_text(), by[sim.as_uri()], enc)
    # the edits of open documents are for their current version
    for ch in edit.document_changes or []:
        if ch.text_document.uri in (client.py_uri, client.tvl_uri):
            assert ch.text_document.version == 1


async def test_rename_an_argument_of_an_included_file_from_its_key(client: LanguageClient):
    text = client.py.read_text()
    enc = client.enc
    prep = await client.text_document_prepare_rename_async(types.PrepareRenameParams(
        text_document=tdi(client.py_uri), position=find(text, "'rate': '10'", enc, offset=1)))
    rng = prep.range if hasattr(prep, "range") else prep
    assert text_at(text, rng, enc) == "rate"
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=tdi(client.py_uri), position=find(text, "'rate': '10'", enc, offset=3), new_name="hz"))
    by = edits_by_uri(edit)
    sonar = client.ws / "src" / "rover_sensors" / "launch" / "sonar.launch.py"
    clean = client.launch_dir / "clean.launch.py"
    assert set(by) == {client.py_uri, sonar.as_uri(), clean.as_uri()}
    new_sonar = apply(sonar.read_text(), by[sonar.as_uri()], enc)
    assert "DeclareLaunchArgument('hz', default_value='5')" in new_sonar and "LaunchConfiguration('hz')" in new_sonar
    assert "{'hz': '10', 'frame': 'sonar_link'}" in apply(text, by[client.py_uri], enc)
    assert "{'hz': '10', 'frame': 'sonar_link'}" in apply(clean.read_text(), by[clean.as_uri()], enc)


async def test_names_read_in_an_opaque_function(client: LanguageClient):
    """``context.launch_configurations['x']`` and ``LaunchConfiguration('x').perform(context)``
    are references of the argument: found, and renamed."""
    path = client.launch_dir / "camera.launch.py"
    text = path.read_text()
    uri = open_doc(client, path)
    enc = client.enc
    locs = await _locations(client, "references", uri, find(text, "launch_configurations['Camera']", enc, offset=24))
    # (and the use in listed.launch.py, paired with camera.tvl too)
    assert _texts(client, locs) == [("camera.launch.py", "Camera"), ("camera.launch.py", "Camera"),
                                    ("camera.tvl", "Camera"), ("listed.launch.py", "Camera")]
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=tdi(uri), position=find(text, "LaunchConfiguration('fps')", enc, offset=22), new_name="rate"))
    new = apply(text, edits_by_uri(edit)[uri], enc)
    assert "DeclareLaunchArgument('rate', default_value='30')" in new
    assert "LaunchConfiguration('rate').perform(context)" in new and "fps = " in new


async def test_from_an_xml_file_that_includes_the_python_file(client: LanguageClient):
    """An arg of an XML <include> of the generic .launch.py is the Python file's argument (and
    its model's feature): declaration, and a rename that reaches all three files."""
    sim = client.launch_dir / "sim.launch.xml"
    text = sim.read_text()
    uri = open_doc(client, sim)
    enc = client.enc
    pos = find(text, '<arg name="Lidar"', enc, offset=12)
    locs = await _locations(client, "declaration", uri, pos)
    assert [loc.uri for loc in locs] == [client.py_uri] and _texts(client, locs) == [("rover.launch.py", "Lidar")]
    locs = await _locations(client, "definition", uri, pos)
    assert _texts(client, locs) == [("rover.tvl", "Lidar")]
    edit = await client.text_document_rename_async(types.RenameParams(text_document=tdi(uri), position=pos,
                                                                      new_name="Laser"))
    by = edits_by_uri(edit)
    assert set(by) == {uri, client.py_uri, client.tvl_uri}
    assert '<arg name="Laser" value="true"/>' in apply(text, by[uri], enc)
    new_py = apply(client.py.read_text(), by[client.py_uri], enc)
    # the declaration, the IfCondition and the use inside the PythonExpression
    assert new_py.count("'Laser'") == 3 and "'Lidar'" not in new_py
    ast.parse(new_py)


async def test_rename_says_which_strings_it_left(client: LanguageClient):
    """Arguments declared from a list of names: the rename changes the uses it knows and says
    which other strings with the old name it left as they are."""
    path = client.launch_dir / "listed.launch.py"
    text = path.read_text()
    uri = open_doc(client, path)
    enc = client.enc
    before = len(client.messages)
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=tdi(uri), position=find(text, "LaunchConfiguration('Camera')", enc, offset=22),
        new_name="Webcam"))
    by = edits_by_uri(edit)
    assert "LaunchConfiguration('Webcam')" in apply(text, by[uri], enc)
    assert "camera.tvl" in {Path(u).name for u in by}
    for _ in range(50):
        if len(client.messages) > before:
            break
        await asyncio.sleep(0.05)
    notes = [m.message for m in client.messages[before:]]
    assert any("listed.launch.py (line 10)" in m and "'Camera'" in m for m in notes), notes


async def test_rename_refuses_a_name_the_file_declares(client: LanguageClient):
    text = client.py.read_text()
    with pytest.raises(Exception, match="already"):
        await client.text_document_rename_async(types.RenameParams(
            text_document=tdi(client.py_uri), position=find(text, "'Sonar', default", client.enc, offset=2),
            new_name="Lidar"))


# ------------------------------------------------------------------ completion

async def _labels(client, uri, pos):
    res = await client.text_document_completion_async(types.CompletionParams(text_document=tdi(uri), position=pos))
    items = res.items if isinstance(res, types.CompletionList) else (res or [])
    return {i.label: i for i in items}


async def test_completion_of_argument_names(client: LanguageClient):
    enc = client.enc
    path = client.launch_dir / "scratch.launch.py"
    base = client.py.read_text()
    text = base.replace("        Node(package='rover', executable='diff_drive', name='drive',",
                        "        DeclareLaunchArgument('Te\n"
                        "        Node(package='rover', executable='x', condition=IfCondition(LaunchConfiguration('Ca\n"
                        "        IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(sensors, 'launch', "
                        "'sonar.launch.py')), launch_arguments=[('rate', '3'), ('\n"
                        "        Node(package='rover', executable='diff_drive', name='drive',")
    path.write_text(base)
    uri = open_doc(client, path, base.replace("# The rover's", "# tvl-lsp: model=rover.tvl\n# The rover's"))
    await full_diagnostics(client, uri)  # (the file was analysed before it was broken by typing)
    text = "# tvl-lsp: model=rover.tvl\n" + text
    change(client, uri, text, 2)
    labels = await _labels(client, uri, find(text, "LaunchConfiguration('Ca", enc, offset=23))
    assert {"Camera", "Diff", "Sonar", "Teleop"} <= set(labels)
    item = labels["Camera"]
    assert text_at(text, item.text_edit.range, enc) == "Ca" and item.text_edit.new_text == "Camera"
    assert "no DeclareLaunchArgument" in labels["Teleop"].detail
    labels = await _labels(client, uri, find(text, "DeclareLaunchArgument('Te", enc, offset=25))
    assert set(labels) == {"Teleop"}  # the features without an argument
    # keys of an include: the included file's arguments not passed yet
    labels = await _labels(client, uri, find(text, "('rate', '3'), ('", enc, offset=17))
    assert set(labels) == {"frame"} and "default `sonar`" in labels["frame"].detail
    # elsewhere in a string: nothing
    assert not await _labels(client, uri, find(text, "executable='x'", enc, offset=12))


# ------------------------------------------------------------------ code actions

async def _actions(client, uri, rng, diags):
    return await client.text_document_code_action_async(types.CodeActionParams(
        text_document=tdi(uri), range=rng, context=types.CodeActionContext(diagnostics=diags)))


async def test_quick_fix_adds_the_missing_declare_launch_argument(client: LanguageClient):
    enc = client.enc
    path = client.launch_dir / "fixme.launch.py"
    text = client.py.read_text().replace("# The rover's", "# tvl-lsp: model=rover.tvl\n# The rover's")
    path.write_text(text)
    uri = open_doc(client, path, text)
    diags = await full_diagnostics(client, uri)
    d = next(d for d in diags if str(d.code) == "missing-arg")
    actions = await _actions(client, uri, d.range, [d])
    fix = next(a for a in actions if a.title == "Add DeclareLaunchArgument('Teleop')")
    assert fix.kind == types.CodeActionKind.QuickFix and fix.is_preferred
    new = apply(text, edits_by_uri(fix.edit)[uri], enc)
    ast.parse(new)
    assert ("        DeclareLaunchArgument('Sonar', default_value='false'),\n"
            "        DeclareLaunchArgument('Teleop', default_value='false'),\n"
            "        Node(") in new
    change(client, uri, new, 2)
    after = await full_diagnostics(client, uri)
    assert not any(str(x.code) == "missing-arg" for x in after)


async def test_add_all_missing_arguments_to_an_add_action_file_with_the_import(client: LanguageClient):
    enc = client.enc
    path = client.launch_dir / "teleop_launch.py"
    text = path.read_text()
    uri = open_doc(client, path)
    diags = await full_diagnostics(client, uri)
    missing = [d for d in diags if str(d.code) == "missing-arg"]
    assert len(missing) == 8 and {text_at(text, d.range, enc) for d in missing} == {"generate_launch_description"}
    actions = await _actions(client, uri, missing[0].range, missing)
    fix = next(a for a in actions if a.title == "Add all 8 missing DeclareLaunchArgument actions")
    new = apply(text, edits_by_uri(fix.edit)[uri], enc)
    ast.parse(new)
    assert new.count("from launch.actions import DeclareLaunchArgument\n") == 1
    assert "from launch import LaunchDescription\nfrom launch.actions import DeclareLaunchArgument\n" in new
    assert "    ld.add_action(DeclareLaunchArgument('Teleop', default_value='false'))\n" in new
    assert new.index("DeclareLaunchArgument('Teleop'") < new.index("executable='teleop'")
    change(client, uri, new, 2)
    after = await full_diagnostics(client, uri)
    assert not any(str(x.code) == "missing-arg" for x in after)


async def test_generate_configuration_launch_files_for_the_generic_python_file(client: LanguageClient):
    path = client.launch_dir / "clean.launch.py"
    res = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.generateConfigurations", arguments=[{"uri": path.as_uri(), "mode": "all"}]))
    files = [Path(f) for f in res["files"]]
    assert len(files) == 24 and all(f.name.endswith(".launch.xml") and f.parent.name == "configs" for f in files)
    text = files[0].read_text() if files[0].exists() else ""
    assert '<include file="$(find-pkg-share rover)/launch/clean.launch.py">' in text
    assert text.count("<arg name=") == 8


# ------------------------------------------------------------------ graph and configurator

async def test_graph_and_configurator_of_a_python_launch_file(client: LanguageClient):
    g = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.graph", arguments=[client.py_uri]))
    nodes = {n["name"]: n for n in g["nodes"]}
    assert {"/drive", "/sensor", "/sonar"} <= set(nodes)
    res = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.include", arguments=[client.py_uri, "Nav"]))
    assert res["remaining"] == 8 and res["forced"].get("Lidar") is True
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.reset", arguments=[client.py_uri]))
