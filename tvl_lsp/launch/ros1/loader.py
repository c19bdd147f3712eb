"""The symbolic roslaunch loader.

One walker mirrors roslaunch 1.15's ``XmlLoader`` (``xmlloader.py``, ``loader.py``,
``substitution_args.py``) tag by tag, but every value is a list of *cases*
``(condition, string)``: the formula over the free (feature) args under which the value
is that string.  A feature arg X with no value is ``[(X, "true"), (!X, "false")]``;
everything else is computed.  Each check roslaunch makes becomes an :class:`ErrorFact`
whose condition is the disjunction of the cases where roslaunch raises it.

With concrete arg values every condition folds to a constant, so the same walker is the
concrete loader (:func:`load_launch`).
"""

from __future__ import annotations

import itertools
import os
import re
import shlex
import shutil
from dataclasses import dataclass, field
from typing import Callable, Iterable, Mapping, Optional

import yaml

from ...base.formula import FALSE, TRUE, Formula, Var, conj, disj, evaluate, neg, variables
from ...base.diagnostics import Diagnostic, Related, Severity, register
from ...base.text import LineIndex, Span
from . import subst as S
from ..model import (ArgDecl, Attr, Element, ErrorFact, IncludeFact, LaunchAnalysis, LoadResult, NodeFact,
                    ParamFact, Subst)
from ..packages import find_packages, guess_workspace_root
from ..xml import XAttr, XElement, XmlDoc, parse_xml, value_span

Cases = list  # list[tuple[Formula, str]]

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION


def _reg(code: str, sev: Severity, summary: str) -> str:
    return register(code, sev, summary, "launch")


UNDEFINED_ARG = _reg("undefined-arg", E, "$(arg X) where X is not declared in scope")
UNSET_ARG = _reg("unset-arg", W, "$(arg X) where X is declared without a value and nothing sets it")
DUPLICATE_ARG = _reg("duplicate-arg", E, "An <arg> is declared twice in the same scope")
ARG_ALREADY_SET = _reg("arg-already-set", E, "<arg value=...> for an arg that already has a value")
ARG_VALUE_AND_DEFAULT = _reg("arg-value-and-default", E, "<arg> with both value and default")
INVALID_CONDITION = _reg("invalid-condition", E, "if/unless does not evaluate to true/false/1/0")
IF_AND_UNLESS = _reg("if-and-unless", E, "Both 'if' and 'unless' on the same tag")
DUPLICATE_NODE = _reg("duplicate-node", E, "Two nodes with the same resolved name are loaded")
MISSING_ATTRIBUTE = _reg("missing-attribute", E, "A required attribute is missing")
UNKNOWN_ATTRIBUTE = _reg("unknown-attribute", W, "roslaunch does not know this attribute (it warns)")
UNKNOWN_TAG = _reg("unknown-tag", W, "roslaunch does not know this tag (it warns and ignores it)")
INVALID_VALUE = _reg("invalid-attribute-value", E, "An attribute value roslaunch rejects")
NODE_NAME_NS = _reg("node-name-namespace", E, "A node name contains a namespace")
ILLEGAL_NAME = _reg("illegal-node-name", W, "A node name that is not a legal ROS name")
EMPTY_NS = _reg("empty-ns", E, "An empty 'ns' attribute")
RESPAWN_REQUIRED = _reg("respawn-and-required", E, "respawn and required both true")
PARAM_VALUE_COUNT = _reg("param-value-count", E, "<param> without exactly one of value/textfile/binfile/command")
PARAM_INVALID = _reg("invalid-param", E, "A <param> or <rosparam> roslaunch cannot load")
COMMAND_NOT_FOUND = _reg("command-not-found", E, "<param command=...> names a program that does not exist")
FILE_NOT_FOUND = _reg("file-not-found", E, "A file a tag loads does not exist")
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
INCLUDE_ARG_NO_VALUE = _reg("include-arg-no-value", E, "An <arg> inside <include> without value or default")
UNUSED_INCLUDE_ARG = _reg("unused-include-arg", E, "An arg passed to an include that it does not declare")
NO_LAUNCH_ROOT = _reg("no-launch-root", E, "The file has no single <launch> element")
LAUNCH_IF_UNLESS = _reg("launch-if-unless", W, "if/unless on <launch> (roslaunch ignores it or crashes)")
MACHINE_INVALID = _reg("invalid-machine", E, "A <machine> roslaunch rejects")
ENV_INVALID = _reg("invalid-env", E, "An <env> roslaunch rejects")
REMAP_INVALID = _reg("invalid-remap", E, "A <remap> roslaunch rejects")
TEST_INVALID = _reg("invalid-test", E, "A <test> roslaunch rejects")
BUDGET = _reg("launch-analysis-budget", W, "The launch file is too large to analyse completely")

MAX_CASES = 64
MAX_INCLUDE_DEPTH = 12
MAX_VISITS = 200_000
MAX_WALK_DEPTH = 150
UNRESOLVED = "\x01"  # marks text produced by an unresolved $(find pkg)
# the value of an arg whose value/default failed to evaluate (the failure is already reported;
# uses of the arg are not reported again)
POISON = UNRESOLVED + "?" + UNRESOLVED

NAME_LEGAL = re.compile(r"^[~/A-Za-z][\w/]*$")

LAUNCH_CHILD_TAGS = {"arg", "group", "node", "test", "param", "remap", "machine", "rosparam", "master",
                     "include", "env"}
NODE_ATTRS = ("pkg", "type", "machine", "name", "args", "output", "respawn", "respawn_delay", "cwd", "ns",
              "clear_params", "launch-prefix", "required")
TAG_ATTRS = {
    "node": NODE_ATTRS,
    "test": NODE_ATTRS + ("test-name", "time-limit", "retry"),
    "param": ("name", "value", "type", "textfile", "binfile", "command"),
    "rosparam": ("command", "ns", "file", "param", "subst_value"),
    "arg": ("name", "value", "default", "doc"),
    "machine": ("name", "address", "env-loader", "ssh-port", "user", "password", "default", "timeout",
                "ros-root", "ros-package-path", "ros-ip", "ros-hostname"),
    "remap": ("from", "to"),
    "env": ("name", "value"),
    "include": ("file", "ns", "clear_params", "pass_all_args"),
    "group": ("ns", "clear_params"),
    "launch": ("deprecated",),
    "master": ("auto",),
}


# ------------------------------------------------------------------ helpers

def ns_join(ns: str, name: str) -> str:
    if name and name[0] in "~/":
        return name
    if ns == "~":
        return "~" + name
    if not ns:
        return name
    if ns[-1] == "/":
        return ns + name
    return ns + "/" + name


def make_global_ns(name: str) -> str:
    if not name.startswith("/"):
        name = "/" + name
    if not name.endswith("/"):
        name += "/"
    return name


def canonicalize(name: str) -> str:
    if not name or name == "/":
        return name
    if name[0] == "/":
        return "/" + "/".join(x for x in name.split("/") if x)
    return "/".join(x for x in name.split("/") if x)


def is_legal_name(name: str) -> bool:
    if name == "":
        return True
    return bool(NAME_LEGAL.match(name)) and "//" not in name


def shown(s: str) -> str:
    """A value for messages: unresolved $(find) markers printed back as written."""
    s = s.replace(POISON, "<error>")
    return re.sub(UNRESOLVED + r"([^" + UNRESOLVED + r"]*)" + UNRESOLVED, r"$(find \1)", s)


def merge(cases: Iterable[tuple[Formula, str]]) -> Cases:
    out: dict[str, Formula] = {}
    for c, v in cases:
        if c == FALSE:
            continue
        out[v] = disj([out[v], c]) if v in out else c
    return [(c, v) for v, c in out.items()]


