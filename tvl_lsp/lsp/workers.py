"""Work off the event loop: a thread pool for parses, two worker processes (the solver-backed
check, and counts / the configurator) at the server's priority -- they compute what the user
waits for -- and a third, niced one started only for background work (a count retried with a
longer budget, :mod:`.procinit`), all dying with the server; ``$/progress`` reporting, and the
event-loop watchdog (a debug aid).

Solvers and counters hold the GIL, so anything that may take more than a few milliseconds
runs in a worker process, never in a thread of the server.  :class:`Workers` is a mixin of
:class:`~tvl_lsp.lsp.server.TvlLanguageServer`; its state is set up by
:meth:`Workers._init_workers`.
"""

from __future__ import annotations

import asyncio
import concurrent.futures as cf
import os
import sys
import threading
import time
from typing import Optional

from lsprotocol import types

from ..base.pools import kill_pool
from .procinit import BACKGROUND_NICE, _warm, _worker_init


class Workers:
    """Thread and process pools, progress (a mixin of the server)."""

    def _init_workers(self) -> None:
        self.executor = cf.ThreadPoolExecutor(max_workers=2, thread_name_prefix="tvl-check")
        self._proc_pool: Optional[cf.ProcessPoolExecutor] = None
        self._check_pool: Optional[cf.ProcessPoolExecutor] = None
        self._background_pool: Optional[cf.ProcessPoolExecutor] = None
        self._proc_lock = threading.Lock()
        self.progress_counter = 0

    async def run_in_thread(self, fn, *args):
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self.executor, fn, *args)

    @staticmethod
    def _new_pool(nice: int = 0) -> cf.ProcessPoolExecutor:
        import multiprocessing as mp
        return cf.ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("spawn"),
                                      initializer=_worker_init, initargs=(nice,))

    @property
    def proc_pool(self) -> cf.ProcessPoolExecutor:
        """The count process: counts, the configurator, the graph (the user waits for them)."""
        with self._proc_lock:
            if self._proc_pool is None:
                self._proc_pool = self._new_pool()
            return self._proc_pool

    @property
    def check_pool(self) -> cf.ProcessPoolExecutor:
        """The check process: the solver-backed checks of open documents, first counts."""
        with self._proc_lock:
            if self._check_pool is None:
                self._check_pool = self._new_pool()
            return self._check_pool

    @property
    def background_pool(self) -> cf.ProcessPoolExecutor:
        """The niced process of work nobody waits for yet (counts retried with a longer budget);
        started on demand, stopped when its work is done or stale
        (:meth:`stop_background_pool`): it holds a big model's memory only meanwhile."""
        with self._proc_lock:
            if self._background_pool is None:
                self._background_pool = self._new_pool(BACKGROUND_NICE)
            return self._background_pool

    def stop_background_pool(self) -> None:
        with self._proc_lock:
            pool, self._background_pool = self._background_pool, None
        kill_pool(pool)

    def restart_check_pool(self) -> None:
        with self._proc_lock:
            pool, self._check_pool = self._check_pool, None
        kill_pool(pool)

    def warm_up(self) -> None:
        """Start the worker processes now, so the first check / count does not pay for it."""
        try:
            self.proc_pool.submit(_warm)
            self.check_pool.submit(_warm)
        except Exception:
            pass

    def restart_proc_pool(self) -> None:
        with self._proc_lock:
            pool, self._proc_pool = self._proc_pool, None
        kill_pool(pool)

    # ------------------------------------------------------------ progress
    async def with_progress(self, title: str, coro):
        """Run ``coro`` with a ``$/progress`` bar when the client supports it."""
        if not self.supports_progress:
            return await coro
        self.progress_counter += 1
        token = f"tvl-lsp-{os.getpid()}-{self.progress_counter}"
        # the work starts now, not after the client's answer to the progress request (a
        # round trip: the counts of a model compiled before would be queued behind its check)
        task = asyncio.ensure_future(coro)
        try:
            await asyncio.wait_for(self.work_done_progress.create_async(token), 2)
        except asyncio.CancelledError:
            task.cancel()
            raise
        except Exception:
            return await task
        if task.done():
            return task.result()
        self.work_done_progress.begin(token, types.WorkDoneProgressBegin(title=title, cancellable=False))
        try:
            return await task
        finally:
            self.work_done_progress.end(token, types.WorkDoneProgressEnd(message="done"))


_RELEASED = [0.0]


def release_memory(every: float = 5.0) -> bool:
    """Collect the garbage cycles, then give the free memory at the top and inside the heap back
    to the system (glibc's ``malloc_trim``), at most every ``every`` seconds: called when the
    server goes idle, so the peak of a big document's analysis does not stay in its RSS for
    good.  The collection comes first: a big document's parse (trees with parent links: cycles)
    reaches the oldest generation, which Python collects only once it has grown by a quarter,
    so its arenas stayed allocated (fuzz seed 3: +47-62 % server RSS at the end, +25 % with it)."""
    now = time.monotonic()
    if now - _RELEASED[0] < every:
        return False
    _RELEASED[0] = now
    import gc
    gc.collect()
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes
        return bool(ctypes.CDLL(None).malloc_trim(0))
    except (OSError, AttributeError, TypeError):
        return False


def _consume(fut) -> None:
    """Retrieve a future's exception so that asyncio does not log it as never retrieved."""
    if not fut.cancelled():
        fut.exception()


def start_watchdog(path: str, threshold: float = 0.3) -> None:
    """Debug aid (``TVL_LSP_WATCHDOG=FILE``): log the event loop's stack whenever it is
    blocked for more than ``threshold`` seconds."""
    import traceback
    main_id = threading.get_ident()
    beat = [time.monotonic()]

    async def heartbeat():
        while True:
            beat[0] = time.monotonic()
            await asyncio.sleep(0.05)

    def watch():
        while True:
            time.sleep(0.1)
            stalled = time.monotonic() - beat[0]
            if stalled > threshold:
                frame = sys._current_frames().get(main_id)
                from ..base.safewrite import open_append
                try:  # (a regular file: never a FIFO that would block the watchdog)
                    with open_append(path) as fh:
                        fh.write(f"--- loop blocked {stalled:.2f}s\n")
                        fh.write("".join(traceback.format_stack(frame)[-12:]))
                except OSError:
                    return
    threading.Thread(target=watch, daemon=True).start()
    _WATCHDOG.append(heartbeat)


_WATCHDOG: list = []

