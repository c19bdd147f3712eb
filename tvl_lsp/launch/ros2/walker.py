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

import os
import threading
from typing import Mapping, Optional

from ...base.formula import FALSE, TRUE, Formula, conj, disj, neg, unknown
from ...base.diagnostics import Diagnostic, Related, Severity
from ...base.text import Span
from ...base.files import is_regular, read_text_or_none
from ..model import Element, ErrorFact, IncludeFact, Reach
from . import actions as A
from . import subst as S
from .frontend import parse_launch_file
from .includes import IncludeRules
from . import coerce as C
from .nodes import NodeRules
from .substitutions import SubstEval
from .values import (E, I, W, declared_in, ARG_LEAK, EXTENSION_TAG, BUDGET, CONDITION_NOT_ANALYSABLE, NOT_ANALYSABLE, Cases, INVALID_CHOICE, INVALID_CONDITION,
                     INVALID_NAMESPACE, INVALID_VALUE, LaunchFact, MAX_CASES, MAX_VISITS, MAX_WALK_DEPTH, Node2Fact, OPAQUE,
                     PARAM_INVALID,
                     RList,
                     Scope, Stop, UNSET_ARG, Unit, _CLASS, _extension, _python_error, _yaml_value, cond_value,
                     make_absolute, merge, opaque, prefix_namespace, present, shown, validate_namespace)


# parsed files, by content: a file and its parse are immutable once made (the walks only read
# them), so the files a workspace's launch files share are parsed once per process.  Bounded in
# files, in characters, and in versions of one path: an editor sends a new text of the same file
# on every keystroke, and each parse is many times its text in memory (the server kept up to
# 4,000 parses of one edited file before: +40 MB after a thousand edits)
_PARSED: dict = {}
_PARSED_LOCK = threading.Lock()
_PARSED_CHARS = [0]
MAX_PARSED = 4000
MAX_PARSED_CHARS = 4_000_000
VERSIONS_PER_PATH = 2


def _remember_parse(key: tuple, unit) -> None:
    """Keep ``unit`` (the parse of ``key`` = (path, length, hash)): the oldest versions of the
    same path beyond :data:`VERSIONS_PER_PATH`, then the oldest files, make room."""
    with _PARSED_LOCK:
        if key in _PARSED:
            return
        same = [k for k in _PARSED if k[0] == key[0]]
        for k in same[:max(0, len(same) - VERSIONS_PER_PATH + 1)]:
            _PARSED_CHARS[0] -= k[1]
            del _PARSED[k]
        _PARSED[key] = unit
        _PARSED_CHARS[0] += key[1]
        while len(_PARSED) > 1 and (len(_PARSED) > MAX_PARSED or _PARSED_CHARS[0] > MAX_PARSED_CHARS):
            k = next(iter(_PARSED))
            _PARSED_CHARS[0] -= k[1]
            del _PARSED[k]


