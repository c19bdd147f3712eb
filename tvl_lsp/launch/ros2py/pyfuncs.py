"""The builtins and library functions of the Python launch-file interpreter (``len``,
``sorted``, ``os.path.join``, ``os.environ.get``, ``get_package_share_directory``,
``yaml.safe_load``, ``pathlib.Path`` ...), and how dotted library names resolve: a launch class
of the modelled version (:mod:`.apitable`), a function implemented here, or an unmodelled
:class:`~.values.Sym`.  ``exec`` / ``eval`` / ``compile`` / ``__import__`` are declined;
``subprocess`` / ``xacro`` / machine queries give unknown values; nothing is ever run.
"""

from __future__ import annotations

import copy
import math
import posixpath
import sys
from typing import Optional

from .. import evalguard as guard
from . import apitable
from .classes import PyClass, is_instance
from .library import (_plain_items, _strs, _unknown_in, environ_get, exists, interp_plain, json_load, open_file,
                      package_share, to_str, yaml_load)
from .values import (BoundMethod, Builtin, Decline, EnvMap, Func, LClass, LObj, ModuleNS, PathObj, PyError, Sym, Unknown, marked,
                     type_name)

_PLAIN = (str, int, float, bool, type(None))

# ------------------------------------------------------------------ imports and names

LAUNCH_PACKAGES = ("launch", "launch_ros", "launch_xml", "launch_yaml", "ament_index_python")


# what ros2 launch's Python has besides the standard library: the launch packages and their
# dependencies, xacro (commonly pip-installed beside them) and the ROS client library's modules
# launch_ros itself imports (rclpy, lifecycle_msgs, composition_interfaces)
INSTALLED = {"launch", "launch_ros", "launch_xml", "launch_yaml", "ament_index_python", "yaml", "lark", "packaging",
             "osrf_pycommon", "xacro", "pkg_resources", "setuptools"}
ROS_STUBS = {"rclpy", "rclpy.executors", "rclpy.logging", "rclpy.parameter", "rclpy.exceptions",
             "rclpy.validate_namespace", "rclpy.validate_node_name", "lifecycle_msgs", "lifecycle_msgs.msg",
             "lifecycle_msgs.srv", "composition_interfaces", "composition_interfaces.srv"}


def check_import(name: str, m: ModuleNS, node, concrete: bool = False) -> None:
    """``import name`` of a library module: the launch packages' modules must exist in the
    modelled version (a newer module is declined, not guessed).  The concrete load (what
    ``ros2 launch`` does with this file, compared with the real one) also declines a module that is
    neither the standard library nor the launch packages (nor the workspace's, put on
    ``sys.path`` by the file): launch would fail to import it unless it is installed, and what it
    does is unknown here.  The symbolic analysis goes on with unknown values instead."""
    top = name.split(".", 1)[0]
    if concrete and top not in INSTALLED and name not in ROS_STUBS and top not in sys.stdlib_module_names:
        raise Decline(f"the file imports {name}, a Python module that is neither part of ros2/launch nor a "
                      "module of the workspace on the file's sys.path: what it does is not known (ros2 launch "
                      "needs it installed)", m.where(node))
    if top in LAUNCH_PACKAGES and name not in apitable.EXPORTS and name.count(".") <= 1:
        parent = name.rsplit(".", 1)[0]
        exp = apitable.EXPORTS.get(parent)
        if exp is not None and exp.get(name.rsplit(".", 1)[-1]) != "module":
            raise Decline(f"tvl-lsp models launch 3.7.1 / launch_ros 0.28, which have no module {name}",
                          m.where(node))


