"""Code actions, configuration generation and the configurator commands, end to end with
both client profiles (pytest-lsp)."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from testenv import ROSLAUNCH_MISSING, have_roslaunch
from server_helpers import (CONFIG, PROFILES, apply_text_edits, codes, copy_ws, diagnostics,
                            install_client_handlers, open_doc, start)

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="module")
async def client(lsp_client: LanguageClient, request, tmp_path_factory):
    ws = copy_ws(tmp_path_factory.mktemp("ws"))
    lsp_client.ws = ws
    install_client_handlers(lsp_client)
    await start(lsp_client, request.param, ws)
    yield
    await lsp_client.shutdown_session()


def _change_all(client, uri, text, version):
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))


def _command_of(a):
    """(name, arguments) of an action's command.  lsprotocol structures every code action
    that carries a command as a plain Command on the client side, so accept both."""
    if isinstance(a, types.Command):
        return a.command, a.arguments
    if a.command is not None:
        return a.command.command, a.command.arguments
    return None, None


def _fixes(actions):
    return [a for a in actions if isinstance(a, types.CodeAction) and a.edit is not None]


async def _actions(client, uri, diag):
    return await client.text_document_code_action_async(types.CodeActionParams(
        text_document=types.TextDocumentIdentifier(uri=uri), range=diag.range,
        context=types.CodeActionContext(diagnostics=[diag])))


async def test_add_missing_arg_action_removes_the_diagnostic(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic.launch"
    original = path.read_text()
    text = original.replace('  <arg name="Random"/>\n', "")
    uri = open_doc(client, path, text)
    diags = await diagnostics(client, uri, lambda ds: "missing-arg" in codes(ds))
    missing = [d for d in diags if d.code == "missing-arg"]
    assert len(missing) == 1 and "Random" in missing[0].message
    actions = await _actions(client, uri, missing[0])
    fix = [a for a in _fixes(actions) if a.kind == types.CodeActionKind.QuickFix and "Random" in a.title]
    assert fix, [a.title for a in actions]
    edits = fix[0].edit.changes[uri]
    new_text = apply_text_edits(text, edits)
    # inserted after the last top-level arg, with the file's indentation
    assert '  <arg name="Multiplexer"/>\n  <arg name="Random"/>\n' in new_text
    _change_all(client, uri, new_text, 2)
    diags = await diagnostics(client, uri, lambda ds: "missing-arg" not in codes(ds))
    assert "missing-arg" not in codes(diags)


async def test_add_all_missing_args_at_once(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic.launch"
    text = path.read_text().replace('  <arg name="Random"/>\n', "").replace('  <arg name="Teleop"/>\n', "")
    uri = open_doc(client, path, text)
    diags = await diagnostics(client, uri, lambda ds: codes(ds).count("missing-arg") == 2)
    missing = [d for d in diags if d.code == "missing-arg"]
    assert len(missing) == 2
    actions = await _actions(client, uri, missing[0])
    both = [a for a in _fixes(actions) if a.title.startswith("Add all 2 missing")]
    assert both, [a.title for a in actions]
    new_text = apply_text_edits(text, both[0].edit.changes[uri])
    _change_all(client, uri, new_text, 2)
    diags = await diagnostics(client, uri, lambda ds: "missing-arg" not in codes(ds))
    assert "missing-arg" not in codes(diags)



async def test_undeclared_arg_close_to_a_feature_is_renamed_by_a_quick_fix(client: LanguageClient):
    """"did you mean `Random`?" comes with the quick fix that says it, for the first undeclared
    arg of a value and for the later ones (one problem each); applied, the errors are gone."""
    path = client.ws / "src/turtlerand/launch/generic.launch"
    text = path.read_text().replace('  <param name="vel" type="double" value="0.5" if="$(arg Vel)"/>\n',
                                    '  <param name="vel" type="double" value="0.5" if="$(arg Vel)"/>\n'
                                    '  <param name="who" value="$(arg randm) $(arg  Vel) $(arg telop)" if="$(arg Vel)"/>\n')
    assert "$(arg randm)" in text
    uri = open_doc(client, path, text)
    diags = await diagnostics(client, uri, lambda ds: codes(ds).count("undefined-arg") == 2)
    undefined = sorted((d for d in diags if d.code == "undefined-arg"), key=lambda d: d.range.start.character)
    assert "did you mean `Random`" in undefined[0].message and "did you mean `Teleop`" in undefined[1].message
    edits = []
    for d, name in zip(undefined, ("Random", "Teleop")):
        fix = [a for a in _fixes(await _actions(client, uri, d)) if a.title == f"Change to `{name}`"]
        assert fix and fix[0].is_preferred, [a.title for a in await _actions(client, uri, d)]
        edits += fix[0].edit.changes[uri]
    text = apply_text_edits(text, edits)
    assert '"$(arg Random) $(arg  Vel) $(arg Teleop)"' in text
    _change_all(client, uri, text, 2)
    diags = await diagnostics(client, uri, lambda ds: "undefined-arg" not in codes(ds))
    assert "undefined-arg" not in codes(diags)

EXPECTED_NODES = {
    frozenset(): ["/Turtlesim"],
    frozenset({"Teleop"}): ["/Teleop", "/Turtlesim"],
    frozenset({"Random"}): ["/Random", "/Turtlesim"],
    frozenset({"Teleop", "Random"}): ["/Multiplexer", "/Random", "/Teleop", "/Turtlesim"],
}


# loads each file with Debian's real roslaunch (run by /usr/bin/python3) and prints the nodes
ROSLAUNCH = r"""
import io, json, os, sys
jobs = json.load(sys.stdin)
os.environ["ROS_PACKAGE_PATH"] = jobs[0]["package_path"]
from roslaunch.config import ROSLaunchConfig
from roslaunch.xmlloader import XmlLoader
out = []
for job in jobs:
    cfg = ROSLaunchConfig()
    saved = sys.stdout, sys.stderr
    sys.stdout = sys.stderr = io.StringIO()
    try:
        XmlLoader().load(job["file"], cfg, argv=["roslaunch", job["file"]], verbose=False)
        out.append({"ok": True, "nodes": sorted(n.namespace + n.name for n in cfg.nodes)})
    except BaseException as e:
        out.append({"ok": False, "error": type(e).__name__, "message": str(e)[:500]})
    finally:
        sys.stdout, sys.stderr = saved
