"""Node hints from HAROS project files: which topics, services and parameters a node uses.

HAROS extracts a node's publishers and subscribers from its source code; for nodes it has no
source of (third-party packages), the project file says what they use.  The thesis (§5.2,
Listing 5.6) writes them per node *type*, at the top level, so that they hold in every
configuration of a generic launch file::

    nodes:
        turtlesim/turtlesim_node:            # package/executable
            subscribe:
                /turtle1/cmd_vel: geometry_msgs/Twist
        turtlesim/turtle_teleop_key:
            advertise:
                /turtle1/cmd_vel: geometry_msgs/Twist

Sections: ``advertise`` (publishes), ``subscribe``, ``service`` (provides), ``client`` (calls),
``readParam`` / ``writeParam``; each maps a name -- as the node's code writes it, before any
remapping: global ``/x``, relative ``x`` or private ``~x`` -- to a message / service type.
A section may also be a list of names, or of ``{name: ..., type: ...}`` mappings (HAROS's
JSON form, ``topic`` / ``service`` / ``msg_type`` / ``srv_type`` accepted).

Plain HAROS project files also give hints per configuration and per node *name* (thesis
Listing 3.1)::

    configurations:
        multiplexer:
            launch: [turtlerand/launch/third.launch]
            hints:
                /turtle_teleop_key:
                    advertise: {/turtle1/cmd_vel: geometry_msgs/Twist}

Those are read too (:attr:`ProjectHints.by_config`), applying to the nodes of that name in
that configuration's launch files.  Malformed hints get ``invalid-hint`` diagnostics on the
project file; they never raise.  Pure: no LSP here.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from typing import Iterable, Optional

from ..base.diagnostics import Diagnostic, Severity, register
from ..base.text import Pos, Span

INVALID_HINT = register(
    "invalid-hint", Severity.WARNING,
    "A node hint of a HAROS project file (`nodes:` / `hints:`) is malformed and is ignored.", "graph")

# section key -> link kind
SECTIONS = {
    "advertise": "publish",
    "subscribe": "subscribe",
    "service": "service",
    "client": "client",
    "readParam": "read",
    "writeParam": "write",
}
KINDS = tuple(SECTIONS.values())
# HAROS's other per-node keys: known, not about links
OTHER_KEYS = {"values", "rosname", "nodelet", "fix", "hpl", "create", "base", "args", "remaps", "node_type",
              "traceability", "conditional"}
NAME_KEYS = ("name", "topic", "service", "param")
TYPE_KEYS = ("type", "msg_type", "srv_type", "param_type")
MAX_BYTES = 2_000_000


@dataclass(frozen=True)
class HintEntry:
    """One name a node uses: ``kind`` (publish, subscribe, service, client, read, write),
    ``name`` as the node's code writes it, ``type`` (message / service / parameter type;
    None when not given), and where the entry is written."""
    kind: str
    name: str
    type: Optional[str]
    path: str
    span: Span


@dataclass
class NodeHints:
    """The hints of one node type (``pkg/type``) or node name (``/name``)."""
    key: str
    path: str
    span: Span  # the key in the project file
    entries: list[HintEntry] = field(default_factory=list)
    # run-time values of what the node's code computes (``values: {real_name: turtle1}``): each
    # ``{expression}`` of a dynamic name read from the sources is replaced by its value
    values: dict[str, str] = field(default_factory=dict)


@dataclass
class ProjectHints:
    """Everything one or more project files hint."""
    by_type: dict[str, NodeHints] = field(default_factory=dict)         # "pkg/type" -> hints
    by_config: dict[str, dict[str, NodeHints]] = field(default_factory=dict)  # config -> node name -> hints
    diagnostics: list[Diagnostic] = field(default_factory=list)
    sources: list[str] = field(default_factory=list)                    # project files read

    def __bool__(self) -> bool:
        return bool(self.by_type or self.by_config)

    def merge(self, other: "ProjectHints") -> "ProjectHints":
        """Both files' hints; for a node type hinted in both, the entries of both."""
        out = ProjectHints(dict(self.by_type), {k: dict(v) for k, v in self.by_config.items()},
                           list(self.diagnostics) + list(other.diagnostics),
                           list(dict.fromkeys(self.sources + other.sources)))
        for k, nh in other.by_type.items():
            if k in out.by_type:
                mine = out.by_type[k]
                out.by_type[k] = NodeHints(k, mine.path, mine.span, mine.entries + [
                    e for e in nh.entries if e not in mine.entries], {**nh.values, **mine.values})
            else:
                out.by_type[k] = nh
        for c, d in other.by_config.items():
            out.by_config.setdefault(c, {}).update(d)
        return out

    def for_node(self, package: str, type_: str, name: str,
                 configs: Optional[Iterable[str]] = None) -> list[NodeHints]:
        """The hints that apply to a node: by its type, and by its name in ``configs`` (all
        configurations when None)."""
        out = []
        t = self.by_type.get(f"{package}/{type_}")
        if t is not None:
            out.append(t)
        for c, d in self.by_config.items():
            if configs is not None and c not in configs:
                continue
            h = d.get(name) or d.get(name.lstrip("/"))
            if h is not None:
                out.append(h)
        return out


