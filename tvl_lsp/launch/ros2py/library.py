"""The library of the Python launch-file interpreter: conversions and operators beyond plain
data, the methods of strings, lists, dictionaries and paths, ``os.environ``, files and packages
(the builtins and library functions themselves are in :mod:`.pyfuncs`).

Nothing here runs the file's code or a program: ``exec`` / ``eval`` / ``compile`` /
``__import__`` are declined, ``subprocess`` and ``xacro`` give unknown values, files are read
(never written) through the host's bounded reader and only inside the workspace.
"""

from __future__ import annotations

import ast
import os
import posixpath
from typing import Optional

from ...base import yamlsafe
from .. import evalguard as guard
from .classes import BoundFunc, PyClass, PyInstance, SuperProxy
from .values import (SysPath, Builtin, BoundMethod, CtxEnvMap, Decline, EnvMap, FileObj, Func, LaunchCtx, LClass, LCMap, LObj, ModuleNS,
                     PathObj, PyError, Sym, Unknown, marked, type_name)

_PLAIN = (str, int, float, bool, type(None))


# ------------------------------------------------------------------ conversions

def to_str(interp, v, m: ModuleNS, n):
    """``str(v)``."""
    if isinstance(v, Unknown):
        return v
    if isinstance(v, str):
        return str(v)
    if isinstance(v, PathObj):
        return v.path
    if isinstance(v, bool) or v is None or isinstance(v, (int, float)):
        return str(v)
    if isinstance(v, (list, tuple, dict, set)):
        if interp_plain(v):
            s = str(v)
            if len(s) > guard.MAX_LEN * 10:
                raise Decline("a value too large to analyse", m.where(n))
            return s
        return Unknown(f"the text of a {type_name(v)} holding launch objects", m.where(n))
    if isinstance(v, LObj):
        return Unknown(f"str() of a {v.cls} is Python's text of the object, not its value (use it as a "
                       "substitution instead)", m.where(n))
    return Unknown(f"the text of a {type_name(v)}", m.where(n))


def interp_plain(v, depth: int = 0) -> bool:
    if depth > 30:
        return False
    if isinstance(v, _PLAIN):
        return not marked(v)
    if isinstance(v, (list, tuple, set, frozenset)):
        return all(interp_plain(x, depth + 1) for x in v)
    if isinstance(v, dict):
        return all(interp_plain(k, depth + 1) and interp_plain(x, depth + 1) for k, x in v.items())
    return False


def format_value(interp, v, conversion: int, spec, m: ModuleNS, n):
    if conversion == ord("r"):
        if interp_plain(v):
            return repr(v)
        return Unknown(f"repr() of a {type_name(v)}", m.where(n))
    s = to_str(interp, v, m, n) if not (spec and isinstance(v, (int, float))) else v
    if isinstance(s, Unknown):
        return s
    if spec:
        if len(str(spec)) > 20 or any(ch.isdigit() for ch in str(spec)) and int("".join(
                c for c in str(spec) if c.isdigit())[:6] or 0) > 10_000:
            raise Decline("a format width too large to analyse", m.where(n))
        try:
            return format(s, spec)
        except (ValueError, TypeError) as ex:
            raise PyError(type(ex).__name__, str(ex), m.where(n))
    return s


def percent_format(interp, a: str, b, m: ModuleNS, n):
    vals = b if isinstance(b, tuple) else (b,)
    for x in vals:
        if isinstance(x, Unknown):
            return x
        if not isinstance(x, _PLAIN + (list, tuple, dict)) or (isinstance(x, str) and marked(x) and False):
            if isinstance(x, PathObj):
                continue
            return Unknown(f"'%' formatting of a {type_name(x)}", m.where(n))
    if isinstance(b, dict) and not interp_plain(b):
        return Unknown("'%' formatting of a dictionary holding launch objects", m.where(n))
    if any(ch.isdigit() for ch in a) and len(a) < 2000:
        import re
        if re.search(r"%[-+ #0]*\d{5,}", a):
            raise Decline("a format width too large to analyse", m.where(n))
    try:
        b2 = tuple(x.path if isinstance(x, PathObj) else x for x in vals) if isinstance(b, tuple) else \
            (b.path if isinstance(b, PathObj) else b)
        return a % b2
    except (TypeError, ValueError, KeyError) as ex:
        raise PyError(type(ex).__name__, str(ex), m.where(n))


