"""``tvl-lsp ui [PATH] [--port N] [--no-browser] [--folder DIR] [--project FILE]``: the
configurator in the browser.

Serves the feature diagram, the computation graph and the filtered problems of the workspace
at PATH (a folder, a model or a generic launch file; default: the current folder) on
127.0.0.1, prints the URL -- with this run's token -- on the first line of stdout, and opens
the browser unless ``--no-browser``.  Ctrl-C or SIGTERM stops it.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys


COUNT_BUDGET = 120.0  # seconds: models d4 compiles at all take a few seconds (bench/README.md)


class _Stop(Exception):
    pass


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp ui",
                                 description="The configurator (feature diagram, computation graph, problems) "
                                             "in the browser, on 127.0.0.1.")
    ap.add_argument("path", nargs="?", default=".", help="workspace folder, model or generic launch file")
    ap.add_argument("--port", type=int, default=0, help="port on 127.0.0.1 (default: a free one)")
    ap.add_argument("--no-browser", action="store_true", help="print the URL only")
    ap.add_argument("--folder", help="where Generate writes configuration launch files (absolute, or "
                                     "relative to the launch file's package; default: configs)")
    ap.add_argument("--project", action="append", metavar="FILE",
                    help="a YAML file with the graph's node hints (HAROS `nodes:`; repeatable; default: the "
                         "workspace's HAROS project files)")
    ap.add_argument("--limit", type=int, default=100, help="at most this many files per Generate (default 100)")
    ap.add_argument("--count-budget", type=float, default=COUNT_BUDGET, metavar="SECONDS",
                    help=f"how long d4 may compile a model for the counts (default {COUNT_BUDGET:g} s); past it the "
                         "configurator works on without counts")
    ap.add_argument("--verbose", "-v", action="store_true", help="log every request on stderr")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    if not 0 <= args.port <= 65535:
        print("tvl-lsp ui: --port must be between 0 and 65535", file=sys.stderr)
        return 2

    from ..configurator import SessionError
    from .server import make_server
    try:
        httpd, url = make_server(args.path, args.port, args.folder, verbose=args.verbose, limit=max(1, args.limit),
                                 project_files=args.project, compile_budget=max(0.01, args.count_budget))
    except SessionError as ex:
        print(f"tvl-lsp ui: {ex}", file=sys.stderr)
        return 2
    except OSError as ex:
        print(f"tvl-lsp ui: cannot listen on 127.0.0.1:{args.port}: {ex.strerror or ex}", file=sys.stderr)
        return 2
    print(url, flush=True)

    def stop(signum, frame):
        raise _Stop()

    signal.signal(signal.SIGTERM, stop)
    if not args.no_browser:
        import webbrowser
        try:
            webbrowser.open(url)
        except Exception:
            pass
    try:
        httpd.serve_forever(poll_interval=0.2)
    except (KeyboardInterrupt, _Stop):
        pass
    finally:
        _close_within(httpd, CLOSE_SECONDS)
    print("tvl-lsp ui: stopped", file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    # nothing is left to save; do not wait for a background session build or a graph layout
    # still running in a thread
    os._exit(0)


CLOSE_SECONDS = 10.0


def _close_within(httpd, seconds: float) -> None:
    """Stop the server and its checking worker process, then run the finalizers that unregister
    the pool's semaphores (os._exit skips them, and the resource tracker warned of "leaked
    semaphore objects" after every Ctrl-C) -- in a thread, for at most ``seconds``: a worker
    still being spawned when the stop came is waited for by the pool's shutdown, and the
    process must stop all the same (CI saw it outlive a 20 s wait once)."""
    import threading

    def close():
        try:
            httpd.server_close()  # stops the checking worker process too
        except Exception:
            pass
        try:
            from multiprocessing import util as mp_util
            mp_util._run_finalizers(0)
        except Exception:
            pass
        try:  # the semaphore tracker: stopped and reaped, not left behind (a zombie where no init reaps)
            from multiprocessing import resource_tracker
            resource_tracker._resource_tracker._stop()
        except Exception:
            pass
    t = threading.Thread(target=close, name="tvl-lsp-ui-close", daemon=True)
    t.start()
    t.join(seconds)
