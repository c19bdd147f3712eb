"""Errors and cancellation tokens shared by the counting engines."""

from __future__ import annotations

import threading
from typing import Callable, Union

CancelLike = Union[threading.Event, Callable[[], bool], None]


class CountTimeout(Exception):
    """The count did not finish within its time budget."""


class CountCancelled(Exception):
    """The count was cancelled by the caller."""


class EngineFailed(RuntimeError):
    """An engine (d4, ddnnife) failed on this input; the service falls back on another."""


def is_cancelled(cancel: CancelLike) -> bool:
    if cancel is None:
        return False
    if isinstance(cancel, threading.Event):
        return cancel.is_set()
    return bool(cancel())
