"""``$(eval EXPR)`` of ROS 2 launch: Python's ``eval`` with the ``math`` module's names, evaluated
here without running any code.

launch evaluates the expanded text with ``eval(text, {}, vars(math))``: builtins and math
functions are available, and a name that is neither (``true`` from ``$(var flag)``) raises
``NameError: name 'true' is not defined``.  This module parses the text with Python's own
parser (so syntax errors read exactly as launch's) and interprets a safe subset: literals,
names, arithmetic, comparisons, ``and``/``or``/``not``, conditional expressions, subscripts,
the pure builtins and the pure methods of built-in values (:func:`evalguard.call_method`).  Anything else raises :class:`NotAnalysable` (the caller
then treats the value as unknown) -- nothing is ever executed.
"""

from __future__ import annotations

import ast
import builtins
import math
import operator
import re

from .. import evalguard as guard

_WIDTH = re.compile(r"\d{6,}")  # a format width / precision that would build a huge string


class NotAnalysable(Exception):
    pass


class EvalFailure(Exception):
    """What Python's eval would raise: ``kind`` (e.g. NameError) and its message."""

    def __init__(self, kind: str, message: str):
        super().__init__(message)
        self.kind = kind
        self.message = message


_MATH = {k: v for k, v in vars(math).items() if not k.startswith("_")}
_BUILTINS = {"int": int, "float": float, "str": str, "bool": bool, "len": len, "abs": abs, "min": min,
             "max": max, "round": round, "sum": sum, "list": list, "tuple": tuple, "sorted": sorted,
             "any": any, "all": all, "set": set, "frozenset": frozenset, "dict": dict, "range": range,
             "enumerate": enumerate, "zip": zip, "reversed": reversed, "isinstance": isinstance,
             "repr": repr, "chr": chr, "ord": ord, "divmod": divmod, "pow": pow, "hex": hex, "oct": oct,
             "bin": bin, "format": format, "True": True, "False": False, "None": None}
_ALL_BUILTINS = set(dir(builtins))
_BIN = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_CMP = {ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
        ast.Gt: operator.gt, ast.GtE: operator.ge, ast.In: lambda a, b: a in b,
        ast.NotIn: lambda a, b: a not in b, ast.Is: operator.is_, ast.IsNot: operator.is_not}


def evaluate(text: str, modules: tuple[str, ...] = ("math",)) -> str:
    """``str(eval(text, {}, locals))`` as launch computes it, or EvalFailure / NotAnalysable."""
    if len(text) > 10_000:
        raise NotAnalysable()
    text = text.lstrip(" \t")  # as the builtin eval does with a string
    try:
        tree = compile(text, "<string>", "eval", ast.PyCF_ONLY_AST, dont_inherit=True)
    except SyntaxError as e:
        raise EvalFailure("SyntaxError", str(e))
    except (MemoryError, RecursionError):  # nesting beyond Python's parser: not analysed here
        raise NotAnalysable() from None
    except ValueError as e:
        raise EvalFailure(type(e).__name__, str(e))
    names = dict(_BUILTINS)
    if "math" in modules:
        names.update(_MATH)
        names["math"] = math
    elif modules:
        raise NotAnalysable()
    try:
        return str(guard.ordered(_Eval(names).ev(tree)))
    except (EvalFailure, NotAnalysable):
        raise
    except (RecursionError, MemoryError, guard.TooBig):
        raise NotAnalysable() from None
    except Exception as e:  # an error Python's eval raises too
        raise EvalFailure(type(e).__name__, str(e)) from None


