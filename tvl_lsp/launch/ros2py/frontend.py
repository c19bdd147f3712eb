"""A Python launch file as a unit of the ROS 2 walker: parsed with Python's ``ast`` (never
imported, never run), its module code and ``generate_launch_description()`` interpreted
(:mod:`.interp`), the launch description it returns turned into the walker's actions
(:mod:`.convert`) with entities whose ranges point into the ``.py`` text.

:func:`load_unit` is what the walker calls for a ``.py`` file.  The unit it returns is an
ordinary :class:`~tvl_lsp.launch.ros2.values.Unit`: ``errors`` when ros2 launch refuses the
file (a syntax error, no ``generate_launch_description``, a constructor's TypeError), and
``python=True`` with ``decline`` = (reason, path, span) when tvl-lsp cannot know what the file
describes (it then says so at that line, and never guesses).
"""

from __future__ import annotations

import ast
import os
import sys
import threading
from typing import Optional

from ...base.diagnostics import Diagnostic, Severity, register
from ...base.formula import FALSE, conj, neg
from ...base.text import LineIndex, Pos, Span
from ..ros2 import actions as A
from ..ros2.frontend import Document
from ..ros2.values import OPAQUE, UNRESOLVED, Unit, declared_in, opaque, present
from . import subst_ext  # noqa: F401  (registers the walker's Python-only substitutions)
from .actions import OpaqueA, ensure_elements
from .convert import Converter, PyEntity, PyValue
from .interp import Interp
from .values import Decline, Func, LObj, ModuleNS, PyError, SysPath, Unknown

PY_SYNTAX = register("python-syntax", Severity.ERROR, "A Python launch file that Python cannot parse.", "launch")

MAX_PY_CHARS = 2_000_000
MAX_MODULES = 64
_MISSING = object()

# parsed syntax trees by content (a tree is never changed by the interpreter)
_TREES: dict = {}
_TREES_LOCK = threading.Lock()
_TREES_CHARS = [0]
MAX_TREE_CHARS = 8_000_000


def parse_python(text: str, path: str):
    """(tree, None) or (None, (message, span)) -- Python's own parser, bounded."""
    key = (path, len(text), hash(text))
    with _TREES_LOCK:
        t = _TREES.get(key)
    if t is not None:
        return t, None
    idx = LineIndex(text)
    if len(text) > MAX_PY_CHARS:
        return None, (f"the file has {len(text):,} characters; tvl-lsp analyses Python launch files of at most "
                      f"{MAX_PY_CHARS:,}", idx.span(0, 0), "TooLarge")
    try:
        tree = ast.parse(text, filename=path)
    except SyntaxError as e:
        line = max((e.lineno or 1) - 1, 0)
        col = max((e.offset or 1) - 1, 0)
        lt = idx.line_text(line)
        # offset counts characters of the line (Python 3.10+); end_offset likewise
        col = min(col, len(lt))
        end_line = (e.end_lineno or e.lineno or 1) - 1
        end = (e.end_offset - 1) if e.end_offset and e.end_offset > 0 else col + 1
        if end_line != line:
            end_line, end = line, len(lt)
        end = min(max(end, col), len(lt))
        if end == col and col < len(lt):
            end = col + 1
        return None, (f"{type(e).__name__}: {e.msg}", Span(Pos(line, col), Pos(end_line, end)), type(e).__name__)
    except (RecursionError, MemoryError):
        return None, ("Python's parser gives up: the file is nested too deeply", idx.span(0, 0), "RecursionError")
    except ValueError as e:
        return None, (f"ValueError: {e}", idx.span(0, 0), "ValueError")
    with _TREES_LOCK:
        _TREES[key] = tree
        _TREES_CHARS[0] += len(text)
        while len(_TREES) > 1 and _TREES_CHARS[0] > MAX_TREE_CHARS:
            k = next(iter(_TREES))
            _TREES_CHARS[0] -= k[1]
            del _TREES[k]
    return tree, None


# modules that are never a workspace's: the standard library and the launch packages
_NEVER_WORKSPACE = frozenset(sys.stdlib_module_names) | {"launch", "launch_ros", "launch_xml", "launch_yaml",
                                                         "ament_index_python", "yaml", "xacro"}


