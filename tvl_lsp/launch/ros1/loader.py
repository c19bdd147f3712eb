"""The symbolic roslaunch loader.

One walker mirrors roslaunch 1.15's ``XmlLoader`` (``xmlloader.py``, ``loader.py``,
``substitution_args.py``) tag by tag, but every value is a list of *cases*
``(condition, string)``: the formula over the free (feature) args under which the value
is that string.  A feature arg X with no value is ``[(X, "true"), (!X, "false")]``;
everything else is computed.  Each check roslaunch makes becomes an :class:`ErrorFact`
whose condition is the disjunction of the cases where roslaunch raises it.

With concrete arg values every condition folds to a constant, so the same walker is the
concrete loader (:func:`load_launch`).

This module is the walker's core (files, elements, the recursion over tags, error facts) and
the public API; the rules live beside it: ``rules`` (codes, limits, known tags and
attributes, helpers), ``scopes`` (scopes, substitution args, if/unless, ``<arg>``), ``tags``
(``<node>``, ``<group>``, ``<remap>``, ``<env>``, ``<machine>``), ``params`` (``<param>``,
``<rosparam>``), ``includes`` (``<include>``).
"""

from __future__ import annotations

import itertools
import os
from dataclasses import dataclass
from typing import Iterable, Mapping, Optional

from ...base.formula import FALSE, TRUE, Formula, Var, disj, forall_unknowns, neg, substitute, variables
from ...base.diagnostics import Diagnostic, Related, Severity
from ...base.text import LineIndex, Span
from ...base.files import is_regular, model_workspace, read_text_or_none
from . import subst as S
from ..model import Reach
from ..model import (ArgDecl, Attr, Element, ErrorFact, IncludeFact, LaunchAnalysis, LoadResult, NodeFact,
                    ParamFact, Subst)
from ..packages import guess_workspace_root, ros_packages
from ..xml import XElement, XmlDoc, parse_xml, value_span
from .rules import (_bool_val, _satisfiable, BUDGET, Cases, E, I, cmdline_arg, cmdline_settable, MAX_VISITS,
                    MAX_WALK_DEPTH, NO_LAUNCH_ROOT, POISON, UNRESOLVED, W)
from .argtypes import ArgTyping, default_reads, marker
from .includes import IncludeRules
from .params import ParamRules
from .scopes import Scope, ScopeRules
from .tags import TagRules


@dataclass
class _Unit:
    """A parsed file (cached per path)."""
    path: str
    doc: XmlDoc
    launch: Optional[XElement]
    error: Optional[str]


# ------------------------------------------------------------------ walker

