"""Plain-words labels of a model's pieces for explanations: a constraint's source text,
shortened to one line."""

from __future__ import annotations

from typing import Optional

from ..base.text import ZERO_SPAN, LineIndex, Span
from ..tvl import model as M


def source_text(model: M.Model, path: str, span: Span, limit: int = 80,
                cache: Optional[dict] = None) -> str:
    text = model.sources.get(path)
    if not text or span == ZERO_SPAN:
        return ""
    idx = cache.get(path) if cache is not None else None
    if idx is None:
        idx = LineIndex(text)
        if cache is not None:
            cache[path] = idx
    try:
        s = text[idx.offset(span.start):idx.offset(span.end)]
    except Exception:
        return ""
    s = " ".join(s.split())
    return s if len(s) <= limit else s[: limit - 1] + "…"


def line_text(model: M.Model, c: M.Constraint, cache: dict, limit: int = 80) -> str:
    """:func:`source_text` of a constraint that is one whole line (a DIMACS clause), by line."""
    lines = cache.get(("lines", c.path))
    if lines is None:
        lines = cache[("lines", c.path)] = (model.sources.get(c.path) or "").splitlines()
    ln = c.span.start.line
    s = " ".join(lines[ln].split()) if 0 <= ln < len(lines) and c.span.start.col == 0 else ""
    if not s:
        return source_text(model, c.path, c.span, limit, cache)
    return s if len(s) <= limit else s[: limit - 1] + "…"
