"""Plain-words labels of a model's pieces for explanations: a constraint's source text,
shortened to one line."""

from __future__ import annotations

from array import array
from itertools import accumulate
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


# the line breaks of str.splitlines() other than "\n"
_OTHER_BREAKS = ("\r", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029")


class _Lines:
    """The lines of a text (``str.splitlines()``), one at a time.  Given the length of each
    line (a DIMACS constraint has them: ``line_lens``) and a text whose only line break is
    ``"\n"``, by the offsets of the lines (8 bytes a line) rather than a list of them (a
    string a line: 40 MB for 600,000 clauses, when an explanation needs a few)."""

    def __init__(self, text: str, lens: Optional[list[int]]):
        self.text = text
        self.lens = lens
        if (lens is not None and len(text) - sum(lens) - len(lens) in (0, -1)  # the lengths are this text's
                and not any(b in text for b in _OTHER_BREAKS)):
            self.starts: Optional[array] = array("q", accumulate(map((1).__add__, lens), initial=0))
            self.lines: Optional[list[str]] = None
        else:
            self.starts = None
            self.lines = text.splitlines()

    def __len__(self) -> int:
        return len(self.lines) if self.lines is not None else len(self.lens)  # type: ignore[arg-type]

    def __getitem__(self, ln: int) -> str:
        if self.lines is not None:
            return self.lines[ln]
        start = self.starts[ln]  # type: ignore[index]
        return self.text[start:start + self.lens[ln]]  # type: ignore[index]


def line_text(model: M.Model, c: M.Constraint, cache: dict, limit: int = 80) -> str:
    """:func:`source_text` of a constraint that is one whole line (a DIMACS clause), by line."""
    lines = cache.get(("lines", c.path))
    if lines is None:
        lines = cache[("lines", c.path)] = _Lines(model.sources.get(c.path) or "", getattr(c, "line_lens", None))
    ln = c.span.start.line
    s = " ".join(lines[ln].split()) if 0 <= ln < len(lines) and c.span.start.col == 0 else ""
    if not s:
        return source_text(model, c.path, c.span, limit, cache)
    return s if len(s) <= limit else s[: limit - 1] + "…"
