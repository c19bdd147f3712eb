"""The symbolic ROS 2 launch walker: ros2/launch's visit of a launch file, for all args at once.

It visits the actions of :mod:`.actions` in launch's order (``LaunchService`` visits entities
depth first; a ``<group>`` yields push / actions / pop, an ``<include>`` yields its args'
``SetLaunchConfiguration`` and the included description), but every value is a list of
*cases* ``(condition, string)``: the formula over the free (feature) args under which the value
is that string.  Each check launch makes becomes an :class:`~tvl_lsp.launch.model.ErrorFact`
whose condition is where launch raises it.  With concrete args every condition folds to a
constant: the same walker is then the concrete loader, and it stops at the first error, as
launch does.

The semantics copied (each seen in the real ros2/launch, see ``tests/data/ros2/README.md``):
launch configurations are one dictionary: ``<include>`` does not scope it (args passed and
declared leak out, and flow into later includes, where ``DeclareLaunchArgument`` uses its
default only when nothing is set yet); ``<group>`` copies it (``scoped="false"`` does not;
``forwarding="false"`` clears it but for ``<keep>``); ``ros_namespace``, ``ros_remaps`` and
``global_params`` live in it, the last two as lists that a group copies shallowly (so
additions leak once the list exists outside); conditions take only true/false/1/0;
``$(dirname)`` is the folder of the file launch included last; ``$(eval)`` is Python.
"""

from __future__ import annotations

import itertools
import math
import os
import re
import shlex
import shutil
from dataclasses import dataclass, field
from typing import Mapping, Optional

import yaml

from ...base.formula import FALSE, TRUE, And, Const, Formula, Not, Or, Var, conj, disj, neg
from ...base.diagnostics import Diagnostic, Related, Severity, register
from ...base.text import LineIndex, Span
from ..model import Element, ErrorFact, IncludeFact, NodeFact, RemapCase
from . import actions as A
from . import pyexpr
from . import subst as S
from .frontend import Document, make_elements, parse_launch_file

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION


def _reg(code: str, sev: Severity, summary: str) -> str:
    return register(code, sev, summary, "launch")


# codes shared with ROS 1 (registered by tvl_lsp.launch.loader too; registration is idempotent)
UNDEFINED_ARG = _reg("undefined-arg", E, "$(arg X) where X is not declared in scope")
UNSET_ARG = _reg("unset-arg", W, "$(arg X) where X is declared without a value and nothing sets it")
INVALID_CONDITION = _reg("invalid-condition", E, "if/unless does not evaluate to true/false/1/0")
IF_AND_UNLESS = _reg("if-and-unless", E, "Both 'if' and 'unless' on the same tag")
DUPLICATE_NODE = _reg("duplicate-node", E, "Two nodes with the same resolved name are loaded")
MISSING_ATTRIBUTE = _reg("missing-attribute", E, "A required attribute is missing")
UNKNOWN_ATTRIBUTE = _reg("unknown-attribute", W, "roslaunch does not know this attribute (it warns)")
UNKNOWN_TAG = _reg("unknown-tag", W, "roslaunch does not know this tag (it warns and ignores it)")
INVALID_VALUE = _reg("invalid-attribute-value", E, "An attribute value roslaunch rejects")
SUBST_SYNTAX = _reg("substitution-syntax", E, "Malformed $(...) substitution")
SUBST_UNKNOWN = _reg("unknown-substitution", E, "Unknown $(...) substitution command")
SUBST_ARITY = _reg("substitution-arity", E, "Wrong number of arguments to a $(...) substitution")
EVAL_ERROR = _reg("eval-error", E, "A $(eval ...) expression fails")
ENV_NOT_SET = _reg("env-not-set", E, "$(env X) where X is not set in tvl-lsp's environment")
PACKAGE_NOT_FOUND = _reg("package-not-found", E, "$(find pkg) of a package roslaunch cannot find")
CONDITION_NOT_ANALYSABLE = _reg("condition-not-analysable", I, "A condition tvl-lsp cannot translate to a formula")
INCLUDE_NOT_FOUND = _reg("include-not-found", E, "An included file does not exist")
INCLUDE_INVALID = _reg("include-invalid", E, "An included file is not a valid launch file")
INCLUDE_CYCLE = _reg("include-cycle", E, "Files include each other in a cycle")
INCLUDE_TOO_DEEP = _reg("include-too-deep", W, "Includes nested too deeply to follow")
NO_LAUNCH_ROOT = _reg("no-launch-root", E, "The file has no single <launch> element")
FILE_NOT_FOUND = _reg("file-not-found", E, "A file a tag loads does not exist")
BUDGET = _reg("launch-analysis-budget", W, "The launch file is too large to analyse completely")
# ROS 2 only
INVALID_CHOICE = _reg("invalid-choice", E, "An <arg> value that is not one of its <choice> values (ROS 2)")
INVALID_NODE_NAME = _reg("invalid-node-name", E, "A node name ros2 launch rejects (ROS 2)")
INVALID_NAMESPACE = _reg("invalid-namespace", E, "A namespace ros2 launch rejects (ROS 2)")
SUBST_FAILED = _reg("substitution-failed", E, "A $(...) substitution fails when launched (ROS 2)")
PYTHON_INCLUDE = _reg("python-launch-include", I, "An <include> of a Python launch file, which tvl-lsp does not "
                      "execute (ROS 2)")
ARG_LEAK = _reg("include-arg-leak", W, "An arg set by an <include> leaks out and changes a later element (ROS 2)")
PARAM_FILE_NOT_FOUND = _reg("param-file-not-found", W, "<param from=...> names a file that does not exist (ROS 2)")
LAUNCH_PARSE = _reg("invalid-launch-file", E, "ros2 launch refuses to load the file (ROS 2)")

MAX_CASES = 64
MAX_INCLUDE_DEPTH = 12
MAX_VISITS = 200_000
MAX_WALK_DEPTH = 150
UNRESOLVED = "\x01"   # around a package name whose folder is unknown (as the ROS 1 loader)
OPAQUE = "\x02"       # a value tvl-lsp cannot compute ($(eval) it cannot analyse, $(command) ...)

_CLASS = {
    "var": "launch.substitutions.launch_configuration.LaunchConfiguration",
    "env": "launch.substitutions.environment_variable.EnvironmentVariable",
    "eval": "launch.substitutions.python_expression.PythonExpression",
    "not": "launch.substitutions.boolean_substitution.NotSubstitution",
    "and": "launch.substitutions.boolean_substitution.AndSubstitution",
    "or": "launch.substitutions.boolean_substitution.OrSubstitution",
    "any": "launch.substitutions.boolean_substitution.AnySubstitution",
    "all": "launch.substitutions.boolean_substitution.AllSubstitution",
    "equals": "launch.substitutions.equals_substitution.EqualsSubstitution",
    "not-equals": "launch.substitutions.not_equals_substitution.NotEqualsSubstitution",
    "if": "launch.substitutions.if_else_substitution.IfElseSubstitution",
    "dirname": "launch.substitutions.this_launch_file_dir.ThisLaunchFileDir",
    "filename": "launch.substitutions.this_launch_file.ThisLaunchFile",
    "anon": "launch.substitutions.anon_name.AnonName",
    "command": "launch.substitutions.command.Command",
    "find-exec": "launch.substitutions.find_executable.FindExecutable",
    "file-content": "launch.substitutions.file_content.FileContent",
    "launch_log_dir": "launch.substitutions.launch_log_dir.LaunchLogDir",
    "log_dir": "launch.substitutions.launch_log_dir.LaunchLogDir",
    "find-pkg-prefix": "launch_ros.substitutions.find_package.FindPackagePrefix",
    "find-pkg-share": "launch_ros.substitutions.find_package.FindPackageShare",
    "exec-in-pkg": "launch_ros.substitutions.executable_in_package.ExecutableInPackage",
    "param": "launch_ros.substitutions.parameter.Parameter",
}

Cases = list  # list[tuple[Formula, str]]


@dataclass
class LaunchFact(ErrorFact):
    """An ErrorFact that also knows what ros2 launch itself raises (exception class and text)."""
    launch_type: str = ""
    launch_message: str = ""


@dataclass
class Node2Fact(NodeFact):
    """A node (``name`` is "" when the file gives none: the executable decides)."""
    package: str = ""
    executable: str = ""
    ns: Optional[str] = None        # resolved namespace (None: none given or pushed)
    kind: str = "node"
    params: dict = field(default_factory=dict)
    param_files: list = field(default_factory=list)
    source: str = ""


def fvars(f: Formula) -> set[str]:
    """The variables of a formula (shared sub-formulas visited once)."""
    out: set[str] = set()
    seen: set[int] = set()
    stack = [f]
    while stack:
        g = stack.pop()
        if id(g) in seen:
            continue
        seen.add(id(g))
        if isinstance(g, Var):
            out.add(g.name)
        elif isinstance(g, Not):
            stack.append(g.arg)
        elif isinstance(g, (And, Or)):
            stack.extend(g.args)
    return out


def feval(f: Formula, env: Mapping[str, bool], memo: Optional[dict] = None) -> bool:
    """Evaluate (shared sub-formulas evaluated once)."""
    memo = {} if memo is None else memo
    k = id(f)
    if k in memo:
        return memo[k]
    if isinstance(f, Const):
        r = f.value
    elif isinstance(f, Var):
        r = bool(env.get(f.name, False))
    elif isinstance(f, Not):
        r = not feval(f.arg, env, memo)
    elif isinstance(f, And):
        r = all(feval(a, env, memo) for a in f.args)
    else:
        r = any(feval(a, env, memo) for a in f.args)
    memo[k] = r
    return r


