"""rosparam's YAML: what ``yaml.safe_load`` returns inside roslaunch.

roslaunch loads ``<rosparam>`` bodies and files with ``yaml.safe_load`` after importing
``rosparam``, which registers on PyYAML's ``SafeLoader`` (ros_comm ``rosparam/__init__.py``):

- ``!degrees X`` -> ``float(X) * pi / 180`` and ``!radians X`` -> ``float(eval(X))`` with ``pi``
  meaning ``math.pi``;
- implicit resolvers: a plain scalar ``deg(X)`` is ``!degrees`` and ``rad(X)`` is ``!radians``;
- ``!!binary`` -> an ``xmlrpc.client.Binary``.

tvl-lsp does the same on a subclass (PyYAML's own loaders are left alone), and evaluates the
``!radians`` expression with a small arithmetic interpreter instead of ``eval`` (numbers,
``+ - * / // % **``, ``pi``, ``math.*`` constants and functions); anything else fails as the
real ``eval`` would (NameError) -- a YAML error roslaunch reports as "invalid YAML".
"""

from __future__ import annotations

import ast
import math
import operator
import re
from typing import Any

import yaml

from ...base import yamlsafe
from .. import evalguard as guard

try:  # libyaml's parser when available (same results, faster)
    _Base = yaml.CSafeLoader  # type: ignore[attr-defined]
except AttributeError:  # pragma: no cover
    _Base = yaml.SafeLoader


class RosYamlError(yaml.YAMLError):
    """A rosparam constructor failed (``!degrees abc``, ``!radians foo``)."""


class Binary(bytes):
    """``!!binary`` data (roslaunch wraps it in ``xmlrpc.client.Binary``)."""


_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}


def _arith(expr: str) -> float:
    """``float(eval(expr))`` for the arithmetic a ``!radians`` value holds."""
    try:
        tree = guard.parse(expr.strip())
    except guard.TooBig:
        raise RosYamlError(f"radian expression too long or too deeply nested to analyse: {expr[:80]}") from None
    except SyntaxError:
        raise RosYamlError(f"invalid radian expression: {expr}") from None
    steps = [0]

    def ev(n):
        steps[0] += 1
        if steps[0] > 10_000:
            raise RosYamlError(f"radian expression too complex: {expr}")
        if isinstance(n, ast.Expression):
            return ev(n.body)
        if isinstance(n, ast.Constant) and isinstance(n.value, (int, float)) and not isinstance(n.value, bool):
            return n.value
        if isinstance(n, ast.UnaryOp) and isinstance(n.op, (ast.USub, ast.UAdd)):
            v = ev(n.operand)
            return -v if isinstance(n.op, ast.USub) else +v
        if isinstance(n, ast.BinOp) and type(n.op) in _OPS:
            a, b = ev(n.left), ev(n.right)
            if isinstance(n.op, ast.Pow) and abs(b) > 1000:
                raise RosYamlError(f"radian expression too large: {expr}")
            try:
                guard.check_binop(_OPS[type(n.op)], a, b)
            except guard.TooBig:
                raise RosYamlError(f"radian expression too large: {expr[:80]}") from None
            return _OPS[type(n.op)](a, b)
        if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == "math":
            v = getattr(math, n.attr, None)
            if v is None or n.attr.startswith("_"):
                raise RosYamlError(f"module 'math' has no attribute '{n.attr}'")
            return v
        if isinstance(n, ast.Call) and not n.keywords:
            f = ev(n.func)
            if not callable(f):
                raise RosYamlError(f"'{type(f).__name__}' object is not callable")
            args = [ev(a) for a in n.args]
            try:
                guard.check_call(f, args)
                return guard.bounded(f(*args))
            except guard.TooBig:
                raise RosYamlError(f"radian expression too large: {expr[:80]}") from None
        if isinstance(n, ast.Name):
            raise RosYamlError(f"name '{n.id}' is not defined")
        raise RosYamlError(f"invalid radian expression: {expr}")

    try:
        return float(ev(tree))
    except RosYamlError:
        raise
    except (RecursionError, MemoryError):
        raise RosYamlError(f"radian expression too deeply nested to analyse: {expr[:80]}") from None
    except (ArithmeticError, ValueError, TypeError, OverflowError) as e:
        raise RosYamlError(f"{type(e).__name__}: {e}") from None


def _radians(loader, node) -> float:
    value = loader.construct_scalar(node).strip()
    expr = value.replace("pi", "math.pi")
    if expr.startswith("rad("):
        expr = expr[4:-1]
    return _arith(expr)


def _degrees(loader, node) -> float:
    value = loader.construct_scalar(node)
    expr = value
    if expr.startswith("deg("):
        expr = expr.strip()[4:-1]
    try:
        return float(expr) * math.pi / 180.0
    except ValueError:
        raise RosYamlError(f"invalid degree value: {value}") from None


def _binary(loader, node) -> Binary:
    return Binary(loader.construct_yaml_binary(node))


def rosparam_loader(base: type) -> type:
    """A loader class deriving from ``base`` with rosparam's constructors and resolvers."""
    cls = type("RosparamLoader", (base,), {})
    cls.add_constructor("!radians", _radians)
    cls.add_constructor("!degrees", _degrees)
    cls.add_constructor("tag:yaml.org,2002:binary", _binary)
    cls.add_implicit_resolver("!degrees", re.compile(r"^deg\([^\)]*\)$"), first="deg(")
    cls.add_implicit_resolver("!radians", re.compile(r"^rad\([^\)]*\)$"), first="rad(")
    return cls


RosparamLoader = rosparam_loader(_Base)


def load(text: str) -> Any:
    """``yaml.safe_load(text)`` as roslaunch runs it (rosparam's tags).  Raises
    ``yaml.YAMLError`` (``RosYamlError`` when a rosparam constructor fails)."""
    try:
        return yamlsafe.load(text, RosparamLoader)  # a safe loader subclass; alias bombs refused
    except RecursionError:
        raise RosYamlError("the YAML is nested too deeply") from None