class PyHost:
    """What the interpreter asks the outside world, answered from the walk (files through the
    walker's bounded and confined reader, packages from the workspace and AMENT_PREFIX_PATH, the
    environment), never from running anything."""

    def __init__(self, w, unit_path: str):
        self.w = w
        self.unit_path = unit_path
        if not getattr(w, "py_env_copied", False):
            # the launch files' process environment, which they may change (os.environ['X'] = ...):
            # a copy, never tvl-lsp's own
            w.env = dict(w.env)
            w.py_env_copied = True
        self.env = w.env
        self.concrete = w.concrete
        self.module_cache: dict = {}
        self.world = None
        self.unit: Optional["PyUnit"] = None
        self._found: dict = {}
        self.sys_path = SysPath()

    # -- files
    def read(self, path: str) -> Optional[str]:
        return self.w.read(path)

    def in_workspace(self, path: str) -> bool:
        return self.w.in_workspace(path)

    def exists(self, path: str, kind: str = "exists") -> Optional[bool]:
        known = self.w.in_workspace(path) or any(path.startswith(f.rstrip("/") + "/")
                                                 for f in self.w.installed.values())
        if not known:
            return None
        if kind == "dir":
            return os.path.isdir(path)
        if kind == "file":
            return self.w.exists(path)
        return self.w.exists(path) or os.path.isdir(path)

    def set_env(self, key, value, m, n) -> None:
        """``os.environ[key] = value`` (the walker's $(env) and EnvironmentVariable see it)."""
        if isinstance(key, Unknown) or not isinstance(key, str):
            raise Decline("the file sets an environment variable tvl-lsp cannot name", m.where(n))
        if isinstance(value, str) and not isinstance(value, Unknown):
            self.env[str(key)] = str(value)
        elif isinstance(value, Unknown):
            self.env[str(key)] = OPAQUE
        else:
            raise PyError("TypeError", f"str expected, not {type(value).__name__}", m.where(n), sure=True)

    # -- packages
    def package_dir(self, pkg: str, share: bool, where):
        import re
        w = self.w
        if re.fullmatch(r"[a-zA-Z0-9][a-zA-Z0-9_-]+", pkg, re.ASCII) is None:
            raise PyError("ValueError", f"'{pkg}' is not a valid package name", where)
        folder = w.packages.get(pkg)
        if folder is not None:
            if share:
                return folder
            return os.path.join(w.root, "install") if w.root else os.path.dirname(os.path.dirname(folder))
        inst = w.installed.get(pkg)
        if inst is not None:
            return inst if share else os.path.dirname(os.path.dirname(inst))
        if not w.concrete:
            return UNRESOLVED + pkg + UNRESOLVED
        if w.stub:
            prefix = os.path.join(w.root or "/", "install")
            return os.path.join(prefix, "share", pkg) if share else prefix
        searched = [os.path.join(w.root, "install")] if w.root else []
        raise PyError("PackageNotFoundError", f"\"package '{pkg}' not found, searching: {searched!r}\"", where,
                      sure=True)

    # -- workspace modules
    def workspace_module(self, name: str, interp: Interp):
        if name in self.module_cache:
            return self.module_cache[name]
        if name.split(".", 1)[0] in _NEVER_WORKSPACE:
            return None
        path = self._module_file(name)
        if path is None:
            return None
        text = self.read(path)
        if text is None:
            return None
        if len(self.module_cache) >= MAX_MODULES:
            raise Decline(f"the file imports more than {MAX_MODULES} workspace modules")
        tree, err = parse_python(text, path)
        if tree is None:
            raise PyError("SyntaxError", f"{err[0]} (in {path})", None)
        m = ModuleNS(path, text, LineIndex(text), name, {}, tree)
        m.globals["__name__"] = name
        m.globals["__file__"] = path
        m.is_pkg = os.path.basename(path) == "__init__.py"
        self.module_cache[name] = m
        interp.run_module(m)
        return m

    def _module_file(self, name: str) -> Optional[str]:
        """The file of a workspace module: in a folder the file put on ``sys.path`` (where ros2
        launch finds it too); the symbolic analysis also looks in the packages' folders (where
        an installed package's modules come from)."""
        key = (name, tuple(self.sys_path.added))
        if key in self._found:
            return self._found[key]
        parts = name.split(".")
        if not all(p.isidentifier() for p in parts):
            return None
        roots = [r for r in self.sys_path.added if self.w.in_workspace(os.path.join(r, "x"))]
        if not self.concrete:
            # an installed package's Python modules: a ROS package installs the Python package of
            # its own name (ament_python, ament_python_install_package)
            folder = self.w.packages.get(parts[0])
            if folder is not None:
                roots += [folder, os.path.join(folder, "src")]
            roots.append(os.path.dirname(self.unit_path))
        found = None
        for r in roots:
            base = os.path.join(r, *parts)
            for cand in (base + ".py", os.path.join(base, "__init__.py")):
                if self.w.exists(cand) and (len(parts) == 1 or self.w.exists(os.path.join(r, parts[0],
                                                                                          "__init__.py"))):
                    found = cand
                    break
            if found:
                break
        self._found[key] = found
        return found

    def relative_module(self, m: ModuleNS, level: int, module: Optional[str]) -> Optional[str]:
        if m.path == self.unit_path:
            return None
        pkg = m.name if getattr(m, "is_pkg", False) else m.name.rsplit(".", 1)[0] if "." in m.name else ""
        for _ in range(level - 1):
            pkg = pkg.rsplit(".", 1)[0] if "." in pkg else ""
        if not pkg:
            return None
        return f"{pkg}.{module}" if module else pkg

    # -- the launch context (OpaqueFunction)
    def _world(self, m, n, what: str):
        if self.world is None:
            raise Decline(f"{what} exists only when launching (inside an OpaqueFunction)", m.where(n))
        return self.world

    def launch_configuration(self, name, default, m, n, required: bool = False, presence: bool = False):
        world = self._world(m, n, "context.launch_configurations")
        if isinstance(name, Unknown):
            return name
        if not isinstance(name, str):
            return Unknown("a launch configuration named by a non-string", m.where(n))
        sc = world.sc
        g = world.guard
        vals = sc.configs.get(str(name), [])
        cases = [(conj([g, c]), v) for c, v in vals]
        missing = conj([g, neg(present(vals))])
        if missing != FALSE and sc.opaque != FALSE:
            cases.append((conj([missing, sc.opaque]), OPAQUE))
            missing = conj([missing, neg(sc.opaque)])
        if missing != FALSE:
            cases.append((missing, _MISSING))
        v = world.choose(cases)
        if v is None and world.guard == FALSE:
            return Unknown("an unreachable case", m.where(n))
        if v is _MISSING:
            if presence:
                return False
            if required:
                raise PyError("KeyError", repr(str(name)), m.where(n), sure=True)
            return default
        if isinstance(v, str) and opaque(v):
            return Unknown(f"the value of the launch configuration '{name}' (tvl-lsp cannot compute it)", m.where(n))
        if presence:
            return True
        return v

    def context_env(self, name, default, m, n, required: bool = False, presence: bool = False):
        """``context.environment.get(name, default)`` / ``[name]`` / ``name in``: the launch's
        environment changes in scope, else the process's environment (a variable that is not set
        here is unknown to the symbolic analysis: it may be when launching)."""
        world = self._world(m, n, "context.environment")
        if isinstance(name, Unknown):
            return name
        if not isinstance(name, str):
            raise PyError("TypeError", "str expected, not " + type(name).__name__, m.where(n))
        cases = world.w.env_lookup(world.sc, str(name), world.guard)
        v = world.choose([(c, _MISSING if val is None else val) for c, val in cases])
        if v is None and world.guard == FALSE:
            return Unknown("an unreachable case", m.where(n))
        if v is _MISSING:
            if not self.concrete:
                return Unknown(f"the environment variable {name} (not set here; it may be when launching)",
                               m.where(n))
            if presence:
                return False
            if required:
                raise PyError("KeyError", repr(str(name)), m.where(n), sure=True)
            return default
        if isinstance(v, str) and opaque(v):
            return Unknown(f"the environment variable {name} (tvl-lsp cannot compute it)", m.where(n))
        return True if presence else v

    def perform(self, ctx, subs, m, n):
        if isinstance(ctx, LObj) and ctx.cls == "LaunchContext":   # LaunchContext() made by the file
            from .launchapi import perform_fresh
            return perform_fresh(self, subs, m, n)
        world = self._world(m, n, "performing a substitution")
        conv = self.unit.conv
        parts = conv.parts(subs, True)
        v = PyValue(parts, None, None, m.span(n) if m.path == world.el.path else None)
        cases = world.w.ev_parts(parts, v, world.sc, world.guard, world.el)
        if not cases:
            world.guard = FALSE
            return Unknown("a substitution that fails when launching", m.where(n))
        val = world.choose(cases)
        if val is None:
            return Unknown("an unreachable case", m.where(n))
        if opaque(val):
            return Unknown("a substitution's value tvl-lsp cannot compute", m.where(n))
        return val


