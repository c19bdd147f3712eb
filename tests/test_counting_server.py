"""The counting service in the language server and the configurator (issue #15): a model
compiled before answers its counts without waiting for the check, the work of a progress bar
starts before the client acknowledges the bar, and a configurator decision on a compiled
model is one pass over the circuit (no SAT call per open feature)."""

from __future__ import annotations

import asyncio
import concurrent.futures as cf
import random
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

from tvl_lsp.analysis import configure
from tvl_lsp.analysis.counting import service as S
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.formats import parse_any_model
from tvl_lsp.lsp import checks
from tvl_lsp.lsp.scheduler import Scheduler
from tvl_lsp.lsp.workers import Workers
from tvl_lsp.project import facts as F
from tvl_lsp.project import models

REPO = Path(__file__).resolve().parents[1]
CARDS = REPO / "tests" / "data" / "counting" / "cards.tvl"
ROBOT = REPO / "tests" / "data" / "uvl" / "robot.uvl"
EXAMPLE = REPO / "examples" / "ws" / "src" / "turtlerand" / "launch" / "generic.tvl"


def load(path: Path) -> ModelAnalysis:
    res = parse_any_model(path.read_text(), str(path))
    assert not res.errors, res.errors
    return ModelAnalysis(res.model)


# ------------------------------------------------------------------ configurator decisions

def _sat_propagate(a: ModelAnalysis, decisions):
    a.counter  # noqa: B018 (the service exists)
    S.MEMORY.clear()  # not in memory: the SAT path
    return configure.propagate(a, decisions, count=True)


@pytest.mark.parametrize("path", [CARDS, ROBOT, EXAMPLE])
def test_decisions_on_a_compiled_model_take_one_pass_and_equal_the_sat_answer(path, fresh_cache, monkeypatch):
    a = load(path)
    names = [a.name(f) for f in a.encoding.features]
    rng = random.Random(5)
    trials = [{}] + [{n: rng.random() < 0.5 for n in rng.sample(names, k)} for k in (1, 1, 2, 2, 3) for _ in range(4)]
    expected = []
    for d in trials:
        p = _sat_propagate(a, d)
        expected.append((p.ok, p.forced, sorted(p.open), p.count))
    a.counter.circuit()
    assert a.counter.ready()
    real_decide = configure.decide
    calls = []

    def counting_decide(enc, lits):
        calls.append(list(lits))
        return real_decide(enc, lits)
    monkeypatch.setattr(configure, "decide", counting_decide)
    for d, exp in zip(trials, expected):
        p = configure.propagate(a, d, count=True)
        assert (p.ok, p.forced, sorted(p.open), p.count) == exp, d
        if p.ok:
            assert not calls, "a consistent decision on a compiled model made a SAT call"
        else:
            assert p.conflict and calls  # the minimal conflicting decisions come from SAT
            calls.clear()


def test_feature_counts_if_ready_never_compiles(fresh_cache):
    a = load(CARDS)
    assert a.counter.feature_counts_if_ready([]) is None
    assert not a.counter.ready() and not a.counter.on_disk()
    a.counter.circuit()
    r = a.counter.feature_counts_if_ready([])
    assert r is not None and r.total == a.count() and r.engine == "d4"
    assert a.counter.on_disk()


# ------------------------------------------------------------------ facts from the disk cache

def test_facts_wait_for_a_circuit_read_back_from_the_disk_cache(fresh_cache, monkeypatch):
    """A model compiled before (on disk) is counted in the first request even when reading
    the circuit back takes longer than the request's poll interval: no second round behind
    the check."""
    src = {str(CARDS): CARDS.read_text()}
    first = F.compute_model_facts(str(CARDS), src, 30.0)
    assert first.total and first.pending is None
    S.MEMORY.clear()
    models.clear()
    slow = S.CNFCounter._load

    def slow_load(self, text, from_disk=False):
        time.sleep(0.4)
        return slow(self, text, from_disk)
    monkeypatch.setattr(S.CNFCounter, "_load", slow_load)
    again = F.compute_model_facts(str(CARDS), src, 30.0, wait=0.01)
    assert again.pending is None, again
    assert again.total == first.total and again.per_feature == first.per_feature


def test_facts_of_a_model_never_compiled_are_pending_after_the_poll(fresh_cache, monkeypatch):
    def never_done(self, timeout=None, cancel=None, progress=None):
        time.sleep(1.0)
        raise S.CountTimeout("slow")
    monkeypatch.setattr(S.CNFCounter, "circuit", never_done)
    f = F.compute_model_facts(str(CARDS), {str(CARDS): CARDS.read_text()}, 30.0, wait=0.05)
    assert f.pending == "compiling"


# ------------------------------------------------------------------ progress bars

class _Progress:
    def __init__(self, delay):
        self.delay = delay
        self.events = []

    async def create_async(self, token):
        await asyncio.sleep(self.delay)
        self.events.append(("created", time.perf_counter()))

    def begin(self, token, value):
        self.events.append(("begin", time.perf_counter()))

    def end(self, token, value):
        self.events.append(("end", time.perf_counter()))


