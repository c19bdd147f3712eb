"""Bounds for the expression evaluators (ROS 1 ``$(eval)``, ROS 2 ``$(eval)``, rosparam
``!radians``): tvl-lsp interprets a safe subset of Python itself, and these limits keep every
evaluation small and fast whatever the text asks for.

- the expression's text: at most ``MAX_EXPR_CHARS`` characters, and Python's parser errors on
  deep nesting (``MemoryError``, ``RecursionError``) are caught;
- steps: at most ``MAX_STEPS`` nodes evaluated per expression;
- intermediate values: integers up to ``MAX_INT_BITS`` bits, strings, lists, tuples, dicts and
  ranges up to ``MAX_LEN`` items; operations whose result would exceed them are refused
  *before* they are computed (``2 ** 10 ** 9``, ``[0] * 10 ** 9``, ``factorial(10 ** 7)``).

Beyond a bound the evaluator raises :class:`TooBig`; each evaluator turns it into its own
"not analysable" (the value is then unknown, reported as a note), never an error of the file.

Methods of built-in values (``{'iron': False}.get(arg('robot'), True)``, ``[...].index(x)``,
``'a_b'.split('_')``, ``set(...).intersection(...)``) go through :func:`call_method`: the pure
methods of ``str``, ``list``, ``tuple``, ``dict``, ``set`` / ``frozenset`` and numbers (never one
that changes its object), bounded like the rest.  A set of strings has no fixed order in Python
(string hashes are randomised per process: ``list(set(['a', 'b']))`` differs from run to run of
roslaunch itself); the evaluators give it one, sorted (:func:`canon`), so that their answers
are the same every run and one of those the launch tool can give -- what is then done with it
(``'ndt' in ...``, ``len(...)``) is what the launch tool computes, whatever the order.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from typing import Any, Optional

MAX_EXPR_CHARS = 10_000
MAX_STEPS = 100_000
MAX_INT_BITS = 1 << 14        # 16,384 bits (~4,900 digits; Python prints at most 4,300 by default)
MAX_LEN = 100_000


class TooBig(Exception):
    """An expression or a value beyond the evaluators' bounds."""


class Unordered(TooBig):
    """A value whose text depends on a set's iteration order, which Python does not fix for
    strings (hash randomisation): no single answer to give."""


def parse(expr: str) -> ast.Expression:
    """``ast.parse(expr, mode="eval")`` within the bounds (SyntaxError passes through)."""
    if len(expr) > MAX_EXPR_CHARS:
        raise TooBig()
    try:
        return ast.parse(expr, mode="eval")
    except (MemoryError, RecursionError):  # "too many nested ..." in Python's own parser
        raise TooBig() from None


def _bits(v: Any) -> int:
    return v.bit_length() if isinstance(v, int) and not isinstance(v, bool) else 0


def _len(v: Any) -> int:
    if isinstance(v, (str, bytes, list, tuple, dict, set, frozenset, range)):
        return len(v)
    return 0


def bounded(v: Any) -> Any:
    """``v`` when it is within the bounds, else :class:`TooBig`."""
    if _bits(v) > MAX_INT_BITS or _len(v) > MAX_LEN:
        raise TooBig()
    return v


def check_binop(op, a: Any, b: Any) -> None:
    """Refuse, before computing it, an arithmetic operation whose result would be too big."""
    if op is operator.pow:
        if isinstance(a, int) and isinstance(b, int) and b > 0 and abs(a) > 1:
            if max(_bits(a), 1) * b > MAX_INT_BITS:
                raise TooBig()
        elif isinstance(b, (int, float)) and abs(b) > 10_000:  # floats: overflow or 0; keep it cheap
            raise TooBig()
    elif op is operator.mul:
        if isinstance(a, int) and isinstance(b, int):
            if _bits(a) + _bits(b) > MAX_INT_BITS:
                raise TooBig()
        else:
            seq, n = (a, b) if _len(a) or isinstance(a, (str, list, tuple)) else (b, a)
            if isinstance(n, int) and isinstance(seq, (str, bytes, list, tuple)) and len(seq) * max(n, 0) > MAX_LEN:
                raise TooBig()
    elif op is operator.add:
        if _len(a) + _len(b) > MAX_LEN:
            raise TooBig()
    elif op is operator.lshift:
        if isinstance(b, int) and _bits(a) + max(b, 0) > MAX_INT_BITS:
            raise TooBig()


