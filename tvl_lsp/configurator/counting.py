"""The configurator's counts: products that remain under decisions, and per feature.

One seam, :data:`COUNTER`: every count the configurator shows goes through it, so the
counting service of issue #15 (d4 + ddnnife, every feature's count in one pass) replaces the
interim implementation here by assigning another :class:`Counter` -- nothing else changes.

The interim :class:`EngineCounter` asks :meth:`ModelAnalysis.count` once for the remaining
products and once per open feature (decided and implied features need no count), visiting the
features in the order the caller gives (the UI asks for the visible ones first) within a time
budget: what is not counted in time is left out, never guessed.
"""

from __future__ import annotations

import time
from typing import Callable, Iterable, Mapping, Optional, Protocol

from ..analysis.count import CountCancelled, CountTimeout

Cancel = Optional[Callable[[], bool]]


class Counter(Protocol):
    name: str

    def remaining(self, analysis, decisions: Mapping[str, bool], timeout: Optional[float] = None,
                  cancel: Cancel = None) -> Optional[int]:
        """Products respecting ``decisions`` (None: no answer within ``timeout``)."""

    def per_feature(self, analysis, decisions: Mapping[str, bool], fixed: Mapping[str, bool],
                    remaining: int, features: Iterable[str], timeout: Optional[float] = None,
                    cancel: Cancel = None) -> dict[str, int]:
        """For each of ``features``: how many of the ``remaining`` products select it.
        ``fixed``: every feature the decisions determine (decided or implied)."""


def _split(decisions: Mapping[str, bool]) -> tuple[list[str], list[str]]:
    return [k for k, v in decisions.items() if v], [k for k, v in decisions.items() if not v]


class EngineCounter:
    """One exact count per question (today's counting engine)."""

    name = "engine"

    def remaining(self, analysis, decisions, timeout=None, cancel=None):
        inc, exc = _split(decisions)
        try:
            return analysis.count(include=inc, exclude=exc, timeout=timeout, cancel=cancel)
        except (CountTimeout, CountCancelled):
            return None

    def per_feature(self, analysis, decisions, fixed, remaining, features, timeout=None, cancel=None):
        inc, exc = _split(decisions)
        start = time.monotonic()
        out: dict[str, int] = {}
        for f in features:
            if cancel is not None and cancel():
                break
            if f in fixed:
                out[f] = remaining if fixed[f] else 0
                continue
            left = None if timeout is None else timeout - (time.monotonic() - start)
            if left is not None and left <= 0:
                break
            try:
                out[f] = analysis.count(include=inc + [f], exclude=exc, timeout=left, cancel=cancel)
            except (CountTimeout, CountCancelled):
                break
        return out


COUNTER: Counter = EngineCounter()


def set_counter(counter: Counter) -> None:
    global COUNTER
    COUNTER = counter
