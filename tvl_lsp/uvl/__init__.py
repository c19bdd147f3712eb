"""UVL front end: lexer with an indentation pre-pass, grammar (``grammars/uvl.lark``), parser with
line-by-line recovery, and a builder that makes the same feature-model objects as the TVL front
end (:mod:`tvl_lsp.tvl.model`).  Pure: no LSP here.

    parse_uvl(text, path, read_file=None) -> UvlResult(model, diagnostics)

``read_file(abs_path) -> str | None`` supplies imported models (default: read from disk).  The
model is always built, possibly partially, whatever the input.
"""

from __future__ import annotations

import gc
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Optional

if TYPE_CHECKING:  # (importing the package stays cheap: ``tvl-lsp count`` reads plain UVL with
    # :mod:`.plain` alone)
    from ..base.diagnostics import Diagnostic
    from ..tvl.model import Model

__all__ = ["parse_uvl", "UvlResult"]


@dataclass
class UvlResult:
    model: Model
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def errors(self) -> list[Diagnostic]:
        from ..base.diagnostics import Severity
        return [d for d in self.diagnostics if d.severity == Severity.ERROR]


def _default_read(path: str) -> Optional[str]:
    from ..base.files import read_text_or_none
    return read_text_or_none(path)  # regular files within the size cap only


def parse_uvl(text: str, path: str, read_file: Callable[[str], Optional[str]] | None = None) -> UvlResult:
    """Parse and check a UVL model; never raises on bad input."""
    from .build import UvlBuilder
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        b = UvlBuilder(text, str(path), read_file or _default_read)
        model = b.run()
    finally:
        if was_enabled:
            gc.enable()
    seen = set()
    out = []
    for d in sorted(b.diags, key=lambda d: d.sort_key()):
        k = (d.code, d.path, d.span, d.message)
        if k not in seen:
            seen.add(k)
            out.append(d)
    return UvlResult(model, out)
