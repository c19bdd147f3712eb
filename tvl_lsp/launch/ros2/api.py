"""Entry points of the ROS 2 front end (see the package docstring)."""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass, field
from typing import Iterable, Mapping, Optional

from ...base.formula import FALSE, TRUE, Formula, Var, conj, neg
from ...base.diagnostics import Diagnostic, Severity
from ...base.files import model_workspace
from ..model import ArgDecl, LaunchAnalysis
from . import actions as A
from . import subst as S
from .ament import find_ament_packages, guess_ament_root, installed_packages
from .frontend import make_elements
from .values import (IF_AND_UNLESS, LAUNCH_PARSE, MISSING_ATTRIBUTE, NO_LAUNCH_ROOT, OPAQUE, SUBST_ARITY, SUBST_SYNTAX,
                     SUBST_UNKNOWN, UNKNOWN_ATTRIBUTE, UNKNOWN_TAG, merge_facts, shown)
from .values import NOT_ANALYSABLE, Scope, Stop
from .walker import Walker

E = Severity.ERROR


def _packages(workspace_root: Optional[str], packages: Optional[Mapping[str, str]]) -> dict[str, str]:
    if packages is not None:
        return dict(packages)
    return dict(_real_folders(tuple((n, p.folder) for n, p in find_ament_packages(workspace_root).items())))


@functools.lru_cache(maxsize=32)
def _real_folders(folders: tuple) -> tuple:
    """(name, real folder) of each package (remembered: a workspace's files are checked one by one)."""
    return tuple((n, os.path.realpath(f)) for n, f in folders)


def load_error_code(err: A.LoadError) -> str:
    m = err.message
    if err.kind == "ParseError":
        return ""
    if m.startswith("Unrecognized entity"):
        return UNKNOWN_TAG
    if m.startswith(("Unexpected attribute", "Unexpected key", "Unexpected nested")):
        return UNKNOWN_ATTRIBUTE
    if err.kind == "AttributeError" and ("not found in Entity" in m or "Can not find attribute" in m):
        return MISSING_ATTRIBUTE
    if err.kind == "UnexpectedCharacters":
        return SUBST_SYNTAX
    if m.startswith("Unknown substitution"):
        return SUBST_UNKNOWN
    if ("substitution" in m or "substitutions" in m) and "expect" in m:
        return SUBST_ARITY
    if m.startswith("if and unless"):
        return IF_AND_UNLESS
    if m.startswith("Expected 'launch' as root") or m == "Expected only one root":
        return NO_LAUNCH_ROOT
    return LAUNCH_PARSE


def load_error_message(err: A.LoadError) -> str:
    code = load_error_code(err)
    m = err.message
    if code == UNKNOWN_TAG:
        tag = m.rsplit(": ", 1)[-1]
        return f"ros2 launch does not know the tag <{tag}>: it refuses to load the file ({m})"
    if code == UNKNOWN_ATTRIBUTE:
        return f"{m}: ros2 launch refuses to load the file"
    if code == NO_LAUNCH_ROOT:
        return f"{m}: a ROS 2 launch file has one <launch> root"
    return m


def _root_diagnostics(w: Walker, path: str, errors: list) -> list[Diagnostic]:
    out = []
    for e in errors:
        code = load_error_code(e)
        if not code:
            continue  # syntax errors: the document's own diagnostics
        out.append(Diagnostic(code, E, e.path or path, e.span, load_error_message(e)))
    return out


# ------------------------------------------------------------------ free args

