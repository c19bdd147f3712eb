"""Includes: ``<include>`` resolves its file, passes args (``pass_all_args``, ``<arg>``
children), checks what the included file declares, and walks it in a child scope; cycles and
depth are bounded."""

from __future__ import annotations

import os
import re

from ...base.formula import FALSE, TRUE, Formula, conj, disj, neg
from ...base.text import Span
from ..model import Element, IncludeFact
from ..xml import XElement
from ..model import outside_message, outside_reach
from .rules import INCLUDE_OUTSIDE
from .rules import (INCLUDE_ARG_NO_VALUE, INCLUDE_CYCLE, INCLUDE_INVALID, INCLUDE_NOT_FOUND, INCLUDE_TOO_DEEP,
                    INVALID_VALUE, MAX_INCLUDE_DEPTH, MISSING_ATTRIBUTE, UNDEFINED_ARG, UNRESOLVED, UNSET_ARG,
                    UNUSED_INCLUDE_ARG, W, OPAQUE, _attr_bool, merge, shown)
from .scopes import Scope


class IncludeRules:
    """``<include>`` (a mixin of :class:`~tvl_lsp.launch.ros1.loader.Walker`)."""

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
        if self.typing is not None:  # arg typing: follow the file the args' defaults name
            files = [(c, self.typing.concrete(f)) for c, f in files]
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
        # the command line's values reach the included file only through pass_all_args
        child.cmdline = sc.cmdline if pass_all else FALSE
        child.arg_names = {}
        child.include_args = None
        child.include_names = None

        inc = IncludeFact(el, shown(fname), c, False, namespace=child.ns)
        self.includes.append(inc)
        if self.typing is not None and not self._followable(fname):
            # arg typing: how a file that is not followed uses the args it gets is unknown --
            # so they are not booleans (true/false could be meaningless there)
            self.typing.sink([cv for vals in child.args.values() for cv in vals])
        if UNRESOLVED in fname:
            el.unresolved = True
            m = re.search(UNRESOLVED + "([^" + UNRESOLVED + "]*)" + UNRESOLVED, fname)
            inc.package = m.group(1) if m and not m.group(1).startswith(OPAQUE) else None
            return
        path = os.path.abspath(fname)
        in_ws = any(path.startswith(p.rstrip("/") + "/") for p in self.packages.values())
        if not os.path.isabs(fname) and not self.concrete:
            el.unresolved = True  # relative to roslaunch's working directory: unknown
            self.fact(INCLUDE_NOT_FOUND, f"'{shown(fname)}' is a relative path: roslaunch opens it relative to the "
                      "folder it is started in, not to this file, so it loads only when started from the right "
                      "place (name it from its package, $(find pkg)/..., or from this file, $(dirname)/...)",
                      el, self.aspan(el, "file"), c, severity=W)
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
        if outside_reach(path, self.reach):  # one rule in every command (docs/architecture.md)
            inc.outside = True
            el.unresolved = True
            self.fact(INCLUDE_OUTSIDE, outside_message(shown(fname), path), el, self.aspan(el, "file"), c,
                      severity=W)
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
            unused = [(name, conj([pc, neg(child.arg_names.get(name, FALSE))])) for name, pc in passed.items()]
            if self.concrete:
                # one assignment: roslaunch names every unused arg in one error, in the include's order
                bad = [name for name, c in unused if c == TRUE]
                if bad:
                    self.fact(UNUSED_INCLUDE_ARG, f"unused args [{', '.join(bad)}] for include of [{fname}]", el,
                              self.arg_child_span(x, el, emap, bad[0]), TRUE)
                unused = [(name, c) for name, c in unused if c != TRUE]
            for name, c in unused:  # each at its own <arg> (an editor shows each where it is)
                self.fact(UNUSED_INCLUDE_ARG, f"unused args [{name}] for include of [{fname}]", el,
                          self.arg_child_span(x, el, emap, name), c)

    def _followable(self, fname: str) -> bool:
        """Whether include_one follows ``fname`` (a valid launch file in reach)."""
        if UNRESOLVED in fname or not os.path.isabs(fname):
            return False
        path = os.path.abspath(fname)
        if path in self.stack or len(self.stack) > MAX_INCLUDE_DEPTH:
            return False
        u = self.unit(path)
        return u is not None and u.launch is not None and not u.error

    def arg_child_span(self, x: XElement, el: Element, emap, name: str) -> Span:
        for cx in x.children:
            if cx.tag == "arg" and cx.attrs.get("name") and cx.attrs["name"].value == name:
                return cx.attrs["name"].value_span
        return el.tag_span or el.span