_GROWING = {math.factorial, math.comb, math.perm}


def check_call(f, args: list) -> None:
    """Refuse, before calling it, a builtin or math function call that would build too much."""
    if f in _GROWING and any(isinstance(a, int) and a > 2_000 for a in args):
        raise TooBig()
    if f is pow and len(args) >= 2:
        if len(args) == 2:
            check_binop(operator.pow, args[0], args[1])
    if f is range and any(_bits(a) > 64 for a in args):
        raise TooBig()
    if f is range:
        try:
            if len(range(*args)) > MAX_LEN:
                raise TooBig()
        except (TypeError, ValueError, OverflowError):
            pass
    for a in args:
        bounded(a)
    if f in _ORDER_VISIBLE:
        for a in args:
            ordered(a)


# builtins whose result shows the iteration order of their argument (a set's: see ordered)
_ORDER_VISIBLE = {list, tuple, str, repr, format, enumerate, zip, map, dict, reversed}


class Steps:
    """A step counter: ``tick()`` once per node evaluated."""

    __slots__ = ("n",)

    def __init__(self):
        self.n = 0

    def tick(self) -> None:
        self.n += 1
        if self.n > MAX_STEPS:
            raise TooBig()


# ------------------------------------------------------------------ methods of built-in values

# the pure methods of each built-in type (a new value out, the object unchanged), by type
_STR_METHODS = frozenset({
    "startswith", "endswith", "lower", "upper", "strip", "lstrip", "rstrip", "split", "rsplit", "find", "rfind",
    "count", "isdigit", "isalpha", "isalnum", "islower", "isupper", "capitalize", "title", "replace", "index",
    "rindex", "format", "join", "zfill", "center", "ljust", "rjust", "partition", "rpartition", "splitlines",
    "swapcase", "casefold", "isspace", "isnumeric", "isdecimal", "isidentifier", "istitle", "removeprefix",
    "removesuffix", "expandtabs", "encode"})
_SET_METHODS = frozenset({"union", "intersection", "difference", "symmetric_difference", "issubset",
                          "issuperset", "isdisjoint", "copy"})
METHODS: dict[type, frozenset] = {
    str: _STR_METHODS,
    list: frozenset({"index", "count", "copy"}),
    tuple: frozenset({"index", "count"}),
    dict: frozenset({"get", "keys", "values", "items", "copy"}),
    set: _SET_METHODS,
    frozenset: _SET_METHODS,
    int: frozenset({"bit_length", "conjugate"}),
    float: frozenset({"is_integer", "conjugate", "hex"}),
}
METHOD_NAMES = frozenset().union(*METHODS.values())  # every method an expression may call
_WIDTH = re.compile(r"\d{6,}")  # a format width / precision that would build a huge string


class NotAllowed(Exception):
    """A method tvl-lsp does not call (it exists, but changes its object or is not pure)."""