def when(cases: Cases, pred: Callable[[str], bool]) -> Formula:
    return disj(c for c, v in cases if pred(v))


def _bool_val(v: str) -> Optional[bool]:
    lv = v.lower().strip()
    if lv in ("true", "1"):
        return True
    if lv in ("false", "0"):
        return False
    return None


def _attr_bool(v: str) -> Optional[bool]:
    lv = v.lower()
    if lv == "true":
        return True
    if lv == "false":
        return False
    return None


def _is_float(v: str) -> bool:
    try:
        float(v)
        return True
    except ValueError:
        return False


# ------------------------------------------------------------------ scope

class Scope:
    """roslaunch's LoaderContext, with guarded values."""

    __slots__ = ("ns", "filename", "arg_names", "args", "include_args", "include_names", "pass_all",
                 "params", "remaps", "env", "anon", "passed", "lookup_names")

    def __init__(self, ns: str, filename: str):
        self.ns = make_global_ns(ns or "/") if ns != "~" else "~"
        self.filename = filename
        self.arg_names: dict[str, Formula] = {}
        self.args: dict[str, Cases] = {}
        self.include_args: Optional[dict[str, Cases]] = None
        self.include_names: Optional[dict[str, Formula]] = None
        self.pass_all = False
        self.params: list = []
        self.remaps: list[tuple[str, str, Formula]] = []
        self.env: list = []
        self.anon: dict[str, str] = {}
        self.passed: dict[str, Formula] = {}
        self.lookup_names: Optional[dict[str, Formula]] = None  # declared names for $(arg) lookups

    def child(self, ns: Optional[str]) -> "Scope":
        if ns:
            if ns[0] == "/":
                cns = ns
            elif ns == "~":
                cns = "~"
            else:
                cns = ns_join(self.ns, ns)
        else:
            cns = self.ns
        c = Scope.__new__(Scope)
        c.ns = make_global_ns(cns) if cns != "~" else "~"
        c.filename = self.filename
        c.arg_names = dict(self.arg_names)
        c.args = {k: list(v) for k, v in self.args.items()}
        c.include_args = self.include_args
        c.include_names = None
        c.pass_all = False
        c.params = self.params
        c.remaps = list(self.remaps)
        c.env = list(self.env)
        c.anon = dict(self.anon)
        c.passed = {}
        c.lookup_names = None
        return c


@dataclass
class _Unit:
    """A parsed file (cached per path)."""
    path: str
    doc: XmlDoc
    launch: Optional[XElement]
    error: Optional[str]


# ------------------------------------------------------------------ walker

