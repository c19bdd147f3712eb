"""Parameters: ``<param>`` (value, textfile, binfile, command; types) and ``<rosparam>``
(load / dump / delete, YAML files and inline YAML), as roslaunch loads and checks them."""

from __future__ import annotations

import os
import shlex
import shutil
from typing import Optional

import yaml

from ...base.formula import FALSE, TRUE, Formula, conj, disj
from ..model import Element, ParamFact
from ..xml import XElement
from .rules import (COMMAND_NOT_FOUND, FILE_NOT_FOUND, INVALID_VALUE, MISSING_ATTRIBUTE, PARAM_INVALID,
                    PARAM_VALUE_COUNT, UNRESOLVED, _attr_bool, _convert_error, ns_join, shown)
from .scopes import Scope


class ParamRules:
    """``<param>`` and ``<rosparam>`` (a mixin of :class:`~tvl_lsp.launch.ros1.loader.Walker`)."""

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
