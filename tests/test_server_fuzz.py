"""A bounded fuzz of the language server (issue 12): random edits (with lone surrogates,
non-ASCII text, line breaks of every kind) and requests (valid and invalid positions) on a
TVL model and a launch file, through raw stdio.  Every request is answered, never with
-32603, and every range in a result lies inside the document as the client sees it.

The default run has a fixed seed (Hypothesis ``derandomize``) and ~60 sequences; the long run
is behind the ``fuzz`` marker: ``pytest -m fuzz tests/test_server_fuzz.py``.

The campaign of issue 12's judge (bench/bench_server_fuzz.py: the real ``tvl-lsp`` on stdio over
the repository's examples, random edits, requests and malformed messages) runs here too: a
short one in the default suite, the judged size behind ``-m fuzz``
(``TVL_LSP_FUZZ_EDITS``, default 1000, and ``TVL_LSP_FUZZ_SEEDS``, default 3)::

    TVL_LSP_FUZZ_EDITS=1000 .venv/bin/pytest -m fuzz tests/test_server_fuzz.py -k campaign"""

from __future__ import annotations

import itertools

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from lsp_raw import RawServer

SEEDS = {
    "tvl": "root Robot {\n  group someOf { Nav, Arm, Cam }\n  Arm -> Cam;\n}\n",
    "launch": '<launch>\n  <arg name="Nav" default="true"/>\n  <arg name="Cam" default="false"/>\n'
              '  <node pkg="a" type="b" name="n" if="$(arg Nav)"/>\n  <include file="$(find x)/y.launch"/>\n</launch>\n',
}
ALPHABET = st.sampled_from(["a", "B", " ", "{", "}", "<", ">", "/", '"', "=", "$(arg ", ")", "\n", "\r\n", "\r",
                            "é", "\ud800", "\udfff", "group", "root", "allOf", "->", ";", "<node ", "if="])
METHODS = ["textDocument/hover", "textDocument/definition", "textDocument/references", "textDocument/completion",
           "textDocument/documentSymbol", "textDocument/foldingRange", "textDocument/semanticTokens/full",
           "textDocument/codeAction", "textDocument/codeLens", "textDocument/prepareRename",
           "textDocument/formatting", "textDocument/diagnostic", "textDocument/documentHighlight"]


def lines_of(text: str) -> list[str]:
    import re
    return re.split(r"\r\n|\r|\n", text)


def u16(s: str) -> int:
    return len(s.encode("utf-16-le", "surrogatepass")) // 2


def offset(text: str, line: int, ch: int) -> int:
    """Code-point offset of a (clamped) UTF-16 position, as the server applies it."""
    import re
    starts = [0] + [m.end() for m in re.finditer(r"\r\n|\r|\n", text)]
    line = min(line, len(starts) - 1)
    ls = lines_of(text)[line]
    units, i = 0, 0
    while i < len(ls) and units < ch:
        units += u16(ls[i])
        i += 1
    return starts[line] + i


def ranges(value):
    if isinstance(value, dict):
        if set(value) >= {"start", "end"} and isinstance(value["start"], dict) and "line" in value["start"]:
            yield value
        for v in value.values():
            yield from ranges(v)
    elif isinstance(value, list):
        for v in value:
            yield from ranges(v)


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    root = tmp_path_factory.mktemp("fuzz")
    s = RawServer(cwd=str(root))
    s.initialize(root, {"debounce": 0.05, "count": {"timeBudget": 2}})
    s.root = root
    s.counter = itertools.count()
    yield s
    rid = s.request("shutdown", None)
    s.response(rid, 10)
    s.notify("exit", None)
    assert s.proc.wait(20) == 0


step = st.one_of(
    st.tuples(st.just("edit"), st.integers(0, 12), st.integers(0, 40), st.integers(0, 3), st.integers(0, 40),
              st.lists(ALPHABET, max_size=4).map("".join)),
    st.tuples(st.just("request"), st.sampled_from(METHODS), st.integers(0, 12), st.integers(0, 60)),
    st.tuples(st.just("bad"), st.sampled_from(METHODS[:4]),
              st.sampled_from([-1, 2 ** 31, 2 ** 40, None, "x", 1.5e300])),
)


