"""Parameters: ``<param>`` (value, textfile, binfile, command; types) and ``<rosparam>``
(load / dump / delete, YAML files and inline YAML, ``subst_value``), as roslaunch loads and
checks them: the names it gives them (a ``<param>`` inside a ``<node>`` is the node's private
parameter whatever its name says; ``~name`` params of a scope apply to the nodes declared after
them) and the values it sets (``convert_value`` for ``<param>``, rosparam's YAML for
``<rosparam>``, dictionaries unrolled)."""

from __future__ import annotations

import os
import shlex
import shutil
from typing import Any, Optional

import yaml

from ...base.files import unreadable_reason
from ...base.formula import FALSE, TRUE, Formula, conj, disj
from ...base.text import Span
from ..model import Element, ParamFact
from ..xml import XElement, text_offsets, value_span
from . import rosyaml
from .rules import (COMMAND_NOT_FOUND, FILE_NOT_FOUND, INVALID_VALUE, MISSING_ATTRIBUTE, PARAM_INVALID, W,
                    PARAM_VALUE_COUNT, UNRESOLVED, _attr_bool, canonicalize, convert_value, make_global_ns, ns_join,
                    shown)
from .scopes import Scope

PRE = "error loading <rosparam> tag: "


def display(data: Any) -> str:
    """A parameter value as text for people (hover, ``tvl-lsp launch``)."""
    if isinstance(data, bool):
        return "true" if data else "false"
    if isinstance(data, str):
        return data
    if isinstance(data, rosyaml.Binary):
        return f"<{len(data)} bytes>"
    if isinstance(data, (list, dict)):
        try:
            return yaml.safe_dump(data, default_flow_style=True, width=1 << 30).strip()
        except yaml.YAMLError:
            return repr(data)
    return repr(data) if isinstance(data, float) else str(data)


def _unshown(data: Any) -> Any:
    """Unresolved ``$(find pkg)`` markers inside YAML data printed back as written."""
    if isinstance(data, str):
        return shown(data) if UNRESOLVED in data else data
    if isinstance(data, list):
        return [_unshown(x) for x in data]
    if isinstance(data, dict):
        return {k: _unshown(v) for k, v in data.items()}
    return data


class NodeParams:
    """Where a ``<node>``'s children put parameters: the node's scope cases and name cases
    (``param_ns`` per case), and its ``<param>``s, which roslaunch sets after the scope's
    ``~params`` (``local``: (name, [(condition, data, text, source)]) in order)."""

    def __init__(self, scopes, names):
        self.scopes = scopes
        self.names = names
        self.local: list = []

    def bases(self) -> list[tuple[Formula, str]]:
        out = []
        for sc_c, child in self.scopes:
            for nc, nn in self.names:
                c = conj([sc_c, nc])
                if c != FALSE and nn:
                    out.append((c, param_ns(child.ns, nn)))
        return out


def param_ns(ns: str, node_name: str) -> str:
    """The private namespace of node ``node_name`` in namespace ``ns`` (``/ns/name/``)."""
    if ns == "~":
        ns = "~/"
    return make_global_ns(ns_join(ns, node_name)) if not ns.startswith("~") else ns + node_name + "/"