class Walker(ScopeRules, TagRules, ParamRules, IncludeRules):
    """One walk over a launch file and its includes (symbolic, or concrete with
    ``concrete=True``); the tag rules live in the mixins."""

    def __init__(self, *, concrete: bool, workspace_root: Optional[str], read_file, env: Mapping[str, str],
                 packages: Optional[dict[str, str]] = None, typing: Optional[ArgTyping] = None):
        self.concrete = concrete
        self.cmdline_undeclared = False  # an undeclared arg the command line may give: a warning
        self.typing = typing  # an arg-typing walk (argtypes.py): values are markers, facts do not matter
        self.flow = 0         # > 0 while resolving values that pass args on (if/unless, <arg> values)
        self.read_file = read_file
        self.env = env
        if packages is None:  # what roslaunch's $(find) finds: the workspace and ROS_PACKAGE_PATH
            packages = ros_packages(workspace_root, env)
        self.packages = dict(packages)
        self.ambiguous: dict[str, list[str]] = dict(getattr(packages, "ambiguous", None) or {})
        # every walk (symbolic: --check, the editor, graph, the configurator; concrete: tvl-lsp
        # launch) reads files inside the workspace and its packages only: a file elsewhere is
        # never read, so never quoted in a diagnostic (model.outside_reach: the one rule)
        self.confine = ([workspace_root] + list(self.packages.values())) if workspace_root else None
        self.reach = Reach(self.confine) if self.confine is not None else None
        self.facts: list[ErrorFact] = []
        self.nodes: list[NodeFact] = []
        self.params: list[ParamFact] = []
        self.elements: list[Element] = []
        self.includes: list[IncludeFact] = []
        self.diagnostics: list[Diagnostic] = []
        self.units: dict[str, _Unit] = {}
        self.index: dict[str, LineIndex] = {}
        self.node_names: dict[str, list[NodeFact]] = {}
        self.node_name_any: dict[str, Formula] = {}  # name -> some node of that name is loaded
        self.visits = 0
        self.budget_hit = False
        self.anon_counter = itertools.count(1)
        self.reported_not_analysable: set = set()
        self.unknowns: dict[tuple[str, str], Formula] = {}  # unknown if/unless values (scopes.py)
        self.stack: list[str] = []
        self.machines: dict[str, list] = {}
        self.depth = 0

    # ---------------------------------------------------------------- facts

    def fact(self, code: str, message: str, el: Element, span: Optional[Span], cond: Formula,
             severity: Severity = E, related=None):
        if cond == FALSE:
            return
        self.facts.append(ErrorFact(code, severity, message, el.path, span or el.span, cond, list(related or [])))

    def note(self, code: str, message: str, el: Element, span: Span, severity: Severity = I):
        key = (code, el.path, span)
        if key in self.reported_not_analysable:
            return
        self.reported_not_analysable.add(key)
        self.facts.append(ErrorFact(code, severity, message, el.path, span, TRUE))

    # ---------------------------------------------------------------- files

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

    def unit(self, path: str, text: Optional[str] = None, doc: Optional[XmlDoc] = None) -> Optional[_Unit]:
        if path in self.units:
            return self.units[path]
        if doc is None:
            if text is None:
                text = self.read(path)
                if text is None:
                    return None
            doc = parse_xml(text, path)
        self.index[path] = doc.index
        launch = None
        error = None
        if doc.refused:
            error = doc.diagnostics[0].message if doc.diagnostics else "refused"
        elif doc.root is None:
            error = "Invalid roslaunch XML syntax"
        else:
            found = []
            stack = [doc.root]
            while stack:
                x = stack.pop()
                if x.tag == "launch":
                    found.append(x)
                stack.extend(reversed(x.children))
            if len(found) != 1:
                error = "Invalid roslaunch XML syntax: no root <launch> tag"
            else:
                launch = found[0]
            if any(d.severity == Severity.ERROR for d in doc.diagnostics):
                error = doc.diagnostics[0].message
        u = _Unit(path, doc, launch, error)
        self.units[path] = u
        return u

    # ---------------------------------------------------------------- elements

    def make_elements(self, x: XElement, path: str, parent: Optional[Element], depth: int,
                      emap: dict[int, Element]) -> Element:
        idx = self.index[path]
        attrs = {k: Attr(k, a.value, a.name_span, a.value_span) for k, a in x.attrs.items()}
        el = Element(x.tag, x.span, attrs, path, FALSE, parent, [], [], x.tag_span, x.text, depth)
        for k, a in x.attrs.items():
            v = a.value
            if "$" not in v:
                continue
            if S.is_eval(v):
                el.substitutions.append(Subst("eval", (v[7:-1],), value_span(a, idx, 0, len(v)), k))
                continue
            try:
                for inner, i, j in S.collect(v):
                    words = [w for w in inner.split(" ") if w]
                    el.substitutions.append(Subst(words[0] if words else "", tuple(words[1:]),
                                                  value_span(a, idx, i, j), k))
            except S.SubstError:
                pass
        emap[id(x)] = el
        self.elements.append(el)
        for c in x.children:
            el.children.append(self.make_elements(c, path, el, depth, emap))
        return el

    def aspan(self, el: Element, name: str) -> Span:
        a = el.attrs.get(name)
        return a.value_span if a else (el.tag_span or el.span)

    # ---------------------------------------------------------------- entry

    def run_root(self, path: str, text: str, root_args: dict[str, Cases],
                 doc: Optional[XmlDoc] = None) -> Optional[Element]:
        self.units.pop(path, None)
        u = self.unit(path, text, doc)
        self.diagnostics.extend(u.doc.diagnostics)
        if u.doc.root is None:
            return None
        emap: dict[int, Element] = {}
        root_el = self.make_elements(u.doc.root, path, None, 0, emap)
        if u.launch is None:
            if not u.doc.refused and not any(d.severity == E for d in u.doc.diagnostics):
                self.diagnostics.append(Diagnostic(NO_LAUNCH_ROOT, E, path, u.doc.root.tag_span or u.doc.root.span,
                                                   "Invalid roslaunch XML syntax: no root <launch> tag"))
            return root_el
        self.static_checks(u.launch, emap, path)
        sc = Scope("/", path)
        sc.args = root_args
        if self.concrete:
            sc.cmdline = FALSE  # the command line is known: these args are all it gives
        lel = emap[id(u.launch)]
        lel.condition = TRUE
        self.launch_tag(u.launch, lel, sc)
        self.stack = [os.path.abspath(path)]
        try:
            self.recurse(u.launch.children, sc, TRUE, emap)
        except RecursionError:
            self.facts.append(ErrorFact(BUDGET, W, "the launch file is nested too deeply to analyse completely",
                                        path, lel.tag_span or lel.span, TRUE))
        return root_el

    # ---------------------------------------------------------------- recursion

    def tick(self, el: Element) -> bool:
        self.visits += 1
        if self.visits > MAX_VISITS:
            if not self.budget_hit:
                self.budget_hit = True
                self.facts.append(ErrorFact(BUDGET, W, f"the launch file (with its includes) is too large to analyse "
                                            f"completely; analysis stopped after {MAX_VISITS:,} elements",
                                            el.path, el.tag_span or el.span, TRUE))
            return False
        return True

    def recurse(self, children: list[XElement], sc: Scope, guard: Formula, emap):
        self.depth += 1
        try:
            if self.depth > MAX_WALK_DEPTH:
                if children and not self.budget_hit:
                    self.budget_hit = True
                    el = emap[id(children[0])]
                    self.facts.append(ErrorFact(BUDGET, W, "groups and includes are nested too deeply to analyse; "
                                                "the deeper elements are not analysed", el.path,
                                                el.tag_span or el.span, TRUE))
                return
            self._recurse(children, sc, guard, emap)
        finally:
            self.depth -= 1

    def _recurse(self, children: list[XElement], sc: Scope, guard: Formula, emap):
        for x in children:
            el = emap[id(x)]
            if not self.tick(el):
                return
            if guard == FALSE:
                continue
            t = x.tag
            if t == "arg":
                self.arg_tag(x, el, sc, guard)
            elif t == "group":
                cond = self.ifunless(x, el, sc, guard)
                if cond == FALSE:
                    continue
                # the group is entered where its ns resolves (roslaunch fails on it elsewhere,
                # e.g. an ns reading an unset arg): its children are loaded there only
                scoped = self.ns_clear_params(x, el, sc, cond, "group")
                el.condition = disj([el.condition] + [c for c, _ in scoped])
                for c, child in scoped:
                    child.params = list(child.params)  # roslaunch copies a group's params
                    child.params_link = None
                    self.recurse(x.children, child, c, emap)
            elif t == "node":
                self.node_tag(x, el, sc, guard, emap, False)
            elif t == "test":
                self.node_tag(x, el, sc, guard, emap, True)
            elif t == "param":
                self.param_tag(x, el, sc, guard)
            elif t == "remap":
                cond = self.ifunless(x, el, sc, guard)
                if cond != FALSE:
                    el.condition = disj([el.condition, cond])
                    self.remap_tag(x, el, sc, cond, sc)
            elif t == "machine":
                self.machine_tag(x, el, sc, guard)
            elif t == "rosparam":
                self.rosparam_tag(x, el, sc, guard)
            elif t == "master":
                pass
            elif t == "include":
                self.include_tag(x, el, sc, guard, emap)
            elif t == "env":
                cond = self.ifunless(x, el, sc, guard)
                if cond != FALSE:
                    el.condition = disj([el.condition, cond])
                    self.env_tag(x, el, sc, cond)


