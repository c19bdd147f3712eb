"""The UVL lexer and its indentation pre-pass.

:func:`tokenize` follows uvl-parser's ANTLR lexer: every keyword is reserved (the longest match
wins, so ``group-cardinality`` is one keyword and ``orange`` a name), a plain name starts with a
letter and goes on with letters, digits and ``_ # § % ? \\ ' ä ü ö ß ;``, a quoted name is
``"..."`` (no line break inside), a string is ``'...'``, ``[1..3]`` / ``[2]`` / ``[0..*]`` is one
cardinality token, numbers may carry a ``-`` sign glued to them, ``//`` and ``/* */`` are
comments.  Departure: a double-quoted text may contain dots (``"a.b"``); where a name is
expected the builder rejects it, where an attribute value is expected it is a string.

:func:`layout` turns line structure into ``_NL`` / ``_INDENT`` / ``_DEDENT`` tokens as UVL's
own Python lexer does: only the first token of a physical line outside brackets starts a
logical line; its indentation is the width of the line's leading blanks (a tab advances to the
next multiple of 8); a deeper line opens a block, a shallower one closes blocks down to the
level it matches -- a level that matches no open block is reported and read as the nearest
enclosing level.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

KEYWORDS = {
    "namespace": "NAMESPACE", "include": "INCLUDE", "imports": "IMPORTS", "as": "AS",
    "features": "FEATURES", "constraints": "CONSTRAINTS", "constraint": "CONSTRAINT",
    "cardinality": "CARDINALITY", "or": "OR_G", "alternative": "ALTERNATIVE", "optional": "OPTIONAL",
    "mandatory": "MANDATORY", "String": "STRING_T", "Integer": "INTEGER_T", "Boolean": "BOOLEAN_T",
    "Real": "REAL_T", "Type": "TYPE_KW", "Arithmetic": "ARITHMETIC_KW", "len": "LEN", "sum": "SUM",
    "avg": "AVG", "floor": "FLOOR", "ceil": "CEIL", "true": "TRUE", "false": "FALSE",
}
HYPHENATED = {"group-cardinality": "GROUP_CARD_KW", "feature-cardinality": "FEATURE_CARD_KW",
              "aggregate-function": "AGGREGATE_KW", "string-constraints": "STRING_CONSTRAINTS_KW"}

OPERATORS = {
    "<=>": "IFF", "=>": "IMPLIES", "==": "EQ", "!=": "NEQ", "<=": "LEQ", ">=": "GEQ", "<": "LT",
    ">": "GT", "!": "NOT", "&": "AND", "|": "OR", "+": "PLUS", "-": "MINUS", "*": "TIMES", "/": "DIV",
    "(": "LPAR", ")": "RPAR", "[": "LBRACK", "]": "RBRACK", "{": "LBRACE", "}": "RBRACE",
    ",": "COMMA", ".": "DOT",
}
_OPEN = {"LPAR", "LBRACK", "LBRACE"}
_CLOSE = {"RPAR", "RBRACK", "RBRACE"}

_TOKEN_RE = re.compile(
    r"""
    [ \t\f]*
    (?:
    (?P<end>\Z)
  | (?P<nl>\r\n|\r|\n)
  | (?P<lcomment>//[^\r\n]*)
  | (?P<bcomment>/\*.*?\*/)
  | (?P<ubcomment>/\*)
  | (?P<card>\[[ \t]*[0-9]+[ \t]*(?:\.\.[ \t]*(?:[0-9]+|\*)[ \t]*)?\])
  | (?P<hkw>(?:group|feature)-cardinality|aggregate-function|string-constraints)(?![\w#§%?\\'äüöß;])
  | (?P<float>-?[0-9]*\.[0-9]+)
  | (?P<int>-?[0-9]+)
  | (?P<id>[A-Za-z][A-Za-z0-9_#§%?\\'äüöß;]*)
  | (?P<qid>"[^"\r\n]*")
  | (?P<uqid>")
  | (?P<string>'[^'\r\n]*')
  | (?P<ustring>')
  | (?P<op><=>|=>|==|!=|<=|>=|[<>!&|+\-*/()\[\]{},.])
  | (?P<bad>.)
    )
    """,
    re.VERBOSE | re.DOTALL,
)

# The common physical line, read without the general pattern: indentation (blanks and tabs), one
# plain or quoted name (or keyword), trailing blanks, the line break.  It makes the very tokens
# and line the general loop makes (tests/test_uvl_fastpath.py compares them).
_SIMPLE_LINE_RE = re.compile(
    r"""([ \t]*)(?:([A-Za-z][A-Za-z0-9_#§%?\\'äüöß;]*)|("[^"\r\n]*"))[ \t]*(?:\r\n|\n|\r)""")


@dataclass(slots=True)
class Tok:
    type: str
    value: str
    start: int
    end: int


@dataclass(slots=True)
class LexError:
    kind: str  # "illegal-character" | "unterminated-comment" | "unterminated-string"
    start: int
    end: int
    text: str


class TooManyTokens(Exception):
    pass


@dataclass(slots=True)
class Line:
    """A logical line: its tokens (without layout tokens) and indentation width."""
    indent: int
    toks: list[Tok]
    start: int  # offset of the physical line's first character
    alive: bool = True
    # tokens kept after a repair (None: all of them)
    keep: int | None = None


def tokenize(text: str, max_tokens: int = 0, fast: bool = True) -> tuple[list[Line], list[LexError]]:
    """The logical lines of ``text`` and its lexical errors.  ``fast=False`` reads every line
    with the general pattern (the tests compare both)."""
    lines: list[Line] = []
    errors: list[LexError] = []
    kw = KEYWORDS
    ops = OPERATORS
    pos = 0
    n = len(text)
    match = _TOKEN_RE.match
    simple = _SIMPLE_LINE_RE.match
    line_start = 0          # offset of the current physical line
    opened = 0              # bracket depth (line breaks inside brackets do not count)
    cur: list[Tok] | None = None
    ntok = 0
    bad_start = bad_end = -1

    def flush_bad():
        nonlocal bad_start
        if bad_start >= 0:
            errors.append(LexError("illegal-character", bad_start, bad_end, text[bad_start:bad_end]))
            bad_start = -1

    while pos < n:
        m = match(text, pos)
        if m is None:
            break
        kind = m.lastgroup
        if kind == "end":
            break
        start = m.start(kind)
        end = m.end()
        pos = end
        if kind != "bad":
            flush_bad()
        if kind == "nl":
            line_start = end
            if opened == 0:
                cur = None
                if fast:
                    # the common lines: one name (or keyword) each
                    while True:
                        fm = simple(text, pos)
                        if fm is None:
                            break
                        v = fm.group(2)
                        if v is not None:
                            t = Tok(kw.get(v, "ID"), v, fm.start(2), fm.end(2))
                        else:
                            v = fm.group(3)
                            t = Tok("QID", v, fm.start(3), fm.end(3))
                        ind = fm.group(1)
                        if "\t" not in ind:
                            w = len(ind)
                        elif " " not in ind:
                            w = 8 * len(ind)  # tabs only
                        else:
                            w = _width(text, pos)
                        lines.append(Line(w, [t], pos))
                        pos = line_start = fm.end()
                        ntok += 1
                        if max_tokens and ntok > max_tokens:
                            raise TooManyTokens(ntok)
            continue
        if kind == "lcomment":
            continue
        if kind == "bcomment":
            nl = max(text.rfind("\n", start, end), text.rfind("\r", start, end))
            if nl >= 0:
                line_start = nl + 1
            continue
        if kind == "ubcomment":
            errors.append(LexError("unterminated-comment", start, start + 2, "/*"))
            break
        if kind == "bad":
            if bad_start < 0:
                bad_start = start
            bad_end = end
            if len(errors) > 200:
                break
            continue
        if kind in ("uqid", "ustring"):
            eol = end
            while eol < n and text[eol] not in "\r\n":
                eol += 1
            errors.append(LexError("unterminated-string", start, eol, text[start:eol]))
            pos = eol
            continue
        v = m.group(kind)
        if kind == "id":
            t = Tok(kw.get(v, "ID"), v, start, end)
        elif kind == "op":
            t = Tok(ops[v], v, start, end)
        elif kind == "qid":
            t = Tok("QID", v, start, end)
        elif kind == "string":
            t = Tok("STRING", v, start, end)
        elif kind == "int":
            t = Tok("INT", v, start, end)
        elif kind == "float":
            t = Tok("FLOAT", v, start, end)
        elif kind == "card":
            t = Tok("CARD", v, start, end)
        else:  # hkw
            t = Tok(HYPHENATED[v], v, start, end)
        if cur is None:
            cur = []
            lines.append(Line(_width(text, line_start), cur, line_start))
        cur.append(t)
        if t.type in _OPEN:
            opened += 1
        elif t.type in _CLOSE and opened > 0:
            opened -= 1
        ntok += 1
        if max_tokens and ntok > max_tokens:
            raise TooManyTokens(ntok)
    flush_bad()
    return lines, errors


def _width(text: str, i: int) -> int:
    w = 0
    n = len(text)
    while i < n:
        c = text[i]
        if c == " ":
            w += 1
        elif c == "\t":
            w += 8 - (w % 8)
        elif c == "\f":
            w = 0
        else:
            break
        i += 1
    return w


@dataclass
class Layout:
    tokens: list[Tok]
    # (line index, offset, end, message) of indentation problems
    problems: list[tuple[int, int, int, str]] = field(default_factory=list)
    # index in ``tokens`` of each line's first token, parallel to the alive lines
    line_of_token: list[int] = field(default_factory=list)


def layout(lines: list[Line], end_pos: int) -> Layout:
    """The token stream with ``_NL`` / ``_INDENT`` / ``_DEDENT`` for the alive lines.
    ``line_of_token[i]`` is the index (in ``lines``) of the line token ``i`` belongs to."""
    out: list[Tok] = []
    owner: list[int] = []
    problems: list[tuple[int, int, int, str]] = []
    stack = [0]
    for li, ln in enumerate(lines):
        if not ln.alive:
            continue
        toks = ln.toks if ln.keep is None else ln.toks[:ln.keep]
        if not toks:
            continue
        first = toks[0]
        ind = ln.indent
        if ind > stack[-1]:
            stack.append(ind)
            out.append(Tok("_INDENT", "", first.start, first.start))
            owner.append(li)
        elif ind < stack[-1]:
            popped = None
            while len(stack) > 1 and stack[-1] > ind:
                popped = stack.pop()
                out.append(Tok("_DEDENT", "", first.start, first.start))
                owner.append(li)
            if stack[-1] != ind:
                # between two levels: read it at the deeper one (one block less closed)
                problems.append((li, ln.start, first.start,
                                 "this line's indentation matches no enclosing level (check tabs and spaces)"))
                if popped is not None:
                    stack.append(popped)
                    out.pop()
                    owner.pop()
        out.extend(toks)
        owner.extend([li] * len(toks))
        last = toks[-1]
        out.append(Tok("_NL", "", last.end, last.end))
        owner.append(li)
    for _ in stack[1:]:
        out.append(Tok("_DEDENT", "", end_pos, end_pos))
        owner.append(len(lines))
    return Layout(out, problems, owner)
