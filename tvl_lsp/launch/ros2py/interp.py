"""A bounded interpreter of Python's syntax tree, for launch files: it evaluates what a launch
file computes when ``ros2 launch`` loads it (module code, ``generate_launch_description()``,
the functions they call, an ``OpaqueFunction``'s function with the arguments' values) without
importing or running anything.

What it knows: literals, names, assignments (with unpacking, subscripts, augmented),
containers and comprehensions, arithmetic and string operations (``+``, ``%``, ``.format``,
f-strings), comparisons, ``if`` / ``for`` / ``while`` / ``try`` / ``with`` on values it knows,
functions of the file and of the workspace's modules (bounded depth), and the library calls of
:mod:`.library` and :mod:`.launchapi`.  A value it cannot know is an :class:`~.values.Unknown`
that propagates; where the program's path depends on one, it stops with
:class:`~.values.Decline` (the construct and why).  It never executes the file's code:
``exec``, ``eval``, ``__import__``, ``subprocess``, writing files are declined or unknown.

Bounds: ``MAX_STEPS`` evaluation steps per run, calls ``MAX_CALL_DEPTH`` deep, expressions
``MAX_EXPR_DEPTH`` deep, values within :mod:`tvl_lsp.launch.evalguard`'s sizes.
"""

from __future__ import annotations

import ast
import builtins
from typing import Callable, Optional

from .. import evalguard as guard
from .exprs import _CONTAINERS, _PLAIN, Exprs, first_unknown, plain_value
from .classes import PyClass
from .values import (Builtin, BoundMethod, Decline, Env, Func, LClass, LObj, ModuleNS, PathObj, PyError,
                     SStr, Sym, Unknown, marked, type_name)

MAX_STEPS = 300_000
MAX_CALL_DEPTH = 40
MAX_EXPR_DEPTH = 120



class _Return(Exception):
    def __init__(self, value):
        self.value = value


class _Break(Exception):
    pass


class _Continue(Exception):
    pass


class TooBig(Exception):
    pass


