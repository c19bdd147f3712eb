"""Counts for a configurator: the products left under decisions and, in the same pass, how many
of them select each feature.

:class:`OnePassCounter` has the shape of the configurator's counting seam (issue #18's
``configurator.counting.Counter``: ``remaining`` and ``per_feature``); with it, a decision
costs one pass over the compiled d-DNNF whatever the number of features, instead of one count
per open feature.
"""

from __future__ import annotations

from typing import Callable, Iterable, Mapping, Optional

from .errors import CountCancelled, CountTimeout

Cancel = Optional[Callable[[], bool]]


def _split(decisions: Mapping[str, bool]) -> tuple[list[str], list[str]]:
    return [k for k, v in decisions.items() if v], [k for k, v in decisions.items() if not v]


class OnePassCounter:
    name = "one-pass"

    def remaining(self, analysis, decisions: Mapping[str, bool], timeout: Optional[float] = None,
                  cancel: Cancel = None) -> Optional[int]:
        inc, exc = _split(decisions)
        try:
            return analysis.count(include=inc, exclude=exc, timeout=timeout, cancel=cancel)
        except (CountTimeout, CountCancelled):
            return None

    def per_feature(self, analysis, decisions: Mapping[str, bool], fixed: Mapping[str, bool],
                    remaining: int, features: Iterable[str], timeout: Optional[float] = None,
                    cancel: Cancel = None) -> dict[str, int]:
        inc, exc = _split(decisions)
        try:
            r = analysis.feature_counts_result(inc, exc, timeout=timeout, cancel=cancel)
        except (CountTimeout, CountCancelled):
            return {}
        enc = analysis.encoding
        out: dict[str, int] = {}
        for f in features:
            if f in fixed:
                out[f] = remaining if fixed[f] else 0
                continue
            n = r.counts[enc.var(f)]
            if n is not None:
                out[f] = n
        return out