# ------------------------------------------------------------------ public API

def _top_args(doc_root: Optional[XElement]) -> list[XElement]:
    if doc_root is None or doc_root.tag != "launch":
        return []
    return [x for x in doc_root.children if x.tag == "arg"]


def _candidates(launch: Optional[XElement], with_defaults: bool, settable: bool = True) -> list[str]:
    """Top-level args that may be free: no ``value`` (and no ``default`` unless
    ``with_defaults``), a plain name (that roslaunch's command line can set, if ``settable``:
    roslaunch ignores ``3d_sensor:=...``)."""
    # an arg the file sets with ``value`` anywhere at the top (say under if="$(arg omni)", with a
    # default under unless=) is not free: given on the command line, roslaunch rejects that
    # ``<arg value>`` ("cannot override arg"), which running the file with its defaults never does
    valued = {x.attrs["name"].value for x in _top_args(launch) if "name" in x.attrs and "value" in x.attrs}
    out = []
    for x in _top_args(launch):
        a = x.attrs
        if "name" in a and "value" not in a and (with_defaults or "default" not in a) and "$" not in a["name"].value \
                and a["name"].value not in valued and (not settable or cmdline_settable(a["name"].value)):
            out.append(a["name"].value)
    return list(dict.fromkeys(out))


def arg_uses(text: str, path: str, names: Iterable[str], workspace_root: Optional[str] = None, read_file=None, *,
             env: Optional[Mapping[str, str]] = None, packages: Optional[dict[str, str]] = None,
             doc: Optional[XmlDoc] = None) -> ArgTyping:
    """How the load uses the values of the top-level args ``names`` (see :mod:`.argtypes`):
    a walk of the file and its includes with each arg's value an opaque marker."""
    names = list(names)
    doc = doc if doc is not None else parse_xml(text, path)
    launch = doc.root if doc.root is not None and doc.root.tag == "launch" else None
    defaults = {x.attrs["name"].value: x.attrs["default"].value for x in _top_args(launch)
                if "name" in x.attrs and "default" in x.attrs and "$" not in x.attrs["default"].value}
    derived: dict[str, set[str]] = {}
    direct: dict[str, set[str]] = {}
    for x in _top_args(launch):
        if "name" in x.attrs and "default" in x.attrs and x.attrs["name"].value in names:
            flows, uses = default_reads(x.attrs["default"].value, set(names))
            if flows:
                derived[x.attrs["name"].value] = flows
            for y, kinds in uses.items():
                direct.setdefault(y, set()).update(kinds)
    typing = ArgTyping(names, defaults, derived, direct)
    if not names:
        return typing
    if workspace_root is None and packages is None and os.path.isabs(path):
        workspace_root = guess_workspace_root(path) or model_workspace(path)
    w = Walker(concrete=False, workspace_root=workspace_root, read_file=read_file,
               env=os.environ if env is None else env, packages=packages, typing=typing)
    try:
        w.run_root(path, text, {n: [(TRUE, marker(n))] for n in names}, doc)
    except RecursionError:
        pass
    return typing


