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
from concurrent.futures.process import BrokenProcessPool
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from ..base.diagnostics import Diagnostic
from ..project import budget as file_budget
from ..project import facts as _facts
from . import checks
from .documents import content_key
from .workers import _consume, release_memory

TRIM_DELAY = 1.0  # seconds after a throttled trim: the next try, if the checks are idle (at most one a second)

FACTS_POLL = 0.3  # seconds: how often the server asks whether a model's compilation is done

log = logging.getLogger("tvl_lsp.server")


@dataclass
class CheckResult:
    version: Optional[int]
    phase: str  # "syntax" | "full"
    diagnostics: list[Diagnostic]


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
        self._facts_futures: dict[str, asyncio.Future] = {}
        self._facts_queued: dict[str, tuple] = {}
        self._facts_submitted: dict[str, asyncio.Event] = {}  # set once a count is in a pool's queue
        self._facts_lookups: dict[str, asyncio.Future] = {}  # content key -> read of the stored facts
        self._trim_handle: Optional[asyncio.TimerHandle] = None  # a memory trim waiting for idle checks

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
                try:
                    # the parse requests share (hover, outline, model_sources) when one of
                    # this text is under way: one parse per text at a time
                    parsed = await asyncio.shield(self.parse_task(path, kind, text))
                    diags = list(getattr(parsed, "diagnostics", []) or [])
                    log.info("syntax of %s: %d diagnostics", path, len(diags))
                except Exception:
                    log.exception("syntax check of %s failed", path)
                    diags = []
                doc = self.docs.get(uri)
                cur = self.results.get(uri)
                if doc is not None and doc.version == version and not (
                        cur and cur.version == version and cur.phase == "full"):
                    self.results[uri] = CheckResult(version, "syntax", diags)
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
            self.results[uri] = CheckResult(version, "full", diags)
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
            sources = await self.model_sources(model_path)
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
        # a count queued for an older text of this model is stale: drop it
        old = self._facts_queued.get(model_path)
        if old is not None and old[0] != key[1]:
            old[1].cancel()
        fut = self._facts_futures.get(key[1])
        if fut is None:
            # counted before (this very content, in any process): the facts stored on disk,
            # read in a thread -- no parse, encoding or circuit in a worker process
            stored = await self._stored_facts(model_path, sources, key[1])
            if stored is not None:
                self.cache[key] = stored
                self._remember(key)
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
                    end = loop.time() + budget + 30

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
                            return _facts.ModelFacts(error=f"no count within {budget:g} s")
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
                        facts = await asyncio.wait_for(asyncio.shield(afut), budget + 30)
                except (cf.CancelledError, asyncio.CancelledError):
                    if cfut is not None and cfut.cancelled():
                        return _facts.ModelFacts(error="cancelled: the model changed")
                    raise
                except Exception as e:
                    facts = _facts.ModelFacts(error=f"{type(e).__name__}: {e}")
                    if pool_of == "count" and isinstance(e, (BrokenProcessPool, asyncio.TimeoutError)):
                        self.restart_proc_pool()
                    elif pool_of == "check" and isinstance(e, asyncio.TimeoutError):
                        self.restart_check_pool()  # (a broken one: the next check restarts it)
                    return facts
                # (a count that ran out of its budget is cached too: the same text and
                # budget would run out again)
                self.cache[key] = facts
                self._remember(key)
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
            self.cache[key] = facts
            self._remember(key)
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

