"""``tvl-lsp ui``: the configurator in the browser, served on the loopback interface.

Security model (a local server that can write files must not be drivable by other web pages):

- binds 127.0.0.1 only;
- every request carries the per-run token (``?token=`` on the page and its assets, the
  ``X-TVL-Token`` header on the API); a wrong or missing token gets 403;
- the ``Host`` header must be ``127.0.0.1:PORT`` or ``localhost:PORT`` (DNS rebinding: a foreign
  name resolving to 127.0.0.1 gets 403), and an API call with an ``Origin`` must come from there;
- the API answers only POST with a JSON body of at most 1 MB, never CORS;
- generated files are written inside the workspace only (:func:`tvl_lsp.configurator.api.write_files`);
- file excerpts are served only for the session's own files inside the workspace.

Limits (a local page, but any local process can connect): a listen backlog of
``BACKLOG``; at most ``MAX_CONNECTIONS`` connections served at once (more are answered 503 at
once, without a thread); each request must arrive within ``REQUEST_SECONDS`` (request line,
headers and body: a slow sender is cut off, not waited for) and every socket operation within
``SOCKET_SECONDS``; a body nested deeper than ``MAX_DEPTH`` is answered 400; a request with two
``Host`` (or ``Content-Length``, ``Origin``, token...) headers, or with ``Transfer-Encoding``, is
answered 400.  Every error is a JSON ``{"error": ...}`` (or one line of text before the API
route is known), never a dropped connection or a traceback.

Standard library only (``http.server.ThreadingHTTPServer``): the API is a handful of JSON
routes on loopback, nothing a framework would add to.
"""

from __future__ import annotations

import hmac
import io
import json
import mimetypes
import os
import secrets
import sys
import threading
import time
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Optional
from urllib.parse import parse_qs, urlsplit

from ..base.files import read_bytes, read_text
from ..base.pools import kill_pool
from .httplimits import (REQUEST_SECONDS, SINGLE_HEADERS, SOCKET_SECONDS, BoundedServer, DeadlineRaw,
                         os_message, os_status, parse_body)
from ..configurator import Session, SessionError, configurable_models
from ..configurator import api
from ..project.workspace import find_workspace_root, is_launch, is_model, norm

STATIC = Path(__file__).with_name("static")
MAX_BODY = 1 << 20
TOKEN_PLACEHOLDER = "__TVL_TOKEN__"
CHANGES = ("decide", "set", "reset", "complete", "load")  # the requests that change the decisions
CSP = ("default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
       "connect-src 'self'; font-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'")