def free_args(text: str, path: str, workspace_root: Optional[str] = None, read_file=None, *,
              with_defaults: bool = True, env: Optional[Mapping[str, str]] = None,
              packages: Optional[dict[str, str]] = None, doc: Optional[XmlDoc] = None) -> list[str]:
    """The top-level args a launch file checked on its own takes as free booleans: those
    without ``value`` (and, unless ``with_defaults`` is False, with or without a default: a
    default is only what roslaunch uses when the command line does not set the arg) whose
    value the load -- this file and the files it includes, through ``<arg>`` values, include
    args and ``pass_all_args`` -- only ever uses as a boolean (a whole if/unless value, a
    boolean operand in ``$(eval)``).  An arg also used as a string (a name, a file, a
    parameter value, a string comparison) keeps its value: true/false would be meaningless."""
    if doc is None:
        doc = parse_xml(text, path)
    launch = doc.root if doc.root is not None and doc.root.tag == "launch" else None
    names = _candidates(launch, with_defaults)
    # the args the command line cannot set are walked with markers too: their uses pass the
    # values of the others on (a default built from several args)
    typing = arg_uses(text, path, _candidates(launch, with_defaults, settable=False), workspace_root, read_file,
                      env=env, packages=packages, doc=doc)
    strings = typing.strings()
    names = [n for n in names if n not in strings]
    # an arg whose default is no boolean (default="", default="$(optenv UNSET_VAR)") is not free:
    # roslaunch run with the file's defaults reads that value (an if="$(arg x)" then fails), so
    # the check analyses it as it is, like `tvl-lsp launch` does
    with_default = [n for n in names if n in _top_defaults(launch)]
    if with_default:
        if packages is None:
            packages = ros_packages(workspace_root or (guess_workspace_root(path) if os.path.isabs(path) else None),
                                    env)
        values = _default_values(doc, path, with_default, os.environ if env is None else env, packages)
        names = [n for n in names if n not in values or not values[n] or
                 all(_bool_val(v) is not None for v in values[n])]
    return names