def resolve(interp, qual: str, m: ModuleNS, node, importing: bool):
    """The value of a dotted library name."""
    f = FUNCS.get(qual)
    if f is not None:
        return f
    mod, _, name = qual.rpartition(".")
    exp = apitable.EXPORTS.get(mod)
    if exp is not None:
        kind = exp.get(name)
        if kind is None:
            what = "import" if importing else "use"
            why = f"tvl-lsp models launch 3.7.1 / launch_ros 0.28, where {mod} has no {name}"
            if interp.host.concrete:   # ros2 launch of that version fails on it
                raise Decline(f"{why} (cannot {what} it)", m.where(node))
            return Unknown(f"{name} of a newer launch ({why})", m.where(node))   # the symbolic analysis goes on
        if kind in apitable.CLASSES:
            return LClass(kind, name)
        if kind == "function":
            f = FUNCS.get(f"{mod}.{name}") or FUNCS.get(_ALIASES.get(name, ""))
            if f is not None:
                return f
            return Sym(qual)
        return Sym(qual)
    if qual in CONSTANTS:
        return CONSTANTS[qual](interp)
    if qual.split(".", 1)[0] in LAUNCH_PACKAGES and qual in apitable.CLASSES:
        return LClass(qual, name)   # imported from the module that defines it
    return Sym(qual)


_ALIASES = {"perform_substitutions": "launch.utilities.perform_substitutions",
            "get_package_share_directory": "ament_index_python.packages.get_package_share_directory",
            "get_package_prefix": "ament_index_python.packages.get_package_prefix",
            "get_package_share_path": "ament_index_python.packages.get_package_share_path"}



# ------------------------------------------------------------------ builtins

def _b(name):
    def deco(fn):
        BUILTINS[name] = Builtin(name, fn)
        return fn
    return deco


BUILTINS: dict[str, Builtin] = {}
FUNCS: dict[str, Builtin] = {}
CONSTANTS: dict = {}


def builtin(name: str) -> Optional[Builtin]:
    return BUILTINS.get(name)


@_b("len")
def _len(interp, args, kwargs, m, n):
    v = args[0] if args else None
    if isinstance(v, Unknown):
        return v
    if isinstance(v, (str, list, tuple, dict, set, frozenset, range)):
        if isinstance(v, str) and marked(v):
            return Unknown("the length of a path tvl-lsp cannot know", m.where(n))
        return len(v)
    raise PyError("TypeError", f"object of type '{type_name(v)}' has no len()", m.where(n))


@_b("str")
def _str(interp, args, kwargs, m, n):
    if not args:
        return ""
    return to_str(interp, args[0], m, n)


def _num(kind):
    def fn(interp, args, kwargs, m, n):
        if not args:
            return kind()
        v = args[0]
        if isinstance(v, Unknown):
            return v
        if isinstance(v, str) and marked(v):
            return Unknown("a number from a path tvl-lsp cannot know", m.where(n))
        if not isinstance(v, (str, int, float, bool)):
            return Unknown(f"{kind.__name__}() of a {type_name(v)}", m.where(n))
        try:
            if kind is int and len(args) > 1:
                return int(v, args[1])
            if isinstance(v, str) and len(v) > 4000:
                raise Decline("a number too long to analyse", m.where(n))
            return kind(v)
        except (ValueError, TypeError) as ex:
            raise PyError(type(ex).__name__, str(ex), m.where(n))
    return fn


BUILTINS["int"] = Builtin("int", _num(int))
BUILTINS["float"] = Builtin("float", _num(float))


@_b("bool")
def _bool(interp, args, kwargs, m, n):
    if not args:
        return False
    v = args[0]
    if isinstance(v, Unknown):
        return v
    return interp.truth(v, m, n, "value")


def _container(kind):
    def fn(interp, args, kwargs, m, n):
        if kind is dict:
            out = {}
            if args:
                src = args[0]
                if isinstance(src, Unknown):
                    return src
                if isinstance(src, dict):
                    out.update(src)
                else:
                    for item in interp.iterate(src, m, n):
                        pair = interp.iterate(item, m, n)
                        if len(pair) != 2:
                            raise PyError("ValueError", "dictionary update sequence element has wrong length",
                                          m.where(n))
                        if isinstance(pair[0], Unknown):
                            return pair[0]
                        out[pair[0]] = pair[1]
            out.update(kwargs)
            return out
        if not args:
            return kind()
        items = interp.iterate(args[0], m, n)
        try:
            return kind(items)
        except TypeError as ex:
            raise PyError("TypeError", str(ex), m.where(n))
    return fn


