"""``tvl-lsp ui``'s HTTP host probed directly: token, Host header, Origin, loopback, writes
inside the workspace, clean stop."""

from __future__ import annotations

import http.client
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from urllib.parse import urlsplit

import pytest

from tvl_lsp.ui.server import make_server

REPO = Path(__file__).resolve().parent.parent


@pytest.fixture()
def ws(tmp_path):
    d = tmp_path / "ws"
    shutil.copytree(REPO / "examples" / "ws", d)
    return d


@pytest.fixture()
def server(ws):
    httpd, url = make_server(str(ws), 0)
    t = threading.Thread(target=httpd.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    t.start()
    parts = urlsplit(url)
    token = parts.query.split("=", 1)[1]
    yield httpd, parts.port, token, url
    httpd.shutdown()
    httpd.server_close()


def raw(port, method, path, headers=None, body=None):
    """A request with exactly these headers (http.client adds Host unless given)."""
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    hdrs = dict(headers or {})
    c.putrequest(method, path, skip_host="Host" in hdrs, skip_accept_encoding=True)
    data = json.dumps(body).encode() if body is not None else None
    if data is not None:
        hdrs.setdefault("Content-Type", "application/json")
        hdrs["Content-Length"] = str(len(data))
    for k, v in hdrs.items():
        c.putheader(k, v)
    c.endheaders(data)
    r = c.getresponse()
    out = r.status, dict(r.getheaders()), r.read()
    c.close()
    return out


def api(port, token, op, body, **extra):
    h = {"Host": f"127.0.0.1:{port}", "X-TVL-Token": token}
    h.update(extra)
    return raw(port, "POST", f"/api/{op}", h, body)


def test_binds_loopback_only(server):
    httpd, port, token, url = server
    assert httpd.server_address[0] == "127.0.0.1"
    assert url.startswith(f"http://127.0.0.1:{port}/?token=") and len(token) >= 24


def test_page_needs_the_token(server):
    _, port, token, _ = server
    host = {"Host": f"127.0.0.1:{port}"}
    st, h, body = raw(port, "GET", f"/?token={token}", host)
    assert st == 200 and b"<title>TVL configurator</title>" in body and token.encode() in body
    assert "default-src 'none'" in h["Content-Security-Policy"] and h["X-Frame-Options"] == "DENY"
    assert raw(port, "GET", "/", host)[0] == 403
    assert raw(port, "GET", "/?token=wrong", host)[0] == 403
    assert raw(port, "GET", f"/?token={token[:-1]}", host)[0] == 403
    assert raw(port, "GET", "/static/app.js", host)[0] == 403
    st, h, body = raw(port, "GET", f"/static/app.js?token={token}", host)
    assert st == 200 and h["Content-Type"].split(";")[0] in ("text/javascript", "application/javascript")
    assert raw(port, "GET", f"/static/elk-worker.js?token={token}", host)[0] == 200


def test_api_needs_the_token(server):
    _, port, token, _ = server
    assert api(port, token, "targets", {})[0] == 200
    assert api(port, "", "targets", {})[0] == 403
    assert api(port, token + "x", "targets", {})[0] == 403
    # the token in the query works for the API too, a token in a cookie does not
    assert raw(port, "POST", "/api/targets", {"Host": f"127.0.0.1:{port}", "Cookie": f"token={token}"}, {})[0] == 403


@pytest.mark.parametrize("host", ["evil.example:{port}", "127.0.0.1:{other}", "127.0.0.1", "localhost.evil.example:{port}",
                                  "[::1]:{port}", "0.0.0.0:{port}", ""])
def test_foreign_host_header_is_refused(server, host):
    """DNS rebinding: a page of evil.example resolving to 127.0.0.1 sends Host: evil.example."""
    _, port, token, _ = server
    h = host.format(port=port, other=port + 1)
    st, _, body = raw(port, "GET", f"/?token={token}", {"Host": h})
    assert st == 403 and b"Host" in body
    assert api(port, token, "targets", {}, Host=h)[0] == 403


def test_localhost_name_is_accepted(server):
    _, port, token, _ = server
    assert raw(port, "GET", f"/?token={token}", {"Host": f"localhost:{port}"})[0] == 200


def test_cross_origin_post_is_refused(server):
    _, port, token, _ = server
    assert api(port, token, "targets", {}, Origin="http://evil.example")[0] == 403
    assert api(port, token, "targets", {}, Origin=f"http://127.0.0.1:{port}")[0] == 200
    # no CORS preflight answer
    st, h, _ = raw(port, "OPTIONS", "/api/targets", {"Host": f"127.0.0.1:{port}", "Origin": "http://evil.example"})
    assert st == 403 and "Access-Control-Allow-Origin" not in h
    st, h, _ = raw(port, "OPTIONS", f"/api/targets?token={token}", {"Host": f"127.0.0.1:{port}"})
    assert st == 405 and "Access-Control-Allow-Origin" not in h


def test_api_rejects_bad_requests(server):
    _, port, token, _ = server
    h = {"Host": f"127.0.0.1:{port}", "X-TVL-Token": token, "Content-Type": "text/plain"}
    assert raw(port, "POST", "/api/targets", h, {})[0] == 415
    assert api(port, token, "nope", {})[0] == 404
    st, _, body = api(port, token, "decide", {"feature": "NoSuchFeature", "value": True})
    assert st == 422 and b"unknown feature" in body
    assert api(port, token, "model", {"model": "/etc/passwd"})[0] == 422
    st, _, _ = raw(port, "GET", f"/static/..%2f..%2fserver.py?token={token}", {"Host": f"127.0.0.1:{port}"})
    assert st == 404
    st, _, _ = raw(port, "GET", f"/static/../server.py?token={token}", {"Host": f"127.0.0.1:{port}"})
    assert st == 404


def test_click_flow_and_write_inside_workspace(server, ws):
    _, port, token, _ = server
    st, _, body = api(port, token, "model", {})
    m = json.loads(body)
    assert m["name"] == "Turtlerand" and m["launch"].endswith("generic.launch")
    out = json.loads(api(port, token, "decide", {"feature": "Random", "value": True})[2])
    assert out["ok"] and out["state"]["decisions"] == {"Random": True}
    assert json.loads(api(port, token, "counts", {})[2])["remaining"] == "2"
    out = json.loads(api(port, token, "decide", {"feature": "Vel", "value": False})[2])
    assert not out["ok"] and out["refused"]["conflictsWith"] == {"Random": True}
    for f, v in (("Teleop", False), ("Multiplexer", False)):
        assert json.loads(api(port, token, "decide", {"feature": f, "value": v})[2])["ok"]
    st, _, body = api(port, token, "generate", {"mode": "current"})
    g = json.loads(body)
    assert st == 200 and len(g["written"]) == 1
    p = Path(g["written"][0])
    assert p.is_file() and str(p).startswith(str(ws)) and '<arg name="Random" value="true"/>' in p.read_text()
    # a folder outside the workspace is refused, nothing written
    st, _, body = api(port, token, "generate", {"mode": "current", "folder": "/tmp/tvl-ui-outside"})
    assert st == 422 and b"outside the workspace" in body and not os.path.exists("/tmp/tvl-ui-outside")
    st, _, body = api(port, token, "generate", {"mode": "current", "folder": "../../../.."})
    assert st == 422


def test_excerpt_limited_to_the_session_files(server, ws):
    _, port, token, _ = server
    launch = str(ws / "src" / "turtlerand" / "launch" / "generic.launch")
    st, _, body = api(port, token, "excerpt", {"path": launch, "line": 9})
    assert st == 200 and "turtlesim_node" in json.loads(body)["lines"][9 - json.loads(body)["start"]]
    assert api(port, token, "excerpt", {"path": "/etc/passwd", "line": 0})[0] == 422
    assert api(port, token, "excerpt", {"path": str(ws / "haros.yaml") + "/../../../../etc/passwd", "line": 0})[0] == 422


def _start_cli(ws, *extra):
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    # as from a terminal: Ctrl-C's SIGINT at its default disposition (a background job of a
    # non-interactive shell, such as `pytest &`, inherits it ignored)
    return subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(ws), "--no-browser", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_cli_prints_the_url_first_and_stops_cleanly(ws, sig):
    proc = _start_cli(ws)
    try:
        url = proc.stdout.readline().strip()
        parts = urlsplit(url)
        assert parts.scheme == "http" and parts.hostname == "127.0.0.1" and parts.query.startswith("token=")
        st, _, _ = raw(parts.port, "GET", f"/?{parts.query}", {"Host": parts.netloc})
        assert st == 200
        # the problems are checked in a worker process: it is running when the signal comes
        token = parts.query.split("=", 1)[1]
        st, _, _ = raw(parts.port, "POST", "/api/problems", {"Host": parts.netloc, "X-TVL-Token": token,
                                                             "Content-Type": "application/json"}, {})
        assert st == 200
        proc.send_signal(sig)
        rc = proc.wait(timeout=20)
        err = proc.stderr.read()
        assert rc == 0, err
        # one line, as a user reads it after Ctrl-C: no warning of leaked semaphores, no traceback
        assert err == "tvl-lsp ui: stopped\n", err
        with pytest.raises(OSError):
            raw(parts.port, "GET", f"/?{parts.query}", {"Host": parts.netloc})
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_each_run_has_its_own_token(ws):
    a, b = _start_cli(ws), _start_cli(ws)
    try:
        ua, ub = a.stdout.readline().strip(), b.stdout.readline().strip()
        ta, tb = ua.split("token=")[1], ub.split("token=")[1]
        assert ta != tb
        pb = urlsplit(ub).port
        assert raw(pb, "GET", f"/?token={ta}", {"Host": f"127.0.0.1:{pb}"})[0] == 403
    finally:
        for p in (a, b):
            p.terminate()
            p.wait(timeout=20)


def test_cli_errors(tmp_path):
    r = subprocess.run([sys.executable, "-m", "tvl_lsp", "ui", str(tmp_path / "missing"), "--no-browser"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "does not exist" in r.stderr


def _descendants(pid: int) -> dict[int, str]:
    """Every process below ``pid`` (from /proc, as on the Linux machines ROS runs on): pid ->
    command line."""
    parent: dict[int, int] = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as fh:
                    parent[int(d)] = int(fh.read().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                pass
    out, todo = {}, [pid]
    while todo:
        p = todo.pop()
        for c, pp in parent.items():
            if pp == p and c not in out:
                try:
                    with open(f"/proc/{c}/cmdline", "rb") as fh:
                        out[c] = fh.read().replace(b"\0", b" ").decode(errors="replace")
                except OSError:
                    out[c] = "?"
                todo.append(c)
    return out


def test_sigterm_leaves_no_child_process(tmp_path):
    """Stopped while d4 compiles a big model and the problems are checked in a worker process:
    the compilation, the worker and multiprocessing's semaphore tracker all end with the server
    (and are reaped: no zombie left where no init reaps orphans)."""
    from model_gen import generated_model
    d = tmp_path / "ws" / "src" / "big" / "launch"
    d.mkdir(parents=True)
    (tmp_path / "ws" / ".catkin_workspace").write_text("")
    (d / "big.tvl").write_text(generated_model(1500, seed=1))
    env = dict(os.environ, TVL_LSP_CACHE_DIR=str(tmp_path / "cache"))
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(d / "big.tvl"), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert proc.stdout.readline().startswith("http://127.0.0.1:")
        # the server checks the model in a worker process and compiles it with d4 from the start
        deadline = time.monotonic() + 30
        kids = _descendants(proc.pid)
        while not any("counting.d4" in c for c in kids.values()) and time.monotonic() < deadline:
            time.sleep(0.02)
            kids.update(_descendants(proc.pid))
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == 0
        time.sleep(0.3)
        left = {p: c for p, c in kids.items() if os.path.exists(f"/proc/{p}")}
        assert left == {}, left
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_decisions_sent_at_once_are_all_kept(tmp_path):
    """Clicks answered at the same time (a user quicker than a loaded server): each decision is
    made from the decisions the one before left, none is dropped."""
    ws = tmp_path / "ws"
    (ws / "src" / "m").mkdir(parents=True)
    (ws / ".catkin_workspace").write_text("")
    names = [f"F{i}" for i in range(24)]
    model = ws / "src" / "m" / "m.tvl"
    # (and enough other features that each answer takes the server a while: the clicks overlap)
    filler = [f"G{i}" for i in range(1500)]
    model.write_text("root M {\n  group allOf {\n    " + ",\n    ".join(f"opt {n}" for n in names + filler)
                     + "\n  }\n" + "".join(f"  {a} -> {b};\n" for a, b in zip(filler, filler[1:])) + "}\n")
    httpd, url = make_server(str(model), 0)
    t = threading.Thread(target=httpd.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    t.start()
    try:
        port, token = urlsplit(url).port, urlsplit(url).query.split("=", 1)[1]
        assert api(port, token, "state", {})[0] == 200
        start = threading.Barrier(len(names))
        answers: list[int] = []

        def click(name):
            start.wait()
            answers.append(api(port, token, "decide", {"feature": name, "value": True})[0])

        clicks = [threading.Thread(target=click, args=(n,)) for n in names]
        for c in clicks:
            c.start()
        for c in clicks:
            c.join(60)
        assert answers == [200] * len(names)
        st, _, body = api(port, token, "state", {})
        assert st == 200 and sorted(json.loads(body)["decisions"]) == sorted(names)
    finally:
        httpd.shutdown()
        httpd.server_close()