# ------------------------------------------------------------------ operators

_OBJECTS = (Func, Builtin, Sym, LClass, BoundMethod, PyClass, PyInstance, BoundFunc, SuperProxy, EnvMap, LaunchCtx,
            LCMap, FileObj, CtxEnvMap)

def binop_special(interp, op, a, b, m: ModuleNS, n):
    if isinstance(op, ast.Div) and isinstance(a, PathObj):
        if isinstance(b, PathObj):
            return PathObj(posixpath.join(a.path, b.path))
        if isinstance(b, str):
            return PathObj(posixpath.join(a.path, b))
        if isinstance(b, LObj):
            return Unknown("a pathlib path joined with a launch substitution", m.where(n))
    if isinstance(op, ast.Div) and isinstance(a, str) and isinstance(b, PathObj):
        return PathObj(posixpath.join(a, b.path))
    if isinstance(a, LObj) or isinstance(b, LObj):
        return interp.api.binop(interp, op, a, b, m, n)
    if isinstance(a, _OBJECTS) or isinstance(b, _OBJECTS):
        if isinstance(a, Sym) or isinstance(b, Sym):
            s = a if isinstance(a, Sym) else b
            return Unknown(f"{s.qual} is not modelled", m.where(n))
        return Unknown(f"an operation on a {type_name(a)} and a {type_name(b)}", m.where(n))
    if isinstance(op, ast.Add) and isinstance(a, list) and isinstance(b, list):
        if len(a) + len(b) > guard.MAX_LEN:
            raise Decline("a list too long to analyse", m.where(n))
        return a + b
    return NotImplemented


def subscript_special(interp, obj, key, m: ModuleNS, n):
    if isinstance(obj, EnvMap):
        if isinstance(key, Unknown):
            return key
        return environ_get(interp, key, None, m, n, required=True)
    if isinstance(obj, LCMap):
        return interp.host.launch_configuration(key, None, m, n, required=True)
    if isinstance(obj, CtxEnvMap):
        return interp.host.context_env(key, None, m, n, required=True)
    if isinstance(obj, LObj):
        return interp.api.subscript(interp, obj, key, m, n)
    return NotImplemented


def environ_contains(interp, container, item, m, n):
    if isinstance(container, EnvMap):
        v = environ_get(interp, item, None, m, n)
        if isinstance(v, Unknown):
            return v
        return v is not None
    if isinstance(container, LCMap):
        v = interp.host.launch_configuration(item, None, m, n, presence=True)
        return v
    if isinstance(container, CtxEnvMap):
        return interp.host.context_env(item, None, m, n, presence=True)
    return NotImplemented


def is_environ(obj) -> bool:
    return isinstance(obj, EnvMap)


def iterate_special(interp, v, m, n):
    if isinstance(v, FileObj):
        return v.text.splitlines(keepends=True)
    if isinstance(v, LObj):
        return interp.api.iterate(interp, v, m, n)
    if isinstance(v, Sym):
        raise Decline(f"this loop goes over {v.qual}, which tvl-lsp does not model", m.where(n))
    return NotImplemented


# ------------------------------------------------------------------ environment

def environ_get(interp, name, default, m: ModuleNS, n, required: bool = False):
    """``os.environ.get(name, default)`` / ``os.environ[name]``: the analysis environment's value
    where it decides (a concrete load, or a variable that is set); unknown otherwise."""
    if isinstance(name, Unknown):
        return name
    if not isinstance(name, str):
        raise PyError("TypeError", "str expected, not " + type_name(name), m.where(n))
    host = interp.host
    v = host.env.get(str(name))
    if v is not None:
        return v
    if host.concrete:
        if required:
            raise PyError("KeyError", repr(str(name)), m.where(n), sure=True)
        return default
    return Unknown(f"the environment variable {name} (not set here; it may be when launching)", m.where(n))


# ------------------------------------------------------------------ files and packages

def _path_arg(interp, v, m, n) -> Optional[str]:
    if isinstance(v, PathObj):
        return v.path
    if isinstance(v, str):
        return str(v)
    return None