class Walker:
    def __init__(self, *, concrete: bool, workspace_root: Optional[str], read_file, env: Mapping[str, str],
                 packages: Optional[dict[str, str]] = None):
        self.concrete = concrete
        self.read_file = read_file
        self.env = env
        self.packages = dict(packages) if packages is not None else find_packages(workspace_root)
        self.facts: list[ErrorFact] = []
        self.nodes: list[NodeFact] = []
        self.params: list[ParamFact] = []
        self.elements: list[Element] = []
        self.includes: list[IncludeFact] = []
        self.diagnostics: list[Diagnostic] = []
        self.units: dict[str, _Unit] = {}
        self.index: dict[str, LineIndex] = {}
        self.node_names: dict[str, list[NodeFact]] = {}
        self.visits = 0
        self.budget_hit = False
        self.anon_counter = itertools.count(1)
        self.reported_not_analysable: set = set()
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

    # ---------------------------------------------------------------- substitution

    def resolve(self, x: XElement, el: Element, name: str, sc: Scope, guard: Formula,
                where: str = "") -> Optional[Cases]:
        """Cases of attribute ``name`` (None if absent). Errors become facts; the cases
        cover ``guard`` minus the error cases."""
        a = x.attrs.get(name)
        if a is None:
            return None
        return self.resolve_text(a.value, a, el, sc, guard, where)

    def resolve_text(self, value: str, a: Optional[XAttr], el: Element, sc: Scope, guard: Formula,
                     where: str = "") -> Cases:
        if guard == FALSE:
            return []
        if not value or "$" not in value:
            return [(guard, value)]
        idx = self.index[el.path]

        def sp(i: int, j: int) -> Span:
            return value_span(a, idx, i, j) if a is not None else el.span

        whole = sp(0, len(value))
        if S.is_eval(value):
            return self.resolve_eval(value, a, el, sc, guard, whole, where)
        try:
            parts = S.collect(value)
        except S.SubstError as e:
            self.fact(SUBST_SYNTAX, str(e), el, whole, guard)
            return []
        for inner, i, j in parts:
            words = [w for w in inner.split(" ") if w]
            if not words or words[0] not in S.VALID:
                self.fact(SUBST_UNKNOWN, f"Unknown substitution command [{inner}]. Valid commands are "
                          f"{list(S.VALID)}", el, sp(i, j), guard)
                return []
        cases: Cases = [(guard, value)]
        for inner, i, j in parts:
            words = [w for w in inner.split(" ") if w]
            cmd, args = words[0], words[1:]
            if cmd == "find":
                continue
            token = f"$({inner})"
            span = sp(i, j)
            new: Cases = []
            for c, s in cases:
                if token not in s:
                    new.append((c, s))
                    continue
                for c2, rep in self.subst_one(cmd, args, inner, el, sc, c, span, where):
                    new.append((c2, s.replace(token, rep)))
            cases = merge(new)
            if len(cases) > MAX_CASES:
                self.note(CONDITION_NOT_ANALYSABLE, "too many combinations of arg values to analyse this value",
                          el, whole)
                cases = cases[:MAX_CASES]
        # second pass: $(find)
        out: Cases = []
        for c, s in cases:
            if "$" not in s:
                out.append((c, s))
                continue
            try:
                parts2 = S.collect(s)
            except S.SubstError as e:
                self.fact(SUBST_SYNTAX, str(e), el, whole, c)
                continue
            ok = True
            for inner, _, _ in parts2:
                words = [w for w in inner.split(" ") if w]
                if not words or words[0] not in S.VALID:
                    self.fact(SUBST_UNKNOWN, f"Unknown substitution command [{inner}]. Valid commands are "
                              f"{list(S.VALID)}", el, whole, c)
                    ok = False
                    break
            if not ok:
                continue
            for inner, _, _ in parts2:
                words = [w for w in inner.split(" ") if w]
                if words[0] != "find":
                    continue
                token = f"$({inner})"
                k = value.find("$(find")
                span = sp(k, value.find(")", k) + 1) if k >= 0 else whole
                if len(words) != 2:
                    self.fact(SUBST_ARITY, f"$(find pkg) command only accepts one argument [{inner}]", el, span, c)
                    ok = False
                    break
                pkg = words[1]
                path = self.packages.get(pkg)
                if path is None:
                    if self.concrete:
                        self.fact(PACKAGE_NOT_FOUND, f"ResourceNotFound: {pkg}", el, span, c)
                        ok = False
                        break
                    path = UNRESOLVED + pkg + UNRESOLVED
                k2 = s.find(token)
                after = s[k2 + len(token):]
                sep = after.find(" ")
                rel, rest = (after, "") if sep < 0 else (after[:sep], after[sep:])
                rel = rel.lstrip("/")
                s = s[:k2] + (os.path.join(path, rel) if rel else path) + rest
            if ok:
                out.append((c, s))
        return merge(out)

    def subst_one(self, cmd: str, args: list[str], inner: str, el: Element, sc: Scope, c: Formula,
                  span: Span, where: str) -> Cases:
        if cmd == "arg":
            if len(args) == 0:
                self.fact(SUBST_ARITY, f"$(arg var) must specify a variable name [{inner}]", el, span, c)
                return []
            if len(args) > 1:
                self.fact(SUBST_ARITY, f"$(arg var) may only specify one arg [{inner}]", el, span, c)
                return []
            return self.lookup_arg(args[0], el, sc, c, span, where)
        if cmd == "env":
            if len(args) != 1:
                self.fact(SUBST_ARITY, f"$(env var) command only accepts one argument [{inner}]", el, span, c)
                return []
            if args[0] not in self.env:
                self.fact(ENV_NOT_SET, f"environment variable '{args[0]}' is not set (in tvl-lsp's environment; "
                          "roslaunch fails the same way unless it is set when launching)", el, span, c)
                return []
            return [(c, self.env[args[0]])]
        if cmd == "optenv":
            if len(args) == 0:
                self.fact(SUBST_ARITY, f"$(optenv var) must specify an environment variable [{inner}]", el, span, c)
                return []
            return [(c, self.env.get(args[0], " ".join(args[1:])))]
        if cmd == "anon":
            if len(args) != 1:
                self.fact(SUBST_ARITY, "$(anon var) must specify a name [%s]" % inner if not args
                          else "$(anon var) may only specify one name [%s]" % inner, el, span, c)
                return []
            if args[0] not in sc.anon:
                sc.anon[args[0]] = S.anon_name(args[0], lambda: next(self.anon_counter))
            return [(c, sc.anon[args[0]])]
        if cmd == "dirname":
            if not sc.filename:
                self.fact(SUBST_ARITY, "Cannot substitute $(dirname), no file/directory information available.",
                          el, span, c)
                return []
            return [(c, os.path.abspath(os.path.dirname(sc.filename)))]
        return [(c, f"$({inner})")]

    def lookup_arg(self, name: str, el: Element, sc: Scope, c: Formula, span: Span, where: str) -> Cases:
        vals = sc.args.get(name, [])
        out = [(conj([c, vc]), v) for vc, v in vals]
        out = [(f, v) for f, v in out if f != FALSE]
        present = disj(vc for vc, _ in vals)
        missing = conj([c, neg(present)])
        if missing != FALSE:
            names = sc.lookup_names if sc.lookup_names is not None else sc.arg_names
            declared = names.get(name, FALSE)
            if where == "arg":
                base = f"arg '{name}' is not defined"
            elif where.startswith("include:"):
                base = f"included file [{os.path.basename(where[8:])}] requires the '{name}' arg to be set"
            else:
                base = f"{os.path.basename(sc.filename)} requires the '{name}' arg to be set"
            self.fact(UNDEFINED_ARG, f"{base}: '{name}' is not declared in this scope", el, span,
                      conj([missing, neg(declared)]))
            self.fact(UNSET_ARG, f"{base}: '{name}' is declared without value or default and nothing sets it",
                      el, span, conj([missing, declared]))
        return out

    def resolve_eval(self, value: str, a, el: Element, sc: Scope, guard: Formula, span: Span,
                     where: str) -> Cases:
        expr = value[7:-1]
        try:
            tree = S.parse_eval(expr)
        except S.SubstError as e:
            self.fact(EVAL_ERROR, str(e), el, span, guard)
            return []
        names, ok = S.eval_names(tree)
        if not ok:
            self.note(CONDITION_NOT_ANALYSABLE, f"tvl-lsp cannot translate '$(eval {expr.strip()})' into a "
                      "formula over args; it assumes the value may be anything", el, span)
            return [(guard, value)]
        names_l = sorted(names)
        per: list[Cases] = []
        for n in names_l:
            vals = [(vc, v) for vc, v in sc.args.get(n, []) if conj([guard, vc]) != FALSE]
            present = disj(vc for vc, _ in vals)
            rest = conj([guard, neg(present)])
            if rest != FALSE:
                vals = vals + [(rest, None)]
            per.append(vals)
        total = 1
        for p in per:
            total *= max(len(p), 1)
        if total > MAX_CASES:
            self.note(CONDITION_NOT_ANALYSABLE, "too many combinations of arg values to analyse this $(eval)",
                      el, span)
            return [(guard, value)]
        out: Cases = []
        for combo in itertools.product(*per) if per else [()]:
            cond = conj([guard] + [vc for vc, _ in combo])
            if cond == FALSE:
                continue
            env_args = {n: v for n, (_, v) in zip(names_l, combo) if v is not None}
            try:
                out.append((cond, S.run_eval(tree, env_args, self.env)))
            except S.EvalArgMissing as m:
                self.lookup_arg(m.name, el, sc, cond, span, where)
            except S.NotAnalysable:
                self.note(CONDITION_NOT_ANALYSABLE, f"tvl-lsp cannot evaluate '$(eval {expr.strip()})'; it "
                          "assumes the value may be anything", el, span)
                return [(guard, value)]
            except S.SubstError as e:
                self.fact(EVAL_ERROR, str(e), el, span, cond)
        return merge(out)

    # ---------------------------------------------------------------- conditions

    def ifunless(self, x: XElement, el: Element, sc: Scope, guard: Formula, where: str = "") -> Formula:
        if guard == FALSE:
            return FALSE
        ifc = self.resolve(x, el, "if", sc, guard, where)
        unc = self.resolve(x, el, "unless", sc, guard, where)
        if ifc is None and unc is None:
            return guard
        if ifc is not None and unc is not None:
            self.fact(IF_AND_UNLESS, "cannot set both 'if' and 'unless' on the same tag", el,
                      el.tag_span, conj([disj(c for c, _ in ifc), disj(c for c, _ in unc)]))
            return FALSE
        cases = ifc if ifc is not None else unc
        key = "if" if ifc is not None else "unless"
        bad = []
        ok = []
        for c, v in cases:
            if v.startswith("$(eval ") or UNRESOLVED in v:
                ok.append(c)  # not analysable: assume loaded
                continue
            b = _bool_val(v)
            if b is None:
                bad.append((c, v))
            elif b == (key == "if"):
                ok.append(c)
        for c, v in bad:
            self.fact(INVALID_CONDITION, f"{v.lower().strip()} is not a 'bool' type: the value of '{key}' must be "
                      "true, false, 1 or 0", el, self.aspan(el, key), c)
        return disj(ok)

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

    def launch_tag(self, x: XElement, el: Element, sc: Scope):
        for k in ("if", "unless"):
            a = x.attrs.get(k)
            if a is None:
                continue
            if "$" in a.value:
                self.fact(LAUNCH_IF_UNLESS, f"roslaunch crashes on '{k}' with a substitution on <launch> "
                          "(AttributeError: it evaluates it without an arg context); use a <group> instead",
                          el, a.value_span, el.condition)
            elif _bool_val(a.value) is None:
                self.fact(LAUNCH_IF_UNLESS, f"{a.value.lower().strip()} is not a 'bool' type (roslaunch fails on "
                          f"'{k}' of <launch>)", el, a.value_span, el.condition)
            else:
                self.fact(LAUNCH_IF_UNLESS, f"roslaunch ignores '{k}' on <launch> (it only controls the "
                          "deprecation message): the whole file is always loaded; use a <group> instead",
                          el, a.name_span, el.condition, severity=W)

    def static_checks(self, launch: XElement, emap, path: str):
        """Unknown tags and attributes (roslaunch warns about them)."""
        def attrs(x: XElement, tag: str):
            allowed = TAG_ATTRS.get(tag)
            if allowed is None:
                return
            el = emap[id(x)]
            for k, a in x.attrs.items():
                if k in ("if", "unless") or k in allowed:
                    continue
                if tag == "launch":
                    continue
                self.diagnostics.append(Diagnostic(UNKNOWN_ATTRIBUTE, W, path, a.name_span,
                                                   f"[{path}] unknown <{tag}> attribute '{k}'"))

        def walk(children: list[XElement], ctx: str, depth: int):
            for x in children:
                el = emap[id(x)]
                if ctx in ("launch", "group"):
                    if x.tag not in LAUNCH_CHILD_TAGS:
                        self.diagnostics.append(Diagnostic(UNKNOWN_TAG, W, path, el.tag_span or el.span,
                                                           f"unrecognized tag {x.tag}"))
                        continue
                    attrs(x, x.tag)
                    if x.tag == "group":
                        walk(x.children, "group", depth + 1)
                    elif x.tag in ("node", "test", "include", "machine"):
                        walk(x.children, x.tag, depth + 1)
                elif ctx in ("node", "test"):
                    t = x.tag.lower()
                    if t not in ("remap", "param", "rosparam", "env"):
                        self.diagnostics.append(Diagnostic(UNKNOWN_TAG, W, path, el.tag_span or el.span,
                                                           f"WARN: unrecognized '{x.tag}' child tag in <{ctx}>"))
                    else:
                        attrs(x, t)
                elif ctx == "include":
                    t = x.tag.lower()
                    if t not in ("env", "arg"):
                        self.diagnostics.append(Diagnostic(UNKNOWN_TAG, W, path, el.tag_span or el.span,
                                                           f"WARN: unrecognized '{x.tag}' tag in <include> tag"))
                    else:
                        attrs(x, t)
                elif ctx == "machine" and x.tag != "env":
                    self.diagnostics.append(Diagnostic(UNKNOWN_TAG, W, path, el.tag_span or el.span,
                                                       f"unrecognized '{x.tag}' tag in <machine> tag"))
        attrs(launch, "launch")
        walk(launch.children, "launch", 0)

    # ---------------------------------------------------------------- recursion

    def tick(self, el: Element) -> bool:
        self.visits += 1
        if self.visits > MAX_VISITS:
            if not self.budget_hit:
                self.budget_hit = True
                self.facts.append(ErrorFact(BUDGET, W, f"the launch file (with its includes) is too large to analyse "
                                            f"completely; analysis stopped after {MAX_VISITS} elements",
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
                el.condition = disj([el.condition, cond])
                for c, child in self.ns_clear_params(x, el, sc, cond, "group"):
                    child.params = list(child.params)
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

    def ns_clear_params(self, x: XElement, el: Element, sc: Scope, guard: Formula, tag: str,
                        include_file: Optional[str] = None, node_name: Optional[Cases] = None):
        """Child scopes per case of the 'ns' attribute: [(condition, scope)]."""
        nsc = self.resolve(x, el, "ns", sc, guard)
        out = []
        if nsc is None:
            nsc_ = [(guard, None)]
        else:
            self.fact(EMPTY_NS, f"<{tag}> tag has an empty 'ns' attribute", el, self.aspan(el, "ns"),
                      when(nsc, lambda v: not v))
            nsc_ = [(c, v) for c, v in nsc if v]
        cp = self.resolve(x, el, "clear_params", sc, guard)
        if cp:
            pre = "Invalid <node> tag: " if tag == "node" else ""
            for c, v in cp:
                if v and _attr_bool(v) is None:
                    self.fact(INVALID_VALUE, f"{pre}invalid bool value for clear_params: {v}", el,
                              self.aspan(el, "clear_params"), c)
            if tag not in ("node",) and nsc is None:
                self.fact(INVALID_VALUE, "'ns' attribute must be set in order to use 'clear_params'", el,
                          self.aspan(el, "clear_params"), when(cp, lambda v: _attr_bool(v) is True))
            if tag == "node" and node_name is not None:
                self.fact(INVALID_VALUE, "<node> tag must have a 'name' attribute to use 'clear_params' attribute",
                          el, self.aspan(el, "clear_params"),
                          conj([when(cp, lambda v: _attr_bool(v) is True), when(node_name, lambda v: not v)]))
        for c, v in nsc_:
            child = sc.child(v)
            if include_file is not None:
                child.arg_names = {}
                child.filename = include_file
                child.include_args = {}
                child.include_names = {}
            out.append((c, child))
        return out

    # ---------------------------------------------------------------- <arg>

    def arg_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        if "name" not in x.attrs:
            self.fact(MISSING_ATTRIBUTE, "Invalid <arg> tag: 'name'", el, el.tag_span, cond)
            return
        names = self.resolve(x, el, "name", sc, cond, "arg")
        value = self.resolve(x, el, "value", sc, cond, "arg")
        default = self.resolve(x, el, "default", sc, cond, "arg")
        self.resolve(x, el, "doc", sc, cond, "arg")
        if value is not None and default is not None:
            self.fact(ARG_VALUE_AND_DEFAULT, "<arg> tag must have one and only one of value/default.", el,
                      el.tag_span, cond)
            return
        for cs in (value, default):
            if cs is not None:
                failed = conj([cond, neg(disj(c for c, _ in cs))])
                if failed != FALSE and (len(variables(failed)) > 10 or _satisfiable(failed) is not None):
                    cs.append((failed, POISON))  # reported already: do not cascade
        for nc, name in names:
            vals = None
            if value is not None:
                vals = [(conj([nc, c]), v) for c, v in value]
            elif default is not None:
                vals = [(conj([nc, c]), v) for c, v in default]
            self.add_arg(sc, name, nc, vals, value is not None, el)

    def add_arg(self, sc: Scope, name: str, g: Formula, vals: Optional[Cases], is_value: bool, el: Element):
        names = sc.include_names if sc.include_names is not None else sc.arg_names
        d = names.get(name, FALSE)
        if not sc.pass_all:
            self.fact(DUPLICATE_ARG, f"Invalid <arg> tag: arg '{name}' has already been declared", el,
                      self.aspan(el, "name"), conj([g, d]))
        names[name] = disj([d, g])
        adict = sc.include_args if sc.include_args is not None else sc.args
        old = adict.get(name, [])
        present = disj(c for c, _ in old)
        if vals is None:
            return
        if is_value:
            if not sc.pass_all:
                self.fact(ARG_ALREADY_SET, f"Invalid <arg> tag: cannot override arg '{name}', which has already "
                          "been set", el, self.aspan(el, "value"), conj([g, present]))
            ng = neg(g)
            new = [(conj([c, ng]), v) for c, v in old] + list(vals)
        else:
            np_ = neg(present)
            new = list(old) + [(conj([c, np_]), v) for c, v in vals]
        adict[name] = merge(new)

    # ---------------------------------------------------------------- <node>/<test>

    def node_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula, emap, is_test: bool):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        tag = "test" if is_test else "node"
        wrap = "Invalid <node> tag: "
        if is_test:
            for k in ("respawn", "respawn_delay", "output"):
                if k in x.attrs:
                    self.fact(TEST_INVALID, f"{wrap}<test> tags cannot have '{k}' attribute", el,
                              x.attrs[k].name_span, cond)
                    return
            if "test-name" not in x.attrs:
                self.fact(MISSING_ATTRIBUTE, "<test> tag is missing required attribute: 'test-name'", el,
                          el.tag_span, cond)
                return
            tname = self.resolve(x, el, "test-name", sc, cond)
            for k, msg in (("time-limit", "'time-limit' must be a number"), ("retry", "'retry' must be a number")):
                tc = self.resolve(x, el, k, sc, cond)
                if tc:
                    conv = float if k == "time-limit" else int
                    def bad(v, conv=conv):
                        if not v:
                            return False
                        try:
                            conv(v)
                            return False
                        except ValueError:
                            return True
                    for c, v in tc:
                        if bad(v):
                            self.fact(TEST_INVALID, f"{wrap}{msg}: [{v}]", el, self.aspan(el, k), c)
                    if k == "time-limit":
                        self.fact(TEST_INVALID, f"{wrap}'time-limit' must be a positive number", el,
                                  self.aspan(el, k), when(tc, lambda v: bool(v) and _is_float(v) and float(v) <= 0))
            name = self.resolve(x, el, "name", sc, cond)
            if name is None:
                name = tname
            else:
                name = merge([(c, v) for c, v in name if v] +
                             [(conj([c, c2]), v2) for c, v in name if not v for c2, v2 in tname])
        else:
            if "name" not in x.attrs:
                self.fact(MISSING_ATTRIBUTE, "<node> tag is missing required attribute: 'name'", el, el.tag_span, cond)
                return
            name = self.resolve(x, el, "name", sc, cond)
        for c, v in name:
            if not is_legal_name(v) and UNRESOLVED not in v and "$(" not in v:
                self.fact(ILLEGAL_NAME, f"WARN: illegal <{tag}> name '{v}'", el, self.aspan(el, "name"), c, severity=W)
        scopes = self.ns_clear_params(x, el, sc, cond, "node", node_name=name)
        for k in ("pkg", "type"):
            if k not in x.attrs:
                self.fact(MISSING_ATTRIBUTE, f"<{tag}> tag is missing required attribute: '{k}'", el, el.tag_span, cond)
                return
        pkg = self.resolve(x, el, "pkg", sc, cond) or []
        typ = self.resolve(x, el, "type", sc, cond) or []
        opt = {k: self.resolve(x, el, k, sc, cond) for k in
               ("machine", "args", "output", "respawn", "respawn_delay", "cwd", "launch-prefix", "required")}
        for k in ("required", "respawn"):
            cs = opt[k]
            if cs is None:
                continue
            self.fact(INVALID_VALUE, f"{wrap}bool value for {k} must be non-empty", el, self.aspan(el, k),
                      when(cs, lambda v: v == ""))
            for c, v in cs:
                if v and _attr_bool(v) is None:
                    self.fact(INVALID_VALUE, f"{wrap}invalid bool value for {k}: {v}", el, self.aspan(el, k), c)
        if opt["respawn_delay"]:
            self.fact(INVALID_VALUE, f"{wrap}bool value for respawn_delay must be non-empty", el,
                      self.aspan(el, "respawn_delay"), when(opt["respawn_delay"], lambda v: v == ""))
            for c, v in opt["respawn_delay"]:
                if v and not _is_float(v):
                    self.fact(INVALID_VALUE, f"{wrap}invalid float value for respawn_delay: {v}", el,
                              self.aspan(el, "respawn_delay"), c)
        # children
        remaps = list(sc.remaps)
        node_remap_scope = Scope.__new__(Scope)
        node_remap_scope.remaps = remaps
        for cx in x.children:
            cel = emap[id(cx)]
            if not self.tick(cel):
                return
            t = cx.tag.lower()
            if t == "remap":
                c2 = self.ifunless(cx, cel, sc, cond)
                if c2 != FALSE:
                    cel.condition = disj([cel.condition, c2])
                    self.remap_tag(cx, cel, sc, c2, node_remap_scope)
            elif t == "param":
                self.param_tag(cx, cel, sc, cond, node_ns=(scopes, name))
            elif t == "rosparam":
                self.rosparam_tag(cx, cel, sc, cond, node_ns=(scopes, name))
            elif t == "env":
                c2 = self.ifunless(cx, cel, sc, cond)
                if c2 != FALSE:
                    cel.condition = disj([cel.condition, c2])
                    self.env_tag(cx, cel, sc, c2, wrap)
        # Node() validation
        if opt["respawn"] is not None and opt["required"] is not None:
            self.fact(RESPAWN_REQUIRED, f"{wrap}respawn and required cannot both be set to true", el, el.tag_span,
                      conj([when(opt["respawn"], lambda v: _attr_bool(v) is True),
                            when(opt["required"], lambda v: _attr_bool(v) is True)]))
        self.fact(NODE_NAME_NS, f"{wrap}node name cannot contain a namespace", el, self.aspan(el, "name"),
                  when(name, lambda v: "/" in v and UNRESOLVED not in v))
        self.fact(INVALID_VALUE, f"{wrap}package must be non-empty", el, self.aspan(el, "pkg"),
                  when(pkg, lambda v: not v.strip()))
        self.fact(INVALID_VALUE, f"{wrap}type must be non-empty", el, self.aspan(el, "type"),
                  when(typ, lambda v: not v.strip()))
        if opt["output"] is not None and not is_test:
            self.fact(INVALID_VALUE, f"{wrap}output must be one of 'log', 'screen'", el, self.aspan(el, "output"),
                      when(opt["output"], lambda v: v not in ("log", "screen")))
        if opt["cwd"] is not None:
            self.fact(INVALID_VALUE, f"{wrap}cwd must be one of 'ROS_HOME', 'node'", el, self.aspan(el, "cwd"),
                      when(opt["cwd"], lambda v: v not in ("ROS_HOME", "node", "ros_home")))
        pkg1 = pkg[0][1] if len(pkg) == 1 else "|".join(v for _, v in pkg)
        typ1 = typ[0][1] if len(typ) == 1 else "|".join(v for _, v in typ)
        argstr = (opt["args"] or [(TRUE, "")])[0][1] if opt["args"] else ""
        for sc_c, child in scopes:
            for nc, nm in name:
                c = conj([sc_c, nc])
                if c == FALSE or not nm:
                    continue
                nsn = child.ns if child.ns != "~" else "~/"
                nsn = re.sub("//+", "/", make_global_ns(nsn)) if nsn != "~/" else nsn
                full = ns_join(nsn, nm)
                node_remaps = [(f, t) for f, t, rc in node_remap_scope.remaps if conj([rc, c]) != FALSE]
                nf = NodeFact(shown(full), shown(pkg1), shown(typ1), nsn, el, c, el.path, shown(argstr),
                              node_remaps, is_test)
                for pname, pcases, pc in sc.params:
                    for vc, pv in pcases:
                        pcond = conj([c, pc, vc])
                        if pcond != FALSE:
                            self.params.append(ParamFact(shown(full + "/" + pname[1:]), shown(pv), el, pcond))
                if is_test:
                    self.nodes.append(nf)
                    continue
                for other in self.node_names.get(full, []):
                    both = conj([other.condition, c])
                    self.fact(DUPLICATE_NODE, f"roslaunch file contains multiple nodes named [{shown(full)}]. Please "
                              "check all <node> 'name' attributes to make sure they are unique.", el,
                              self.aspan(el, "name"), both,
                              related=[(other.path, other.element.attrs["name"].value_span
                                        if "name" in other.element.attrs else other.element.span,
                                        "the other node with this name")])
                self.node_names.setdefault(full, []).append(nf)
                self.nodes.append(nf)

    # ---------------------------------------------------------------- <param>

    def param_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula, node_ns=None):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        vals = {k: self.resolve(x, el, k, sc, cond) for k in ("value", "textfile", "binfile", "command")}
        present = [k for k, v in vals.items() if v is not None]
        if len(present) != 1:
            self.fact(PARAM_VALUE_COUNT, "<param> tag must have one and only one of value/textfile/binfile.", el,
                      el.tag_span, cond)
            return
        if "name" not in x.attrs:
            self.fact(MISSING_ATTRIBUTE, "<param> tag is missing required attribute: 'name'", el, el.tag_span, cond)
            return
        a = x.attrs["name"]
        names = self.resolve_text(a.value.strip(), a, el, sc, cond)
        kind = present[0]
        ptype = (x.attrs["type"].value if "type" in x.attrs else "auto").lower().strip() or "auto"
        for c, v in vals[kind]:
            if kind == "value":
                err = _convert_error(v.strip(), ptype)
                if err:
                    self.fact(PARAM_INVALID, f"Invalid <param> tag: {err}", el, self.aspan(el, "value"), c)
            elif kind in ("textfile", "binfile"):
                if UNRESOLVED not in v and not self.exists(v):
                    self.fact(FILE_NOT_FOUND, f"Invalid <param> tag: [Errno 2] No such file or directory: '{v}'", el,
                              self.aspan(el, kind), c)
            elif kind == "command":
                self.check_command(v, el, c)
        for c, nm in names:
            if not nm:
                self.fact(PARAM_INVALID, "Invalid <param> tag: no parameter name specified", el,
                          self.aspan(el, "name"), c)
                continue
            if node_ns is not None:
                for sc_c, child in node_ns[0]:
                    for nc, nn in node_ns[1]:
                        key = ns_join(ns_join(child.ns, nn) + "/", nm.lstrip("~"))
                        self.params.append(ParamFact(shown(key), shown(vals[kind][0][1]) if vals[kind] else "",
                                                     el, conj([c, sc_c, nc])))
            elif nm.startswith("~"):
                sc.params.append((nm, vals[kind], c))
            else:
                self.params.append(ParamFact(shown(ns_join(sc.ns, nm)), shown(vals[kind][0][1]) if vals[kind] else "",
                                             el, c))

    def check_command(self, v: str, el: Element, c: Formula):
        if UNRESOLVED in v:
            return
        try:
            words = shlex.split(v)
        except ValueError as e:
            self.fact(PARAM_INVALID, f"Invalid <param> tag: cannot split command: {e}", el,
                      self.aspan(el, "command"), c)
            return
        if not words:
            self.fact(PARAM_INVALID, "Invalid <param> tag: empty command", el, self.aspan(el, "command"), c)
            return
        prog = words[0]
        if "/" in prog:
            found = os.path.exists(prog)
            if not found and not self.concrete:
                return  # a path we cannot check statically (e.g. an install space)
        else:
            found = shutil.which(prog, path=self.env.get("PATH", os.defpath)) is not None
        if not found:
            self.fact(COMMAND_NOT_FOUND, f"Invalid <param> tag: Cannot load command parameter: no such command "
                      f"[{words!r}]", el, self.aspan(el, "command"), c)

    # ---------------------------------------------------------------- <rosparam>

    def rosparam_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula, node_ns=None):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        r = {k: self.resolve(x, el, k, sc, cond) for k in ("command", "ns", "file", "param", "subst_value")}
        pre = "error loading <rosparam> tag: "
        if r["subst_value"]:
            for c, v in r["subst_value"]:
                if v and _attr_bool(v) is None:
                    self.fact(INVALID_VALUE, f"{pre}invalid bool value for subst_value: {v}", el,
                              self.aspan(el, "subst_value"), c)
        cmds = r["command"] or [(cond, "load")]
        has_param = bool(r["param"] and any(v for _, v in r["param"])) or bool(r["ns"] and any(v for _, v in r["ns"]))
        for c, cmd in cmds:
            cmd = cmd or "load"
            if cmd not in ("load", "dump", "delete"):
                self.fact(PARAM_INVALID, f"{pre}command must be 'load', 'dump', or 'delete'", el,
                          self.aspan(el, "command"), c)
                continue
            if r["file"] is not None:
                for c2, f in r["file"]:
                    cc = conj([c, c2])
                    if cmd == "load" and UNRESOLVED not in f and not self.exists(f):
                        self.fact(FILE_NOT_FOUND, f"{pre}file does not exist [{f}]", el, self.aspan(el, "file"), cc)
                    elif cmd == "delete":
                        self.fact(PARAM_INVALID, f"{pre}'file' attribute is invalid with 'delete' command.", el,
                                  self.aspan(el, "file"), cc)
                    elif cmd == "load" and UNRESOLVED not in f:
                        text = self.read(f)
                        if text is not None and len(text) < 2_000_000:
                            self.rosparam_values(self.check_yaml(text, el, cc, has_param, f), r, sc, el, cc,
                                                 node_ns)
            elif cmd == "load":
                self.rosparam_values(self.check_yaml(x.text, el, c, has_param, None), r, sc, el, c, node_ns)

    def rosparam_values(self, data, r, sc: Scope, el: Element, c: Formula, node_ns):
        """Record the params a loaded <rosparam> sets (dicts flattened, as roslaunch)."""
        if data is None:
            return
        ns_c = r["ns"] or [(c, "")]
        par_c = r["param"] or [(c, "")]
        bases = []
        if node_ns is not None:
            for sc_c, child in node_ns[0]:
                for nc, nn in node_ns[1]:
                    bases.append((conj([sc_c, nc]), ns_join(child.ns, nn) + "/"))
        else:
            bases.append((TRUE, sc.ns))
        for bc, base in bases:
            for c1, nsv in ns_c:
                for c2, pv in par_c:
                    cond = conj([c, bc, c1, c2])
                    if cond == FALSE:
                        continue
                    param = ns_join(nsv or "", pv or "")
                    full = ns_join(base, param) if param else base
                    self._flatten(full, data, el, cond, 0)

    def _flatten(self, key: str, value, el: Element, cond: Formula, depth: int):
        if len(self.params) > 100_000 or depth > 50:
            return
        if isinstance(value, dict):
            for k, v in value.items():
                self._flatten(ns_join(key, str(k)), v, el, cond, depth + 1)
        else:
            self.params.append(ParamFact(shown(key.rstrip("/") or "/"), shown(str(value)), el, cond))

    def check_yaml(self, text: str, el: Element, c: Formula, has_param: bool, file: Optional[str]):
        pre = "error loading <rosparam> tag: "
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as e:
            msg = f"file {file} contains invalid YAML" if file else f"Error within YAML block: {str(e)[:200]}"
            if "$(" in text:
                return None  # may be fine once substituted (subst_value)
            self.fact(PARAM_INVALID, pre + msg, el, el.tag_span, c)
            return None
        except Exception:
            return None
        if data is None:
            data = {}
        if not has_param and not isinstance(data, dict):
            self.fact(PARAM_INVALID, f"{pre}'param' attribute must be set for non-dictionary values", el,
                      el.tag_span, c)
            return None
        return data

    # ---------------------------------------------------------------- <remap>, <env>, <machine>

    def remap_tag(self, x: XElement, el: Element, sc: Scope, cond: Formula, target: Scope):
        pre = "Invalid <remap> tag: "
        if "from" not in x.attrs or "to" not in x.attrs:
            self.fact(REMAP_INVALID, f"{pre}<remap> tag is missing required from/to attributes", el, el.tag_span, cond)
            return
        fr = self.resolve(x, el, "from", sc, cond) or []
        to = self.resolve(x, el, "to", sc, cond) or []
        for c1, f in fr:
            for c2, t in to:
                c = conj([c1, c2])
                if c == FALSE:
                    continue
                f2, t2 = canonicalize(f), canonicalize(t)
                if not f2 or not t2:
                    self.fact(REMAP_INVALID, f"{pre}remap from/to attributes cannot be empty", el, el.tag_span, c)
                    continue
                if not is_legal_name(f2):
                    self.fact(REMAP_INVALID, f"{pre}remap from [{f2}] is not a valid ROS name", el,
                              self.aspan(el, "from"), c)
                    continue
                if not is_legal_name(t2):
                    self.fact(REMAP_INVALID, f"{pre}remap to [{t2}] is not a valid ROS name", el,
                              self.aspan(el, "to"), c)
                    continue
                nc = neg(c)
                target.remaps = [(a, b, conj([rc, nc]) if a == f2 else rc) for a, b, rc in target.remaps]
                target.remaps = [r for r in target.remaps if r[2] != FALSE]
                target.remaps.append((f2, t2, c))

    def env_tag(self, x: XElement, el: Element, sc: Scope, cond: Formula, wrap: str = ""):
        if "name" not in x.attrs or "value" not in x.attrs:
            self.fact(ENV_INVALID, f"{wrap}<env> tag is missing required name/value attributes", el, el.tag_span, cond)
            return
        names = self.resolve(x, el, "name", sc, cond) or []
        self.resolve(x, el, "value", sc, cond)
        self.fact(ENV_INVALID, f"{wrap}Invalid <env> tag: 'name' attribute must be non-empty", el,
                  self.aspan(el, "name"), when(names, lambda v: not v))

    def machine_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        for k in ("ros-root", "ros-package-path", "ros-ip", "ros-hostname"):
            cs = self.resolve(x, el, k, sc, cond)
            if cs:
                self.fact(MACHINE_INVALID, "<machine>: ros-* attributes are not supported since ROS Fuerte. Please "
                          "use env-loader instead.", el, x.attrs[k].name_span, when(cs, bool))
        for k in ("name", "address"):
            if k not in x.attrs:
                self.fact(MISSING_ATTRIBUTE, f"<machine> tag is missing required attribute: '{k}'", el,
                          el.tag_span, cond)
                return
        r = {k: self.resolve(x, el, k, sc, cond) for k in
             ("name", "address", "env-loader", "ssh-port", "user", "password", "default", "timeout")}
        if r["ssh-port"]:
            for c, v in r["ssh-port"]:
                try:
                    int(v or "22")
                except ValueError:
                    self.fact(MACHINE_INVALID, f"invalid literal for int() with base 10: '{v}'", el,
                              self.aspan(el, "ssh-port"), c)
        if r["default"]:
            for c, v in r["default"]:
                if (v or "false").lower() not in ("true", "false", "never"):
                    self.fact(MACHINE_INVALID, f"Invalid value for 'attribute': {(v or 'false').lower()}", el,
                              self.aspan(el, "default"), c)
        for cx in x.children:
            if cx.tag == "env":
                self.fact(MACHINE_INVALID, "<machine>: <env> tag is not supported since ROS Fuerte. Please use "
                          "env-loader instead.", el, cx.span, cond)
                break
        if r["timeout"] is not None:
            for c, v in r["timeout"]:
                if v == "":
                    self.fact(MACHINE_INVALID, "'timeout' cannot be empty", el, self.aspan(el, "timeout"), c)
                elif not _is_float(v):
                    self.fact(MACHINE_INVALID, f"'timeout' be a number: [{v}]", el, self.aspan(el, "timeout"), c)
                elif float(v) <= 0:
                    self.fact(MACHINE_INVALID, f"'timeout' be a positive number: [{float(v)}]", el,
                              self.aspan(el, "timeout"), c)

    # ---------------------------------------------------------------- <include>

    def include_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula, emap):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        if "file" not in x.attrs:
            self.fact(MISSING_ATTRIBUTE, "<include> tag is missing required attribute: 'file'", el, el.tag_span, cond)
            return
        files = self.resolve(x, el, "file", sc, cond) or []
        pa = self.resolve(x, el, "pass_all_args", sc, cond)
        pass_cases = [(cond, False)]
        if pa is not None:
            pass_cases = []
            for c, v in pa:
                if v and _attr_bool(v) is None:
                    self.fact(INVALID_VALUE, f"invalid bool value for pass_all_args: {v}", el,
                              self.aspan(el, "pass_all_args"), c)
                    continue
                if v == "":
                    self.fact(INVALID_VALUE, "bool value for pass_all_args must be non-empty", el,
                              self.aspan(el, "pass_all_args"), c)
                    continue
                pass_cases.append((c, _attr_bool(v) is True))
        for fc, fname in files:
            for pc, pass_all in pass_cases:
                c0 = conj([fc, pc])
                if c0 == FALSE:
                    continue
                for c, child in self.ns_clear_params(x, el, sc, c0, "include", include_file=fname):
                    self.include_one(x, el, sc, child, c, fname, pass_all, emap)

    def include_one(self, x: XElement, el: Element, sc: Scope, child: Scope, c: Formula, fname: str,
                    pass_all: bool, emap):
        if pass_all:
            for name, vals in sc.args.items():
                child.include_names[name] = disj([child.include_names.get(name, FALSE),
                                                  conj([c, disj(vc for vc, _ in vals)])])
                child.include_args[name] = merge(list(child.include_args.get(name, [])) +
                                                 [(conj([vc, c]), v) for vc, v in vals])
            child.pass_all = True
        # <arg>/<env> children evaluated in the parent
        child.filename = sc.filename
        child.lookup_names = sc.arg_names
        for cx in x.children:
            cel = emap[id(cx)]
            t = cx.tag.lower()
            if t == "arg":
                self.arg_tag(cx, cel, child, c)
            elif t == "env":
                c2 = self.ifunless(cx, cel, child, c)
                if c2 != FALSE:
                    cel.condition = disj([cel.condition, c2])
                    self.env_tag(cx, cel, child, c2)
        child.filename = fname
        child.lookup_names = None
        # process_include_args
        inc_args = child.include_args or {}
        for name, d in (child.include_names or {}).items():
            have = disj(vc for vc, _ in inc_args.get(name, []))
            self.fact(INCLUDE_ARG_NO_VALUE, f"include args must have declared values ('{name}' has none)", el,
                      el.tag_span, conj([c, d, neg(have)]))
        passed = {n: disj(vc for vc, _ in vs) for n, vs in inc_args.items()}
        child.args = {n: list(vs) for n, vs in inc_args.items()}
        child.arg_names = {}
        child.include_args = None
        child.include_names = None

        inc = IncludeFact(el, shown(fname), c, False, namespace=child.ns)
        self.includes.append(inc)
        if UNRESOLVED in fname:
            el.unresolved = True
            m = re.search(UNRESOLVED + "([^" + UNRESOLVED + "]*)" + UNRESOLVED, fname)
            inc.package = m.group(1) if m else None
            return
        path = os.path.abspath(fname)
        in_ws = any(path.startswith(p.rstrip("/") + "/") for p in self.packages.values())
        if not os.path.isabs(fname) and not self.concrete:
            el.unresolved = True  # relative to roslaunch's working directory: unknown
            return
        if path in self.stack:
            self.fact(INCLUDE_CYCLE, f"include cycle: {' -> '.join(os.path.basename(p) for p in self.stack)} -> "
                      f"{os.path.basename(path)} (roslaunch recurses until it crashes)", el,
                      self.aspan(el, "file"), c)
            return
        if len(self.stack) > MAX_INCLUDE_DEPTH:
            self.fact(INCLUDE_TOO_DEEP, f"includes are nested more than {MAX_INCLUDE_DEPTH} deep; not followed",
                      el, self.aspan(el, "file"), c, severity=W)
            el.unresolved = True
            return
        u = self.unit(path)
        if u is None:
            if in_ws or self.concrete:
                self.fact(INCLUDE_NOT_FOUND, f"Invalid roslaunch XML syntax: [Errno 2] No such file or directory: "
                          f"'{shown(fname)}'", el, self.aspan(el, "file"), c)
            else:
                el.unresolved = True
            return
        if u.launch is None or u.error:
            self.fact(INCLUDE_INVALID, f"while processing {fname}: {u.error}", el, self.aspan(el, "file"), c,
                      related=[(path, d.span, d.message) for d in u.doc.diagnostics[:3]])
            return
        inc.followed = True
        el.resolved_file = path
        iemap: dict[int, Element] = {}
        root = self.make_elements(u.doc.root, path, el, el.include_depth + 1, iemap)
        root.parent = el
        lel = iemap[id(u.launch)]
        lel.condition = disj([lel.condition, c])
        self.launch_tag(u.launch, lel, child)
        child.pass_all = pass_all
        self.stack.append(path)
        nfacts = len(self.facts)
        before = len(self.includes)
        try:
            self.recurse(u.launch.children, child, c, iemap)
        finally:
            self.stack.pop()
        inc.children = self.includes[before:]
        del self.includes[before:]
        for f in self.facts[nfacts:]:
            if f.code in (UNDEFINED_ARG, UNSET_ARG) and f.path == path and "requires the" in f.message:
                f.message = f.message.replace(f"[{path}] requires", f"included file [{fname}] requires")
        if not pass_all:
            for name, pc in passed.items():
                self.fact(UNUSED_INCLUDE_ARG, f"unused args [{name}] for include of [{fname}]", el,
                          self.arg_child_span(x, el, emap, name), conj([pc, neg(child.arg_names.get(name, FALSE))]))

    def arg_child_span(self, x: XElement, el: Element, emap, name: str) -> Span:
        for cx in x.children:
            if cx.tag == "arg" and cx.attrs.get("name") and cx.attrs["name"].value == name:
                return cx.attrs["name"].value_span
        return el.tag_span or el.span