class _Host(Workers):
    supports_progress = True

    def __init__(self, delay):
        self._init_workers()
        self.work_done_progress = _Progress(delay)


def test_progress_bar_does_not_delay_the_work():
    host = _Host(0.3)
    started = []

    async def work():
        started.append(time.perf_counter())
        await asyncio.sleep(0.5)
        return 42

    async def main():
        return await host.with_progress("Counting", work())
    assert asyncio.run(main()) == 42
    created = dict(host.work_done_progress.events)["created"]
    assert started and started[0] < created  # the work began before the client answered
    assert [e for e, _ in host.work_done_progress.events] == ["created", "begin", "end"]


def test_progress_bar_cancelled_cancels_the_work():
    host = _Host(0.3)
    state = {}

    async def work():
        try:
            await asyncio.sleep(5)
        except asyncio.CancelledError:
            state["cancelled"] = True
            raise

    async def main():
        t = asyncio.ensure_future(host.with_progress("Counting", work()))
        await asyncio.sleep(0.05)
        t.cancel()
        with pytest.raises(asyncio.CancelledError):
            await t
        await asyncio.sleep(0)
    asyncio.run(main())
    assert state.get("cancelled")


# ------------------------------------------------------------------ the check process's queue

class _Pool:
    """A check process that records what it is asked, in order."""

    def __init__(self):
        self.calls = []

    def submit(self, fn, *args):
        self.calls.append(fn.__name__)
        fut = cf.Future()
        fut.set_result(F.ModelFacts(total=4) if fn is F.compute_model_facts else [])
        return fut


class _Server(Scheduler, Workers):
    supports_progress = False
    epoch = 0

    def __init__(self, path: str, text: str):
        self._init_workers()
        self._init_scheduler()
        self.settings = SimpleNamespace(debounce=0.0, time_budget=30.0)
        self.docs = {"file://m": SimpleNamespace(version=1, text=text, path=path, kind=checks.file_kind(path))}
        self.cache = {}
        self.pool = _Pool()
        self.published = []

    @property
    def check_pool(self):
        return self.pool

    async def model_sources(self, path):
        await asyncio.sleep(0.05)  # the server's parse of the model
        return {path: self.docs["file://m"].text}

    def own_sources(self, path):
        return None  # (the parse decides)

    def _remember(self, key):
        pass

    def roots_for(self, path):
        return []

    def publish(self, uri):
        self.published.append(uri)


@pytest.mark.parametrize("path", ["/w/m.tvl", "/w/m.uvl", "/w/m.dimacs"])
def test_counts_are_queued_before_the_check(path):
    """In the one check process, a model's counts come first: when it was compiled before,
    they are one parse and one pass away instead of behind the whole anomaly search."""
    srv = _Server(path, "root M {}")

    async def main():
        srv._generation["file://m"] = 1
        await srv._full_pass("file://m", 1)
        await asyncio.sleep(0.1)
    asyncio.run(main())
    assert srv.pool.calls[:2] == ["compute_model_facts", "full_check_worker"], srv.pool.calls
    assert srv.published == ["file://m"]


def test_a_launch_file_check_is_not_delayed_by_counts():
    srv = _Server("/w/a.launch", "<launch/>")
    srv.models_for_launch = lambda p: []

    async def main():
        srv._generation["file://m"] = 1
        await srv._full_pass("file://m", 1)
    asyncio.run(main())
    assert srv.pool.calls == ["full_check_worker"]


# ------------------------------------------------------------------ while the check process checks

def test_facts_without_compiling_wait_for_another_process(fresh_cache, monkeypatch):
    """The count process asks with compile=False: it never starts d4 (the check process's d4
    compiles the model), and counts as soon as the circuit is in the disk cache."""
    src = {str(CARDS): CARDS.read_text()}
    started = []
    real_start = S.CNFCounter.start

    def start(self, *a, **k):
        started.append(self.key)
        return real_start(self, *a, **k)
    monkeypatch.setattr(S.CNFCounter, "start", start)
    f = F.compute_model_facts(str(CARDS), src, 30.0, wait=0.05, compile=False)
    assert f.pending == "compiling" and not started
    models.load(str(CARDS), src[str(CARDS)], src.get)[1].counter.circuit()  # "another process"
    S.MEMORY.clear()
    models.clear()
    f = F.compute_model_facts(str(CARDS), src, 30.0, wait=0.05, compile=False)
    assert f.pending is None and f.total and f.per_feature


class _BusyCheckPool:
    """A check process busy with a long check: every counts question answers "compiling"."""

    def __init__(self):
        self.calls = []

    def submit(self, fn, *args):
        self.calls.append(args)
        fut = cf.Future()
        fut.set_result(F.ModelFacts(pending="compiling"))
        return fut


class _CountPool:
    def __init__(self):
        self.calls = []

    def submit(self, fn, *args):
        self.calls.append(args)
        fut = cf.Future()
        compile_ = args[4] if len(args) > 4 else True
        fut.set_result(F.ModelFacts(total=7) if not compile_ else F.ModelFacts(pending="compiling"))
        return fut