def read_text(interp, path, m: ModuleNS, n):
    """The text of a file the launch file reads.  Reading a file that may not exist raises in
    Python: where tvl-lsp cannot read it (a path it cannot know, relative to the folder ros2 launch
    runs in, outside the workspace), the concrete load declines there; the symbolic analysis goes
    on with unknown content (the file may well be there on the machine that launches)."""
    try:
        return _read_text(interp, path, m, n)
    except Decline as d:
        if interp.host.concrete:
            raise
        return Unknown(d.reason, d.where)


def _read_text(interp, path, m: ModuleNS, n):
    p = _path_arg(interp, path, m, n)
    if p is None:
        why = path.reason if isinstance(path, Unknown) else f"a file named by a {type_name(path)}"
        raise Decline(f"the file reads a file tvl-lsp cannot know ({why})", m.where(n))
    if marked(p):
        raise Decline("the file reads a file of a package tvl-lsp cannot find", m.where(n))
    if not os.path.isabs(p):
        raise Decline(f"the file reads {p}, relative to the folder ros2 launch runs in", m.where(n))
    t = interp.host.read(p)
    if t is None:
        ex = interp.host.exists(p)
        if ex is False and interp.host.in_workspace(p):
            raise PyError("FileNotFoundError", f"[Errno 2] No such file or directory: '{p}'", m.where(n),
                          sure=True)
        raise Decline(f"the file reads {p}, which tvl-lsp cannot read (outside the workspace)", m.where(n))
    return t


def exists(interp, path, m, n, kind: str = "exists"):
    p = _path_arg(interp, path, m, n)
    if p is None:
        return path if isinstance(path, Unknown) else Unknown(f"a path given as a {type_name(path)}", m.where(n))
    if marked(p):
        return Unknown("a path in a package tvl-lsp cannot find", m.where(n))
    if not os.path.isabs(p):
        return Unknown(f"the path {p} relative to the folder ros2 launch runs in", m.where(n))
    r = interp.host.exists(p, kind)
    if r is None:
        return Unknown(f"whether {p} exists on the machine that launches", m.where(n))
    return r


def package_share(interp, args, kwargs, m, n, prefix: bool = False, as_path: bool = False):
    pkg = args[0] if args else kwargs.get("package_name")
    if isinstance(pkg, Unknown):
        return pkg
    if not isinstance(pkg, str):
        return Unknown(f"a package named by a {type_name(pkg)}", m.where(n))
    r = interp.host.package_dir(str(pkg), share=not prefix, where=m.where(n))
    if as_path and isinstance(r, str):
        return PathObj(r)
    return r


def yaml_load(interp, args, kwargs, m, n):
    src = args[0] if args else kwargs.get("stream")
    if isinstance(src, Unknown):
        return src
    if isinstance(src, FileObj):
        src = src.text[src.pos:]
        text = src
    elif isinstance(src, str):
        text = str(src)
    else:
        return Unknown(f"YAML read from a {type_name(src)}", m.where(n))
    if marked(text):
        return Unknown("YAML text tvl-lsp cannot know", m.where(n))
    try:
        return yamlsafe.safe_load(text)
    except Exception as ex:  # a YAML error, or beyond the bounds
        import yaml
        if isinstance(ex, yaml.YAMLError):
            raise PyError(type(ex).__name__, str(ex).splitlines()[0] if str(ex) else "", m.where(n))
        raise Decline("YAML too large or too deep to analyse", m.where(n))


def json_load(interp, args, kwargs, m, n):
    import json
    src = args[0] if args else None
    if isinstance(src, FileObj):
        src = src.text
    if not isinstance(src, str) or marked(src):
        return src if isinstance(src, Unknown) else Unknown("JSON of an unknown text", m.where(n))
    if len(src) > 5_000_000:
        raise Decline("JSON too large to analyse", m.where(n))
    try:
        return json.loads(src)
    except (ValueError, RecursionError) as ex:
        raise PyError("JSONDecodeError", str(ex), m.where(n))


def open_file(interp, args, kwargs, m, n):
    mode = args[1] if len(args) > 1 else kwargs.get("mode", "r")
    if isinstance(mode, Unknown) or not isinstance(mode, str) or any(c in mode for c in "wax+"):
        raise Decline("the file opens a file for writing: tvl-lsp never writes files", m.where(n))
    t = read_text(interp, args[0] if args else kwargs.get("file"), m, n)
    if isinstance(t, Unknown):
        return t   # (the symbolic analysis: a file of the machine that launches)
    return FileObj(t)


