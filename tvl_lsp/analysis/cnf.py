"""The literal-level CNF pieces of the encoding: :class:`Element` (a piece of the model that can
take part in an explanation); :class:`_Builder` and :func:`_clean` live in :mod:`.clauses`
(no model objects) and are re-exported here."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from ..base.text import Span
from .clauses import _Builder, _clean  # noqa: F401 (imported from here by the encoding)


@dataclass(eq=False, slots=True)
class Element:
    """A piece of the model that can take part in an explanation."""
    kind: str  # root | parent-link | mandatory | group | group-lower | constraint | attribute
    label: str  # plain words: "B is mandatory in A"
    path: str
    span: Span
    obj: object = None
    clauses: list[list[int]] = field(default_factory=list)
    selector: int = 0
    # literals whose conjunction is the negation of the element (for redundancy checks),
    # None when unknown
    negation: Optional[list[int]] = None
