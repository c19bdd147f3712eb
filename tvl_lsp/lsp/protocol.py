"""The JSON-RPC / LSP protocol object: pygls's, made robust to hostile and broken input.

- Every string the client sends is cleaned of lone UTF-16 surrogates (a JSON ``"\\ud800"``
  escape is legal JSON but not text: the core would fail on it).  Each one becomes U+FFFD,
  which has the same length in code points, UTF-16 and UTF-8 units as the surrogate had
  (1, 1 and 3): every position the client and the server exchange stays exact.
- A message whose params do not fit the method's type (negative or huge positions, ``null``
  params, wrong types) is answered with -32602 InvalidParams; a malformed request with -32600.
- A request before ``initialize`` gets -32002 ServerNotInitialized; a request after
  ``shutdown`` gets -32600 InvalidRequest (pygls drops both silently).
- Every request handler is guarded: an internal error is logged and answered with an empty
  result (:func:`empty_result`), never -32603 and never a missing response.  A deliberate
  error answer (a handler raising -32602 InvalidParams, an unknown command) is sent as is and
  logged in one line: a traceback on stderr means a bug, nothing else.
- ``exit`` records the exit code (0 after ``shutdown``, 1 without, as the LSP says) and stops
  the transport (:mod:`tvl_lsp.lsp.transport`) instead of raising ``SystemExit`` in a handler.
"""

from __future__ import annotations

import logging
import re
from typing import Any, Optional

from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pygls.protocol import LanguageServerProtocol
from pygls.protocol.language_server import lsp_method

log = logging.getLogger("tvl_lsp.server")

INVALID_REQUEST = -32600
INVALID_PARAMS = -32602
INTERNAL_ERROR = -32603
SERVER_NOT_INITIALIZED = -32002

_SURROGATE = re.compile("[\ud800-\udfff]")

# requests whose result may not be null: what an empty answer is
_EMPTY: dict[str, Any] = {
    types.TEXT_DOCUMENT_DIAGNOSTIC: lambda p: {"kind": "full", "items": []},
    types.WORKSPACE_DIAGNOSTIC: lambda p: {"items": []},
    types.CODE_ACTION_RESOLVE: lambda p: p,
    types.CODE_LENS_RESOLVE: lambda p: p,
    types.COMPLETION_ITEM_RESOLVE: lambda p: p,
    types.DOCUMENT_LINK_RESOLVE: lambda p: p,
    types.INLAY_HINT_RESOLVE: lambda p: p,
    types.WORKSPACE_SYMBOL_RESOLVE: lambda p: p,
}


class _QuietDeserialize(logging.Filter):
    """pygls logs a full traceback for every message whose params do not fit: the client
    gets -32602 and the log one line (:meth:`TvlProtocol.handle_message`)."""

    def filter(self, record: logging.LogRecord) -> bool:
        return not str(record.msg).startswith("Unable to deserialize message")


logging.getLogger("pygls.protocol.json_rpc").addFilter(_QuietDeserialize())


def clean_text(s: str) -> str:
    """``s`` with every lone surrogate replaced by U+FFFD (same length in every encoding)."""
    return _SURROGATE.sub("\ufffd", s) if _SURROGATE.search(s) else s


def _clean(value):
    if isinstance(value, str):
        return clean_text(value)
    if isinstance(value, list):
        return [_clean(v) for v in value]
    return value  # dicts were cleaned by the object hook already (innermost first)


def empty_result(method: str | None, params: Any) -> Any:
    make = _EMPTY.get(method or "")
    return make(params) if make is not None else None


class InvalidMessage:
    """A JSON-RPC message that could not be turned into its LSP type."""

    __slots__ = ("data", "error")

    def __init__(self, data: dict, error: Exception):
        self.data = data
        self.error = error


def _valid_id(msg_id) -> bool:
    return isinstance(msg_id, (str, int)) and not isinstance(msg_id, bool)


def pull_refresh(caps: Optional[types.ClientCapabilities]) -> bool:
    """The client pulls diagnostics and accepts ``workspace/diagnostic/refresh``."""
    try:
        return bool(caps.text_document.diagnostic is not None and caps.workspace.diagnostics.refresh_support)
    except AttributeError:
        return False


