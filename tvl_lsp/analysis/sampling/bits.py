"""Bitsets over feature literals, as Python ints.

Literal ``v`` (variable ``v`` selected) is bit ``2 (v - 1)``, ``-v`` is bit ``2 (v - 1) + 1``: a
variable's two literals are neighbours, so negating a set of literals swaps the bits of each
pair (:func:`negate`) and the literals of a set of variables are ``both(vars)``.  Python ints are
arbitrary-precision bit vectors with C-speed ``& | ^ ~`` and ``int.bit_count``: a model of a few
thousand features is a few hundred machine words per set.
"""

from __future__ import annotations

import random
from itertools import compress, count
from typing import Iterable, Iterator, Sequence

_TO_DIGITS = bytes.maketrans(b"\x00\x01", b"12")  # a model's sign per variable -> base-4 digit


def idx(x: int) -> int:
    """The bit of literal ``x``."""
    return 2 * x - 2 if x > 0 else -2 * x - 1


def lit(i: int) -> int:
    """The literal of bit ``i``."""
    v = (i >> 1) + 1
    return -v if i & 1 else v


def even_mask(n: int) -> int:
    """Bits of the positive literals of variables 1..n."""
    return int("1" * n, 4) if n else 0


def negate(bits: int, even: int) -> int:
    """The complementary literals of ``bits`` (``even``: :func:`even_mask` of at least the
    variables in ``bits``)."""
    return ((bits & even) << 1) | ((bits >> 1) & even)


_ONE = "1".__eq__


def iter_bits(x: int) -> Iterator[int]:
    """The set bits of ``x``, lowest first (its binary digits read in C: one pass over the int,
    not one big-int operation per bit)."""
    return compress(count(), map(_ONE, bin(x)[:1:-1])) if x > 0 else iter(())


def shuffled(items: Sequence[int], rng: random.Random) -> list[int]:
    """``items`` in a random order drawn from ``rng`` (one call for all the random numbers:
    ``rng.shuffle`` makes one Python call per item)."""
    k = len(items)
    if k < 2:
        return list(items)
    keys = memoryview(rng.randbytes(4 * k)).cast("I")
    return [items[i] for i in sorted(range(k), key=keys.__getitem__)]


def from_indices(indices: Iterable[int]) -> int:
    out = 0
    for i in indices:
        out |= 1 << i
    return out


def from_lits(lits: Iterable[int]) -> int:
    out = 0
    for x in lits:
        out |= 1 << (2 * x - 2 if x > 0 else -2 * x - 1)
    return out


def from_model(model: Sequence[int], n: int) -> int:
    """The literals of variables 1..n in a solver's model (``model[v - 1]`` is ``v`` or ``-v``),
    as a bitset: one base-4 digit per variable (1: selected, 2: not), written as a string and
    read by ``int(..., 4)`` in C."""
    if n <= 0:
        return 0
    signs = bytes(map((0).__gt__, model[n - 1::-1])) if n <= len(model) else \
        bytes(map((0).__gt__, list(model[::-1]))).rjust(n, b"\x01")
    return int(signs.translate(_TO_DIGITS), 4)