# ------------------------------------------------------------------ helpers

def _unknown_in(args, kwargs=None):
    for x in list(args) + list((kwargs or {}).values()):
        if isinstance(x, Unknown):
            return x
    return None


def _plain_items(interp, items, m, n, what):
    for x in items:
        if isinstance(x, Unknown):
            return x
        if not isinstance(x, _PLAIN + (tuple, list)) or (isinstance(x, str) and marked(x)):
            return Unknown(f"{what} of {type_name(x)} values", m.where(n))
    return None


def _strs(interp, args, m, n, what):
    out = []
    for a in args:
        if isinstance(a, Unknown):
            return a
        if isinstance(a, PathObj):
            out.append(a.path)
        elif isinstance(a, str):
            out.append(str(a))
        elif isinstance(a, LObj):
            return Unknown(f"{what}() of a {a.cls} (a substitution is performed when launching; use "
                           "PathJoinSubstitution)", m.where(n))
        else:
            raise PyError("TypeError", f"{what}() argument must be str, bytes, or os.PathLike object, not "
                          f"'{type_name(a)}'", m.where(n))
    return out


# ------------------------------------------------------------------ attributes and methods

_STR_METHODS = {"lower", "upper", "strip", "lstrip", "rstrip", "split", "rsplit", "replace", "join", "format",
                "startswith", "endswith", "find", "rfind", "count", "isdigit", "isalpha", "isalnum", "isnumeric",
                "title", "capitalize", "splitlines", "partition", "rpartition", "zfill", "removeprefix",
                "removesuffix", "casefold", "index", "rindex", "center", "ljust", "rjust", "islower", "isupper",
                "isspace", "swapcase", "encode", "format_map", "expandtabs", "isidentifier", "isdecimal"}
_STR_ASK = {"startswith", "endswith", "find", "rfind", "count", "isdigit", "isalpha", "isalnum", "isnumeric",
            "index", "rindex", "islower", "isupper", "isspace", "split", "rsplit", "partition", "rpartition",
            "isidentifier", "isdecimal", "splitlines"}
_LIST_METHODS = {"append", "extend", "insert", "pop", "remove", "index", "count", "copy", "sort", "reverse", "clear"}
_DICT_METHODS = {"get", "items", "keys", "values", "update", "setdefault", "pop", "copy", "clear", "popitem"}
_SET_METHODS = {"add", "update", "union", "discard", "remove", "intersection", "difference", "copy", "issubset",
                "issuperset", "pop", "clear"}
_PATH_ATTRS = {"parent", "name", "stem", "suffix", "parts", "anchor"}
_PATH_METHODS = {"joinpath", "exists", "is_file", "is_dir", "read_text", "open", "resolve", "absolute",
                 "with_suffix", "with_name", "as_posix", "expanduser", "is_absolute", "relative_to", "glob",
                 "iterdir", "rglob"}


