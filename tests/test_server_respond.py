"""The server answers from what it knows at once (issue #28: 14, 15): a launch file's quick pass
(its syntax and the checks that need no solver) is published before the solver-backed check,
the findings of the last full check move with the edits made since (published, and answering
code actions, while the next check is pending), and a count that ran out of its budget is
retried in the background with a longer one.

None of these tests measures time: a pending check is one whose debounce (60 s) outlasts the
test; ``bench/bench_server_respond.py`` measures the latencies."""

from __future__ import annotations

import asyncio
import concurrent.futures as cf
import shutil
from pathlib import Path
from types import SimpleNamespace

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from server_helpers import CONFIG, PROFILES, apply_text_edits, install_client_handlers, open_doc, start
from tvl_lsp.base.diagnostics import Diagnostic, Fix, Related, Severity, TextEdit
from tvl_lsp.base.text import LineIndex, Pos, Span
from tvl_lsp.lsp import checks
from tvl_lsp.lsp.documents import Document, DocumentStore, text_diff
from tvl_lsp.lsp.known import map_diagnostics, map_range
from tvl_lsp.lsp.scheduler import MAX_RETRY_BUDGET, RETRY_FACTOR, Scheduler
from tvl_lsp.lsp.workers import Workers
from tvl_lsp.project import facts as F

REPO = Path(__file__).resolve().parents[1]
RESPOND_WS = REPO / "tests" / "data" / "respond"
LAUNCH = "src/robot/launch/robot.launch"


# ------------------------------------------------------------------ moving findings with the edits

def test_map_range_moves_shifts_and_drops():
    # (start, end, inserted length) edits, code-point offsets in the text before each
    assert map_range(10, 15, [(0, 0, 3)]) == (13, 18)          # inserted before: moved
    assert map_range(10, 15, [(20, 22, 0)]) == (10, 15)        # after: unchanged
    assert map_range(10, 15, [(15, 15, 4)]) == (10, 15)        # typed right after it: unchanged
    assert map_range(10, 15, [(10, 10, 2)]) == (12, 17)        # typed right before it: moved
    assert map_range(10, 15, [(12, 12, 1)]) is None            # typed inside: gone
    assert map_range(10, 15, [(8, 11, 0)]) is None             # part of it deleted: gone
    assert map_range(10, 15, [(2, 6, 0), (0, 0, 1)]) == (7, 12)  # edits in order
    assert map_range(5, 5, [(2, 8, 1)]) is None                # an empty range in a replaced part


def test_findings_and_their_fixes_move_with_the_text():
    old = "line one\n<arg name=\"Camra\"/>\nline three $(arg Lidr)\n"
    p = "/w/a.launch"
    idx = LineIndex(old)

    def span_of(needle):
        i = old.index(needle)
        return idx.span(i, i + len(needle))
    rename = Diagnostic("unmatched-arg", Severity.WARNING, p, span_of("Camra"), "typo",
                        related=[Related(p, span_of("line one"), "see")],
                        fixes=[Fix("Rename", (TextEdit(p, span_of("Camra"), "Camera"),)),
                               Fix("Elsewhere", (TextEdit("/w/other.tvl", Span(Pos(0, 0), Pos(0, 1)), "x"),))])
    lidr = Diagnostic("undefined-arg", Severity.ERROR, p, span_of("Lidr"), "undeclared",
                      fixes=[Fix("Change", (TextEdit(p, span_of("Lidr"), "Lidar"),))])
    # a new first line, and a change inside "line one"
    new = "added\n" + old.replace("line one", "line 1")
    edits = [(0, 0, len("added\n")), (len("added\nline "), len("added\nline one"), 1)]
    got = map_diagnostics([rename, lidr], p, old, LineIndex(new), edits, other_ok=lambda q: q != "/w/other.tvl")
    nidx = LineIndex(new)
    assert [d.code for d in got] == ["unmatched-arg", "undefined-arg"]
    r, u = got
    assert new[nidx.offset(r.span.start):nidx.offset(r.span.end)] == "Camra"
    assert new[nidx.offset(u.span.start):nidx.offset(u.span.end)] == "Lidr"
    assert [f.title for f in r.fixes] == ["Rename"]  # the other file changed: its fix is gone
    assert r.related == []                            # "line one" was edited: its related is gone
    assert new[nidx.offset(u.fixes[0].edits[0].span.start):nidx.offset(u.fixes[0].edits[0].span.end)] == "Lidr"
    # typing inside a finding drops it
    new2 = old.replace("Lidr", "Lidxr")
    edits2 = [(old.index("Lidr") + 3, old.index("Lidr") + 3, 1)]
    assert [d.code for d in map_diagnostics([rename, lidr], p, old, LineIndex(new2), edits2)] == ["unmatched-arg"]


