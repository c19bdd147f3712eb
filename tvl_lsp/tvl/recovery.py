"""Error recovery helpers of the TVL parser (:func:`tvl_lsp.tvl.parser.parse_tokens`): where a
statement, block or top-level item begins and ends around a token that cannot be used, and which
separator is missing at a line's end."""

from __future__ import annotations

from typing import Optional

from .lexer import Tok
from .raw import SyntaxIssue


_TOP_START = frozenset({"ROOT", "ID", "CONST", "STRUCT", "INTK", "REALK", "BOOL", "ENUM"})


def _opens_item(toks: list, i: int) -> bool:
    """The token at ``i`` begins what can only be a top-level item: 'root X {', 'X {' / 'X.Y {',
    'struct x {', 'const ...'."""
    t = toks[i].type
    if t in ("ROOT", "STRUCT", "CONST"):
        return True
    if t == "ID":
        j = i + 1
        while j + 1 < len(toks) and toks[j].type == "DOT" and toks[j + 1].type == "ID":
            j += 2
        return j < len(toks) and toks[j].type == "LBRACE"
    return False


def _missing_braces(toks: list, smap, issues: list) -> list:
    """A '}' forgotten inside a block, told by the indentation: a '}' that begins its line at a
    column left of the line that opened the innermost '{', where the '{' below that one opened at
    exactly that column, closes the outer block: the inner one lacks its '}'.  It is reported on
    the '{' left open and supplied there (one error, no cascade through the rest of the file)."""
    if len(toks) > 200_000:
        return toks
    line_col: list = []
    first_col: dict = {}
    for t in toks:
        p = smap.span(t.start, t.start).start
        line_col.append((p.line, p.col))
        if p.line not in first_col:
            first_col[p.line] = p.col
    stack: list = []  # indexes of open '{'
    inserts: list = []  # (index to insert before, the '{' left open)
    for i, t in enumerate(toks):
        line, col = line_col[i]
        if (stack and col == 0 and first_col.get(line) == 0 and (i == 0 or line_col[i - 1][0] != line)
                and t.type in _TOP_START and first_col[line_col[stack[-1]][0]] == 0
                and line_col[stack[-1]][0] != line and _opens_item(toks, i)):
            # a top-level item (a feature's body, 'root X {', a declaration) begins at the left
            # margin while a '{' opened at the left margin is still open: its '}' is missing
            inserts.append((i, stack.pop()))
        if t.type == "LBRACE":
            stack.append(i)
        elif t.type == "RBRACE" and stack:
            line, col = line_col[i]
            top = stack[-1]
            if first_col.get(line) == col and len(stack) >= 2:
                ind_top = first_col[line_col[top][0]]
                ind_next = first_col[line_col[stack[-2]][0]]
                if ind_top > col and ind_next == col and line_col[top][0] != line:
                    inserts.append((i, top))
                    stack.pop()
            stack.pop()
    # only where braces do not balance: a file whose braces match is never changed
    missing = sum(t.type == "LBRACE" for t in toks) - sum(t.type == "RBRACE" for t in toks)
    inserts = inserts[:max(0, missing)]
    if not inserts:
        return toks
    out = list(toks)
    for i, top in reversed(inserts):
        if top > 0 and toks[top - 1].type == "IN" and toks[i - 1].type == "SEMI":
            i -= 1  # 'in {a, b;': the set lacks its '}', the declaration has its ';'
        prev = toks[i - 1]
        out.insert(i, Tok("RBRACE", "", prev.end, prev.end))
        o = toks[top]
        issues.append(SyntaxIssue("syntax-error", o.start, o.end,
                                  f"this '{{' (line {line_col[top][0] + 1}) is never closed: a '}}' is missing "
                                  f"before line {line_col[i][0] + 1 if toks[i].type != 'SEMI' else line_col[i + 1][0] + 1}"))
    return out


def _prev_alive(alive, k) -> Optional[int]:
    j = k - 1
    while j >= 0 and not alive[j]:
        j -= 1
    return j if j >= 0 else None


