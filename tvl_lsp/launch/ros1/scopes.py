"""Scopes and substitution: roslaunch's ``LoaderContext`` with guarded values (:class:`Scope`),
the resolution of ``$(...)`` substitution args into guarded cases, if/unless conditions, and
the ``<arg>`` tag that fills scopes."""

from __future__ import annotations

import itertools
import os
from typing import Optional

from ...base.formula import FALSE, TRUE, Formula, conj, disj, neg, unknown, variables
from ...base.text import Span
from . import subst as S
from ..model import Element
from ..xml import XAttr, XElement, value_span
from .rules import (_satisfiable, ARG_ALREADY_SET, ARG_VALUE_AND_DEFAULT, CONDITION_NOT_ANALYSABLE, Cases,
                    DUPLICATE_ARG, ENV_NOT_SET, EVAL_ERROR, IF_AND_UNLESS, INVALID_CONDITION, MAX_CASES,
                    MISSING_ATTRIBUTE, PACKAGE_AMBIGUOUS, PACKAGE_NOT_FOUND, POISON, SUBST_ARITY, SUBST_SYNTAX, SUBST_UNKNOWN,
                    UNDEFINED_ARG, UNRESOLVED, UNSET_ARG, W, _bool_val, cmdline_settable, make_global_ns, merge,
                    ns_join, opaque)


class Scope:
    """roslaunch's LoaderContext, with guarded values."""

    __slots__ = ("ns", "filename", "arg_names", "args", "include_args", "include_names", "pass_all",
                 "params", "remaps", "env", "anon", "passed", "lookup_names", "params_link", "cmdline")

    def __init__(self, ns: str, filename: str):
        self.ns = make_global_ns(ns or "/") if ns != "~" else "~"
        self.filename = filename
        self.arg_names: dict[str, Formula] = {}
        self.args: dict[str, Cases] = {}
        self.include_args: Optional[dict[str, Cases]] = None
        self.include_names: Optional[dict[str, Formula]] = None
        self.pass_all = False
        self.params: list = []
        # (from, to, condition, the <remap> element), in roslaunch's order
        self.remaps: list[tuple[str, str, Formula, object]] = []
        self.env: list = []
        self.anon: dict[str, str] = {}
        self.passed: dict[str, Formula] = {}
        self.lookup_names: Optional[dict[str, Formula]] = None  # declared names for $(arg) lookups
        # roslaunch's context.params is shared with a child context when it is not empty (its
        # LoaderContext does ``params or []``): (the parent's list, when it was not empty, the
        # parent's own link) -- a ~param added here is added there too under that condition
        self.params_link: Optional[tuple] = None
        # when the command line's args reach this scope's arg values (the root file, its groups,
        # includes with pass_all_args; never in the concrete loader, whose command line is known)
        self.cmdline: Formula = TRUE

    def child(self, ns: Optional[str], share_args: bool = False) -> "Scope":
        """roslaunch's ``LoaderContext.child``.  ``share_args``: the child only reads args (a
        ``<node>``'s scope: no ``<arg>`` may appear in it), so the dicts are shared, not
        copied -- a copy per node would make a file with many nodes and args quadratic."""
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
        if share_args:
            c.arg_names = self.arg_names
            c.args = self.args
        else:
            c.arg_names = dict(self.arg_names)
            c.args = {k: list(v) for k, v in self.args.items()}
        c.include_args = self.include_args
        c.include_names = None
        c.pass_all = False
        c.params = list(self.params)
        c.params_link = (self.params, disj(e[2] for e in self.params), self.params_link) if self.params else None
        c.cmdline = self.cmdline
        c.remaps = list(self.remaps)
        c.env = list(self.env)
        c.anon = dict(self.anon)
        c.passed = {}
        c.lookup_names = None
        return c


def _close_name(name: str, declared) -> bool:
    """Whether an arg of ``declared`` looks like ``name`` mistyped (same letters in another case,
    or a close spelling)."""
    import difflib
    low = name.lower()
    return any(n != name and (n.lower() == low or difflib.SequenceMatcher(None, n, name).ratio() >= 0.8)
               for n in declared)