class PyUnit:
    """What a Python launch file holds for the walk: its host, converter and module."""

    def __init__(self, host: PyHost, conv: Converter, module: ModuleNS):
        self.host = host
        self.conv = conv
        self.module = module

    def call_opaque(self, world, fn: Func, args: list, kwargs: dict, where):
        self.host.world = world
        try:
            it = Interp(self.host)
            return it.call_func(fn, args, kwargs, fn.module, fn.node)
        finally:
            self.host.world = None

    def convert_dynamic(self, result, ent: PyEntity, el, emap: dict, w) -> list:
        """The actions an OpaqueFunction returned, with elements for the places that made them
        (under the OpaqueFunction's element)."""
        acts = self.conv.actions(list(result), ent)
        _bind_units(acts, self)
        for k in ent.sub_entities():
            ensure_elements(k, el, emap, w.elements)
        for a in acts:
            if id(a.entity) not in emap:
                ensure_elements(a.entity, el, emap, w.elements)
        return acts


def _bind_units(acts: list, unit: PyUnit) -> None:
    stack = list(acts)
    while stack:
        a = stack.pop()
        if isinstance(a, OpaqueA):
            a.unit = unit
        for k in ("actions",):
            sub = getattr(a, k, None)
            if isinstance(sub, list):
                stack.extend(sub)


