"""Conversions between the core's positions (code-point columns) and LSP's (the client's
negotiated position encoding, UTF-16 unless the client asked for another).

Only the protocol layer imports this module.
"""

from __future__ import annotations

import urllib.parse
from pathlib import Path
from typing import Callable, Iterable, Optional

from lsprotocol import types

from ..base.diagnostics import Diagnostic, Fix, Severity
from ..base.text import LineIndex, Pos, Span, from_encoding, to_encoding

_ENCODINGS = {"utf-8": "utf-8", "utf-16": "utf-16", "utf-32": "utf-32"}


def encoding_name(kind) -> str:
    """PositionEncodingKind (or its string) -> "utf-8" | "utf-16" | "utf-32"."""
    value = getattr(kind, "value", kind) or "utf-16"
    return _ENCODINGS.get(str(value).lower(), "utf-16")


# ------------------------------------------------------------------ URIs

def uri_to_path(uri: str) -> str:
    parsed = urllib.parse.urlparse(uri)
    if parsed.scheme not in ("file", ""):
        return uri
    return str(Path(urllib.parse.unquote(parsed.path)))


def path_to_uri(path: str) -> str:
    if "://" in path:
        return path
    return Path(path).absolute().as_uri()


# ------------------------------------------------------------------ positions

def to_lsp_position(index: LineIndex, pos: Pos, encoding: str = "utf-16") -> types.Position:
    line = max(0, pos.line)
    if line >= index.line_count:
        # past the end: the end of the text
        line = index.line_count - 1
        text = index.line_text(line)
        return types.Position(line=line, character=to_encoding(text, len(text), encoding))
    text = index.line_text(line)
    col = max(0, min(pos.col, len(text)))
    return types.Position(line=line, character=to_encoding(text, col, encoding))


def to_lsp_range(index: LineIndex, span: Span, encoding: str = "utf-16") -> types.Range:
    start = to_lsp_position(index, span.start, encoding)
    end = to_lsp_position(index, span.end, encoding)
    if (end.line, end.character) < (start.line, start.character):
        end = start
    return types.Range(start=start, end=end)


def from_lsp_position(index: LineIndex, position: types.Position, encoding: str = "utf-16") -> Pos:
    """Client position -> core position, clamped as LSP says (a column past the end of
    a line is the end of the line; a line past the end is the end of the text)."""
    line = max(0, position.line)
    if line >= index.line_count:
        last = index.line_count - 1
        return Pos(last, len(index.line_text(last)))
    text = index.line_text(line)
    return Pos(line, from_encoding(text, max(0, position.character), encoding))


def from_lsp_range(index: LineIndex, rng: types.Range, encoding: str = "utf-16") -> Span:
    a = from_lsp_position(index, rng.start, encoding)
    b = from_lsp_position(index, rng.end, encoding)
    return Span(min(a, b), max(a, b))


def offset_of(index: LineIndex, position: types.Position, encoding: str = "utf-16") -> int:
    return index.offset(from_lsp_position(index, position, encoding))


def apply_change(text: str, rng: Optional[types.Range], new_text: str, encoding: str = "utf-16") -> str:
    """Apply one ``didChange`` content change (``rng is None``: the whole text)."""
    return apply_change_at(text, rng, new_text, encoding)[0]


def apply_change_at(text: str, rng: Optional[types.Range], new_text: str,
                    encoding: str = "utf-16") -> tuple[str, Optional[tuple[int, int, int]]]:
    """:func:`apply_change`, and where: (start, end) code-point offsets of the replaced part
    of ``text`` and the inserted length (None for a whole text)."""
    if rng is None:
        return new_text, None
    index = LineIndex(text)
    a = offset_of(index, rng.start, encoding)
    b = offset_of(index, rng.end, encoding)
    if b < a:
        a, b = b, a
    return text[:a] + new_text + text[b:], (a, b, len(new_text))


# ------------------------------------------------------------------ diagnostics

IndexOf = Callable[[str], Optional[LineIndex]]


def lsp_severity(sev) -> types.DiagnosticSeverity:
    return types.DiagnosticSeverity(int(sev))


_URIS: dict[str, str] = {}


def _uri(path: str) -> str:
    u = _URIS.get(path)
    if u is None:
        if len(_URIS) > 10000:
            _URIS.clear()
        u = _URIS[path] = path_to_uri(path)
    return u


def _location(path: str, span: Span, index_of: IndexOf, encoding: str) -> types.Location:
    idx = index_of(path) or LineIndex("")
    return types.Location(uri=_uri(path), range=to_lsp_range(idx, span, encoding))


MAX_RELATED = 8  # related locations sent per diagnostic (explanations can be long)


def to_lsp_diagnostic(d: Diagnostic, index: LineIndex, encoding: str, index_of: IndexOf,
                      severity: Severity | None = None) -> types.Diagnostic:
    related = None
    if d.related:
        related = [types.DiagnosticRelatedInformation(
            location=_location(r.path, r.span, index_of, encoding), message=r.message)
            for r in d.related[:MAX_RELATED]]
    data: dict = {}
    if d.data:
        data.update(_jsonable(d.data))
    if d.witness:
        data["witness"] = dict(sorted(d.witness.items()))
    if d.fixes:
        data["fixes"] = len(d.fixes)
    tags = None
    if d.code in ("dead-element", "dead-feature"):
        tags = [types.DiagnosticTag.Unnecessary]
    message = d.message
    return types.Diagnostic(
        range=to_lsp_range(index, d.span, encoding),
        message=message,
        severity=lsp_severity(severity or d.severity),
        code=d.code,
        source="tvl-lsp",
        related_information=related,
        tags=tags,
        data=data or None,
    )


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, set, frozenset)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    return str(value)


def fix_to_edit(fix: Fix, index_of: IndexOf, encoding: str) -> types.WorkspaceEdit:
    changes: dict[str, list[types.TextEdit]] = {}
    for e in fix.edits:
        idx = index_of(e.path) or LineIndex("")
        changes.setdefault(path_to_uri(e.path), []).append(
            types.TextEdit(range=to_lsp_range(idx, e.span, encoding), new_text=e.new_text))
    return types.WorkspaceEdit(changes=changes)


def fix_to_versioned_edit(fix: Fix, uri: str, version: Optional[int], index: LineIndex,
                          encoding: str) -> types.WorkspaceEdit:
    """A fix of one document as ``documentChanges`` naming the version it was computed for: the
    client applies it only to that version (an edited document refuses it)."""
    edits = [types.TextEdit(range=to_lsp_range(index, e.span, encoding), new_text=e.new_text) for e in fix.edits]
    return types.WorkspaceEdit(document_changes=[types.TextDocumentEdit(
        text_document=types.OptionalVersionedTextDocumentIdentifier(uri=uri, version=version), edits=edits)])


def spans_overlap(a: Span, b: Span) -> bool:
    return a.start <= b.end and b.start <= a.end


def lsp_ranges(index: LineIndex, spans: Iterable[Span], encoding: str) -> list[types.Range]:
    return [to_lsp_range(index, s, encoding) for s in spans]