def _bool_uses(acts: list, names: set[str], unused: bool = False) -> set[str]:
    """The top-level args used somewhere other than as a boolean: not free."""
    bad: set[str] = set()
    good: set[str] = set()

    def visit_value(v: A.Value, as_condition: bool):
        def go(parts, boolean: bool):
            only = [p for p in parts if not (isinstance(p, S.Text) and not p.text.strip())]
            for p in parts:
                if not isinstance(p, S.Sub):
                    continue
                if p.name == "var":
                    n = S.plain(p.args[0]) if p.args else ""
                    if not (boolean and len(only) == 1):
                        bad.add(n)
                    else:
                        good.add(n)
                    for a in p.args[1:]:
                        go(a, False)
                    continue
                if p.name in ("not", "and", "or", "any", "all"):
                    for a in p.args:
                        go(a, True)
                    continue
                if p.name == "if" and p.args:
                    go(p.args[0], True)
                    for a in p.args[1:]:
                        go(a, False)
                    continue
                for a in p.args:
                    go(a, False)
        go(v.parts, as_condition)

    def visit(obj, depth=0):
        if depth > 200:
            return
        if isinstance(obj, A.Value):
            visit_value(obj, False)
            return
        if isinstance(obj, A.Cond):
            visit_value(obj.value, True)
            return
        if isinstance(obj, (list, tuple)):
            for x in obj:
                visit(x, depth + 1)
            return
        if hasattr(obj, "__dataclass_fields__"):
            for k in obj.__dataclass_fields__:
                if k in ("entity",):
                    continue
                visit(getattr(obj, k), depth + 1)

    visit(acts)
    # an arg never used here may be read by an included file (includes see every launch
    # configuration): free only when this file uses it, and only as a boolean
    return ((names if unused else names & good)) - bad


def free_args_of(actions: list, unused: bool = False) -> list[str]:
    tops = [a for a in actions if isinstance(a, A.ArgA) and a.choices is None and "$(" not in a.name]
    names = [a.name for a in tops]
    good = _bool_uses(actions, set(names), unused)
    return [n for n in dict.fromkeys(names) if n in good]


def free_args2(text: str, path: str, unused: bool = False) -> list[str]:
    """The top-level args checked as free booleans when there is no model: every top-level
    ``<arg>`` (without <choice>) used here and whose every ``$(var X)`` is a whole ``if``/``unless`` value or
    an operand of ``$(not)``/``$(and)``/``$(or)``/``$(any)``/``$(all)``/the condition of
    ``$(if)`` (an arg also used as a string -- a name, a file, inside ``$(eval)`` or
    ``$(equals)`` -- keeps its default).  ``unused``: args this file never reads count too (a
    generic file paired with a model: its top-level args are the product's)."""
    if path.endswith(".py"):
        u = _python_unit(text, path)
        return python_free_args(u, unused) if u is not None else []
    from .frontend import parse_launch_file
    doc = parse_launch_file(text, path)
    if doc.root is None:
        return []
    acts, _ = A.parse_description(doc.root, path)
    return free_args_of(acts, unused)


def python_free_args(u, unused: bool = False) -> list[str]:
    """:func:`free_args_of` of a Python launch file's unit: arguments an OpaqueFunction reads are
    used as strings there (not free)."""
    bad = {x.args[0] for x in getattr(u.doc.root, "substs", []) if x.attr == "python" and x.args}
    return [n for n in free_args_of(u.actions, unused) if n not in bad]


def _python_unit(text: str, path: str):
    """A Python launch file's unit on its own (its workspace's packages, no environment): what
    it declares does not depend on the walk."""
    path = os.path.abspath(path)
    root = guess_ament_root(path)
    w = Walker(concrete=False, packages=_packages(root, None), env={}, workspace_root=root)
    w.root_path = path
    try:
        u = w.unit(path, text)
    except Exception:
        return None
    return u if u is not None and u.doc is not None else None


def choice_cases(name: str, choices: list[str], selectors: Optional[list[tuple[Formula, str]]] = None):
    """The cases of an arg with <choice> values as a free variable: ``selectors`` (a model's
    alternatives: formula -> value), or, alone, one value per choice through auxiliary
    variables ``name=value`` (the first true one), and not set at all when none is (the
    default applies, or launch says the arg is required)."""
    if selectors is not None:
        return [(f, v) for f, v in selectors]
    out = []
    rest: list[Formula] = []
    for c in choices:
        v = Var(f"{name}={c}")
        out.append((conj(rest + [v]), c))
        rest.append(neg(v))
    return out


# ------------------------------------------------------------------ symbolic