def _span(node) -> Span:
    s, e = node.start_mark, node.end_mark
    a, b = Pos(s.line, s.column), Pos(e.line, e.column)
    if b < a:
        b = a
    if b.line > a.line and isinstance(getattr(node, "value", None), str):
        # a plain scalar's end mark can run past trailing blank lines
        b = Pos(a.line, a.column + len(node.value))
    return Span(a, b)


def parse_hints(path: str, text: str) -> ProjectHints:
    """The hints of one project file (empty when it has none or is not valid YAML)."""
    import yaml

    from ..base import yamlsafe

    out = ProjectHints(sources=[path])
    if text is None or len(text) > MAX_BYTES or ("nodes" not in text and "hints" not in text):
        return out
    try:
        root = yamlsafe.compose(text)
    except Exception:
        return out  # the project file's own check reports its YAML errors
    if not isinstance(root, yaml.MappingNode):
        return out

    def diag(node, msg: str) -> None:
        out.diagnostics.append(Diagnostic(INVALID_HINT, Severity.WARNING, path, _span(node), msg))

    def scalar(n) -> Optional[str]:
        if isinstance(n, yaml.ScalarNode):
            return n.value
        return None

    def entries_of(section_key: str, kind: str, node) -> list[HintEntry]:
        res: list[HintEntry] = []

        def add(name_node, type_node) -> None:
            name = scalar(name_node)
            if name is None or not name.strip():
                diag(name_node, f"`{section_key}`: a name must be a non-empty string")
                return
            typ = None
            if type_node is not None:
                t = scalar(type_node)
                if t is None:
                    diag(type_node, f"`{section_key}` `{name}`: the type must be a string such as "
                                    "`std_msgs/String`")
                    return
                typ = t.strip() or None
                if typ in ("null", "~", "?", "*"):
                    typ = None
            res.append(HintEntry(kind, name.strip(), typ, path, _span(name_node)))

        if isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                add(k, v)
        elif isinstance(node, yaml.SequenceNode):
            for item in node.value:
                if isinstance(item, yaml.ScalarNode):
                    add(item, None)
                elif isinstance(item, yaml.MappingNode):
                    keys = {scalar(k): (k, v) for k, v in item.value}
                    nk = next((keys[k] for k in NAME_KEYS if k in keys), None)
                    tk = next((keys[k] for k in TYPE_KEYS if k in keys), None)
                    if nk is None:
                        diag(item, f"`{section_key}`: an entry needs a `name` (and a `type`)")
                        continue
                    add(nk[1], tk[1] if tk else None)
                else:
                    diag(item, f"`{section_key}`: each entry is a name or a `{{name, type}}` mapping")
        elif isinstance(node, yaml.ScalarNode) and node.value.strip() in ("", "null", "~"):
            pass
        else:
            diag(node, f"`{section_key}` must map names to types (`/topic: pkg/Type`)")
        return res

    def node_hints(key_node, val, by_name: bool) -> Optional[NodeHints]:
        key = scalar(key_node)
        if key is None:
            diag(key_node, "a hinted node is named by a string")
            return None
        key = key.strip()
        if not by_name and (key.count("/") != 1 or key.startswith("/") or key.endswith("/")):
            diag(key_node, f"`{key}`: a node type under `nodes:` is written `package/executable`")
            return None
        nh = NodeHints(key, path, _span(key_node))
        if isinstance(val, yaml.ScalarNode) and val.value.strip() in ("", "null", "~"):
            return nh
        if not isinstance(val, yaml.MappingNode):
            diag(val, f"`{key}`: expected a mapping of `advertise`, `subscribe`, `service`, `client`")
            return nh
        for k, v in val.value:
            sk = scalar(k)
            if sk in SECTIONS:
                nh.entries += entries_of(sk, SECTIONS[sk], v)
            elif sk == "values":
                if isinstance(v, yaml.MappingNode):
                    for vk, vv in v.value:
                        a, b = scalar(vk), scalar(vv)
                        if a is None or b is None or not a.strip():
                            diag(vk, "`values` maps an expression of the code (as `tvl-lsp extract` shows it "
                                     "between braces) to its run-time value, both strings")
                            continue
                        nh.values[" ".join(a.split()).strip("{}")] = b.strip()
                elif not (isinstance(v, yaml.ScalarNode) and v.value.strip() in ("", "null", "~")):
                    diag(v, "`values` maps expressions of the code to their run-time values "
                            "(`real_name: turtle1`)")
            elif sk in OTHER_KEYS:
                continue
            else:
                close = difflib.get_close_matches(str(sk), list(SECTIONS), n=1, cutoff=0.6)
                hint = f"; did you mean `{close[0]}`?" if close else \
                    " (known: advertise, subscribe, service, client, readParam, writeParam)"
                diag(k, f"`{sk}` is not a hint section of `{key}`{hint}")
        return nh

    for k, v in root.value:
        kk = scalar(k)
        if kk == "nodes":
            if isinstance(v, yaml.MappingNode):
                for nk, nv in v.value:
                    nh = node_hints(nk, nv, False)
                    if nh is not None:
                        if nh.key in out.by_type:
                            out.by_type[nh.key].entries += nh.entries
                            out.by_type[nh.key].values.update(nh.values)
                        else:
                            out.by_type[nh.key] = nh
            elif not (isinstance(v, yaml.ScalarNode) and v.value.strip() in ("", "null", "~")):
                diag(v, "`nodes` must map node types (`package/executable`) to their hints")
        elif kk == "configurations" and isinstance(v, yaml.MappingNode):
            keys = [scalar(x) for x, _ in v.value]
            if any(x in ("lf", "tvl", "launch") for x in keys):
                continue  # one HAROS-TVL configuration, no per-name hints
            for ck, cv in v.value:
                cname = scalar(ck)
                if cname is None or not isinstance(cv, yaml.MappingNode):
                    continue
                for hk, hv in cv.value:
                    if scalar(hk) != "hints":
                        continue
                    if not isinstance(hv, yaml.MappingNode):
                        diag(hv, "`hints` must map node names to their hints")
                        continue
                    d = out.by_config.setdefault(cname, {})
                    for nk, nv in hv.value:
                        if scalar(nk) == "nodes":
                            continue  # HAROS's later `hints: nodes:` fixes: not node usage hints
                        nh = node_hints(nk, nv, True)
                        if nh is not None:
                            name = nh.key if nh.key.startswith("/") else "/" + nh.key
                            d[name] = nh
    return out