def attribute(interp, obj, name: str, m: ModuleNS, n, importing: bool):
    if isinstance(obj, str):
        if name in _STR_METHODS:
            return BoundMethod(obj, name, m.where(n))
        raise PyError("AttributeError", f"'str' object has no attribute '{name}'", m.where(n))
    if isinstance(obj, list) and name in _LIST_METHODS or isinstance(obj, dict) and name in _DICT_METHODS or \
            isinstance(obj, (set, frozenset)) and name in _SET_METHODS:
        return BoundMethod(obj, name, m.where(n))
    if isinstance(obj, (list, dict, set, tuple, int, float, bool, type(None))):
        if isinstance(obj, tuple) and name in ("index", "count"):
            return BoundMethod(obj, name, m.where(n))
        raise PyError("AttributeError", f"'{type_name(obj)}' object has no attribute '{name}'", m.where(n),
                      sure=obj is None)
    if isinstance(obj, PathObj):
        p = obj.path
        if name in _PATH_ATTRS:
            if marked(p) and name in ("name", "stem", "suffix"):
                pass
            return {"parent": lambda: PathObj(posixpath.dirname(p.rstrip("/")) or "/"),
                    "name": lambda: posixpath.basename(p), "stem": lambda: posixpath.splitext(posixpath.basename(p))[0],
                    "suffix": lambda: posixpath.splitext(p)[1], "parts": lambda: tuple(x for x in p.split("/") if x),
                    "anchor": lambda: "/" if p.startswith("/") else ""}[name]()
        if name in _PATH_METHODS:
            return BoundMethod(obj, name, m.where(n))
        raise PyError("AttributeError", f"'PosixPath' object has no attribute '{name}'", m.where(n))
    if isinstance(obj, FileObj):
        if name in ("read", "readlines", "close", "readline"):
            return BoundMethod(obj, name, m.where(n))
        return Unknown(f"file.{name}", m.where(n))
    if isinstance(obj, SysPath):
        if name in ("insert", "append", "extend", "remove"):
            return BoundMethod(obj, name, m.where(n))
        return Unknown(f"sys.path.{name}", m.where(n))
    if isinstance(obj, EnvMap):
        if name in ("get", "copy", "keys", "items", "values", "update", "setdefault"):
            return BoundMethod(obj, name, m.where(n))
        return Unknown(f"os.environ.{name}", m.where(n))
    if isinstance(obj, LaunchCtx):
        if name == "launch_configurations":
            return LCMap()
        if name == "environment":
            return CtxEnvMap()
        if name in ("perform_substitution",):
            return BoundMethod(obj, name, m.where(n))
        return Unknown(f"context.{name} (the launch context at run time)", m.where(n))
    if isinstance(obj, LCMap):
        if name in ("get", "keys", "items", "copy", "values"):
            return BoundMethod(obj, name, m.where(n))
        return Unknown(f"launch_configurations.{name}", m.where(n))
    if isinstance(obj, CtxEnvMap):
        if name == "get":
            return BoundMethod(obj, name, m.where(n))
        return Unknown(f"context.environment.{name}", m.where(n))
    if isinstance(obj, LObj):
        return interp.api.attribute(interp, obj, name, m, n)
    if isinstance(obj, LClass):
        return Unknown(f"{obj.name}.{name} is not modelled", m.where(n))
    if isinstance(obj, (Func, Builtin, BoundMethod, PyClass)):
        if name == "__name__" and isinstance(obj, Func):
            return obj.name
        return Unknown(f"an attribute of a {type_name(obj)}", m.where(n))
    return Unknown(f"the attribute {name} of a {type_name(obj)}", m.where(n))


def call_method(interp, bm: BoundMethod, args, kwargs, m, n):
    obj, name = bm.obj, bm.name
    try:
        if isinstance(obj, str):
            return _str_method(interp, obj, name, args, kwargs, m, n)
        if isinstance(obj, list):
            return _list_method(interp, obj, name, args, kwargs, m, n)
        if isinstance(obj, dict):
            return _dict_method(interp, obj, name, args, kwargs, m, n)
        if isinstance(obj, (set, frozenset)):
            u = _unknown_in(args)
            if u is not None:
                return u
            fn = getattr(obj, name)
            r = fn(*[interp.iterate(a, m, n) if name in ("update", "union", "intersection", "difference",
                                                         "issubset", "issuperset") else a for a in args])
            return r
        if isinstance(obj, tuple):
            return getattr(obj, name)(*args)
        if isinstance(obj, PathObj):
            return _path_method(interp, obj, name, args, kwargs, m, n)
        if isinstance(obj, FileObj):
            if name == "read":
                t = obj.text[obj.pos:]
                obj.pos = len(obj.text)
                return t
            if name == "readlines":
                t = obj.text[obj.pos:]
                obj.pos = len(obj.text)
                return t.splitlines(keepends=True)
            if name == "readline":
                i = obj.text.find("\n", obj.pos)
                j = len(obj.text) if i < 0 else i + 1
                t = obj.text[obj.pos:j]
                obj.pos = j
                return t
            return None
        if isinstance(obj, SysPath):
            items = [args[-1]] if name in ("insert", "append") else interp.iterate(args[0], m, n) \
                if name == "extend" else []
            for x in items:
                p = x.path if isinstance(x, PathObj) else str(x) if isinstance(x, str) and not marked(x) else None
                if p is not None and p not in obj.added:
                    obj.added.append(p)
            return None
        if isinstance(obj, EnvMap):
            if name == "get":
                return environ_get(interp, args[0] if args else kwargs.get("key"),
                                   args[1] if len(args) > 1 else kwargs.get("default"), m, n)
            if name == "update":
                src = args[0] if args else {}
                if not isinstance(src, dict):
                    raise Decline("os.environ updated with values tvl-lsp cannot know", m.where(n))
                for k, v in list(src.items()) + list(kwargs.items()):
                    interp.host.set_env(k, v, m, n)
                return None
            if name == "setdefault":
                cur = environ_get(interp, args[0], None, m, n)
                if isinstance(cur, Unknown):
                    return cur
                if cur is None:
                    interp.host.set_env(args[0], args[1] if len(args) > 1 else "", m, n)
                    return args[1] if len(args) > 1 else ""
                return cur
            return Unknown(f"os.environ.{name}() (the whole environment of the machine that launches)", m.where(n))
        if isinstance(obj, LCMap):
            if name == "get":
                return interp.host.launch_configuration(args[0] if args else None,
                                                        args[1] if len(args) > 1 else None, m, n)
            return Unknown(f"launch_configurations.{name}() (every launch configuration)", m.where(n))
        if isinstance(obj, CtxEnvMap) and name == "get":
            return interp.host.context_env(args[0] if args else kwargs.get("key"),
                                           args[1] if len(args) > 1 else kwargs.get("default"), m, n)
        if isinstance(obj, LaunchCtx) and name == "perform_substitution":
            return interp.host.perform(obj, args[0] if args else None, m, n)
        if isinstance(obj, LObj):
            return interp.api.call_method(interp, obj, name, args, kwargs, m, n)
    except (IndexError, KeyError, ValueError, TypeError, AttributeError) as ex:
        raise PyError(type(ex).__name__, str(ex).strip("'") if isinstance(ex, KeyError) else str(ex), m.where(n))
    return Unknown(f"{type_name(obj)}.{name}()", m.where(n))


