"""The one diagnostic type shared by the CLI and the language server.

Codes are stable kebab-case strings; each is documented in ``tvl_lsp/data/diagnostics.md`` (the catalogue, :mod:`.catalogue`) and
registered in :data:`CODES` with its default severity and a one-line summary.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any

from .text import Span


class Severity(enum.IntEnum):
    # values equal LSP's DiagnosticSeverity
    ERROR = 1
    WARNING = 2
    INFORMATION = 3
    HINT = 4

    @property
    def label(self) -> str:
        return self.name.lower()


@dataclass(frozen=True)
class Related:
    path: str
    span: Span
    message: str


@dataclass(frozen=True)
class TextEdit:
    """Replace ``span`` of the file at ``path`` by ``new_text`` (a quick fix)."""
    path: str
    span: Span
    new_text: str


@dataclass(frozen=True)
class Fix:
    title: str
    edits: tuple[TextEdit, ...]
    preferred: bool = False


@dataclass
class Diagnostic:
    code: str
    severity: Severity
    path: str
    span: Span
    message: str
    related: list[Related] = field(default_factory=list)
    # variability-aware diagnostics: feature name -> selected?
    witness: dict[str, bool] | None = None
    fixes: list[Fix] = field(default_factory=list)
    # free-form data for the server (e.g. the name a fix would insert)
    data: dict[str, Any] | None = None

    def sort_key(self):
        return (self.path, self.span.start, self.span.end, self.code, self.message)


@dataclass(frozen=True)
class CodeInfo:
    code: str
    severity: Severity
    summary: str
    area: str  # "tvl", "launch", "analysis", "cross"


CODES: dict[str, CodeInfo] = {}


def register(code: str, severity: Severity, summary: str, area: str) -> str:
    """Register a diagnostic code (idempotent). Returns the code for use as a constant."""
    info = CODES.get(code)
    if info is None:
        CODES[code] = CodeInfo(code, severity, summary, area)
    return code
