"""Formatters for ``tvl-lsp --check``: text, json, sarif (2.1.0) and github (workflow commands).

All take diagnostics already sorted and a ``read_file`` to convert code-point columns to
UTF-16 code units where the format wants them (json: 0-based LSP positions; sarif: 1-based
columns in UTF-16 code units, SARIF's default ``columnKind``).  ``text`` and ``github``
print 1-based code-point columns, as compilers and GitHub annotations count characters.
Paths are shown relative to ``base`` (the current folder) when below it, absolute otherwise.
"""

from __future__ import annotations

import json
import os
import urllib.parse
from typing import Callable, Optional, Sequence

from ..base.diagnostics import CODES, Diagnostic, Severity
from ..base.text import LineIndex, Pos, Span, to_encoding

ReadFile = Callable[[str], Optional[str]]

FORMATS = ("text", "json", "sarif", "github")

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
SARIF_VERSION = "2.1.0"


class _Lines:
    """Caches LineIndex per path for column conversion."""

    def __init__(self, read_file: ReadFile):
        self.read_file = read_file
        self.cache: dict[str, Optional[LineIndex]] = {}

    def index(self, path: str) -> Optional[LineIndex]:
        if path not in self.cache:
            text = None
            try:
                text = self.read_file(path)
            except Exception:
                text = None
            self.cache[path] = LineIndex(text) if text is not None else None
        return self.cache[path]

    def utf16(self, path: str, pos: Pos) -> tuple[int, int]:
        """(line, UTF-16 column), both 0-based, clamped to the text."""
        idx = self.index(path)
        if idx is None:
            return max(pos.line, 0), max(pos.col, 0)
        line = max(0, pos.line)
        if line >= idx.line_count:
            line = idx.line_count - 1
            text = idx.line_text(line)
            return line, to_encoding(text, len(text), "utf-16")
        text = idx.line_text(line)
        col = max(0, min(pos.col, len(text)))
        return line, to_encoding(text, col, "utf-16")


def display_path(path: str, base: Optional[str] = None) -> str:
    base = os.path.abspath(base or os.getcwd())
    ap = os.path.abspath(path)
    if ap == base or ap.startswith(base.rstrip(os.sep) + os.sep):
        return os.path.relpath(ap, base)
    return ap


def _lsp_range(lines: _Lines, path: str, span: Span) -> dict:
    sl, sc = lines.utf16(path, span.start)
    el, ec = lines.utf16(path, span.end)
    if (el, ec) < (sl, sc):
        el, ec = sl, sc
    return {"start": {"line": sl, "character": sc}, "end": {"line": el, "character": ec}}


# ------------------------------------------------------------------ text

def format_text(diags: Sequence[Diagnostic], base: Optional[str] = None, **_: object) -> str:
    out = []
    for d in diags:
        msg = d.message.replace("\r", " ").replace("\n", " ")
        out.append(f"{display_path(d.path, base)}:{d.span.start.line + 1}:{d.span.start.col + 1}: "
                   f"{d.severity.label}[{d.code}] {msg}")
    return "".join(line + "\n" for line in out)


# ------------------------------------------------------------------ json

def to_json_objects(diags: Sequence[Diagnostic], read_file: ReadFile, base: Optional[str] = None) -> list[dict]:
    lines = _Lines(read_file)
    out = []
    for d in diags:
        out.append({
            "path": display_path(d.path, base),
            "range": _lsp_range(lines, d.path, d.span),
            "severity": d.severity.label,
            "code": d.code,
            "message": d.message,
            "related": [{"path": display_path(r.path, base), "range": _lsp_range(lines, r.path, r.span),
                         "message": r.message} for r in d.related],
            "witness": dict(sorted(d.witness.items())) if d.witness is not None else None,
        })
    return out


def format_json(diags: Sequence[Diagnostic], read_file: ReadFile, base: Optional[str] = None, **_: object) -> str:
    return json.dumps(to_json_objects(diags, read_file, base), indent=2, ensure_ascii=False) + "\n"


# ------------------------------------------------------------------ sarif

_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning",
                Severity.INFORMATION: "note", Severity.HINT: "note"}


def _artifact(path: str, base: str) -> dict:
    shown = display_path(path, base)
    if os.path.isabs(shown):
        return {"uri": "file://" + urllib.parse.quote(shown.replace(os.sep, "/"))}
    return {"uri": urllib.parse.quote(shown.replace(os.sep, "/")), "uriBaseId": "%SRCROOT%"}