def call_method(obj: Any, name: str, args: list, kwargs: Optional[dict] = None) -> Any:
    """``obj.name(*args, **kwargs)`` for the pure methods of built-in values (:data:`METHODS`),
    within the bounds.  ``AttributeError`` when the value has no such method (as Python raises
    it: the caller reports it as the launch tool's own error); :class:`NotAllowed` for a method
    that exists but is not called here; :class:`TooBig` / :class:`Unordered` as elsewhere;
    any other exception is the one Python raises (``ValueError`` of ``[].index(1)`` ...)."""
    kwargs = kwargs or {}
    kind = next((t for t in METHODS if type(obj) is t), None)
    if kind is None and isinstance(obj, bool):
        kind = int
    if kind is None and isinstance(obj, (SortedSet, SortedFrozenSet)):
        kind = set if isinstance(obj, set) else frozenset
    if not hasattr(obj, name):
        raise AttributeError(f"'{type(obj).__name__}' object has no attribute '{name}'")
    if kind is None or name not in METHODS[kind]:
        raise NotAllowed(name)
    for a in list(args) + list(kwargs.values()):
        bounded(a)
    if kind is str:
        if name == "replace" and len(args) >= 2 and isinstance(args[1], str) and \
                len(obj) * max(len(args[1]), 1) > MAX_LEN:
            raise TooBig()
        if name in ("zfill", "center", "ljust", "rjust") and args and isinstance(args[0], int) and args[0] > MAX_LEN:
            raise TooBig()
        if name == "expandtabs" and args and isinstance(args[0], int) and len(obj) * max(args[0], 1) > MAX_LEN:
            raise TooBig()
        if name == "format":
            if _WIDTH.search(obj):
                raise TooBig()
            for a in list(args) + list(kwargs.values()):
                ordered(a)
        if name == "join" and args:
            ordered(args[0])
    return canon(bounded(getattr(obj, name)(*args, **kwargs)))


def _sort_key(x: Any):
    return (type(x).__name__, repr(x))


class SortedSet(set):
    """A set iterated and printed in sorted order (see :func:`canon`)."""

    def __iter__(self):
        return iter(sorted(set.__iter__(self), key=_sort_key))

    def __repr__(self) -> str:
        return "{" + ", ".join(repr(x) for x in self) + "}" if self else "set()"

    __str__ = __repr__


class SortedFrozenSet(frozenset):
    """A frozenset iterated and printed in sorted order (see :func:`canon`)."""

    def __iter__(self):
        return iter(sorted(frozenset.__iter__(self), key=_sort_key))

    def __repr__(self) -> str:
        return "frozenset({" + ", ".join(repr(x) for x in self) + "})" if self else "frozenset()"

    __str__ = __repr__


def canon(v: Any) -> Any:
    """``v``, a set or frozenset whose order Python does not fix (two or more strings) made
    one that iterates and prints sorted; anything else as it is."""
    if type(v) in (set, frozenset) and len(v) > 1 and not all(_stable(x) for x in v):
        return SortedSet(v) if type(v) is set else SortedFrozenSet(v)
    return v


def _stable(x: Any) -> bool:
    """Whether ``x``'s hash is the same in every Python process (not a string's)."""
    if x is None or isinstance(x, (bool, int, float)):
        return True
    if isinstance(x, tuple):
        return all(_stable(y) for y in x)
    return False


def ordered(v: Any, _depth: int = 0) -> Any:
    """``v`` when its printed form (and its iteration order) is the same in every process;
    :class:`Unordered` when it is or holds a set of two or more strings (or other values
    whose hash Python randomises) that is not :func:`canon`'s.  Called where an order becomes
    visible: the result's text, ``list()`` / ``tuple()`` / ``str()`` / ``', '.join()`` ... of a
    value."""
    if _depth > 50:
        raise TooBig()
    if isinstance(v, (set, frozenset)):
        if len(v) > 1 and not isinstance(v, (SortedSet, SortedFrozenSet)) and not all(_stable(x) for x in v):
            raise Unordered()
        return v
    if isinstance(v, (list, tuple)):
        for x in v:
            if isinstance(x, (set, frozenset, list, tuple, dict)):
                ordered(x, _depth + 1)
    elif isinstance(v, dict):
        for x in list(v.keys()) + list(v.values()):
            if isinstance(x, (set, frozenset, list, tuple, dict)):
                ordered(x, _depth + 1)
    return v