def _convert_error(value: str, ptype: str) -> Optional[str]:
    if "$(" in value or UNRESOLVED in value:
        return None
    if ptype == "auto" or ptype in ("str", "string"):
        return None
    try:
        if ptype == "int":
            int(value)
        elif ptype == "double":
            float(value)
        elif ptype in ("bool", "boolean"):
            if value.lower().strip() not in ("true", "1", "false", "0"):
                return f"{value.lower().strip()} is not a '{ptype}' type"
        elif ptype == "yaml":
            try:
                yaml.safe_load(value)
            except yaml.YAMLError as e:
                return str(e)[:200]
        else:
            return f"Unknown type '{ptype}'"
    except ValueError as e:
        return str(e)
    return None


# ------------------------------------------------------------------ public API

def _top_args(doc_root: Optional[XElement]) -> list[XElement]:
    if doc_root is None or doc_root.tag != "launch":
        return []
    return [x for x in doc_root.children if x.tag == "arg"]


def _boolean_only_args(launch: XElement, names: set[str]) -> set[str]:
    """Top-level args never used as a string: every ``$(arg X)`` is a whole if/unless
    condition or inside an ``$(eval)`` (where 'true'/'false' become booleans)."""
    bad: set[str] = set()
    pat = re.compile(r"\$\(arg\s+([^\s)]+)\s*\)")
    stack = [(c, "launch") for c in launch.children]
    while stack:
        x, ptag = stack.pop()
        stack.extend((c, x.tag) for c in x.children)
        for k, a in x.attrs.items():
            if k in ("if", "unless", "required", "respawn", "clear_params", "pass_all_args", "subst_value") \
                    or S.is_eval(a.value):
                continue
            if x.tag == "arg" and ptag == "include" and k == "value" and pat.fullmatch(a.value.strip()):
                continue  # passed on whole to an include
            for m in pat.finditer(a.value):
                bad.add(m.group(1))
    return names - bad


