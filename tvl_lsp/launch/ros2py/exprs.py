"""The expressions of the Python launch-file interpreter (a mixin of :class:`.interp.Interp`):
literals, names, containers, operators, comparisons, subscripts and attributes, with Python's
semantics on plain values and :class:`~.values.Unknown` propagated (a comparison with an
unknown value is unknown, never False)."""

from __future__ import annotations

import ast
import operator
from typing import Optional

from .. import evalguard as guard
from .values import Decline, LClass, ModuleNS, PathObj, PyError, Sym, Unknown, marked, sstr, type_name

_BIN: dict = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
              ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow,
              ast.BitOr: operator.or_, ast.BitAnd: operator.and_, ast.BitXor: operator.xor,
              ast.LShift: operator.lshift, ast.RShift: operator.rshift}
_CMP: dict = {ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
              ast.Gt: operator.gt, ast.GtE: operator.ge}
_PLAIN = (str, int, float, bool, type(None), bytes)
_CONTAINERS = (list, tuple, dict, set, frozenset)
_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//", ast.Mod: "%", ast.Pow: "**",
        ast.BitOr: "|", ast.BitAnd: "&", ast.BitXor: "^", ast.LShift: "<<", ast.RShift: ">>"}


def plain_value(v) -> bool:
    """A value made only of plain Python data (no launch object, no unknown)."""
    if isinstance(v, _PLAIN):
        return not marked(v)
    if isinstance(v, (list, tuple, set, frozenset)):
        return all(plain_value(x) for x in v)
    if isinstance(v, dict):
        return all(plain_value(k) and plain_value(x) for k, x in v.items())
    return False


def first_unknown(v, depth: int = 0) -> Optional[Unknown]:
    """The first Unknown inside a value (None: none)."""
    if isinstance(v, Unknown):
        return v
    if depth > 30:
        return None
    if isinstance(v, (list, tuple, set, frozenset)):
        for x in v:
            u = first_unknown(x, depth + 1)
            if u is not None:
                return u
    elif isinstance(v, dict):
        for k, x in v.items():
            u = first_unknown(k, depth + 1) or first_unknown(x, depth + 1)
            if u is not None:
                return u
    return None


def guard_len(v, m, n) -> None:
    if isinstance(v, (str, list, tuple, dict, set)) and len(v) > guard.MAX_LEN * 10:
        raise Decline("a value too large to analyse", m.where(n))