_TEST_MODULES = ("launch_pytest", "launch_testing", "pytest", "unittest")


def _test_framework(tree) -> Optional[str]:
    """The test framework a file without ``generate_launch_description`` imports at its top
    level (``launch_pytest``, ``pytest``...), if any."""
    for st in tree.body:
        names = [a.name for a in st.names] if isinstance(st, ast.Import) else \
            [st.module or ""] if isinstance(st, ast.ImportFrom) and not st.level else []
        for nm in names:
            if nm.split(".", 1)[0] in _TEST_MODULES:
                return nm.split(".", 1)[0]
    return None


def load_unit(w, path: str, text: str) -> Unit:
    """The walker's unit of a Python launch file."""
    idx = LineIndex(text)
    tree, err = parse_python(text, path)
    root = PyEntity("launch", path, idx.span(0, min(len(text), len(idx.line_text(0)))))
    doc = Document(path, text, idx, root, [], kind="py")
    if tree is None:
        msg, span, kind = err
        doc.diagnostics.append(Diagnostic(PY_SYNTAX, Severity.ERROR, path, span, msg))
        doc.error = ("ParseError", msg, span)
        return Unit(path, doc, [], [A.LoadError("ParseError", msg, span, path)])
    gen_def = next((st for st in tree.body if isinstance(st, ast.FunctionDef)
                    and st.name == "generate_launch_description"), None)
    if gen_def is not None:
        # the launch description's place: where a missing argument would be declared
        line = gen_def.lineno - 1
        col = idx.line_text(line).find("generate_launch_description")
        if col >= 0:
            root.span = root.tag_span = Span(Pos(line, col), Pos(line, col + len("generate_launch_description")))
    host = PyHost(w, path)
    conv = Converter(path, root)
    m = ModuleNS(path, text, idx, "python_launch_file", {}, tree)
    m.globals["__name__"] = "python_launch_file"
    m.globals["__file__"] = path
    unit = PyUnit(host, conv, m)
    host.unit = unit
    conv.unit = unit
    interp = Interp(host)
    acts: list = []
    errors: list = []
    decline = None
    try:
        interp.run_module(m)
        gen = m.globals.get("generate_launch_description")
        if gen is None and "generate_test_description" in m.globals:
            # a launch_testing test: launch_test runs it, not ros2 launch
            decline = ("a launch_testing test (it defines generate_test_description()): launch_test runs it, "
                       "not ros2 launch", None)
        elif gen is None and _test_framework(tree):
            # a test that pytest runs (launch_pytest fixtures, plain pytest): not a launch file
            decline = (f"a test of {_test_framework(tree)} (it has no generate_launch_description()): pytest runs "
                       "it, not ros2 launch", None)
        elif gen is None:
            msg = f"launch file at '{path}' does not contain the required function 'generate_launch_description()'"
            errors.append(A.LoadError("InvalidPythonLaunchFileError", msg, root.tag_span, path))
        elif not isinstance(gen, Func):
            decline = ("generate_launch_description is not a plain function of the file", None)
        else:
            ld = interp.call_func(gen, [], {}, m, gen.node)
            if isinstance(ld, Unknown):
                decline = (f"generate_launch_description() returns a value tvl-lsp cannot know: {ld.reason}", ld.where)
            elif not (isinstance(ld, LObj) and ld.cls == "LaunchDescription"):
                decline = (f"generate_launch_description() returns a {getattr(ld, 'cls', type(ld).__name__)}, not a "
                           "LaunchDescription", m.where(gen.node))
            else:
                acts = conv.actions(ld, root)
                _bind_units(acts, unit)
    except Decline as d:
        decline = (d.reason, d.where)
    except PyError as e:
        if e.sure:
            span = e.where[1] if e.where and e.where[0] == path else root.tag_span
            errors.append(A.LoadError(e.kind, e.message, span, path))
        else:
            decline = (f"Python would raise {e.kind}: {e.message} (or tvl-lsp misses something the file relies on)",
                       e.where)
    except RecursionError:
        decline = ("the file is nested too deeply to analyse", None)
    _static_names(tree, m, conv, root)
    u = Unit(path, doc, acts, errors)
    if decline is not None:
        reason, where = decline
        span = where[1] if where and where[0] == path else root.tag_span
        u = Unit(path, doc, [], errors, python=True)
        u.decline = (reason, path, span)
    u.py = unit
    w.declared_names[path] = _declared(acts)
    return u