class _Eval:
    def __init__(self, names: dict):
        self.names = names
        self.steps = 0

    def ev(self, n):
        self.steps += 1
        if self.steps > guard.MAX_STEPS:
            raise NotAnalysable()
        if isinstance(n, ast.Expression):
            return self.ev(n.body)
        if isinstance(n, ast.Constant):
            return n.value
        if isinstance(n, ast.Name):
            if n.id in self.names:
                return self.names[n.id]
            if n.id in _ALL_BUILTINS:
                raise NotAnalysable()  # a builtin tvl-lsp does not run (open, getattr, ...)
            raise EvalFailure("NameError", f"name '{n.id}' is not defined")
        if isinstance(n, ast.BoolOp):
            if isinstance(n.op, ast.And):
                v = True
                for x in n.values:
                    v = self.ev(x)
                    if not v:
                        return v
                return v
            v = False
            for x in n.values:
                v = self.ev(x)
                if v:
                    return v
            return v
        if isinstance(n, ast.UnaryOp):
            v = self.ev(n.operand)
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
            a, b = self.ev(n.left), self.ev(n.right)
            if op is operator.pow and isinstance(b, (int, float)) and abs(b) > 1000:
                raise NotAnalysable()
            if op is operator.mul and any(isinstance(x, (str, list, tuple)) for x in (a, b)):
                k = b if isinstance(b, int) else a if isinstance(a, int) else 0
                if k > 100_000:
                    raise NotAnalysable()
            guard.check_binop(op, a, b)
            return guard.bounded(op(a, b))
        if isinstance(n, ast.Compare):
            left = self.ev(n.left)
            for op, right in zip(n.ops, n.comparators):
                r = self.ev(right)
                if not _CMP[type(op)](left, r):
                    return False
                left = r
            return True
        if isinstance(n, ast.IfExp):
            return self.ev(n.body) if self.ev(n.test) else self.ev(n.orelse)
        if isinstance(n, (ast.Tuple, ast.List, ast.Set)):
            if any(isinstance(x, ast.Starred) for x in n.elts):
                raise NotAnalysable()
            vals = [self.ev(x) for x in n.elts]
            return tuple(vals) if isinstance(n, ast.Tuple) else guard.canon(set(vals)) if isinstance(n, ast.Set) \
                else vals
        if isinstance(n, ast.Dict):
            if any(k is None for k in n.keys):
                raise NotAnalysable()
            return {self.ev(k): self.ev(v) for k, v in zip(n.keys, n.values)}
        if isinstance(n, ast.Subscript):
            v = self.ev(n.value)
            if isinstance(n.slice, ast.Slice):
                s = n.slice
                lo = self.ev(s.lower) if s.lower else None
                hi = self.ev(s.upper) if s.upper else None
                st = self.ev(s.step) if s.step else None
                return v[lo:hi:st]
            return v[self.ev(n.slice)]
        if isinstance(n, ast.Attribute):
            v = self.ev(n.value)
            if v is math and hasattr(math, n.attr) and not n.attr.startswith("_"):
                return getattr(math, n.attr)
            raise NotAnalysable()
        if isinstance(n, ast.Call):
            if any(isinstance(a, ast.Starred) for a in n.args) or any(k.arg is None for k in n.keywords):
                raise NotAnalysable()
            if isinstance(n.func, ast.Attribute):
                obj = self.ev(n.func.value)
                if obj is math and hasattr(math, n.func.attr) and not n.func.attr.startswith("_"):
                    f = getattr(math, n.func.attr)
                    args = [self.ev(a) for a in n.args]
                    if n.keywords:
                        raise NotAnalysable()
                    guard.check_call(f, args)
                    return guard.bounded(f(*args))
                args = [self.ev(a) for a in n.args]
                kws = {k.arg: self.ev(k.value) for k in n.keywords}
                try:
                    return guard.call_method(obj, n.func.attr, args, kws)
                except guard.NotAllowed:
                    raise NotAnalysable() from None
            f = self.ev(n.func)
            if not callable(f) or (f not in _BUILTINS.values() and f not in _MATH.values()):
                raise NotAnalysable()
            args = [self.ev(a) for a in n.args]
            kws = {k.arg: self.ev(k.value) for k in n.keywords}
            if kws and f not in (dict, sorted, int, round, max, min, sum, format):
                raise NotAnalysable()
            if f is range and any(isinstance(a, int) and abs(a) > 100_000 for a in args):
                raise NotAnalysable()
            if f in (math.factorial, math.comb, math.perm) and any(isinstance(a, int) and a > 1000 for a in args):
                raise NotAnalysable()
            if f is format and len(args) > 1 and isinstance(args[1], str) and _WIDTH.search(args[1]):
                raise NotAnalysable()
            guard.check_call(f, args + list(kws.values()))
            return guard.canon(guard.bounded(f(*args, **kws)))
        raise NotAnalysable()
