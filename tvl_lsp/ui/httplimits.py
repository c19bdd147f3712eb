"""The configurator web server's limits (``tvl-lsp ui``): what a hostile local client can do
to it is bounded (issue #28).

- a listen backlog of ``BACKLOG`` (200 simultaneous connections are queued, not reset);
- at most ``MAX_CONNECTIONS`` connections served at once, one thread each; past that a
  connection is answered 503 at once, from the accepting thread, and closed;
- each request must arrive within ``REQUEST_SECONDS`` (line, headers and body, whatever the
  pace of its bytes: slowloris) and each socket operation within ``SOCKET_SECONDS``;
- the JSON body is nested at most ``MAX_DEPTH`` deep (checked before parsing: 100,000 ``[``
  would exhaust the parser's recursion); one ``Host`` (``Origin``, ``Content-Length``, token,
  ``Content-Type``) header per request;
- a file that cannot be written is an HTTP status with a one-line JSON reason
  (:func:`os_status`); a connection that fails is never a traceback on the terminal.
"""

from __future__ import annotations

import errno
import io
import json
import socket
import sys
import threading
import time
from http import HTTPStatus
from typing import Optional

MAX_DEPTH = 64                # nesting of the JSON body (the API's requests are two levels deep)
BACKLOG = 128                 # pending connections the kernel keeps for us
MAX_CONNECTIONS = 64          # connections served at once (one thread each)
REQUEST_SECONDS = 30.0        # to send a whole request (line, headers, body)
SOCKET_SECONDS = 10.0         # for each read or write on a connection
SINGLE_HEADERS = ("host", "origin", "content-length", "content-type", "x-tvl-token")


def parse_body(data: bytes) -> dict:
    """The API request in ``data``: a JSON object nested at most MAX_DEPTH deep (checked before
    parsing: a body of 100,000 ``[`` would exhaust the parser's recursion).  ValueError says
    what is wrong."""
    depth = 0
    in_string = escaped = False
    opening = data.count(b"[") + data.count(b"{")
    for b in (data if opening > MAX_DEPTH else b""):
        if in_string:
            if escaped:
                escaped = False
            elif b == 0x5C:  # backslash
                escaped = True
            elif b == 0x22:
                in_string = False
        elif b == 0x22:
            in_string = True
        elif b in (0x5B, 0x7B):
            depth += 1
            if depth > MAX_DEPTH:
                raise ValueError(f"the request body is nested more than {MAX_DEPTH} levels deep")
        elif b in (0x5D, 0x7D):
            depth -= 1
    try:
        body = json.loads(data or b"{}")
    except (ValueError, RecursionError):
        raise ValueError("the request body must be a JSON object") from None
    if not isinstance(body, dict):
        raise ValueError("the request body must be a JSON object")
    return body


def os_status(e: OSError) -> int:
    """The HTTP status of a file that could not be written: 507 for a full disk, 409 for a
    refused target (a link, outside the workspace), 500 otherwise."""
    if e.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
        return HTTPStatus.INSUFFICIENT_STORAGE
    if not e.errno or e.errno in (errno.ELOOP, errno.ENOTDIR, errno.EISDIR, errno.EEXIST, errno.EACCES,
                                  errno.EPERM, errno.EROFS, errno.ENAMETOOLONG):
        return HTTPStatus.CONFLICT
    return HTTPStatus.INTERNAL_SERVER_ERROR


def os_message(e: OSError) -> str:
    from ..base.safewrite import WriteError, reason, summary
    if isinstance(e, WriteError):
        return summary(e, getattr(e, "total", 1))
    where = getattr(e, "filename", None)
    return f"cannot write {where}: {reason(e)}" if where else f"cannot write: {reason(e)}"


class DeadlineRaw(io.RawIOBase):
    """A connection's reading side that gives up at ``deadline`` (time.monotonic()) whatever
    the pace of the bytes: each receive waits at most until then (and SOCKET_SECONDS)."""

    def __init__(self, sock: socket.socket):
        self.sock = sock
        self.deadline: Optional[float] = None

    def readable(self) -> bool:
        return True

    def readinto(self, b) -> int:
        if self.deadline is not None:
            left = self.deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("the request took too long to arrive")
            self.sock.settimeout(min(left, SOCKET_SECONDS))
        return self.sock.recv_into(b)


class BoundedServer:
    """A mixin for ``ThreadingHTTPServer``: the backlog, the connection bound, quiet errors."""

    request_queue_size = BACKLOG

    def __init__(self, *args, **kwargs):
        self._slots = threading.BoundedSemaphore(MAX_CONNECTIONS)
        super().__init__(*args, **kwargs)

    def process_request(self, request, client_address) -> None:
        """A thread per connection, at most MAX_CONNECTIONS at once; past that a connection is
        answered 503 at once (from this thread, with a short timeout) and closed."""
        if not self._slots.acquire(blocking=False):
            try:
                request.settimeout(0.5)
                body = b'{"error": "too many connections at once; retry"}'
                request.sendall(b"HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
                                b"Retry-After: 1\r\nConnection: close\r\nContent-Length: "
                                + str(len(body)).encode() + b"\r\n\r\n" + body)
            except OSError:
                pass
            self.shutdown_request(request)
            return
        try:
            super().process_request(request, client_address)
        except BaseException:
            self._slots.release()
            raise

    def process_request_thread(self, request, client_address) -> None:
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._slots.release()

    def handle_error(self, request, client_address) -> None:
        """A connection that failed (reset, timed out): one line when verbose, never a traceback
        on the terminal."""
        exc = sys.exc_info()[1]
        if getattr(self.RequestHandlerClass, "verbose", False):
            sys.stderr.write(f"tvl-lsp ui: connection from {client_address[0]} ended: {type(exc).__name__}: {exc}\n")

