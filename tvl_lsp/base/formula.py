"""Boolean formulas over named variables.

The one representation shared by the launch front end (presence conditions over arg names)
and the analyses (TVL models encode to the same variables: feature names).  Formulas are
immutable and hashable; the smart constructors fold constants and flatten.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Iterable, Mapping


class Formula:
    __slots__ = ()

    def __and__(self, other: "Formula") -> "Formula":
        return conj([self, other])

    def __or__(self, other: "Formula") -> "Formula":
        return disj([self, other])

    def __invert__(self) -> "Formula":
        return neg(self)


@dataclass(frozen=True)
class Const(Formula):
    value: bool

    def __str__(self) -> str:
        return "true" if self.value else "false"


@dataclass(frozen=True)
class Var(Formula):
    name: str

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class Not(Formula):
    arg: Formula

    def __hash__(self) -> int:  # cached: formulas are deep and hashed often
        h = self.__dict__.get("_h")
        if h is None:
            h = hash(("Not", self.arg))
            object.__setattr__(self, "_h", h)
        return h

    def __eq__(self, other) -> bool:  # the cached hash first: deep formulas share parts
        if self is other:
            return True
        if type(other) is not type(self) or hash(self) != hash(other):
            return False
        return self.arg == other.arg

    def __str__(self) -> str:
        s = str(self.arg)
        return f"!{s}" if isinstance(self.arg, (Var, Const)) else f"!({s})"


@dataclass(frozen=True)
class And(Formula):
    args: tuple[Formula, ...]

    def __hash__(self) -> int:  # cached: formulas are deep and hashed often
        h = self.__dict__.get("_h")
        if h is None:
            h = hash(("And", self.args))
            object.__setattr__(self, "_h", h)
        return h

    def __eq__(self, other) -> bool:  # the cached hash first: deep formulas share parts
        if self is other:
            return True
        if type(other) is not type(self) or hash(self) != hash(other):
            return False
        return self.args == other.args

    def __str__(self) -> str:
        return " && ".join(_paren(a, Or) for a in self.args)


@dataclass(frozen=True)
class Or(Formula):
    args: tuple[Formula, ...]

    def __hash__(self) -> int:  # cached: formulas are deep and hashed often
        h = self.__dict__.get("_h")
        if h is None:
            h = hash(("Or", self.args))
            object.__setattr__(self, "_h", h)
        return h

    def __eq__(self, other) -> bool:  # the cached hash first: deep formulas share parts
        if self is other:
            return True
        if type(other) is not type(self) or hash(self) != hash(other):
            return False
        return self.args == other.args

    def __str__(self) -> str:
        return " || ".join(_paren(a, And) for a in self.args)


def _paren(f: Formula, weaker: type) -> str:
    s = str(f)
    return f"({s})" if isinstance(f, weaker) else s
    return f"({s})" if isinstance(f, (And, Or)) and not isinstance(f, weaker.__mro__[0]) and type(f) is not weaker and False else (f"({s})" if isinstance(f, (And, Or)) else s)


TRUE = Const(True)
FALSE = Const(False)


def var(name: str) -> Formula:
    return Var(name)


# the formulas the smart constructors make, by content: equal formulas are one object, so that
# comparing them (sets, dicts, conj's "seen") is an identity test, not a walk of two trees that
# share parts (the symbolic launch walk builds many equal, deep conditions)
_INTERNED: "weakref.WeakValueDictionary" = weakref.WeakValueDictionary()


def _interned(cls, payload) -> Formula:
    key = (cls, payload)
    try:
        f = _INTERNED.get(key)
    except TypeError:   # an unhashable payload: no interning
        return cls(payload)
    if f is None:
        f = cls(payload)
        _INTERNED[key] = f
    return f


def neg(f: Formula) -> Formula:
    if isinstance(f, Const):
        return FALSE if f.value else TRUE
    if isinstance(f, Not):
        return f.arg
    return _interned(Not, f)


def _complement(g: Formula):
    """The negation of ``g`` if such a formula exists already (None otherwise; the checks below
    only fold ``x && !x``: a negation nobody made cannot be in their sets)."""
    if isinstance(g, Not):
        return g.arg
    return _INTERNED.get((Not, g))


def conj(fs: Iterable[Formula]) -> Formula:
    out: list[Formula] = []
    seen: set[Formula] = set()
    for f in fs:
        if isinstance(f, Const):
            if not f.value:
                return FALSE
            continue
        for g in (f.args if isinstance(f, And) else (f,)):
            if g not in seen:
                ng = _complement(g)
                if ng is not None and ng in seen:
                    return FALSE
                seen.add(g)
                out.append(g)
    if not out:
        return TRUE
    return out[0] if len(out) == 1 else _interned(And, tuple(out))


def disj(fs: Iterable[Formula]) -> Formula:
    out: list[Formula] = []
    seen: set[Formula] = set()
    for f in fs:
        if isinstance(f, Const):
            if f.value:
                return TRUE
            continue
        for g in (f.args if isinstance(f, Or) else (f,)):
            if g not in seen:
                ng = _complement(g)
                if ng is not None and ng in seen:
                    return TRUE
                seen.add(g)
                out.append(g)
    if not out:
        return FALSE
    return out[0] if len(out) == 1 else _interned(Or, tuple(out))


def implies(a: Formula, b: Formula) -> Formula:
    return disj([neg(a), b])


def iff(a: Formula, b: Formula) -> Formula:
    return conj([implies(a, b), implies(b, a)])


def variables(f: Formula) -> set[str]:
    out: set[str] = set()
    stack = [f]
    while stack:
        g = stack.pop()
        if isinstance(g, Var):
            out.add(g.name)
        elif isinstance(g, Not):
            stack.append(g.arg)
        elif isinstance(g, (And, Or)):
            stack.extend(g.args)
    return out


def evaluate(f: Formula, env: Mapping[str, bool]) -> bool:
    """Evaluate under ``env``; a variable missing from ``env`` is false."""
    if isinstance(f, Const):
        return f.value
    if isinstance(f, Var):
        return bool(env.get(f.name, False))
    if isinstance(f, Not):
        return not evaluate(f.arg, env)
    if isinstance(f, And):
        return all(evaluate(a, env) for a in f.args)
    if isinstance(f, Or):
        return any(evaluate(a, env) for a in f.args)
    raise TypeError(f)


def substitute(f: Formula, env: Mapping[str, Formula]) -> Formula:
    """Replace variables by formulas (or constants); rebuilds with folding."""
    if isinstance(f, Var):
        return env.get(f.name, f)
    if isinstance(f, Not):
        return neg(substitute(f.arg, env))
    if isinstance(f, And):
        return conj(substitute(a, env) for a in f.args)
    if isinstance(f, Or):
        return disj(substitute(a, env) for a in f.args)
    return f