def _separator(toks, depth, alive, k, expected) -> str:
    """Which separator is missing before ``k``: ',' between the children of a group, else ';'."""
    if "COMMA" not in expected:
        return "SEMI"
    if "SEMI" not in expected:
        return "COMMA"
    d = depth[k]
    j = k - 1
    while j >= 0 and not (toks[j].type == "LBRACE" and depth[j] == d - 1):
        j -= 1
    i = j - 1
    if i >= 0 and toks[i].type == "RBRACK":  # group [n..m] {
        while i >= 0 and toks[i].type != "LBRACK":
            i -= 1
        i -= 1
    elif i >= 0 and toks[i].type in ("ALLOF", "ONEOF", "SOMEOF"):
        i -= 1
    # inside `group ... { ... }` (not inside a child's own body): the children are separated by ','
    return "COMMA" if i >= 0 and toks[i].type == "GROUP" else "SEMI"


def _find(ltoks, tok) -> Optional[int]:
    lo, hi = 0, len(ltoks) - 1
    sp = tok.start
    while lo <= hi:
        mid = (lo + hi) // 2
        s = ltoks[mid].start
        if s == sp:
            return mid
        if s < sp:
            lo = mid + 1
        else:
            hi = mid - 1
    return None


def _statement_range(toks, depth, alive, k) -> tuple[int, int]:
    d = depth[k]
    a = k
    while a > 0:
        j = a - 1
        if not alive[j]:
            a = j
            continue
        t = toks[j].type
        if depth[j] == d and t in ("SEMI", "RBRACE", "LBRACE", "COMMA"):
            break
        if depth[j] < d:  # the '{' opening our block
            break
        a = j
    b = k
    n = len(toks)
    while b < n:
        t = toks[b].type
        if depth[b] == d and t == "SEMI":
            break
        if t == "RBRACE" and depth[b] < d:
            b -= 1
            break
        if depth[b] == d and t == "RBRACE" and b > k:
            # a '}' closing something we were inside of at the same level: keep it
            break
        b += 1
    return a, min(b, n - 1)


def _block_range(toks, depth, k) -> tuple[int, int]:
    """The construct whose block the '}' at ``k`` closes: from its statement start to ``k``."""
    d = depth[k]  # depth of the '}' (after closing) == depth of its '{'
    j = k - 1
    while j >= 0 and not (toks[j].type == "LBRACE" and depth[j] == d):
        j -= 1
    if j < 0:
        return k, k
    a = j
    while a > 0:
        i = a - 1
        if depth[i] < d or (depth[i] == d and toks[i].type in ("SEMI", "RBRACE", "LBRACE", "COMMA")):
            break
        a = i
    return a, k


def _item_range(toks, depth, alive, k) -> tuple[int, int]:
    a = k
    while a > 0 and not (depth[a - 1] == 0 and toks[a - 1].type in ("SEMI", "RBRACE")):
        a -= 1
    b = k
    n = len(toks)
    while b < n - 1 and not (depth[b] == 0 and toks[b].type in ("SEMI", "RBRACE") and b >= k):
        b += 1
    return a, b


_DECL_START = frozenset({"INTK", "REALK", "BOOL", "ENUM", "CONST"})
_TYPE_KW = frozenset({"INTK", "REALK", "BOOL", "ENUM"})
_LITERALS = frozenset({"INT", "REAL", "TRUE", "FALSE"})


def _declaration_head(toks, depth, alive, a, b, k) -> Optional[set]:
    """When the statement ``a..b`` (ending with its ';') that has a syntax error at ``k`` is an
    attribute or constant declaration whose type and name come before ``k``: the indexes of the
    tokens that still make a valid declaration ('int speed;', 'const int most 2;'), else None."""
    idx = [i for i in range(a, b + 1) if alive[i]]
    if len(idx) < 3 or toks[idx[-1]].type != "SEMI" or depth[idx[-1]] != depth[idx[0]]:
        return None
    t = [toks[i].type for i in idx]
    if t[0] == "CONST":
        if (len(idx) >= 5 and t[1] in _TYPE_KW and t[2] == "ID" and idx[2] < k
                and t[-2] in _LITERALS and idx[-2] > k):
            return {idx[0], idx[1], idx[2], idx[-2], idx[-1]}
        return None
    if t[0] in _TYPE_KW and t[1] == "ID" and idx[1] < k:
        return {idx[0], idx[1], idx[-1]}
    return None