def _top_defaults(launch: Optional[XElement]) -> dict[str, str]:
    """name -> default of the top-level args that have one (and no value)."""
    return {x.attrs["name"].value: x.attrs["default"].value for x in _top_args(launch)
            if "name" in x.attrs and "default" in x.attrs and "value" not in x.attrs}


def _default_values(doc: XmlDoc, path: str, names: list[str], env: Mapping[str, str],
                    packages: dict[str, str]) -> dict[str, list[str]]:
    """The values roslaunch gives the top-level args ``names`` when the command line sets none:
    the file's top-level ``<arg>`` tags walked concretely, in order (nothing else: no include,
    no node).  An arg whose default fails to evaluate (it reads an unset arg) has no value."""
    w = Walker(concrete=True, workspace_root=None, read_file=None, env=env, packages=packages)
    u = w.unit(path, doc=doc)
    if u is None or u.launch is None:
        return {}
    emap: dict[int, Element] = {}
    w.make_elements(u.launch, path, None, 0, emap)
    sc = Scope("/", path)
    sc.cmdline = FALSE
    w.stack = [os.path.abspath(path)]
    try:
        for x in u.launch.children:
            if x.tag == "arg":
                w.arg_tag(x, emap[id(x)], sc, TRUE)
    except RecursionError:
        return {}
    return {n: [v for c, v in sc.args.get(n, []) if c == TRUE and POISON not in v and UNRESOLVED not in v]
            for n in names}