def _str_method(interp, s: str, name, args, kwargs, m, n):
    s = str(s)
    u = _unknown_in(args, kwargs)
    if u is not None:
        return u
    if marked(s) and name in _STR_ASK:
        return Unknown("a path in a package tvl-lsp cannot find", m.where(n))
    if name == "join":
        items = interp.iterate(args[0], m, n)
        out = []
        for x in items:
            if isinstance(x, Unknown):
                return x
            if not isinstance(x, str):
                if isinstance(x, LObj):
                    return Unknown(f"str.join() of a {x.cls} (a substitution)", m.where(n))
                raise PyError("TypeError", f"sequence item: expected str instance, {type_name(x)} found", m.where(n))
            out.append(str(x))
        r = s.join(out)
        if len(r) > guard.MAX_LEN * 10:
            raise Decline("a value too large to analyse", m.where(n))
        return r
    if name in ("format", "format_map"):
        vals = list(args) + list(kwargs.values())
        if name == "format_map":
            vals = list(args[0].values()) if isinstance(args[0], dict) else [args[0]]
        for v in vals:
            if isinstance(v, Unknown):
                return v
            if isinstance(v, LObj):
                return Unknown(f"str.format() of a {v.cls} gives Python's text of the object", m.where(n))
        fa = [a.path if isinstance(a, PathObj) else a for a in args]
        fk = {k: (v.path if isinstance(v, PathObj) else v) for k, v in kwargs.items()}
        import re
        if re.search(r"\{[^{}]*:[^{}]*\d{5,}", s):
            raise Decline("a format width too large to analyse", m.where(n))
        if not all(interp_plain(v) for v in list(fa) + list(fk.values())):
            return Unknown("str.format() of values tvl-lsp cannot write out", m.where(n))
        try:
            r = s.format(*fa, **fk) if name == "format" else s.format_map(args[0])
        except (IndexError, KeyError, ValueError, AttributeError) as ex:
            raise PyError(type(ex).__name__, str(ex), m.where(n))
        return r
    if name == "replace" and len(args) >= 2 and isinstance(args[1], str):
        if len(args[1]) > 1 and s.count(str(args[0]) or " ") * len(args[1]) > guard.MAX_LEN * 10:
            raise Decline("a value too large to analyse", m.where(n))
    if name in ("center", "ljust", "rjust", "zfill") and args and isinstance(args[0], int) and args[0] > guard.MAX_LEN:
        raise Decline("a value too large to analyse", m.where(n))
    if name == "encode":
        return Unknown("bytes", m.where(n))
    fn = getattr(s, name)
    return fn(*[str(a) if isinstance(a, str) else a for a in args], **kwargs)