def run_sequence(server: RawServer, kind: str, steps) -> None:
    n = next(server.counter)
    path = server.root / (f"f{n}.tvl" if kind == "tvl" else f"f{n}.launch")
    uri = path.as_uri()
    text = SEEDS[kind]
    version = 1
    server.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": kind, "version": 1,
                                                            "text": text}})
    try:
        for st_ in steps:
            if st_[0] == "edit":
                _, line, ch, dl, ch2, new = st_
                a = offset(text, line, ch)
                b = offset(text, line + dl, ch2)
                a, b = min(a, b), max(a, b)
                ls = lines_of(text[:a])
                start = {"line": len(ls) - 1, "character": u16(ls[-1])}
                le = lines_of(text[:b])
                end = {"line": len(le) - 1, "character": u16(le[-1])}
                text = text[:a] + new + text[b:]
                version += 1
                server.notify("textDocument/didChange", {
                    "textDocument": {"uri": uri, "version": version},
                    "contentChanges": [{"range": {"start": start, "end": end}, "text": new}]})
                continue
            if st_[0] == "bad":
                _, method, value = st_
                rid = server.request(method, {"textDocument": {"uri": uri},
                                              "position": {"line": value, "character": 0},
                                              "context": {"includeDeclaration": True}})
                rep = server.response(rid, 20)
                assert rep is not None, ("no response", method, value)
                assert rep.get("error", {}).get("code") == -32602, (method, value, rep)
                continue
            _, method, line, ch = st_
            p: dict = {"textDocument": {"uri": uri}, "position": {"line": line, "character": ch}}
            if method == "textDocument/references":
                p["context"] = {"includeDeclaration": True}
            elif method == "textDocument/codeAction":
                p = {"textDocument": {"uri": uri}, "context": {"diagnostics": []},
                     "range": {"start": {"line": 0, "character": 0}, "end": {"line": line, "character": ch}}}
            elif method == "textDocument/formatting":
                p = {"textDocument": {"uri": uri}, "options": {"tabSize": 2, "insertSpaces": True}}
            elif method in ("textDocument/documentSymbol", "textDocument/foldingRange",
                            "textDocument/semanticTokens/full", "textDocument/codeLens", "textDocument/diagnostic"):
                p = {"textDocument": {"uri": uri}}
            rid = server.request(method, p)
            rep = server.response(rid, 20)
            assert rep is not None, ("no response", method, text)
            assert rep.get("error", {}).get("code") != -32603, (method, rep, text)
            if "error" in rep:
                continue
            if method in ("textDocument/definition", "textDocument/references"):
                results = [r for r in (rep["result"] or []) if r.get("uri", uri) == uri]
            elif method == "textDocument/diagnostic":
                results = rep["result"]["items"]
            elif method in ("textDocument/codeAction", "textDocument/codeLens"):
                continue  # (edits may name other files)
            else:
                results = rep["result"]
            cur = lines_of(text)
            for r in ranges(results):
                for pos in (r["start"], r["end"]):
                    assert 0 <= pos["line"] < len(cur), (method, r, text)
                    assert 0 <= pos["character"] <= u16(cur[pos["line"]]), (method, r, text)
    finally:
        server.notify("textDocument/didClose", {"textDocument": {"uri": uri}})


SHORT = settings(max_examples=100, derandomize=True, deadline=None, database=None,
                 suppress_health_check=list(HealthCheck))
LONG = settings(max_examples=600, deadline=None, database=None, suppress_health_check=list(HealthCheck))


@pytest.mark.parametrize("kind", ["tvl", "launch"])
@SHORT
@given(steps=st.lists(step, min_size=1, max_size=10))
def test_fuzzed_sessions_answer_every_request_with_valid_ranges(server, kind, steps):
    run_sequence(server, kind, steps)


@pytest.mark.fuzz
@pytest.mark.parametrize("kind", ["tvl", "launch"])
@LONG
@given(steps=st.lists(step, min_size=1, max_size=30))
def test_fuzzed_sessions_long_run(server, kind, steps):
    run_sequence(server, kind, steps)


# ------------------------------------------------------------------ the judged campaign

def _campaign():
    import sys
    from testenv import REPO
    sys.path.insert(0, str(REPO / "bench"))
    import bench_server_fuzz
    return bench_server_fuzz


def _check_campaign(seed: int, edits: int, strict_latency: bool) -> dict:
    import os
    B = _campaign()
    res = B.run_campaign(seed, edits)
    s = B.summary(res)
    failures = [f for f in s["failures"] if not f.startswith(f"over {B.LIMIT_S} s")]
    assert not failures, (s, failures[:10])
    assert s["edits"] == edits and s["requests"] >= edits // 4, s
    # a request over 2 s on a loaded machine may be the load (bench/README.md): the default
    # suite asserts the latency on a machine with a core to spare, the opt-in run always
    busy = os.getloadavg()[0] >= (os.cpu_count() or 1)
    if strict_latency or not busy:
        assert s["over_2s"] == 0, (s["over_2s_methods"], [f for f in s["failures"] if f.startswith("over")][:10],
                                   "load average", s["load"])
    return s


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
def test_a_short_campaign_of_edits_requests_and_malformed_messages():
    """150 edits (~20 s with the server's start): the fuzz judge's thresholds."""
    _check_campaign(seed=12, edits=150, strict_latency=False)


@pytest.mark.fuzz
def test_the_judged_campaign():
    import os
    edits = int(os.environ.get("TVL_LSP_FUZZ_EDITS", "1000"))
    seeds = int(os.environ.get("TVL_LSP_FUZZ_SEEDS", "3"))
    first = int(os.environ.get("TVL_LSP_FUZZ_SEED", "1"))
    for seed in range(first, first + seeds):
        _check_campaign(seed, edits, strict_latency=True)
