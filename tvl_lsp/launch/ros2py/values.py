"""The values of the Python launch-file interpreter.

Plain Python values stand for themselves (``str``, ``int``, ``float``, ``bool``, ``None``,
``list``, ``tuple``, ``dict``, ``set``): the interpreter computes with them as Python would.
Everything else is one of the classes below: a value that cannot be known statically
(:class:`Unknown`, which carries where and why), a launch object (:class:`LObj`: a ``Node``, a
``LaunchConfiguration``, ...), a function of the file (:class:`Func`), a library name that is
not modelled (:class:`Sym`), and a few stand-ins (paths, files, ``os.environ``, the launch
context of an ``OpaqueFunction``).  A string literal of the file keeps its source range
(:class:`SStr`), so that the launch objects made from it point at it.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from pathlib import PurePosixPath
from typing import Any, Optional

from ...base.text import LineIndex, Pos, Span

Where = tuple  # (path, Span)


class Unknown:
    """A value tvl-lsp cannot know without running the file: ``reason`` says why, ``where``
    (path, span) where it was made.  Every operation on it gives it back (the first reason
    stays); it never becomes a guess."""

    __slots__ = ("reason", "where")

    def __init__(self, reason: str, where: Optional[Where] = None):
        self.reason = reason
        self.where = where

    def __repr__(self) -> str:
        return f"Unknown({self.reason!r})"


class SStr(str):
    """A string with the source range of the literal it was written as (``where``: (path,
    span) of the characters between the quotes, or None when the literal has escapes,
    prefixes or parts and the range would not be exact)."""

    where: Optional[Where] = None


def sstr(value: str, where: Optional[Where]) -> str:
    s = SStr(value)
    s.where = where
    return s


def where_of(v) -> Optional[Where]:
    return getattr(v, "where", None) if isinstance(v, SStr) else None


class PyError(Exception):
    """A Python exception the file's code raises (``kind``: its class name): caught by the
    file's own ``try`` / ``except``, else the load fails."""

    def __init__(self, kind: str, message: str, where: Optional[Where] = None, sure: bool = False):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.where = where
        # raised by a launch constructor's own check (an unknown keyword, a missing argument):
        # the file certainly fails to load, whatever tvl-lsp does not model
        self.sure = sure


class Decline(Exception):
    """The interpreter cannot go on without knowing what it cannot know (a branch on an
    unknown value, a loop over one, a construct it does not model): ``reason`` and the
    (path, span) of the construct that stops it."""

    def __init__(self, reason: str, where: Optional[Where] = None):
        super().__init__(reason)
        self.reason = reason
        self.where = where


@dataclass(eq=False)
class ModuleNS:
    """One interpreted module (the launch file, or a workspace module it imports)."""
    path: str
    text: str
    index: LineIndex
    name: str
    globals: dict = field(default_factory=dict)
    tree: Optional[ast.Module] = None
    _ascii: Optional[bool] = None
    _spans: dict = field(default_factory=dict)     # id(node) -> Span (the tree lives as long)
    _literals: dict = field(default_factory=dict)  # id(node) -> the range between its quotes

    def pos(self, line: int, col_bytes: int) -> Pos:
        """ast's (1-based line, UTF-8 byte column) as a code-point position."""
        ln = line - 1
        if self._ascii is None:
            self._ascii = self.text.isascii()
        if self._ascii:
            return Pos(ln, col_bytes)
        t = self.index.line_text(ln)
        return Pos(ln, len(t.encode("utf-8")[:col_bytes].decode("utf-8", "replace")))

    def span(self, node) -> Span:
        k = id(node)
        sp = self._spans.get(k)
        if sp is None:
            sp = self._spans[k] = self._span(node)
        return sp

    def _span(self, node) -> Span:
        s = self.pos(getattr(node, "lineno", 1), getattr(node, "col_offset", 0))
        end_line = getattr(node, "end_lineno", None)
        if end_line is None:
            return Span(s, s)
        return Span(s, self.pos(end_line, getattr(node, "end_col_offset", 0) or 0))

    def where(self, node) -> Where:
        return (self.path, self.span(node))

    def literal_where(self, node: ast.Constant) -> Optional[Where]:
        """The range between the quotes of a plain one-line string literal (None otherwise)."""
        k = id(node)
        if k not in self._literals:
            self._literals[k] = self._literal_where(node)
        return self._literals[k]

    def _literal_where(self, node: ast.Constant) -> Optional[Where]:
        if getattr(node, "end_lineno", None) != node.lineno:
            return None
        sp = self.span(node)
        line = self.index.line_text(sp.start.line)
        seg = line[sp.start.col:sp.end.col]
        i = 0
        while i < len(seg) and seg[i] in "rRuUbB":
            i += 1
        for q in ('"""', "'''", '"', "'"):
            if seg.startswith(q, i) and seg.endswith(q) and len(seg) >= i + 2 * len(q):
                inner = seg[i + len(q):len(seg) - len(q)]
                if inner == node.value:
                    return (self.path, Span(Pos(sp.start.line, sp.start.col + i + len(q)),
                                            Pos(sp.start.line, sp.end.col - len(q))))
                return None
        return None