for _k in (list, tuple, set, frozenset, dict):
    BUILTINS[_k.__name__] = Builtin(_k.__name__, _container(_k))


@_b("range")
def _range(interp, args, kwargs, m, n):
    u = _unknown_in(args)
    if u is not None:
        return u
    if not all(isinstance(a, int) for a in args):
        raise PyError("TypeError", "range() integer arguments expected", m.where(n))
    try:
        guard.check_call(range, list(args))
        return range(*args)
    except guard.TooBig:
        raise Decline("a range too long to analyse", m.where(n))
    except (ValueError, TypeError) as ex:
        raise PyError(type(ex).__name__, str(ex), m.where(n))


@_b("enumerate")
def _enumerate(interp, args, kwargs, m, n):
    start = args[1] if len(args) > 1 else kwargs.get("start", 0)
    return [(i + start, x) for i, x in enumerate(interp.iterate(args[0], m, n))]


@_b("zip")
def _zip(interp, args, kwargs, m, n):
    seqs = [interp.iterate(a, m, n) for a in args]
    return [tuple(t) for t in zip(*seqs)]


@_b("reversed")
def _reversed(interp, args, kwargs, m, n):
    return list(reversed(interp.iterate(args[0], m, n)))


@_b("sorted")
def _sorted(interp, args, kwargs, m, n):
    items = interp.iterate(args[0], m, n)
    u = _plain_items(interp, items, m, n, "sorting")
    if u is not None:
        return u
    key = kwargs.get("key")
    try:
        if key is not None:
            keyed = [(interp.call(key, [x], {}, m, n), x) for x in items]
            u = _plain_items(interp, [k for k, _ in keyed], m, n, "sorting")
            if u is not None:
                return u
            keyed.sort(key=lambda t: t[0], reverse=bool(kwargs.get("reverse", False)))
            return [x for _, x in keyed]
        return sorted(items, reverse=bool(kwargs.get("reverse", False)))
    except TypeError as ex:
        raise PyError("TypeError", str(ex), m.where(n))


def _minmax(fn):
    def f(interp, args, kwargs, m, n):
        items = interp.iterate(args[0], m, n) if len(args) == 1 else list(args)
        u = _plain_items(interp, items, m, n, fn.__name__ + "()")
        if u is not None:
            return u
        try:
            if not items and "default" in kwargs:
                return kwargs["default"]
            return fn(items)
        except (TypeError, ValueError) as ex:
            raise PyError(type(ex).__name__, str(ex), m.where(n))
    return f


BUILTINS["min"] = Builtin("min", _minmax(min))
BUILTINS["max"] = Builtin("max", _minmax(max))


@_b("sum")
def _sum(interp, args, kwargs, m, n):
    items = interp.iterate(args[0], m, n)
    u = _plain_items(interp, items, m, n, "sum()")
    if u is not None:
        return u
    try:
        return sum(items, args[1] if len(args) > 1 else 0)
    except TypeError as ex:
        raise PyError("TypeError", str(ex), m.where(n))


def _anyall(fn):
    def f(interp, args, kwargs, m, n):
        items = interp.iterate(args[0], m, n)
        out = []
        for x in items:
            if isinstance(x, Unknown):
                return x
            out.append(interp.truth(x, m, n, "value"))
        return fn(out)
    return f


BUILTINS["any"] = Builtin("any", _anyall(any))
BUILTINS["all"] = Builtin("all", _anyall(all))


@_b("abs")
def _abs(interp, args, kwargs, m, n):
    v = args[0]
    if isinstance(v, (int, float)):
        return abs(v)
    return v if isinstance(v, Unknown) else Unknown("abs() of a " + type_name(v), m.where(n))


@_b("round")
def _round(interp, args, kwargs, m, n):
    u = _unknown_in(args)
    if u is not None:
        return u
    if isinstance(args[0], (int, float)):
        return round(*args)
    raise PyError("TypeError", "type doesn't define __round__", m.where(n))