class Exprs:
    def e_constant(self, n, env, m):
        v = n.value
        if isinstance(v, str):
            return sstr(v, m.literal_where(n))
        if v is Ellipsis:
            return Unknown("'...'", m.where(n))
        return v

    def e_name(self, n, env, m):
        return self.lookup(n.id, env, m, n)

    def e_joined(self, n, env, m):
        out = []
        for part in n.values:
            if isinstance(part, ast.Constant):
                out.append(str(part.value))
                continue
            v = self.ev(part.value, env, m)
            if isinstance(v, Unknown):
                return v
            spec = ""
            if part.format_spec is not None:
                spec = self.ev(part.format_spec, env, m)
                if isinstance(spec, Unknown):
                    return spec
            r = self.lib.format_value(self, v, part.conversion, spec, m, part)
            if isinstance(r, Unknown):
                return r
            out.append(r)
        s = "".join(out)
        guard_len(s, m, n)
        return s

    def e_list(self, n, env, m):
        return self.elements(n.elts, env, m)

    def e_tuple(self, n, env, m):
        return tuple(self.elements(n.elts, env, m))

    def e_set(self, n, env, m):
        items = self.elements(n.elts, env, m)
        try:
            return set(items)
        except TypeError as ex:
            raise PyError("TypeError", str(ex), m.where(n))

    def elements(self, elts, env, m) -> list:
        out = []
        for e in elts:
            if isinstance(e, ast.Starred):
                out.extend(self.iterate(self.ev(e.value, env, m), m, e))
            else:
                out.append(self.ev(e, env, m))
        if len(out) > guard.MAX_LEN:
            raise Decline("a list too long to analyse", m.where(elts[0]) if elts else None)
        return out

    def e_dict(self, n, env, m):
        out: dict = {}
        for k, v in zip(n.keys, n.values):
            if k is None:
                d = self.ev(v, env, m)
                if isinstance(d, Unknown):
                    return d
                if not isinstance(d, dict):
                    raise PyError("TypeError", f"'{type_name(d)}' object is not a mapping", m.where(v))
                out.update(d)
                continue
            key = self.ev(k, env, m)
            if isinstance(key, Unknown):
                return key
            val = self.ev(v, env, m)
            try:
                out[key] = val
            except TypeError as ex:
                raise PyError("TypeError", str(ex), m.where(k))
        return out

    def e_binop(self, n, env, m):
        a = self.ev(n.left, env, m)
        b = self.ev(n.right, env, m)
        return self.binop(n.op, a, b, m, n)

    def binop(self, op, a, b, m, n):
        if isinstance(a, Unknown):
            return a
        if isinstance(b, Unknown):
            return b
        special = self.lib.binop_special(self, op, a, b, m, n)
        if special is not NotImplemented:
            return special
        f = _BIN.get(type(op))
        if f is None or not (isinstance(a, _PLAIN + _CONTAINERS) and isinstance(b, _PLAIN + _CONTAINERS)):
            raise PyError("TypeError", f"unsupported operand type(s) for {_OPS.get(type(op), '?')}: "
                          f"'{type_name(a)}' and '{type_name(b)}'", m.where(n))
        if f is operator.mod and isinstance(a, str):
            return self.lib.percent_format(self, a, b, m, n)
        try:
            guard.check_binop(f, a, b)
            r = f(a, b)
        except guard.TooBig:
            raise Decline("a value too large to analyse", m.where(n))
        except ZeroDivisionError as ex:
            raise PyError("ZeroDivisionError", str(ex), m.where(n), sure=True)
        except (TypeError, ValueError, OverflowError) as ex:
            raise PyError(type(ex).__name__, str(ex), m.where(n))
        if isinstance(r, str) and (marked(a) or marked(b)):
            return r
        guard_len(r, m, n)
        return r

    def e_unary(self, n, env, m):
        v = self.ev(n.operand, env, m)
        if isinstance(n.op, ast.Not):
            if isinstance(v, Unknown):
                return v
            return not self.truth(v, m, n.operand, "value")
        if isinstance(v, Unknown):
            return v
        if not isinstance(v, (int, float)):
            raise PyError("TypeError", f"bad operand type for unary operator: '{type_name(v)}'", m.where(n))
        if isinstance(n.op, ast.USub):
            return -v
        if isinstance(n.op, ast.UAdd):
            return +v
        if isinstance(n.op, ast.Invert) and isinstance(v, int):
            return ~v
        raise PyError("TypeError", "bad operand type for unary operator", m.where(n))

    def e_boolop(self, n, env, m):
        is_and = isinstance(n.op, ast.And)
        v = None
        for x in n.values:
            v = self.ev(x, env, m)
            if isinstance(v, Unknown):
                return v
            t = self.truth(v, m, x, "value")
            if is_and and not t:
                return v
            if not is_and and t:
                return v
        return v

    def e_compare(self, n, env, m):
        left = self.ev(n.left, env, m)
        for op, right_n in zip(n.ops, n.comparators):
            right = self.ev(right_n, env, m)
            r = self.compare(op, left, right, m, n)
            if isinstance(r, Unknown):
                return r
            if not r:
                return False
            left = right
        return True

    def compare(self, op, a, b, m, n):
        if isinstance(a, Unknown):
            return a
        if isinstance(b, Unknown):
            return b
        t = type(op)
        if t in (ast.Is, ast.IsNot):
            if a is None or b is None or isinstance(a, bool) or isinstance(b, bool):
                r = a is b if not (isinstance(a, bool) or isinstance(b, bool)) else (a is b)
            else:
                r = a is b
            return r if t is ast.Is else not r
        if t in (ast.In, ast.NotIn):
            r = self.contains(b, a, m, n)
            if isinstance(r, Unknown):
                return r
            return r if t is ast.In else not r
        if marked(a) or marked(b):
            return Unknown("a path in a package tvl-lsp cannot find", m.where(n))
        u = first_unknown(a) or first_unknown(b)
        if u is not None:
            return u
        if t in (ast.Eq, ast.NotEq):
            if isinstance(a, PathObj) and isinstance(b, PathObj):
                r = a.path == b.path
            else:
                r = a == b if (isinstance(a, _PLAIN + _CONTAINERS) or isinstance(b, _PLAIN + _CONTAINERS)) else a is b
            return r if t is ast.Eq else not r
        try:
            return _CMP[t](a, b)
        except TypeError as ex:
            raise PyError("TypeError", str(ex), m.where(n))

    def contains(self, container, item, m, n):
        if isinstance(container, Unknown):
            return container
        if isinstance(item, Unknown):
            return item
        env_in = self.lib.environ_contains(self, container, item, m, n)
        if env_in is not NotImplemented:
            return env_in
        if isinstance(container, str):
            if not isinstance(item, str):
                raise PyError("TypeError", "'in <string>' requires string as left operand", m.where(n))
            if marked(container) or marked(item):
                return Unknown("a path in a package tvl-lsp cannot find", m.where(n))
            return item in container
        if isinstance(container, _CONTAINERS):
            if isinstance(container, dict):
                try:
                    return item in container
                except TypeError as ex:
                    raise PyError("TypeError", str(ex), m.where(n))
            for x in container:
                if isinstance(x, Unknown):
                    return x
                if isinstance(x, _PLAIN) and isinstance(item, _PLAIN):
                    if (marked(x) or marked(item)) and x != item:
                        return Unknown("a path in a package tvl-lsp cannot find", m.where(n))
                    if x == item:
                        return True
                elif x is item:
                    return True
            return False
        if isinstance(container, PathObj):
            raise PyError("TypeError", "argument of type 'PosixPath' is not iterable", m.where(n))
        return Unknown(f"membership in a {type_name(container)}", m.where(n))

    def e_ifexp(self, n, env, m):
        t = self.ev(n.test, env, m)
        if isinstance(t, Unknown):
            # both branches might be the same plain value; otherwise the value is unknown
            a = self.ev(n.body, env, m)
            b = self.ev(n.orelse, env, m)
            if plain_value(a) and plain_value(b) and a == b and type(a) is type(b):
                return a
            return Unknown(t.reason, t.where)
        return self.ev(n.body if self.truth(t, m, n.test) else n.orelse, env, m)

    def e_subscript(self, n, env, m):
        obj = self.ev(n.value, env, m)
        key = self.ev(n.slice, env, m)
        return self.subscript(obj, key, m, n)

    def subscript(self, obj, key, m, n):
        if isinstance(obj, Unknown):
            return obj
        special = self.lib.subscript_special(self, obj, key, m, n)
        if special is not NotImplemented:
            return special
        if isinstance(key, Unknown):
            return key
        if isinstance(obj, (list, tuple, str)):
            if isinstance(key, slice):
                return obj[key]
            if not isinstance(key, int):
                raise PyError("TypeError", f"{type_name(obj)} indices must be integers or slices, not "
                              f"{type_name(key)}", m.where(n))
            try:
                return obj[key]
            except IndexError:
                raise PyError("IndexError", f"{type_name(obj)} index out of range", m.where(n), sure=True)
        if isinstance(obj, dict):
            try:
                return obj[key]
            except KeyError:
                raise PyError("KeyError", repr(str(key)) if isinstance(key, str) else repr(key), m.where(n),
                              sure=plain_value(key))
            except TypeError as ex:
                raise PyError("TypeError", str(ex), m.where(n))
        if isinstance(obj, (Sym, LClass)):
            return obj  # typing annotations (List[...]) and the like
        raise PyError("TypeError", f"'{type_name(obj)}' object is not subscriptable", m.where(n))

    def e_slice(self, n, env, m):
        parts = [self.ev(x, env, m) if x is not None else None for x in (n.lower, n.upper, n.step)]
        for p in parts:
            if isinstance(p, Unknown):
                return p
        return slice(*parts)

    def e_attribute(self, n, env, m):
        obj = self.ev(n.value, env, m)
        return self.attr_of(obj, n.attr, m, n)

    def attr_of(self, obj, name: str, m, n, importing: bool = False):
        if isinstance(obj, Unknown):
            return obj
        if isinstance(obj, ModuleNS):
            if name in obj.globals:
                return obj.globals[name]
            sub = self.host.workspace_module(obj.name + "." + name, self)
            if sub is not None:
                return sub
            raise PyError("ImportError" if importing else "AttributeError",
                          f"cannot import name '{name}' from '{obj.name}'" if importing else
                          f"module '{obj.name}' has no attribute '{name}'", m.where(n))
        if isinstance(obj, Sym):
            return self.funcs.resolve(self, f"{obj.qual}.{name}", m, n, importing)
        got = self.classes.get_attr(self, obj, name, m, n)
        if got is not None:
            return got
        return self.lib.attribute(self, obj, name, m, n, importing)
