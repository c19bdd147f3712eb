"""roslaunch substitution args: tokenizer with positions and a small ``$(eval)`` interpreter.

The tokenizer is roslaunch's ``_collect_args`` state machine (same quirks, same errors);
the eval interpreter accepts the safe subset of Python that launch files use (literals,
arg names, ``arg('x')``, comparisons, and/or/not, arithmetic, conditional expressions,
math functions, ``env``/``optenv``, ``str``/``int``/``float``) and says "not analysable"
for anything else instead of guessing.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from typing import Callable, Mapping

from .. import evalguard as guard

VALID = ("find", "env", "optenv", "dirname", "anon", "arg")


class SubstError(Exception):
    pass


def collect(s: str) -> list[tuple[str, int, int]]:
    """The ``$(...)`` of ``s`` as (inner text, start of '$', end after ')'), in order."""
    out: list[tuple[str, int, int]] = []
    OUT, DOLLAR, LP, IN = 0, 1, 2, 3
    state = OUT
    buf: list[str] = []
    start = 0
    for i, c in enumerate(s):
        if c == "$":
            if state == OUT:
                state = DOLLAR
                start = i
            elif state == DOLLAR:
                start = i
            else:
                raise SubstError(f"Dollar signs '$' cannot be inside of substitution args [{s}]")
        elif c == "(":
            if state == DOLLAR:
                state = LP
            elif state != OUT:
                raise SubstError(f"Invalid left parenthesis '(' in substitution args [{s}]")
        elif c == ")":
            if state == IN:
                out.append(("".join(buf), start, i + 1))
                buf = []
            state = OUT
        elif state == DOLLAR:
            state = OUT
        elif state == LP:
            state = IN
        if state == IN:
            buf.append(c)
    return out


def is_eval(s: str) -> bool:
    return s.startswith("$(eval ") and s.endswith(")")


def convert_auto(value: str):
    """roslaunch's ``convert_value(value, 'auto')``."""
    try:
        if "." in value:
            return float(value)
        if "_" not in value:
            return int(value)
    except ValueError:
        pass
    lv = value.lower()
    if lv == "true":
        return True
    if lv == "false":
        return False
    return value


class NotAnalysable(Exception):
    pass


class EvalArgMissing(Exception):
    """``arg('x')`` or a bare name x with no value."""

    def __init__(self, name: str):
        super().__init__(name)
        self.name = name


_MATH = {k: v for k, v in math.__dict__.items() if not k.startswith("_")}
_CONSTS = {"true": True, "false": False, "True": True, "False": False}
_SAFE_FUNCS = {"str": str, "int": int, "float": float, "list": list, "dict": dict, "map": map}
# roslaunch evaluates with eval(s, {}, ...): Python adds the real builtins to the empty globals,
# so every builtin works there; these are the pure ones (results bounded, printed the same
# every run -- not zip/filter/reversed/enumerate, whose str() is an object address; a set of
# strings, whose order changes from run to run, is unknown where its order shows: evalguard.ordered)
_BUILTINS = {"len": len, "abs": abs, "max": max, "min": min, "round": round, "bool": bool, "sorted": sorted,
             "sum": sum, "any": any, "all": all, "tuple": tuple, "repr": repr, "hex": hex, "oct": oct,
             "bin": bin, "chr": chr, "ord": ord, "divmod": divmod, "format": format, "set": set,
             "frozenset": frozenset, "isinstance": isinstance}
_RESERVED = set(_CONSTS) | set(_MATH) | set(_SAFE_FUNCS) | set(_BUILTINS) | {
    "arg", "env", "optenv", "find", "anon", "dirname", "range"}
MAX_BUILD = 100_000  # the largest string / sequence an $(eval) may build here

_BIN = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_CMP = {ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
        ast.Gt: operator.gt, ast.GtE: operator.ge, ast.In: lambda a, b: a in b,
        ast.NotIn: lambda a, b: a not in b, ast.Is: operator.is_, ast.IsNot: operator.is_not}