def analyse_launch(text: str, path: str, workspace_root: Optional[str] = None, read_file=None, *,
                   features: Optional[Iterable[str]] = None, env: Optional[Mapping[str, str]] = None,
                   packages: Optional[dict[str, str]] = None, alone: Optional[bool] = None) -> LaunchAnalysis:
    """Analyse a launch file for all assignments of its feature args at once.

    ``features``: the args to treat as free booleans (the paired model's features). If None,
    the top-level args without value/default whose every use is an if/unless condition.
    ``read_file(path) -> str | None`` supplies unsaved editor text for other files.
    ``alone``: the file is checked without a model (default: when ``features`` is None).
    """
    if workspace_root is None and packages is None and os.path.isabs(path):
        workspace_root = guess_workspace_root(path) or model_workspace(path)
    w = Walker(concrete=False, workspace_root=workspace_root, read_file=read_file,
               env=os.environ if env is None else env, packages=packages)
    # checked alone, the command line is how the file is meant to be run: an undeclared
    # $(arg X) it gives is a warning (paired with a model, configurations pass only features)
    w.cmdline_undeclared = alone if alone is not None else features is None
    doc = parse_xml(text, path)
    launch = doc.root if doc is not None and doc.root is not None and doc.root.tag == "launch" else None
    feature_decls: list[ArgDecl] = []
    if features is not None:
        free = [f for f in features]
    elif launch is not None:
        free = sorted(free_args(text, path, workspace_root, read_file, with_defaults=False, env=env,
                                packages=w.packages, doc=doc))
    else:
        free = []
    root_args = {f: [(Var(f), "true"), (neg(Var(f)), "false")] for f in free}
    root = w.run_root(path, text, root_args, doc)
    if root is not None and root.tag == "launch":
        for el in root.children:
            if el.tag == "arg" and "name" in el.attrs:
                a = el.attrs
                feature_decls.append(ArgDecl(a["name"].value, el.span, a["name"].value_span,
                                             a["default"].value if "default" in a else None,
                                             a["value"].value if "value" in a else None,
                                             a["doc"].value if "doc" in a else None, path, el))
    return LaunchAnalysis(path, w.diagnostics, feature_decls, free, w.elements, w.nodes, _merge_facts(w.facts),
                          w.includes, w.params, root, required_args=_required_free(feature_decls, free, w))


def _required_free(decls: list[ArgDecl], free: list[str], w: Walker) -> list[str]:
    """Free args declared without value or default whose value the load uses: roslaunch run
    with the file's defaults fails on them."""
    free_set = set(free)
    cands = {d.name for d in decls if d.name in free_set and d.default is None and d.value is None}
    if not cands:
        return []
    used: set[str] = set()
    formulas = [e.condition for e in w.elements] + [n.condition for n in w.nodes] + \
               [p.condition for p in w.params] + [f.condition for f in w.facts] + [i.condition for i in w.includes]
    for f in formulas:
        if f is TRUE or f is FALSE:
            continue
        used |= variables(f) & cands
        if len(used) == len(cands):
            break
    return sorted(used)


def _merge_facts(facts: list[ErrorFact]) -> list[ErrorFact]:
    """One fact per (code, place, message): conditions of the same error joined by 'or'."""
    out: dict[tuple, ErrorFact] = {}
    for f in facts:
        key = (f.code, f.path, f.span, f.message)
        g = out.get(key)
        if g is None:
            out[key] = ErrorFact(f.code, f.severity, f.message, f.path, f.span, f.condition, list(f.related), arg=f.arg)
        else:
            g.condition = disj([g.condition, f.condition])
            for r in f.related:
                if r not in g.related:
                    g.related.append(r)
    # an error is reported only where it holds whatever the unknowns are (an if/unless value
    # tvl-lsp cannot compute is never the cause of an error); then drop facts that no
    # assignment can trigger (checked by brute force when small)
    for f in out.values():
        f.condition = forall_unknowns(f.condition)
    return [f for f in out.values() if f.condition != FALSE and
            (len(variables(f.condition)) > 10 or _satisfiable(f.condition) is not None)]



def check_launch(analysis: LaunchAnalysis) -> list[Diagnostic]:
    """Diagnostics for a launch file on its own (no model): the unconditional diagnostics
    plus every fact whose condition some assignment of the free args satisfies, with that
    assignment as the witness."""
    out = list(analysis.diagnostics)
    seen = set()
    for f in analysis.facts:
        w = _satisfiable(f.condition)
        if w is None:
            continue
        key = (f.code, f.path, f.span, f.message)
        if key in seen:
            continue
        seen.add(key)
        msg = f.message
        if f.condition != TRUE:
            msg += f" (when {f.condition})"
        out.append(Diagnostic(f.code, f.severity, f.path, f.span, msg,
                              [Related(p, s, m) for p, s, m in f.related], witness=w or None))
    out.sort(key=lambda d: d.sort_key())
    return out