def satisfiable(f: Formula, limit: int = 14) -> Optional[bool]:
    """True / False by brute force over at most ``limit`` variables; None beyond."""
    if f == FALSE:
        return False
    if f == TRUE:
        return True
    vs = sorted(fvars(f))
    if len(vs) > limit:
        return None
    for bits in itertools.product((False, True), repeat=len(vs)):
        if feval(f, dict(zip(vs, bits))):
            return True
    return False


def merge_facts(facts: list) -> list:
    """One fact per (code, place, message), conditions joined; facts no assignment can trigger
    dropped (when small enough to tell)."""
    out: dict = {}
    for f in facts:
        key = (f.code, f.path, f.span, f.message)
        g = out.get(key)
        if g is None:
            out[key] = LaunchFact(f.code, f.severity, f.message, f.path, f.span, f.condition, list(f.related),
                                  getattr(f, "launch_type", ""), getattr(f, "launch_message", ""))
        else:
            g.condition = disj([g.condition, f.condition])
            for r in f.related:
                if r not in g.related:
                    g.related.append(r)
    # the cross-check asks the SAT service about each fact anyway: here only the cheap cases
    return [f for f in out.values() if satisfiable(f.condition, limit=8) is not False]


class Stop(Exception):
    """The concrete walk stops at launch's first error."""


def shown(s: str) -> str:
    s = s.replace(OPAQUE, "")
    return re.sub(UNRESOLVED + r"([^" + UNRESOLVED + r"]*)" + UNRESOLVED, r"$(find-pkg-share \1)", s)


def opaque(s: str) -> bool:
    return OPAQUE in s or UNRESOLVED in s


def merge(cases) -> Cases:
    out: dict[str, Formula] = {}
    for c, v in cases:
        if c == FALSE:
            continue
        out[v] = disj([out[v], c]) if v in out else c
    return [(c, v) for v, c in out.items()]


def present(cases: Cases) -> Formula:
    return disj(c for c, _ in cases)


def when(cases: Cases, pred) -> Formula:
    return disj(c for c, v in cases if pred(v))


def cond_value(v: str) -> Optional[bool]:
    """evaluate_condition_expression."""
    lv = v.strip().lower()
    if lv in ("true", "1"):
        return True
    if lv in ("false", "0"):
        return False
    return None


def typed_bool(v: str):
    """perform_typed_substitution(..., bool): True/False, or the error message."""
    s = "true" if v == "1" else "false" if v == "0" else v
    if s:
        try:
            out = yaml.safe_load(s)
        except Exception:
            return f"Failed to convert '{s}' to '<class 'bool'>': yaml.safe_load() failed"
        if isinstance(out, bool):
            return out
    return f"Cannot convert value '{s}' to '<class 'bool'>'"


def _is_bool_text(s: str) -> bool:
    return s.lower() in ("true", "false", "1", "0")


