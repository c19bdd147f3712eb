"""The server's transport: LSP base-protocol framing that survives broken and hostile input.

pygls's reading loop trusts every ``Content-Length``: a wrong one desynchronises it for good,
``Content-Length: 99999999999999`` asks for that many bytes at once (and kills it), and a body
it cannot parse is never answered.  This loop replaces it for stdio and TCP:

- bytes that are not a header are skipped (reported on stderr) up to the next
  ``Content-Length:`` header: the stream resynchronises on it;
- a body is never read blindly: bytes are buffered as they arrive, at most ``MAX_BODY``;
  a declared length that is too long is noticed when a new header shows up inside the body
  (a raw CR LF cannot occur inside a JSON text) or when the bytes received so far are a
  complete JSON message and nothing more comes for ``STALL`` seconds; a declared length that
  is too short is noticed when the body does not parse and the body up to the next header does;
- an unparsable body gets a -32700 ParseError response, a JSON value that is not a JSON-RPC
  message -32600 InvalidRequest; everything else goes to the protocol
  (:class:`tvl_lsp.lsp.protocol.TvlProtocol`), which answers what the LSP says.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import re
import sys
import threading
from typing import Optional

from lsprotocol import types
from pygls.io_ import StdoutWriter

from .protocol import InvalidMessage

log = logging.getLogger("tvl_lsp.server")

MAX_BODY = 64 * 2 ** 20   # bytes of one message: beyond, it is dropped
MAX_HEADER = 8192         # bytes of a header block
STALL = 0.3               # seconds of silence after which a complete JSON body is taken as is
PARSE_ERROR = -32700
INVALID_REQUEST = -32600

HEADER = re.compile(rb"content-length[ \t]*:[ \t]*(\d{1,30})[ \t]*\r?\n", re.IGNORECASE)
_HEADER_END = re.compile(rb"\r?\n\r?\n")


def complain(msg: str) -> None:
    """A transport problem: on stderr (the client's log), never on stdout (the protocol)."""
    log.debug("%s", msg)
    try:
        print(f"tvl-lsp: {msg}", file=sys.stderr, flush=True)
    except Exception:
        pass


def _parses(data: bytes) -> bool:
    try:
        json.loads(data)
        return True
    except (ValueError, RecursionError):
        return False


_TOKEN = re.compile(rb'"(?:[^"\\]|\\.)*"|[{}\[\]]')
_ID_VALUE = re.compile(rb'[ \t\r\n]*:[ \t\r\n]*(-?[0-9]+|"(?:[^"\\]|\\.)*")[ \t\r\n]*[,}]')


def top_level_id(body: bytes):
    """The ``id`` member (an integer or a string) of the JSON object ``body``, found by a
    linear scan without recursion (for a message too deeply nested to parse); else None."""
    if not body.lstrip().startswith(b"{"):
        return None
    depth = 0
    for m in _TOKEN.finditer(body):
        t = m.group()
        if t in (b"{", b"["):
            depth += 1
        elif t in (b"}", b"]"):
            depth -= 1
        elif depth == 1 and t == b'"id"':
            v = _ID_VALUE.match(body, m.end())
            if v is None:
                return None
            try:
                return json.loads(v.group(1))
            except ValueError:
                return None
    return None


class Chunks:
    """Chunks of bytes from a blocking stream, read by a daemon thread (b"" at the end)."""

    def __init__(self, stream):
        self.queue: asyncio.Queue = asyncio.Queue()
        loop = asyncio.get_running_loop()
        try:  # the file descriptor itself: no buffer lock held by this thread at exit
            fd = stream.fileno()

            def read(n: int) -> bytes:
                return os.read(fd, n)
        except (OSError, AttributeError, ValueError):
            read = getattr(stream, "read1", None) or stream.read

        def pump():
            while True:
                try:
                    data = read(65536)
                except (OSError, ValueError):
                    data = b""
                loop.call_soon_threadsafe(self.queue.put_nowait, data or b"")
                if not data:
                    return
        threading.Thread(target=pump, name="tvl-lsp-stdin", daemon=True).start()

    async def get(self, timeout: Optional[float]) -> Optional[bytes]:
        try:
            return await asyncio.wait_for(self.queue.get(), timeout)
        except asyncio.TimeoutError:
            return None


class StreamChunks:
    """Chunks from an asyncio StreamReader (TCP)."""

    def __init__(self, reader: asyncio.StreamReader):
        self.reader = reader

    async def get(self, timeout: Optional[float]) -> Optional[bytes]:
        try:
            return await asyncio.wait_for(self.reader.read(65536), timeout)
        except asyncio.TimeoutError:
            return None
        except (OSError, asyncio.IncompleteReadError):
            return b""


class Framer:
    """Reads messages from ``chunks`` and hands them to ``protocol`` until the end of the
    input or ``stop`` is set."""

    def __init__(self, protocol, chunks, stop: threading.Event):
        self.protocol = protocol
        self.chunks = chunks
        self.stop = stop
        self.buf = bytearray()
        self.eof = False

    async def more(self, timeout: Optional[float] = None) -> bool:
        data = await self.chunks.get(timeout)
        if data is None:
            return False
        if not data:
            self.eof = True
            return False
        self.buf.extend(data)
        return True

    async def run(self) -> None:
        buf = self.buf
        while not self.stop.is_set():
            m = HEADER.search(buf)
            if m is None:
                if self.eof:
                    if buf.strip():
                        complain(f"{len(buf)} bytes at the end of the input are not a message: ignored")
                    return
                if len(buf) > 64:  # keep a tail that may be the start of a header
                    complain(f"{len(buf) - 64} bytes that are not a message skipped")
                    del buf[:len(buf) - 64]
                await self.more()
                continue
            if m.start() > 0:
                junk = bytes(buf[:m.start()])
                del buf[:m.start()]
                if junk.strip():
                    complain(f"{len(junk)} bytes before a header are not a message: skipped")
                continue
            end = _HEADER_END.search(buf, m.end() - 2)
            nxt = HEADER.search(buf, m.end())
            if end is None or (nxt is not None and nxt.start() < end.start()):
                if nxt is not None and (end is None or nxt.start() < end.start()):
                    complain("a header without its blank line: skipped")
                    del buf[:nxt.start()]
                    continue
                if len(buf) > MAX_HEADER:
                    complain("a header block too long: skipped")
                    del buf[:m.end()]
                    continue
                if self.eof:
                    return
                await self.more()
                continue
            length: Optional[int] = int(m.group(1))
            if length > MAX_BODY:
                complain(f"Content-Length {length} is over the limit of {MAX_BODY} bytes: "
                         "the length is ignored")
                length = None
            body = await self.body(end.end(), length)
            if body is None:
                continue
            self.dispatch(body)

    async def body(self, start: int, length: Optional[int]) -> Optional[bytes]:
        """The body that starts at ``start``: ``length`` bytes, or fewer when the framing is
        broken (see the module doc); None when there is nothing to dispatch."""
        buf = self.buf
        checked = -1
        while True:
            avail = len(buf) - start
            limit = start + (avail if length is None else min(avail, length))
            h = HEADER.search(buf, start, limit)
            if h is not None:  # the next message starts inside this one: the length was wrong
                body = bytes(buf[start:h.start()])
                del buf[:h.start()]
                complain("Content-Length past the end of the message: resynchronised on the next header")
                return body
            if length is not None and avail >= length:
                body = bytes(buf[start:start + length])
                del buf[:start + length]
                if not _parses(body):
                    return self.extend_short(body)
                return body
            if length is None and avail > MAX_BODY:
                complain(f"a message over {MAX_BODY} bytes: dropped")
                del buf[:]
                return None
            if self.eof or self.stop.is_set():
                tail = bytes(buf[start:]).strip()
                del buf[:]
                if tail:
                    complain("the input ended inside a message")
                    return tail if _parses(tail) else None
                return None
            if await self.more(STALL):
                continue
            if self.eof:
                continue
            if checked != len(buf):  # silence: is what came a complete message?
                checked = len(buf)
                tail = bytes(buf[start:]).rstrip()
                if tail[-1:] in (b"}", b"]") and _parses(tail):
                    del buf[:]
                    complain("Content-Length past the end of the message: took the message as sent")
                    return tail

    def extend_short(self, body: bytes) -> bytes:
        """``body`` does not parse: if the declared length was too short, the rest of the
        message follows up to the next header."""
        buf = self.buf
        h = HEADER.search(buf)
        cut = h.start() if h is not None else len(buf)
        candidate = body + bytes(buf[:cut])
        if cut and _parses(candidate):
            del buf[:cut]
            complain("Content-Length short of the end of the message: took the whole message")
            return candidate
        return body

    def dispatch(self, body: bytes) -> None:
        protocol = self.protocol
        try:
            message = json.loads(body, object_hook=protocol.structure_message)
        except RecursionError:
            # JSON perhaps, but nested deeper than the parser goes: a request still gets its
            # answer (its id is found without parsing the rest)
            msg_id = top_level_id(body)
            if msg_id is not None:
                complain("a message nested too deeply to read: answered with an invalid request error")
                self.reply(msg_id, INVALID_REQUEST, "invalid request: the message is nested too deeply")
            else:
                complain("a message nested too deeply to read (RecursionError): answered with a parse error")
                self.reply(None, PARSE_ERROR, "parse error: the message is nested too deeply")
            return
        except ValueError as exc:
            complain(f"a message that is not JSON ({exc.__class__.__name__}): answered with a parse error")
            self.reply(None, PARSE_ERROR, "parse error: the message is not JSON")
            return
        except Exception:
            log.exception("cannot read a message")
            self.reply(None, PARSE_ERROR, "parse error")
            return
        if isinstance(message, dict) or not (hasattr(message, "jsonrpc") or isinstance(message, InvalidMessage)):
            msg_id = message.get("id") if isinstance(message, dict) else None
            if isinstance(message, dict) and "method" not in message and "id" in message:
                log.warning("a response without jsonrpc: ignored")
                return
            self.reply(msg_id, INVALID_REQUEST, "invalid request: not a JSON-RPC 2.0 message")
            return
        try:
            protocol.handle_message(message)
        except SystemExit as exc:
            protocol.exit_code = exc.code if isinstance(exc.code, int) else 1
            self.stop.set()
        except Exception:
            log.exception("cannot handle a message")

    def reply(self, msg_id, code: int, message: str) -> None:
        if not (isinstance(msg_id, (str, int)) and not isinstance(msg_id, bool)):
            msg_id = None
        try:
            self.protocol._send_response(msg_id, error=types.ResponseError(code=code, message=message))
        except Exception:
            log.exception("cannot send an error response")


def serve_stdio(server, stdin=None, stdout=None) -> None:
    """Serve LSP on stdin/stdout until ``exit`` or the end of the input."""
    server._stop_event = stop = threading.Event()
    server.protocol.set_writer(StdoutWriter(stdout or sys.stdout.buffer))

    async def main():
        await Framer(server.protocol, Chunks(stdin or sys.stdin.buffer), stop).run()
    try:
        asyncio.run(main())
    except BrokenPipeError:
        complain("the client has gone (broken pipe)")
    except (KeyboardInterrupt, SystemExit):
        pass


def serve_tcp(server, host: str, port: int) -> None:
    """Serve LSP on a TCP port (one client at a time), as pygls's ``start_tcp`` does."""
    server._stop_event = stop = threading.Event()

    async def connection(reader: asyncio.StreamReader, writer: asyncio.StreamWriter):
        server.protocol.set_writer(writer)
        await Framer(server.protocol, StreamChunks(reader), stop).run()
        stop.set()
        srv.close()

    async def main():
        nonlocal srv
        srv = await asyncio.start_server(connection, host, port)
        async with srv:
            try:
                await srv.serve_forever()
            except asyncio.CancelledError:
                pass
    srv = None
    try:
        asyncio.run(main())
    except (KeyboardInterrupt, SystemExit, asyncio.CancelledError):
        pass