def analyse_launch(text: str, path: str, workspace_root: Optional[str] = None, read_file=None, *,
                   features: Optional[Iterable[str]] = None, env: Optional[Mapping[str, str]] = None,
                   packages: Optional[dict[str, str]] = None) -> LaunchAnalysis:
    """Analyse a launch file for all assignments of its feature args at once.

    ``features``: the args to treat as free booleans (the paired model's features). If None,
    the top-level args without value/default whose every use is an if/unless condition.
    ``read_file(path) -> str | None`` supplies unsaved editor text for other files.
    """
    if workspace_root is None and packages is None and os.path.isabs(path):
        workspace_root = guess_workspace_root(path)
    w = Walker(concrete=False, workspace_root=workspace_root, read_file=read_file,
               env=os.environ if env is None else env, packages=packages)
    doc = parse_xml(text, path)
    launch = doc.root if doc is not None and doc.root is not None and doc.root.tag == "launch" else None
    feature_decls: list[ArgDecl] = []
    tops = _top_args(launch)
    plain = {x.attrs["name"].value for x in tops if "name" in x.attrs and "value" not in x.attrs
             and "default" not in x.attrs and "$" not in x.attrs["name"].value}
    if features is not None:
        free = [f for f in features]
    elif launch is not None:
        free = sorted(_boolean_only_args(launch, plain))
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
                          w.includes, w.params, root)


