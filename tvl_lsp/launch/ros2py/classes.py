"""Classes defined in a launch file or a workspace module: ``class X(Base): ...`` interpreted like
the rest (methods are functions of the file with ``self``; ``super().__init__``; properties,
static and class methods), so that helpers such as configuration builders and custom
``Substitution`` subclasses are followed instead of making everything after them unknown.

Instances are :class:`PyInstance`; a class whose bases tvl-lsp does not know (a library's) keeps
going with unknown attributes rather than failing.  A ``Substitution`` subclass is performed when
launching: :mod:`.convert` turns an instance into a ``py-perform`` part whose ``perform(context)``
the walker interprets with the arguments' values (:mod:`.subst_ext`).
"""

from __future__ import annotations

import ast
from typing import Optional

from .values import Decline, Func, LClass, ModuleNS, PyError, Sym, Unknown

MAX_MRO = 16


class PyClass:
    """A class of an interpreted module: its bases, methods and class attributes."""

    def __init__(self, name: str, where, bases: list, module: ModuleNS):
        self.name = name
        self.where = where
        self.bases = bases
        self.module = module
        self.attrs: dict = {}        # name -> value, or ("static" | "class" | "property", Func)
        self.opaque: Optional[str] = None   # why the body could not be followed (None: it could)

    def __repr__(self) -> str:
        return f"PyClass({self.name})"

    def mro(self) -> list:
        """The class and its ancestors, depth first (enough for launch files' helpers)."""
        out: list = []
        stack = [self]
        while stack and len(out) < MAX_MRO:
            c = stack.pop(0)
            if any(c is x for x in out):
                continue
            out.append(c)
            if isinstance(c, PyClass):
                stack.extend(c.bases)
        return out

    def lookup(self, name: str):
        """(value, owner) of a class attribute along the MRO; (None, None) when absent; an
        unknown base makes an absent name unknown."""
        unknown_base = None
        for c in self.mro():
            if isinstance(c, PyClass):
                if name in c.attrs:
                    return c.attrs[name], c
            elif isinstance(c, (Sym, Unknown)):
                unknown_base = c
        if unknown_base is not None:
            what = unknown_base.qual if isinstance(unknown_base, Sym) else unknown_base.reason
            return Unknown(f"{self.name}.{name} (from the base {what}, not modelled)", self.where), None
        return None, None

    def derives_from(self, launch_name: str) -> bool:
        return any(isinstance(c, LClass) and (c.name == launch_name or launch_name in _bases_of(c))
                   for c in self.mro())

    def has_unknown_base(self) -> bool:
        return any(isinstance(c, (Sym, Unknown)) for c in self.mro())


def _bases_of(c: LClass) -> list:
    from . import apitable
    return apitable.CLASSES.get(c.qual, {}).get("bases", [])


class PyInstance:
    __slots__ = ("cls", "attrs")

    def __init__(self, cls: PyClass):
        self.cls = cls
        self.attrs: dict = {}

    def __repr__(self) -> str:
        return f"<{self.cls.name} instance>"


class BoundFunc:
    """A method bound to its instance (or class, for a classmethod)."""
    __slots__ = ("func", "self_value")

    def __init__(self, func: Func, self_value):
        self.func = func
        self.self_value = self_value


class SuperProxy:
    """``super()`` in a method of ``owner``, for ``self_value``."""
    __slots__ = ("owner", "self_value")

    def __init__(self, owner: PyClass, self_value):
        self.owner = owner
        self.self_value = self_value


_NOOP = object()


def define(interp, st: ast.ClassDef, env, m: ModuleNS) -> PyClass:
    """``class`` statement: the body's functions and simple assignments."""
    bases = [interp.ev(b, env, m) for b in st.bases]
    cls = PyClass(st.name, m.where(st), bases, m)
    if st.decorator_list:
        cls.opaque = "a decorated class (dataclass ...)"
    for sub in st.body:
        if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef)):
            kind = None
            for d in sub.decorator_list:
                name = d.id if isinstance(d, ast.Name) else d.attr if isinstance(d, ast.Attribute) else ""
                if name in ("staticmethod", "classmethod", "property"):
                    kind = {"staticmethod": "static", "classmethod": "class", "property": "property"}[name]
                elif name == "setter":
                    kind = "setter"
                else:
                    kind = "unknown"
            a = sub.args
            fn = Func(sub.name, sub, m, env, [interp.ev(d, env, m) for d in a.defaults],
                      [interp.ev(d, env, m) if d is not None else None for d in a.kw_defaults])
            fn.owner = cls
            if kind is None:
                cls.attrs[sub.name] = fn
            elif kind == "setter":
                continue
            elif kind == "unknown":
                cls.attrs[sub.name] = Unknown(f"the decorated method {st.name}.{sub.name}", m.where(sub))
            else:
                cls.attrs[sub.name] = (kind, fn)
        elif isinstance(sub, ast.Assign) and all(isinstance(t, ast.Name) for t in sub.targets):
            v = interp.ev(sub.value, env, m)
            for t in sub.targets:
                cls.attrs[t.id] = v
        elif isinstance(sub, ast.AnnAssign) and isinstance(sub.target, ast.Name):
            if sub.value is not None:
                cls.attrs[sub.target.id] = interp.ev(sub.value, env, m)
        elif isinstance(sub, (ast.Expr, ast.Pass)):
            continue
        else:
            cls.opaque = f"a '{type(sub).__name__}' statement in the class body"
    return cls