def analyse_launch2(text: str, path: str, workspace_root: Optional[str] = None, read_file=None, *,
                    features: Optional[Iterable[str]] = None, env: Optional[Mapping[str, str]] = None,
                    packages: Optional[Mapping[str, str]] = None,
                    choices: Optional[Mapping[str, list[tuple[Formula, str]]]] = None,
                    partial: bool = False, lenient: bool = False) -> LaunchAnalysis:
    """Analyse a ROS 2 launch file for all assignments of its feature args at once.

    ``features``: the args to treat as free booleans (the paired model's features); if None,
    :func:`free_args_of`.  ``choices``: arg name -> [(formula, value)] for args with <choice>
    paired with alternatives of the model (others with <choice> get auxiliary variables).
    ``partial``: the file is included by another launch file (and launched by none on its own):
    launch configurations it reads without declaring them come from its includers, so a missing
    one is unknown here rather than an error (the includer's analysis checks them).
    ``lenient`` (a file checked without a model): a configuration that no file of the analysis
    declares is a warning rather than an error (a file that includes this one may set it)."""
    path = os.path.abspath(path)
    env = os.environ if env is None else env
    if workspace_root is None and packages is None:
        workspace_root = guess_ament_root(path) or model_workspace(path)
    w = Walker(concrete=False, packages=_packages(workspace_root, packages), env=env, read_file=read_file,
               workspace_root=workspace_root, installed=installed_packages(env))
    w.root_path = path
    w.lenient = lenient
    u = w.unit(path, text)
    if u.doc is None:   # a Python file outside what the analysis reads
        return LaunchAnalysis(path, [], [], [], [], [], [], [], [], None, "ros2")
    w.diagnostics.extend(u.doc.diagnostics)
    if u.python and getattr(u, "decline", None) is not None:
        reason, _, dspan = u.decline
        w.diagnostics.append(Diagnostic(NOT_ANALYSABLE, Severity.INFORMATION, path,
                                        dspan or u.doc.root.tag_span,
                                        f"tvl-lsp cannot analyse this Python launch file: {reason}"))
    root_el = None
    feature_decls: list[ArgDecl] = []
    free: list[str] = []
    if u.doc.root is not None:
        emap: dict = {}
        root_el = make_elements(u.doc.root, path, None, 0, emap, w.elements)
        root_el.condition = TRUE
        w.diagnostics.extend(_root_diagnostics(w, path, u.errors))
        tops = [a for a in u.actions if isinstance(a, A.ArgA)]
        free = list(features) if features is not None else python_free_args(u) if u.python is False and \
            getattr(u.doc, "kind", "") == "py" else free_args_of(u.actions)
        root_args: dict = {}
        for f in free:
            root_args[f] = [(Var(f), "true"), (neg(Var(f)), "false")]
        for a in tops:
            if a.choices is not None:
                # an arg with <choice> values is never a boolean: its values are the choices
                sel = (choices or {}).get(a.name)
                root_args[a.name] = choice_cases(a.name, a.choices, sel)
                free = [f for f in free if f != a.name]
        w.free = set(root_args)
        w.cur_file = [(TRUE, path)]
        sc = Scope()
        try:
            if partial:
                sc.opaque = TRUE
                needed = []
            else:
                needed = w.check_required(u, list(root_args), root_el, TRUE, root_el.tag_span or root_el.span,
                                          root=True)
                needed += _required_behind_include(w, tops, root_args, needed)
            for k, v in root_args.items():
                sc.configs[k] = [(c, x) for c, x in v if c != FALSE]
            for k in needed:  # the command line must give them (reported): their value is unknown
                sc.configs.setdefault(k, [(TRUE, OPAQUE)])
            w.timers = []
            w.run(u.actions, sc, TRUE, emap)
            _run_timers(w, sc)
        except RecursionError:
            from .values import BUDGET, LaunchFact
            w.facts.append(LaunchFact(BUDGET, Severity.WARNING, "the launch file is nested too deeply to analyse "
                                      "completely", path, root_el.tag_span or root_el.span, TRUE))
        for a in tops:
            el = emap.get(id(a.entity))
            if el is None or "name" not in el.attrs:
                continue
            at = el.attrs
            default = at["default"].value if "default" in at else None
            if getattr(a.entity, "kind", "") == "py":   # one place of a Python file may declare several
                default = S.plain(a.default.parts) if a.default is not None else None
            feature_decls.append(ArgDecl(a.name, el.span, at["name"].value_span, default, None,
                                         a.description, path, el))
    la = LaunchAnalysis(path, w.diagnostics, feature_decls, free, w.elements, w.nodes, merge_facts(w.facts),
                        w.includes, [], root_el, "ros2")
    la.unknown_conditions = list(dict.fromkeys(w.unknown_conditions))
    la.complete = not any(f.code == NOT_ANALYSABLE and f.path == path for f in list(w.facts) + w.diagnostics)
    for d in feature_decls:
        a = next((x for x in (u.actions if u.doc.root is not None else []) if isinstance(x, A.ArgA)
                  and x.name == d.name and x.choices is not None), None)
        if a is not None:
            la.choices[d.name] = (list(a.choices), d.element)
    return la


