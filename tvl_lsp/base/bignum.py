"""Exact counts of any size as decimal text.

Python refuses to convert an ``int`` of more than 4,300 digits to or from a decimal string
(``sys.set_int_max_str_digits``: a guard against quadratic conversions of untrusted input,
which the process keeps).  A model's product count is often bigger (2^15000 for 15,000 free
features), so the counts tvl-lsp prints go through :func:`decimal` (divide and conquer on
chunks the guard allows) and :func:`parse_decimal`.
"""

from __future__ import annotations

CHUNK = 4000  # digits converted at once (under the interpreter's 4,300)


def decimal(n: int) -> str:
    """``str(n)`` for an int of any size."""
    if n < 0:
        return "-" + decimal(-n)
    if n < 10 ** CHUNK:
        return str(n)
    # split at 10**k, k the largest CHUNK * 2**j below the number of digits (10**k <= n, so
    # both halves are smaller); ``low`` never exceeds the number of digits
    low = (n.bit_length() - 1) * 30102 // 100000 + 1
    k = CHUNK
    while k * 2 <= low - 1:
        k *= 2
    hi, lo = divmod(n, 10 ** k)
    return decimal(hi) + decimal(lo).rjust(k, "0")


def parse_decimal(text: str) -> int:
    """``int(text)`` for a decimal string of any length (digits only)."""
    text = text.strip()
    if not text.isdigit() or not text.isascii():
        raise ValueError(f"not a decimal number: {text[:40]!r}")
    if len(text) <= CHUNK:
        return int(text)
    mid = len(text) // 2
    return parse_decimal(text[:mid]) * 10 ** (len(text) - mid) + parse_decimal(text[mid:])
