"""The scheduler of background work: the two passes of every check (the syntax pass at once,
in a thread; the solver-backed pass after ``settings.debounce`` of quiet, in the check
process, one per document at a time, the newest text replacing queued work), re-checks of
dependent files, and the model facts (counts, anomalies) and counts computed in the count
process, cached by content.

:class:`Scheduler` is a mixin of :class:`~tvl_lsp.lsp.server.TvlLanguageServer` (it uses
the document store, the workers and the server's ``publish``); its state is set up by
:meth:`Scheduler._init_scheduler`.
"""

from __future__ import annotations

import asyncio
import concurrent.futures as cf
import itertools
from concurrent.futures.process import BrokenProcessPool
import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from ..analysis.counting.clock import WALL_FACTOR
from ..base.diagnostics import Diagnostic
from ..base.text import LineIndex
from ..project import budget as file_budget
from ..project import facts as _facts
from . import checks
from .documents import content_key
from .workers import _consume, release_memory

TRIM_DELAY = 1.0  # seconds after a throttled trim: the next try, if the checks are idle (at most one a second)

FACTS_POLL = 0.3  # seconds: how often the server asks whether a model's compilation is done

# a count that ran out of its budget is retried in the background with RETRY_FACTOR times the
# budget, again and again up to MAX_RETRY_BUDGET seconds
FACTS_PER_MODEL = 2  # facts kept per model: its current text's and the one before (an undo)

RETRY_FACTOR = 4.0
MAX_RETRY_BUDGET = 640.0

log = logging.getLogger("tvl_lsp.server")


_SERIAL = itertools.count(1)


@dataclass
class CheckResult:
    version: Optional[int]
    # "syntax" (a model's front end), "quick" (a launch file's checks that need no solver: its
    # own diagnostics, its pairing's, missing-arg, unmatched-arg...) or "full"
    phase: str
    diagnostics: list[Diagnostic]
    text: Optional[str] = None  # the text checked (its findings are mapped onto later texts)
    # full: the indexes of the diagnostics the quick pass does not make (the solver's findings)
    solver: frozenset = frozenset()
    versions: dict = field(default_factory=dict)  # full: the open documents' versions it read
    serial: int = field(default_factory=lambda: next(_SERIAL))
    _index: Optional[LineIndex] = None

    @property
    def index(self) -> Optional[LineIndex]:
        if self._index is None and self.text is not None:
            self._index = LineIndex(self.text)
        return self._index