def choice_args(text: str, path: str) -> dict[str, list[str]]:
    """The top-level args with <choice> values: name -> values."""
    if path.endswith(".py"):
        u = _python_unit(text, path)
        acts = u.actions if u is not None else []
        return {a.name: list(a.choices) for a in acts if isinstance(a, A.ArgA) and a.choices is not None}
    from .frontend import parse_launch_file
    doc = parse_launch_file(text, path)
    if doc.root is None:
        return {}
    acts, _ = A.parse_description(doc.root, path)
    return {a.name: list(a.choices) for a in acts if isinstance(a, A.ArgA) and a.choices is not None}


def _required_behind_include(w, tops: list, root_args: dict, needed: list) -> list:
    """The file's own top-level args without default that launch's look-ahead did not report
    because an include before them declares the same name (and passes it): without a value on
    the command line launch still fails (at that include's substitution or at the declaration),
    so the command line gives them -- their value is unknown, as for every required arg."""
    from .values import UNSET_ARG
    out = []
    for a in tops:
        if a.default is not None or a.cond is not None or a.name in root_args or a.name in needed or a.name in out:
            continue
        ent = a.entity
        aspan = ent.attrs["name"].value_span if "name" in ent.attrs else ent.tag_span
        w.fact(UNSET_ARG, f"arg '{a.name}' has no default: ros2 launch needs {a.name}:=... on the command line",
               ent.path, aspan, TRUE, Severity.WARNING)
        out.append(a.name)
    return out


def _run_timers(w: Walker, sc: Scope) -> None:
    """Timer actions run after everything else (shortest period first), as the oracle does."""
    done = 0
    while getattr(w, "timers", None) and done < 1000:
        done += 1
        w.timers.sort(key=lambda t: _period(t[0]))
        a, el, _, cond, emap = w.timers.pop(0)
        w.run(a.actions, sc, cond, emap)


def _period(a) -> float:
    p = a.period
    if isinstance(p, (int, float)) and not isinstance(p, bool):
        return float(p)
    return 0.0


# ------------------------------------------------------------------ concrete

@dataclass
class Launch2Result:
    """What ros2 launch does with one file and one set of args (first error in ``error``)."""
    file: str
    args: dict
    declared: dict
    configurations: dict
    nodes: list
    executables: list
    includes: list
    warnings: list
    error: Optional[str] = None
    error_type: Optional[str] = None
    error_code: Optional[str] = None
    error_path: Optional[str] = None
    error_line: Optional[int] = None
    not_analysed: list = field(default_factory=list)
    logs: list = field(default_factory=list)
    # actions of event handlers (Python's RegisterEventHandler): they start only when a process
    # starts / exits ... at run time, so they are listed apart from ``nodes``
    events: list = field(default_factory=list)

    def to_json(self) -> dict:
        out = {"dialect": "ros2", "file": self.file, "args": self.declared, "given": self.args,
               "launch_configurations": self.configurations, "nodes": self.nodes,
               "executables": self.executables, "includes": self.includes, "logs": self.logs,
               "warnings": self.warnings, "not_analysed": self.not_analysed, "error": self.error}
        if self.events:
            out["events"] = self.events
        if self.error is not None:
            out.update(error_type=self.error_type, error_code=self.error_code, error_file=self.error_path,
                       error_line=self.error_line)
        return out