def parse_eval(expr: str) -> ast.Expression:
    if "__" in expr:
        raise SubstError("$(eval ...) may not contain double underscore expressions")
    try:
        return guard.parse(expr.strip())
    except guard.TooBig:
        raise NotAnalysable() from None
    except SyntaxError as e:
        raise SubstError(f"invalid $(eval) expression: {e.msg}") from None


def eval_names(tree: ast.Expression) -> tuple[set[str], bool]:
    """Arg names the expression reads, and whether it only uses the supported subset."""
    names: set[str] = set()
    ok = True
    parents = {id(c): n for n in ast.walk(tree) for c in ast.iter_child_nodes(n)}
    for n in ast.walk(tree):
        if isinstance(n, ast.Call):
            f = n.func
            if isinstance(f, ast.Name) and f.id == "arg":
                if len(n.args) == 1 and isinstance(n.args[0], ast.Constant) and isinstance(n.args[0].value, str):
                    names.add(n.args[0].value)
                else:
                    ok = False
            elif isinstance(f, ast.Attribute):
                pass  # a method of a value ('x'.split(...), {...}.get(...)): evaluate_call_method decides
            elif not (isinstance(f, ast.Name) and f.id in _RESERVED):
                ok = False
        elif isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load):
            if n.id not in _RESERVED:
                names.add(n.id)
        elif isinstance(n, ast.Attribute) and isinstance(parents.get(id(n)), ast.Call) and parents[id(n)].func is n:
            pass
        elif isinstance(n, ast.Starred) and isinstance(parents.get(id(n)), ast.Call):
            pass  # f(*args): expanded when evaluated
        elif isinstance(n, (ast.Attribute, ast.Lambda, ast.ListComp, ast.DictComp,
                            ast.SetComp, ast.GeneratorExp, ast.NamedExpr, ast.Starred)):
            ok = False
    return names, ok