def instantiate(interp, cls: PyClass, args: list, kwargs: dict, m: ModuleNS, n):
    if cls.opaque is not None:
        return Unknown(f"an instance of {cls.name} ({cls.opaque}: not modelled)", m.where(n))
    inst = PyInstance(cls)
    init, owner = cls.lookup("__init__")
    if isinstance(init, Func):
        interp.call_func(init, [inst] + list(args), kwargs, m, n)
    elif isinstance(init, Unknown) and not cls.derives_from("Substitution"):
        # a library base's constructor: what it sets is unknown (attributes it would set are)
        pass
    return inst


def get_attr(interp, obj, name: str, m: ModuleNS, n):
    if isinstance(obj, PyInstance):
        if name in obj.attrs:
            return obj.attrs[name]
        v, owner = obj.cls.lookup(name)
        return _bind(interp, v, obj, obj.cls, name, m, n)
    if isinstance(obj, PyClass):
        if name == "__name__":
            return obj.name
        v, owner = obj.lookup(name)
        return _bind(interp, v, None, obj, name, m, n)
    if isinstance(obj, SuperProxy):
        mro = obj.self_value.cls.mro() if isinstance(obj.self_value, PyInstance) else obj.owner.mro()
        after = False
        for c in mro:
            if c is obj.owner:
                after = True
                continue
            if not after:
                continue
            if isinstance(c, PyClass) and name in c.attrs:
                return _bind(interp, c.attrs[name], obj.self_value, c, name, m, n)
            if isinstance(c, LClass):
                # a launch base's method (Substitution.__init__ ...): nothing tvl-lsp follows
                return BoundFunc(_NOOP, None) if name == "__init__" else Unknown(f"{c.name}.{name}", m.where(n))
            if isinstance(c, (Sym, Unknown)):
                return BoundFunc(_NOOP, None) if name == "__init__" else \
                    Unknown(f"{name} of a base tvl-lsp does not model", m.where(n))
        if name == "__init__":
            return BoundFunc(_NOOP, None)
        raise PyError("AttributeError", f"'super' object has no attribute '{name}'", m.where(n))
    return None


def _bind(interp, v, inst, cls: PyClass, name: str, m: ModuleNS, n):
    if v is None:
        if inst is not None and cls.has_unknown_base():
            return Unknown(f"{cls.name}.{name} (set by a base tvl-lsp does not model)", m.where(n))
        who = f"'{cls.name}' object" if inst is not None else f"type object '{cls.name}'"
        raise PyError("AttributeError", f"{who} has no attribute '{name}'", m.where(n),
                      sure=not cls.has_unknown_base())
    if isinstance(v, tuple) and len(v) == 2 and v[0] in ("static", "class", "property"):
        kind, fn = v
        if kind == "static":
            return fn
        if kind == "class":
            return BoundFunc(fn, cls)
        if inst is None:
            return Unknown(f"the property {cls.name}.{name}", m.where(n))
        return interp.call_func(fn, [inst], {}, m, n)
    if isinstance(v, Func) and inst is not None:
        return BoundFunc(v, inst)
    return v


def set_attr(obj, name: str, v) -> bool:
    if isinstance(obj, PyInstance):
        obj.attrs[name] = v
        return True
    if isinstance(obj, PyClass):
        obj.attrs[name] = v
        return True
    return False


def call(interp, f, args: list, kwargs: dict, m: ModuleNS, n):
    """Calls of the objects above (None: not one of them)."""
    if isinstance(f, PyClass):
        return instantiate(interp, f, args, kwargs, m, n)
    if isinstance(f, BoundFunc):
        if f.func is _NOOP:
            return None
        return interp.call_func(f.func, [f.self_value] + list(args), kwargs, m, n)
    if isinstance(f, SuperProxy):
        raise PyError("TypeError", "'super' object is not callable", m.where(n))
    return _NOT


_NOT = object()


def make_super(interp, env, m: ModuleNS, n):
    """Zero-argument ``super()``: the class of the method being run and its first argument."""
    e = env
    while e is not None:
        f = e.vars.get("\x00func")
        if isinstance(f, Func) and getattr(f, "owner", None) is not None:
            a = f.node.args
            params = a.posonlyargs + a.args
            if params:
                return SuperProxy(f.owner, e.vars.get(params[0].arg))
        e = e.parent
    raise Decline("super() outside a method of a class tvl-lsp follows", m.where(n))


def is_instance(v, cls: PyClass) -> bool:
    return isinstance(v, PyInstance) and any(c is cls for c in v.cls.mro())


__all__ = ["PyClass", "PyInstance", "BoundFunc", "SuperProxy", "define", "instantiate", "get_attr", "set_attr",
           "call", "make_super", "is_instance"]
