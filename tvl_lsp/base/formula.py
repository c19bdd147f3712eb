"""Boolean formulas over named variables.

The one representation shared by the launch front end (presence conditions over arg names)
and the analyses (TVL models encode to the same variables: feature names).  Formulas are
immutable and hashable; the smart constructors fold constants and flatten.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Iterable, Mapping, Optional


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
    """The variable names of ``f`` (a shared subformula visited once: formulas built by the
    launch front ends share subterms, and a tree walk of such a DAG is exponential)."""
    out: set[str] = set()
    stack = [f]
    seen: set[int] = set()
    while stack:
        g = stack.pop()
        if isinstance(g, Var):
            out.add(g.name)
        elif isinstance(g, (Not, And, Or)):
            if id(g) in seen:
                continue
            seen.add(id(g))
            if isinstance(g, Not):
                stack.append(g.arg)
            else:
                stack.extend(g.args)
    return out


def evaluate(f: Formula, env: Mapping[str, bool], _memo: Optional[dict] = None) -> bool:
    """Evaluate under ``env``; a variable missing from ``env`` is false (a shared subformula
    once)."""
    if isinstance(f, Const):
        return f.value
    if isinstance(f, Var):
        return bool(env.get(f.name, False))
    memo = {} if _memo is None else _memo
    hit = memo.get(id(f))
    if hit is not None:
        return hit[1]
    if isinstance(f, Not):
        out = not evaluate(f.arg, env, memo)
    elif isinstance(f, And):
        out = all(evaluate(a, env, memo) for a in f.args)
    elif isinstance(f, Or):
        out = any(evaluate(a, env, memo) for a in f.args)
    else:
        raise TypeError(f)
    memo[id(f)] = (f, out)
    return out


def substitute(f: Formula, env: Mapping[str, Formula], _memo: Optional[dict] = None) -> Formula:
    """Replace variables by formulas (or constants); rebuilds with folding (a shared
    subformula once)."""
    if isinstance(f, Var):
        return env.get(f.name, f)
    if isinstance(f, Const):
        return f
    memo = {} if _memo is None else _memo
    hit = memo.get(id(f))
    if hit is not None:
        return hit[1]
    if isinstance(f, Not):
        out = neg(substitute(f.arg, env, memo))
    elif isinstance(f, And):
        out = conj(substitute(a, env, memo) for a in f.args)
    elif isinstance(f, Or):
        out = disj(substitute(a, env, memo) for a in f.args)
    else:
        out = f
    memo[id(f)] = (f, out)  # (f kept alive: its id is not reused while the memo lives)
    return out


# ------------------------------------------------------------------ unknowns

# A condition a launch front end cannot evaluate (an ``if`` reading an ``$(eval)`` it cannot
# compute, a value whose evaluation failed) is an *unknown*: a variable of its own, named with
# this prefix (no arg or feature name starts with it), so that ``if`` and ``unless`` of the same
# unknown value exclude each other.  An error whose condition reads unknowns is reported only
# where it holds whatever they are (:func:`forall_unknowns`): an unknown never makes an error.
UNKNOWN_PREFIX = "?"
MAX_UNKNOWNS = 8  # a condition over more unknowns than this is treated as never certain


def unknown(key: str) -> Formula:
    """The unknown variable named ``?key``."""
    return Var(UNKNOWN_PREFIX + key)


def is_unknown(name: str) -> bool:
    return name.startswith(UNKNOWN_PREFIX)


def forall_unknowns(f: Formula) -> Formula:
    """``f`` with its unknowns universally quantified: where ``f`` holds whatever their
    values (FALSE over more than :data:`MAX_UNKNOWNS` of them)."""
    us = sorted(v for v in variables(f) if is_unknown(v))
    if not us:
        return f
    if len(us) > MAX_UNKNOWNS:
        return FALSE
    # the common case, cheaply: false when all the unknowns are true, or all false
    for value in (TRUE, FALSE):
        if substitute(f, dict.fromkeys(us, value)) == FALSE:
            return FALSE
    for u in us:
        f = conj([substitute(f, {u: TRUE}), substitute(f, {u: FALSE})])
        if f == FALSE:
            return FALSE
    return f