class App:
    """The state behind the server: one :class:`Session` per model, the decisions per model."""

    def __init__(self, path: str, folder: Optional[str] = None, limit: int = 100,
                 project_files: Optional[list[str]] = None, compile_budget: Optional[float] = None):
        path = norm(path)
        if not os.path.exists(path):
            raise SessionError(f"{path} does not exist")
        self.roots = [find_workspace_root(path)]
        self.folder = folder
        self.limit = limit
        self.project_files = [norm(p) for p in project_files] if project_files else None
        self.lock = threading.Lock()
        self.sessions: dict[str, Session] = {}
        self.decisions: dict[str, dict[str, bool]] = {}
        self.versions: dict[str, int] = {}
        self.changing: dict[str, threading.Lock] = {}  # model -> held while its decisions change
        self.pairings: dict[str, str] = {}  # model -> the launch file chosen on the page
        self.compile_budget = compile_budget
        self.initial: Optional[str] = None
        if is_model(path):
            self.initial = path
        elif is_launch(path):
            s = Session.open(path, self.roots, project_files=project_files)
            if compile_budget is not None:
                s.compile_budget = compile_budget
            self.sessions[s.model_path] = s
            self.initial = s.model_path
        self._targets: Optional[list[dict]] = None
        self.pool = None
        self.pool_lock = threading.Lock()  # not self.lock: that one is held while a session opens
        self.closed = False
        self.active = 0  # requests being answered
        self.checks: dict = {}

    def targets(self) -> dict:
        if self._targets is None:
            self._targets = configurable_models(self.roots)
        initial = self.initial
        if initial is None:
            with_launch = [t["model"] for t in self._targets if t["launches"]]
            initial = (with_launch or [t["model"] for t in self._targets] or [None])[0]
        return {"roots": self.roots, "models": self._targets, "initial": initial}

    def warm_up(self) -> None:
        """Open the first session ahead of the first page load, check its files in a worker
        process (the checks would hold the interpreter while the user clicks), build its graph."""
        def run():
            try:
                s = self.session(None)
                s.compile_status()  # compile the model for the counts (d4, in the background)
                self.check_in_background(s)
                s.graph  # noqa: B018 (built on first use)
            except Exception:
                pass  # the page will say what is wrong
        threading.Thread(target=run, name="tvl-ui-warm-up", daemon=True).start()

    def check_in_background(self, s: Session):
        from concurrent.futures import ProcessPoolExecutor
        import multiprocessing as mp
        from ..configurator.session import check_files
        with self.pool_lock:
            if self.closed:
                raise RuntimeError("the server is stopping")
            fut = self.checks.get(s.model_path)
            if fut is None:
                if self.pool is None:
                    from ..base.children import watch_parent  # (dies with this server)
                    self.pool = ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("spawn"),
                                                    initializer=watch_parent)
                fut = self.pool.submit(check_files, [s.model_path] + s.launches, s.roots)
                self.checks[s.model_path] = fut
        return fut

    def close(self) -> None:
        from ..analysis.counting.service import cancel_all
        with self.pool_lock:
            self.closed = True
            pool, self.pool = self.pool, None
        # requests in flight see the stop as a cancellation (a count in a pyganak process ends
        # it); background compilations kill their d4 processes; both are waited for, briefly,
        # so that no child outlives the server
        cancel_all(wait=3.0)
        deadline = time.monotonic() + 3.0
        while self.active and time.monotonic() < deadline:
            time.sleep(0.02)
        from ..base.children import kill_all
        kill_all()  # whatever counting process is still running (d4, pyganak): now, with its group
        kill_pool(pool)

    def session(self, model: Optional[str]) -> Session:
        if not isinstance(model, str) or not model:
            model = self.targets()["initial"]
            if model is None:
                raise SessionError("no TVL model in this workspace")
        model = norm(model)
        from ..project.generate import inside
        if not inside(model, self.roots):
            raise SessionError("the model is outside the workspace")
        with self.lock:
            s = self.sessions.get(model)
            if s is None:
                launch = self.pairings.get(model)
                s = self.sessions[model] = Session(model, self.roots, project_files=self.project_files,
                                                   launches=[launch] if launch else None)
                if self.compile_budget is not None:
                    s.compile_budget = self.compile_budget
                self.decisions.setdefault(model, {})
            return s

    def pair(self, model: Optional[str], launch: object) -> dict:
        """Configure ``launch`` (a launch file of the workspace) with the model from now on: a
        new session, the decisions kept where the model still accepts them."""
        from ..project.generate import inside
        from ..project.workspace import is_launch as _is_launch
        s = self.session(model)
        if not isinstance(launch, str) or not launch:
            raise SessionError("pair needs the launch file to configure")
        launch = norm(launch)
        if not inside(launch, self.roots) or not _is_launch(launch) or not os.path.isfile(launch):
            raise SessionError(f"{launch} is not a launch file of this workspace")
        with self.lock:
            self.pairings[s.model_path] = launch
            for t in self._targets or []:
                if t["model"] == s.model_path:
                    t["launches"] = [launch]
            self.sessions.pop(s.model_path, None)
            self.checks.pop(s.model_path, None)
            self.versions[s.model_path] = self.versions.get(s.model_path, 0) + 1
        s2 = self.session(s.model_path)
        try:
            self.check_in_background(s2)
        except RuntimeError:
            pass
        return {"model": s2.model_path, "launch": s2.launch}

    def request(self, op: str, body: dict) -> dict:
        if op == "targets":
            return self.targets()
        if op == "pair":
            return self.pair(body.get("model"), body.get("launch"))
        s = self.session(body.get("model"))
        key = s.model_path
        if op in CHANGES:
            # one change of a model's decisions at a time, each from the decisions the one before
            # left: two clicks answered at once would both start from the same decisions and the
            # second would drop the first's
            with self.lock:
                changing = self.changing.setdefault(key, threading.Lock())
            with changing:
                return self._request(s, key, op, body)
        return self._request(s, key, op, body)

    def _request(self, s: Session, key: str, op: str, body: dict) -> dict:
        with self.lock:
            decisions = dict(self.decisions.get(key, {}))
            version = self.versions.get(key, 0)

        def cancelled() -> bool:
            return self.closed or self.versions.get(key, 0) != version

        if op == "problems" and s._problems is None:
            try:
                s.set_problems(self.check_in_background(s).result(timeout=300))
            except Exception:
                pass  # checked in this process instead

        with self.pool_lock:
            self.active += 1
        try:
            out, new = api.handle(s, op, body, decisions, cancel=cancelled, generate_folder=self.folder,
                                  generate_limit=self.limit)
        finally:
            with self.pool_lock:
                self.active -= 1
        if new != decisions:
            with self.lock:
                self.decisions[key] = new
                self.versions[key] = version + 1
        if op == "generate" and body.get("write", True):
            out["written"] = api.write_files(s, out["files"])
        if op == "save" and body.get("write", True):
            out["written"] = api.write_files(s, [{"path": out["path"], "text": out["text"]}])
        out["model"] = out.get("model", key) if op == "model" else key
        return out


