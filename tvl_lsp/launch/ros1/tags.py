"""Tag rules: what roslaunch checks and records for ``<launch>``, ``<group>``, ``<node>`` /
``<test>``, ``<remap>``, ``<env>`` and ``<machine>``."""

from __future__ import annotations

import re
from typing import Optional

from ...base.formula import FALSE, TRUE, Formula, conj, disj, neg
from ...base.diagnostics import Diagnostic
from ..model import Element, NodeFact, RemapCase
from ..xml import XElement
MAX_RELATED = 64  # related locations listed for a duplicate node

from .rules import (Cases, DUPLICATE_NODE, EMPTY_NS, ENV_INVALID, ILLEGAL_NAME, INVALID_VALUE,
                    LAUNCH_CHILD_TAGS, LAUNCH_IF_UNLESS, MACHINE_INVALID, MISSING_ATTRIBUTE, NODE_NAME_NS,
                    REMAP_INVALID, RESPAWN_REQUIRED, TAG_ATTRS, TEST_INVALID, UNKNOWN_ATTRIBUTE, UNKNOWN_TAG,
                    UNRESOLVED, W, _attr_bool, _bool_val, _is_float, canonicalize, is_legal_name,
                    make_global_ns, merge, ns_join, shown, when)
from .params import NodeParams, param_ns
from .scopes import Scope


class TagRules:
    """``<launch>``, ``<group>``, ``<node>`` / ``<test>``, ``<remap>``, ``<env>``, ``<machine>`` (a mixin
    of :class:`~tvl_lsp.launch.ros1.loader.Walker`)."""

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
            child = sc.child(v, share_args=tag == "node")
            if include_file is not None:
                child.arg_names = {}
                child.filename = include_file
                child.include_args = {}
                child.include_names = {}
            out.append((c, child))
        return out

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
        node_params = NodeParams(scopes, name)
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
                self.param_tag(cx, cel, sc, cond, node=node_params)
            elif t == "rosparam":
                self.rosparam_tag(cx, cel, sc, cond, node=node_params)
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
                node_remaps = [(f, t) for f, t, rc, _ in node_remap_scope.remaps if conj([rc, c]) != FALSE]
                nf = NodeFact(shown(full), shown(pkg1), shown(typ1), nsn, el, c, el.path, shown(argstr),
                              node_remaps, is_test)
                nf.remap_cases = [RemapCase(shown(f), shown(t), rcc, rel) for f, t, rc, rel in node_remap_scope.remaps
                                  for rcc in [conj([rc, c])] if rcc != FALSE]
                # roslaunch: the scope's ~params, then the node's own <param>s, each under the
                # node's private namespace (a leading ~ dropped, a leading / too: <param
                # name="/x"> inside a node is /ns/node/x)
                pns = param_ns(child.ns, nm)
                for pname, pvals, pc, pel in list(sc.params) + node_params.local:
                    key = pname[1:] if pname.startswith("~") else pname
                    for vc, data, text, source in pvals:
                        self.add_param(pns + key, data, text, source, pel, conj([c, pc, vc]))
                if is_test:
                    self.nodes.append(nf)
                    continue
                others = self.node_names.get(full, [])
                if others:
                    # one fact per node (not one per pair: linear in the number of nodes), the
                    # first few others as related locations
                    if len(others) <= MAX_RELATED:  # pair by pair (the simplest printed condition)
                        both = disj([conj([o.condition, c]) for o in others])
                    else:  # many nodes of one name: one formula per node, not one per pair
                        both = conj([self.node_name_any[full], c])
                    self.fact(DUPLICATE_NODE, f"roslaunch file contains multiple nodes named [{shown(full)}]. Please "
                              "check all <node> 'name' attributes to make sure they are unique.", el,
                              self.aspan(el, "name"), both,
                              related=[(other.path, other.element.attrs["name"].value_span
                                        if "name" in other.element.attrs else other.element.span,
                                        "the other node with this name") for other in others[:MAX_RELATED]])
                self.node_names.setdefault(full, []).append(nf)
                self.node_name_any[full] = disj([self.node_name_any.get(full, FALSE), c])
                self.nodes.append(nf)

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
                target.remaps = [(a, b, conj([rc, nc]) if a == f2 else rc, rel) for a, b, rc, rel in target.remaps]
                target.remaps = [r for r in target.remaps if r[2] != FALSE]
                target.remaps.append((f2, t2, c, el))

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