class Interp(Exprs):
    """One interpretation: ``host`` answers what lies outside the syntax tree (files, packages,
    the environment, workspace modules, launch configurations in an ``OpaqueFunction``)."""

    def __init__(self, host, steps: Optional[list] = None):
        self.host = host
        self.steps = steps if steps is not None else [0]
        self.depth = 0
        self.expr_depth = 0
        self.callsites: list = []   # (path, span) of the calls being interpreted
        from . import classes, launchapi, library, pyfuncs
        self.classes = classes
        self.lib = library
        self.funcs = pyfuncs
        self.api = launchapi
        self.modules: dict[str, ModuleNS] = host.module_cache

    # ------------------------------------------------------------------ helpers
    def tick(self, node=None, module: Optional[ModuleNS] = None) -> None:
        self.steps[0] += 1
        if self.steps[0] > MAX_STEPS:
            raise Decline(f"the file computes more than {MAX_STEPS:,} steps (a loop that does not end?)",
                          module.where(node) if module is not None and node is not None else None)

    def anchor(self, m: ModuleNS, node):
        """Where a launch object made at ``node`` of ``m`` shows in the analysed file: there,
        or at the call of the analysed file that led to ``m`` (a workspace module's helper)."""
        if m.path == self.host.unit_path:
            return m.where(node)
        for where in reversed(self.callsites):
            if where[0] == self.host.unit_path:
                return where
        return m.where(node)

    def unknown(self, reason: str, module: ModuleNS, node) -> Unknown:
        return Unknown(reason, module.where(node))

    def truth(self, v, module: ModuleNS, node, what: str = "condition") -> bool:
        if isinstance(v, Unknown):
            raise Decline(f"this {what} depends on a value tvl-lsp cannot know ({v.reason})", module.where(node))
        if isinstance(v, (LObj, Func, Builtin, LClass, Sym, BoundMethod, PathObj, PyClass)):
            if isinstance(v, Sym):
                raise Decline(f"this {what} depends on {v.qual}, which tvl-lsp does not model", module.where(node))
            return True
        if isinstance(v, _PLAIN + _CONTAINERS):
            return bool(v)
        return True

    # ------------------------------------------------------------------ modules
    def run_module(self, m: ModuleNS) -> None:
        self.exec_block(m.tree.body, None, m)

    # ------------------------------------------------------------------ statements
    def exec_block(self, body: list, env: Optional[Env], m: ModuleNS) -> None:
        for st in body:
            self.exec_stmt(st, env, m)

    def exec_stmt(self, st, env: Optional[Env], m: ModuleNS) -> None:
        self.tick(st, m)
        t = type(st)
        if t is ast.Expr:
            self.ev(st.value, env, m)
        elif t is ast.Assign:
            v = self.ev(st.value, env, m)
            for tgt in st.targets:
                self.assign(tgt, v, env, m)
        elif t is ast.AnnAssign:
            if st.value is not None:
                self.assign(st.target, self.ev(st.value, env, m), env, m)
        elif t is ast.AugAssign:
            self.aug_assign(st, env, m)
        elif t is ast.Return:
            raise _Return(self.ev(st.value, env, m) if st.value is not None else None)
        elif t is ast.If:
            test = self.ev(st.test, env, m)
            if self.truth(test, m, st.test, "'if' condition"):
                self.exec_block(st.body, env, m)
            else:
                self.exec_block(st.orelse, env, m)
        elif t is ast.For:
            self.exec_for(st, env, m)
        elif t is ast.While:
            self.exec_while(st, env, m)
        elif t in (ast.FunctionDef, ast.AsyncFunctionDef):
            self.define_function(st, env, m)
        elif t is ast.ClassDef:
            self.set_name(st.name, self.classes.define(self, st, env, m), env, m)
        elif t in (ast.Import, ast.ImportFrom):
            self.exec_import(st, env, m)
        elif t is ast.Pass:
            pass
        elif t is ast.Break:
            raise _Break()
        elif t is ast.Continue:
            raise _Continue()
        elif t is ast.Try or t.__name__ == "TryStar":
            self.exec_try(st, env, m)
        elif t is ast.With:
            self.exec_with(st, env, m)
        elif t is ast.Global:
            if env is not None:
                env.globals_decl.update(st.names)
        elif t is ast.Nonlocal:
            if env is not None:
                env.nonlocal_decl.update(st.names)
        elif t is ast.Delete:
            for tgt in st.targets:
                self.delete(tgt, env, m)
        elif t is ast.Assert:
            v = self.ev(st.test, env, m)
            if not self.truth(v, m, st.test, "assertion"):
                msg = self.ev(st.msg, env, m) if st.msg is not None else ""
                raise PyError("AssertionError", str(msg) if not isinstance(msg, Unknown) else "", m.where(st))
        elif t is ast.Raise:
            exc = self.ev(st.exc, env, m) if st.exc is not None else None
            kind, msg = "Exception", ""
            if isinstance(exc, tuple) and len(exc) == 2 and exc[0] == "__exc__":
                kind, msg = exc[1]
            elif isinstance(exc, Builtin):
                kind = exc.name
            raise PyError(kind, msg, m.where(st))
        else:
            raise Decline(f"tvl-lsp does not interpret a Python '{t.__name__}' statement", m.where(st))

    def define_function(self, st, env: Optional[Env], m: ModuleNS) -> None:
        if st.decorator_list:
            self.set_name(st.name, Unknown(f"the decorated function {st.name}() is not modelled", m.where(st)),
                          env, m)
            return
        a = st.args
        defaults = [self.ev(d, env, m) for d in a.defaults]
        kw_defaults = [self.ev(d, env, m) if d is not None else _MISSING for d in a.kw_defaults]
        self.set_name(st.name, Func(st.name, st, m, env, defaults, kw_defaults), env, m)

    def exec_for(self, st, env, m) -> None:
        it = self.ev(st.iter, env, m)
        seq = self.iterate(it, m, st.iter)
        broke = False
        for x in seq:
            self.tick(st, m)
            self.assign(st.target, x, env, m)
            try:
                self.exec_block(st.body, env, m)
            except _Break:
                broke = True
                break
            except _Continue:
                continue
        if not broke:
            self.exec_block(st.orelse, env, m)

    def exec_while(self, st, env, m) -> None:
        while True:
            self.tick(st, m)
            if not self.truth(self.ev(st.test, env, m), m, st.test, "'while' condition"):
                self.exec_block(st.orelse, env, m)
                return
            try:
                self.exec_block(st.body, env, m)
            except _Break:
                return
            except _Continue:
                continue

    def exec_try(self, st, env, m) -> None:
        try:
            try:
                self.exec_block(st.body, env, m)
            except PyError as e:
                for h in st.handlers:
                    if self.handler_matches(h, e, env, m):
                        if h.name:
                            self.set_name(h.name, ("__exc__", (e.kind, e.message)), env, m)
                        self.exec_block(h.body, env, m)
                        break
                else:
                    raise
            else:
                self.exec_block(st.orelse, env, m)
        finally:
            if st.finalbody:
                self.exec_block(st.finalbody, env, m)

    _HIERARCHY = {"KeyError": ("LookupError",), "IndexError": ("LookupError",),
                  "FileNotFoundError": ("OSError", "IOError", "EnvironmentError"),
                  "PackageNotFoundError": ("KeyError", "LookupError"), "ModuleNotFoundError": ("ImportError",),
                  "ZeroDivisionError": ("ArithmeticError",), "UnicodeDecodeError": ("ValueError",)}

    def handler_matches(self, h, e: PyError, env, m) -> bool:
        if h.type is None:
            return True
        types = h.type.elts if isinstance(h.type, ast.Tuple) else [h.type]
        names = set()
        for t in types:
            v = self.ev(t, env, m)
            if isinstance(v, Builtin):
                names.add(v.name)
            elif isinstance(v, (Sym, LClass)):
                names.add(v.qual.rsplit(".", 1)[-1])
            elif isinstance(v, PyClass):
                names.add(v.name)
            else:
                raise Decline("tvl-lsp cannot tell which exceptions this 'except' catches", m.where(h))
        kinds = {e.kind, *self._HIERARCHY.get(e.kind, ())}
        if names & {"Exception", "BaseException"} or names & kinds:
            return True
        return False

    def exec_with(self, st, env, m) -> None:
        for item in st.items:
            v = self.ev(item.context_expr, env, m)
            if item.optional_vars is not None:
                self.assign(item.optional_vars, v, env, m)
        self.exec_block(st.body, env, m)

    def exec_import(self, st, env, m) -> None:
        if isinstance(st, ast.Import):
            for a in st.names:
                if a.asname:
                    self.set_name(a.asname, self.import_module(a.name, m, st), env, m)
                else:
                    top = a.name.split(".", 1)[0]
                    self.import_module(a.name, m, st)  # checks that it is known
                    self.set_name(top, self.import_module(top, m, st), env, m)
            return
        if st.level:
            base = self.host.relative_module(m, st.level, st.module)
            if base is None:
                for a in st.names:
                    self.set_name(a.asname or a.name, Unknown(f"relative import from {'.' * st.level}"
                                                              f"{st.module or ''} is not modelled", m.where(st)), env, m)
                return
            modname = base
        else:
            modname = st.module or ""
        mod = self.import_module(modname, m, st)
        for a in st.names:
            if a.name == "*":
                if isinstance(mod, ModuleNS):
                    for k, v in mod.globals.items():
                        if not k.startswith("_"):
                            self.set_name(k, v, env, m)
                    continue
                raise Decline(f"'from {modname} import *' is not modelled", m.where(st))
            self.set_name(a.asname or a.name, self.attr_of(mod, a.name, m, st, importing=True), env, m)

    def import_module(self, name: str, m: ModuleNS, node):
        """A module: a workspace module (interpreted), else a library name (:class:`Sym`)."""
        ws = self.host.workspace_module(name, self)
        if ws is not None:
            return ws
        self.funcs.check_import(name, m, node, self.host.concrete)
        return Sym(name)

    # ------------------------------------------------------------------ names
    def lookup(self, name: str, env: Optional[Env], m: ModuleNS, node):
        e = env
        if e is not None and name in e.globals_decl:
            e = None
        while e is not None:
            if name in e.vars:
                return e.vars[name]
            e = e.parent
        g = m.globals
        if name in g:
            return g[name]
        b = self.funcs.builtin(name)
        if b is not None:
            return b
        if name in _PY_BUILTINS:
            return Unknown(f"the builtin {name} is not modelled", m.where(node))
        raise PyError("NameError", f"name '{name}' is not defined", m.where(node), sure=True)

    def set_name(self, name: str, v, env: Optional[Env], m: ModuleNS) -> None:
        if env is None or name in env.globals_decl:
            m.globals[name] = v
            return
        if name in env.nonlocal_decl:
            e = env.parent
            while e is not None:
                if name in e.vars:
                    e.vars[name] = v
                    return
                e = e.parent
        env.vars[name] = v

    def assign(self, tgt, v, env, m) -> None:
        t = type(tgt)
        if t is ast.Name:
            self.set_name(tgt.id, v, env, m)
        elif t in (ast.Tuple, ast.List):
            if isinstance(v, Unknown):
                for e in tgt.elts:
                    self.assign(e.value if isinstance(e, ast.Starred) else e, v, env, m)
                return
            items = self.iterate(v, m, tgt)
            star = [i for i, e in enumerate(tgt.elts) if isinstance(e, ast.Starred)]
            if star:
                i = star[0]
                after = len(tgt.elts) - i - 1
                if len(items) < len(tgt.elts) - 1:
                    raise PyError("ValueError", "not enough values to unpack", m.where(tgt))
                parts = items[:i] + [list(items[i:len(items) - after])] + items[len(items) - after:]
                for e, x in zip(tgt.elts, parts):
                    self.assign(e.value if isinstance(e, ast.Starred) else e, x, env, m)
                return
            if len(items) != len(tgt.elts):
                raise PyError("ValueError", f"too many values to unpack (expected {len(tgt.elts)})"
                              if len(items) > len(tgt.elts) else
                              f"not enough values to unpack (expected {len(tgt.elts)}, got {len(items)})",
                              m.where(tgt))
            for e, x in zip(tgt.elts, items):
                self.assign(e, x, env, m)
        elif t is ast.Subscript:
            obj = self.ev(tgt.value, env, m)
            key = self.ev(tgt.slice, env, m)
            if isinstance(obj, (dict, list)) and not isinstance(key, Unknown):
                if isinstance(key, slice) and isinstance(obj, list):
                    obj[key] = self.iterate(v, m, tgt)
                    return
                try:
                    obj[key] = v
                except (IndexError, TypeError) as ex:
                    raise PyError(type(ex).__name__, str(ex), m.where(tgt))
                return
            if isinstance(obj, dict) and isinstance(key, Unknown):
                raise Decline(f"a dictionary key tvl-lsp cannot know ({key.reason})", m.where(tgt))
            if self.lib.is_environ(obj):
                self.host.set_env(key, v, m, tgt)   # os.environ['X'] = ...: what launch reads later
                return
            if isinstance(obj, Unknown):
                return
            raise Decline(f"tvl-lsp does not model assigning an item of a {type_name(obj)}", m.where(tgt))
        elif t is ast.Attribute:
            obj = self.ev(tgt.value, env, m)
            if isinstance(obj, Unknown):
                return
            if isinstance(obj, LObj):
                obj.extra[tgt.attr] = v
                return
            if self.classes.set_attr(obj, tgt.attr, v):
                return
            raise Decline(f"tvl-lsp does not model setting an attribute of a {type_name(obj)}", m.where(tgt))
        elif t is ast.Starred:
            self.assign(tgt.value, v, env, m)
        else:
            raise Decline("tvl-lsp does not model this assignment", m.where(tgt))

    def aug_assign(self, st, env, m) -> None:
        tgt = st.target
        if isinstance(tgt, ast.Name):
            cur = self.lookup(tgt.id, env, m, tgt)
        elif isinstance(tgt, ast.Subscript):
            cur = self.ev(tgt, env, m)
        elif isinstance(tgt, ast.Attribute):
            cur = self.ev(tgt, env, m)
        else:
            raise Decline("tvl-lsp does not model this assignment", m.where(st))
        val = self.ev(st.value, env, m)
        if isinstance(cur, list) and isinstance(st.op, ast.Add):
            cur.extend(self.iterate(val, m, st.value))   # in place, as Python does
            new = cur
        elif isinstance(cur, dict) and isinstance(st.op, ast.BitOr) and isinstance(val, dict):
            cur.update(val)
            new = cur
        else:
            new = self.binop(st.op, cur, val, m, st)
        self.assign(tgt, new, env, m)

    def delete(self, tgt, env, m) -> None:
        if isinstance(tgt, ast.Name):
            if env is not None and tgt.id in env.vars:
                del env.vars[tgt.id]
            elif tgt.id in m.globals:
                del m.globals[tgt.id]
        elif isinstance(tgt, ast.Subscript):
            obj = self.ev(tgt.value, env, m)
            key = self.ev(tgt.slice, env, m)
            if isinstance(obj, (dict, list)) and not isinstance(key, Unknown):
                try:
                    del obj[key]
                except (KeyError, IndexError, TypeError) as ex:
                    raise PyError(type(ex).__name__, str(ex), m.where(tgt))
            elif not isinstance(obj, Unknown):
                raise Decline(f"tvl-lsp does not model deleting an item of a {type_name(obj)}", m.where(tgt))

    # ------------------------------------------------------------------ expressions
    def ev(self, n, env: Optional[Env], m: ModuleNS):
        if n is None:
            return None
        self.expr_depth += 1
        try:
            if self.expr_depth > MAX_EXPR_DEPTH:
                raise Decline("an expression nested too deeply to analyse", m.where(n))
            self.tick(n, m)
            fn = self._EXPR.get(type(n))
            if fn is None:
                raise Decline(f"tvl-lsp does not interpret a Python '{type(n).__name__}' expression", m.where(n))
            return fn(self, n, env, m)
        finally:
            self.expr_depth -= 1






















    def e_call(self, n, env, m):
        if isinstance(n.func, ast.Name) and n.func.id == "super" and not n.args and not n.keywords and \
                "super" not in m.globals:
            return self.classes.make_super(self, env, m, n)
        f = self.ev(n.func, env, m)
        args = []
        for a in n.args:
            if isinstance(a, ast.Starred):
                args.extend(self.iterate(self.ev(a.value, env, m), m, a))
            else:
                args.append(self.ev(a, env, m))
        kwargs = {}
        for k in n.keywords:
            if k.arg is None:
                d = self.ev(k.value, env, m)
                if isinstance(d, Unknown):
                    raise Decline(f"the keyword arguments of this call are unknown ({d.reason})", m.where(k.value))
                if not isinstance(d, dict):
                    raise PyError("TypeError", "argument after ** must be a mapping", m.where(k.value))
                for kk, vv in d.items():
                    if not isinstance(kk, str):
                        raise PyError("TypeError", "keywords must be strings", m.where(k.value))
                    kwargs[str(kk)] = vv
            else:
                kwargs[k.arg] = self.ev(k.value, env, m)
        return self.call(f, args, kwargs, m, n)

    def call(self, f, args: list, kwargs: dict, m: ModuleNS, n):
        if isinstance(f, Func):
            return self.call_func(f, args, kwargs, m, n)
        if isinstance(f, Unknown):
            return f
        if isinstance(f, Builtin):
            return f.fn(self, args, kwargs, m, n)
        if isinstance(f, LClass):
            return self.api.construct(self, f, args, kwargs, m, n)
        if isinstance(f, BoundMethod):
            return self.lib.call_method(self, f, args, kwargs, m, n)
        if isinstance(f, Sym):
            return self.funcs.call_symbol(self, f, args, kwargs, m, n)
        r = self.classes.call(self, f, args, kwargs, m, n)
        if r is not self.classes._NOT:
            return r
        raise PyError("TypeError", f"'{type_name(f)}' object is not callable", m.where(n))

    def call_func(self, f: Func, args: list, kwargs: dict, m: ModuleNS, n):
        if self.depth >= MAX_CALL_DEPTH:
            raise Decline(f"calls nested more than {MAX_CALL_DEPTH} deep (recursion?)", m.where(n))
        fm = f.module
        env = Env(fm, f.closure)
        self.bind(f, args, kwargs, env, m, n)
        env.vars["\x00func"] = f   # (for super())
        self.depth += 1
        self.callsites.append(m.where(n))
        try:
            if isinstance(f.node, ast.Lambda):
                return self.ev(f.node.body, env, fm)
            if _is_generator(f.node):
                raise Decline(f"the generator function {f.name}() is not modelled", fm.where(f.node))
            try:
                self.exec_block(f.node.body, env, fm)
            except _Return as r:
                return r.value
            except (_Break, _Continue):
                raise Decline("'break' or 'continue' outside a loop", fm.where(f.node))
            return None
        finally:
            self.depth -= 1
            self.callsites.pop()

    def bind(self, f: Func, args: list, kwargs: dict, env: Env, m: ModuleNS, n) -> None:
        a = f.node.args
        params = a.posonlyargs + a.args
        names = [p.arg for p in params]
        if len(args) > len(names) and a.vararg is None:
            raise PyError("TypeError", f"{f.name}() takes {len(names)} positional arguments but {len(args)} were "
                          "given", m.where(n))
        bound: dict = {}
        for name, v in zip(names, args):
            bound[name] = v
        if a.vararg is not None:
            bound[a.vararg.arg] = tuple(args[len(names):])
        extra: dict = {}
        posonly = {p.arg for p in a.posonlyargs}
        kwonly = [p.arg for p in a.kwonlyargs]
        for k, v in kwargs.items():
            if k in bound and k not in posonly:
                raise PyError("TypeError", f"{f.name}() got multiple values for argument '{k}'", m.where(n))
            if (k in names and k not in posonly) or k in kwonly:
                bound[k] = v
            elif a.kwarg is not None:
                extra[k] = v
            else:
                raise PyError("TypeError", f"{f.name}() got an unexpected keyword argument '{k}'", m.where(n))
        nd = len(f.defaults)
        for i, name in enumerate(names):
            if name not in bound:
                j = i - (len(names) - nd)
                if j >= 0:
                    bound[name] = f.defaults[j]
                else:
                    raise PyError("TypeError", f"{f.name}() missing required positional argument: '{name}'",
                                  m.where(n))
        for name, d in zip(kwonly, f.kw_defaults):
            if name not in bound:
                if d is _MISSING:
                    raise PyError("TypeError", f"{f.name}() missing required keyword-only argument: '{name}'",
                                  m.where(n))
                bound[name] = d
        if a.kwarg is not None:
            bound[a.kwarg.arg] = extra
        env.vars.update(bound)

    def e_lambda(self, n, env, m):
        a = n.args
        defaults = [self.ev(d, env, m) for d in a.defaults]
        kw_defaults = [self.ev(d, env, m) if d is not None else _MISSING for d in a.kw_defaults]
        return Func("<lambda>", n, m, env, defaults, kw_defaults)

    def e_comp(self, n, env, m):
        inner = Env(m, env)
        out: list = []
        kind = type(n)

        def go(i: int) -> None:
            if i == len(n.generators):
                if kind is ast.DictComp:
                    out.append((self.ev(n.key, inner, m), self.ev(n.value, inner, m)))
                else:
                    out.append(self.ev(n.elt, inner, m))
                if len(out) > guard.MAX_LEN:
                    raise Decline("a list too long to analyse", m.where(n))
                return
            g = n.generators[i]
            src = self.ev(g.iter, inner if i else env, m)
            for x in self.iterate(src, m, g.iter):
                self.tick(g, m)
                self.assign(g.target, x, inner, m)
                ok = True
                for cond in g.ifs:
                    if not self.truth(self.ev(cond, inner, m), m, cond, "comprehension condition"):
                        ok = False
                        break
                if ok:
                    go(i + 1)
        go(0)
        if kind is ast.DictComp:
            d = {}
            for k, v in out:
                if isinstance(k, Unknown):
                    return k
                d[k] = v
            return d
        if kind is ast.SetComp:
            try:
                return set(out)
            except TypeError as ex:
                raise PyError("TypeError", str(ex), m.where(n))
        return out  # list comprehensions and generator expressions (used once: a list is the same)

    def e_namedexpr(self, n, env, m):
        v = self.ev(n.value, env, m)
        self.assign(n.target, v, env, m)
        return v

    def e_starred(self, n, env, m):
        raise Decline("a starred expression here is not modelled", m.where(n))

    def e_await(self, n, env, m):
        raise Decline("'await' is not modelled", m.where(n))

    _EXPR: dict[type, Callable] = {}

    # ------------------------------------------------------------------ iteration
    def iterate(self, v, m: ModuleNS, n) -> list:
        if isinstance(v, Unknown):
            raise Decline(f"this loop or unpacking goes over a value tvl-lsp cannot know ({v.reason})", m.where(n))
        if isinstance(v, (list, tuple)):
            return list(v)
        if isinstance(v, str):
            if marked(v):
                raise Decline("this loop goes over a path in a package tvl-lsp cannot find", m.where(n))
            return list(v)
        if isinstance(v, dict):
            return list(v.keys())
        if isinstance(v, (set, frozenset)):
            return list(v)
        if isinstance(v, range):
            if len(v) > guard.MAX_LEN:
                raise Decline("a range too long to analyse", m.where(n))
            return list(v)
        it = self.lib.iterate_special(self, v, m, n)
        if it is not NotImplemented:
            return it
        raise PyError("TypeError", f"'{type_name(v)}' object is not iterable", m.where(n))