def test_a_document_remembers_its_edits_by_version():
    d = Document("file:///w/a.launch", "abc", 1)
    d.set_text("abXc", 2, [(2, 2, 1)])
    d.set_text("Xc", 3)  # a whole text: the change is found by comparing
    assert d.edits_since(3) == [] and d.edits_since(2) == [(0, 2, 0)]
    assert d.edits_since(1) == [(2, 2, 1), (0, 2, 0)]
    assert d.edits_since(0) is None and d.edits_since(None) is None
    assert text_diff("hello world", "hello brave world") == (6, 6, 6)
    assert text_diff("same", "same") == (4, 4, 0)


# ------------------------------------------------------------------ end to end

@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="function")
async def client(lsp_client: LanguageClient, request, tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(RESPOND_WS, ws)
    lsp_client.ws = ws
    lsp_client.profile = request.param
    install_client_handlers(lsp_client)
    yield
    await lsp_client.shutdown_session()


async def _state(client, uri):
    return await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.documentState", arguments=[uri]))


async def _until(pred, what: str, timeout: float = 60.0):
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while loop.time() < end:
        got = await pred()
        if got:
            return got
        await asyncio.sleep(0.1)
    raise AssertionError(f"never: {what}")


async def _known(client, uri):
    """The document's diagnostics as the client has them (pulled or pushed)."""
    if client.init_result.capabilities.diagnostic_provider is not None:
        rep = await client.text_document_diagnostic_async(types.DocumentDiagnosticParams(
            text_document=types.TextDocumentIdentifier(uri=uri)))
        return list(rep.items)
    return list(client.diagnostics.get(uri, []))


def _pos(text: str, needle: str) -> types.Position:
    i = text.index(needle)
    return types.Position(line=text.count("\n", 0, i), character=i - (text.rfind("\n", 0, i) + 1))


async def _actions_at(client, uri, pos):
    return await client.text_document_code_action_async(types.CodeActionParams(
        text_document=types.TextDocumentIdentifier(uri=uri), range=types.Range(start=pos, end=pos),
        context=types.CodeActionContext(diagnostics=[], trigger_kind=types.CodeActionTriggerKind.Automatic)))


async def test_quick_findings_come_before_the_solver_backed_check(client: LanguageClient):
    """A launch file's syntax and solver-free findings (an arg naming no feature, a feature
    without its arg) are published while its solver-backed check has not even started."""
    await start(client, client.profile, client.ws, {"debounce": 60})  # (no full check in this test)
    path = client.ws / LAUNCH
    uri = open_doc(client, path)

    async def quick():
        ds = await _known(client, uri)
        return {str(d.code) for d in ds} >= {"unmatched-arg", "missing-arg"} and ds
    ds = await _until(quick, "the quick pass's findings")
    st = await _state(client, uri)
    assert st["phase"] == "quick" and st["resultVersion"] == 1, st
    assert not {"dead-element", "undefined-arg"} & {str(d.code) for d in ds}  # (the solver's)
    # its quick fix is there already
    acts = await _actions_at(client, uri, _pos(path.read_text(), "Camra"))
    assert any(a.title == "Rename to `Camera`" for a in acts if isinstance(a, types.CodeAction))


async def test_code_actions_answer_from_the_last_check_while_the_next_is_pending(client: LanguageClient):
    """After an edit, the solver's findings of the last full check (here an undeclared
    ``$(arg Lidr)`` with its quick fix) move with the text: published for the new version and
    offered as code actions at once, while the check of the new text is still pending."""
    await start(client, client.profile, client.ws, {"debounce": 0.05})
    path = client.ws / LAUNCH
    text = path.read_text()
    uri = open_doc(client, path, text)

    async def full():
        st = await _state(client, uri)
        return st["phase"] == "full" and st["resultVersion"] == 1
    await _until(full, "the first full check")
    # from now on the next check waits for a minute of quiet
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"tvl-lsp": {"debounce": 60, "count": {"timeBudget": 20}}}))

    async def settled():
        return (await _state(client, uri))["debounce"] == 60
    await _until(settled, "the new settings taken")  # (before the edit)
    new_text = text.replace("<launch>\n", "<launch>\n  <!-- a line typed above -->\n", 1)
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
        content_changes=[types.TextDocumentContentChangePartial(
            range=types.Range(start=types.Position(line=1, character=0), end=types.Position(line=1, character=0)),
            text="  <!-- a line typed above -->\n")]))
    lidr = _pos(new_text, "$(arg Lidr)")

    async def moved():
        ds = await _known(client, uri)
        und = [d for d in ds if str(d.code) == "undefined-arg"]
        return und if und and und[0].range.start.line == lidr.line else None
    und = await _until(moved, "the undeclared arg moved to its new line")
    assert und[0].range.start.character == lidr.character
    acts = await _actions_at(client, uri, lidr)
    change = [a for a in acts if isinstance(a, types.CodeAction) and a.title == "Change to `Lidar`"]
    assert change, [a.title for a in acts]
    assert "$(arg Lidar)" in apply_text_edits(new_text, change[0].edit.changes[uri])
    st = await _state(client, uri)
    assert st["version"] == 2 and st["phase"] != "full", st  # (the check of version 2 is pending)
    # the solver-free findings of the new text are there too, and nothing was left behind
    ds = await _known(client, uri)
    assert sorted(str(d.code) for d in ds) == ["dead-element", "missing-arg", "undefined-arg", "unmatched-arg"]