print(json.dumps(out))
"""


async def test_generate_turtlerand_configurations(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic.launch"
    uri = open_doc(client, path)
    actions = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=types.TextDocumentIdentifier(uri=uri),
        range=types.Range(start=types.Position(line=0, character=0), end=types.Position(line=0, character=0)),
        context=types.CodeActionContext(diagnostics=[])))
    gen = [a for a in actions if isinstance(a, types.CodeAction) and a.data
           and a.data.get("tvl-lsp.resolve") == "generate" and a.data["args"].get("mode") == "all"]
    assert gen, actions
    resolved = await client.code_action_resolve_async(gen[0])
    from server_helpers import apply_workspace_edit
    files = sorted(apply_workspace_edit(resolved.edit))
    assert len(files) == 4 and all(f.is_file() for f in files)
    assert all(f.parent == client.ws / "src/turtlerand/configs" for f in files)
    texts = [f.read_text() for f in files]
    assert all('<include file="$(find turtlerand)/launch/generic.launch">' in t for t in texts)
    # deterministic: the same request names the same files
    res = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.generateConfigurations", arguments=[gen[0].data["args"]]))
    assert sorted(Path(f) for f in res["files"]) == files and res["applied"]
    if not have_roslaunch():
        pytest.skip(ROSLAUNCH_MISSING)
    jobs = [{"file": str(f), "args": {}, "package_path": str(client.ws / "src")} for f in files]
    out = subprocess.run(["/usr/bin/python3", "-c", ROSLAUNCH],
                         input=json.dumps(jobs), capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    results = json.loads(out.stdout)
    for f, t, r in zip(files, texts, results):
        assert r["ok"], (f, r)
        on = frozenset(n for n in ("Teleop", "Random") if f'name="{n}" value="true"' in t)
        assert r["nodes"] == EXPECTED_NODES[on], (f, r)


async def test_generation_refuses_a_folder_outside_the_workspace(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic.launch"
    uri = open_doc(client, path)
    with pytest.raises(Exception) as e:
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.generateConfigurations",
            arguments=[{"uri": uri, "mode": "all", "folder": "../../../../outside"}]))
    assert "outside the workspace" in str(e.value)
    assert not (client.ws.parent / "outside").exists()


async def test_configurator_commands(client: LanguageClient):
    path = client.ws / "src/scout/launch/generic.tvl"
    uri = open_doc(client, path)

    async def run(cmd, *args):
        return await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command=cmd, arguments=[uri, *args]))
    c = await run("tvl-lsp.count")
    assert c["total"] == 1152 and c["remaining"] == 1152
    r = await run("tvl-lsp.include", "Slam")
    assert r["forced"].get("Planner") is True and r["forced"].get("Laser") is True
    assert r["conflict"] is None and r["remaining"] == 288
    r2 = await run("tvl-lsp.exclude", "Laser")
    assert r2["conflict"] is not None and set(r2["conflict"]) == {"Slam", "Laser"}
    r3 = await run("tvl-lsp.reset", "Laser")
    assert r3["conflict"] is None and r3["remaining"] == r["remaining"]
    lst = await run("tvl-lsp.listProducts", 5)
    assert len(lst["products"]) == 5 and all("Slam" in p for p in lst["products"])
    r4 = await run("tvl-lsp.reset")
    assert r4["remaining"] == 1152


async def test_tvl_quick_fixes_for_grammar_and_unknown_names(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic_alt.tvl"
    text = path.read_text().replace("Turtlesim {", "Turtlesim {\n  Telop -> Random;\n  constant int k 3;")
    uri = open_doc(client, path, text)
    want = {"infix-and-or", "unknown-name", "constant-keyword"}
    diags = await diagnostics(client, uri, lambda ds: want <= set(codes(ds)))
    fixed = text
    for code, title in (("infix-and-or", "Replace 'and' with '&&'"), ("unknown-name", "Change to 'Teleop'"),
                        ("constant-keyword", "Replace 'constant' with 'const'")):
        d = [d for d in diags if d.code == code][0]
        acts = [a for a in _fixes(await _actions(client, uri, d)) if a.title == title]
        assert acts, (code, [a.title for a in await _actions(client, uri, d)])
        assert acts[0].diagnostics[0].code == code
        fixed = apply_text_edits(fixed, acts[0].edit.changes[uri])
    assert "Teleop -> Random;" in fixed and "const int k 3;" in fixed and "&& Random" in fixed


async def test_diagnostics_carry_the_version_and_stale_results_are_dropped(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic_split.tvl"
    text = path.read_text()
    uri = open_doc(client, path, text)
    for v in range(2, 30):
        _change_all(client, uri, text + "\n" * (v % 3) + ("Oops" if v % 2 else ""), v)
    final = text + "\n" * (30 % 3) + "Oops"
    _change_all(client, uri, final, 30)
    diags = await diagnostics(client, uri, lambda ds: "syntax-error" in codes(ds))
    assert "syntax-error" in codes(diags)
    _change_all(client, uri, text, 31)
    diags = await diagnostics(client, uri, lambda ds: "syntax-error" not in codes(ds))
    assert "syntax-error" not in codes(diags)


async def test_generate_every_completion_of_the_configurators_decisions(client: LanguageClient):
    path = client.ws / "src/turtlerand/launch/generic.launch"
    uri = open_doc(client, path)
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.include", arguments=[uri, "Teleop"]))
    try:
        res = await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.generateConfigurations",
            arguments=[{"uri": uri, "mode": "completions", "folder": "completions"}]))
        files = sorted(Path(f).name for f in res["files"])
        assert files == ["generic_turtlesim-teleop-random-vel-multiplexer.launch", "generic_turtlesim-teleop.launch"]
        assert all((client.ws / "src/turtlerand/completions" / f).is_file() for f in files)
        one = await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.generateConfigurations", arguments=[{"uri": uri, "mode": "one", "folder": "one"}]))
        assert [Path(f).name for f in one["files"]] == ["generic_turtlesim-teleop.launch"]
    finally:
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.reset", arguments=[uri]))