class ParamRules:
    """``<param>`` and ``<rosparam>`` (a mixin of :class:`~tvl_lsp.launch.ros1.loader.Walker`)."""

    def add_param(self, name: str, data: Any, text: str, source: str, el: Element, cond: Formula):
        if cond == FALSE:
            return
        self.params.append(ParamFact(shown(canonicalize(name)), shown(text), el, cond, _unshown(data), source))

    def add_private(self, sc: Scope, entry: tuple):
        """A ``~param`` of scope ``sc`` (roslaunch's context.add_param), also in the lists
        roslaunch shares with it (see :attr:`Scope.params_link`).  ``entry``: (name, [(condition,
        data, text, source)], condition, element)."""
        sc.params.append(entry)
        link, cond = sc.params_link, entry[2]
        while link is not None and cond != FALSE:
            plist, nonempty, nxt = link
            cond = conj([cond, nonempty])
            if cond != FALSE:
                plist.append((entry[0], entry[1], cond, entry[3]))
            link = nxt

    # ---------------------------------------------------------------- <param>

    def param_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula, node: Optional[NodeParams] = None):
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
        lead = len(a.value) - len(a.value.lstrip())
        idx = self.index[el.path]
        names = self.resolve_text(a.value.strip(), a, el, sc, cond,
                                  spans=lambda i, j: value_span(a, idx, i + lead, j + lead))
        kind = present[0]
        t = x.attrs["type"].value if "type" in x.attrs else ""
        ptype = (t or "auto").lower().strip()
        pvals = []  # (condition, data, text, source)
        for c, v in vals[kind]:
            if kind == "value":
                v = v.strip()
                if "$(" in v or UNRESOLVED in v:
                    pvals.append((c, v, v, "value"))  # not analysable: the text as is
                    continue
                try:
                    pvals.append((c, convert_value(v, ptype), v, "value"))
                except ValueError as e:
                    self.fact(PARAM_INVALID, f"Invalid <param> tag: {e}", el, self.aspan(el, "value"), c)
            elif kind in ("textfile", "binfile"):
                if UNRESOLVED not in v and not self.exists(v):
                    why = unreadable_reason(v) if os.path.lexists(v) else None
                    msg = (f"Invalid <param> tag: '{v}' is not read: {why}" if why else
                           f"Invalid <param> tag: [Errno 2] No such file or directory: '{v}'")
                    self.fact(FILE_NOT_FOUND, msg, el, self.aspan(el, kind), c)
                    continue
                pvals.append((c, v, v, kind))
            elif kind == "command":
                if self.check_command(v, el, c):
                    pvals.append((c, v, v, "command"))
        for nc, nm in names:
            for c, data, text, source in pvals:
                cc = conj([nc, c])
                if cc == FALSE:
                    continue
                if not nm:
                    self.fact(PARAM_INVALID, "Invalid <param> tag: no parameter name specified", el,
                              self.aspan(el, "name"), cc)
                    continue
                if node is not None:
                    node.local.append((nm, [(cc, data, text, source)], cc, el))
                elif nm.startswith("~"):
                    self.add_private(sc, (nm, [(cc, data, text, source)], cc, el))
                else:
                    self.add_param(ns_join(sc.ns, nm), data, text, source, el, cc)

    def check_command(self, v: str, el: Element, c: Formula) -> bool:
        """Whether roslaunch can run the command (facts for the failures)."""
        if UNRESOLVED in v:
            return True
        try:
            words = shlex.split(v)
        except ValueError as e:
            self.fact(PARAM_INVALID, f"Invalid <param> tag: cannot split command: {e}", el,
                      self.aspan(el, "command"), c)
            return False
        if not words:
            self.fact(PARAM_INVALID, "Invalid <param> tag: empty command", el, self.aspan(el, "command"), c)
            return False
        prog = words[0]
        if "/" in prog:
            found = os.path.exists(prog)
            if not found and not self.concrete:
                pkg = next((n for n, folder in self.packages.items() if prog.startswith(folder.rstrip("/") + "/")),
                           None)
                if pkg is not None:
                    # roslaunch on the sources fails; after a build, $(find) also finds programs in
                    # the devel/install space's lib/<pkg> (catkin's libexec): a warning
                    self.fact(COMMAND_NOT_FOUND, f"Invalid <param> tag: Cannot load command parameter: no such "
                              f"command [{words!r}]: the package {pkg} has no such file (roslaunch fails unless a "
                              "build puts the program in its lib folder)", el, self.aspan(el, "command"), c,
                              severity=W)
                return True  # a path we cannot check statically (e.g. an install space)
        else:
            found = shutil.which(prog, path=self.env.get("PATH", os.defpath)) is not None
        if not found:
            self.fact(COMMAND_NOT_FOUND, f"Invalid <param> tag: Cannot load command parameter: no such command "
                      f"[{words!r}]", el, self.aspan(el, "command"), c)
            return False
        return True

    # ---------------------------------------------------------------- <rosparam>

    def rosparam_tag(self, x: XElement, el: Element, sc: Scope, guard: Formula, node: Optional[NodeParams] = None):
        cond = self.ifunless(x, el, sc, guard)
        if cond == FALSE:
            return
        el.condition = disj([el.condition, cond])
        r = {k: self.resolve(x, el, k, sc, cond) for k in ("command", "ns", "file", "param", "subst_value")}
        substs = [(cond, False)]
        if r["subst_value"] is not None:
            substs = []
            for c, v in r["subst_value"]:
                b = _attr_bool(v)
                if b is None:
                    msg = (f"invalid bool value for subst_value: {v}" if v else
                           "bool value for subst_value must be non-empty")
                    self.fact(INVALID_VALUE, f"{PRE}{msg}", el, self.aspan(el, "subst_value"), c)
                    continue
                substs.append((c, b))
        # roslaunch: param = ns_join(ns or '', param or '')
        params = [(conj([c1, c2]), ns_join(nsv or "", pv or "")) for c1, nsv in (r["ns"] or [(cond, "")])
                  for c2, pv in (r["param"] or [(cond, "")])]
        params = [(c, p) for c, p in params if c != FALSE]
        for c, cmd in r["command"] or [(cond, "load")]:
            cmd = cmd or "load"
            if cmd not in ("load", "dump", "delete"):
                self.fact(PARAM_INVALID, f"{PRE}command must be 'load', 'dump', or 'delete'", el,
                          self.aspan(el, "command"), c)
                continue
            if r["file"] is not None:
                for c2, f in r["file"]:
                    cc = conj([c, c2])
                    if cc == FALSE:
                        continue
                    if cmd == "load" and UNRESOLVED not in f and not self.exists(f):
                        why = unreadable_reason(f) if os.path.lexists(f) else None
                        msg = f"{PRE}file [{f}] is not read: {why}" if why else f"{PRE}file does not exist [{f}]"
                        self.fact(FILE_NOT_FOUND, msg, el, self.aspan(el, "file"), cc)
                    elif cmd == "delete":
                        self.fact(PARAM_INVALID, f"{PRE}'file' attribute is invalid with 'delete' command.", el,
                                  self.aspan(el, "file"), cc)
                    elif cmd == "load" and UNRESOLVED not in f:
                        text = self.read(f)
                        if text is not None and len(text) < 2_000_000:
                            fspan = self.aspan(el, "file")
                            self.rosparam_load(text, f, lambda i, j: fspan, x, el, sc, cc, substs, params, node)
            elif cmd == "load":
                offs = text_offsets(self.units[el.path].doc.text, x) if "$" in x.text else None
                idx = self.index[el.path]

                def body_span(i: int, j: int, offs=offs) -> Span:
                    if offs is None:
                        return el.tag_span or el.span
                    i = min(max(i, 0), len(offs) - 1)
                    j = min(max(j, 0), len(offs) - 1)
                    return idx.span(offs[i], offs[j])
                self.rosparam_load(x.text, None, body_span, x, el, sc, c, substs, params, node)

    def rosparam_load(self, text: str, file: Optional[str], spans, x: XElement, el: Element, sc: Scope,
                      cond: Formula, substs, params, node: Optional[NodeParams]):
        """roslaunch's load_rosparam: substitute (subst_value), parse, set the values."""
        for sc_, subst in substs:
            c = conj([cond, sc_])
            if c == FALSE:
                continue
            if subst and "$" in text:
                where = f"rosparam:{file}" if file else "rosparam"
                texts = self.resolve_text(text, None, el, sc, c, where, spans=spans)
            else:
                texts = [(c, text)]
            if self.typing is not None:
                continue  # typing walk: the uses are known, the YAML does not matter
            for ct, t in texts:
                data = self.check_yaml(t, el, ct, file, subst)
                if data is None:
                    continue
                self.rosparam_values(data, params, sc, el, ct, node)

    def rosparam_values(self, data, params, sc: Scope, el: Element, c: Formula, node: Optional[NodeParams]):
        """Record the params a loaded <rosparam> sets (dicts unrolled, as roslaunch)."""
        bases = node.bases() if node is not None else [(TRUE, sc.ns)]
        for bc, base in bases:
            for pc, param in params:
                cond = conj([c, bc, pc])
                if cond == FALSE:
                    continue
                if not param and not isinstance(data, dict):
                    self.fact(PARAM_INVALID, f"{PRE}'param' attribute must be set for non-dictionary values", el,
                              el.tag_span, cond)
                    continue
                full = ns_join(base, param) if param else base
                self._unroll(full, data, el, cond, 0)

    def _unroll(self, key: str, value, el: Element, cond: Formula, depth: int):
        if len(self.params) > 100_000 or depth > 50:
            return
        if key == "/" and not isinstance(value, dict):
            self.fact(PARAM_INVALID, f"{PRE}Cannot load non-dictionary types into global namespace '/'", el,
                      el.tag_span, cond)
            return
        if isinstance(value, dict):
            for k, v in value.items():
                if not isinstance(k, str):
                    self.fact(PARAM_INVALID, f"{PRE}the YAML key {k!r} is not a string: roslaunch fails on it "
                              "(TypeError while naming the parameter)", el, el.tag_span, cond)
                    continue
                self._unroll(ns_join(key, k), v, el, cond, depth + 1)
        else:
            self.add_param(key, value, display(value), "yaml", el, cond)

    def check_yaml(self, text: str, el: Element, c: Formula, file: Optional[str], subst: bool = False):
        if UNRESOLVED in text:
            text = shown(text)  # $(find pkg) of a package outside the workspace, as written
        try:
            data = rosyaml.load(text)
        except rosyaml.RosYamlError as e:
            msg = f"file {file} contains invalid YAML: {e}" if file else f"invalid YAML: {e}"
            self.fact(PARAM_INVALID, PRE + msg, el, el.tag_span, c)
            return None
        except yaml.YAMLError as e:
            if subst and "$(" in text:
                return None  # a substitution tvl-lsp could not resolve: no finding
            msg = f"file {file} contains invalid YAML" if file else f"Error within YAML block: {str(e)[:200]}"
            self.fact(PARAM_INVALID, PRE + msg, el, el.tag_span, c)
            return None
        except Exception:
            return None
        if data is None:
            data = {}
        return data
