"""Text positions.

The core stores positions as (line, column) with 0-based lines and columns counted in
Unicode code points.  Only the protocol layer converts columns to the client's negotiated
encoding (UTF-16 by default) with :func:`to_encoding` / :func:`from_encoding`.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass


@dataclass(frozen=True, order=True, slots=True)
class Pos:
    line: int
    col: int  # code points

    def __str__(self) -> str:  # 1-based, as compilers print it
        return f"{self.line + 1}:{self.col + 1}"


@dataclass(frozen=True, order=True, slots=True)
class Span:
    start: Pos
    end: Pos

    @staticmethod
    def of(l1: int, c1: int, l2: int, c2: int) -> "Span":
        return Span(Pos(l1, c1), Pos(l2, c2))

    def contains(self, pos: Pos) -> bool:
        return self.start <= pos <= self.end

    def __str__(self) -> str:
        return f"{self.start}-{self.end}"


ZERO_SPAN = Span(Pos(0, 0), Pos(0, 0))


class LineIndex:
    """Maps character offsets in a text to (line, column) positions and back.

    Lines end at ``\\n``, ``\\r\\n`` or a lone ``\\r``, as LSP defines them.
    """

    __slots__ = ("text", "starts")

    def __init__(self, text: str):
        self.text = text
        starts = [0]
        i = 0
        n = len(text)
        find_n = text.find
        # fast path for \n-only texts
        if "\r" not in text:
            pos = find_n("\n")
            while pos != -1:
                starts.append(pos + 1)
                pos = find_n("\n", pos + 1)
        else:
            while i < n:
                ch = text[i]
                if ch == "\r":
                    if i + 1 < n and text[i + 1] == "\n":
                        i += 1
                    starts.append(i + 1)
                elif ch == "\n":
                    starts.append(i + 1)
                i += 1
        self.starts = starts

    @property
    def line_count(self) -> int:
        return len(self.starts)

    def pos(self, offset: int) -> Pos:
        offset = max(0, min(offset, len(self.text)))
        line = bisect.bisect_right(self.starts, offset) - 1
        return Pos(line, offset - self.starts[line])

    def span(self, start: int, end: int) -> Span:
        return Span(self.pos(start), self.pos(end))

    def offset(self, pos: Pos) -> int:
        line = min(max(pos.line, 0), len(self.starts) - 1)
        start = self.starts[line]
        end = self.line_end(line)
        return min(start + max(pos.col, 0), end)

    def line_end(self, line: int) -> int:
        """Offset of the end of ``line`` without its line terminator."""
        if line + 1 < len(self.starts):
            end = self.starts[line + 1]
            if end > 0 and self.text[end - 1] == "\n":
                end -= 1
            if end > 0 and self.text[end - 1] == "\r":
                end -= 1
            return end
        return len(self.text)

    def line_text(self, line: int) -> str:
        if line < 0 or line >= len(self.starts):
            return ""
        return self.text[self.starts[line]: self.line_end(line)]


def _units(ch: str, encoding: str) -> int:
    o = ord(ch)
    if encoding == "utf-16":
        return 2 if o > 0xFFFF else 1
    if encoding == "utf-8":
        return 1 if o < 0x80 else 2 if o < 0x800 else 3 if o < 0x10000 else 4
    return 1  # utf-32: code points


def to_encoding(line_text: str, col: int, encoding: str = "utf-16") -> int:
    """Code-point column -> column in ``encoding`` units for a line's text."""
    if encoding == "utf-32" or line_text.isascii():
        return col
    return sum(_units(ch, encoding) for ch in line_text[:col])


def from_encoding(line_text: str, col: int, encoding: str = "utf-16") -> int:
    """Column in ``encoding`` units -> code-point column (clamped to the line)."""
    if encoding == "utf-32" or line_text.isascii():
        return max(0, min(col, len(line_text)))
    units = 0
    for i, ch in enumerate(line_text):
        if units >= col:
            return i
        units += _units(ch, encoding)
    return len(line_text)


_onew = object.__new__
# the slots' descriptors: setting them directly skips the frozen dataclass's __init__ checks
_set_line = Pos.__dict__["line"].__set__
_set_col = Pos.__dict__["col"].__set__
_set_start = Span.__dict__["start"].__set__
_set_end = Span.__dict__["end"].__set__


def fast_span(l1: int, c1: int, l2: int, c2: int) -> Span:
    """Span(Pos(l1, c1), Pos(l2, c2)) without the frozen-dataclass __init__ cost (hot path)."""
    a = _onew(Pos)
    _set_line(a, l1)
    _set_col(a, c1)
    b = _onew(Pos)
    _set_line(b, l2)
    _set_col(b, c2)
    sp = _onew(Span)
    _set_start(sp, a)
    _set_end(sp, b)
    return sp


def single_file_span(idx: "LineIndex"):
    """``span(s, e)`` for offsets into ``idx``'s text: :class:`Span` made without the frozen
    dataclass's ``__init__`` (the front ends' hot path)."""
    starts = idx.starts
    n = len(idx.text)
    nl = len(starts)
    br = bisect.bisect_right
    mk = fast_span

    def span(s: int, e: int) -> Span:
        if s > n:
            s = n
        if e < s:
            e = s
        elif e > n:
            e = n
        l1 = br(starts, s) - 1
        b = starts[l1]
        if l1 + 1 >= nl or e < starts[l1 + 1]:
            return mk(l1, s - b, l1, e - b)
        l2 = br(starts, e) - 1
        return mk(l1, s - b, l2, e - starts[l2])
    return span