def _declared(acts: list) -> set:
    """The configurations a Python file sets itself (``declared_in``), without the include arguments
    that only pass a configuration on under its own name (``'map_path': LaunchConfiguration('map_path')``:
    the file expects whoever launches it to give it)."""
    from ..ros2 import subst as S
    out = declared_in(acts)
    stack = list(acts)
    passed: set = set()
    own: set = set()
    while stack:
        a = stack.pop()
        if isinstance(a, A.IncludeA):
            for x in a.args:
                n = S.plain(x.name.parts)
                p = x.value.parts
                if len(p) == 1 and isinstance(p[0], S.Sub) and p[0].name == "var" and \
                        S.plain(p[0].args[0]) == n:
                    passed.add(n)
                else:
                    own.add(n)
        elif isinstance(a, (A.ArgA,)):
            own.add(a.name)
        elif isinstance(a, A.LetA) and S.is_text(a.name.parts):
            own.add(S.plain(a.name.parts))
        stack.extend(getattr(a, "actions", None) or [])
    return out - (passed - own)


def _static_names(tree, m: ModuleNS, conv: Converter, root: PyEntity) -> None:
    """Every literal argument name the file reads or declares where it is no action's value
    (``context.launch_configurations['x']``, ``.get('x')`` in an OpaqueFunction, a
    ``LaunchConfiguration('x')`` made but not yet used): Subst entries of the root, for
    references and rename."""
    covered = {s.span for e in conv.entities.values() for s in e.substs}
    for node in ast.walk(tree):
        name_node = None
        call_node = node
        if isinstance(node, ast.Call):
            f = node.func
            fname = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""
            if fname in ("LaunchConfiguration", "LaunchConfigurationEquals", "LaunchConfigurationNotEquals"):
                if node.args:
                    name_node = node.args[0]
                else:
                    name_node = next((k.value for k in node.keywords if k.arg in ("variable_name",
                                                                                   "launch_configuration_name")), None)
            elif fname == "get" and isinstance(f, ast.Attribute) and isinstance(f.value, ast.Attribute) and \
                    f.value.attr == "launch_configurations" and node.args:
                name_node = node.args[0]
        elif isinstance(node, ast.Subscript) and isinstance(node.value, ast.Attribute) and \
                node.value.attr == "launch_configurations":
            name_node = node.slice
        if not (isinstance(name_node, ast.Constant) and isinstance(name_node.value, str)):
            continue
        span = m.span(call_node)
        if span in covered:
            continue
        lw = m.literal_where(name_node)
        covered.add(span)
        conv.cur = root
        conv.add_subst("var", (name_node.value,), span, "python", lw[1] if lw else None)
    conv.cur = None
