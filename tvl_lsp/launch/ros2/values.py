"""The values of the ROS 2 walker: diagnostic codes, markers, cases (condition, string), facts,
ROS 2 name rules and launch's type coercions.  Pure helpers, no walking."""

from __future__ import annotations

import itertools
import math
import os
import re
from dataclasses import dataclass, field
from typing import Mapping, Optional

import yaml
from ...base import yamlsafe

from ...base.formula import FALSE, TRUE, And, Const, Formula, Not, Or, Var, disj, forall_unknowns
from ...base.diagnostics import Severity, register
from ...base.text import Span
from ..model import Element, ErrorFact, NodeFact
from . import actions as A
from .frontend import Document

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION


def _reg(code: str, sev: Severity, summary: str) -> str:
    return register(code, sev, summary, "launch")


# codes shared with ROS 1 (registered by tvl_lsp.launch.loader too; registration is idempotent)
UNDEFINED_ARG = _reg("undefined-arg", E, "A $(arg X) where X is not declared in scope.")
UNSET_ARG = _reg("unset-arg", W, "A $(arg X) where X is declared without a value and nothing sets it.")
INVALID_CONDITION = _reg("invalid-condition", E, "An if/unless condition does not evaluate to true/false/1/0.")
IF_AND_UNLESS = _reg("if-and-unless", E, "Both 'if' and 'unless' on the same tag.")
DUPLICATE_NODE = _reg("duplicate-node", E, "Two nodes with the same resolved name are loaded.")
MISSING_ATTRIBUTE = _reg("missing-attribute", E, "A required attribute is missing.")
UNKNOWN_ATTRIBUTE = _reg("unknown-attribute", W, "An attribute roslaunch does not know (it warns).")
UNKNOWN_TAG = _reg("unknown-tag", W, "A tag roslaunch does not know (it warns and ignores it).")
INVALID_VALUE = _reg("invalid-attribute-value", E, "An attribute value roslaunch rejects.")
SUBST_SYNTAX = _reg("substitution-syntax", E, "A malformed $(...) substitution.")
SUBST_UNKNOWN = _reg("unknown-substitution", E, "An unknown $(...) substitution command.")
SUBST_ARITY = _reg("substitution-arity", E, "Wrong number of arguments to a $(...) substitution.")
EVAL_ERROR = _reg("eval-error", E, "A $(eval ...) expression fails.")
ENV_NOT_SET = _reg("env-not-set", E, "A $(env X) where X is not set in tvl-lsp's environment.")
PACKAGE_NOT_FOUND = _reg("package-not-found", E, "A $(find pkg) of a package roslaunch cannot find.")
CONDITION_NOT_ANALYSABLE = _reg("condition-not-analysable", I, "A condition tvl-lsp cannot translate to a formula.")
INCLUDE_NOT_FOUND = _reg("include-not-found", E, "An included file does not exist.")
INCLUDE_OUTSIDE = _reg("include-outside-workspace", W, "An included file outside the workspace: it is not read.")
INCLUDE_INVALID = _reg("include-invalid", E, "An included file is not a valid launch file.")
INCLUDE_CYCLE = _reg("include-cycle", E, "Files include each other in a cycle.")
INCLUDE_TOO_DEEP = _reg("include-too-deep", W, "Includes nested too deeply to follow.")
NO_LAUNCH_ROOT = _reg("no-launch-root", E, "The file has no single <launch> element.")
EXTENSION_TAG = _reg("extension-tag", I, "A tag a launch extension adds (tvl-lsp does not model what it does).")
FILE_NOT_FOUND = _reg("file-not-found", E, "A file a tag loads does not exist.")
PARAM_INVALID = _reg("invalid-param", E, "A <param> or <rosparam> roslaunch cannot load.")
BUDGET = _reg("launch-analysis-budget", W, "The launch file is too large to analyse completely.")
# ROS 2 only
INVALID_CHOICE = _reg("invalid-choice", E, "An <arg> value that is not one of its <choice> values (ROS 2).")
INVALID_NODE_NAME = _reg("invalid-node-name", E, "A node name ros2 launch rejects (ROS 2).")
INVALID_NAMESPACE = _reg("invalid-namespace", E, "A namespace ros2 launch rejects (ROS 2).")
SUBST_FAILED = _reg("substitution-failed", E, "A $(...) substitution fails when launched (ROS 2).")
PYTHON_INCLUDE = _reg("python-launch-include", I, "An include of a Python launch file tvl-lsp cannot analyse (ROS 2).")
ARG_LEAK = _reg("include-arg-leak", W, "An arg set by an <include> leaks out and changes a later element (ROS 2).")
PARAM_FILE_NOT_FOUND = _reg("param-file-not-found", W, "A <param from=...> names a file that does not exist (ROS 2).")
LAUNCH_PARSE = _reg("invalid-launch-file", E, "The ros2 launch command refuses to load the file (ROS 2).")
NOT_ANALYSABLE = _reg("launch-not-analysable", I, "A part of a launch file tvl-lsp cannot know without running it "
                      "(the analysis stops there).")

MAX_CASES = 64
MAX_INCLUDE_DEPTH = 12
MAX_VISITS = 20_000  # elements visited (includes expanded) per analysis: a file has at most 10,000
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
    event: Optional[str] = None     # started by an event handler (OnProcessExit ...), not by the launch


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


def _vars_upto(f: Formula, limit: int) -> Optional[list[str]]:
    """The sorted variables of ``f``, or None as soon as there are more than ``limit``."""
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
            if len(out) > limit:
                return None
        elif isinstance(g, Not):
            stack.append(g.arg)
        elif isinstance(g, (And, Or)):
            stack.extend(g.args)
    return sorted(out)


def satisfiable(f: Formula, limit: int = 14) -> Optional[bool]:
    """True / False by brute force over at most ``limit`` variables; None beyond."""
    if f == FALSE:
        return False
    if f == TRUE:
        return True
    vs = _vars_upto(f, limit)
    if vs is None:
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
    # an error is reported only where it holds whatever the unknowns are (an if/unless value
    # tvl-lsp cannot compute is never the cause of an error); the cross-check asks the SAT
    # service about each fact anyway: here only the cheap cases
    for f in out.values():
        f.condition = forall_unknowns(f.condition)
    return [f for f in out.values() if f.condition != FALSE and satisfiable(f.condition, limit=8) is not False]


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
            out = yamlsafe.safe_load(s)
        except Exception:
            return f"Failed to convert '{s}' to '<class 'bool'>': yamlsafe.safe_load() failed"
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


def declared_in(acts: list) -> set[str]:
    """The configuration names a file's actions declare (<arg>, <let>, <keep> with a plain name)."""
    from . import subst as S
    out: set[str] = set()
    stack = list(acts)
    while stack:
        a = stack.pop()
        if isinstance(a, A.ArgA):
            out.add(a.name)
        elif isinstance(a, A.LetA) and S.is_text(a.name.parts):
            out.add(S.plain(a.name.parts))
        elif isinstance(a, A.IncludeA):
            out |= {S.plain(x.name.parts) for x in a.args if S.is_text(x.name.parts)}
        if isinstance(a, (A.GroupA, A.ResetA)):
            out |= {S.plain(k.name.parts) for k in (a.keeps or []) if S.is_text(k.name.parts)}
        if isinstance(a, (A.GroupA, A.TimerA)):
            stack.extend(a.actions)
    return out


def _yaml_value(s: str):
    if not s:
        return s
    try:
        v = yamlsafe.safe_load(s)
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
