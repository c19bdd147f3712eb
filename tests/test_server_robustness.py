"""The server never fails, stalls or dies because of what the client sends (issue 12, the
server side): lone surrogates, invalid params, requests before ``initialize``, ``exit``
without ``shutdown``, broken framing; and ``generate`` never overwrites or writes outside
the workspace.  Raw stdio (tests/lsp_raw.py) where a client library could not send the bytes;
each case's input is under tests/data/robustness/."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from lsp_raw import RawServer, frame
from testenv import REPO

DATA = REPO / "tests/data/robustness"


@pytest.fixture
def server(tmp_path):
    s = RawServer(cwd=str(tmp_path))
    yield s
    s.close()


def _hover(uri: str, line: int = 0, character: int = 0) -> dict:
    return {"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}


def _open(s: RawServer, uri: str, text: str, lang: str = "xml") -> None:
    s.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": lang, "version": 1, "text": text}})


def _utf16(s: str) -> int:
    return len(s.encode("utf-16-le", "surrogatepass")) // 2


# ------------------------------------------------------------------ lifecycle

def test_a_request_before_initialize_is_refused_with_server_not_initialized(server):
    rid = server.request("textDocument/hover", _hover("file:///x.tvl"))
    rep = server.response(rid, 10)
    assert rep is not None and rep.get("error", {}).get("code") == -32002, rep
    assert server.initialize() is not None  # and the server still initialises afterwards


def test_exit_without_shutdown_exits_with_code_1(server, tmp_path):
    server.initialize(tmp_path)
    server.notify("exit", None)
    assert server.proc.wait(15) == 1


def test_exit_after_shutdown_exits_with_code_0(server, tmp_path):
    server.initialize(tmp_path)
    rid = server.request("shutdown", None)
    assert server.response(rid, 10) is not None
    # a request after shutdown gets an error, not silence
    rid = server.request("textDocument/hover", _hover("file:///x.tvl"))
    rep = server.response(rid, 10)
    assert rep is not None and rep["error"]["code"] == -32600
    server.notify("exit", None)
    assert server.proc.wait(15) == 0


# ------------------------------------------------------------------ invalid params

def test_invalid_params_are_answered_with_invalid_params(server, tmp_path):
    server.initialize(tmp_path)
    uri = (tmp_path / "m.tvl").as_uri()
    _open(server, uri, "root A { group allOf { B, C } }\n", "tvl")
    cases = json.loads((DATA / "invalid_params.json").read_text().replace("URI", uri))
    ids = [server.request(c["method"], c["params"]) for c in cases]
    for c, rid in zip(cases, ids):
        rep = server.response(rid, 10)
        assert rep is not None, f"no response to {c}"
        assert rep.get("error", {}).get("code") == -32602, (c, rep)
    rid = server.request("textDocument/hover", _hover(uri, 0, 24))
    assert "result" in server.response(rid, 10)  # the server goes on


# ------------------------------------------------------------------ lone surrogates

METHODS = ["textDocument/hover", "textDocument/definition", "textDocument/references",
           "textDocument/documentSymbol", "textDocument/foldingRange", "textDocument/semanticTokens/full",
           "textDocument/completion", "textDocument/codeAction", "textDocument/codeLens",
           "textDocument/prepareRename", "textDocument/diagnostic"]


def _params(method: str, uri: str, line: int, ch: int) -> dict:
    p: dict = {"textDocument": {"uri": uri}}
    if method in ("textDocument/documentSymbol", "textDocument/foldingRange", "textDocument/semanticTokens/full",
                  "textDocument/codeLens", "textDocument/diagnostic"):
        return p
    if method == "textDocument/codeAction":
        p["range"] = {"start": {"line": 0, "character": 0}, "end": {"line": line, "character": ch}}
        p["context"] = {"diagnostics": []}
        return p
    p["position"] = {"line": line, "character": ch}
    if method == "textDocument/references":
        p["context"] = {"includeDeclaration": True}
    return p


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
def test_lone_surrogates_never_make_a_request_fail_and_positions_stay_exact(server, tmp_path):
    server.initialize(tmp_path)
    text = json.loads((DATA / "surrogate.launch.json").read_text())["text"]
    assert "\ud800" in text
    uri = (tmp_path / "s.launch").as_uri()
    _open(server, uri, text)
    lines = text.split("\n")
    for method in METHODS:
        for line in range(len(lines)):
            for ch in range(0, _utf16(lines[line]) + 1, 6):
                rid = server.request(method, _params(method, uri, line, ch))
                rep = server.response(rid, 20)
                assert rep is not None, (method, line, ch)
                assert "error" not in rep, (method, line, ch, rep)
    # positions after the surrogate are counted in UTF-16 units as the client counts them:
    # the definition of `use_b` in line 3 (after a lone surrogate) is its declaration
    node = lines[3]
    col = _utf16(node[:node.index("use_b")])
    rid = server.request("textDocument/definition", _params("textDocument/definition", uri, 3, col + 1))
    locs = server.response(rid, 20)["result"]
    assert locs, "no definition"
    rng = locs[0]["range"] if "range" in locs[0] else locs[0]["targetSelectionRange"]
    decl = lines[rng["start"]["line"]]
    a, b = rng["start"]["character"], rng["end"]["character"]
    units = decl.encode("utf-16-le", "surrogatepass")
    assert units[2 * a: 2 * b].decode("utf-16-le", "surrogatepass") == "use_b"


# ------------------------------------------------------------------ framing

def _req(i: int, uri: str = "file:///nowhere.tvl") -> dict:
    return {"jsonrpc": "2.0", "id": i, "method": "textDocument/hover", "params": _hover(uri)}


def test_a_short_content_length_is_recovered(server, tmp_path):
    server.initialize(tmp_path)
    server.send(frame(_req(101), length=20))
    server.send(frame(_req(102)))
    assert server.response(101, 10) is not None
    assert server.response(102, 10) is not None


def test_a_long_content_length_does_not_swallow_the_next_message(server, tmp_path):
    server.initialize(tmp_path)
    server.send(frame(_req(103), length=500))
    assert server.response(103, 10) is not None  # answered although the rest never comes
    server.send(frame(_req(104), length=5000))
    server.send(frame(_req(105)))
    assert server.response(104, 10) is not None and server.response(105, 10) is not None


def test_a_huge_content_length_neither_kills_nor_blocks_the_server(server, tmp_path):
    server.initialize(tmp_path)
    server.send(b"Content-Length: 99999999999999\r\n\r\n" + json.dumps(_req(106)).encode())
    assert server.response(106, 10) is not None
    server.send(b"Content-Length: 99999999999999\r\n\r\n{\"jsonrpc\": \"2.0\", ")
    time.sleep(0.5)
    server.send(frame(_req(107)))
    assert server.response(107, 10) is not None
    assert server.proc.poll() is None
    assert b"Traceback" not in server.stderr
    assert b"Content-Length 99999999999999" in _stderr_after_close(server)


def _stderr_after_close(server) -> bytes:
    server.close()
    for _ in range(50):
        if server.stderr:
            break
        time.sleep(0.1)
    return server.stderr


def test_garbage_is_skipped_and_a_body_that_is_not_json_gets_a_parse_error(server, tmp_path):
    server.initialize(tmp_path)
    server.send((DATA / "framing.txt").read_bytes())
    server.send(frame(b"{not json"))
    server.send(frame(b"[" * 100000))
    server.send(frame(b"\xff\xfe\x00"))
    server.send(frame(b"[1, 2]"))
    server.send(frame(_req(108)))
    assert server.response(108, 10) is not None
    errors = [m["error"]["code"] for m in server.messages if m.get("id") is None and "error" in m]
    assert errors == [-32700, -32700, -32700, -32600], errors
    assert server.proc.poll() is None


# ------------------------------------------------------------------ long analysis

def test_hover_and_definition_answer_within_2_s_during_a_long_analysis(server, tmp_path):
    """A 10,000-node launch file takes many seconds to analyse: requests answer from the last
    result (or empty) instead of waiting for it."""
    server.initialize(tmp_path)
    text = ('<launch>\n  <arg name="use_b" default="true"/>\n' + "".join(
        f'  <node pkg="a" type="b" name="n{i}" if="$(arg use_b)"><param name="p" value="{i}"/></node>\n'
        for i in range(10000)) + "</launch>\n")
    uri = (tmp_path / "big.launch").as_uri()
    _open(server, uri, text)
    for version, method in enumerate(["textDocument/hover", "textDocument/definition", "textDocument/hover"], 2):
        t = time.monotonic()
        rid = server.request(method, _hover(uri, 2, 60))
        rep = server.response(rid, 30)
        assert rep is not None and "error" not in rep, rep
        assert time.monotonic() - t < 2.0, (method, time.monotonic() - t)
        server.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": [
            {"range": {"start": {"line": 3, "character": 0}, "end": {"line": 3, "character": 0}}, "text": " "}]})


# ------------------------------------------------------------------ deliberate errors, stale decisions

@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
def test_a_deliberate_error_answer_is_not_logged_as_a_crash(server, tmp_path):
    """Found by bench/bench_server_fuzz.py: every -32602 a handler raises on purpose (nothing to
    rename, an invalid new name, an unknown command) left a traceback on stderr, as a crash
    does; the fuzz judge counts a traceback as an internal error."""
    server.initialize(tmp_path)
    uri = (tmp_path / "m.tvl").as_uri()
    _open(server, uri, "root A { group allOf { B, C } }\n", "tvl")
    asks = [("textDocument/rename", {**_hover(uri, 0, 1), "newName": "X"}),          # on `root`
            ("textDocument/rename", {**_hover(uri, 0, 23), "newName": "é"}),         # on `B`
            ("workspace/executeCommand", {"command": "tvl-lsp.noSuchCommand", "arguments": []}),
            ("workspace/executeCommand", {"command": "tvl-lsp.include", "arguments": [uri]})]
    for method, params in asks:
        rep = server.response(server.request(method, params), 20)
        assert rep is not None and rep.get("error", {}).get("code") == -32602, (method, params, rep)
    err = _stderr_after_close(server)
    assert b"Traceback" not in err, err.decode(errors="replace")


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
def test_decisions_on_features_an_edit_removed_are_refused_not_an_internal_error(server, tmp_path):
    """Found by bench/bench_server_fuzz.py: the configurator keeps its decisions while the model
    is edited; once a decided feature was gone, listing products or generating configurations
    failed inside the worker (KeyError: unknown feature) instead of saying so."""
    server.initialize(tmp_path)
    path = tmp_path / "m.tvl"
    path.write_text("root A { group someOf { B, C } }\n")
    uri = path.as_uri()
    _open(server, uri, path.read_text(), "tvl")
    rep = server.response(server.request("workspace/executeCommand",
                                         {"command": "tvl-lsp.include", "arguments": [uri, "B"]}), 30)
    assert "result" in rep and rep["result"]["decisions"] == {"B": True}, rep
    server.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 2}, "contentChanges": [
        {"range": {"start": {"line": 0, "character": 24}, "end": {"line": 0, "character": 25}}, "text": "D"}]})
    rep = server.response(server.request("workspace/executeCommand",
                                         {"command": "tvl-lsp.listProducts", "arguments": [uri, 5]}), 30)
    assert rep is not None and rep.get("error", {}).get("code") == -32602, rep
    assert "unknown feature(s): B" in rep["error"]["message"], rep
    rep = server.response(server.request("workspace/executeCommand", {"command": "tvl-lsp.reset", "arguments": [uri]}), 30)
    assert "result" in rep and rep["result"]["decisions"] == {}, rep
    err = _stderr_after_close(server)
    assert b"Traceback" not in err, err.decode(errors="replace")


def test_ids_of_the_wrong_type_get_invalid_request_and_deep_messages_their_answer(server, tmp_path):
    """Found by bench/bench_server_fuzz.py: a request whose id is an object or an array made the
    protocol fail (unhashable id, a traceback, no answer); one nested deeper than the JSON
    parser goes was answered with a parse error of id null, so its sender waited forever."""
    server.initialize(tmp_path)
    uri = (tmp_path / "m.tvl").as_uri()
    for bad in ({"a": 1}, [1], 1.5, True):
        server.send(frame({"jsonrpc": "2.0", "id": bad, "method": "textDocument/hover", "params": _hover(uri)}))
    for depth in (5000, 100000):
        rid = 700 + depth
        server.send(frame(b'{"jsonrpc": "2.0", "id": %d, "method": "textDocument/hover", "params": {"x": %s0%s}}'
                          % (rid, b"[" * depth, b"]" * depth)))
        rep = server.response(rid, 10)
        assert rep is not None and rep["error"]["code"] == -32600, rep
    rid = server.request("textDocument/hover", _hover(uri))
    assert server.response(rid, 10) is not None
    nulls = [m["error"]["code"] for m in server.messages if m.get("id") is None and "error" in m]
    assert nulls == [-32600] * 4, nulls
    err = _stderr_after_close(server)
    assert b"Traceback" not in err, err.decode(errors="replace")


def test_finished_notification_handlers_are_forgotten(server, tmp_path):
    """Found by bench/bench_server_fuzz.py: pygls kept the future of every notification
    (each didChange) for good; the server forgets them once finished."""
    server.initialize(tmp_path)
    uri = (tmp_path / "m.tvl").as_uri()
    _open(server, uri, "root A { group allOf { B, C } }\n", "tvl")
    for v in range(2, 302):
        server.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": v}, "contentChanges": [
            {"range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}}, "text": " "}]})
    rid = server.request("workspace/executeCommand", {"command": "tvl-lsp.documentState", "arguments": [uri]})
    state = server.response(rid, 20)["result"]
    assert state["version"] == 301
    assert state["handlers"] < 20, state["handlers"]


def test_a_pull_answers_at_once_when_the_client_accepts_refreshes(server, tmp_path):
    """Found by bench/bench_server_fuzz.py: ``textDocument/diagnostic`` waited for the
    solver-backed check (up to its budget, 11 s) while requests are to be answered within
    2 s; a client that accepts ``workspace/diagnostic/refresh`` gets the latest results at
    once and a refresh when the check is done.  (A 3 s debounce stands for a slow check.)"""
    rid = server.request("initialize", {
        "processId": None, "rootUri": tmp_path.as_uri(), "initializationOptions": {"debounce": 3},
        "capabilities": {"textDocument": {"diagnostic": {}}, "workspace": {"diagnostics": {"refreshSupport": True}}}})
    assert "result" in server.response(rid, 30)
    server.notify("initialized", {})
    uri = (tmp_path / "m.tvl").as_uri()
    _open(server, uri, "root A { group allOf { B, B } }\n", "tvl")
    t = time.monotonic()
    rep = server.response(server.request("textDocument/diagnostic", {"textDocument": {"uri": uri}}), 30)
    assert rep is not None and "result" in rep, rep
    assert time.monotonic() - t < 2.0
    end = time.monotonic() + 20
    while time.monotonic() < end and not any(m.get("method") == "workspace/diagnostic/refresh" for m in server.messages):
        time.sleep(0.1)
    assert any(m.get("method") == "workspace/diagnostic/refresh" for m in server.messages)


def test_a_client_that_pulls_without_refreshes_gets_pushed_diagnostics(server, tmp_path):
    """Neovim 0.10 and 0.11 pull diagnostics but cannot be asked to pull again: their pulls
    waited for the solver-backed check (up to its budget, 11 s on a hard model) while requests
    are to be answered within 2 s.  Such a client is not offered pull diagnostics; they are
    pushed, and a pull it sends all the same is answered at once."""
    rid = server.request("initialize", {
        "processId": None, "rootUri": tmp_path.as_uri(), "initializationOptions": {"debounce": 3},
        "capabilities": {"textDocument": {"diagnostic": {"dynamicRegistration": False}}}})
    caps = server.response(rid, 30)["result"]["capabilities"]
    assert caps.get("diagnosticProvider") is None
    server.notify("initialized", {})
    uri = (tmp_path / "m.tvl").as_uri()
    _open(server, uri, "root A { group allOf { B, B } }\n", "tvl")
    t = time.monotonic()
    rep = server.response(server.request("textDocument/diagnostic", {"textDocument": {"uri": uri}}), 30)
    assert rep is not None and "result" in rep and time.monotonic() - t < 2.0, rep
    end = time.monotonic() + 20
    pushed = []
    while time.monotonic() < end and not pushed:
        pushed = [m for m in server.messages if m.get("method") == "textDocument/publishDiagnostics"
                  and m["params"]["uri"] == uri and m["params"]["diagnostics"]]
        time.sleep(0.1)
    assert pushed and "duplicate-feature" in {d.get("code") for d in pushed[-1]["params"]["diagnostics"]}, pushed


def test_a_client_that_accepts_refreshes_is_offered_pull_diagnostics(server, tmp_path):
    rid = server.request("initialize", {
        "processId": None, "rootUri": tmp_path.as_uri(),
        "capabilities": {"textDocument": {"diagnostic": {}}, "workspace": {"diagnostics": {"refreshSupport": True}}}})
    caps = server.response(rid, 30)["result"]["capabilities"]
    assert caps.get("diagnosticProvider", {}).get("identifier") == "tvl-lsp"
