"""Which top-level args are booleans: how each arg's value is used, through the whole load.

A launch file analysed on its own has no model saying which args are features; tvl-lsp takes
as free booleans (checked for both ``true`` and ``false``) the top-level args that are only
ever used as booleans.  Deciding that needs the real scoping of roslaunch: an arg's value is
passed on by ``<arg name="y" value="$(arg x)"/>``, by the ``<arg>`` children of an
``<include>`` and by ``pass_all_args``, and it is *used* in the included files as much as in
the file itself.  So the typing is a walk of the symbolic loader (:class:`Walker` with
``typing=``) in which each candidate arg's value is an opaque marker; the walker reports where
a value holding a marker ends up:

- a whole ``if`` / ``unless`` value that is exactly one arg's marker: a **boolean** use;
- inside ``$(eval ...)``: boolean where the expression treats it as one (``not x``, ``x and
  y``, a bare condition), a **string** use where it compares it with a string, computes with it
  or calls a function on it (``arg('robot') == 'pmb2'``, ``arg('ns') + '/'``, ``int(x)``);
- anywhere else (a node name, a parameter value, a file name, part of a longer value...): a
  **string** use.

Values an ``<arg>`` or an ``<include>``'s ``<arg>`` passes on are not uses: they are followed.
So is an arg an ``$(eval)`` returns as it is (``end_effector if end_effector else 'no-ee'``, ``a or
b``, ``arg('x')``): the eval's result carries its marker, and where the result is used decides
(its other reads were classified in the expression).  An ``<include>`` whose file name holds a
marked arg is followed with the arg's default.  A default reading another candidate arg
(``<arg name="arm" default="$(eval {'iron': False}.get(arg('robot'), True))"/>``) classifies that
read like any other use, and passes the uses of the arg it defines on to the args it returns.
"""

from __future__ import annotations

import ast
import re
from typing import Iterable, Optional

from ...base.formula import FALSE, Formula, disj
from . import subst as S
from .rules import UNRESOLVED, _bool_val

ARG_MARK = "\x02"
EVAL_MARK = "\x03"
_ARG_RE = re.compile(ARG_MARK + "([^" + ARG_MARK + "]*)" + ARG_MARK)
_EVAL_RE = re.compile(EVAL_MARK + "[^" + EVAL_MARK + "]*" + EVAL_MARK)

BOOL, STRING = "bool", "string"
FLOW = "flow"  # an eval read whose value is the eval's result (its use is the result's)


def marker(name: str) -> str:
    return ARG_MARK + name + ARG_MARK


class ArgTyping:
    """The uses of the marked args seen during one typing walk."""

    def __init__(self, names: Iterable[str], defaults: Optional[dict[str, str]] = None,
                 derived: Optional[dict[str, set[str]]] = None,
                 direct: Optional[dict[str, set[str]]] = None):
        self.uses: dict[str, set[str]] = {n: set(direct.get(n, ())) if direct else set() for n in names}
        self.defaults = dict(defaults or {})
        # derived[x]: the marked args the default of the marked arg x reads.  The walk gives x
        # its marker (the command line's value wins over the default), so the default is never
        # resolved: x's uses are theirs too (<arg name="urdf" default="...$(arg base).xacro"/>
        # used in a command makes 'base' a string)
        self.derived = {x: set(ys) for x, ys in (derived or {}).items()}

    def concrete(self, value: str) -> str:
        """``value`` with each arg marker replaced by the arg's default (to find the file an
        ``<include>`` names with a marked arg: the walk follows it with the default)."""
        if ARG_MARK not in value:
            return value
        return _ARG_RE.sub(lambda m: self.defaults.get(m.group(1), m.group(0)), value)

    def _add(self, name: str, kind: str) -> None:
        if name in self.uses:
            self.uses[name].add(kind)

    def _closed(self) -> dict[str, set[str]]:
        uses = {n: set(k) for n, k in self.uses.items()}
        changed = True
        while changed:
            changed = False
            for x, ys in self.derived.items():
                for y in ys:
                    if y in uses and x in uses and not uses[x] <= uses[y]:
                        uses[y] |= uses[x]
                        changed = True
        return uses

    def strings(self) -> set[str]:
        return {n for n, k in self._closed().items() if STRING in k}

    def used(self) -> set[str]:
        return {n for n, k in self._closed().items() if k}

    # ------------------------------------------------------------ hooks called by the walker

    def sink(self, cases) -> None:
        """A resolved value used as a string."""
        for _, v in cases:
            if ARG_MARK in v:
                for m in _ARG_RE.finditer(v):
                    self._add(m.group(1), STRING)

    def condition(self, cases, key: str) -> Formula:
        """An if/unless value: a marker alone is a boolean use, and the element is walked
        (both values are possible); other values are evaluated as roslaunch does."""
        ok = []
        for c, v in cases:
            if ARG_MARK in v or EVAL_MARK in v:
                outside = _EVAL_RE.sub("", v)
                rest = _ARG_RE.sub("", outside).strip()
                evals = _EVAL_RE.findall(v)
                # one arg, or one eval (whose result is the args it returns as they are): boolean
                kind = BOOL if not rest and len(_ARG_RE.findall(outside)) + len(evals) == 1 else STRING
                for n in _ARG_RE.findall(v):
                    self._add(n, kind)
                ok.append(c)
                continue
            if v.startswith("$(eval ") or UNRESOLVED in v:
                ok.append(c)
                continue
            b = _bool_val(v)
            if b is not None and b == (key == "if"):
                ok.append(c)
        return disj(ok) if ok else FALSE

    def eval_uses(self, value: str, sc, guard: Formula) -> Optional[list]:
        """``$(eval ...)`` reading marked args: classify each read, and return an inert
        result; None when it reads no marked arg (then it is evaluated as usual)."""
        try:
            tree = S.parse_eval(value[7:-1])
        except (S.SubstError, S.NotAnalysable):
            return None
        marked: dict[str, set[str]] = {}
        flows: set[str] = set()
        for name, kind in _reads(tree):
            ms = set()
            for _, v in sc.args.get(name, []):
                ms.update(_ARG_RE.findall(v))
                if EVAL_MARK in v:
                    ms.add("")
            if ms:
                marked.setdefault(name, set()).update(ms)
                for m in ms:
                    if m and kind == FLOW:
                        flows.add(m)  # returned as it is: the result's use is its use
                    elif m:
                        self._add(m, kind)
        if not marked:
            return None
        return [(guard, EVAL_MARK + ",".join(sorted(marked)) + "".join(marker(m) for m in sorted(flows)) + EVAL_MARK)]