def _region(lines: _Lines, path: str, span: Span) -> dict:
    r = _lsp_range(lines, path, span)
    return {"startLine": r["start"]["line"] + 1, "startColumn": r["start"]["character"] + 1,
            "endLine": r["end"]["line"] + 1, "endColumn": r["end"]["character"] + 1}


def to_sarif(diags: Sequence[Diagnostic], read_file: ReadFile, base: Optional[str] = None,
             tool_version: Optional[str] = None) -> dict:
    from .. import __version__
    base = os.path.abspath(base or os.getcwd())
    lines = _Lines(read_file)
    used = sorted({d.code for d in diags})
    rule_index = {c: i for i, c in enumerate(used)}
    rules = []
    docs = _doc_sections()
    for c in used:
        info = CODES.get(c)
        rule = {"id": c, "name": "".join(w.capitalize() for w in c.split("-")),
                "shortDescription": {"text": info.summary if info else c},
                "defaultConfiguration": {"level": _SARIF_LEVEL[info.severity] if info else "warning"}}
        if c in docs:
            rule["help"] = {"text": docs[c], "markdown": docs[c]}
        rules.append(rule)
    results = []
    for d in diags:
        res: dict = {
            "ruleId": d.code,
            "ruleIndex": rule_index[d.code],
            "level": _SARIF_LEVEL[d.severity],
            "message": {"text": d.message},
            "locations": [{"physicalLocation": {"artifactLocation": _artifact(d.path, base),
                                                "region": _region(lines, d.path, d.span)}}],
        }
        if d.related:
            res["relatedLocations"] = [
                {"id": i, "physicalLocation": {"artifactLocation": _artifact(r.path, base),
                                               "region": _region(lines, r.path, r.span)},
                 "message": {"text": r.message}}
                for i, r in enumerate(d.related)]
        if d.witness is not None:
            res["properties"] = {"witness": dict(sorted(d.witness.items()))}
        results.append(res)
    return {
        "$schema": SARIF_SCHEMA,
        "version": SARIF_VERSION,
        "runs": [{
            "tool": {"driver": {"name": "tvl-lsp", "version": tool_version or __version__,
                                "rules": rules}},
            "originalUriBaseIds": {"%SRCROOT%": {"uri": "file://" + urllib.parse.quote(base.replace(os.sep, "/").rstrip("/") + "/")}},
            "columnKind": "utf16CodeUnits",
            "results": results,
        }],
    }


def _doc_sections() -> dict[str, str]:
    """code -> its page of the diagnostics catalogue (package data)."""
    from ..base.catalogue import all_sections
    return all_sections()


def format_sarif(diags: Sequence[Diagnostic], read_file: ReadFile, base: Optional[str] = None, **_: object) -> str:
    return json.dumps(to_sarif(diags, read_file, base), indent=2, ensure_ascii=False) + "\n"


# ------------------------------------------------------------------ github

_GH_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning",
             Severity.INFORMATION: "notice", Severity.HINT: "notice"}


def gh_escape_data(s: str) -> str:
    return s.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def gh_escape_property(s: str) -> str:
    return gh_escape_data(s).replace(":", "%3A").replace(",", "%2C")


def format_github(diags: Sequence[Diagnostic], base: Optional[str] = None, **_: object) -> str:
    out = []
    for d in diags:
        props = [("file", display_path(d.path, base)), ("line", str(d.span.start.line + 1)),
                 ("col", str(d.span.start.col + 1)), ("endLine", str(d.span.end.line + 1)),
                 ("endColumn", str(d.span.end.col + 1)), ("title", d.code)]
        p = ",".join(f"{k}={gh_escape_property(v)}" for k, v in props)
        out.append(f"::{_GH_LEVEL[d.severity]} {p}::{gh_escape_data(d.message)}\n")
    return "".join(out)


def render(fmt: str, diags: Sequence[Diagnostic], read_file: ReadFile, base: Optional[str] = None) -> str:
    if fmt == "text":
        return format_text(diags, base)
    if fmt == "json":
        return format_json(diags, read_file, base)
    if fmt == "sarif":
        return format_sarif(diags, read_file, base)
    if fmt == "github":
        return format_github(diags, base)
    raise ValueError(f"unknown format {fmt!r}")