def load_launch(path: str, args: Mapping[str, str], workspace_root: Optional[str] = None, read_file=None, *,
                text: Optional[str] = None, env: Optional[Mapping[str, str]] = None,
                packages: Optional[dict[str, str]] = None) -> LoadResult:
    """What roslaunch loads from ``path`` with ``name:=value`` args (one assignment)."""
    env = os.environ if env is None else env
    if packages is None:
        if workspace_root is None:
            workspace_root = guess_workspace_root(path)
        packages = ros_packages(workspace_root, env)  # the one resolver, as --check's
    w = Walker(concrete=True, workspace_root=workspace_root or model_workspace(path), read_file=read_file, env=env,
               packages=packages)
    if text is None:
        text = w.read(path, confined=False)  # (the file named on the command line, wherever it is)
        if text is None:
            return LoadResult([], {}, [], [], f"[Errno 2] No such file or directory: '{path}'", "file-not-found")
    # roslaunch takes the command line as ROS remappings: some name:=value pairs never reach it
    root_args: dict[str, Cases] = {}
    ignored: list[str] = []
    for k, v in args.items():
        kv, why = cmdline_arg(k, v)
        if kv is None:
            ignored.append(why)
        else:
            root_args[kv[0]] = [(TRUE, kv[1])]
    w.run_root(path, text, root_args)
    error = None
    code = None
    for d in w.diagnostics:
        if d.severity == E:
            error, code = d.message, d.code
            break
    warnings = ignored + [d.message for d in w.diagnostics if d.severity != E]
    if error is None:
        for f in w.facts:  # (an unknown condition never makes an error: forall_unknowns)
            if f.severity == E and forall_unknowns(f.condition) == TRUE:
                error, code = f.message, f.code
                break
        warnings += [f.message for f in w.facts if f.condition == TRUE and f.severity != E]
    # an if/unless tvl-lsp cannot compute: the elements are listed as if it were true (if= loads,
    # unless= skips: never both), and the warning says so; an error never depends on it (above)
    taken = {u.name: TRUE for u in w.unknowns.values()}

    def loaded(c) -> bool:
        return c == TRUE or (bool(taken) and substitute(c, taken) == TRUE)
    for u in w.unknowns.values():
        if any(u.name in variables(x.condition) for x in list(w.nodes) + list(w.params)):
            warnings.append(f"tvl-lsp cannot evaluate the condition {u.name.split(':', 1)[-1]}: the elements it "
                            "decides are listed as if it were true")
    nodes = [dict(name=n.name, pkg=n.pkg, type=n.type, namespace=n.namespace, args=n.args,
                  remaps=[list(r) for r in n.remaps], file=n.path, line=n.element.span.start.line + 1)
             for n in w.nodes if loaded(n.condition) and not n.is_test]
    params: dict = {}
    sources: dict[str, str] = {}
    text: dict[str, str] = {}
    for p in w.params:
        if loaded(p.condition):
            params[p.name] = p.data
            text[p.name] = p.value
            if p.source in ("textfile", "binfile", "command"):
                sources[p.name] = p.source
            else:
                sources.pop(p.name, None)

    def inc_tree(incs: list[IncludeFact]) -> list[dict]:
        return [dict(file=i.file, followed=i.followed, namespace=i.namespace, package=i.package,
                     includes=inc_tree(i.children), **({"outside": True} if i.outside else {}))
                for i in incs if loaded(i.condition)]

    remaps = []
    for n in nodes:
        for f_, t_ in n["remaps"]:
            remaps.append(dict(node=n["name"], **{"from": f_, "to": t_}))
    return LoadResult(nodes, params, remaps, inc_tree(w.includes), error, code, warnings, sources, text)