def _list_method(interp, lst: list, name, args, kwargs, m, n):
    if name == "append":
        if len(lst) >= guard.MAX_LEN:
            raise Decline("a list too long to analyse", m.where(n))
        lst.append(args[0])
        return None
    if name == "extend":
        items = interp.iterate(args[0], m, n)
        if len(lst) + len(items) > guard.MAX_LEN:
            raise Decline("a list too long to analyse", m.where(n))
        lst.extend(items)
        return None
    if name == "insert":
        lst.insert(args[0], args[1])
        return None
    if name in ("index", "count", "remove"):
        if any(isinstance(x, Unknown) for x in lst) or _unknown_in(args):
            return Unknown(f"list.{name}() over values tvl-lsp cannot know", m.where(n))
        return getattr(lst, name)(*args)
    if name == "sort":
        u = _plain_items(interp, lst, m, n, "sorting")
        if u is not None:
            raise Decline("sorting values tvl-lsp cannot know", m.where(n))
        key = kwargs.get("key")
        if key is not None:
            keyed = [(interp.call(key, [x], {}, m, n), x) for x in lst]
            keyed.sort(key=lambda t: t[0], reverse=bool(kwargs.get("reverse", False)))
            lst[:] = [x for _, x in keyed]
        else:
            lst.sort(reverse=bool(kwargs.get("reverse", False)))
        return None
    return getattr(lst, name)(*args)


def _dict_method(interp, d: dict, name, args, kwargs, m, n):
    if name in ("get", "pop", "setdefault"):
        if args and isinstance(args[0], Unknown):
            return args[0]
        if name == "get":
            return d.get(args[0], args[1] if len(args) > 1 else kwargs.get("default"))
    if name == "items":
        return list(d.items())
    if name == "keys":
        return list(d.keys())
    if name == "values":
        return list(d.values())
    if name == "update":
        if args:
            src = args[0]
            if isinstance(src, Unknown):
                raise Decline(f"a dictionary updated with values tvl-lsp cannot know ({src.reason})", m.where(n))
            if isinstance(src, dict):
                d.update(src)
            else:
                for item in interp.iterate(src, m, n):
                    k, v = interp.iterate(item, m, n)
                    d[k] = v
        d.update(kwargs)
        return None
    return getattr(d, name)(*args)


def _path_method(interp, p: PathObj, name, args, kwargs, m, n):
    if name == "joinpath":
        s = _strs(interp, args, m, n, "joinpath")
        if isinstance(s, Unknown):
            return s
        return PathObj(posixpath.join(p.path, *s))
    if name in ("exists", "is_file", "is_dir"):
        return exists(interp, p, m, n, {"exists": "exists", "is_file": "file", "is_dir": "dir"}[name])
    if name == "read_text":
        return read_text(interp, p, m, n)
    if name == "open":
        return open_file(interp, [p] + list(args), kwargs, m, n)
    if name in ("resolve", "absolute", "expanduser"):
        if not posixpath.isabs(p.path):
            return Unknown(f"the path {p.path} relative to the folder ros2 launch runs in", m.where(n))
        return PathObj(posixpath.normpath(p.path))
    if name == "with_suffix":
        return PathObj(posixpath.splitext(p.path)[0] + str(args[0]))
    if name == "with_name":
        return PathObj(posixpath.join(posixpath.dirname(p.path), str(args[0])))
    if name == "as_posix":
        return p.path
    if name == "is_absolute":
        return posixpath.isabs(p.path)
    if name == "relative_to":
        s = _strs(interp, args, m, n, "relative_to")
        if isinstance(s, Unknown):
            return s
        return PathObj(posixpath.relpath(p.path, s[0]))
    return Unknown(f"Path.{name}() (a listing of the machine's files)", m.where(n))


__all__ = ["attribute", "call_method", "to_str", "format_value", "percent_format", "binop_special",
           "subscript_special", "environ_contains", "iterate_special", "is_environ", "interp_plain", "environ_get",
           "read_text", "exists", "package_share", "yaml_load", "json_load", "open_file"]
