"""``tvl-lsp ui``'s web server under a hostile local client (issue #28, defect 10): the listen
backlog holds a burst of connections, a slow sender is cut off, the number of connections served
at once is bounded (the rest get 503 at once), a deeply nested body is a 400 (it was a
RecursionError and a dropped connection), and a request with two ``Host`` headers is refused."""

from __future__ import annotations

import http.client
import json
import shutil
import socket
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from urllib.parse import urlsplit

import pytest

from tvl_lsp.ui import httplimits, server as ui_server
from tvl_lsp.ui.server import make_server

REPO = Path(__file__).resolve().parent.parent


@pytest.fixture()
def srv(tmp_path, monkeypatch):
    monkeypatch.setattr(ui_server, "REQUEST_SECONDS", 2.0)
    monkeypatch.setattr(httplimits, "SOCKET_SECONDS", 2.0)
    monkeypatch.setattr(ui_server, "SOCKET_SECONDS", 2.0)
    ws = tmp_path / "ws"
    shutil.copytree(REPO / "examples" / "ws", ws)
    httpd, url = make_server(str(ws), 0)
    t = threading.Thread(target=httpd.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    t.start()
    port, token = urlsplit(url).port, url.split("token=", 1)[1]
    yield httpd, port, token
    httpd.shutdown()
    httpd.server_close()


def request(port, token, body: bytes, headers=None, op="targets", timeout=30):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    c.putrequest("POST", f"/api/{op}", skip_host=True, skip_accept_encoding=True)
    hdrs = [("Host", f"127.0.0.1:{port}"), ("X-TVL-Token", token), ("Content-Type", "application/json"),
            ("Content-Length", str(len(body)))] + list(headers or [])
    for k, v in hdrs:
        c.putheader(k, v)
    c.endheaders(body)
    r = c.getresponse()
    out = r.status, r.read()
    c.close()
    return out


def test_a_deeply_nested_body_is_a_400(srv):
    _, port, token = srv
    for body in (b"[" * 100_000 + b"]" * 100_000, b'{"a":' * 50_000 + b"1" + b"}" * 50_000, b"[" * 100_000):
        st, out = request(port, token, body)
        assert st == 400 and "error" in json.loads(out)
    assert request(port, token, b'{"s": "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["}')[0] == 200


def test_two_host_headers_are_refused(srv):
    _, port, token = srv
    st, out = request(port, token, b"{}", [("Host", "evil.example:80")])
    assert st == 400 and b"more than one host header" in out
    st, _ = request(port, token, b"{}", [("Content-Length", "2")])
    assert st == 400
    st, _ = request(port, token, b"{}", [("Transfer-Encoding", "chunked")])
    assert st == 501


def test_a_slow_sender_is_cut_off(srv):
    _, port, token = srv
    s = socket.create_connection(("127.0.0.1", port))
    s.settimeout(15)
    t0 = time.monotonic()
    closed = False
    head = f"POST /api/targets HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n".encode()
    try:
        for b in head * 50:  # one byte every 0.2 s, for ever (slowloris)
            s.send(bytes([b]))
            time.sleep(0.2)
            if time.monotonic() - t0 > 10:
                break
    except OSError:
        closed = True
    if not closed:
        closed = s.recv(100) == b""
    s.close()
    assert closed and time.monotonic() - t0 < 8  # the request had 2 s (REQUEST_SECONDS here)


def test_connections_are_bounded_and_the_rest_answered_at_once(srv, monkeypatch):
    httpd, port, token = srv
    idle = [socket.create_connection(("127.0.0.1", port)) for _ in range(httpd._slots._value)]
    try:
        time.sleep(0.3)
        t0 = time.monotonic()
        s = socket.create_connection(("127.0.0.1", port))
        s.settimeout(5)
        s.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
        assert s.recv(100).startswith(b"HTTP/1.1 503") and time.monotonic() - t0 < 2
        s.close()
    finally:
        for s in idle:
            s.close()
    time.sleep(2.5)  # the idle ones time out / close; slots come back
    assert request(port, token, b"{}")[0] == 200
    assert threading.active_count() < 40


def test_a_burst_of_connections_is_answered(srv):
    """200 clients at once: the backlog queues them (a backlog of 5 reset 5-35 of them)."""
    _, port, token = srv

    def one(_):
        try:
            return request(port, token, b"{}", timeout=60)[0]
        except OSError as e:
            return repr(e)
    with ThreadPoolExecutor(200) as ex:
        got = list(ex.map(one, range(200)))
    assert all(st in (200, 503) for st in got), [g for g in got if g not in (200, 503)][:5]
    assert got.count(200) >= 64


def test_the_limits_module_parses_what_the_api_sends():
    assert httplimits.parse_body(b'{"model": "a", "features": ["x", "y"], "value": true}')["value"] is True
    for bad in (b"[]", b"1", b"not json", b"[" * 65 + b"]" * 65):
        with pytest.raises(ValueError):
            httplimits.parse_body(bad)