class Scheduler:
    """Checks, re-checks, facts and counts in the background (a mixin of the server)."""

    def _init_scheduler(self) -> None:
        # per-uri scheduling
        self._generation: dict[str, int] = {}
        self._syntax_running: dict[str, asyncio.Task] = {}
        self._syntax_dirty: set[str] = set()
        self._full_tasks: dict[str, asyncio.Task] = {}
        self._check_running: dict[str, tuple] = {}
        self.results: dict[str, CheckResult] = {}
        self.last_full: dict[str, CheckResult] = {}  # uri -> its last solver-backed check
        self._quick_keys: dict[str, tuple] = {}  # uri -> (version, keys of its quick pass's diagnostics)
        self._facts_futures: dict[str, asyncio.Future] = {}
        self._facts_queued: dict[str, tuple] = {}
        self._facts_submitted: dict[str, asyncio.Event] = {}  # set once a count is in a pool's queue
        self._facts_lookups: dict[str, asyncio.Future] = {}  # content key -> read of the stored facts
        self._trim_handle: Optional[asyncio.TimerHandle] = None  # a memory trim waiting for idle checks
        self._facts_keys: dict[str, list] = {}  # model path -> its cached facts' keys, oldest first
        self._retries: dict[str, tuple] = {}  # model path -> (facts key, task): counts retried in the background
        self._retry_lock = asyncio.Lock()

    # ------------------------------------------------------------ scheduling
    def schedule(self, uri: str, syntax: bool = True) -> None:
        """(Re)check ``uri``: the syntax pass at once (coalesced while one runs), the
        solver-backed pass after ``settings.debounce`` of quiet."""
        doc = self.docs.get(uri)
        if doc is None or doc.kind is None:
            return
        self._generation[uri] = self._generation.get(uri, 0) + 1
        if syntax:
            if uri in self._syntax_running:
                self._syntax_dirty.add(uri)
            else:
                self._syntax_running[uri] = asyncio.ensure_future(self._syntax_pass(uri))
        old = self._full_tasks.pop(uri, None)
        if old is not None and not old.done():
            old.cancel()
        self._full_tasks[uri] = asyncio.ensure_future(self._full_pass(uri, self._generation[uri]))

    async def _syntax_pass(self, uri: str) -> None:
        try:
            while True:
                self._syntax_dirty.discard(uri)
                doc = self.docs.get(uri)
                if doc is None:
                    return
                version, text, path, kind = doc.version, doc.text, doc.path, doc.kind
                phase = "quick" if kind == "launch" else "syntax"
                try:
                    # the parse requests share (hover, outline, model_sources) when one of
                    # this text is under way: one parse per text at a time
                    parsed = await asyncio.shield(self.parse_task(path, kind, text))
                    diags = list(getattr(parsed, "diagnostics", []) or [])
                    if uri in self._syntax_dirty and uri in self.results:
                        continue  # a newer text came meanwhile: on to it (a burst of keys)
                    if kind == "launch":
                        if uri not in self.results and self.docs.get(uri) is doc and doc.version == version:
                            # a file just opened: its syntax at once (milliseconds), then ...
                            self.results[uri] = CheckResult(version, "syntax", diags, text)
                            self.publish(uri)
                        # ... the checks that need no solver (pairing, missing / unmatched
                        # args): shown before the worker processes are even up
                        try:
                            diags = await self.run_in_thread(self._quick_check, path, text, self.snapshot_reader())
                        except Exception:  # (its syntax, then: the full check reports the rest)
                            log.exception("quick check of %s failed", path)
                            phase = "syntax"
                    log.info("%s pass of %s: %d diagnostics", phase, path, len(diags))
                except Exception:
                    log.exception("%s pass of %s failed", phase, path)
                    diags = []
                self._quick_keys[uri] = (version, frozenset(d.sort_key() for d in diags))
                doc = self.docs.get(uri)
                cur = self.results.get(uri)
                if doc is not None and doc.version == version and not (
                        cur and cur.version == version and cur.phase == "full"):
                    self.results[uri] = CheckResult(version, phase, diags, text)
                    self.publish(uri)
                if uri not in self._syntax_dirty:
                    return
        finally:
            self._syntax_running.pop(uri, None)

    async def _full_pass(self, uri: str, generation: int) -> None:
        try:
            await asyncio.sleep(self.settings.debounce)
            if self._generation.get(uri) != generation:
                return
            doc = self.docs.get(uri)
            if doc is None:
                return
            version, text, path, kind = doc.version, doc.text, doc.path, doc.kind
            budget = self.settings.time_budget
            texts = {d.path: d.text for d in self.docs.values()}
            versions = {d.path: d.version for d in self.docs.values() if d.path != path}
            running = self._check_running.get(uri)
            if running is not None and not running.done():
                # one check per document at a time: wait for the one on an older text (each
                # newer keystroke cancels this wait, so only the latest text is checked next)
                try:
                    await asyncio.wait_for(asyncio.shield(running), budget + 10)
                except asyncio.TimeoutError:
                    log.warning("a check of %s hangs: restarting the check process", path)
                    self.restart_check_pool()
                except asyncio.CancelledError:
                    raise
                except Exception:
                    pass
                if self._generation.get(uri) != generation:
                    return
            if kind in _facts.MODEL_KINDS:
                await self._facts_before_check(path)
                if self._generation.get(uri) != generation:
                    return
            try:
                log.info("check of %s: submitted", path)
                cfut = self.check_pool.submit(checks.full_check_worker, kind, path, text, texts,
                                              self.roots_for(path), budget, self.epoch)
                afut = asyncio.wrap_future(cfut)
                afut.add_done_callback(_consume)
                self._check_running[uri] = afut
                # the worker stops a check at the per-file CPU budget (as --check does, with
                # analysis-budget-exceeded); this wall-clock limit is the backstop behind it
                diags = await asyncio.wait_for(asyncio.shield(afut), timeout=max(budget, file_budget.CPU_SECONDS) + 10)
            except asyncio.TimeoutError:
                log.warning("check of %s ran out of its time budget", path)
                self.restart_check_pool()
                self._budget_exceeded(uri, version, generation, path, "more time than its budget")
                return
            except asyncio.CancelledError:
                raise
            except BrokenProcessPool:
                log.warning("the check process died; restarting it")
                self.restart_check_pool()
                self._budget_exceeded(uri, version, generation, path, "more memory or time than its budget "
                                      "(its check process died)")
                return
            except Exception:
                log.exception("check of %s failed", path)
                return
            doc = self.docs.get(uri)
            if doc is None or doc.version != version or self._generation.get(uri) != generation:
                return  # stale: the text changed meanwhile
            res = CheckResult(version, "full", diags, text, await self._solver_part(uri, version, diags), versions)
            doc = self.docs.get(uri)
            if doc is None or doc.version != version or self._generation.get(uri) != generation:
                return
            self.results[uri] = self.last_full[uri] = res
            self.publish(uri)
            log.info("check of %s: %d diagnostics", path, len(diags))
            self.prefetch_facts(path, kind)
            if kind in ("tvl", "uvl"):
                from .features import quickfix
                quickfix.prefetch(self, uri)  # the anomalies' checked quick fixes (bounded)
            if not any(not t.done() for u, t in self._full_tasks.items() if u != uri):
                self.trim_when_idle()  # nothing else pending: give the freed heap back
        except asyncio.CancelledError:
            pass

    def _quick_check(self, path: str, text: str, read) -> list[Diagnostic]:
        """A launch file's quick check (in a thread), with the server's workspace."""
        try:
            ws = self.workspace_model(path)
        except Exception:  # noqa: BLE001 (the check finds it again itself, and reports what fails)
            ws = None
        return checks.quick_check("launch", path, text, read, self.roots_for(path), ws)

    async def _solver_part(self, uri: str, version, diags: list[Diagnostic]) -> frozenset:
        """The indexes of ``diags`` (the full check of ``version``) that its quick pass does
        not make: what is kept, mapped, while later texts wait for their own full check."""
        quick = self._quick_keys.get(uri)
        if quick is None or quick[0] != version:
            running = self._syntax_running.get(uri)  # (the quick pass of this text, under way)
            if running is not None:
                try:
                    await asyncio.wait_for(asyncio.shield(running), 5.0)
                except (asyncio.TimeoutError, Exception):
                    pass
            quick = self._quick_keys.get(uri)
        if quick is None or quick[0] != version:
            return frozenset()  # (unknown: nothing of this check outlives its text)
        return frozenset(i for i, d in enumerate(diags) if d.sort_key() not in quick[1])

    def trim_when_idle(self) -> None:
        """Give the freed heap back to the system: now, or -- when the last trim was too recent
        -- once the throttle allows and the checks are still idle.  The last check of a burst of
        edits must not leave its peak in the server's RSS for good (bench_server_fuzz.py)."""
        if self._trim_handle is not None:
            return
        if release_memory():
            return

        def later():
            self._trim_handle = None
            if not any(not t.done() for t in self._full_tasks.values()):
                release_memory(every=0.0)
        self._trim_handle = asyncio.get_running_loop().call_later(TRIM_DELAY, later)

    def _budget_exceeded(self, uri: str, version, generation, path: str, what: str) -> None:
        """Say so, rather than leave the last (or no) result standing: the file gets one
        ``analysis-budget-exceeded`` error, as ``--check`` gives it."""
        doc = self.docs.get(uri)
        if doc is None or doc.version != version or self._generation.get(uri) != generation:
            return
        self.results[uri] = CheckResult(version, "full", [file_budget.exceeded(path, what)])
        self.last_full.pop(uri, None)
        self.publish(uri)

    async def _facts_before_check(self, path: str) -> None:
        """Queue the counts of the model at ``path`` in the check process *before* its check:
        when the model was compiled before (the counting cache), the counts are then one
        parse, one encoding and one pass away (the check reuses that parse), instead of
        waiting for the whole anomaly search; otherwise this starts d4 in the background
        before the check (every model format) and the counts follow the check."""
        submitted = asyncio.Event()
        task = asyncio.ensure_future(self.model_facts(path, submitted=submitted))
        task.add_done_callback(_consume)
        waiter = asyncio.ensure_future(submitted.wait())
        try:
            # (the wait is for the server's parse of the model, which the syntax pass of the
            # same text has usually begun: model_sources)
            await asyncio.wait({task, waiter}, timeout=10.0, return_when=asyncio.FIRST_COMPLETED)
        finally:
            waiter.cancel()

    def prefetch_facts(self, path: str, kind: str) -> None:
        """Start counting the products of the model behind ``path`` (the model itself, or the
        models paired with a launch file) in the background, so that the first hover and the
        code lens find the counts ready instead of saying "counting…"."""
        try:
            models = [path] if kind in ("tvl", "uvl", "dimacs") else list(self.models_for_launch(path))
        except Exception:
            log.exception("pairing failed")
            return
        for mp in models:
            task = asyncio.ensure_future(self.model_facts(mp))
            task.add_done_callback(_consume)

    async def wait_full(self, uri: str, timeout: float) -> Optional[CheckResult]:
        """The latest results of ``uri`` once no check of it is pending (or time runs out)."""
        loop = asyncio.get_running_loop()
        end = loop.time() + timeout
        while True:
            task = self._full_tasks.get(uri)
            left = end - loop.time()
            if task is None or task.done() or left <= 0:
                break
            try:
                await asyncio.wait_for(asyncio.shield(task), left)
            except (asyncio.TimeoutError, asyncio.CancelledError):
                if loop.time() >= end:
                    break
        return self.results.get(uri)

    def recheck_dependents(self, path: str) -> None:
        """Editing a model re-checks its paired launch files and vice versa (open ones)."""
        for uri, doc in list(self.docs.items()):
            if doc.path == path or doc.kind is None:
                continue
            if checks.depends_on(self, doc, path):
                self.schedule(uri, syntax=False)

    def recheck_all(self) -> None:
        for uri in list(self.docs):
            self.schedule(uri)

    def facts_ready(self, sources: dict[str, str]):
        return self.cache.get(("facts", content_key(*sorted(f"{k}\0{v}" for k, v in sources.items()))))

    async def model_facts(self, model_path: str, wait: Optional[float] = None,
                          submitted: Optional[asyncio.Event] = None):
        """Counts and anomalies of a model, computed in a worker process (so a slow count
        never blocks the event loop), cached by content.  With ``wait``, give up waiting
        after that many seconds (the computation goes on and lands in the cache).
        ``submitted`` is set once the work is queued (or not needed)."""
        try:
            # (a model that reads no other file: its text alone, without waiting for its parse)
            sources = self.own_sources(model_path) or await self.model_sources(model_path)
        except BaseException:
            if submitted is not None:
                submitted.set()
            raise
        if sources is None:
            if submitted is not None:
                submitted.set()
            return None
        budget = self.settings.time_budget
        key = ("facts", content_key(*sorted(f"{k}\0{v}" for k, v in sources.items())), budget)
        hit = self.cache.get(key)
        if hit is not None:
            if submitted is not None:
                submitted.set()
            return hit
        # a count queued (or retried in the background) for an older text of this model is
        # stale: drop it
        old = self._facts_queued.get(model_path)
        if old is not None and old[0] != key[1]:
            old[1].cancel()
        retried = self._retries.get(model_path)
        if retried is not None and retried[0] != key:
            del self._retries[model_path]
            retried[1].cancel()
        fut = self._facts_futures.get(key[1])
        if fut is None:
            # counted before (this very content, in any process): the facts stored on disk,
            # read in a thread -- no parse, encoding or circuit in a worker process
            stored = await self._stored_facts(model_path, sources, key[1])
            if stored is not None:
                self._keep_facts(model_path, key, stored)
                if submitted is not None:
                    submitted.set()
                return stored
            fut = self._facts_futures.get(key[1])
        if fut is None:
            loop = asyncio.get_running_loop()

            async def compute():
                cfut = None
                pool_of = "check"
                try:
                    # first in the check process, which has just parsed and encoded this text
                    # for its diagnostics (one parse, one encoding: tvl_lsp.project.models);
                    # d4 compiles in the background there and the check process stays free
                    # for checks: ask again until the circuit is ready, then one pass counts
                    # (the workers' count budgets are CPU time: on a busy machine a count takes
                    # longer than its budget on the wall clock, up to WALL_FACTOR times)
                    end = loop.time() + budget * WALL_FACTOR + 30

                    def ask_check_process():
                        c = self.check_pool.submit(_facts.compute_model_facts, model_path, sources, budget,
                                                   FACTS_POLL)
                        self._facts_queued[model_path] = (key[1], c)
                        queued.set()
                        a = asyncio.wrap_future(c)
                        a.add_done_callback(_consume)
                        return c, a

                    cfut, afut = ask_check_process()
                    facts = await asyncio.wait_for(asyncio.shield(afut), max(1.0, end - loop.time()) + 10)
                    source = "check"
                    while facts.pending == "compiling":
                        # d4 compiles in the check process's background while that process
                        # checks; the counts are asked of the count process too, which never
                        # compiles but reads the circuit back from the disk cache as soon as d4
                        # has written it -- the next question to the check process waits
                        # behind its check (it still settles a failed compilation: fallback)
                        if loop.time() > end:
                            facts = _facts.ModelFacts(error=f"no count within {budget:g} s", timed_out=True)
                            break
                        await asyncio.sleep(FACTS_POLL)
                        latest = self._facts_queued.get(model_path)
                        if latest is not None and latest[0] != key[1]:
                            return _facts.ModelFacts(error="cancelled: the model changed")
                        if afut.done():
                            if afut.cancelled():
                                return _facts.ModelFacts(error="cancelled: the model changed")
                            if afut.exception() is not None:
                                raise afut.exception()
                            if afut.result().pending != "compiling":
                                facts = afut.result()
                                break
                            cfut, afut = ask_check_process()
                        pool_of = "count"
                        pfut = asyncio.wrap_future(self.proc_pool.submit(
                            _facts.compute_model_facts, model_path, sources, budget, FACTS_POLL, False))
                        pfut.add_done_callback(_consume)
                        got = await asyncio.wait_for(asyncio.shield(pfut), max(1.0, end - loop.time()) + 10)
                        pool_of = "check"
                        if got.pending != "compiling":
                            facts, source = got, "count"
                            cfut.cancel()  # (when still queued behind the check)
                    log.info("facts of %s: %s (the %s process)", model_path, facts.pending or "counted", source)
                    if facts.pending == "fallback":
                        # d4 cannot count it: pyganak, one count per feature, in the count
                        # process (a slow count there never delays a check)
                        pool_of = "count"
                        cfut = self.proc_pool.submit(_facts.compute_model_facts, model_path, sources, budget)
                        self._facts_queued[model_path] = (key[1], cfut)
                        afut = asyncio.wrap_future(cfut)
                        afut.add_done_callback(_consume)
                        facts = await asyncio.wait_for(asyncio.shield(afut), budget * WALL_FACTOR + 30)
                except (cf.CancelledError, asyncio.CancelledError):
                    if cfut is not None and cfut.cancelled():
                        return _facts.ModelFacts(error="cancelled: the model changed")
                    raise
                except Exception as e:
                    timed_out = isinstance(e, asyncio.TimeoutError)
                    facts = _facts.ModelFacts(error=f"{type(e).__name__}: {e}" if str(e) else
                                              f"no count within {budget:g} s", timed_out=timed_out)
                    if pool_of == "count" and isinstance(e, (BrokenProcessPool, asyncio.TimeoutError)):
                        self.restart_proc_pool()
                    elif pool_of == "check" and timed_out:
                        self.restart_check_pool()  # (a broken one: the next check restarts it)
                    if not timed_out:
                        return facts
                if facts.timed_out:
                    # not an answer: the hovers say so while it is counted again, in the
                    # background with a longer budget (the same text and budget would run
                    # out again: the timeout stands for this text until the retry answers)
                    facts.retry = self._retry_facts(model_path, sources, key, budget)
                self._keep_facts(model_path, key, facts)
                return facts

            async def run():
                try:
                    return await self.with_progress(f"Counting the products of {Path(model_path).name}", compute())
                finally:
                    queued.set()
                    self._facts_futures.pop(key[1], None)
                    self._facts_submitted.pop(key[1], None)
            queued = self._facts_submitted[key[1]] = asyncio.Event()
            fut = loop.create_task(run())
            self._facts_futures[key[1]] = fut
        if submitted is not None:  # once this text's count is queued (now or by an earlier caller)
            in_queue = self._facts_submitted.get(key[1])
            if in_queue is None:
                submitted.set()
            else:
                async def relay():
                    await in_queue.wait()
                    submitted.set()
                relay_task = asyncio.ensure_future(relay())
                relay_task.add_done_callback(_consume)
        if wait is None:
            return await asyncio.shield(fut)
        try:
            return await asyncio.wait_for(asyncio.shield(fut), wait)
        except asyncio.TimeoutError:
            return None

    def _retry_facts(self, model_path: str, sources: dict[str, str], key: tuple, last: float) -> Optional[float]:
        """Count the model again in the background process (niced: nobody waits for it yet)
        with :data:`RETRY_FACTOR` times the ``last`` budget, at most :data:`MAX_RETRY_BUDGET`
        seconds; returns that budget, or None when ``last`` was the longest.  A newer text of
        the model cancels it."""
        nxt = min(MAX_RETRY_BUDGET, last * RETRY_FACTOR)
        if nxt <= last:
            return None
        old = self._retries.get(model_path)
        if old is not None and old[0] != key:
            old[1].cancel()
        task = asyncio.ensure_future(self._run_retry(model_path, sources, key, nxt))
        task.add_done_callback(_consume)
        self._retries[model_path] = (key, task)
        return nxt

    async def _run_retry(self, model_path: str, sources: dict[str, str], key: tuple, budget: float) -> None:
        def current() -> bool:
            got = self._retries.get(model_path)
            return got is not None and got[0] == key
        async with self._retry_lock:  # one at a time: the background process has one worker
            if not current():
                return
            log.info("facts of %s: counting again in the background with %g s", model_path, budget)
            try:
                cfut = self.background_pool.submit(_facts.compute_model_facts, model_path, sources, budget)
                afut = asyncio.wrap_future(cfut)
                afut.add_done_callback(_consume)
                facts = await asyncio.wait_for(asyncio.shield(afut), budget * WALL_FACTOR + 30)
            except asyncio.CancelledError:
                self.stop_background_pool()  # (stale: the model changed)
                raise
            except Exception as e:
                facts = _facts.ModelFacts(error=f"{type(e).__name__}: {e}" if str(e) else
                                          f"no count within {budget:g} s",
                                          timed_out=isinstance(e, asyncio.TimeoutError))
                self.stop_background_pool()
        if not current():
            return
        log.info("facts of %s: %s after the retry with %g s", model_path,
                 "counted" if not facts.timed_out else "still not counted", budget)
        if facts.timed_out:
            facts.retry = self._retry_facts(model_path, sources, key, budget)
        if facts.retry is None:
            self._retries.pop(model_path, None)
            if not self._retries:
                self.stop_background_pool()  # nothing more to do there: give its memory back
        self._keep_facts(model_path, key, facts)
        if self.cap("workspace.code_lens.refresh_support", False):
            try:
                self.workspace_code_lens_refresh(None)
            except Exception:
                pass

    def _keep_facts(self, model_path: str, key: tuple, facts) -> None:
        """Cache ``facts`` under ``key``: those of the latest :data:`FACTS_PER_MODEL` texts of
        each model (a big model's facts hold a count per feature: automotive2_1's, 1,261-digit
        counts of 14,010 features, weigh 15 MB; one per edit grew the server by 300 MB)."""
        self.cache[key] = facts
        self._remember(key)
        keys = self._facts_keys.setdefault(model_path, [])
        if key in keys:
            keys.remove(key)
        keys.append(key)
        for old in keys[:-FACTS_PER_MODEL]:
            self.cache.pop(old, None)
        del keys[:-FACTS_PER_MODEL]

    async def _stored_facts(self, model_path: str, sources: dict[str, str], ckey: str):
        """The facts stored on disk for this content (:func:`.facts.stored_model_facts`), or
        None; one look-up per content, shared by concurrent callers."""
        if ("facts-stored-miss", ckey) in self.cache:
            return None
        running = self._facts_lookups.get(ckey)
        first = running is None
        if first:
            running = asyncio.ensure_future(self.run_in_thread(_facts.stored_model_facts, model_path, sources))
            running.add_done_callback(_consume)
            self._facts_lookups[ckey] = running
        try:
            got = await asyncio.shield(running)
        except asyncio.CancelledError:
            raise
        except Exception:
            log.exception("reading the stored facts of %s failed", model_path)
            got = None
        finally:
            if running.done():
                self._facts_lookups.pop(ckey, None)
        if got is None:
            self.cache[("facts-stored-miss", ckey)] = True
            self._remember(("facts-stored-miss", ckey))
        elif first:
            log.info("facts of %s: read from the disk cache in %.3f s", model_path, got.seconds)
        return got

    async def stored_feature_hover(self, path: str, pos):
        """(markdown, span) of the feature declared at ``pos`` from the facts stored for the
        current text of ``path`` (a model that reads no other file: its text alone decides
        it), before any parse here; None when nothing stored answers there."""
        text = self.read_file(path)
        if text is None:
            return None
        sources = {path: text}
        ckey = content_key(f"{path}\0{text}")  # (model_facts's key of these sources)
        facts = await self._stored_facts(path, sources, ckey)
        if facts is None or not facts.hover:
            return None
        key = ("facts", ckey, self.settings.time_budget)
        if key not in self.cache:
            self._keep_facts(path, key, facts)
        return _facts.hover_at(facts.hover, pos)

    async def count_under(self, model_path: str, formula, wait: Optional[float] = None):
        sources = await self.model_sources(model_path)
        if sources is None:
            return None
        key = ("count", content_key(*sorted(f"{k}\0{v}" for k, v in sources.items())), str(formula))
        if key in self.cache:
            return self.cache[key]
        budget = self.settings.time_budget
        cfut = self.proc_pool.submit(_facts.count_under, model_path, sources, formula, budget)
        afut = asyncio.wrap_future(cfut)
        afut.add_done_callback(_consume)
        try:
            n = await asyncio.wait_for(asyncio.shield(afut), wait or budget + 5)
        except asyncio.TimeoutError:
            return None
        except Exception:
            log.exception("count failed")
            return None
        self.cache[key] = n
        self._remember(key)
        return n