@_b("print")
def _print(interp, args, kwargs, m, n):
    return None


@_b("repr")
def _repr(interp, args, kwargs, m, n):
    if interp_plain(args[0]):
        return repr(args[0])
    return Unknown("repr() of a " + type_name(args[0]), m.where(n))


_TYPES = {"str": str, "int": int, "float": float, "bool": bool, "list": list, "tuple": tuple, "dict": dict,
          "set": set, "frozenset": frozenset}


@_b("isinstance")
def _isinstance(interp, args, kwargs, m, n):
    v, t = args[0], args[1]
    if isinstance(v, Unknown):
        return v
    ts = list(t) if isinstance(t, tuple) else [t]
    for x in ts:
        if isinstance(x, Builtin) and x.name in _TYPES:
            if isinstance(v, LObj) or isinstance(v, (Func, PathObj)):
                continue
            if isinstance(v, _TYPES[x.name]) and not (x.name == "int" and isinstance(v, bool) and False):
                return True
            continue
        if isinstance(x, LClass) and isinstance(v, LObj):
            if v.qual == x.qual or x.name in apitable.CLASSES.get(v.qual, {}).get("bases", []):
                return True
            continue
        if isinstance(x, LClass):
            continue
        if isinstance(x, PyClass):
            if is_instance(v, x):
                return True
            continue
        return Unknown("isinstance() with a type tvl-lsp does not model", m.where(n))
    return False


@_b("map")
def _map(interp, args, kwargs, m, n):
    f = args[0]
    seqs = [interp.iterate(a, m, n) for a in args[1:]]
    return [interp.call(f, list(t), {}, m, n) for t in zip(*seqs)]


@_b("filter")
def _filter(interp, args, kwargs, m, n):
    f = args[0]
    out = []
    for x in interp.iterate(args[1], m, n):
        keep = x if f is None else interp.call(f, [x], {}, m, n)
        if interp.truth(keep, m, n, "filter"):
            out.append(x)
    return out


@_b("getattr")
def _getattr(interp, args, kwargs, m, n):
    name = args[1]
    if not isinstance(name, str):
        return name if isinstance(name, Unknown) else Unknown("getattr() with a computed name", m.where(n))
    try:
        return interp.attr_of(args[0], str(name), m, n)
    except PyError:
        if len(args) > 2:
            return args[2]
        raise


@_b("hasattr")
def _hasattr(interp, args, kwargs, m, n):
    try:
        v = _getattr(interp, args[:2], {}, m, n)
    except PyError:
        return False
    return v if isinstance(v, Unknown) else True


@_b("open")
def _open(interp, args, kwargs, m, n):
    return open_file(interp, args, kwargs, m, n)


@_b("type")
def _type(interp, args, kwargs, m, n):
    v = args[0]
    if isinstance(v, _PLAIN + (list, tuple, dict, set)) and type(v).__name__ in _TYPES:
        return BUILTINS[type(v).__name__ if not isinstance(v, str) else "str"]
    return Unknown("type() of a " + type_name(v), m.where(n))


@_b("super")
def _super(interp, args, kwargs, m, n):
    return Unknown("classes defined in Python are not modelled", m.where(n))


def _declined(name):
    def fn(interp, args, kwargs, m, n):
        raise Decline(f"{name}() runs code tvl-lsp does not run", m.where(n))
    return fn


for _name in ("exec", "eval", "compile", "__import__", "globals", "locals", "vars", "input", "breakpoint", "exit",
              "quit", "setattr", "delattr", "memoryview", "help"):
    BUILTINS[_name] = Builtin(_name, _declined(_name))


def _exception(kind):
    def fn(interp, args, kwargs, m, n):
        msg = args[0] if args else ""
        return ("__exc__", (kind, str(msg) if isinstance(msg, str) else ""))
    return fn