_MISSING = object()
_PY_BUILTINS = frozenset(dir(builtins))
_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//", ast.Mod: "%", ast.Pow: "**",
        ast.BitOr: "|", ast.BitAnd: "&", ast.BitXor: "^", ast.LShift: "<<", ast.RShift: ">>"}


_GENERATORS: dict = {}


def _is_generator(node) -> bool:
    k = id(node)
    got = _GENERATORS.get(k)
    if got is not None and got[0] is node:
        return got[1]
    r = _has_yield(node)
    if len(_GENERATORS) > 50_000:
        _GENERATORS.clear()
    _GENERATORS[k] = (node, r)
    return r


def _has_yield(node) -> bool:
    stack = list(node.body)
    while stack:
        x = stack.pop()
        if isinstance(x, (ast.Yield, ast.YieldFrom)):
            return True
        if isinstance(x, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            continue
        stack.extend(ast.iter_child_nodes(x))
    return False


Interp._EXPR = {
    ast.Constant: Interp.e_constant, ast.Name: Interp.e_name, ast.JoinedStr: Interp.e_joined,
    ast.List: Interp.e_list, ast.Tuple: Interp.e_tuple, ast.Set: Interp.e_set, ast.Dict: Interp.e_dict,
    ast.BinOp: Interp.e_binop, ast.UnaryOp: Interp.e_unary, ast.BoolOp: Interp.e_boolop,
    ast.Compare: Interp.e_compare, ast.IfExp: Interp.e_ifexp, ast.Subscript: Interp.e_subscript,
    ast.Slice: Interp.e_slice, ast.Attribute: Interp.e_attribute, ast.Call: Interp.e_call,
    ast.Lambda: Interp.e_lambda, ast.ListComp: Interp.e_comp, ast.SetComp: Interp.e_comp,
    ast.DictComp: Interp.e_comp, ast.GeneratorExp: Interp.e_comp, ast.NamedExpr: Interp.e_namedexpr,
    ast.Starred: Interp.e_starred, ast.Await: Interp.e_await,
}

__all__ = ["Interp", "MAX_STEPS", "MAX_CALL_DEPTH", "plain_value", "first_unknown", "SStr"]
