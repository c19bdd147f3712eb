"""Nodes, composable nodes, executables and their parameters (launch_ros' Node.execute)."""

from __future__ import annotations

import functools
import os
from typing import Optional

import yaml
from ...base import yamlsafe

from ...base.formula import FALSE, TRUE, Formula, conj, disj, neg
from ..model import Element
from . import actions as A
from . import subst as S
from . import coerce as C
from .values import (W, PARAM_INVALID, DUPLICATE_NODE, FILE_NOT_FOUND, INVALID_NAMESPACE, INVALID_NODE_NAME, INVALID_VALUE, MAX_CASES,
                     Node2Fact, PARAM_FILE_NOT_FOUND, SUBST_SYNTAX, SUBST_UNKNOWN, Scope, _yaml_value, make_absolute,
                     opaque, prefix_namespace, present, shown, typed_bool, validate_namespace, validate_node_name)

from ..model import RemapCase

PAIRWISE_DUPLICATES = 8  # up to this many earlier nodes of a name: one duplicate-node fact per pair
MAX_RELATED = 64  # related locations listed for a duplicate node


@functools.lru_cache(maxsize=64)
def _valid_yaml(text: str) -> bool:
    """A substituted parameter file parses as YAML (remembered: the symbolic walk checks the
    same text once per case and per node)."""
    try:
        yamlsafe.safe_load(text)
        return True
    except Exception:
        return False


_FAILED = object()  # a parameter value launch fails to type