for _name in ("Exception", "BaseException", "ValueError", "KeyError", "IndexError", "TypeError", "RuntimeError",
              "FileNotFoundError", "OSError", "IOError", "ImportError", "ModuleNotFoundError", "AttributeError",
              "NameError", "LookupError", "AssertionError", "NotImplementedError", "EnvironmentError",
              "ArithmeticError", "ZeroDivisionError", "StopIteration", "SystemExit", "KeyboardInterrupt",
              "PermissionError", "UnicodeDecodeError"):
    BUILTINS[_name] = Builtin(_name, _exception(_name))


@_b("chr")
def _chr(interp, args, kwargs, m, n):
    return chr(args[0]) if isinstance(args[0], int) else Unknown("chr()", m.where(n))


@_b("ord")
def _ord(interp, args, kwargs, m, n):
    return ord(args[0]) if isinstance(args[0], str) and len(args[0]) == 1 else Unknown("ord()", m.where(n))


@_b("iter")
def _iter(interp, args, kwargs, m, n):
    return interp.iterate(args[0], m, n)


@_b("next")
def _next(interp, args, kwargs, m, n):
    items = interp.iterate(args[0], m, n)
    if items:
        return items[0]
    if len(args) > 1:
        return args[1]
    raise PyError("StopIteration", "", m.where(n))


@_b("callable")
def _callable(interp, args, kwargs, m, n):
    return isinstance(args[0], (Func, Builtin, LClass, BoundMethod))


# ------------------------------------------------------------------ library functions

def _f(qual, *aliases):
    def deco(fn):
        b = Builtin(qual, fn)
        FUNCS[qual] = b
        for a in aliases:
            FUNCS[a] = b
        return fn
    return deco


@_f("os.path.join", "posixpath.join")
def _join(interp, args, kwargs, m, n):
    s = _strs(interp, args, m, n, "os.path.join")
    if isinstance(s, Unknown):
        return s
    if not s:
        raise PyError("TypeError", "join() missing 1 required positional argument: 'a'", m.where(n))
    return posixpath.join(*s)


def _path1(fn, name):
    def f(interp, args, kwargs, m, n):
        s = _strs(interp, args[:1], m, n, name)
        if isinstance(s, Unknown):
            return s
        return fn(s[0])
    return f


for _name, _fn in (("dirname", posixpath.dirname), ("basename", posixpath.basename), ("normpath", posixpath.normpath),
                   ("isabs", posixpath.isabs), ("splitext", posixpath.splitext), ("split", posixpath.split)):
    FUNCS[f"os.path.{_name}"] = Builtin(_name, _path1(_fn, _name))


def _abspath(interp, args, kwargs, m, n):
    s = _strs(interp, args[:1], m, n, "abspath")
    if isinstance(s, Unknown):
        return s
    if not posixpath.isabs(s[0]):
        return Unknown(f"the path {s[0]} relative to the folder ros2 launch runs in", m.where(n))
    return posixpath.normpath(s[0])


FUNCS["os.path.abspath"] = Builtin("abspath", _abspath)
FUNCS["os.path.realpath"] = Builtin("realpath", _abspath)


@_f("os.path.expanduser")
def _expanduser(interp, args, kwargs, m, n):
    s = _strs(interp, args[:1], m, n, "expanduser")
    if isinstance(s, Unknown):
        return s
    if not s[0].startswith("~"):
        return s[0]
    home = interp.host.env.get("HOME")
    if home is None or not interp.host.concrete:
        return Unknown("the home folder of the user who launches", m.where(n))
    return s[0].replace("~", home, 1)


@_f("os.path.exists")
def _exists(interp, args, kwargs, m, n):
    return exists(interp, args[0], m, n)


@_f("os.path.isfile")
def _isfile(interp, args, kwargs, m, n):
    return exists(interp, args[0], m, n, "file")


@_f("os.path.isdir")
def _isdir(interp, args, kwargs, m, n):
    return exists(interp, args[0], m, n, "dir")