class ScopeRules:
    """Substitution args (``$(arg)``, ``$(find)``, ``$(eval)``, ...), if/unless and ``<arg>``
    (a mixin of :class:`~tvl_lsp.launch.ros1.loader.Walker`)."""

    # ---------------------------------------------------------------- substitution

    def resolve(self, x: XElement, el: Element, name: str, sc: Scope, guard: Formula,
                where: str = "", keep_poison: bool = False) -> Optional[Cases]:
        """Cases of attribute ``name`` (None if absent). Errors become facts; the cases
        cover ``guard`` minus the error cases."""
        a = x.attrs.get(name)
        if a is None:
            return None
        return self.resolve_text(a.value, a, el, sc, guard, where, keep_poison=keep_poison)

    def resolve_text(self, value: str, a: Optional[XAttr], el: Element, sc: Scope, guard: Formula,
                     where: str = "", spans=None, keep_poison: bool = False) -> Cases:
        """Cases of ``value`` with its substitution args resolved (roslaunch's resolve_args).
        ``spans(i, j)`` gives the source range of ``value[i:j]`` (default: inside attribute
        ``a``, or the element).  A case that reads an arg whose own value failed to evaluate
        (``POISON``: roslaunch stops at that arg, and that failure is reported where it
        happens) is an error case like any other and is left out, so that no check of the
        attribute reports a value roslaunch never computes (``keep_poison``: kept, for
        ``if``/``unless``, which take such a case as loaded)."""
        out = self._resolve_text(value, a, el, sc, guard, where, spans)
        if not keep_poison:
            out = [(c, v) for c, v in out if POISON not in v]
        if self.typing is not None and not self.flow:
            self.typing.sink(out)
        return out

    def _resolve_text(self, value: str, a: Optional[XAttr], el: Element, sc: Scope, guard: Formula,
                      where: str, spans) -> Cases:
        if guard == FALSE:
            return []
        if not value or "$" not in value:
            return [(guard, value)]
        idx = self.index[el.path]

        def sp(i: int, j: int) -> Span:
            if spans is not None:
                return spans(i, j)
            return value_span(a, idx, i, j) if a is not None else el.span

        whole = sp(0, len(value))
        if S.is_eval(value):
            if self.typing is not None:
                typed = self.typing.eval_uses(value, sc, guard)
                if typed is not None:
                    return typed
            return self.resolve_eval(value, a, el, sc, guard, whole, where)
        try:
            parts = S.collect(value)
        except S.SubstError as e:
            self.fact(SUBST_SYNTAX, str(e), el, whole, guard)
            return []
        cases: Cases = [(guard, value)]
        for inner, i, j in parts:  # in order, as roslaunch: the first failure stops it
            words = [w for w in inner.split(" ") if w]
            if not words or words[0] not in S.VALID:
                self.fact(SUBST_UNKNOWN, f"Unknown substitution command [{inner}]. Valid commands are "
                          f"{list(S.VALID)}", el, sp(i, j), disj(c for c, _ in cases))
                return []
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
                self.note_ambiguous(pkg, el, span)
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
            undeclared = conj([missing, neg(declared)])
            if undeclared != FALSE and self.cmdline_undeclared and cmdline_settable(name) and \
                    not _close_name(name, names):
                # roslaunch puts the whole command line into the root file's args, declared or not
                # (load_sysargs_into_context): `roslaunch f.launch bag:=x` loads $(arg bag) without
                # <arg name="bag"/> -- a warning where the command line reaches; a name close to a
                # declared one stays an error (a typo)
                self.fact(UNDEFINED_ARG, f"{base}: '{name}' is not declared in this scope; roslaunch takes it "
                          f"only from the command line ({name}:=...): declare it (<arg name=\"{name}\"/>)",
                          el, span, conj([undeclared, sc.cmdline]), severity=W)
                undeclared = conj([undeclared, neg(sc.cmdline)])
            self.fact(UNDEFINED_ARG, f"{base}: '{name}' is not declared in this scope", el, span, undeclared)
            # roslaunch fails either way; whether --check calls it an error depends on whether the
            # command line can give the value: it reaches the root file and, through
            # pass_all_args, the files it includes -- never an include without pass_all_args
            unset = conj([missing, declared])
            if unset != FALSE and not cmdline_settable(name):
                # roslaunch reads its command line as ROS remappings: it ignores '3d_sensor:=...'
                self.fact(UNSET_ARG, f"{base}: '{name}' is declared without value or default, and roslaunch's "
                          f"command line cannot give it one (it ignores '{name}:=...': an arg given there must "
                          "start with a letter, '_', '/' or '~' and hold only letters, digits, '_' and '/')",
                          el, span, unset)
            elif unset != FALSE and self.concrete and self.stack and os.path.abspath(sc.filename) == self.stack[0]:
                # tvl-lsp launch FILE name:=value ...: the root file's command line is known
                self.fact(UNSET_ARG, f"{base}: '{name}' is declared without value or default and the command "
                          f"line does not give it ({name}:=...)", el, span, unset)
            elif unset != FALSE:
                self.fact(UNSET_ARG, f"{base}: '{name}' is declared without value or default; give it on the "
                          f"command line ({name}:=...)", el, span, conj([unset, sc.cmdline]), severity=W)
                self.fact(UNSET_ARG, f"{base}: '{name}' is declared without value or default and nothing sets it "
                          "(the including file does not pass it, and the command line reaches an included file "
                          "only through pass_all_args)", el, span, conj([unset, neg(sc.cmdline)]))
        return out

    def resolve_eval(self, value: str, a, el: Element, sc: Scope, guard: Formula, span: Span,
                     where: str) -> Cases:
        expr = value[7:-1]
        try:
            tree = S.parse_eval(expr)
        except S.SubstError as e:
            self.fact(EVAL_ERROR, str(e), el, span, guard)
            return []
        except S.NotAnalysable:
            self.note(CONDITION_NOT_ANALYSABLE, f"'$(eval ...)' is too long or nested too deeply for tvl-lsp to "
                      "evaluate; it assumes the value may be anything", el, span)
            return [(guard, opaque(value))]
        names, ok = S.eval_names(tree)
        if not ok:
            self.note(CONDITION_NOT_ANALYSABLE, f"tvl-lsp cannot translate '$(eval {expr.strip()})' into a "
                      "formula over args; it assumes the value may be anything", el, span)
            return [(guard, opaque(value))]
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
            return [(guard, opaque(value))]
        out: Cases = []
        for combo in itertools.product(*per) if per else [()]:
            cond = conj([guard] + [vc for vc, _ in combo])
            if cond == FALSE:
                continue
            env_args = {n: v for n, (_, v) in zip(names_l, combo) if v is not None}
            if any(UNRESOLVED in v for v in env_args.values()):
                out.append((cond, opaque(value)))  # reads a value tvl-lsp does not know
                continue
            try:
                out.append((cond, S.run_eval(tree, env_args, self.env, lambda p: self.eval_find(p, el, span),
                                             dirname=lambda: os.path.abspath(os.path.dirname(sc.filename)),
                                             anon=lambda ident: self.eval_anon(sc, ident))))
            except S.EvalArgMissing as m:
                self.lookup_arg(m.name, el, sc, cond, span, where)
            except S.NotAnalysable:
                # unknown in this case only: what the other cases compute (or fail on) is certain
                self.note(CONDITION_NOT_ANALYSABLE, f"tvl-lsp cannot evaluate '$(eval {expr.strip()})'; it "
                          "assumes the value may be anything", el, span)
                out.append((cond, opaque(value)))
            except S.SubstError as e:
                self.fact(EVAL_ERROR, str(e), el, span, cond)
        return merge(out)

    def eval_anon(self, sc: Scope, ident: str) -> str:
        """``anon('id')`` inside ``$(eval)``: the name ``$(anon id)`` gives in this file."""
        if ident not in sc.anon:
            sc.anon[ident] = S.anon_name(ident, lambda: next(self.anon_counter))
        return sc.anon[ident]

    def eval_find(self, pkg: str, el: Optional[Element] = None, span: Optional[Span] = None):
        """``find('pkg')`` inside ``$(eval)``: the package's folder (roslaunch raises
        ResourceNotFound for a package it cannot find; outside the workspace, tvl-lsp cannot
        tell: an unknown value, the rest of the expression still evaluated)."""
        path = self.packages.get(pkg)
        if el is not None and span is not None:
            self.note_ambiguous(pkg, el, span)
        if path is None:
            if self.concrete:
                raise S.SubstError(f"ResourceNotFound: {pkg}")
            return S.UNKNOWN
        return path

    def note_ambiguous(self, pkg: str, el: Element, span: Span) -> None:
        """A note where ``$(find pkg)`` names a package several folders hold (the one roslaunch
        takes is what tvl-lsp takes, but an editor user may be looking at the other)."""
        folders = self.ambiguous.get(pkg)
        if not folders:
            return
        self.note(PACKAGE_AMBIGUOUS, f"$(find {pkg}) is {folders[0]}: {len(folders)} folders hold a package named "
                  f"'{pkg}' (also {', '.join(folders[1:3])}{' ...' if len(folders) > 3 else ''}); roslaunch takes "
                  "the first on ROS_PACKAGE_PATH (this workspace first when ROS_PACKAGE_PATH does not list it), "
                  "and of two in one folder the first it crawls", el, span)

    # ---------------------------------------------------------------- conditions

    def ifunless(self, x: XElement, el: Element, sc: Scope, guard: Formula, where: str = "") -> Formula:
        if guard == FALSE:
            return FALSE
        self.flow += 1  # an if/unless value is not a string use of the args it reads (arg typing)
        try:
            ifc = self.resolve(x, el, "if", sc, guard, where, keep_poison=True)
            unc = self.resolve(x, el, "unless", sc, guard, where, keep_poison=True)
        finally:
            self.flow -= 1
        if ifc is None and unc is None:
            return guard
        if self.typing is not None and (ifc is None or unc is None):
            return self.typing.condition(ifc if ifc is not None else unc, "if" if ifc is not None else "unless")
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
                # a value tvl-lsp cannot compute (or whose computation failed, reported there):
                # an unknown, the same for every if/unless of that value, so that if= and unless=
                # of it exclude each other; an error that depends on it is never reported
                u = self.unknown_condition(el, x.attrs[key].value, v)
                ok.append(conj([c, u if key == "if" else neg(u)]))
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

    def unknown_condition(self, el: Element, raw: str, value: str) -> Formula:
        """The unknown (:func:`~tvl_lsp.base.formula.unknown`) of an if/unless whose value
        tvl-lsp cannot compute: one per (file, value), named after the attribute's text."""
        k = (el.path, value)
        u = self.unknowns.get(k)
        if u is None:
            u = self.unknowns[k] = unknown(f"{len(self.unknowns) + 1}:{raw.strip()[:60]}")
        return u

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
        self.flow += 1  # an arg's value passes the args it reads on (arg typing follows it)
        try:
            value = self.resolve(x, el, "value", sc, cond, "arg")
            default = self.resolve(x, el, "default", sc, cond, "arg")
        finally:
            self.flow -= 1
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
