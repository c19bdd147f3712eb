"""Plain UVL read for counting: the Boolean subset, without spans or model objects.

``tvl-lsp count`` of a UVL model needs its CNF and nothing else.  The full front end
(:func:`tvl_lsp.uvl.parse_uvl`: tokens, layout, parser with recovery, a model with a span on
every node, name resolution with suggestions, then :mod:`tvl_lsp.analysis.encode`) spends on a
640 KB model more than twice what counting its DIMACS twin takes.  :func:`read_plain` reads
the subset that industrial models use -- a tree of plain or quoted names under ``mandatory`` /
``optional`` / ``alternative`` / ``or`` / ``[n..m]`` groups, ``abstract`` flags and string
attributes, constraints of names with ``! & | => <=>`` and parentheses -- into lists and
tuples, and :mod:`tvl_lsp.analysis.plaincnf` makes the clauses the encoding makes, in the same
order.

Anything else -- imports, comments, typed features, other attributes, arithmetic, a name
that resolves to no feature or to two, odd indentation, expressions nested too deeply, any
text the full front end would report -- gives ``None`` and the caller uses the full path.
So a model read here has no error, and the full path's CNF is this one clause for clause
(``tests/test_uvl_plain.py`` compares them on generated models, ``bench/bench_count_cold.py``
on the real ones).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Optional, Union

# the lexer's reserved words (tvl_lsp.uvl.lexer.KEYWORDS and HYPHENATED; a test keeps them equal):
# such a word is never a name
KEYWORDS = frozenset((
    "namespace", "include", "imports", "as", "features", "constraints", "constraint", "cardinality", "or",
    "alternative", "optional", "mandatory", "String", "Integer", "Boolean", "Real", "Type", "Arithmetic",
    "len", "sum", "avg", "floor", "ceil", "true", "false",
    "group-cardinality", "feature-cardinality", "aggregate-function", "string-constraints"))
GROUP_WORDS = {"mandatory": "mandatory", "optional": "optional", "alternative": "alternative", "or": "or"}
MAX_DEPTH = 200  # tvl_lsp.uvl.parser.MAX_DEPTH: deeper expressions are not analysed

_NAME = r"[A-Za-z][A-Za-z0-9_#§%?\\'äüöß;]*"
# a feature line: a name, then at most one attribute block
_FEATURE_RE = re.compile(r'(?:(' + _NAME + r')|"([^"\r\n.]+)")[ \t]*(?:\{(.*)\})?\Z')
# one attribute: ``abstract`` [true|false], or a key with a string value
_ATTR_RE = re.compile(r"""[ \t]*(""" + _NAME + r"""|"[^"\r\n.]+")(?:[ \t]+(true|false|'[^'\r\n]*'|"[^"\r\n]*"))?[ \t]*(,|\Z)""")
_CARD_RE = re.compile(r"\[([0-9]+)(?:\.\.([0-9]+|\*))?\]\Z")
_NAMESPACE_RE = re.compile(r"namespace[ \t]+(?:" + _NAME + r'|"[^"\r\n]*")\Z')
# a constraint line's tokens; group 4 is anything else
_TOKEN_RE = re.compile(r'[ \t]*(?:"([^"\r\n.]+)"|(' + _NAME + r')|(<=>|=>|[!&|()])|(.))')
_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_PLAIN_NAME = re.compile(_NAME + r"\Z")

# an expression: a feature's number (1-based), ("!", e), ("&&" | "||", [operands]) or
# ("->" | "<->", left, right) (the model's operator names)
Expr = Union[int, tuple]


@dataclass
class Group:
    kind: str  # mandatory | optional | alternative | or | card
    lo: int
    hi: Optional[int]
    children: list[int]  # feature numbers


@dataclass
class Plain:
    names: list[str]            # feature i + 1 is names[i], in document order (the root first)
    parent: list[int]           # feature number of each feature's parent (0 for the root)
    groups: list[list[Group]]   # each feature's groups, in document order
    constraints: list[Expr]


class _Decline(Exception):
    pass


def _width(ind: str) -> int:
    w = 0
    for c in ind:
        w = w + 1 if c == " " else w + 8 - (w % 8)
    return w


def read_plain(text: str) -> Optional[Plain]:
    """The model when ``text`` is plain UVL (see the module's text), else None."""
    if "\f" in text or "\v" in text or "\x00" in text:
        return None
    if ("//" in text or "/*" in text) and _comment_outside_quotes(text):
        return None
    try:
        return _read(text)
    except (_Decline, RecursionError):
        return None


# quoted names and strings, as the lexer reads them from left to right (neither spans lines)
_QUOTED = re.compile(r""""[^"\r\n]*"|'[^'\r\n]*'""")


def _comment_outside_quotes(text: str) -> bool:
    """Does a comment start outside every quoted name and string?  A ``//`` inside a quoted
    name is no comment (the Financial Services models of uvl-models have such names).  The
    quoted spans are found from left to right as the lexer finds them, so the first comment the
    lexer sees is left over."""
    rest = _QUOTED.sub(" ", text)
    return "//" in rest or "/*" in rest


def _lines(text: str):
    """(indentation width, content) of the non-blank lines."""
    out = []
    for raw in _LINE_BREAK.split(text):
        s = raw.strip(" \t")
        if not s:
            continue
        ind = raw[:len(raw) - len(raw.lstrip(" \t"))]
        out.append((len(ind) if "\t" not in ind else _width(ind), s))
    return out


def _read(text: str) -> Plain:
    lines = _lines(text)
    i = 0
    n = len(lines)
    if i < n and lines[i][0] == 0 and lines[i][1].startswith("namespace"):
        if not _NAMESPACE_RE.match(lines[i][1]):
            raise _Decline
        i += 1
    if i >= n or lines[i] != (0, "features"):
        raise _Decline
    i += 1
    j = i
    while j < n and lines[j][0] > 0:
        j += 1
    names, parent, groups = _tree(lines[i:j])
    constraints: list[Expr] = []
    if j < n:
        if lines[j] != (0, "constraints"):
            raise _Decline
        body = lines[j + 1:]
        if body:
            w = body[0][0]
            if w == 0 or any(x[0] != w for x in body):
                raise _Decline  # another section, or a deeper line (a layout the grammar reads otherwise)
            var = {nm: k + 1 for k, nm in enumerate(names)}
            # a token's meaning: an operator, or a feature's number for its plain name (not a
            # keyword) and for its quoted form
            lookup: dict[str, object] = dict(_OPERATORS)
            for nm, k in var.items():
                lookup['"' + nm + '"'] = k
                if nm not in KEYWORDS and _PLAIN_NAME.match(nm):
                    lookup[nm] = k
            for _, s in body:
                constraints.append(_constraint(_tokens(s, lookup, var), s))
    return Plain(names, parent, groups, constraints)


def _tree(lines) -> tuple[list[str], list[int], list[list[Group]]]:
    if not lines:
        raise _Decline
    names: list[str] = []
    parent: list[int] = []
    groups: list[list[Group]] = []
    seen: set[str] = set()
    # open lines, innermost last: (width, feature number or group)
    stack: list[tuple[int, object]] = []
    for w, s in lines:
        popped = False
        while stack and w < stack[-1][0]:
            stack.pop()
            popped = True
        if stack and w == stack[-1][0]:
            stack.pop()  # a sibling: same kind as the line it follows
        elif stack and popped:
            raise _Decline  # between two levels: the full front end reports it
        top = stack[-1][1] if stack else None
        g = GROUP_WORDS.get(s)
        card = None
        if g is None and s[0] == "[":
            card = _CARD_RE.match(s)
            if card is None:
                raise _Decline
        if g is not None or card is not None:
            if type(top) is not int:
                raise _Decline  # a group belongs under a feature
            if card is not None:
                lo = int(card.group(1))
                hi_s = card.group(2)
                hi = lo if hi_s is None else (None if hi_s == "*" else int(hi_s))
                if hi is not None and hi < lo:
                    raise _Decline  # reported by the full front end
                grp = Group("card", lo, hi, [])
            elif g == "or":
                grp = Group("or", 1, None, [])
            elif g == "alternative":
                grp = Group("alternative", 1, 1, [])
            else:
                grp = Group(g, 0, None, [])  # (allOf: its bounds are its number of children)
            groups[top - 1].append(grp)
            stack.append((w, grp))
            continue
        if top is None:
            if names:
                raise _Decline  # a second root
        elif type(top) is int:
            raise _Decline  # a feature right under a feature: no group keyword
        m = _FEATURE_RE.match(s)
        if m is None:
            raise _Decline
        name = m.group(1)
        if name is None:
            name = m.group(2)
        elif name in KEYWORDS:
            raise _Decline
        if name in seen:
            raise _Decline  # two features of one name: reported
        if m.group(3) is not None:
            _attributes(m.group(3))
        seen.add(name)
        names.append(name)
        num = len(names)
        groups.append([])
        if top is None:
            parent.append(0)
        else:
            parent.append(_owner(stack))
            top.children.append(num)
        stack.append((w, num))
    for gs in groups:
        for grp in gs:
            if not grp.children:
                raise _Decline
            if grp.kind in ("mandatory", "optional"):
                grp.lo = grp.hi = len(grp.children)
    return names, parent, groups


def _owner(stack) -> int:
    """The feature that owns the group on top of ``stack``."""
    for _, x in reversed(stack):
        if type(x) is int:
            return x
    raise _Decline


def _attributes(body: str) -> None:
    """Accept ``abstract`` (with or without true/false) and keys with string values."""
    pos = 0
    n = len(body)
    if not body.strip(" \t"):
        raise _Decline
    while pos < n:
        m = _ATTR_RE.match(body, pos)
        if m is None:
            raise _Decline
        key, value = m.group(1), m.group(2)
        if key == "abstract":
            if value is not None and value not in ("true", "false"):
                raise _Decline
        elif key in KEYWORDS or value is None or value in ("true", "false"):
            raise _Decline
        pos = m.end()
        if m.group(3) == ",":
            if pos >= n:
                raise _Decline
        elif pos < n:
            raise _Decline


_PREC = {"<=>": 0, "=>": 1, "|": 2, "&": 3}  # loosest first, all left-associative (the grammar's)
_BIN = {"&": "&&", "|": "||", "=>": "->", "<=>": "<->"}
_OPERATORS = {x: x for x in ("&", "|", "=>", "<=>", "(", ")", "!")}


def _tokens(s: str, lookup: dict, var: dict) -> list:
    """A constraint line's tokens: operators as themselves, names as feature numbers.  The
    common line is split at blanks (parentheses and ``!`` set apart first) when every piece is
    an operator or a name; anything else goes through :data:`_TOKEN_RE`, the lexer's rules."""
    padded = s.replace("(", " ( ").replace(")", " ) ").replace("!", " ! ")
    pieces = padded.split()
    out = list(map(lookup.get, pieces))
    # (no piece unknown, and no blank but spaces and tabs: str.split splits at others too)
    if None not in out and sum(map(len, pieces)) == len(padded) - padded.count(" ") - padded.count("\t"):
        return out
    out = []
    for q, name, op, bad in _TOKEN_RE.findall(s):
        if op:
            out.append(op)
        elif bad:
            raise _Decline
        else:
            if name:
                if name in KEYWORDS:
                    raise _Decline
                v = var.get(name)
            else:
                v = var.get(q)
            if v is None:
                raise _Decline  # no such feature: reported by the full front end
            out.append(v)
    return out


def _constraint(toks: list, s: str = "") -> Expr:
    """One constraint line by operator precedence, in one pass over its tokens.  Chains of
    ``&`` / ``|`` become one node whose operands are what :func:`.distribute._chain` gives for
    the binary tree (parentheses do not stop it); ``=>`` / ``<=>`` stay binary.  The depth of
    each node is counted as the parser counts it on the binary tree, and a depth over
    :data:`MAX_DEPTH` declines (the full path leaves such a constraint out)."""
    vals: list = []   # operands: [expression, depth, parenthesised]
    ops: list = []    # "(", "!" and binary operators
    prec = _PREC
    operand = True    # an operand is expected next

    def reduce() -> None:
        op = ops.pop()
        right, dr, _ = vals.pop()
        left, dl, pl = vals[-1]
        name = _BIN[op]
        d = max(dl, dr) + 1
        if name == "&&" or name == "||":
            if type(left) is tuple and left[0] == name:
                if not pl:
                    d = max(dl, dr + 1)  # a flat chain is not nesting
                node = left
            else:
                node = (name, [left])
            if type(right) is tuple and right[0] == name:
                node[1].extend(right[1])
            else:
                node[1].append(right)
        else:
            node = (name, left, right)
        if d > MAX_DEPTH:
            raise _Decline
        vals[-1] = [node, d, False]

    def negations(v) -> None:
        while ops and ops[-1] == "!":
            ops.pop()
            v[0] = ("!", v[0])
            v[1] += 1
            v[2] = False
            if v[1] > MAX_DEPTH:
                raise _Decline

    for t in toks:
        if operand:
            if type(t) is int:
                x = [t, 1, False]
                if ops and ops[-1] == "!":
                    negations(x)
                vals.append(x)
                operand = False
            elif t == "!" or t == "(":
                ops.append(t)
            else:
                raise _Decline
            continue
        if t == ")":
            while ops and ops[-1] != "(":
                reduce()
            if not ops:
                raise _Decline
            ops.pop()
            x = vals[-1]
            x[1] += 1
            x[2] = True
            if x[1] > MAX_DEPTH:
                raise _Decline
            if ops and ops[-1] == "!":
                negations(x)
            continue
        if type(t) is int:
            raise _Decline  # an operand where an operator belongs
        p = prec.get(t)
        if p is None:
            raise _Decline
        while ops and prec.get(ops[-1], -1) >= p:
            # reduce(), inline (the hot path: a long chain)
            op = ops.pop()
            right, dr, _ = vals.pop()
            x = vals[-1]
            left, dl, pl = x
            name = _BIN[op]
            if name == "&&" or name == "||":
                if type(left) is tuple and left[0] == name:
                    d = max(dl, dr + 1) if not pl else max(dl, dr) + 1
                    node = left
                else:
                    d = max(dl, dr) + 1
                    node = (name, [left])
                if type(right) is tuple and right[0] == name:
                    node[1].extend(right[1])
                else:
                    node[1].append(right)
            else:
                d = max(dl, dr) + 1
                node = (name, left, right)
            if d > MAX_DEPTH:
                raise _Decline
            x[0] = node
            x[1] = d
            x[2] = False
        ops.append(t)
        operand = True
    if operand:
        raise _Decline
    while ops:
        if ops[-1] == "(":
            raise _Decline
        reduce()
    return vals[0][0]