@_f("os.listdir")
def _listdir(interp, args, kwargs, m, n):
    """A folder of the workspace: its entries in the file system's order, as Python gives them."""
    s = _strs(interp, args[:1], m, n, "listdir")
    if isinstance(s, Unknown):
        return s
    p = s[0]
    if marked(p) or not posixpath.isabs(p) or not interp.host.in_workspace(posixpath.join(p, "x")):
        return Unknown(f"os.listdir() of {p} (a folder of the machine that launches)", m.where(n))
    import os
    try:
        names = os.listdir(p)
    except OSError as ex:
        raise PyError("FileNotFoundError" if isinstance(ex, FileNotFoundError) else "OSError", str(ex), m.where(n),
                      sure=isinstance(ex, FileNotFoundError))
    if len(names) > 10_000:
        raise Decline("a folder too large to list", m.where(n))
    return names


@_f("os.getenv", "os.environ.get")
def _getenv(interp, args, kwargs, m, n):
    return environ_get(interp, args[0] if args else kwargs.get("key"),
                       args[1] if len(args) > 1 else kwargs.get("default"), m, n)


CONSTANTS["os.environ"] = lambda interp: EnvMap()
CONSTANTS["os.sep"] = lambda interp: "/"
CONSTANTS["os.pathsep"] = lambda interp: ":"
CONSTANTS["os.linesep"] = lambda interp: "\n"
CONSTANTS["os.name"] = lambda interp: "posix"
CONSTANTS["sys.platform"] = lambda interp: "linux"
CONSTANTS["math.pi"] = lambda interp: math.pi
CONSTANTS["math.e"] = lambda interp: math.e
CONSTANTS["math.inf"] = lambda interp: math.inf


def _unknown_fn(what):
    def fn(interp, args, kwargs, m, n):
        return Unknown(what, m.where(n))
    return fn


for _name in ("os.getcwd", "os.walk", "glob.glob", "os.path.getmtime", "os.getpid", "time.time",
              "datetime.datetime.now", "socket.gethostname", "getpass.getuser", "os.uname", "platform.machine",
              "uuid.uuid4", "random.random", "random.randint", "tempfile.mkdtemp", "tempfile.gettempdir",
              "tempfile.NamedTemporaryFile", "tempfile.mkstemp", "shutil.which"):
    FUNCS[_name] = Builtin(_name, _unknown_fn(f"{_name}() (it depends on the machine that launches)"))

def _program(name):
    def fn(interp, args, kwargs, m, n):
        why = f"{name}() runs a program (tvl-lsp never does)"
        if interp.host.concrete:   # it may fail, and launch with it
            raise Decline(f"{why}: its output, and whether it fails, are not known", m.where(n))
        return Unknown(why, m.where(n))
    return fn


for _name in ("subprocess.run", "subprocess.check_output", "subprocess.call", "subprocess.Popen",
              "subprocess.check_call", "subprocess.getoutput", "os.system", "os.popen"):
    FUNCS[_name] = Builtin(_name, _program(_name))

def _xacro(name):
    def fn(interp, args, kwargs, m, n):
        why = f"{name}() (xacro runs macros: tvl-lsp does not run it)"
        if interp.host.concrete:
            # whether xacro succeeds (its includes, the packages it finds) decides whether launch
            # loads the file at all
            raise Decline(f"{why}; whether it succeeds, and so whether ros2 launch loads the file, is not known",
                          m.where(n))
        return Unknown(why, m.where(n))
    return fn


for _name in ("xacro.process_file", "xacro.process", "xacro.parse", "xacro.process_doc"):
    FUNCS[_name] = Builtin(_name, _xacro(_name))

for _name in ("os.makedirs", "os.mkdir", "os.remove", "os.unlink", "shutil.copy", "shutil.rmtree", "os.chdir",
              "os.putenv", "shutil.copyfile", "sys.exit"):
    FUNCS[_name] = Builtin(_name, _declined(_name))


@_f("sys.argv.__get__")
def _argv(interp, args, kwargs, m, n):
    return Unknown("sys.argv", m.where(n))


