"""Problems of a model and its launch files, filtered by the configurator's decisions.

A problem the analyses found for *some* product carries the presence condition under which it
occurs (``data["condition"]``, a formula over feature / arg names) and a witness product.  Under
decisions it is:

- ``possible``: some remaining product has it (the model, the decisions and its condition are
  satisfiable together; without a condition: its witness agrees with every decision);
- ``certain``: every remaining product has it (unconditional problems are always certain);
- ``excluded``: no remaining product has it -- the UI hides it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Mapping, Optional

from ..base import formula as fm
from ..base.diagnostics import Diagnostic

_TOKEN = re.compile(r"\s*(&&|\|\||!|\(|\)|[^\s()!&|]+)")


class FormulaSyntaxError(ValueError):
    pass


def parse_condition(text: str) -> fm.Formula:
    """The formula printed by ``str(Formula)`` (``!a && (b || c)``, ``true``, ``false``)."""
    toks: list[str] = []
    pos = 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise FormulaSyntaxError(f"unexpected {text[pos:pos + 10]!r}")
        toks.append(m.group(1))
        pos = m.end()
        while pos < len(text) and text[pos].isspace():
            pos += 1
    i = 0

    def peek() -> Optional[str]:
        return toks[i] if i < len(toks) else None

    def take() -> str:
        nonlocal i
        if i >= len(toks):
            raise FormulaSyntaxError("unexpected end")
        i += 1
        return toks[i - 1]

    def disj() -> fm.Formula:
        parts = [conj()]
        while peek() == "||":
            take()
            parts.append(conj())
        return fm.disj(parts)

    def conj() -> fm.Formula:
        parts = [unary()]
        while peek() == "&&":
            take()
            parts.append(unary())
        return fm.conj(parts)

    def unary() -> fm.Formula:
        t = take()
        if t == "!":
            return fm.neg(unary())
        if t == "(":
            f = disj()
            if take() != ")":
                raise FormulaSyntaxError("missing )")
            return f
        if t in ("&&", "||", ")"):
            raise FormulaSyntaxError(f"unexpected {t}")
        if t == "true":
            return fm.TRUE
        if t == "false":
            return fm.FALSE
        return fm.var(t)

    f = disj()
    if i != len(toks):
        raise FormulaSyntaxError(f"unexpected {toks[i]}")
    return f


@dataclass
class Problem:
    id: str
    diagnostic: Diagnostic
    condition: Optional[fm.Formula] = None   # None: unconditional or unknown
    witness: Optional[dict[str, bool]] = None
    extra: dict = field(default_factory=dict)


def problem_of(i: int, d: Diagnostic) -> Problem:
    cond = None
    text = (d.data or {}).get("condition") if isinstance(d.data, dict) else None
    if isinstance(text, str) and d.witness is not None:
        try:
            cond = parse_condition(text)
        except FormulaSyntaxError:
            cond = None
    return Problem(f"p{i}", d, cond, dict(d.witness) if d.witness else None)


def status(p: Problem, decisions: Mapping[str, bool], logic, decided: fm.Formula) -> str:
    """``possible`` / ``certain`` / ``excluded`` (see the module docstring)."""
    if p.condition is not None:
        if not logic.sat(fm.conj([decided, p.condition])):
            return "excluded"
        if not logic.sat(fm.conj([decided, fm.neg(p.condition)])):
            return "certain"
        return "possible"
    if p.witness is not None:
        for k, v in decisions.items():
            if k in p.witness and p.witness[k] != v:
                return "excluded"
        return "possible"
    return "certain"