def load_launch2(path: str, args: Mapping[str, str], workspace_root: Optional[str] = None, read_file=None, *,
                 text: Optional[str] = None, env: Optional[Mapping[str, str]] = None,
                 packages: Optional[Mapping[str, str]] = None, stub_packages: bool = True) -> Launch2Result:
    """What ``ros2 launch FILE name:=value ...`` starts, without starting anything.

    Packages: the workspace's (``$(find-pkg-share p)`` is the source folder) and those of
    ``AMENT_PREFIX_PATH``; any other package counts as installed with an empty share folder
    (``stub_packages``, as the oracle's ``--stub-missing-packages``) or is launch's "package not
    found" error.  Python launch files are never executed: an include of one is listed in
    ``not_analysed`` and skipped."""
    path = os.path.abspath(path)
    env = os.environ if env is None else env
    if workspace_root is None and packages is None:
        workspace_root = guess_ament_root(path) or model_workspace(path)
    w = Walker(concrete=True, packages=_packages(workspace_root, packages), env=env, read_file=read_file,
               workspace_root=workspace_root, stub_packages=stub_packages, installed=installed_packages(env))
    res = Launch2Result(path, dict(args), {}, {}, [], [], [], [])
    w.root_path = path
    w.timers = []
    if text is None:
        text = w.read(path, confined=False)  # (the file named on the command line, wherever it is)
    sc = Scope()
    try:
        if text is None:
            err = f"[Errno 2] No such file or directory: '{path}'"
            from .values import _extension
            res.error = (f"Caught multiple exceptions when trying to load file of format [{_extension(path)}]:\n"
                         f" - FileNotFoundError: {err}\n - FileNotFoundError: {err}")
            res.error_type, res.error_code = "InvalidLaunchFileError", "include-not-found"
            return res
        u = w.unit(path, text)
        if u.python:
            reason, dpath, dspan = getattr(u, "decline", None) or ("tvl-lsp does not execute it", path, None)
            res.error = f"tvl-lsp cannot analyse the Python launch file {os.path.basename(path)}: {reason}"
            res.error_type, res.error_code = "NotAnalysed", NOT_ANALYSABLE
            res.error_path, res.error_line = dpath, (dspan.start.line + 1 if dspan is not None else None)
            return res
        if u.errors:
            first = u.errors[0]
            res.error = w.load_message(path, u.errors)
            res.error_type = "InvalidLaunchFileError"
            res.error_code = load_error_code(first) or "xml-syntax"
            res.error_path, res.error_line = first.path or path, first.span.start.line + 1
            return res
        emap: dict = {}
        root_el = make_elements(u.doc.root, path, None, 0, emap, w.elements)
        root_el.condition = TRUE
        w.cur_file = [(TRUE, path)]
        w.check_required(u, list(args), root_el, TRUE, root_el.tag_span or root_el.span, root=True)
        for k, v in args.items():
            sc.configs[k] = [(TRUE, v)]
        w.run(u.actions, sc, TRUE, emap)
        _run_timers(w, sc)
        for fn in list(getattr(w, "post_walk", [])):
            fn(w)   # e.g. the actions of event handlers, analysed apart
    except Stop:
        f = w.error
        res.error = f.launch_message or f.message
        res.error_type = f.launch_type or "Error"
        res.error_code = f.code
        res.error_path, res.error_line = f.path, f.span.start.line + 1
    except RecursionError:
        res.error, res.error_type, res.error_code = "maximum recursion depth exceeded", "RecursionError", "include-cycle"
    res.declared = {k: shown(v[0][1]) for k, v in w.declared_root.items() if v}
    res.configurations = {k: shown(v[0][1]) for k, v in sc.configs.items()
                          if v and not k.startswith("anon") and isinstance(v[0][1], str)}
    def node_json(n) -> dict:
        return {"name": n.name or None, "package": n.package or None, "executable": n.executable or None,
                "namespace": n.ns, "remaps": [list(r) for r in n.remaps], "params": n.params,
                "param_files": n.param_files, "kind": n.kind, "source": n.path,
                "line": n.element.span.start.line + 1}
    for n in w.nodes:
        if n.condition != TRUE or getattr(n, "event", None):
            continue
        res.nodes.append(node_json(n))
    for rec in getattr(w, "py_events", []):
        if rec["condition"] != TRUE:
            continue
        res.events.append({"event": rec["event"], "target": rec["target"] or None, "source": rec["source"],
                           "line": rec["line"], "nodes": [node_json(n) for n in rec["nodes"] if n.condition == TRUE],
                           "not_analysed": rec["not_analysed"]})
    res.executables = w.executables

    def inc_tree(incs) -> list:
        return [{"file": i.file, "followed": i.followed, "source": i.element.path,
                 "line": i.element.span.start.line + 1, "includes": inc_tree(i.children),
                 **({"outside": True} if i.outside else {})}
                for i in incs if i.condition == TRUE]
    res.includes = inc_tree(w.includes)
    res.warnings = list(w.warnings) + [f.message for f in w.facts if f.condition == TRUE and f.severity != E
                                       and f.code != "param-file-not-found"]
    res.not_analysed = list(w.python_includes)
    res.logs = list(w.logs)
    return res
