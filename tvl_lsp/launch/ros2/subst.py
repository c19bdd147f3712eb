"""ROS 2 launch substitution syntax: ``$(name arg ...)`` with positions.

ros2/launch parses every substitution string with a small grammar (its ``grammar.lark``):

- at the top level, text is anything up to an unescaped ``$(``; ``$(`` always starts a
  substitution (``\\$(`` is text);
- a substitution is ``$(`` IDENTIFIER, then optionally ONE blank and arguments separated by
  single blanks, then ``)``; IDENTIFIER is a letter followed by letters, digits, ``_`` or ``-``;
- an argument is either a run of parts (text without blanks, quotes, ``(`` or ``)`` unless
  escaped with a backslash, and nested substitutions), or a whole ``'...'`` / ``"..."``
  template: inside quotes blanks and the other quote are text, and nested substitutions take
  arguments without templates;
- text has its backslash escapes removed (``\\x`` -> ``x``).

This module is an independent implementation of that grammar with exact positions: a string
parses to a list of :class:`Text` and :class:`Sub` parts, or raises :class:`SubstSyntaxError`
(launch then refuses the whole file).  Nothing here evaluates anything.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Union

Part = Union["Text", "Sub"]


@dataclass
class Text:
    text: str         # escapes removed
    start: int        # offsets in the parsed string
    end: int


@dataclass
class Sub:
    name: str
    args: list[list[Part]]
    start: int        # the '$'
    end: int          # after ')'
    name_start: int = 0
    arg_spans: list[tuple[int, int]] = field(default_factory=list)
    quote: str = ""   # the quote of the argument it is written in ("": none)

    def __repr__(self) -> str:
        return f"$({self.name} {self.args!r})"


class SubstSyntaxError(ValueError):
    def __init__(self, message: str, pos: int):
        super().__init__(message)
        self.pos = pos


_ESC = re.compile(r"\\(.)")


def unescape(s: str) -> str:
    """launch's ``replace_escaped_characters``."""
    return _ESC.sub(r"\1", s)


def _is_letter(c: str) -> bool:
    return ("a" <= c <= "z") or ("A" <= c <= "Z")


def _is_ident(c: str) -> bool:
    return _is_letter(c) or ("0" <= c <= "9") or c in "_-"


class _Parser:
    def __init__(self, s: str):
        self.s = s
        self.n = len(s)

    def error(self, msg: str, pos: int):
        raise SubstSyntaxError(msg, pos)

    def starts_sub(self, i: int) -> bool:
        """An unescaped ``$(`` at i."""
        s = self.s
        return s.startswith("$(", i) and not (i > 0 and s[i - 1] == "\\")

    # -- top level
    def template(self) -> list[Part]:
        out: list[Part] = []
        i = 0
        s = self.s
        while i < self.n:
            if self.starts_sub(i):
                sub, i = self.substitution(i, None)
                out.append(sub)
                continue
            j = s.find("$(", i + 1)  # the next unescaped "$(" (a jump, not a loop per character)
            while j > 0 and s[j - 1] == "\\":
                j = s.find("$(", j + 1)
            if j < 0:
                j = self.n
            out.append(Text(unescape(s[i:j]), i, j))
            i = j
        return out

    # -- substitutions: quote is None (unquoted context), "'" or '"'
    def substitution(self, i: int, quote) -> tuple[Sub, int]:
        s = self.s
        start = i
        i += 2
        j = i
        if j >= self.n or not _is_letter(s[j]):
            self.error("a substitution name (a letter, then letters, digits, '_' or '-') must follow '$('", j)
        while j < self.n and _is_ident(s[j]):
            j += 1
        sub = Sub(s[i:j], [], start, start, i, [], quote or "")
        i = j
        if i < self.n and s[i] == " ":
            while True:
                i += 1  # the single blank
                a0 = i
                val, i = self.value(i, quote)
                sub.args.append(val)
                sub.arg_spans.append((a0, i))
                if i < self.n and s[i] == " ":
                    continue
                break
        if i >= self.n:
            self.error(f"'$({sub.name}' is not closed: ')' expected", i)
        if s[i] != ")":
            what = "a blank" if s[i] == " " else repr(s[i])
            self.error(f"unexpected {what} in '$({sub.name} ...)': arguments are separated by one blank "
                       "and ')' closes the substitution", i)
        sub.end = i + 1
        return sub, i + 1

    def value(self, i: int, quote) -> tuple[list[Part], int]:
        s = self.s
        if i >= self.n or s[i] in " )":
            self.error("an empty argument (two blanks in a row, or a blank before ')')", i)
        if quote is None and s[i] in "'\"":
            return self.quoted(i, s[i])
        parts: list[Part] = []
        while i < self.n:
            if self.starts_sub(i):
                sub, i = self.substitution(i, quote)
                parts.append(sub)
                continue
            j = i
            while j < self.n and self.rchar(j, quote):
                j += 1
            if j == i:
                break
            parts.append(Text(unescape(s[i:j]), i, j))
            i = j
        if not parts:
            self.error(f"unexpected {s[i]!r} in a substitution argument (quote or escape it)", i)
        return parts, i

    def rchar(self, j: int, quote) -> bool:
        """Is s[j] part of an unquoted argument's text (the *_RSTRING terminals)?"""
        s = self.s
        c = s[j]
        prev = s[j - 1] if j > 0 else ""
        if c == "\\":
            return True
        if c == " ":
            return False
        if c in "()":
            return prev == "\\"
        if c == "$":
            return prev == "\\" or not s.startswith("$(", j)
        if c == "'":
            return prev == "\\" or quote == '"'
        if c == '"':
            return prev == "\\" or quote == "'"
        return True

    def quoted(self, i: int, q: str) -> tuple[list[Part], int]:
        """A whole '...' or "..." argument (a quote after a backslash does not close it)."""
        s = self.s
        i += 1
        parts: list[Part] = []
        while True:
            if i >= self.n:
                self.error(f"the quote {q} is not closed", i)
            if s[i] == q and s[i - 1] != "\\":
                break
            if self.starts_sub(i):
                sub, i = self.substitution(i, q)
                parts.append(sub)
                continue
            j = i
            while j < self.n and not self.starts_sub(j) and not (s[j] == q and s[j - 1] != "\\"):
                j += 1
            parts.append(Text(unescape(s[i:j]), i, j))
            i = j
        return parts, i + 1


def parse(s: str) -> list[Part]:
    """Parse a substitution string (raises :class:`SubstSyntaxError`)."""
    if not s:
        return [Text("", 0, 0)]
    return _Parser(s).template()


def is_text(parts: list[Part]) -> bool:
    return all(isinstance(p, Text) for p in parts)


def plain(parts: list[Part]) -> str:
    """The text of parts without substitutions (``$(...)`` written back)."""
    out = []
    for p in parts:
        if isinstance(p, Text):
            out.append(p.text)
        else:
            out.append("$(" + p.name + "".join(" " + plain(a) for a in p.args) + ")")
    return "".join(out)


def walk(parts: list[Part]):
    """Every Sub in parts, outermost first."""
    for p in parts:
        if isinstance(p, Sub):
            yield p
            for a in p.args:
                yield from walk(a)