# ------------------------------------------------------------------ a count that ran out of its budget

async def _settle(pred, what: str, timeout: float = 30.0):
    """Until ``pred()`` (polled: no test assumes how fast a machine runs)."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while not pred():
        if loop.time() > end:
            raise AssertionError(f"never: {what}")
        await asyncio.sleep(0.005)


class _Pool:
    """A process pool answering each call with the next of ``answers`` (a function of the
    call's arguments), recording the calls."""

    def __init__(self, answer):
        self.calls = []
        self.answer = answer

    def submit(self, fn, *args):
        self.calls.append((fn.__name__, args))
        fut = cf.Future()
        fut.set_result(self.answer(fn, args))
        return fut


class _Server(Scheduler, Workers):
    supports_progress = False
    epoch = 0

    def __init__(self, path: str, text: str, background):
        self._init_workers()
        self._init_scheduler()
        self.settings = SimpleNamespace(debounce=0.0, time_budget=2.0)
        self.docs = {"file://m": SimpleNamespace(version=1, text=text, path=path, kind=checks.file_kind(path))}
        self.cache = {}
        self.text = text
        # the check process: the first count runs out of its budget
        self.pool = _Pool(lambda fn, a: F.ModelFacts(error="CountTimeout: no answer within 2 s", timed_out=True))
        self.bg = _Pool(background)
        self.stopped = 0
        self.refreshed = 0

    @property
    def check_pool(self):
        return self.pool

    @property
    def proc_pool(self):
        raise AssertionError("the count process is not asked")

    @property
    def background_pool(self):
        return self.bg

    def stop_background_pool(self):
        self.stopped += 1

    async def model_sources(self, path):
        return {path: self.text}

    def own_sources(self, path):
        return None

    async def _stored_facts(self, *a):
        return None

    def _remember(self, key):
        pass

    def cap(self, *a):
        return True

    def workspace_code_lens_refresh(self, params):
        self.refreshed += 1


def test_a_timed_out_count_is_retried_in_the_background_and_says_so():
    srv = _Server("/w/m.tvl", "root M { group allOf { opt A } }",
                  lambda fn, a: F.ModelFacts(total=2, per_feature={"A": 1}))

    async def main():
        first = await srv.model_facts("/w/m.tvl")
        line = F.count_line(first, SimpleNamespace(is_root=False, parent=object(), long_name="A", name="A"))
        await _settle(lambda: "/w/m.tvl" not in srv._retries, "the retry")
        return first, line, await srv.model_facts("/w/m.tvl")
    first, line, again = asyncio.run(main())
    assert first.total is None and first.timed_out and first.retry == 2.0 * RETRY_FACTOR
    assert "counting again in the background" in line and "CountTimeout" in line
    assert again.total == 2 and again.per_feature == {"A": 1}
    # in the background process, with the longer budget, then that process is stopped
    assert [(name, args[2]) for name, args in srv.bg.calls] == [("compute_model_facts", 2.0 * RETRY_FACTOR)]
    assert srv.stopped == 1 and srv.refreshed == 1


def test_retries_grow_up_to_their_limit_then_say_why():
    srv = _Server("/w/m.tvl", "root M {}",
                  lambda fn, a: F.ModelFacts(error=f"CountTimeout: no answer within {a[2]:g} s", timed_out=True))

    async def main():
        await srv.model_facts("/w/m.tvl")
        await _settle(lambda: "/w/m.tvl" not in srv._retries, "the last retry")
        return await srv.model_facts("/w/m.tvl")
    final = asyncio.run(main())
    budgets = [args[2] for _, args in srv.bg.calls]
    expected, b = [], 2.0
    while min(MAX_RETRY_BUDGET, b * RETRY_FACTOR) > b:
        b = min(MAX_RETRY_BUDGET, b * RETRY_FACTOR)
        expected.append(b)
    assert budgets == expected and budgets[-1] == MAX_RETRY_BUDGET
    assert final.retry is None and final.timed_out and f"{MAX_RETRY_BUDGET:g} s" in final.error
    assert "not counted (" in F.count_line(final, SimpleNamespace(is_root=False, parent=object(), long_name="A",
                                                                  name="A"))


def test_a_newer_text_cancels_the_retry():
    class _Slow(_Pool):
        def submit(self, fn, *args):
            self.calls.append((fn.__name__, args))
            fut = cf.Future()  # never answered: the retry is still running
            return fut
    srv = _Server("/w/m.tvl", "root M {}", None)
    srv.bg = _Slow(None)

    async def main():
        first = await srv.model_facts("/w/m.tvl")
        await _settle(lambda: srv.bg.calls, "the retry submitted")
        task = srv._retries["/w/m.tvl"][1]
        srv.text = "root M { group allOf { opt B } }"  # the model changed
        srv.pool = _Pool(lambda fn, a: F.ModelFacts(total=2))
        second = await srv.model_facts("/w/m.tvl")
        await _settle(lambda: task.done() and srv.stopped, "the retry cancelled")
        return first, second, task
    first, second, task = asyncio.run(main())
    assert first.retry and second.total == 2
    assert task.cancelled() and "/w/m.tvl" not in srv._retries and srv.stopped == 1


# ------------------------------------------------------------------ memory: what is kept is bounded

def test_the_models_kept_are_bounded_per_file_and_in_characters(monkeypatch):
    from tvl_lsp.project import models
    models.clear()
    texts = [f"root R{i} {{ group allOf {{ opt A, opt B }} }}\n" for i in range(4)]
    got = [models.load("/w/m.tvl", t, lambda p: None) for t in texts]
    kept = [k for k in models._CACHE if k[0].endswith("m.tvl")]
    assert len(kept) == models.MAX_PER_PATH  # the latest texts of a file being edited
    assert models.load("/w/m.tvl", texts[-1], lambda p: None)[1] is got[-1][1]  # (still reused)
    # other files are kept beside them, within the characters allowed in all
    models.load("/w/other.tvl", texts[0], lambda p: None)
    assert len(models._CACHE) == models.MAX_PER_PATH + 1
    monkeypatch.setattr(models, "MAX_MODEL_CHARS", len(texts[0]) + 1)
    models.load("/w/third.tvl", texts[1], lambda p: None)
    assert [k[0] for k in models._CACHE] == [models._key("/w/third.tvl", "")[0]]  # the latest, always
    models.clear()


def test_the_circuits_kept_are_bounded_by_their_size():
    from tvl_lsp.analysis.counting.cache import MemoryCache
    m = MemoryCache(8, max_weight=10)
    m.put("a", 1, 4)
    m.put("b", 2, 4)
    assert m.get("a") == 1 and m.get("b") == 2
    m.put("c", 3, 4)  # 12 > 10: the least recently used goes
    assert m.get("a") is None and m.get("b") == 2 and m.get("c") == 3
    m.put("huge", 4, 100)  # bigger than all: kept alone
    assert list(m.data) == ["huge"]


def test_the_configurator_keeps_two_sessions_of_a_model_being_edited(tmp_path):
    from tvl_lsp.configurator import pool
    model = tmp_path / "m.tvl"
    texts = [f"root M {{ group allOf {{ opt A{i}, opt B }} }}\n" for i in range(4)]
    pool._SESSIONS.clear()
    for t in texts:
        pool.session(str(model), [str(tmp_path)], {str(model): t})
    assert len(pool._SESSIONS) == pool.MAX_PER_MODEL
    pool._SESSIONS.clear()


def test_the_server_keeps_the_facts_of_the_latest_texts_of_a_model():
    srv = _Server("/w/m.tvl", "root M {}", None)
    for i in range(4):
        srv._keep_facts("/w/m.tvl", ("facts", f"k{i}", 2.0), F.ModelFacts(total=i))
    srv._keep_facts("/w/n.tvl", ("facts", "n", 2.0), F.ModelFacts(total=9))
    assert sorted(k[1] for k in srv.cache) == ["k2", "k3", "n"]


# ------------------------------------------------------------------ counts on a busy machine

def test_a_counting_childs_budget_is_its_cpu_time_in_the_servers_workers(monkeypatch):
    """The server's workers count with CPU-time budgets (a busy machine slows a count, it does
    not make it time out); elsewhere (``count --timeout``) the budget is the wall clock.  A
    sleeping child uses no CPU: spent on the wall clock, not in CPU time."""
    import subprocess
    import time
    from tvl_lsp.analysis.counting import clock
    child = subprocess.Popen(["sleep", "30"])
    try:
        monkeypatch.delenv(clock.ENV, raising=False)
        wall = clock.Budget(child.pid, 0.05, start=time.monotonic() - 0.2)
        assert not wall.cpu and wall.spent()
        monkeypatch.setenv(clock.ENV, "cpu")
        # past its budget on the wall clock (well within WALL_FACTOR times it), not in CPU time
        cpu = clock.Budget(child.pid, 1.0, start=time.monotonic() - 2.0)
        assert cpu.cpu and not cpu.spent()
        assert clock.cpu_seconds(child.pid) is not None and clock.cpu_seconds(child.pid) < 0.05
        stuck = clock.Budget(child.pid, 0.05, start=time.monotonic() - 0.05 * clock.WALL_FACTOR - 1)
        assert stuck.spent()  # (the wall clock still ends it, at WALL_FACTOR times its budget)
    finally:
        child.kill()
        child.wait()


def test_a_model_that_reads_no_other_file_is_counted_without_waiting_for_its_parse(tmp_path):
    from tvl_lsp.lsp.documents import DocumentStore

    class Store(DocumentStore):
        def __init__(self):
            self._init_documents()
    s = Store()
    files = {"a.tvl": "root A { group allOf { opt B } }", "b.tvl": "root A {}\ninclude(c.tvl);",
             "c.uvl": "features\n\tA\n", "d.uvl": "imports\n\tx\nfeatures\n\tA\n", "e.dimacs": "p cnf 1 0\n"}
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    got = {name: s.own_sources(str(tmp_path / name)) for name in files}
    assert got["a.tvl"] == {str(tmp_path / "a.tvl"): files["a.tvl"]}
    assert got["c.uvl"] and got["e.dimacs"]
    assert got["b.tvl"] is None and got["d.uvl"] is None  # (their parse says what they read)


# ------------------------------------------------------------------ priorities

def test_the_workers_keep_the_servers_priority_and_only_the_background_one_is_niced():
    """The check and count processes compute what the user waits for: at the server's
    priority (niced, they lost to every process of a busy machine).  Only the process of
    retried counts is niced."""
    import os
    from tvl_lsp.lsp.procinit import BACKGROUND_NICE
    w = Workers()
    w._init_workers()
    base = os.nice(0)
    try:
        assert w.check_pool.submit(os.nice, 0).result(120) == base
        assert w.proc_pool.submit(os.nice, 0).result(120) == base
        assert w.background_pool.submit(os.nice, 0).result(120) == min(19, base + BACKGROUND_NICE)
    finally:
        w.restart_check_pool()
        w.restart_proc_pool()
        w.stop_background_pool()
        w.executor.shutdown(wait=False)


# ------------------------------------------------------------------ the quick pass is a part of the full check

def _launch_files():
    out = []
    for ws in (RESPOND_WS, REPO / "tests" / "data" / "ws", REPO / "tests" / "data" / "graph" / "ws",
               REPO / "tests" / "data" / "pairs" / "ws", REPO / "tests" / "data" / "configurator" / "ws"):
        out += [(ws, p) for p in sorted(ws.rglob("*.launch"))]
    return out


@pytest.mark.parametrize("ws,path", _launch_files(), ids=lambda v: v.name if isinstance(v, Path) else None)
def test_the_quick_pass_reports_a_part_of_the_full_check(ws, path):
    """What the server shows before its solver-backed check (``solver=False``) is what the
    full check (and ``--check``) says of it: never a finding the full check would take back."""
    from tvl_lsp.project.check import check_document
    quick = {d.sort_key() for d in check_document(str(path), roots=[str(ws)], solver=False)}
    full = {d.sort_key() for d in check_document(str(path), roots=[str(ws)])}
    assert quick <= full, sorted(quick - full)


def test_the_quick_pass_of_the_fixture_has_the_solver_free_findings_only():
    from tvl_lsp.project.check import check_document
    path = RESPOND_WS / LAUNCH
    quick = {d.code for d in check_document(str(path), roots=[str(RESPOND_WS)], solver=False)}
    full = {d.code for d in check_document(str(path), roots=[str(RESPOND_WS)])}
    assert {"unmatched-arg", "missing-arg"} <= quick and not {"dead-element", "undefined-arg"} & quick
    assert {"dead-element", "undefined-arg"} <= full


# ------------------------------------------------------------------ false-optional features from the counts

def _small_models():
    out = []
    for p in sorted((REPO / "tests" / "data").rglob("*")):
        if p.suffix in (".tvl", ".uvl") and p.is_file() and p.stat().st_size < 20_000 \
                and "hostile" not in p.parts and "robustness" not in p.parts:
            out.append(p)
    return out


def test_false_optional_features_from_the_counts_are_the_solvers():
    """The counts say which optional features are in every product with their parent (equal
    counts); the SAT search says the same, on every small model of the test data."""
    from tvl_lsp.project import models
    compared = 0
    for p in _small_models():
        text = p.read_text(encoding="utf-8", errors="replace")
        try:
            eng = models.load(str(p), text, lambda q: Path(q).read_text() if Path(q).is_file() else None)[1]
            if eng is None or eng.model.root is None:
                continue
            r = eng.feature_counts_result(timeout=20)
        except Exception:  # (a model the engine refuses: not this test's business)
            continue
        if not r.complete or not r.total:
            continue
        got = F.false_optional_from_counts(eng, r.counts)
        if got is None:
            continue  # (a feature with several parents: the solver decides)
        assert got == set(eng.false_optional_features()), p
        compared += 1
    models.clear()
    assert compared >= 10, compared


# ------------------------------------------------------------------ one parse of a file at a time

class _Store(DocumentStore):
    def __init__(self, threads):
        self._init_documents()
        self.threads = threads

    async def run_in_thread(self, fn, *args):
        return await asyncio.get_running_loop().run_in_executor(self.threads, fn, *args)


def test_a_newer_text_is_parsed_after_the_parse_of_the_older_one(monkeypatch):
    """A burst of edits to a big model never has two of its parses in memory at once, and an
    older parse never replaces a newer one in the cache."""
    import threading
    import time
    running, overlap, order = [], threading.Event(), []
    lock = threading.Lock()

    def parse(kind, path, text, read, roots, *more):
        with lock:
            running.append(text)
            if len(running) > 1:
                overlap.set()
        if text == "t1":  # a long parse: does another start meanwhile?
            overlap.wait(1.5)
        with lock:
            running.remove(text)
            order.append(text)
        return SimpleNamespace(text=text)
    monkeypatch.setattr(checks, "parse_document", parse)
    pool = cf.ThreadPoolExecutor(4)
    s = _Store(pool)

    async def main():
        t1 = s.parse_task("/w/m.tvl", "tvl", "t1")
        await _settle(lambda: running, "the parse of t1 under way")
        t2 = s.parse_task("/w/m.tvl", "tvl", "t2")
        t3 = s.parse_task("/w/m.tvl", "tvl", "t3")
        return [(await t).text for t in (t1, t2, t3)]
    try:
        t0 = time.monotonic()
        assert asyncio.run(main()) == ["t1", "t2", "t3"]
    finally:
        pool.shutdown()
    assert not overlap.is_set() and order == ["t1", "t2", "t3"]
    assert s.parsed_cache["/w/m.tvl"][1].text == "t3" and not s._parsing
    assert time.monotonic() - t0 >= 1.4  # (t1 waited for an overlap that never came)


def test_a_cancelled_parse_request_does_not_stop_the_next_one(monkeypatch):
    monkeypatch.setattr(checks, "parse_document", lambda kind, path, text, read, roots, *more: SimpleNamespace(text=text))
    pool = cf.ThreadPoolExecutor(2)
    s = _Store(pool)

    async def main():
        t1 = s.parse_task("/w/m.tvl", "tvl", "t1")
        t2 = s.parse_task("/w/m.tvl", "tvl", "t2")
        t1.cancel()
        return (await t2).text
    try:
        assert asyncio.run(main()) == "t2"
    finally:
        pool.shutdown()


# ------------------------------------------------------------------ a quick check that fails

class _Syntax(DocumentStore, Scheduler, Workers):
    def __init__(self):
        self._init_documents()
        self._init_workers()
        self._init_scheduler()
        self.published = []

    def publish(self, uri):
        r = self.results[uri]
        self.published.append((r.phase, [d.code for d in r.diagnostics]))

    def _quick_check(self, path, text, read):
        raise RuntimeError("a bug in a solver-free check")


def test_a_failing_quick_check_leaves_the_syntax_findings_shown(tmp_path):
    """The quick pass of a launch file whose solver-free checks fail publishes its syntax
    findings (the full check reports the rest), not an empty list."""
    path = tmp_path / "a.launch"
    text = '<launch>\n  <node pkg="p" type="t" name="n" unknownattr="1"/>\n</launch>\n'
    path.write_text(text)
    srv = _Syntax()
    doc = Document(path.as_uri(), text, 1)
    srv.docs[doc.uri] = doc
    try:
        asyncio.run(srv._syntax_pass(doc.uri))
    finally:
        srv.executor.shutdown(wait=False)
    assert srv.published[-1] == ("syntax", ["unknown-attribute"]), srv.published


def test_an_idle_worker_trims_once_after_some_work():
    """A worker gives its freed memory back when it goes idle after some work: not while it
    works, not when it has done (almost) nothing since, not twice for the same work."""
    from tvl_lsp.lsp.procinit import IDLE_SECONDS, TRIM_AFTER_CPU, IdleTrim
    t = IdleTrim(0.0)
    assert not t.due(0.0)                       # idle, nothing done yet
    assert not t.due(TRIM_AFTER_CPU * 2)       # working
    assert t.due(TRIM_AFTER_CPU * 2)           # idle after work: trim
    t.done(TRIM_AFTER_CPU * 2 + 0.01)
    assert not t.due(TRIM_AFTER_CPU * 2 + 0.01)  # still idle: once is enough
    small = TRIM_AFTER_CPU * 2 + 0.01 + 0.04 * IDLE_SECONDS  # a little work, then idle
    assert not t.due(small) and not t.due(small)


def test_the_quick_check_skips_a_text_a_newer_one_replaced(tmp_path, monkeypatch):
    """A burst of keys: the text typed while a parse ran is quick-checked, not the older one."""
    import threading
    from tvl_lsp.lsp.scheduler import CheckResult
    path = tmp_path / "a.launch"
    old, new = "<launch>\n</launch>\n", '<launch>\n  <arg name="x"/>\n</launch>\n'
    started, release = threading.Event(), threading.Event()
    real = checks.parse_document

    def parse(kind, p, text, read, roots, *more):
        if text == old:
            started.set()
            release.wait(60)
        return real(kind, p, text, read, roots, *more)
    monkeypatch.setattr(checks, "parse_document", parse)

    class Srv(_Syntax):
        checked = []

        def _quick_check(self, p, text, read):
            self.checked.append(text)
            return []
    srv = Srv()
    doc = Document(path.as_uri(), old, 1)
    srv.docs[doc.uri] = doc
    srv.results[doc.uri] = CheckResult(0, "full", [], "")  # (a file checked before)

    async def main():
        task = asyncio.ensure_future(srv._syntax_pass(doc.uri))
        await _settle(started.is_set, "the parse of the older text")
        doc.set_text(new, 2)
        srv._syntax_dirty.add(doc.uri)  # (what schedule() does while the pass runs)
        release.set()
        await task
    try:
        asyncio.run(main())
    finally:
        release.set()
        srv.executor.shutdown(wait=False)
    assert srv.checked == [new] and srv.results[doc.uri].version == 2 and srv.results[doc.uri].phase == "quick"
