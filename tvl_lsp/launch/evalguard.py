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
"""

from __future__ import annotations

import ast
import math
import operator
from typing import Any

MAX_EXPR_CHARS = 10_000
MAX_STEPS = 100_000
MAX_INT_BITS = 1 << 14        # 16,384 bits (~4,900 digits; Python prints at most 4,300 by default)
MAX_LEN = 100_000


class TooBig(Exception):
    """An expression or a value beyond the evaluators' bounds."""


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


class Steps:
    """A step counter: ``tick()`` once per node evaluated."""

    __slots__ = ("n",)

    def __init__(self):
        self.n = 0

    def tick(self) -> None:
        self.n += 1
        if self.n > MAX_STEPS:
            raise TooBig()
