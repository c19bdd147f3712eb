"""Evaluating substitutions symbolically: each ``$(...)`` of ros2/launch and launch_ros, as cases."""

from __future__ import annotations

import itertools
import os
import re
import shutil
from typing import Optional

from ...base.formula import FALSE, TRUE, Formula, conj, disj, neg
from ...base.text import Span
from ..model import Element
from . import actions as A
from . import pyexpr
from . import subst as S
from .values import (E, W, CONDITION_NOT_ANALYSABLE, Cases, ENV_NOT_SET, EVAL_ERROR, MAX_CASES, OPAQUE, PACKAGE_NOT_FOUND,
                     SUBST_FAILED, Scope, UNDEFINED_ARG, UNRESOLVED, equals, merge, opaque, present, shown, typed_bool)


# substitutions another front end adds (the Python one: PathJoinSubstitution, ...): name ->
# fn(walker, sub, value, scope, condition, element) -> cases
EXTRA: dict = {}


class SubstEval:
    """The substitution part of the walker (mixed into :class:`~.walker.Walker`)."""

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
        ext = EXTRA.get(name)
        if ext is not None:
            return ext(self, sub, v, sc, c, el)
        span = self.span_of(v, sub, el)
        args = sub.args
        path = el.path

        def arg(i: int, g: Formula = c) -> Cases:
            return self.ev_parts(args[i], v, sc, g, el)

        def fail(msg: str, g: Formula, code: str = SUBST_FAILED, friendly: Optional[str] = None,
                 kind: str = "SubstitutionFailure", severity=E):
            self.fact(code, friendly or msg, path, span, g, severity, launch=(kind, msg))

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
                if self.lenient and n not in self.declared_names.get(path, ()):
                    # the file never declares it: it may well expect it from a file that includes it
                    fail(f"launch configuration '{n}' does not exist", missing, UNDEFINED_ARG,
                         f"$(var {n}): {os.path.basename(path)} does not declare '{n}' (ros2 launch: launch "
                         f"configuration '{n}' does not exist), unless a file that includes it sets it", severity=W)
                    # and when one does, its value is unknown here: analyse on (no cascade of errors)
                    out.append((missing, OPAQUE))
                    continue
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
                    py = path.endswith(".py")  # (a Python launch file's PythonExpression, in its own terms)
                    if m and py:
                        hint = (f" (PythonExpression is Python: the value {m.group(1)} of a LaunchConfiguration is a "
                                "name there; compare strings, e.g. PythonExpression([\"'\", LaunchConfiguration('x'), "
                                "\"' == 'true'\"]))")
                    elif m:
                        hint = (f" ($(eval) is Python: the value {m.group(1)} of a $(var) is a name there; compare "
                                f"strings, e.g. '\"$(var x)\" == \"true\"')")
                    what = f"PythonExpression('{text}')" if py else f"$(eval '{text}')"
                    self.fact(EVAL_ERROR, f"{what} fails: {ex.kind}: {ex.message}{hint}", path, span, ce,
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
        if re.fullmatch(r"[a-zA-Z0-9][a-zA-Z0-9_-]+", pkg, re.ASCII) is None:
            # ament_index_python's get_package_prefix (REP 127 names) refuses the name before
            # it looks for the package, installed or not
            msg = f"'{pkg}' is not a valid package name"
            self.fact(PACKAGE_NOT_FOUND, f"{msg}: ament_index accepts letters, digits, '_' and '-', at least "
                      "two characters, not starting with '_' or '-'", path, span, c, launch=("ValueError", msg))
            return None
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