class _Counting(_Server):
    def __init__(self, path, text):
        super().__init__(path, text)
        self.pool = _BusyCheckPool()
        self.counts = _CountPool()
        self.settings.time_budget = 1.0

    @property
    def proc_pool(self):
        return self.counts


def test_counts_come_from_the_count_process_while_the_check_process_checks():
    srv = _Counting("/w/m.uvl", "features\n\tM\n")

    async def main():
        return await srv.model_facts("/w/m.uvl")
    facts = asyncio.run(main())
    assert facts.total == 7, facts
    assert srv.counts.calls and all(c[4] is False for c in srv.counts.calls)  # never compiles there


def test_a_click_makes_one_pass_for_what_it_forces_and_every_count(fresh_cache, monkeypatch):
    """A configurator click asks for the same decisions twice (propagation, then the counts):
    the second answer is the first pass's, and other decisions get their own pass."""
    from tvl_lsp.analysis.counting.circuit import Circuit
    a = load(CARDS)
    a.counter.circuit()
    total = a.count()
    # a feature in some products but not all (a core or dead one needs no pass: the reduced
    # CNF fixes it)
    names = [a.name(f) for f in a.encoding.features]
    names = [n for n in names if 0 < a.count(include=[n]) < total]
    passes = []
    real = Circuit.counts

    def counting(self, lits=()):
        passes.append(list(lits))
        return real(self, lits)
    monkeypatch.setattr(Circuit, "counts", counting)
    p = configure.propagate(a, {names[0]: True}, count=False)
    r = a.feature_counts_result(include=[names[0]])
    assert len(passes) == 1 and r.total == a.count(include=[names[0]]) and p.ok
    r2 = a.feature_counts_result(exclude=[names[0]])
    assert len(passes) == 2 and r2.total + r.total == a.count()
    r.counts[1] = -1  # a caller's change never reaches the next answer
    assert a.feature_counts_result(include=[names[0]]).counts[1] != -1


# ------------------------------------------------------------------ reopening a model counted before

def test_stored_facts_answer_without_any_worker_process(fresh_cache):
    """A model whose facts were stored (counted before, by any process) is answered from the
    disk at once: nothing is asked of the check process (busy with a long check) or the count
    process."""
    path = str(ROBOT)
    text = ROBOT.read_text()
    computed = F.compute_model_facts(path, {path: text}, 30.0)
    assert computed.total and computed.error is None
    srv = _Counting(path, text)

    async def main():
        return await srv.model_facts(path, wait=0.3)
    facts = asyncio.run(main())
    assert facts is not None and facts.total == computed.total and facts.per_feature == computed.per_feature
    assert not srv.pool.calls and not srv.counts.calls
    # another text (even a layout change) is not answered from this text's file
    srv2 = _Counting(path, text + "\n")

    async def main2():
        return await srv2.model_facts(path)
    assert asyncio.run(main2()).total != computed.total  # (the fake processes never count)
    assert srv2.pool.calls


class _Parsing(_Server):
    """The document store's parse sharing, with a slow parse that counts its calls."""

    def __init__(self, path, text):
        super().__init__(path, text)
        from tvl_lsp.lsp.documents import DocumentStore
        self._ds = DocumentStore
        self.parsed_cache = {}
        self._parsing = {}
        self.roots = []
        self.calls = 0

    def parse_task(self, path, kind, text):
        return self._ds.parse_task(self, path, kind, text)

    def _parse_key(self, path, text):
        return self._ds._parse_key(self, path, text)

    def _store_parsed(self, path, text, parsed):
        return self._ds._store_parsed(self, path, text, parsed)

    async def _parse_now(self, path, kind, text, before=None):
        return await self._ds._parse_now(self, path, kind, text, before)

    def snapshot_reader(self):
        return lambda p: None


def test_the_syntax_pass_and_a_request_share_one_parse(monkeypatch):
    """Opening a model starts its syntax pass; a hover at the same moment needs the same parse:
    one parse (two at once in one process share the interpreter lock: each takes twice as
    long -- the first counted hover of a big model waited for both)."""
    text = ROBOT.read_text()
    srv = _Parsing(str(ROBOT), text)
    calls = []
    real = checks.parse_document

    def slow_parse(*a):
        calls.append(a[1])
        time.sleep(0.3)
        return real(*a)
    monkeypatch.setattr(checks, "parse_document", slow_parse)

    async def main():
        srv.docs["file://m"].kind = "uvl"
        srv.schedule = None
        syntax = asyncio.ensure_future(srv._syntax_pass("file://m"))
        await asyncio.sleep(0.05)
        got = await asyncio.shield(srv.parse_task(str(ROBOT), "uvl", text))
        await syntax
        return got
    srv.docs = {"file://m": SimpleNamespace(version=1, text=text, path=str(ROBOT), kind="uvl")}
    got = asyncio.run(main())
    assert got.model is not None and len(calls) == 1, calls
    assert srv.results["file://m"].phase == "syntax"
