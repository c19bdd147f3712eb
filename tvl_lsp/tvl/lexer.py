"""The TVL lexer: mirrors the reference TVLParser's JFlex specification.

- Every keyword is reserved; ``oneof/someof/allof/ifin/ifout/selectedchildren`` are aliases of
  their camel-case forms.
- A number may carry a sign: ``-12`` is one token (so ``a-1`` is a syntax error in the reference,
  while ``a - 1`` is fine).
- A name is made of letters, digits, ``_`` and ``$`` and may begin with a digit (``3D_Camera``):
  the longest match wins, and a run of digits alone is a number.
- Comments ``//`` and ``/* */`` are skipped; an unterminated block comment is reported.
- Characters the reference does not know are reported (``illegal-character``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

KEYWORDS = {
    "shared": "SHARED", "root": "ROOT", "opt": "OPT", "bool": "BOOL", "int": "INTK",
    "enum": "ENUM", "struct": "STRUCT", "real": "REALK", "ifin": "IFIN", "ifout": "IFOUT",
    "ifIn": "IFIN", "ifOut": "IFOUT", "const": "CONST", "group": "GROUP", "oneof": "ONEOF",
    "someof": "SOMEOF", "allof": "ALLOF", "oneOf": "ONEOF", "someOf": "SOMEOF", "allOf": "ALLOF",
    "parent": "PARENT", "this": "THIS", "children": "CHILDREN", "selectedchildren": "SCHILDREN",
    "selectedChildren": "SCHILDREN", "true": "TRUE", "false": "FALSE", "max": "MAX", "min": "MIN",
    "sum": "SUM", "mul": "MUL", "avg": "AVG", "count": "COUNT", "and": "ANDAGG", "or": "ORAGG",
    "xor": "XORAGG", "abs": "ABS", "is": "IS", "in": "IN", "excludes": "EXCLUDES",
    "requires": "REQUIRES", "data": "DATA",
}

OPERATORS = {
    "&&": "AND", "||": "OR", "->": "IMPLIES", "<->": "IFF", "<-": "RIMPLIES", "!": "NOT",
    "==": "EQ", "!=": "NEQ", ">=": "GEQ", "<=": "LEQ", ">": "GT", "<": "LT", "+": "PLUS",
    "-": "MINUS", "*": "TIMES", "/": "DIVIDE", "[": "LBRACK", "]": "RBRACK", ",": "COMMA",
    "(": "LPAR", ")": "RPAR", "{": "LBRACE", "}": "RBRACE", "..": "DOTDOT", ".": "DOT",
    "?": "QUEST", ":": "COLON", ";": "SEMI",
}

_TOKEN_RE = re.compile(
    r"""
    [ \t\f\r\n]*
    (?:
    (?P<lcomment>//[^\r\n]*)
  | (?P<bcomment>/\*.*?\*/)
  | (?P<ubcomment>/\*)
  | (?P<include>include[ \t]*\([ \t]*(?P<incpath>[^)\r\n]*?)[ \t]*\)[ \t]*;)
  | (?P<real>-?[0-9]+\.[0-9]+(?![0-9]))
  | (?P<int>-?[0-9]+(?![\w$]))
  | (?P<string>"[^"]*")
  | (?P<ustring>")
  | (?P<id>[\w$]+)
  | (?P<op><->|->|<-|&&|\|\||==|!=|>=|<=|\.\.|[!><+\-*/\[\],(){}.?:;])
  | (?P<bad>[^\w\s$"/\[\](){}.,;:?!<>=&|+\-*]+|\S)
    )
    """,
    re.VERBOSE | re.DOTALL,
)


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


def tokenize(text: str, keep_comments: bool = False, max_tokens: int = 0) -> tuple[list[Tok], list[LexError]]:
    """Tokens and lexical errors of ``text``; raises TooManyTokens past ``max_tokens`` (if > 0)."""
    toks: list[Tok] = []
    errors: list[LexError] = []
    append = toks.append
    kw = KEYWORDS
    ops = OPERATORS
    pos = 0
    n = len(text)
    match = _TOKEN_RE.match
    bad_start = -1
    bad_end = -1
    while pos < n:
        m = match(text, pos)
        if m is None:  # only blanks remain
            break
        kind = m.lastgroup
        start = m.start(kind)
        end = m.end()
        if kind != "bad" and bad_start >= 0:
            errors.append(LexError("illegal-character", bad_start, bad_end, text[bad_start:bad_end]))
            bad_start = -1
        if kind == "id":
            v = m.group(kind)
            append(Tok(kw.get(v, "ID"), v, start, end))
        elif kind == "op":
            v = m.group(kind)
            append(Tok(ops[v], v, start, end))
        elif kind == "int":
            append(Tok("INT", m.group(kind), start, end))
        elif kind == "real":
            append(Tok("REAL", m.group(kind), start, end))
        elif kind == "lcomment" or kind == "bcomment":
            if keep_comments:
                append(Tok("COMMENT", m.group(kind), start, end))
        elif kind == "include":
            append(Tok("INCLUDE", m.group("incpath"), start, end))
        elif kind == "string":
            append(Tok("STRING", m.group(kind), start, end))
        elif kind == "ubcomment":
            errors.append(LexError("unterminated-comment", start, min(n, start + 2), "/*"))
            break
        elif kind == "ustring":
            eol = text.find("\n", start)
            eol = n if eol < 0 else eol
            errors.append(LexError("unterminated-string", start, eol, text[start:eol]))
            end = eol
        else:  # bad
            if bad_start < 0:
                bad_start = start
            bad_end = end
            if len(errors) > 200:
                break
        pos = end
        if max_tokens and len(toks) > max_tokens:
            raise TooManyTokens(len(toks))
    if bad_start >= 0:
        errors.append(LexError("illegal-character", bad_start, bad_end, text[bad_start:bad_end]))
    return toks, errors