class Handler(BaseHTTPRequestHandler):
    server_version = "tvl-lsp-ui"
    sys_version = ""
    protocol_version = "HTTP/1.1"

    # set on the class by make_server
    app: App
    token: str
    port: int
    verbose: bool = False

    timeout = SOCKET_SECONDS  # each socket operation (StreamRequestHandler.setup applies it)

    def log_message(self, fmt, *args):  # quiet unless asked
        if self.verbose:
            sys.stderr.write("tvl-lsp ui: " + (fmt % args) + "\n")

    def setup(self) -> None:
        super().setup()
        self._raw = DeadlineRaw(self.connection)
        self.rfile = io.BufferedReader(self._raw, 64 * 1024)

    def handle_one_request(self) -> None:
        # the whole request (line, headers, body) must arrive within REQUEST_SECONDS of its
        # first byte being waited for: a sender that trickles bytes is cut off (slowloris)
        self._raw.deadline = time.monotonic() + REQUEST_SECONDS
        try:
            super().handle_one_request()
        except TimeoutError:
            self.close_connection = True
        except (ConnectionError, OSError):
            self.close_connection = True

    def _duplicate_header(self) -> Optional[str]:
        for name in SINGLE_HEADERS:
            if len(self.headers.get_all(name) or []) > 1:
                return name
        return None

    # ------------------------------------------------------------------ checks
    def _allowed_hosts(self) -> set[str]:
        return {f"127.0.0.1:{self.port}", f"localhost:{self.port}"}

    def _host_ok(self) -> bool:
        return (self.headers.get("Host") or "").strip().lower() in self._allowed_hosts()

    def _origin_ok(self) -> bool:
        origin = self.headers.get("Origin")
        if origin is None:
            return True
        return origin.strip().lower() in {"http://" + h for h in self._allowed_hosts()}

    def _token_ok(self, query: dict) -> bool:
        given = self.headers.get("X-TVL-Token") or (query.get("token") or [""])[0]
        return bool(given) and hmac.compare_digest(given.encode(), self.token.encode())

    def _send(self, status: int, body: bytes, ctype: str, extra: Optional[dict] = None) -> None:
        try:
            self.connection.settimeout(SOCKET_SECONDS)  # (reading may have left it shorter)
        except OSError:
            pass
        self.send_response(status)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("Referrer-Policy", "no-referrer")
        self.send_header("X-Frame-Options", "DENY")
        self.send_header("Content-Security-Policy", CSP)
        for k, v in (extra or {}).items():
            self.send_header(k, v)
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(body)

    def _json(self, status: int, obj) -> None:
        self._send(status, json.dumps(obj).encode(), "application/json; charset=utf-8")

    def _refuse(self, status: int, msg: str) -> None:
        self._send(status, (msg + "\n").encode(), "text/plain; charset=utf-8")

    def _gate(self) -> Optional[dict]:
        """The query, or None after refusing the request."""
        dup = self._duplicate_header()
        if dup is not None:
            self.close_connection = True
            self._refuse(HTTPStatus.BAD_REQUEST, f"bad request: more than one {dup} header")
            return None
        if self.headers.get("Transfer-Encoding") is not None:
            self.close_connection = True
            self._refuse(HTTPStatus.NOT_IMPLEMENTED, "Transfer-Encoding is not supported: send a Content-Length")
            return None
        if not self._host_ok():
            self._refuse(HTTPStatus.FORBIDDEN, "forbidden: unexpected Host header")
            return None
        query = parse_qs(urlsplit(self.path).query)
        if not self._token_ok(query):
            self._refuse(HTTPStatus.FORBIDDEN, "forbidden: missing or wrong token")
            return None
        return query

    # ------------------------------------------------------------------ routes
    def do_GET(self):
        if self._gate() is None:
            return
        route = urlsplit(self.path).path
        if route in ("/", "/index.html"):
            html = read_text(str(STATIC / "index.html")).replace(TOKEN_PLACEHOLDER, self.token)
            self._send(HTTPStatus.OK, html.encode(), "text/html; charset=utf-8")
            return
        if route.startswith("/static/"):
            name = route[len("/static/"):]
            f = (STATIC / name).resolve()
            if "/" in name or name.startswith(".") or not f.is_file() or f.parent != STATIC.resolve():
                self._refuse(HTTPStatus.NOT_FOUND, "not found")
                return
            ctype = mimetypes.guess_type(name)[0] or "application/octet-stream"
            if ctype.startswith("text/") or ctype.endswith("javascript"):
                ctype += "; charset=utf-8"
            self._send(HTTPStatus.OK, read_bytes(str(f)), ctype)
            return
        self._refuse(HTTPStatus.NOT_FOUND, "not found")

    do_HEAD = do_GET

    def do_POST(self):
        if self._gate() is None:
            return
        if not self._origin_ok():
            self._refuse(HTTPStatus.FORBIDDEN, "forbidden: cross-origin request")
            return
        route = urlsplit(self.path).path
        if not route.startswith("/api/"):
            self._refuse(HTTPStatus.NOT_FOUND, "not found")
            return
        op = route[len("/api/"):]
        ctype = (self.headers.get("Content-Type") or "").split(";")[0].strip().lower()
        if ctype != "application/json":
            self._refuse(HTTPStatus.UNSUPPORTED_MEDIA_TYPE, "the API takes application/json")
            return
        length = (self.headers.get("Content-Length") or "0").strip()
        n = int(length) if length.isdigit() and len(length) <= 12 else -1
        if n < 0:
            self.close_connection = True
            self._json(HTTPStatus.BAD_REQUEST, {"error": "a request needs a valid Content-Length"})
            return
        if n > MAX_BODY:
            self.close_connection = True  # (the body is not read)
            self._json(HTTPStatus.REQUEST_ENTITY_TOO_LARGE, {"error": f"the request body is larger than {MAX_BODY} bytes"})
            return
        try:
            data = self.rfile.read(n)
        except OSError:
            self.close_connection = True
            return
        if len(data) < n:
            self.close_connection = True
            self._json(HTTPStatus.BAD_REQUEST, {"error": "the request body is shorter than its Content-Length"})
            return
        try:
            body = parse_body(data)
        except ValueError as e:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(e)})
            return
        if op not in api.OPS and op not in ("targets", "pair"):
            self._json(HTTPStatus.NOT_FOUND, {"error": f"unknown request {op!r}"})
            return
        try:
            out = self.app.request(op, body)
        except SessionError as e:
            self._json(HTTPStatus.UNPROCESSABLE_ENTITY, {"error": str(e)})
            return
        except OSError as e:  # a file that cannot be written (a link, a full disk): one line
            self._json(os_status(e), {"error": os_message(e)})
            return
        except RecursionError:
            self._json(HTTPStatus.BAD_REQUEST, {"error": "the request is nested too deeply"})
            return
        except Exception as e:  # a bug: say so, keep serving
            self._json(HTTPStatus.INTERNAL_SERVER_ERROR, {"error": f"internal error: {type(e).__name__}: {e}"})
            return
        self._json(HTTPStatus.OK, out)

    def do_PUT(self):
        if self._gate() is None:
            return
        self._refuse(HTTPStatus.METHOD_NOT_ALLOWED, "method not allowed")

    do_DELETE = do_PATCH = do_OPTIONS = do_PUT


class UiServer(BoundedServer, ThreadingHTTPServer):
    daemon_threads = True
    allow_reuse_address = True
    def server_close(self) -> None:
        super().server_close()
        app = getattr(self.RequestHandlerClass, "app", None)
        if app is not None:
            app.close()


def make_server(path: str, port: int = 0, folder: Optional[str] = None, token: Optional[str] = None,
                verbose: bool = False, limit: int = 100,
                project_files: Optional[list[str]] = None,
                compile_budget: Optional[float] = None) -> tuple[UiServer, str]:
    """The server (not yet serving) and its URL (with the token)."""
    from ..configurator.preload import import_core
    import_core()  # before the warm-up and request threads: concurrent first imports are not safe
    app = App(path, folder, limit, project_files, compile_budget)
    token = token or secrets.token_urlsafe(24)
    handler = type("BoundHandler", (Handler,), {"app": app, "token": token, "verbose": verbose})
    httpd = UiServer(("127.0.0.1", port), handler)
    handler.port = httpd.server_address[1]
    url = f"http://127.0.0.1:{handler.port}/?token={token}"
    app.warm_up()
    return httpd, url
