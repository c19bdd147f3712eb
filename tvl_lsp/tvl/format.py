"""TVL formatter: re-indents by brace level and normalises the blanks between tokens.

It never adds, removes or reorders a token and never glues two tokens together (a run of blanks
between tokens becomes one space; tokens that touched keep touching), so the formatted text
means exactly what the original meant.  Comments are kept verbatim.  The result depends only on
the token sequence, so formatting twice gives the same text.
"""

from __future__ import annotations

from typing import Optional

from .lexer import tokenize

INDENT = "  "
_NO_CONTINUATION = {"SEMI", "LBRACE", "RBRACE", "COMMA", "COMMENT", "INCLUDE"}


def format_tvl(text: str) -> Optional[str]:
    """The formatted text, or None when ``text`` has lexical or syntax errors."""
    from . import parse_model
    res = parse_model(text, "<format>", read_file=lambda p: "")
    if any(d.code in ("syntax-error", "illegal-character", "unterminated-comment", "unterminated-string",
                      "nesting-too-deep", "file-too-large") for d in res.diagnostics):
        return None
    toks, errors = tokenize(text, keep_comments=True)
    if errors:
        return None
    if not toks:
        return ""
    # line number of every offset boundary we need
    line_of = _line_finder(text)
    out: list[str] = []
    depth = 0          # brace depth
    paren = 0          # ( and [ depth
    prev_tok = None    # previous token (for blanks and continuation)
    prev_line_last = None
    cur_line = None
    for t in toks:
        ls = line_of(t.start)
        raw = text[t.start:t.end]
        if cur_line is None or ls != cur_line:
            # a new output line
            if cur_line is not None:
                gap = ls - line_of(prev_tok.end)  # lines between the end of the last token and this one
                out.append("\n")
                if gap >= 2:
                    out.append("\n")
            level = depth - (1 if t.type == "RBRACE" else 0)
            if paren > 0:
                level += 1
            elif (prev_line_last is not None and prev_line_last.type not in _NO_CONTINUATION
                  and t.type not in ("RBRACE", "LBRACE", "COMMENT")):
                level += 1
            out.append(INDENT * max(level, 0))
            out.append(raw)
        else:
            out.append(" " if t.start > prev_tok.end else "")
            out.append(raw)
        if t.type == "LBRACE":
            depth += 1
        elif t.type == "RBRACE":
            depth = max(0, depth - 1)
        elif t.type in ("LPAR", "LBRACK"):
            paren += 1
        elif t.type in ("RPAR", "RBRACK"):
            paren = max(0, paren - 1)
        prev_tok = t
        cur_line = line_of(t.end) if "\n" in raw else ls
        if t.type != "COMMENT":
            prev_line_last = t
        elif prev_line_last is None or True:
            # a comment ends the statement context only if it is alone on its line
            pass
    out.append("\n")
    return "".join(out)


def _line_finder(text: str):
    import bisect
    starts = [0]
    pos = text.find("\n")
    while pos != -1:
        starts.append(pos + 1)
        pos = text.find("\n", pos + 1)

    def line_of(off: int) -> int:
        return bisect.bisect_right(starts, off) - 1
    return line_of