_WHOLE_ARG = re.compile(r"\$\(arg\s+([^\s)]+)\s*\)")


def default_reads(value: str, names: set[str]) -> tuple[set[str], dict[str, set[str]]]:
    """How a top-level arg's default reads the candidate args ``names`` (the typing walk gives
    the arg its marker, so the default itself is never walked): the args it returns as they are
    (``$(arg y)``, ``$(eval y if c else z)``: the arg's own uses are theirs), and the uses it
    makes of the others (``$(eval {'iron': False}.get(arg('robot'), True))``: robot is a string;
    ``prefix_$(arg y)``: a string)."""
    flows: set[str] = set()
    uses: dict[str, set[str]] = {}
    v = value.strip()
    m = _WHOLE_ARG.fullmatch(v)
    if m:
        if m.group(1) in names:
            flows.add(m.group(1))
        return flows, uses
    if S.is_eval(v):
        try:
            tree = S.parse_eval(v[7:-1])
        except (S.SubstError, S.NotAnalysable):
            return flows, uses
        for name, kind in _reads(tree):
            if name not in names:
                continue
            if kind == FLOW:
                flows.add(name)
            else:
                uses.setdefault(name, set()).add(kind)
        return flows, uses
    for name in _WHOLE_ARG.findall(v):
        if name in names:
            uses.setdefault(name, set()).add(STRING)
    return flows, uses


def _reads(tree: ast.AST) -> list[tuple[str, str]]:
    """(arg name, use kind) for every arg an eval expression reads (``x`` or ``arg('x')``):
    BOOL, STRING, or FLOW (the expression may return it as it is)."""
    parents: dict[int, ast.AST] = {}
    for n in ast.walk(tree):
        for c in ast.iter_child_nodes(n):
            parents[id(c)] = n
    out = []
    for n in ast.walk(tree):
        name = None
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "arg":
            if len(n.args) == 1 and isinstance(n.args[0], ast.Constant) and isinstance(n.args[0].value, str):
                name = n.args[0].value
        elif isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load) and n.id not in S._RESERVED:
            if not (isinstance(parents.get(id(n)), ast.Call) and parents[id(n)].func is n):
                name = n.id
        if name is None:
            continue
        out.append((name, _kind(n, parents)))
    return out


def _kind(n: ast.AST, parents: dict[int, ast.AST]) -> str:
    p = parents.get(id(n))
    if p is None or isinstance(p, ast.Expression):
        return FLOW  # the expression's value is the arg's
    if (isinstance(p, ast.IfExp) and n is not p.test) or isinstance(p, ast.BoolOp):
        return _kind(p, parents)  # a branch, an and/or operand: may be the value of p itself
    if isinstance(p, ast.Compare):
        operands = [p.left] + list(p.comparators)
        if any(o is not n and _stringy(o) for o in operands) or any(
                isinstance(op, (ast.In, ast.NotIn)) for op in p.ops):
            return STRING
        return BOOL
    if isinstance(p, (ast.BinOp, ast.Subscript, ast.Attribute, ast.JoinedStr, ast.FormattedValue)):
        return STRING
    if isinstance(p, ast.Call) and p.func is not n:
        return STRING
    if isinstance(p, ast.UnaryOp) and not isinstance(p.op, ast.Not):
        return STRING
    return BOOL


def _stringy(n: ast.AST) -> bool:
    if isinstance(n, ast.Constant):
        return isinstance(n.value, str) or (isinstance(n.value, (int, float)) and not isinstance(n.value, bool))
    return isinstance(n, (ast.List, ast.Tuple, ast.Set, ast.Dict, ast.BinOp, ast.JoinedStr))