class TvlProtocol(LanguageServerProtocol):
    """The server keeps its own documents (LSP line rules, robust to bad positions), so
    pygls's own workspace copy is not updated on every keystroke; and see the module doc."""

    def __init__(self, server, converter):
        super().__init__(server, converter)
        self.initialize_seen = False
        self.exit_code: int | None = None
        self._in_flight: dict = {}  # msg id -> (method, params): for the handler guard

    # ------------------------------------------------------------ incoming messages
    def structure_message(self, data: dict):
        for k in list(data):
            v = data[k]
            if isinstance(v, (str, list)):
                data[k] = _clean(v)
            if isinstance(k, str) and _SURROGATE.search(k):
                data[clean_text(k)] = data.pop(k)
        if "jsonrpc" not in data:
            return data
        try:
            return super().structure_message(data)
        except Exception as exc:  # params that do not fit the method's type
            return InvalidMessage(data, exc)

    def reply_error(self, msg_id, code: int, message: str) -> None:
        self._send_response(msg_id if _valid_id(msg_id) else None,
                            error=types.ResponseError(code=code, message=message))

    def handle_message(self, message):
        if isinstance(message, InvalidMessage):
            data = message.data
            method = data.get("method")
            if "id" not in data:
                log.warning("invalid notification %r ignored: %s", method, message.error)
                return
            if "method" not in data:  # a response to one of our requests, malformed
                log.warning("invalid response ignored: %s", message.error)
                return
            if not isinstance(method, str) or not _valid_id(data.get("id")) or data.get("jsonrpc") != "2.0":
                self.reply_error(data.get("id"), INVALID_REQUEST, "invalid request")
                return
            self.reply_error(data["id"], INVALID_PARAMS, f"invalid params for {method}")
            return
        method = getattr(message, "method", None)
        if getattr(message, "jsonrpc", None) != self.VERSION:
            log.warning("not a JSON-RPC 2.0 message: ignored")
            return
        is_request = method is not None and hasattr(message, "id")
        if is_request and not _valid_id(message.id):  # an object, array, float or boolean id
            self.reply_error(None, INVALID_REQUEST, "invalid request: the id must be an integer or a string")
            return
        if method == types.INITIALIZE:
            self.initialize_seen = True
        elif method is not None and method != types.EXIT and not self.initialize_seen:
            if is_request:
                self.reply_error(message.id, SERVER_NOT_INITIALIZED, "the server is not initialized")
            return
        if self._shutdown and method != types.EXIT:
            if is_request:
                self.reply_error(message.id, INVALID_REQUEST, "the server is shutting down")
            return
        super().handle_message(message)

    # ------------------------------------------------------------ the handler guard
    def _execute_handler(self, msg_id, handler, callback, args=None, kwargs=None):
        """pygls keeps the future of every handler it runs in ``_request_futures`` (for
        ``$/cancelRequest``) but only a request's answer removes it: the future of each
        notification (every ``didChange``) and of each step of a built-in handler stayed for
        good (a thousand per thousand edits).  A finished handler's future is forgotten."""
        super()._execute_handler(msg_id, handler, callback, args=args, kwargs=kwargs)
        fut = self._request_futures.get(msg_id)
        if fut is not None:
            def forget(f, msg_id=msg_id):
                # (a cancelled one is left alone: ``shutdown`` cancels them while iterating)
                if not f.cancelled() and self._request_futures.get(msg_id) is f:
                    self._request_futures.pop(msg_id, None)
            fut.add_done_callback(forget)

    def _handle_request(self, msg_id, method_name, params):
        if method_name in self.fm.features or method_name in self.fm.builtin_features:
            self._in_flight[msg_id] = (method_name, params)
        super()._handle_request(msg_id, method_name, params)

    def _send_handler_result(self, future, *, msg_id):
        method, params = self._in_flight.pop(msg_id, (None, None))
        if not future.cancelled():
            exc = future.exception()
            if isinstance(exc, JsonRpcException) and exc.code != INTERNAL_ERROR:
                # a deliberate error answer (invalid params, unknown command, ...): the client
                # gets it and the log one line (pygls would log a traceback, as for a crash)
                log.info("%s answered with error %s: %s", method, exc.code, exc.message)
                self._request_futures.pop(msg_id, None)
                self._send_response(msg_id, error=exc.to_response_error())
                return
            if exc is not None and (not isinstance(exc, JsonRpcException) or exc.code == INTERNAL_ERROR):
                log.error("internal error answering %s (answered with an empty result)", method,
                          exc_info=(type(exc), exc, exc.__traceback__))
                self._request_futures.pop(msg_id, None)
                try:
                    self._send_response(msg_id, result=empty_result(method, params))
                except Exception:  # (an echo that cannot be serialised)
                    log.exception("cannot send the empty result of %s", method)
                    self._send_response(msg_id, result=None)
                return
        super()._send_handler_result(future, msg_id=msg_id)

    # ------------------------------------------------------------ lifecycle and documents
    @lsp_method(types.INITIALIZE)
    def lsp_initialize(self, params: types.InitializeParams):
        """pygls's, except that pull diagnostics are offered only to a client that accepts
        ``workspace/diagnostic/refresh``: a pull is answered at once with the latest results and
        the client is told to pull again when a check lands.  A client that pulls but cannot be
        told so (Neovim 0.10 and 0.11) gets pushed diagnostics instead: a pull had to wait for
        the solver-backed check, up to its budget (11 s), and requests are answered within 2 s."""
        result = yield from super().lsp_initialize(params)
        if not pull_refresh(params.capabilities) and result is not None:
            result.capabilities.diagnostic_provider = None
            self.server_capabilities.diagnostic_provider = None
        return result

    @lsp_method(types.EXIT)
    def lsp_exit(self, *args):
        if (handler := self.fm.features.get(types.EXIT)) is not None:
            yield handler, args, None
        self.exit_code = 0 if self._shutdown else 1
        stop = getattr(self._server, "_stop_event", None)
        if stop is not None:
            stop.set()

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams):
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: types.DidOpenTextDocumentParams):
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_OPEN)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: types.DidCloseTextDocumentParams):
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CLOSE)) is not None:
            yield handler, (params,), None