CONSTANTS["sys.argv"] = lambda interp: Unknown("the command line (sys.argv) of the process that launches")
CONSTANTS["sys.path"] = lambda interp: interp.host.sys_path
CONSTANTS["sys.version_info"] = lambda interp: (3, 12, 0)
CONSTANTS["typing.TYPE_CHECKING"] = lambda interp: False


@_f("ament_index_python.resources.has_resource", "ament_index_python.has_resource")
def _has_resource(interp, args, kwargs, m, n):
    kind = args[0] if args else kwargs.get("resource_type")
    name = args[1] if len(args) > 1 else kwargs.get("resource_name")
    if kind == "packages" and isinstance(name, str):
        w = interp.host.w
        if name in w.packages or name in w.installed:
            return True
        if interp.host.concrete:
            return False   # the packages of the load are the workspace's and AMENT_PREFIX_PATH's
    return Unknown(f"whether the ament index has the resource {name!r} on the machine that launches", m.where(n))


@_f("ament_index_python.packages.get_package_share_directory", "ament_index_python.get_package_share_directory")
def _share(interp, args, kwargs, m, n):
    return package_share(interp, args, kwargs, m, n)


@_f("ament_index_python.packages.get_package_prefix", "ament_index_python.get_package_prefix")
def _prefix(interp, args, kwargs, m, n):
    return package_share(interp, args, kwargs, m, n, prefix=True)


@_f("ament_index_python.packages.get_package_share_path", "ament_index_python.get_package_share_path")
def _share_path(interp, args, kwargs, m, n):
    return package_share(interp, args, kwargs, m, n, as_path=True)


@_f("yaml.safe_load", "yaml.load", "yaml.full_load", "yaml.unsafe_load")
def _yaml(interp, args, kwargs, m, n):
    return yaml_load(interp, args, kwargs, m, n)


@_f("json.load", "json.loads")
def _json(interp, args, kwargs, m, n):
    return json_load(interp, args, kwargs, m, n)


@_f("pathlib.Path", "pathlib.PurePath", "pathlib.PosixPath", "pathlib.PurePosixPath")
def _pathlib(interp, args, kwargs, m, n):
    s = _strs(interp, args, m, n, "Path")
    if isinstance(s, Unknown):
        return s
    return PathObj(posixpath.join(*s) if s else ".")


@_f("copy.deepcopy", "copy.copy")
def _copy(interp, args, kwargs, m, n):
    v = args[0]
    if interp_plain(v):
        return copy.deepcopy(v)
    if isinstance(v, list):
        return list(v)
    if isinstance(v, dict):
        return dict(v)
    return v


@_f("launch.utilities.perform_substitutions")
def _perform_substitutions(interp, args, kwargs, m, n):
    ctx = args[0] if args else kwargs.get("context")
    subs = args[1] if len(args) > 1 else kwargs.get("subs")
    return interp.host.perform(ctx, subs, m, n)


@_f("launch.utilities.normalize_to_list_of_substitutions")
def _normalize(interp, args, kwargs, m, n):
    v = args[0]
    return [v] if isinstance(v, (str, LObj)) else v


for _name in ("math.sqrt", "math.cos", "math.sin", "math.tan", "math.radians", "math.degrees", "math.floor",
              "math.ceil", "math.atan2", "math.fabs", "math.isclose"):
    _mf = getattr(math, _name.split(".")[1])

    def _mathf(interp, args, kwargs, m, n, _mf=_mf):
        u = _unknown_in(args)
        if u is not None:
            return u
        if not all(isinstance(a, (int, float)) for a in args):
            raise PyError("TypeError", "must be real number", m.where(n))
        try:
            return _mf(*args)
        except (ValueError, OverflowError) as ex:
            raise PyError(type(ex).__name__, str(ex), m.where(n))
    FUNCS[_name] = Builtin(_name, _mathf)



def call_symbol(interp, sym: Sym, args, kwargs, m, n):
    f = FUNCS.get(sym.qual)
    if f is not None:
        return f.fn(interp, args, kwargs, m, n)
    return Unknown(f"{sym.qual}() is not modelled", m.where(n))