@dataclass(eq=False)
class Func:
    """A function of an interpreted module (``def`` or ``lambda``)."""
    name: str
    node: Any                  # ast.FunctionDef | ast.Lambda
    module: ModuleNS
    closure: Optional["Env"]
    defaults: list
    kw_defaults: list

    def __repr__(self) -> str:
        return f"Func({self.name})"


class Env:
    """A function's local names; ``parent``: the enclosing function's (closures)."""

    __slots__ = ("vars", "parent", "globals_decl", "nonlocal_decl", "module")

    def __init__(self, module: ModuleNS, parent: Optional["Env"] = None):
        self.vars: dict = {}
        self.parent = parent
        self.module = module
        self.globals_decl: set = set()
        self.nonlocal_decl: set = set()


@dataclass(eq=False)
class Sym:
    """A name from a module that is neither modelled nor in the workspace (``qual``: its
    dotted name as imported): using it gives an :class:`Unknown`."""
    qual: str

    def __repr__(self) -> str:
        return f"Sym({self.qual})"


@dataclass(eq=False)
class LClass:
    """A class of the launch API (``qual``: its full name in the table)."""
    qual: str
    name: str

    def __repr__(self) -> str:
        return f"LClass({self.name})"


class LObj:
    """An instance of a launch class, with its constructor's arguments by parameter name
    (``args``) and where it was made."""

    __slots__ = ("cls", "qual", "args", "where", "extra", "entity_key")

    def __init__(self, cls: str, qual: str, args: dict, where: Optional[Where]):
        self.cls = cls
        self.qual = qual
        self.args = args
        self.where = where
        self.extra: dict = {}
        self.entity_key = None

    def get(self, name: str, default=None):
        return self.args.get(name, default)

    def __repr__(self) -> str:
        return f"LObj({self.cls})"


@dataclass(eq=False)
class BoundMethod:
    obj: Any
    name: str
    where: Optional[Where] = None


@dataclass(eq=False)
class Builtin:
    """A builtin or library function the interpreter implements (``fn(interp, args, kwargs,
    where)``)."""
    name: str
    fn: Any

    def __repr__(self) -> str:
        return f"Builtin({self.name})"


class PathObj:
    """A ``pathlib.Path``."""

    __slots__ = ("path",)

    def __init__(self, path: str):
        # str(Path(...)) as pathlib spells it: no '.' parts, no doubled or trailing '/' (pure text)
        self.path = str(PurePosixPath(path))

    def __repr__(self) -> str:
        return f"PosixPath({self.path!r})"


class FileObj:
    """A file opened for reading (its text)."""

    __slots__ = ("text", "pos")

    def __init__(self, text: str):
        self.text = text
        self.pos = 0


class EnvMap:
    """``os.environ``."""


class SysPath:
    """``sys.path``: the folders the file adds (its other entries are the interpreter's)."""

    def __init__(self):
        self.added: list[str] = []


class LaunchCtx:
    """The ``LaunchContext`` an ``OpaqueFunction``'s function receives."""


class LCMap:
    """``context.launch_configurations``."""


class CtxEnvMap:
    """``context.environment``: the process's environment with the launch's SetEnvironmentVariable /
    UnsetEnvironmentVariable changes in scope."""


def is_unknown(v) -> bool:
    return isinstance(v, Unknown)


# the markers of the ROS 2 walker (values.py): a value it cannot compute, a package it cannot find
OPAQUE = "\x02"
UNRESOLVED = "\x01"


def marked(s) -> bool:
    """A string that holds a part tvl-lsp does not know (a package folder it cannot find...)."""
    return isinstance(s, str) and (OPAQUE in s or UNRESOLVED in s)


def type_name(v) -> str:
    if isinstance(v, LObj):
        return v.cls
    if isinstance(v, SStr):
        return "str"
    if isinstance(v, (Func, Builtin, BoundMethod)):
        return "function"
    if isinstance(v, PathObj):
        return "PosixPath"
    cls = getattr(v, "cls", None)
    if cls is not None and hasattr(cls, "mro"):
        return cls.name   # an instance of a class of the file
    return type(v).__name__
