"""Error recovery helpers of the TVL parser (:func:`tvl_lsp.tvl.parser.parse_tokens`): where a
statement, block or top-level item begins and ends around a token that cannot be used, and which
separator is missing at a line's end."""

from __future__ import annotations

from typing import Optional


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