class _Unknown:
    """A value tvl-lsp cannot know here (``find('pkg')`` of a package outside the workspace):
    what is computed from it is unknown too, but the evaluation goes on, so that what is
    certain -- an arg the expression reads that has no value -- is still found."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "<unknown>"


UNKNOWN = _Unknown()
_Speculative = (NotAnalysable, SubstError, guard.TooBig, RecursionError, MemoryError, ArithmeticError, LookupError,
                TypeError, ValueError, AttributeError)


def run_eval(tree: ast.Expression, args: Mapping[str, str], env: Mapping[str, str],
             find: Callable[[str], object] | None = None, dirname: Callable[[], str] | None = None,
             anon: Callable[[str], str] | None = None) -> str:
    """Evaluate like roslaunch's ``_eval`` (result as ``str``). Raises EvalArgMissing,
    NotAnalysable, or SubstError (a runtime error roslaunch would raise).  ``find(pkg)``:
    the package's folder (``find('pkg')`` in the expression; without it, not analysable), or
    :data:`UNKNOWN` (then the value is unknown, but an arg read elsewhere in the expression
    without a value is still reported); ``dirname()``, ``anon(id)``: as ``$(dirname)`` and
    ``$(anon id)``."""

    def lookup(name: str):
        # roslaunch's order: its functions and math's names, then the args, then Python's builtins
        if name in _CONSTS:
            return _CONSTS[name]
        if name in _MATH:
            return _MATH[name]
        if name in args:
            return convert_auto(args[name])
        if name in _SAFE_FUNCS:
            return _SAFE_FUNCS[name]
        if name in _BUILTINS:
            return _BUILTINS[name]
        raise EvalArgMissing(name)

    def sized(v):
        if isinstance(v, (str, list, tuple, dict, set)) and len(v) > MAX_BUILD:
            raise NotAnalysable()
        return guard.canon(guard.bounded(v))

    steps = guard.Steps()

    def maybe(n):
        """``n`` evaluated where roslaunch may or may not evaluate it (after an unknown test):
        an arg missing there is not certain, and nothing it computes is known."""
        try:
            ev(n)
        except EvalArgMissing:
            pass
        except _Speculative:
            pass
        return UNKNOWN

    def call_args(nodes) -> list:
        """A call's positional arguments, ``*xs`` expanded (a list, tuple or string)."""
        out = []
        for x in nodes:
            if isinstance(x, ast.Starred):
                v = ev(x.value)
                if v is UNKNOWN:
                    out.append(UNKNOWN)
                elif isinstance(v, (list, tuple, str)):
                    out.extend(guard.bounded(v))
                else:
                    raise NotAnalysable()
            else:
                out.append(ev(x))
        return out

    def ev(n):
        steps.tick()
        if isinstance(n, ast.Expression):
            return ev(n.body)
        if isinstance(n, ast.Constant):
            return n.value
        if isinstance(n, ast.Name):
            return lookup(n.id)
        if isinstance(n, ast.BoolOp):
            v = True if isinstance(n.op, ast.And) else False
            for i, x in enumerate(n.values):
                v = ev(x)
                if v is UNKNOWN:
                    for rest in n.values[i + 1:]:
                        maybe(rest)
                    return UNKNOWN
                if isinstance(n.op, ast.And) and not v:
                    return v
                if isinstance(n.op, ast.Or) and v:
                    return v
            return v
        if isinstance(n, ast.UnaryOp):
            v = ev(n.operand)
            if v is UNKNOWN:
                return UNKNOWN
            if isinstance(n.op, ast.Not):
                return not v
            if isinstance(n.op, ast.USub):
                return -v
            if isinstance(n.op, ast.UAdd):
                return +v
            raise NotAnalysable()
        if isinstance(n, ast.BinOp):
            op = _BIN.get(type(n.op))
            if op is None:
                raise NotAnalysable()
            a, b = ev(n.left), ev(n.right)
            if a is UNKNOWN or b is UNKNOWN:
                return UNKNOWN
            if op is operator.pow and isinstance(b, (int, float)) and abs(b) > 1000:
                raise NotAnalysable()
            if op is operator.mul and (isinstance(a, str) or isinstance(b, str)):
                if (isinstance(a, int) and a > 10000) or (isinstance(b, int) and b > 10000):
                    raise NotAnalysable()
            if op is operator.mod and isinstance(a, str):
                guard.ordered(b)
            guard.check_binop(op, a, b)
            return sized(op(a, b))
        if isinstance(n, ast.Compare):
            left = ev(n.left)
            for k, (op, right) in enumerate(zip(n.ops, n.comparators)):
                r = ev(right)
                if left is UNKNOWN or r is UNKNOWN:
                    for rest in n.comparators[k + 1:]:
                        maybe(rest)
                    return UNKNOWN
                if not _CMP[type(op)](left, r):
                    return False
                left = r
            return True
        if isinstance(n, ast.Subscript):  # indexing and slicing ('fanuc_' + arg('ik')[0:3])
            v = ev(n.value)
            sl = n.slice
            if isinstance(sl, ast.Slice):
                parts = [ev(x) if x is not None else None for x in (sl.lower, sl.upper, sl.step)]
                if v is UNKNOWN or UNKNOWN in parts:
                    return UNKNOWN
                if not isinstance(v, (str, list, tuple, dict)):
                    raise SubstError(f"$(eval) failed: TypeError: '{type(v).__name__}' object is not subscriptable")
                if any(p is not None and not isinstance(p, int) for p in parts) or parts[2] == 0:
                    raise NotAnalysable()
                return v[slice(*parts)]
            if v is not UNKNOWN and not isinstance(v, (str, list, tuple, dict)):
                raise SubstError(f"$(eval) failed: TypeError: '{type(v).__name__}' object is not subscriptable")
            k = ev(sl)
            if v is UNKNOWN or k is UNKNOWN:
                return UNKNOWN
            return v[k]
        if isinstance(n, ast.IfExp):
            t = ev(n.test)
            if t is UNKNOWN:
                # roslaunch takes one branch: an arg missing in both is certain, else unknown
                missing = []
                for branch in (n.body, n.orelse):
                    try:
                        ev(branch)
                    except EvalArgMissing as m:
                        missing.append(m)
                    except _Speculative:
                        pass
                if len(missing) == 2:
                    raise missing[0]
                return UNKNOWN
            return ev(n.body) if t else ev(n.orelse)
        if isinstance(n, (ast.Tuple, ast.List, ast.Set)):
            if any(isinstance(x, ast.Starred) for x in n.elts):
                raise NotAnalysable()
            vals = [ev(x) for x in n.elts]
            if UNKNOWN in vals:
                return UNKNOWN
            return tuple(vals) if isinstance(n, ast.Tuple) else sized(set(vals)) if isinstance(n, ast.Set) else vals
        if isinstance(n, ast.Dict):
            if any(k is None for k in n.keys):
                raise NotAnalysable()
            items = [(ev(k), ev(v)) for k, v in zip(n.keys, n.values)]
            if any(k is UNKNOWN or v is UNKNOWN for k, v in items):
                return UNKNOWN
            return dict(items)
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute):
            obj = ev(n.func.value)
            attr = n.func.attr
            if any(k.arg is None for k in n.keywords):
                raise NotAnalysable()
            if obj is not UNKNOWN and not hasattr(obj, attr):
                raise SubstError(f"$(eval) failed: AttributeError: '{type(obj).__name__}' object has no "
                                 f"attribute '{attr}'")
            vals = call_args(n.args)
            kws = {k.arg: ev(k.value) for k in n.keywords}
            if obj is UNKNOWN or UNKNOWN in vals or UNKNOWN in kws.values():
                return UNKNOWN
            try:
                return sized(guard.call_method(obj, attr, vals, kws))
            except guard.NotAllowed:
                raise NotAnalysable() from None
        if isinstance(n, ast.Call):
            if not isinstance(n.func, ast.Name) or any(k.arg is None for k in n.keywords):
                raise NotAnalysable()
            fname = n.func.id
            vals = call_args(n.args)
            kws = {k.arg: ev(k.value) for k in n.keywords}
            if UNKNOWN in vals or UNKNOWN in kws.values():
                return UNKNOWN
            if fname == "dirname" and not vals and not kws and dirname is not None:
                return dirname()
            if fname == "anon" and len(vals) == 1 and not kws and anon is not None and isinstance(vals[0], str):
                return anon(vals[0])
            if fname == "range" and not kws and 1 <= len(vals) <= 3 and all(isinstance(v, int) for v in vals):
                r = range(*vals)
                if len(r) > MAX_BUILD:
                    raise NotAnalysable()
                return r
            if fname in _BUILTINS or fname in _SAFE_FUNCS:
                f = _BUILTINS.get(fname) or _SAFE_FUNCS[fname]
                guard.check_call(f, vals)
                if fname == "format" and len(vals) > 1 and isinstance(vals[1], str) and _WIDTH.search(vals[1]):
                    raise NotAnalysable()
                return sized(f(*vals, **kws))
            if kws:
                raise NotAnalysable()
            if fname == "find":
                if find is None or len(vals) != 1 or not isinstance(vals[0], str):
                    raise NotAnalysable()
                return find(vals[0])
            if fname == "arg":
                name = vals[0]
                if name not in args:
                    raise EvalArgMissing(name)
                return convert_auto(args[name])
            if fname == "env":
                if vals[0] not in env:
                    raise SubstError(f"environment variable '{vals[0]}' is not set")
                return env[vals[0]]
            if fname == "optenv":
                return env.get(vals[0], vals[1] if len(vals) > 1 else "")
            f = _MATH.get(fname)
            if f is None or not callable(f):
                raise NotAnalysable()
            guard.check_call(f, vals)
            return sized(f(*vals))
        raise NotAnalysable()

    try:
        v = ev(tree)
        if v is UNKNOWN:
            raise NotAnalysable()
        return str(guard.ordered(v))
    except (EvalArgMissing, NotAnalysable, SubstError):
        raise
    except (RecursionError, MemoryError, guard.TooBig):
        raise NotAnalysable() from None
    except Exception as e:  # a runtime error roslaunch's eval would raise too
        raise SubstError(f"$(eval) failed: {type(e).__name__}: {e}") from None


def anon_name(ident: str, counter: Callable[[], int]) -> str:
    return f"{ident}_anon{counter()}"