def _is_float(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def equals(a: str, b: str) -> bool:
    if _is_bool_text(a) and _is_bool_text(b):
        return (a.lower() in ("true", "1")) == (b.lower() in ("true", "1"))
    if _is_float(a) and _is_float(b):
        return math.isclose(float(a), float(b))
    return a == b


def prefix_namespace(base: Optional[str], ns: Optional[str]) -> Optional[str]:
    combined = None
    if base is not None or ns is not None:
        if ns is None:
            combined = base
        elif not base or ns.startswith("/"):
            combined = ns
        else:
            if base == "/":
                base = ""
            combined = base + "/" + ns
        if combined != "/":
            combined = combined.rstrip("/")
    return combined


def make_absolute(ns: Optional[str]) -> Optional[str]:
    if ns is None:
        return None
    return ns if ns.startswith("/") else "/" + ns


def validate_namespace(ns: str) -> Optional[str]:
    """rmw's rules; the message rclpy's NameValidationException prints (None: valid)."""
    def err(msg, i):
        return f"Invalid namespace: {msg}:\n  '{ns}'\n   {' ' * i}^"
    if ns == "":
        return err("namespace must not be empty", 0)
    if not ns.startswith("/"):
        return err("namespace must be absolute, it must lead with a '/'", 0)
    if ns != "/" and ns.endswith("/"):
        return err("namespace must not end with a '/', unless only a '/'", len(ns) - 1)
    for i, c in enumerate(ns):
        if not (c.isascii() and (c.isalnum() or c in "_/")):
            return err("namespace must not contain characters other than alphanumerics, '_', or '/'", i)
    i = ns.find("//")
    if i >= 0:
        return err("namespace must not contain repeated '/'", i + 1)
    m = re.search(r"/(\d)", ns)
    if m:
        return err("namespace must not have a token that starts with a number", m.start(1))
    if len(ns) > 253:
        return err("namespace should not exceed '253'", 252)
    return None


def validate_node_name(n: str) -> Optional[str]:
    def err(msg, i):
        return f"Invalid node name: {msg}:\n  '{n}'\n   {' ' * i}^"
    if n == "":
        return err("node name must not be empty", 0)
    for i, c in enumerate(n):
        if not (c.isascii() and (c.isalnum() or c == "_")):
            return err("node name must not contain characters other than alphanumerics or '_'", i)
    if n[0].isdigit():
        return err("node name must not start with a number", 0)
    if len(n) > 255:
        return err("node name length should not exceed '255'", 254)
    return None


# ------------------------------------------------------------------ scope

class RList:
    """A list held in the launch configurations (``ros_remaps`` / ``global_params``): groups
    copy the dictionary, not the list, so appends are seen by every holder."""
    __slots__ = ("items",)

    def __init__(self):
        self.items: list[tuple[Formula, object]] = []


class Scope:
    """The parts of launch's LaunchContext the analysis follows."""
    __slots__ = ("configs", "remaps", "gparams", "env", "leaks", "opaque")

    def __init__(self):
        self.configs: dict[str, Cases] = {}
        self.remaps: list[tuple[RList, Formula]] = []
        self.gparams: list[tuple[RList, Formula]] = []
        self.env: dict[str, Cases] = {}     # set_env / unset_env (a case "\x00" = unset)
        self.leaks: dict[str, "Leak"] = {}
        # where a Python launch file (not analysed) has run: anything may have been set there
        self.opaque: Formula = FALSE

    def copy(self) -> "Scope":
        c = Scope()
        c.opaque = self.opaque
        c.configs = {k: list(v) for k, v in self.configs.items()}
        c.remaps = list(self.remaps)
        c.gparams = list(self.gparams)
        c.env = {k: list(v) for k, v in self.env.items()}
        c.leaks = dict(self.leaks)
        return c

    def assign(self, other: "Scope") -> None:
        self.configs, self.remaps, self.gparams = other.configs, other.remaps, other.gparams
        self.env, self.leaks, self.opaque = other.env, other.leaks, other.opaque


@dataclass
class Leak:
    """A configuration an <include> set (passed with <arg> or declared in the included file)."""
    name: str
    include: Element
    span: Span
    path: str
    before: Cases           # the value before the include
    after: Cases            # the value the include left
    reported: bool = False


@dataclass
class Unit:
    path: str
    doc: Document
    actions: list
    errors: list            # LoadError, document order
    python: bool = False

    @property
    def error(self) -> Optional[A.LoadError]:
        return self.errors[0] if self.errors else None


# ------------------------------------------------------------------ the walker

class Walker:
    def __init__(self, *, concrete: bool, packages: Mapping[str, str], env: Mapping[str, str],
                 read_file=None, workspace_root: Optional[str] = None, stub_packages: bool = True,
                 installed: Optional[Mapping[str, str]] = None):
        self.concrete = concrete
        self.packages = dict(packages)          # workspace packages: name -> source folder
        self.installed = dict(installed or {})  # AMENT_PREFIX_PATH packages: name -> share folder
        self.env = env
        self.read_file = read_file
        self.root = workspace_root
        self.stub = stub_packages
        self.facts: list[ErrorFact] = []
        self.nodes: list[Node2Fact] = []
        self.executables: list[dict] = []
        self.elements: list[Element] = []
        self.includes: list[IncludeFact] = []
        self.diagnostics: list[Diagnostic] = []
        self.units: dict[str, Unit] = {}
        self.node_names: dict[str, list[Node2Fact]] = {}
        self.visits = 0
        self.budget_hit = False
        self.noted: set = set()
        self.stack: list[str] = []
        self.depth = 0
        self.cur_file: Cases = []
        self.error: Optional[LaunchFact] = None
        self.root_args: dict[str, Cases] = {}
        self.root_path = ""
        self.declared_root: dict[str, Cases] = {}   # the root file's declared args, as set
        self.warnings: list[str] = []
        self.logs: list[str] = []
        self.python_includes: list[str] = []
        self.off: list[dict] = []
        self.given: list[str] = []
        self.free: set[str] = set()
        self.timers: list = []

    # ---------------------------------------------------------------- facts

    def fact(self, code: str, message: str, path: str, span: Span, cond: Formula, severity: Severity = E,
             related=None, launch: tuple[str, str] = ("", "")):
        if cond == FALSE:
            return
        f = LaunchFact(code, severity, message, path, span, cond, list(related or []), launch[0],
                       launch[1] or message)
        self.facts.append(f)
        if self.concrete and cond == TRUE and severity == E and self.error is None:
            self.error = f
            raise Stop()

    def note(self, code: str, message: str, path: str, span: Span, severity: Severity = I):
        key = (code, path, span)
        if key in self.noted:
            return
        self.noted.add(key)
        self.facts.append(LaunchFact(code, severity, message, path, span, TRUE, []))

    # ---------------------------------------------------------------- files

    def read(self, path: str) -> Optional[str]:
        if self.read_file is not None:
            try:
                t = self.read_file(path)
            except Exception:
                t = None
            if t is not None:
                return t
        try:
            if os.path.getsize(path) > 25_000_000:
                return None
            with open(path, encoding="utf-8", errors="replace") as f:
                return f.read()
        except OSError:
            return None

    def exists(self, path: str) -> bool:
        if self.read_file is not None:
            try:
                if self.read_file(path) is not None:
                    return True
            except Exception:
                pass
        return os.path.isfile(path)

    def unit(self, path: str, text: Optional[str] = None) -> Optional[Unit]:
        if path in self.units:
            return self.units[path]
        if path.endswith(".py"):
            if text is None and not self.exists(path):
                return None
            u = Unit(path, None, [], [], python=True)
            self.units[path] = u
            return u
        if text is None:
            text = self.read(path)
            if text is None:
                return None
        doc = parse_launch_file(text, path)
        errors: list = []
        acts: list = []
        if doc.error is not None:
            kind, msg, span = doc.error
            errors.append(A.LoadError(kind, msg, span, path))
        elif doc.root is not None:
            acts, errors = A.parse_description(doc.root, path)
        u = Unit(path, doc, acts, errors)
        self.units[path] = u
        return u

    def load_message(self, path: str, errors: list) -> str:
        """InvalidLaunchFileError's text for a file launch could not load."""
        ext = _extension(path)
        first = errors[0]
        lines = [f" - {first.kind}: {first.launch_text}"]
        py = _python_error(path, self.read(path) if first.kind != "FileNotFoundError" else None)
        if py is not None:
            lines.append(f" - {py}")
        head = "Caught multiple exceptions" if len(lines) > 1 else "Caught exception"
        return f"{head} when trying to load file of format [{ext}]:\n" + "\n".join(lines)

    # ---------------------------------------------------------------- evaluation

    def ev(self, v: Optional[A.Value], sc: Scope, guard: Formula, el: Element) -> Cases:
        """The cases of a parsed value; failures become facts (their cases are dropped)."""
        if v is None or guard == FALSE:
            return []
        return self.ev_parts(v.parts, v, sc, guard, el)

    def ev_parts(self, parts: list, v: A.Value, sc: Scope, guard: Formula, el: Element) -> Cases:
        cases: Cases = [(guard, "")]
        for p in parts:
            if isinstance(p, S.Text):
                cases = [(c, s + p.text) for c, s in cases]
                continue
            new: Cases = []
            for c, s in cases:
                for c2, r in self.sub(p, v, sc, c, el):
                    new.append((c2, s + r))
            cases = merge(new)
            if len(cases) > MAX_CASES:
                cases = self.collapse(cases, el, v.span() or el.span)
        return cases

    def collapse(self, cases: Cases, el: Element, span: Span) -> Cases:
        """Too many values: one unknown value where any of them is (no false errors follow)."""
        self.note(CONDITION_NOT_ANALYSABLE, "too many combinations of arg values to analyse this value: "
                  "tvl-lsp treats it as unknown", el.path, span)
        return [(disj(c for c, _ in cases), OPAQUE)]

    def span_of(self, v: A.Value, sub, el: Element) -> Span:
        s = v.sub_span(sub) if v is not None else None
        return s or el.tag_span or el.span

    def sub(self, sub: S.Sub, v: A.Value, sc: Scope, c: Formula, el: Element) -> Cases:
        name = sub.name
        span = self.span_of(v, sub, el)
        args = sub.args
        path = el.path

        def arg(i: int, g: Formula = c) -> Cases:
            return self.ev_parts(args[i], v, sc, g, el)

        def fail(msg: str, g: Formula, code: str = SUBST_FAILED, friendly: Optional[str] = None,
                 kind: str = "SubstitutionFailure"):
            self.fact(code, friendly or msg, path, span, g, launch=(kind, msg))

        if name == "var":
            out: Cases = []
            defaults = None
            for cn, n in arg(0):
                vals = sc.configs.get(n, [])
                for cv, val in vals:
                    cc = conj([cn, cv])
                    if cc != FALSE:
                        out.append((cc, val))
                        self.check_leak(sc, n, el, span, cc, val)
                missing = conj([cn, neg(present(vals))])
                if missing == FALSE:
                    continue
                if len(args) > 1:
                    if defaults is None:
                        defaults = arg(1, TRUE)
                    out += [(conj([missing, cd]), d) for cd, d in defaults]
                    continue
                if opaque(n):
                    out.append((missing, OPAQUE))
                    continue
                if sc.opaque != FALSE:
                    out.append((conj([missing, sc.opaque]), OPAQUE))
                    missing = conj([missing, neg(sc.opaque)])
                fail(f"launch configuration '{n}' does not exist", missing, UNDEFINED_ARG,
                     f"$(var {n}): no <arg> or <let> named '{n}' is set here (ros2 launch: launch configuration "
                     f"'{n}' does not exist)")
            return merge(out)
        if name == "env":
            out = []
            defaults = arg(1) if len(args) > 1 else None
            for cn, n in arg(0):
                for cv, val in self.env_lookup(sc, n, cn):
                    if val is not None:
                        out.append((cv, val))
                    elif defaults is not None:
                        out += [(conj([cv, cd]), d) for cd, d in defaults]
                    else:
                        fail(f"environment variable '{n}' does not exist", cv, ENV_NOT_SET,
                             f"$(env {n}): environment variable '{n}' is not set (in tvl-lsp's environment; "
                             "ros2 launch fails the same way unless it is set when launching)")
            return merge(out)
        if name in ("find-pkg-share", "find-pkg-prefix"):
            out = []
            for cn, pkg in arg(0):
                r = self.find_package(pkg, name == "find-pkg-share", cn, path, span)
                if r is not None:
                    out.append((cn, r))
            return out
        if name == "exec-in-pkg":
            out = []
            for ce, exe in arg(0):
                for cp, pkg in arg(1, ce):
                    r = self.find_package(pkg, False, cp, path, span)
                    if r is not None:
                        out.append((cp, os.path.join(r, "lib", pkg, exe) if not opaque(r) else OPAQUE))
            return merge(out)
        if name in ("not", "and", "or", "any", "all"):
            # each operand: cases of True/False/None(opaque)
            operands: list[list[tuple[Formula, Optional[bool]]]] = []
            g = c
            for i in range(len(args)):
                vals = []
                for ca, a in arg(i, g):
                    if opaque(a):
                        vals.append((ca, None))
                        continue
                    b = typed_bool(a)
                    if isinstance(b, str):
                        fail(b, ca, SUBST_FAILED, f"$({name} ...): '{a}' is not a boolean ({b})")
                        continue
                    vals.append((ca, b))
                operands.append(vals)
                g = present(vals) if vals else FALSE
                if g == FALSE:
                    return []
            out = []
            for combo in itertools.product(*operands) if operands else [()]:
                cc = conj([c] + [x for x, _ in combo])
                if cc == FALSE:
                    continue
                bs = [b for _, b in combo]
                if any(b is None for b in bs):
                    out.append((cc, OPAQUE))
                    continue
                r = {"not": lambda: not bs[0], "and": lambda: bs[0] and bs[1], "or": lambda: bs[0] or bs[1],
                     "any": lambda: any(bs), "all": lambda: all(bs)}[name]()
                out.append((cc, "true" if r else "false"))
            return merge(out)
        if name in ("equals", "not-equals"):
            out = []
            for ca, a in arg(0):
                for cb, b in arg(1, ca):
                    if opaque(a) or opaque(b):
                        out.append((cb, OPAQUE))
                        continue
                    r = equals(a, b)
                    if name == "not-equals":
                        r = not r
                    out.append((cb, "true" if r else "false"))
            return merge(out)
        if name == "if":
            out = []
            for cc, cv in arg(0):
                if opaque(cv):
                    out.append((cc, OPAQUE))
                    continue
                b = typed_bool(cv)
                if isinstance(b, str):
                    fail(b, cc, SUBST_FAILED, f"$(if ...): '{cv}' is not a boolean ({b})")
                    continue
                if b:
                    out += arg(1, cc)
                elif len(args) > 2:
                    out += arg(2, cc)
                else:
                    out.append((cc, ""))
            return merge(out)
        if name == "eval":
            out = []
            modules: tuple[str, ...] = ("math",)
            if len(args) > 1:
                modules = tuple(m.strip() for m in S.plain(args[1]).split(","))
            for ce, text in arg(0):
                if opaque(text):
                    out.append((ce, OPAQUE))
                    continue
                try:
                    out.append((ce, pyexpr.evaluate(text, modules)))
                except pyexpr.NotAnalysable:
                    self.note(CONDITION_NOT_ANALYSABLE, f"tvl-lsp cannot evaluate '$(eval {shown(text)})' "
                              "without running it; it assumes the value may be anything", path, span)
                    out.append((ce, OPAQUE))
                except pyexpr.EvalFailure as ex:
                    hint = ""
                    m = re.match(r"name '(true|false)' is not defined", ex.message)
                    if m:
                        hint = (f" ($(eval) is Python: the value {m.group(1)} of a $(var) is a name there; compare "
                                f"strings, e.g. '\"$(var x)\" == \"true\"')")
                    self.fact(EVAL_ERROR, f"$(eval '{text}') fails: {ex.kind}: {ex.message}{hint}", path, span, ce,
                              launch=(ex.kind, ex.message))
            return merge(out)
        if name == "dirname":
            return [(conj([c, cf]), os.path.dirname(f)) for cf, f in self.cur_file if conj([c, cf]) != FALSE]
        if name == "filename":
            return [(conj([c, cf]), f) for cf, f in self.cur_file if conj([c, cf]) != FALSE]
        if name == "anon":
            out = []
            for cn, n in arg(0):
                out.append((cn, (n + "_anon").replace(".", "_").replace("-", "_").replace(":", "_")))
            return out
        if name == "command":
            out = []
            for cc, cmd in arg(0):
                out.append((cc, f"$(command {cmd})" if self.concrete else OPAQUE + f"$(command {cmd})"))
            return out
        if name == "find-exec":
            out = []
            for cn, n in arg(0):
                p = shutil.which(n, path=self.env.get("PATH", os.defpath)) if not opaque(n) else OPAQUE
                if p is None:
                    if self.concrete:
                        fail(f"executable '{n}' not found on the PATH", cn)
                    out.append((cn, OPAQUE))
                else:
                    out.append((cn, p))
            return out
        if name == "file-content":
            out = []
            for cn, f in arg(0):
                t = self.read(f) if not opaque(f) else None
                if t is None:
                    if not opaque(f):
                        fail(f"File not found: {f}", cn)
                    out.append((cn, OPAQUE))
                else:
                    out.append((cn, t))
            return out
        if name in ("launch_log_dir", "log_dir"):
            return [(c, OPAQUE + "launch_log_dir")]
        if name == "param":
            out = []
            for cn, n in arg(0):
                found: Cases = []
                for lst, fl in sc.gparams:
                    for ci, item in lst.items:
                        if isinstance(item, tuple) and item[0] == n:
                            found.append((conj([cn, fl, ci]), str(item[1])))
                rest = conj([cn, neg(present(found))])
                out += found
                if rest != FALSE and sc.opaque != FALSE:
                    out.append((conj([rest, sc.opaque]), OPAQUE))
                    rest = conj([rest, neg(sc.opaque)])
                if rest != FALSE:
                    if len(args) > 1:
                        out += arg(1, rest)
                    else:
                        fail(f"parameter '{n}' not found", rest)
            return merge(out)
        return [(c, OPAQUE)]

    def env_lookup(self, sc: Scope, name: str, c: Formula) -> list[tuple[Formula, Optional[str]]]:
        if opaque(name):
            return [(c, OPAQUE)]
        vals = sc.env.get(name)
        out = []
        rest = c
        if vals:
            for cv, val in vals:
                cc = conj([c, cv])
                if cc != FALSE:
                    out.append((cc, None if val == "\x00" else val))
            rest = conj([c, neg(present(vals))])
        if rest != FALSE:
            out.append((rest, self.env.get(name)))
        return out

    def find_package(self, pkg: str, share: bool, c: Formula, path: str, span: Span) -> Optional[str]:
        if opaque(pkg):
            return OPAQUE
        folder = self.packages.get(pkg)
        if folder is not None:
            if share:
                return folder
            return os.path.join(self.root, "install") if self.root else os.path.dirname(os.path.dirname(folder))
        inst = self.installed.get(pkg)
        if inst is not None:
            return inst if share else os.path.dirname(os.path.dirname(inst))
        if not self.concrete:
            return UNRESOLVED + pkg + UNRESOLVED
        if self.stub and pkg and "/" not in pkg:
            prefix = os.path.join(self.root or "/", "install")
            return os.path.join(prefix, "share", pkg) if share else prefix
        searched = [os.path.join(self.root, "install")] if self.root else []
        self.fact(PACKAGE_NOT_FOUND, f"package '{pkg}' not found (not in the workspace nor in AMENT_PREFIX_PATH)",
                  path, span, c, launch=("PackageNotFoundError",
                                         f"\"package '{pkg}' not found, searching: {searched!r}\""))
        return None

    # ---------------------------------------------------------------- configurations

    def set_config(self, sc: Scope, names: Cases, values: Cases, g: Formula, el: Optional[Element] = None) -> None:
        for cn, n in names:
            vals = [(conj([cn, cv]), v) for cv, v in values]
            vals = [(c, v) for c, v in vals if c != FALSE]
            setc = present(vals)
            if setc == FALSE:
                continue
            old = sc.configs.get(n, [])
            keep = [(conj([c, neg(setc)]), v) for c, v in old]
            new = merge(keep + vals)
            if len(new) > MAX_CASES:
                if el is not None:
                    self.note(CONDITION_NOT_ANALYSABLE, f"too many combinations of arg values to analyse the value "
                              f"of '{n}': tvl-lsp treats it as unknown", el.path, el.tag_span or el.span)
                new = [(present(new), OPAQUE)]
            sc.configs[n] = new
            if n in sc.leaks:
                del sc.leaks[n]

    def check_leak(self, sc: Scope, name: str, el: Element, span: Span, c: Formula, value: str) -> None:
        lk = sc.leaks.get(name)
        if lk is None or self.concrete or el.path != self.root_path:
            return
        # the value differs from what it would be without the include
        before = {v: cb for cb, v in lk.before}
        changed = disj(conj([c, ca, neg(before.get(v, FALSE))]) for ca, v in lk.after if v == value)
        if changed == FALSE:
            return
        was = ", ".join(repr(x) for x in sorted({shown(v) for _, v in lk.before}))
        without = f"without the include it would be {was}" if was else \
            "without the include it would not be set (ros2 launch would fail here)"
        self.fact(ARG_LEAK, f"$(var {name}) reads '{shown(value)}', which the <include> on line "
                  f"{lk.include.span.start.line + 1} left behind (ros2 launch does not scope an include's args); "
                  f"{without}: wrap the include in a <group> to keep it out",
                  el.path, span, changed, W, related=[Related(lk.path, lk.span, f"'{name}' is set here")])

    # ---------------------------------------------------------------- conditions

    def condition(self, a, el: Element, sc: Scope, guard: Formula) -> Formula:
        if guard == FALSE:
            return FALSE
        cond = a.cond
        if cond is None:
            return guard
        cases = self.ev(cond.value, sc, guard, el)
        ok = []
        span = cond.value.span() or el.tag_span
        for c, v in cases:
            if opaque(v):
                ok.append(c)
                continue
            b = cond_value(v)
            if b is None:
                unexp = " + ".join(f"<{_CLASS.get(p.name, 'launch.substitutions.text_substitution.TextSubstitution')}"
                                   " object at 0x?>" if isinstance(p, S.Sub) else
                                   "<launch.substitutions.text_substitution.TextSubstitution object at 0x?>"
                                   for p in cond.value.parts)
                exp = v.strip().lower()
                self.fact(INVALID_CONDITION, f"the value of '{cond.kind}' is '{exp}': ros2 launch accepts only "
                          "true, false, 1 or 0 (in any case)", el.path, span, c,
                          launch=("InvalidConditionExpressionError",
                                  f"invalid condition expression, expected one of [true, 1, false, 0] but got '{exp}', "
                                  f"expanded from '{unexp}'"))
            elif b == (cond.kind == "if"):
                ok.append(c)
        return disj(ok)

    # ---------------------------------------------------------------- walking

    def tick(self, el: Element) -> bool:
        self.visits += 1
        if self.visits > MAX_VISITS:
            if not self.budget_hit:
                self.budget_hit = True
                self.facts.append(LaunchFact(BUDGET, W, "the launch file (with its includes) is too large to analyse "
                                             f"completely; analysis stopped after {MAX_VISITS} elements",
                                             el.path, el.tag_span or el.span, TRUE))
            return False
        return True

    def run(self, acts: list, sc: Scope, guard: Formula, emap: dict) -> None:
        self.depth += 1
        try:
            if self.depth > MAX_WALK_DEPTH:
                if acts and not self.budget_hit:
                    self.budget_hit = True
                    el = emap[id(acts[0].entity)]
                    self.facts.append(LaunchFact(BUDGET, W, "groups and includes are nested too deeply to analyse; "
                                                 "the deeper elements are not analysed", el.path,
                                                 el.tag_span or el.span, TRUE))
                return
            for a in acts:
                if guard == FALSE:
                    return
                el = emap[id(a.entity)]
                if not self.tick(el):
                    return
                self.action(a, el, sc, guard, emap)
        finally:
            self.depth -= 1

    def action(self, a, el: Element, sc: Scope, guard: Formula, emap: dict) -> None:
        cond = self.condition(a, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        t = a.tag
        if t == "arg":
            self.arg(a, el, sc, cond)
        elif t == "let":
            self.set_config(sc, self.ev(a.name, sc, cond, el), self.ev(a.value, sc, cond, el), cond, el)
        elif t == "group":
            self.group(a, el, sc, cond, emap)
        elif t == "include":
            self.include(a, el, sc, cond, emap)
        elif t in ("node", "node_container"):
            self.node(a, el, sc, cond, emap)
        elif t == "executable":
            self.executable(a, el, sc, cond)
        elif t in ("push_ros_namespace", "push-ros-namespace"):
            self.push_ns(a, el, sc, cond)
        elif t == "set_remap":
            src = self.ev(a.src, sc, cond, el)
            dst = self.ev(a.dst, sc, cond, el)
            items = [(conj([c1, c2]), (s, d, el)) for c1, s in src for c2, d in dst]
            self.append_list(sc, "remaps", items, cond)
        elif t == "set_parameter":
            names = self.ev(a.name, sc, cond, el)
            vals = self.ev(a.value, sc, cond, el)
            items = [(conj([c1, c2]), (n, _yaml_value(v))) for c1, n in names for c2, v in vals]
            self.append_list(sc, "gparams", items, cond)
        elif t == "set_parameters_from_file":
            for c, f in self.ev(a.filename, sc, cond, el):
                self.append_list(sc, "gparams", [(c, f)], c)
        elif t in ("set_env", "unset_env", "append_env"):
            self.env_action(a, el, sc, cond)
        elif t == "log":
            vals = self.ev(a.message, sc, cond, el)
            if self.concrete and vals:
                self.logs.append(shown(vals[0][1]))
        elif t in ("timer", "ros_timer"):
            if isinstance(a.period, A.Value):
                self.ev(a.period, sc, cond, el)
            self.timers.append((a, el, sc, cond, emap))
        elif t == "reset":
            self.reset(a, el, sc, cond)
        elif t == "load_composable_node":
            self.ev(a.target, sc, cond, el)
            for comp in a.composables:
                self.composable(comp, emap, sc, cond, None)
        elif isinstance(a, A.SimpleA):
            for v in a.values:
                self.ev(v, sc, cond, el)

    # -- lists in the configurations
    def append_list(self, sc: Scope, which: str, items: list, cond: Formula) -> None:
        items = [(c, x) for c, x in items if c != FALSE]
        if not items:
            return
        refs = getattr(sc, which)
        at = present(items)
        for lst, f in refs:
            for c, x in items:
                cc = conj([c, f])
                if cc != FALSE:
                    lst.items.append((cc, x))
        missing = conj([at, neg(disj(f for _, f in refs))])
        if missing != FALSE:
            new = RList()
            for c, x in items:
                cc = conj([c, missing])
                if cc != FALSE:
                    new.items.append((cc, x))
            refs.append((new, missing))

    def list_items(self, sc: Scope, which: str, c: Formula) -> list:
        out = []
        for lst, f in getattr(sc, which):
            for ci, x in lst.items:
                cc = conj([c, f, ci])
                if cc != FALSE:
                    out.append((cc, x))
        return out

    # -- <arg>
    def arg(self, a: A.ArgA, el: Element, sc: Scope, cond: Formula) -> None:
        name = a.name
        vals = sc.configs.get(name, [])
        have = present(vals)
        missing = conj([cond, neg(have)])
        if missing != FALSE:
            if a.default is None:
                span = el.attrs["name"].value_span if "name" in el.attrs else el.tag_span
                if sc.opaque != FALSE:
                    self.set_config(sc, [(TRUE, name)], [(conj([missing, sc.opaque]), OPAQUE)], missing)
                    missing = conj([missing, neg(sc.opaque)])
                self.fact(UNSET_ARG, f"arg '{name}' has no default and nothing sets it: ros2 launch needs "
                          f"{name}:=... (Required launch argument \"{name}\" was not provided)", el.path, span, missing,
                          launch=("RuntimeError", f'Required launch argument "{name}" was not provided.'))
                # the command line sets it (the warning says so); its value is unknown here
                self.set_config(sc, [(TRUE, name)], [(missing, OPAQUE)], missing)
            else:
                d = self.ev(a.default, sc, missing, el)
                self.set_config(sc, [(TRUE, name)], d, missing)
        if a.default is not None and not self.concrete and name in sc.leaks and have != FALSE:
            self.leaked_default(a, el, sc, conj([cond, have]), vals)
        if a.choices is not None:
            span = el.attrs["name"].value_span if "name" in el.attrs else el.tag_span
            for c, v in sc.configs.get(name, []):
                cc = conj([c, cond])
                if cc == FALSE or opaque(v) or v in a.choices:
                    continue
                msg = f'Argument "{name}" provided value "{v}" is not valid. Valid options are: {a.choices}'
                self.fact(INVALID_CHOICE, msg, el.path, span, cc, launch=("RuntimeError", msg))
        if el.path == self.root_path and el.include_depth == 0:
            self.declared_root[name] = [(conj([c, cond]), v) for c, v in sc.configs.get(name, [])
                                        if conj([c, cond]) != FALSE]

    def leaked_default(self, a: A.ArgA, el: Element, sc: Scope, c: Formula, vals: Cases) -> None:
        """A declaration whose default is not used because an earlier include of the analysed
        file left a value behind (the include's args and defaults are not scoped)."""
        lk = sc.leaks[a.name]
        if lk.path != self.root_path and lk.include.path != self.root_path:
            return
        defaults = {v: cd for cd, v in self.ev(a.default, sc, c, el)}
        before = {v: cb for cb, v in lk.before}
        changed = FALSE
        shown_vals = set()
        for cv, v in vals:
            cc = conj([c, cv, neg(before.get(v, FALSE)), neg(defaults.get(v, FALSE))])
            if cc != FALSE:
                changed = disj([changed, cc])
                shown_vals.add(shown(v))
        if changed == FALSE:
            return
        span = el.attrs["name"].value_span if "name" in el.attrs else el.tag_span
        dflt = ", ".join(sorted(shown(v) for v in defaults)) or "?"
        self.fact(ARG_LEAK, f"arg '{a.name}' takes {', '.join(repr(v) for v in sorted(shown_vals))}, which the "
                  f"<include> on line {lk.include.span.start.line + 1} of {os.path.basename(lk.include.path)} left "
                  f"behind, instead of its default '{dflt}' (ros2 launch does not scope an include's args: wrap the "
                  "earlier include in a <group>)", el.path, span, changed, W,
                  related=[Related(lk.path, lk.span, f"'{a.name}' is set here")])

    # -- <group>
    def group(self, g: A.GroupA, el: Element, sc: Scope, cond: Formula, emap: dict) -> None:
        scoped = bool(g.scoped)
        forwarding = bool(g.forwarding)
        if not scoped:
            for k in g.keeps or []:
                kel = emap.get(id(k.entity), el)
                self.set_config(sc, self.ev(k.name, sc, cond, kel), self.ev(k.value, sc, cond, kel), cond)
            self.run(g.actions, sc, cond, emap)
            return
        saved = sc.copy()
        inner = sc  # the group works on the same object (launch pushes a copy and pops it back)
        try:
            if forwarding:
                for k in g.keeps or []:
                    kel = emap.get(id(k.entity), el)
                    self.set_config(inner, self.ev(k.name, inner, cond, kel), self.ev(k.value, inner, cond, kel),
                                    cond)
            else:
                kept = []
                for k in g.keeps or []:
                    kel = emap.get(id(k.entity), el)
                    kept.append((self.ev(k.name, inner, cond, kel), self.ev(k.value, inner, cond, kel)))
                self.clear(inner, cond)
                for names, vals in kept:
                    self.set_config(inner, names, vals, cond)
            self.run(g.actions, inner, cond, emap)
        finally:
            self.restore(sc, saved, cond)

    def clear(self, sc: Scope, cond: Formula) -> None:
        """ResetLaunchConfigurations / ResetEnvironment under ``cond``."""
        nc = neg(cond)
        sc.configs = {k: [(conj([c, nc]), v) for c, v in vs if conj([c, nc]) != FALSE]
                      for k, vs in sc.configs.items()}
        sc.configs = {k: v for k, v in sc.configs.items() if v}
        sc.remaps = [(lst, conj([f, nc])) for lst, f in sc.remaps if conj([f, nc]) != FALSE]
        sc.gparams = [(lst, conj([f, nc])) for lst, f in sc.gparams if conj([f, nc]) != FALSE]
        sc.env = {}
        sc.leaks = {}

    def restore(self, sc: Scope, saved: Scope, cond: Formula) -> None:
        """PopLaunchConfigurations.  Everything inside the group ran under ``cond``, so where
        ``cond`` is false nothing changed: the saved copy is the state everywhere.  (The
        ``ros_remaps`` / ``global_params`` lists themselves are shared, so what was appended to
        an outer list stays, as in launch.)"""
        sc.assign(saved)

    def reset(self, a: A.ResetA, el: Element, sc: Scope, cond: Formula) -> None:
        kept = [(self.ev(k.name, sc, cond, el), self.ev(k.value, sc, cond, el)) for k in a.keeps or []]
        if a.keeps is None:
            self.clear(sc, cond)
            return
        nc = neg(cond)
        sc.configs = {k: [(conj([c, nc]), v) for c, v in vs if conj([c, nc]) != FALSE]
                      for k, vs in sc.configs.items()}
        sc.configs = {k: v for k, v in sc.configs.items() if v}
        for names, vals in kept:
            self.set_config(sc, names, vals, cond)

    # -- environment
    def env_action(self, a: A.EnvA, el: Element, sc: Scope, cond: Formula) -> None:
        names = self.ev(a.name, sc, cond, el)
        if a.tag == "unset_env":
            vals = [(cond, "\x00")]
        else:
            vals = self.ev(a.value, sc, cond, el)
            if isinstance(a.prepend, A.Value):
                self.ev(a.prepend, sc, cond, el)
            if a.separator is not None:
                self.ev(a.separator, sc, cond, el)
        for cn, n in names:
            new = []
            for cv, v in vals:
                cc = conj([cn, cv])
                if cc == FALSE:
                    continue
                if a.tag == "append_env":
                    sep = os.pathsep
                    for co, old in self.env_lookup(sc, n, cc):
                        if old:
                            new.append((co, (v + sep + old) if a.prepend is True else (old + sep + v)))
                        else:
                            new.append((co, v))
                else:
                    new.append((cc, v))
            setc = present(new)
            if setc == FALSE:
                continue
            old = sc.env.get(n, [])
            sc.env[n] = merge([(conj([c, neg(setc)]), v) for c, v in old] + new)

    # -- push_ros_namespace
    def push_ns(self, a: A.PushNsA, el: Element, sc: Scope, cond: Formula) -> None:
        pushed = self.ev(a.namespace, sc, cond, el)
        base = sc.configs.get("ros_namespace", [])
        out = []
        span = a.namespace.span() or el.tag_span
        for cp, p in pushed:
            for cb, b in base + [(conj([cp, neg(present(base))]), None)]:
                cc = conj([cp, cb])
                if cc == FALSE:
                    continue
                ns = make_absolute(prefix_namespace(b, p))
                if opaque(p) or (b is not None and opaque(b)):
                    out.append((cc, ns))
                    continue
                err = validate_namespace(ns)
                if err:
                    self.fact(INVALID_NAMESPACE, f"the namespace pushed here, '{ns}', is invalid: "
                              f"{err.splitlines()[0].split(': ', 1)[1]}", el.path, span, cc,
                              launch=("SubstitutionFailure", "The resulting namespace is invalid: "
                                      f"[previous_namespace='{b}', pushed_namespace='{p}']"))
                    continue
                out.append((cc, ns))
        self.set_config(sc, [(TRUE, "ros_namespace")], out, cond)

    # -- <executable>
    def executable(self, a: A.ExecA, el: Element, sc: Scope, cond: Formula) -> None:
        names = self.ev(a.name, sc, cond, el) if a.name is not None else [(cond, "")]
        cmd = self.cmd(a.cmd, a.cmd_value, sc, cond, el)
        if a.cwd is not None:
            self.ev(a.cwd, sc, cond, el)
        for kn, kv in a.env:
            self.ev(kn, sc, cond, el)
            self.ev(kv, sc, cond, el)
        if self.concrete and cond == TRUE:
            n = names[0][1] if names else ""
            self.exec_counter = getattr(self, "exec_counter", 0) + 1
            base = n or (os.path.basename(cmd[0][1][0]) if cmd and cmd[0][1] else "")
            self.executables.append({"name": shown(base), "process_name": f"{shown(base)}-{self.exec_counter}",
                                     "cmd": [shown(x) for x in (cmd[0][1] if cmd else [])], "source": el.path})

    def cmd(self, cmd: list, v: A.Value, sc: Scope, cond: Formula, el: Element) -> list:
        """Cases of the command line (a list of words)."""
        cases: list = [(cond, [])]
        for word in cmd:
            vals = self.ev_parts(word, v, sc, cond, el) if word else [(cond, "")]
            new = []
            for c, words in cases:
                for c2, w in vals:
                    cc = conj([c, c2])
                    if cc != FALSE:
                        new.append((cc, words + [w]))
            cases = new[:MAX_CASES]
        return cases

    # -- <node>
    def node(self, a: A.NodeA, el: Element, sc: Scope, cond: Formula, emap: dict) -> None:
        path = el.path
        name_cases = self.ev(a.name, sc, cond, el) if a.name is not None else [(cond, None)]
        ok_names = []
        for c, n in name_cases:
            if n is None or opaque(n):
                ok_names.append((c, n))
                continue
            err = validate_node_name(n)
            if err:
                self.fact(INVALID_NODE_NAME, f"the node name '{n}' is invalid: {err.splitlines()[0].split(': ', 1)[1]}",
                          path, a.name.span() or el.tag_span, c, launch=("InvalidNodeNameException", err))
                continue
            ok_names.append((c, n))
        if not ok_names:
            return
        g = present(ok_names)
        ns_cases = self.ev(a.namespace, sc, g, el) if a.namespace is not None else [(g, None)]
        base = sc.configs.get("ros_namespace", [])
        full_ns = []
        for cn, n in ns_cases:
            for cb, b in base + [(conj([cn, neg(present(base))]), None)]:
                cc = conj([cn, cb])
                if cc == FALSE:
                    continue
                ns = make_absolute(prefix_namespace(b, n))
                if ns is not None and not opaque(ns):
                    err = validate_namespace(ns)
                    if err:
                        self.fact(INVALID_NAMESPACE, f"the node's namespace '{ns}' is invalid: "
                                  f"{err.splitlines()[0].split(': ', 1)[1]}", path,
                                  a.namespace.span() if a.namespace is not None else el.tag_span, cc,
                                  launch=("InvalidNamespaceException", err))
                        continue
                full_ns.append((cc, ns))
        g = present(full_ns)
        if g == FALSE:
            return
        params, files = self.node_params(a.params, sc, g, el, emap)
        remaps = self.list_items(sc, "remaps", g)
        own = []
        for r in a.remaps:
            rel = emap.get(id(r.entity), el)
            for c1, s in self.ev(r.src, sc, g, rel):
                for c2, d in self.ev(r.dst, sc, c1, rel):
                    own.append((c2, (s, d, rel)))
        # ExecuteProcess.prepare: the command line (package lookup, arguments)
        pkgs = self.ev(a.package, sc, g, el) if a.package is not None else [(g, None)]
        exes = self.ev(a.executable, sc, g, el)
        okp = []
        for cp, p in pkgs:
            for ce, x in exes:
                cc = conj([cp, ce])
                if cc == FALSE:
                    continue
                if p is not None and not opaque(p) and self.find_package(
                        p, False, cc, path, a.package.span() or el.tag_span) is None:
                    continue
                okp.append((cc, p, x))
        if a.args is not None:
            self.ev(a.args, sc, g, el)
        if a.ros_args is not None:
            self.ev(a.ros_args, sc, g, el)
        kind = a.tag
        for cp, p, x in okp:
            for cn, n in ok_names:
                for cs, ns in full_ns:
                    cc = conj([cp, cn, cs])
                    if cc == FALSE:
                        continue
                    full = ""
                    if n is not None:
                        full = (ns.rstrip("/") if ns else "") + "/" + n
                    nf = self.make_node(full, p or "", x, ns, el, cc, remaps + own, kind,
                                        {k: v for k, (c, v) in params.items() if conj([c, cc]) != FALSE},
                                        [shown(f) for c, f in files if conj([c, cc]) != FALSE])
                    self.add_node(nf, a.name if n is not None else None, el, full)
        for comp in a.composables:
            self.composable(comp, emap, sc, g, None)

    def composable(self, comp: A.ComposableA, emap: dict, sc: Scope, guard: Formula, container) -> None:
        """A composable node: the load request launch sends to its container."""
        el = emap.get(id(comp.entity))
        if el is None:
            return
        cond = self.condition(comp, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        pkgs = self.ev(comp.package, sc, cond, el)
        self.ev(comp.plugin, sc, cond, el)
        names = self.ev(comp.name, sc, cond, el)
        nss = self.ev(comp.namespace, sc, cond, el) if comp.namespace is not None else [(cond, None)]
        base = sc.configs.get("ros_namespace", [])
        remaps = self.list_items(sc, "remaps", cond)
        own = []
        for r in comp.remaps:
            rel = emap.get(id(r.entity), el)
            for c1, s in self.ev(r.src, sc, cond, rel):
                for c2, d in self.ev(r.dst, sc, c1, rel):
                    own.append((c2, (s, d, rel)))
        params, files = self.node_params(comp.params, sc, cond, el, emap, composable=True)
        for cp, p in pkgs:
            for cn, n in names:
                for cs, ns in nss:
                    for cb, b in base + [(neg(present(base)), None)]:
                        cc = conj([cp, cn, cs, cb])
                        if cc == FALSE:
                            continue
                        full_ns = make_absolute(prefix_namespace(b, ns))
                        full = (full_ns.rstrip("/") if full_ns else "") + "/" + n
                        nf = self.make_node(full, p, "", full_ns, el, cc, remaps + own, "composable_node",
                                            {k: v for k, (c, v) in params.items() if conj([c, cc]) != FALSE}, [])
                        self.add_node(nf, comp.name, el, full)

    def make_node(self, full: str, pkg: str, exe: str, ns: Optional[str], el: Element, cc: Formula, remaps: list,
                  kind: str, params: dict, files: list) -> "Node2Fact":
        """A node fact; its remap cases in launch's order (the first rule for a name wins in ROS 2)."""
        rcases = []
        earlier: dict[str, Formula] = {}
        for c, (f, t, rel) in remaps:
            here = conj([c, cc])
            if here == FALSE:
                continue
            f2, t2 = shown(f), shown(t)
            rcases.append(RemapCase(f2, t2, conj([here, neg(earlier.get(f2, FALSE))]), rel))
            earlier[f2] = disj([earlier.get(f2, FALSE), here])
        return Node2Fact(name=shown(full), pkg=shown(pkg), type=shown(exe), namespace=shown(ns or "/"), element=el,
                         condition=cc, path=el.path, args="",
                         remaps=[(shown(f), shown(t)) for c, (f, t, _) in remaps if conj([c, cc]) != FALSE],
                         remap_cases=rcases, package=shown(pkg), executable=shown(exe),
                         ns=shown(ns) if ns is not None else None, kind=kind, params=params, param_files=files,
                         source=el.path)

    def add_node(self, nf: "Node2Fact", name_value, el: Element, full: str) -> None:
        if full and not opaque(full) and not full.endswith("/"):
            for other in self.node_names.get(full, []):
                both = conj([other.condition, nf.condition])
                oel = other.element
                self.fact(DUPLICATE_NODE, f"two nodes named [{shown(full)}] are started: ros2 launch starts both (it "
                          "only warns) but ROS 2 requires node names to be unique", el.path,
                          (name_value.span() if name_value is not None else None) or el.tag_span, both, W,
                          related=[(other.path, oel.attrs["name"].value_span if "name" in oel.attrs else oel.span,
                                    "the other node with this name")])
            self.node_names.setdefault(full, []).append(nf)
        self.nodes.append(nf)

    def node_params(self, params: list, sc: Scope, g: Formula, el: Element, emap: dict, composable: bool = False):
        """{name: (condition, value)} of the inline params (concrete values), and the files.
        A missing parameter file is a warning for a node (launch skips it), an error for a
        composable node (launch opens it to build the load request)."""
        out: dict = {}
        files: list = []
        for item in params:
            if isinstance(item, A.ParamFileA):
                pel = emap.get(id(item.entity), el)
                pel.condition = disj([pel.condition, g])
                for c, f in self.ev(item.path, sc, g, pel):
                    if opaque(f):
                        continue
                    allow = item.allow_substs
                    if isinstance(allow, A.Value):
                        vals = [(ca, typed_bool(x)) for ca, x in self.ev(allow, sc, c, pel) if not opaque(x)]
                        allow_c = disj(ca for ca, b in vals if b is True)
                    else:
                        allow_c = c if allow else FALSE
                    if allow_c != FALSE:
                        self.param_file_substs(f, item, sc, allow_c, pel)
                        c = conj([c, neg(allow_c)])
                        if c == FALSE:
                            files.append((allow_c, f))
                            continue
                        files.append((allow_c, f))
                    if not self.exists(f) and not self.concrete and not self.in_workspace(f):
                        continue  # a file of the machine that launches (e.g. $(env HOME)/...): unknown here
                    if not self.exists(f) and composable:
                        self.fact(FILE_NOT_FOUND, f"the parameter file '{f}' does not exist: ros2 launch fails to load "
                                  "the composable node", pel.path, item.path.span() or pel.tag_span, c,
                                  launch=("FileNotFoundError", f"[Errno 2] No such file or directory: '{f}'"))
                        continue
                    if not self.exists(f):
                        self.fact(PARAM_FILE_NOT_FOUND, f"the parameter file '{f}' does not exist: ros2 launch starts "
                                  "the node without it (Parameter file path is not a file)", pel.path,
                                  item.path.span() or pel.tag_span, c, W)
                        if self.concrete and c == TRUE:
                            self.warnings.append(f"Parameter file path is not a file: {f}")
                        continue
                    files.append((c, f))
                continue
            for p in item:
                self.param(p, "", sc, g, el, emap, out)
        return out, files

    def param_file_substs(self, f: str, item: A.ParamFileA, sc: Scope, c: Formula, pel: Element) -> None:
        """``<param from=... allow_substs="true"/>``: launch reads the file and evaluates the
        substitutions in it (a missing file is then an error, not a warning)."""
        span = item.path.span() or pel.tag_span
        text = self.read(f)
        if text is None and not self.concrete and not self.in_workspace(f):
            return
        if text is None:
            self.fact(FILE_NOT_FOUND, f"the parameter file '{f}' does not exist (with allow_substs launch reads "
                      "it, and fails)", pel.path, span, c,
                      launch=("FileNotFoundError", f"[Errno 2] No such file or directory: '{f}'"))
            return
        if "$(" not in text:
            return
        try:
            parts = S.parse(text)
        except S.SubstSyntaxError as ex:
            self.fact(SUBST_SYNTAX, f"the parameter file '{f}' has a malformed substitution: {ex}", pel.path, span,
                      c, launch=("UnexpectedCharacters", str(ex)))
            return
        for sub in S.walk(parts):
            if sub.name not in A.SUBSTITUTIONS:
                self.fact(SUBST_UNKNOWN, f"the parameter file '{f}' uses an unknown substitution $({sub.name})",
                          pel.path, span, c, launch=("RuntimeError", f"Unknown substitution: {sub.name}"))
                return
        v = A.Value(parts, None, item.entity)
        for cv, out in self.ev(v, sc, c, pel):
            if opaque(out):
                continue
            try:
                yaml.safe_load(out)
            except Exception:
                self.fact(INVALID_VALUE, f"the parameter file '{f}' is not valid YAML once its substitutions are "
                          "made", pel.path, span, cv,
                          launch=("SubstitutionFailure", "The substituted parameter file is not a valid yaml file"))

    def param(self, p: A.ParamA, prefix: str, sc: Scope, g: Formula, el: Element, emap: dict, out: dict) -> None:
        pel = emap.get(id(p.entity), el)
        pel.condition = disj([pel.condition, g])
        for cn, n in self.ev(p.name, sc, g, pel):
            key = prefix + n
            if p.nested is not None:
                for q in p.nested:
                    self.param(q, key + ".", sc, cn, el, emap, out)
                continue
            v = p.value
            if isinstance(v, A.Value):
                # parse_if_substitutions: plain text stays the string YAML gave; a value with
                # substitutions is typed by YAML once substituted
                plain = S.is_text(v.parts)
                for cv, s in self.ev(v, sc, cn, pel):
                    out[key] = (cv, s if p.type == "str" or plain else _yaml_value(s))
            elif isinstance(v, list):
                vals = []
                for x in v:
                    if isinstance(x, A.Value):
                        cs = self.ev(x, sc, cn, pel)
                        vals.append(cs[0][1] if cs else "")
                    else:
                        vals.append(x)
                out[key] = (cn, vals)
            else:
                out[key] = (cn, v)

    # -- <include>
    def include(self, a: A.IncludeA, el: Element, sc: Scope, cond: Formula, emap: dict) -> None:
        files = self.ev(a.file, sc, cond, el)
        span = a.file.span() or el.tag_span
        for c, f in files:
            inc = IncludeFact(el, shown(f), c, False)
            self.includes.append(inc)
            if UNRESOLVED in f or OPAQUE in f:
                el.unresolved = True
                m = re.search(UNRESOLVED + "([^" + UNRESOLVED + "]*)" + UNRESOLVED, f)
                inc.package = m.group(1) if m else None
                continue
            path = os.path.abspath(f)
            if path in self.stack:
                self.fact(INCLUDE_CYCLE, f"include cycle: {' -> '.join(os.path.basename(p) for p in self.stack)} -> "
                          f"{os.path.basename(path)} (ros2 launch recurses until it fails)", el.path, span, c,
                          launch=("RecursionError", "maximum recursion depth exceeded"))
                continue
            if len(self.stack) > MAX_INCLUDE_DEPTH:
                self.fact(INCLUDE_TOO_DEEP, f"includes are nested more than {MAX_INCLUDE_DEPTH} deep; not followed",
                          el.path, span, c, W)
                el.unresolved = True
                continue
            u = self.unit(path)
            if u is None and path.endswith(".py") and self.concrete:
                u = Unit(path, None, [], [], python=True)
            if u is None and not self.concrete and not self.in_workspace(path):
                el.unresolved = True   # e.g. an installed package's file: not on this machine
                continue
            if u is None:
                ext = _extension(path)
                err = f"[Errno 2] No such file or directory: '{path}'"
                self.fact(INCLUDE_NOT_FOUND, f"the included file {path} does not exist", el.path, span, c,
                          launch=("InvalidLaunchFileError",
                                  f"Caught multiple exceptions when trying to load file of format [{ext}]:\n"
                                  f" - FileNotFoundError: {err}\n - FileNotFoundError: {err}"))
                continue
            if u.python or path.endswith(".py"):
                if path not in self.python_includes:
                    self.python_includes.append(path)
                if self.concrete:
                    self.fact(PYTHON_INCLUDE, f"{path} is a Python launch file: tvl-lsp does not execute it; what "
                              "it starts and everything after it is not known", el.path, span, c, E,
                              launch=("NotAnalysed", f"Python launch file not executed: {path}"))
                self.fact(PYTHON_INCLUDE, f"{os.path.basename(path)} is a Python launch file: tvl-lsp does not "
                          "execute it, so the nodes it starts and the args it sets are not analysed", el.path, span,
                          c, I)
                sc.opaque = disj([sc.opaque, c])
                el.unresolved = True
                inc.followed = False
                continue
            if u.errors:
                first = u.errors[0]
                self.fact(INCLUDE_INVALID, f"ros2 launch cannot load {os.path.basename(path)}: {first.message}",
                          el.path, span, c,
                          related=[(e.path or path, e.span, e.message) for e in u.errors[:3]],
                          launch=("InvalidLaunchFileError", self.load_message(path, u.errors)))
                continue
            inc.followed = True
            el.resolved_file = path
            self.include_one(a, el, sc, c, path, u, emap, inc)

    def include_one(self, a: A.IncludeA, el: Element, sc: Scope, c: Formula, path: str, u: Unit, emap: dict,
                    inc: IncludeFact) -> None:
        # locals: the included file (they stay after the include)
        nc = neg(c)
        self.cur_file = merge([(conj([x, nc]), f) for x, f in self.cur_file] + [(c, path)])
        # the required-argument check, ahead of running the file
        names = []
        for ia in a.args:
            iel = emap.get(id(ia.entity), el)
            ns = self.ev(ia.name, sc, c, iel)
            names.append(ns[0][1] if len(ns) == 1 else (ns[0][1] if ns else ""))
        self.check_required(u, names, el, c, self.aspan(el, "file"), root=False)
        # the args, as SetLaunchConfiguration actions in order
        before = {}
        for ia in a.args:
            iel = emap.get(id(ia.entity), el)
            iel.condition = disj([iel.condition, c])
            ncases = self.ev(ia.name, sc, c, iel)
            vcases = self.ev(ia.value, sc, c, iel)
            for _, n in ncases:
                before.setdefault(n, list(sc.configs.get(n, [])))
            self.set_config(sc, ncases, vcases, c)
        # the file itself, in the same scope
        iemap: dict = {}
        root = make_elements(u.doc.root, path, el, el.include_depth + 1, iemap, self.elements)
        root.parent = el
        root.condition = disj([root.condition, c])
        self.stack.append(path)
        nfacts = len(self.includes)
        before_all = {k: list(v) for k, v in sc.configs.items()}
        try:
            self.run(u.actions, sc, c, iemap)
        finally:
            self.stack.pop()
        inc.children = self.includes[nfacts:]
        del self.includes[nfacts:]
        # what leaked (only tracked for the analysed file's own includes)
        if el.include_depth == 0 and el.path == self.root_path:
            for n, after in sc.configs.items():
                if n in ("ros_namespace",) or n.startswith("anon"):
                    continue
                old = before.get(n, before_all.get(n, []))
                if sorted(map(repr, after)) == sorted(map(repr, old)):
                    continue
                span = self.leak_span(a, emap, el, n)
                sc.leaks[n] = Leak(n, el, span[1], span[0], old, after)

    def leak_span(self, a: A.IncludeA, emap: dict, el: Element, name: str) -> tuple[str, Span]:
        for ia in a.args:
            if S.plain(ia.name.parts) == name:
                iel = emap.get(id(ia.entity), el)
                return iel.path, (ia.name.span() or iel.tag_span)
        return el.path, el.tag_span or el.span

    def in_workspace(self, path: str) -> bool:
        """Is ``path`` inside a package of the workspace (where a missing file is a mistake, not
        just a file of another machine)?"""
        p = os.path.realpath(path)
        return any(p.startswith(os.path.realpath(f).rstrip("/") + "/") for f in self.packages.values())

    def aspan(self, el: Element, name: str) -> Span:
        at = el.attrs.get(name)
        return at.value_span if at is not None else (el.tag_span or el.span)

    # -- the required-argument check (IncludeLaunchDescription.execute)
    def check_required(self, u: Unit, given: list[str], el: Element, c: Formula, span: Span, root: bool) -> list:
        """IncludeLaunchDescription's check of required args; returns the names it reported."""
        reported = []
        declared = self.lookahead(u)
        names = list(given)
        for arg, chain in declared:
            if arg.conditional or arg.action.default is not None:
                continue
            argument_names = names
            for inc in chain or []:
                argument_names.extend(self.static_arg_names(inc))
            if arg.action.name in argument_names:
                continue
            if root and arg.action.name in self.free:
                continue
            a = arg.action
            reported.append(a.name)
            msg = (f"Included launch description missing required argument '{a.name}' (description: "
                   f"'{a.described}'), given: [{', '.join(argument_names)}]")
            if root:
                if self.concrete:
                    self.fact(UNSET_ARG, msg, el.path, span, c, launch=("RuntimeError", msg))
                else:
                    aspan = a.entity.attrs["name"].value_span if "name" in a.entity.attrs else a.entity.tag_span
                    self.fact(UNSET_ARG, f"arg '{a.name}' has no default: ros2 launch needs {a.name}:=... on the "
                              "command line", a.entity.path, aspan, c, W, launch=("RuntimeError", msg))
            else:
                where = "" if not chain else f" (in {os.path.basename(a.entity.path)}, included by it)"
                self.fact(UNSET_ARG, f"{os.path.basename(u.path)} requires the arg '{a.name}'{where}, which this "
                          "<include> does not pass (an arg with no default must be passed explicitly, even if it "
                          "is set here)", el.path, span, c,
                          related=[(a.entity.path, a.entity.attrs["name"].value_span if "name" in a.entity.attrs
                                    else a.entity.tag_span, f"'{a.name}' is declared here without a default")],
                          launch=("RuntimeError", msg))
        return reported

    def lookahead(self, u: Unit) -> list:
        key = u.path
        cache = self.__dict__.setdefault("_lookahead_cache", {})
        if key not in cache:
            cache[key] = self._lookahead(u)
        return cache[key]

    def _lookahead(self, u: Unit) -> list:
        """LaunchDescription.get_launch_arguments_with_include_launch_description_actions: the
        declared args of a file and of the files it includes (as far as they can be loaded
        without a context), each with the chain of includes it is behind and whether it is
        "conditionally included" -- which launch decides only for the direct sub-entities of an
        action with a condition (an include's are behind its launch description: never)."""
        out: list = []
        seen: set[str] = set()
        visiting: set[str] = {u.path}

        def process(ents: list, conditional: bool, chain) -> None:
            for a in ents:
                if isinstance(a, A.ArgA):
                    if a.name in seen:
                        continue
                    seen.add(a.name)
                    out.append((_Declared(a, conditional or a.cond is not None), chain))
                if isinstance(a, A.ResetA):
                    return
                nxt = chain
                if isinstance(a, A.IncludeA):
                    if nxt is None:
                        nxt = []
                    nxt.append(a)
                subs = self.sub_entities(a, visiting)
                if isinstance(a, A.TimerA):
                    process(subs, True, nxt)
                elif isinstance(a, _LD) or getattr(a, "cond", None) is None:
                    process(subs, False, nxt)
                else:
                    process(subs, True, nxt)

        process(u.actions, False, None)
        return out

    def sub_entities(self, a, visiting: set) -> list:
        if isinstance(a, _LD):
            return a.actions
        if isinstance(a, A.GroupA):
            if bool(a.scoped) and not bool(a.forwarding):
                return [A.ResetA("reset", a.entity)] + list(a.actions)
            return list(a.actions)
        if isinstance(a, A.TimerA):
            return list(a.actions)
        if isinstance(a, A.IncludeA):
            f = self.static_eval(a.file)
            if f is None:
                return []
            p = os.path.abspath(f)
            if p in visiting or len(visiting) > 64:
                return []
            u = self.unit(p)
            if u is None or u.python or u.errors:
                return []
            visiting.add(p)
            return [_LD(list(u.actions))]
        return []

    def static_arg_names(self, inc: A.IncludeA) -> list[str]:
        out = []
        for ia in inc.args:
            n = self.static_eval(ia.name)
            if n is not None:
                out.append(n)
        return out

    def static_eval(self, v: A.Value) -> Optional[str]:
        """A value evaluated without a launch context (launch's look-ahead): $(var), $(dirname)
        and the like fail."""
        out = []

        def go(parts) -> bool:
            for p in parts:
                if isinstance(p, S.Text):
                    out.append(p.text)
                    continue
                if p.name in ("find-pkg-share", "find-pkg-prefix") and len(p.args) == 1 and S.is_text(p.args[0]):
                    pkg = S.plain(p.args[0])
                    folder = self.packages.get(pkg) or self.installed.get(pkg)
                    if folder is None:
                        if self.concrete and self.stub:
                            folder = os.path.join(self.root or "/", "install", "share", pkg)
                        else:
                            return False
                    out.append(folder if p.name == "find-pkg-share" else os.path.join(self.root or "/", "install"))
                    continue
                if p.name == "env" and all(S.is_text(x) for x in p.args):
                    val = self.env.get(S.plain(p.args[0]))
                    if val is None:
                        if len(p.args) < 2:
                            return False
                        val = S.plain(p.args[1])
                    out.append(val)
                    continue
                return False
            return True
        return "".join(out) if go(v.parts) else None


@dataclass
class _LD:
    """A loaded launch description (what an include yields in launch's look-ahead)."""
    actions: list


@dataclass
class _Declared:
    action: A.ArgA
    conditional: bool


def _yaml_value(s: str):
    if not s:
        return s
    try:
        v = yaml.safe_load(s)
    except Exception:
        return s
    if isinstance(v, (str, int, float, bool, list)):
        return v
    return s


def _extension(path: str) -> str:
    base = os.path.basename(path)
    ext = os.path.splitext(base)[1][1:]
    if ext == "py":
        return "py"
    known = base.endswith((".launch.xml", ".xml", ".launch", ".launch.yaml", ".launch.yml", ".yaml", ".yml"))
    return ext if known else ""


def _python_error(path: str, text: Optional[str]) -> Optional[str]:
    """What launch's fallback to a Python launch file says about a file it could not load:
    the Python compiler's complaint (compiled, never run)."""
    if text is None:
        return f"FileNotFoundError: [Errno 2] No such file or directory: '{path}'"
    if len(text) > 2_000_000:
        return None
    try:
        compile(text.encode("utf-8"), path, "exec", dont_inherit=True, optimize=-1)
    except SyntaxError as e:
        return f"SyntaxError: {e}"
    except (ValueError, MemoryError, RecursionError) as e:
        return f"{type(e).__name__}: {e}"
    return None