class NodeRules:
    """The node part of the walker (mixed into :class:`~.walker.Walker`)."""

    # -- <executable>
    def executable(self, a: A.ExecA, el: Element, sc: Scope, cond: Formula) -> None:
        names = self.ev(a.name, sc, cond, el) if a.name is not None else [(cond, "")]
        cmd = self.cmd(a.cmd, a.cmd_value, sc, cond, el)
        if a.cwd is not None:
            self.ev(a.cwd, sc, cond, el)
        for kn, kv in a.env:
            self.ev(kn, sc, cond, el)
            self.ev(kv, sc, cond, el)
        self.typed_respawn(a, el, sc, cond)
        if self.concrete and cond == TRUE:
            n = names[0][1] if names else ""
            self.exec_counter = getattr(self, "exec_counter", 0) + 1
            base = n or (os.path.basename(cmd[0][1][0]) if cmd and cmd[0][1] else "")
            self.executables.append({"name": shown(base), "process_name": f"{shown(base)}-{self.exec_counter}",
                                     "cmd": [shown(x) for x in (cmd[0][1] if cmd else [])], "source": el.path})

    def typed_respawn(self, a, el: Element, sc: Scope, cond: Formula) -> None:
        """ExecuteLocal.prepare: ``respawn`` substituted and typed as a bool (launch fails on
        'abc' or '[' there)."""
        if a.respawn is None:
            return
        for c, v in self.ev(a.respawn, sc, cond, el):
            if opaque(v):
                continue
            try:
                C.perform_typed(v, bool)
            except ValueError as ex:
                self.fact(INVALID_VALUE, f"respawn is '{v}', which ros2 launch cannot read as a boolean: {ex}",
                          el.path, a.respawn.span() or el.tag_span, c, launch=("ValueError", str(ex)))
            except Exception:
                continue

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
        # <set_parameter> values come first on the command line (later ones overwrite them)
        glob = {}
        for c, item in self.list_items(sc, "gparams", g):
            if isinstance(item, tuple):
                glob[item[0]] = (c, item[1])
        params = {**glob, **params} if glob else params
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
        self.typed_respawn(a, el, sc, g)
        kind = getattr(a, "kind", None) or a.tag
        if self.concrete:
            self.decline_unknown(el, a, okp, ok_names, full_ns, remaps + own)
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
        names = self.ev(comp.name, sc, cond, el) if comp.name is not None else [(cond, None)]
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
                        full = (full_ns.rstrip("/") if full_ns else "") + "/" + n if n is not None else ""
                        if self.concrete and (opaque(p) or (n is not None and opaque(full))):
                            self.decline(el.path, el.tag_span or el.span, "tvl-lsp cannot know the package or "
                                         "name of this composable node", cc)
                        nf = self.make_node(full, p, "", full_ns, el, cc, remaps + own, "composable_node",
                                            {k: v for k, (c, v) in params.items() if conj([c, cc]) != FALSE}, [])
                        self.add_node(nf, comp.name if n is not None else None, el, full)

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

    def decline_unknown(self, el: Element, a, okp, names, nss, remaps) -> None:
        """The concrete load: a node whose package, executable, name, namespace or remaps tvl-lsp
        cannot know is not reported with a made-up value: the load declines there."""
        what = None
        if any(p is not None and opaque(p) for _, p, _ in okp):
            what = "package"
        elif any(opaque(x) for _, _, x in okp):
            what = "executable"
        elif any(p is not None and isinstance(x, str) and "/" in x for _, p, x in okp):
            # launch_ros' ExecutableInPackage: shutil.which() of a name with a '/' looks at that path
            # itself (not in the package): it runs only if that file is executable where it launches
            span = (a.executable.span() if a.executable is not None else None) or el.tag_span or el.span
            self.decline(el.path, span, "the executable of this node is a path: launch_ros starts it only if that "
                         "file is executable on the machine that launches (it does not look in the package)", TRUE)
            return
        elif any(n is not None and opaque(n) for _, n in names):
            what = "name"
        elif any(ns is not None and opaque(ns) for _, ns in nss):
            what = "namespace"
        elif any(opaque(f) or opaque(t) for _, (f, t, _) in remaps):
            what = "remappings"
        if what is not None:
            v = {"package": a.package, "executable": a.executable, "name": a.name,
                 "namespace": a.namespace}.get(what)
            span = (v.span() if v is not None else None) or el.tag_span or el.span
            self.decline(el.path, span, f"tvl-lsp cannot know the {what} of this node", TRUE)

    def add_node(self, nf: "Node2Fact", name_value, el: Element, full: str) -> None:
        nf.event = getattr(self, "event_label", None)
        if full and not opaque(full) and not full.endswith("/"):
            others = self.node_names.get(full, [])

            def where(other):
                oel = other.element
                return (other.path, oel.attrs["name"].value_span if "name" in oel.attrs else oel.span,
                        "the other node with this name")
            msg = (f"two nodes named [{shown(full)}] are started: ros2 launch starts both (it only warns) but "
                   "ROS 2 requires node names to be unique")
            # (the name attribute's value: in a Python file the characters of the name, not its quotes)
            span = (el.attrs["name"].value_span if "name" in el.attrs else None) or \
                (name_value.span() if name_value is not None else None) or el.tag_span
            if len(others) <= PAIRWISE_DUPLICATES:
                for other in others:
                    self.fact(DUPLICATE_NODE, msg, el.path, span, conj([other.condition, nf.condition]), W,
                              related=[where(other)])
            else:  # many nodes of one name (an include fan-out): one fact per node, not one per pair
                self.fact(DUPLICATE_NODE, msg, el.path, span, conj([self.node_name_any[full], nf.condition]), W,
                          related=[where(o) for o in others[:MAX_RELATED]])
            self.node_names.setdefault(full, []).append(nf)
            self.node_name_any[full] = disj([self.node_name_any.get(full, FALSE), nf.condition])
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
            if not _valid_yaml(out):
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
                # substitutions is typed when the node runs (ParameterValue.evaluate:
                # coerce_to_type(value, type), can_be_str=False): YAML that fails, a map, a mixed
                # list, null, int('abc') ... make ros2 launch fail there
                plain = S.is_text(v.parts)
                python = getattr(v, "typed", None) is not None   # a Python file's dict value
                for cv, s in self.ev(v, sc, cn, pel):
                    if python:   # launch_ros' evaluate_parameter_dict: YAML, else the text
                        if not opaque(s):   # (a value tvl-lsp cannot compute is not listed)
                            out[key] = (cv, s if p.type == "str" or (plain and not v.typed) else _yaml_value(s))
                        continue
                    if plain or opaque(s):
                        out[key] = (cv, s if p.type == "str" or plain else _yaml_value(s))
                        continue
                    typed = self.typed_param(key, s, p.dtype, pel, v, cv)
                    if typed is not _FAILED:
                        out[key] = (cv, typed)
            elif isinstance(v, list):
                # perform_typed_substitution of a list: its items with substitutions typed one by one
                item = p.dtype.item if isinstance(p.dtype, C.ListOf) else None
                vals, failed = [], False
                for x in v:
                    if isinstance(x, A.Value):
                        cs = self.ev(x, sc, cn, pel)
                        s = cs[0][1] if cs else ""
                        if S.is_text(x.parts) or opaque(s):
                            vals.append(s)
                            continue
                        typed = self.typed_param(key, s, item, pel, x, cn)
                        failed = failed or typed is _FAILED
                        vals.append(typed)
                    else:
                        vals.append(x)
                if not failed and any(isinstance(x, A.Value) and not S.is_text(x.parts) for x in v) and \
                        not C.is_instance_of(vals, p.dtype):
                    msg = "The output list is not uniform" if item is None else \
                        f"The output list does not match the expected type Got value='{vals}', expected type {item}."
                    self.fact(PARAM_INVALID, f"the value of parameter '{key}': {msg}", pel.path,
                              v[0].span() if isinstance(v[0], A.Value) else pel.tag_span, cn, launch=("ValueError", msg))
                    failed = True
                if not failed:
                    out[key] = (cn, vals)
            else:
                out[key] = (cn, v)

    def typed_param(self, key: str, s: str, data_type, pel: Element, v: A.Value, c: Formula):
        """A ``<param value>`` with substitutions, once substituted, typed as launch types it
        (:func:`coerce.perform_typed`); its error is a fact (and _FAILED)."""
        try:
            return C.perform_typed(s, data_type)
        except ValueError as ex:
            self.fact(PARAM_INVALID, f"the value of parameter '{key}' is '{s}' once substituted, which ros2 launch "
                      f"cannot type ({'as YAML' if data_type is None else C.type_text(data_type)}): {ex}",
                      pel.path, v.span() or pel.tag_span, c, launch=("ValueError", str(ex)))
            return _FAILED
        except Exception:  # beyond the YAML bounds: unknown, not an error
            return s
