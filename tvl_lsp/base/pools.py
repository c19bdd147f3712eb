"""Stopping a process pool at once, without leftovers."""

from __future__ import annotations


def kill_processes(pool) -> None:
    """SIGKILL a pool's processes, nothing else (no lock, no waiting: safe in a signal handler
    of a process about to exit)."""
    try:
        for p in list((getattr(pool, "_processes", None) or {}).values()):
            p.kill()
    except Exception:
        pass


def kill_pool(pool) -> None:
    """Kill a ``concurrent.futures.ProcessPoolExecutor``'s processes, then shut it down and wait
    for its manager thread (quick: its processes are gone).  Waiting is what closes the pool's
    queues, whose semaphores otherwise stay registered with multiprocessing's resource tracker
    ("leaked semaphore objects" at exit)."""
    if pool is None:
        return
    try:
        for p in list((getattr(pool, "_processes", None) or {}).values()):
            p.kill()
    except Exception:
        pass
    try:
        pool.shutdown(wait=True, cancel_futures=True)
    except Exception:
        pass
