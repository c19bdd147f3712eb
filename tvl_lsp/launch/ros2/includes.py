"""Includes: loading the file, launch's look-ahead check of required args, the leak of args."""

from __future__ import annotations

import os
import re
from typing import Optional

from ...base.formula import Formula, conj, disj, neg
from ...base.text import Span
from ..model import Element, IncludeFact, outside_message, outside_reach
from .values import INCLUDE_OUTSIDE
from . import actions as A
from . import subst as S
from .values import (E, I, W, INCLUDE_CYCLE, INCLUDE_INVALID, INCLUDE_NOT_FOUND, INCLUDE_TOO_DEEP, Leak, MAX_INCLUDE_DEPTH,
                     OPAQUE, PYTHON_INCLUDE, Scope, UNRESOLVED, UNSET_ARG, Unit, _extension, merge, shown)

from dataclasses import dataclass
from .frontend import make_elements


class IncludeRules:
    """The include part of the walker (mixed into :class:`~.walker.Walker`)."""

    # -- <include>
    def include(self, a: A.IncludeA, el: Element, sc: Scope, cond: Formula, emap: dict) -> None:
        files = self.ev(a.file, sc, cond, el)
        span = a.file.span() or el.tag_span
        for c, f in files:
            inc = IncludeFact(el, shown(f), c, False)
            self.includes.append(inc)
            if UNRESOLVED in f or OPAQUE in f:
                if self.concrete:
                    self.decline(el.path, span, "tvl-lsp cannot know which file this include loads", c)
                el.unresolved = True
                m = re.search(UNRESOLVED + "([^" + UNRESOLVED + "]*)" + UNRESOLVED, f)
                inc.package = m.group(1) if m else None
                self.not_followed(a, el, sc, c, emap)
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
            if outside_reach(path, self.reach):  # one rule in every command (docs/architecture.md)
                inc.outside = True
                el.unresolved = True
                self.fact(INCLUDE_OUTSIDE, outside_message(shown(f), path), el.path, span, c, W)
                if not self.concrete:
                    self.not_followed(a, el, sc, c, emap)   # what it sets is unknown, not missing
                continue
            u = self.unit(path)
            if u is None and not self.concrete:
                src = self.installed_from(path)
                if src is not None:
                    path = inc.file = src
                    u = self.unit(path)
            if u is None and not self.concrete and not self.in_workspace(path):
                el.unresolved = True   # e.g. an installed package's file: not on this machine
                self.not_followed(a, el, sc, c, emap)
                continue
            if u is None and not self.concrete and self.exists(path + ".in"):
                # made by the build from a template (CMake's configure_file): not in the sources (the
                # concrete load, which runs on the sources as the oracle does, fails on it)
                self.decline(el.path, span, f"{os.path.basename(path)} is made by the build from "
                             f"{os.path.basename(path)}.in: tvl-lsp does not know what it will contain", c)
                el.unresolved = True
                self.not_followed(a, el, sc, c, emap)
                continue
            if u is None:
                ext = _extension(path)
                err = f"[Errno 2] No such file or directory: '{path}'"
                if getattr(a, "source_kind", "any") != "any":   # Python's XML/Python...Source: one loader
                    launch = ("FileNotFoundError", err)
                else:
                    launch = ("InvalidLaunchFileError", f"Caught multiple exceptions when trying to load file of "
                              f"format [{ext}]:\n - FileNotFoundError: {err}\n - FileNotFoundError: {err}")
                self.fact(INCLUDE_NOT_FOUND, f"the included file {path} does not exist", el.path, span, c,
                          launch=launch)
                continue
            kind = getattr(a, "source_kind", "any")   # Python's XMLLaunchDescriptionSource(...) ...
            if (kind == "py") != path.endswith(".py") and kind != "any":
                self.decline(el.path, span, f"a {kind.upper()} launch description source of the file "
                             f"{os.path.basename(path)}: tvl-lsp does not model how launch fails on it", c)
                if not self.concrete:
                    sc.opaque = disj([sc.opaque, c])
                el.unresolved = True
                self.not_followed(a, el, sc, c, emap)
                continue
            if u.python:
                # a Python launch file whose launch description tvl-lsp cannot know
                if path not in self.python_includes:
                    self.python_includes.append(path)
                reason, dpath, dspan = getattr(u, "decline", None) or ("tvl-lsp does not execute it", path, None)
                where = f" (line {dspan.start.line + 1})" if dspan is not None else ""
                msg = (f"tvl-lsp cannot analyse the Python launch file {os.path.basename(path)}{where}: {reason}; "
                       "the nodes it starts and the args it sets are not known")
                if self.concrete:
                    self.fact(PYTHON_INCLUDE, msg, el.path, span, c, E, launch=("NotAnalysed", msg))
                self.fact(PYTHON_INCLUDE, msg, el.path, span, c, I)
                self.not_followed(a, el, sc, c, emap)
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

    def not_followed(self, a: A.IncludeA, el: Element, sc: Scope, c: Formula, emap: dict) -> None:
        """An include whose file is not analysed (outside the workspace, a file name tvl-lsp cannot
        know ...): launch still sets its args first, and the file may set anything (includes do
        not scope): after it, a configuration nobody here sets is unknown, not missing."""
        for ia in a.args:
            iel = emap.get(id(ia.entity), el)
            iel.condition = disj([iel.condition, c])
            self.set_config(sc, self.ev(ia.name, sc, c, iel), self.sure(self.ev(ia.value, sc, c, iel), c), c)
        sc.opaque = disj([sc.opaque, c])

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
            vcases = self.sure(self.ev(ia.value, sc, c, iel), c)
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
                if len(after) == len(old) and set(after) == set(old):
                    continue  # (formulas compare by hash: their repr is exponential in their sharing)
                span = self.leak_span(a, emap, el, n)
                sc.leaks[n] = Leak(n, el, span[1], span[0], old, after)

    def leak_span(self, a: A.IncludeA, emap: dict, el: Element, name: str) -> tuple[str, Span]:
        for ia in a.args:
            if S.plain(ia.name.parts) == name:
                iel = emap.get(id(ia.entity), el)
                return iel.path, (ia.name.span() or iel.tag_span)
        return el.path, el.tag_span or el.span

    def installed_from(self, path: str) -> Optional[str]:
        """``$(find-pkg-share pkg)/launch/x.launch.xml`` is the source folder's file of that path;
        when the package's build installs it elsewhere (e.g. from ``launch/robots/``), the one
        file of the package with that name."""
        p = os.path.realpath(path)
        for folder in self.packages.values():
            root = os.path.realpath(folder).rstrip("/") + "/"
            if not p.startswith(root):
                continue
            name = os.path.basename(p)
            found = []
            for d, dn, fn in os.walk(root):
                dn[:] = [x for x in dn if not x.startswith(".") and x not in ("build", "install", "log", "test")]
                if name in fn:
                    found.append(os.path.join(d, name))
                if len(found) > 1:
                    return None
            return found[0] if found else None
        return None

    def in_workspace(self, path: str) -> bool:
        """Is ``path`` inside a package of the workspace (where a missing file is a mistake, not
        just a file of another machine)?"""
        p = os.path.realpath(path)
        homes = list(self.packages.values()) + ([self.root] if self.root else []) + \
            ([os.path.dirname(self.root_path)] if self.root_path else [])
        return any(p.startswith(os.path.realpath(f).rstrip("/") + "/") for f in homes)

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
                # reported in the included file, at the declaration (the cross-check shows it on
                # the <include> of the analysed file, as an error: no command line reaches it)
                where = "" if not chain else f", which {os.path.basename(u.path)} includes,"
                aspan = a.entity.attrs["name"].value_span if "name" in a.entity.attrs else a.entity.tag_span
                self.fact(UNSET_ARG, f"arg '{a.name}' of {os.path.basename(a.entity.path)}{where} has no default "
                          f"and the <include> of {os.path.basename(u.path)} on line {el.span.start.line + 1} of "
                          f"{os.path.basename(el.path)} does not pass it (an arg without default must be passed "
                          "by the include itself, even if it is set where the include is)", a.entity.path, aspan, c,
                          related=[(el.path, span, "the <include>")], launch=("RuntimeError", msg))
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