def _merge_facts(facts: list[ErrorFact]) -> list[ErrorFact]:
    """One fact per (code, place, message): conditions of the same error joined by 'or'."""
    out: dict[tuple, ErrorFact] = {}
    for f in facts:
        key = (f.code, f.path, f.span, f.message)
        g = out.get(key)
        if g is None:
            out[key] = ErrorFact(f.code, f.severity, f.message, f.path, f.span, f.condition, list(f.related))
        else:
            g.condition = disj([g.condition, f.condition])
            for r in f.related:
                if r not in g.related:
                    g.related.append(r)
    # drop facts that no assignment can trigger (checked by brute force when small)
    return [f for f in out.values() if len(variables(f.condition)) > 10 or _satisfiable(f.condition) is not None]


def _satisfiable(f: Formula, limit: int = 14) -> Optional[dict[str, bool]]:
    """A satisfying assignment (brute force over the formula's variables), or None."""
    if f == FALSE:
        return None
    vs = sorted(variables(f))
    if len(vs) > limit:
        return {}
    for bits in itertools.product((False, True), repeat=len(vs)):
        env = dict(zip(vs, bits))
        if evaluate(f, env):
            return env
    return None


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
        packages = {}
        # like rospack: ROS_PACKAGE_PATH entries, the workspace first
        for d in reversed([x for x in env.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if x]):
            packages.update(find_packages(d))
        packages.update(find_packages(workspace_root))
    w = Walker(concrete=True, workspace_root=workspace_root, read_file=read_file, env=env, packages=packages)
    if text is None:
        text = w.read(path)
        if text is None:
            return LoadResult([], {}, [], [], f"[Errno 2] No such file or directory: '{path}'", "file-not-found")
    root_args = {k: [(TRUE, v)] for k, v in args.items()}
    w.run_root(path, text, root_args)
    error = None
    code = None
    for d in w.diagnostics:
        if d.severity == E:
            error, code = d.message, d.code
            break
    warnings = [d.message for d in w.diagnostics if d.severity != E]
    if error is None:
        for f in w.facts:
            if f.condition == TRUE and f.severity == E:
                error, code = f.message, f.code
                break
        warnings += [f.message for f in w.facts if f.condition == TRUE and f.severity != E]
    nodes = [dict(name=n.name, pkg=n.pkg, type=n.type, namespace=n.namespace, args=n.args,
                  remaps=[list(r) for r in n.remaps], file=n.path, line=n.element.span.start.line + 1)
             for n in w.nodes if n.condition == TRUE and not n.is_test]
    params: dict[str, str] = {}
    for p in w.params:
        if p.condition == TRUE:
            params[p.name] = p.value

    def inc_tree(incs: list[IncludeFact]) -> list[dict]:
        return [dict(file=i.file, followed=i.followed, namespace=i.namespace, package=i.package,
                     includes=inc_tree(i.children)) for i in incs if i.condition == TRUE]

    remaps = []
    for n in nodes:
        for f_, t_ in n["remaps"]:
            remaps.append(dict(node=n["name"], **{"from": f_, "to": t_}))
    return LoadResult(nodes, params, remaps, inc_tree(w.includes), error, code, warnings)