class Walker(SubstEval, NodeRules, IncludeRules):

    def __init__(self, *, concrete: bool, packages: Mapping[str, str], env: Mapping[str, str],
                 read_file=None, workspace_root: Optional[str] = None, stub_packages: bool = True,
                 installed: Optional[Mapping[str, str]] = None):
        self.concrete = concrete
        self.packages = dict(packages)          # workspace packages: name -> source folder
        self.installed = dict(installed or {})  # AMENT_PREFIX_PATH packages: name -> share folder
        self.env = env
        self.read_file = read_file
        self.root = workspace_root
        # every walk reads files inside the workspace and its packages only (see ros1)
        self.confine = ([workspace_root] + list(self.packages.values()) + list(self.installed.values())
                        if workspace_root else None)
        self.reach = Reach(self.confine) if self.confine is not None else None
        self.stub = stub_packages
        self.facts: list[ErrorFact] = []
        self.nodes: list[Node2Fact] = []
        self.executables: list[dict] = []
        self.elements: list[Element] = []
        self.includes: list[IncludeFact] = []
        self.diagnostics: list[Diagnostic] = []
        self.units: dict[str, Unit] = {}
        self.node_names: dict[str, list[Node2Fact]] = {}
        self.node_name_any: dict[str, Formula] = {}  # name -> some node of that name is started
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
        self.lenient = False               # undeclared configurations: warnings (no model paired)
        # (path, span) of if/unless values that are unknown in some case (a configuration an
        # includer sets, $(command) ...): such a condition is neither dead nor constant
        self.unknown_conditions: list = []
        self.unknowns: dict = {}   # (file, value) -> the unknown of an if/unless tvl-lsp cannot compute
        self.declared_names: dict[str, set[str]] = {}   # file -> the names it declares
        self._extensions: Optional[dict] = None

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

    def read(self, path: str, confined: bool = True) -> Optional[str]:
        if confined and self.reach is not None and self.reach.outside(path):
            return None
        if self.read_file is not None:
            try:
                t = self.read_file(path)
            except Exception:
                t = None
            if t is not None:
                return t
        return read_text_or_none(path)  # regular files within the size cap only

    def exists(self, path: str) -> bool:
        if self.read_file is not None:
            try:
                if self.read_file(path) is not None:
                    return True
            except Exception:
                pass
        return is_regular(path)

    def unit(self, path: str, text: Optional[str] = None) -> Optional[Unit]:
        if path in self.units:
            return self.units[path]
        if path.endswith(".py"):
            if text is None:
                text = self.read(path)
            if text is None:
                if not self.exists(path):
                    return None
                u = Unit(path, None, [], [], python=True)   # outside what the analysis reads
                u.decline = ("the file is outside the workspace and its packages", path, None)
            else:
                from ..ros2py.frontend import load_unit   # the Python front end (never runs the file)
                u = load_unit(self, path, text)
            self.units[path] = u
            return u
        if text is None:
            text = self.read(path)
            if text is None:
                return None
        key = (path, len(text), hash(text))
        u = _PARSED.get(key)
        if u is None:
            doc = parse_launch_file(text, path)
            errors: list = []
            acts: list = []
            if doc.error is not None:
                kind, msg, span = doc.error
                errors.append(A.LoadError(kind, msg, span, path))
            elif doc.root is not None:
                acts, errors = A.parse_description(doc.root, path)
            u = Unit(path, doc, acts, errors)
            _remember_parse(key, u)
        if u.errors:
            u = self.extension_tags(u)
        self.declared_names[path] = declared_in(u.actions)
        self.units[path] = u
        return u

    def extension_tags(self, u: Unit) -> Unit:
        """Tags a launch extension of the workspace (or of AMENT_PREFIX_PATH) adds, e.g.
        tracetools_launch's <trace>, are no error: ros2 launch knows them once the package is
        installed.  What they do is not modelled: a note (the root file) or a warning of the
        concrete load says so; the rest of the file is analysed as usual."""
        if self._extensions is None:
            from .ament import launch_extensions
            try:
                self._extensions = {k: v for k, v in launch_extensions(self.packages, self.env).items()
                                    if v[0] == "action"}
            except Exception:
                self._extensions = {}
        ext = []
        for e in u.errors:
            tag = e.message.rsplit(": ", 1)[-1] if e.message.startswith("Unrecognized entity of the type: ") else None
            if tag in self._extensions:
                ext.append((e, tag, self._extensions[tag][1]))
        if not ext:
            return u
        for e, tag, pkg in ext:
            msg = (f"<{tag}> is a tag of the launch extension {pkg}: ros2 launch knows it when {pkg} is installed; "
                   "tvl-lsp does not model what it does")
            if self.concrete:
                self.warnings.append(msg)
            elif u.path == self.root_path:
                self.note(EXTENSION_TAG, msg, u.path, e.span)
        skip = {id(e) for e, _, _ in ext}
        return Unit(u.path, u.doc, u.actions, [e for e in u.errors if id(e) not in skip], u.python)

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

    @staticmethod
    def sure(values: Cases, cond: Formula) -> Cases:
        """A value whose evaluation failed somewhere (reported there) is unknown there: what
        reads it is not reported again."""
        failed = conj([cond, neg(present(values))])
        return values + [(failed, OPAQUE)] if failed != FALSE else values

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
                if self.concrete:
                    self.decline(el.path, span, f"tvl-lsp cannot know the value of this '{cond.kind}' condition, "
                                 "so whether ros2 launch runs this element", c)
                    ok.append(c)
                    continue
                # an unknown, the same for every if/unless of that value (they exclude each
                # other); an error that depends on it is never reported (merge_facts)
                k = (el.path, v)
                u = self.unknowns.get(k)
                if u is None:
                    raw = str(cond.value.attr.value).strip()[:60] if cond.value.attr is not None else cond.kind
                    u = self.unknowns[k] = unknown(f"{len(self.unknowns) + 1}:{raw}")
                ok.append(conj([c, u if cond.kind == "if" else neg(u)]))
                self.unknown_conditions.append((el.path, span))
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

    def tick(self, el: Element) -> bool:
        self.visits += 1
        if self.visits > MAX_VISITS:
            if not self.budget_hit:
                self.budget_hit = True
                self.facts.append(LaunchFact(BUDGET, W, "the launch file (with its includes) is too large to analyse "
                                             f"completely; analysis stopped after {MAX_VISITS:,} elements",
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
            self.set_config(sc, self.ev(a.name, sc, cond, el), self.sure(self.ev(a.value, sc, cond, el), cond),
                            cond, el)
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
            items = []
            for c1, n in names:
                for c2, v in vals:
                    c = conj([c1, c2])
                    if c == FALSE:
                        continue
                    if opaque(v) or opaque(n):
                        items.append((c, (n, _yaml_value(v))))
                        continue
                    try:  # launch_ros' evaluate_parameter_dict: the text typed as YAML
                        items.append((c, (n, C.evaluate_set_parameter(n, v))))
                    except TypeError as ex:
                        self.fact(PARAM_INVALID, f"the value of parameter '{n}' is '{v}', which ros2 launch cannot "
                                  f"type as YAML: {ex}", el.path, a.value.span() or el.tag_span, c,
                                  launch=("TypeError", str(ex)))
                    except Exception:  # beyond the YAML bounds: unknown, not an error
                        items.append((c, (n, v)))
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
                for c, v in self.ev(a.period, sc, cond, el):
                    if opaque(v) or S.is_text(a.period.parts):
                        continue
                    try:  # TimerAction.execute: the period typed as a float
                        C.perform_typed(v, float)
                    except ValueError as ex:
                        self.fact(INVALID_VALUE, f"the timer's period is '{v}', which ros2 launch cannot read as a "
                                  f"number: {ex}", el.path, a.period.span() or el.tag_span, c,
                                  launch=("ValueError", str(ex)))
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
        elif hasattr(a, "walk"):
            a.walk(self, el, sc, cond, emap)   # an action another front end models (OpaqueFunction ...)

    def decline(self, path: str, span: Span, reason: str, cond: Formula = TRUE) -> None:
        """tvl-lsp cannot know what follows without running something: the concrete load stops
        there (saying so, never guessing), the symbolic analysis notes it."""
        if cond == FALSE:
            return
        if self.concrete:
            self.fact(NOT_ANALYSABLE, reason, path, span, cond, E, launch=("NotAnalysed", reason))
        else:
            self.note(NOT_ANALYSABLE, reason, path, span)

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
                d = self.sure(self.ev(a.default, sc, missing, el), missing)
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

    def aspan(self, el: Element, name: str) -> Span:
        at = el.attrs.get(name)
        return at.value_span if at is not None else (el.tag_span or el.span)
