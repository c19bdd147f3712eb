"""A raw stdio client for the language server: bytes in, framed messages out (for tests of
framing, protocol errors and exit codes that a well-behaved client library cannot send)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time

from testenv import REPO


def frame(obj, length: int | None = None) -> bytes:
    body = obj if isinstance(obj, bytes) else json.dumps(obj).encode()
    n = len(body) if length is None else length
    return b"Content-Length: %d\r\n\r\n" % n + body


class RawServer:
    """``python -m tvl_lsp`` on pipes; a reader thread collects the server's messages."""

    def __init__(self, cwd=None):
        env = dict(os.environ, PYTHONPATH=str(REPO))
        self.proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp"], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=cwd)
        self.messages: list[dict] = []
        self.cond = threading.Condition()
        self.stderr = b""
        threading.Thread(target=self._read, daemon=True).start()
        threading.Thread(target=self._read_err, daemon=True).start()
        self.next_id = 1

    def _read_err(self):
        self.stderr = self.proc.stderr.read()

    def _read(self):
        out = self.proc.stdout
        while True:
            headers = {}
            while True:
                line = out.readline()
                if not line:
                    with self.cond:
                        self.cond.notify_all()
                    return
                if line in (b"\r\n", b"\n"):
                    break
                k, _, v = line.decode().partition(":")
                headers[k.strip().lower()] = v.strip()
            body = out.read(int(headers["content-length"]))
            with self.cond:
                self.messages.append(json.loads(body))
                self.cond.notify_all()

    def send(self, data: bytes) -> None:
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def request(self, method, params=None, msg_id=None, send=True) -> int:
        if msg_id is None:
            msg_id = self.next_id
            self.next_id += 1
        msg = {"jsonrpc": "2.0", "id": msg_id, "method": method}
        if params is not ...:
            msg["params"] = params
        if send:
            self.send(frame(msg))
        return msg_id

    def notify(self, method, params=None) -> None:
        self.send(frame({"jsonrpc": "2.0", "method": method, "params": params}))

    def response(self, msg_id, timeout: float = 10.0):
        """The response to ``msg_id`` (None if none came within ``timeout``)."""
        end = time.monotonic() + timeout
        with self.cond:
            while True:
                for m in self.messages:
                    if m.get("id") == msg_id and "method" not in m:
                        return m
                left = end - time.monotonic()
                if left <= 0 or self.proc.poll() is not None and not self._pending():
                    return None
                self.cond.wait(min(left, 0.2))

    def _pending(self):
        return False

    def initialize(self, root=None, options=None) -> dict:
        params = {"processId": None, "capabilities": {},
                  "rootUri": root.as_uri() if root else None,
                  "initializationOptions": options or {"debounce": 0.05}}
        if root:
            params["workspaceFolders"] = [{"uri": root.as_uri(), "name": root.name}]
        rid = self.request("initialize", params)
        res = self.response(rid, 30)
        self.notify("initialized", {})
        return res

    def close(self, timeout: float = 10.0) -> int:
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            return -9
