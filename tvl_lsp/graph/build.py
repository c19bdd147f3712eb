"""Building the computation graph: of all products at once (from the symbolic load of a launch
file), or of one product (from the concrete load, as roslaunch loads it).

    build_graph(analysis: LaunchAnalysis, hints: ProjectHints, configs=None, sources=None) -> Graph
    build_product_graph(result: LoadResult, hints: ProjectHints, launch, configs=None, sources=None) -> Graph

Both go through :func:`assemble` over *node instances*: a ``<node>`` as loaded under a
condition, with its resolved name and the remaps that apply to it (each under its own
condition).  A node's links come from what its package's sources make its program use
(``sources``: ``pkg/executable`` -> :class:`tvl_lsp.graph.sources.Executable`) and from its
hints (:mod:`tvl_lsp.graph.hints`); a hint entry adds a name, or overrides the call of the
sources that asks for the same name (a dynamic one it matches), for its node only; a hint's
``values`` fill in the run-time parts of dynamic names.  Each name is resolved in the node's
namespace and remapped by :func:`tvl_lsp.graph.names.remap_cases`, one case per remap that may
apply; a name that stays dynamic is resolved but not remapped (``/{real_name}/cmd_vel``: no
remap can be known to match it).  ROS 2 parameters belong to their node (``/node/param``).
Nodes known neither from sources nor from hints get no links and a note.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Iterable, Optional

from ..base.formula import FALSE, TRUE, Formula, conj, disj
from ..base.text import Pos, Span
from . import names as N
from .hints import ProjectHints
from .model import RESOURCE_OF_KIND, Graph, GraphNode, Link, Location, RemapUse, Resource, Via

RESOURCE_PREFIX = {"topic": "topic", "service": "service", "parameter": "param"}


@dataclass
class Instance:
    """A node as loaded under ``condition``."""
    name: str
    package: str
    type: str
    namespace: str
    condition: Formula
    remaps: list[tuple[str, str, Formula, Optional[Location]]]  # roslaunch's order
    location: Optional[Location]
    ros2: bool = False


@dataclass
class ParamInstance:
    name: str
    value: str
    condition: Formula
    location: Optional[Location]


def _node_label(el) -> str:
    a = el.attrs.get("name")
    return f'<{el.tag} name="{a.value}">' if a is not None else f"<{el.tag}>"


def _remap_label(el) -> str:
    f = el.attrs.get("from")
    t = el.attrs.get("to")
    return f'<remap from="{f.value if f else ""}" to="{t.value if t else ""}">'


def instances_of_analysis(analysis) -> tuple[list[Instance], list[ParamInstance]]:
    """The node and parameter instances of a symbolic load (``LaunchAnalysis``)."""
    insts = []
    for nf in analysis.nodes:
        if nf.is_test:
            continue
        el = nf.element
        loc = Location(el.path, el.span, _node_label(el))
        remaps = [(r.from_, r.to, r.condition, Location(r.element.path, r.element.span, _remap_label(r.element)))
                  for r in getattr(nf, "remap_cases", [])]
        insts.append(Instance(nf.name, nf.pkg, nf.type, nf.namespace, nf.condition, remaps, loc,
                              hasattr(nf, "executable")))
    params = []
    for p in analysis.params:
        el = p.element
        label = f'<{el.tag} name="{el.attrs["name"].value}">' if "name" in el.attrs else f"<{el.tag}>"
        params.append(ParamInstance(p.name, p.value, p.condition, Location(el.path, el.span, label)))
    return insts, params


def instances_of_result(result) -> tuple[list[Instance], list[ParamInstance]]:
    """The node and parameter instances of one product (a concrete ``LoadResult``)."""
    insts = []
    for n in result.nodes:
        line = max(0, int(n.get("line", 1)) - 1)
        loc = Location(n.get("file", ""), Span(Pos(line, 0), Pos(line, 0)), f'<node name="{n["name"]}">')
        insts.append(Instance(n["name"], n["pkg"], n["type"], n["namespace"], TRUE,
                              [(f, t, TRUE, None) for f, t in n.get("remaps", [])], loc))
    text = getattr(result, "param_text", None) or {}
    params = [ParamInstance(k, text.get(k, str(v)), TRUE, None) for k, v in result.params.items()]
    return insts, params


class _Use:
    """One name a node uses: from a hint entry or a call in its sources."""
    __slots__ = ("kind", "name", "type", "hint", "source", "dynamic", "label")

    def __init__(self, kind: str, name: str, type_: Optional[str], hint: Optional[Location],
                 source: Optional[Location], dynamic: bool, label: str):
        self.kind = kind
        self.name = name
        self.type = type_
        self.hint = hint
        self.source = source
        self.dynamic = dynamic
        self.label = label


def _substitute(name: str, values: dict[str, str]) -> tuple[str, bool]:
    """A dynamic name with the hinted run-time values put in; (name, still dynamic)."""
    if values:
        for k, v in values.items():
            name = name.replace("{" + k + "}", v)
    return name, "{" in name


def _pattern(resolved: str):
    import re
    parts = re.split(r"(\{[^{}]*\})", resolved)
    rx = "".join("[^/]+(?:/[^/]+)*" if p.startswith("{") and p.endswith("}") else re.escape(p) for p in parts)
    return re.compile("^" + rx + "$")


def _source_uses(exe, values: dict[str, str]) -> list[_Use]:
    from .sources import LINK_OF_KIND
    out = []
    for e in exe.endpoints:
        kind = LINK_OF_KIND.get(e.kind)
        if kind is None:
            continue
        name, dyn = (_substitute(e.name, values) if e.dynamic else (e.name, False))
        loc = Location(e.file, Span(Pos(max(0, e.line - 1), e.col), Pos(max(0, e.end_line - 1), e.end_col)),
                       f"{e.kind} `{e.name}` ({os.path.basename(e.file)}:{e.line})")
        out.append(_Use(kind, name, e.type, None, loc, dyn, f"{exe.package}/{exe.name}"))
    return out


def _uses(inst: "Instance", hs, exe) -> tuple[list[_Use], bool]:
    """What a node instance uses: its hints' entries, and its sources' endpoints that no hint
    entry overrides (a hint entry of the same kind whose resolved name equals the endpoint's,
    or matches a dynamic one).  Second: whether some name stays dynamic."""
    uses: list[_Use] = []
    values: dict[str, str] = {}
    for h in hs:
        values.update(h.values)
        for e in h.entries:
            uses.append(_Use(e.kind, e.name, e.type, Location(e.path, e.span, f"{h.key}: {e.kind} {e.name}"),
                             None, False, h.key))
    if exe is None:
        return uses, False
    hinted = {}
    for u in uses:
        hinted.setdefault(u.kind, []).append(N.resolve(u.name, inst.name))
    dynamic = False
    for u in _source_uses(exe, values):
        mine = hinted.get(u.kind, [])
        if mine:
            r = N.resolve(u.name, inst.name)
            if u.dynamic:
                rx = _pattern(r)
                over = [m for m in mine if rx.match(m)]
            else:
                over = [m for m in mine if m == r]
            if over:
                # the hint overrides this call: it keeps the hint's name and type, and the call's place
                for h in uses:
                    if h.kind == u.kind and h.source is None and N.resolve(h.name, inst.name) in over:
                        h.source = u.source
                        if h.type is None:
                            h.type = u.type
                continue
        dynamic = dynamic or u.dynamic
        uses.append(u)
    return uses, dynamic


def assemble(launch: str, instances: Iterable[Instance], params: Iterable[ParamInstance],
             hints: Optional[ProjectHints], configs: Optional[Iterable[str]] = None,
             sources: Optional[dict] = None) -> Graph:
    """The graph of node and parameter instances; what each node uses comes from ``hints``
    and from ``sources`` (``pkg/executable`` -> :class:`tvl_lsp.graph.sources.Executable`)."""
    hints = hints or ProjectHints()
    sources = sources or {}
    instances = [i for i in instances if i.condition != FALSE]
    g = Graph(launch=launch, hint_sources=list(hints.sources))
    # ids: a name used by nodes of several types (in different products) gets the type in its id
    types_of: dict[str, set] = {}
    for i in instances:
        types_of.setdefault(i.name, set()).add((i.package, i.type))

    def node_id(i: Instance) -> str:
        if len(types_of[i.name]) > 1:
            return f"node:{i.name}#{i.package}/{i.type}"
        return f"node:{i.name}"

    link_types: dict[tuple, set] = {}
    pending: list[tuple] = []  # (key, type, via)
    node_conds: dict[str, list[Formula]] = {}
    res_conds: dict[str, list[Formula]] = {}
    type_conds: dict[tuple[str, str], list[Formula]] = {}
    for inst in instances:
        nid = node_id(inst)
        node = g.nodes.get(nid)
        if node is None:
            node = g.nodes[nid] = GraphNode(nid, inst.name, inst.package, inst.type, inst.namespace, FALSE)
        node_conds.setdefault(nid, []).append(inst.condition)
        if inst.location is not None:
            if inst.location not in node.locations:
                node.locations.append(inst.location)
            node.occurrences.append((inst.location, inst.condition))
        hs = hints.for_node(inst.package, inst.type, inst.name, configs)
        exe = sources.get(f"{inst.package}/{inst.type}")
        used: set[str] = set()
        if hs and (any(h.entries for h in hs) or not any(h.values for h in hs)):
            node.hinted = True
        if hs:
            for h in hs:
                loc = Location(h.path, h.span, f"hints for {h.key}")
                if loc not in node.hints:
                    node.hints.append(loc)
        if exe is not None:
            node.extracted = True
        uses, has_dynamic = _uses(inst, hs, exe)
        for e in uses:
            rkind = RESOURCE_OF_KIND[e.kind]
            if rkind == "parameter" and inst.ros2 and not e.name.startswith(("/", "~")):
                pname = "~" + e.name.replace(".", "/")  # a ROS 2 parameter belongs to its node
            else:
                pname = e.name
            used.add(N.resolve(pname, inst.name))
            # a dynamic name cannot be known to match a remap; ROS 2 remaps topics and services only
            cases = ([(TRUE, N.resolve(pname, inst.name), None)]
                     if e.dynamic or (rkind == "parameter" and inst.ros2)
                     else N.remap_cases(pname, inst.name, inst.remaps))
            for c, rname, origin in cases:
                lc = conj([inst.condition, c])
                if lc == FALSE:
                    continue
                rid = f"{RESOURCE_PREFIX[rkind]}:{rname}"
                if rid not in g.resources:
                    g.resources[rid] = Resource(rid, rkind, rname, FALSE, dynamic=e.dynamic)
                res_conds.setdefault(rid, []).append(lc)
                if e.type:
                    type_conds.setdefault((rid, e.type), []).append(lc)
                key = (nid, e.kind, rid)
                link_types.setdefault(key, set()).add(e.type)
                pending.append((key, e.type, Via(e.name, e.type, lc, e.hint, origin, e.source)))
        # how each remap applies to this node (remap-unused)
        for f, t, c, origin in inst.remaps:
            if origin is None or not f or not t or f.startswith("__"):
                continue
            rc = conj([inst.condition, c])
            if rc == FALSE:
                continue
            rf = N.resolve(f, inst.name)
            g.remap_uses.setdefault(origin, []).append(
                RemapUse(nid, rf, N.resolve(t, inst.name), rc, rf in used, node.known and not has_dynamic))
    link_conds: dict[str, list[Formula]] = {}
    for key, typ, via in pending:
        nid, kind, rid = key
        lid = f"{kind}:{nid}>{rid}"
        if len(link_types[key]) > 1:
            lid += f"#{typ or '?'}"
        ln = g.links.get(lid)
        if ln is None:
            ln = g.links[lid] = Link(lid, nid, rid, kind, FALSE, typ)
        link_conds.setdefault(lid, []).append(via.condition)
        if via not in ln.via:
            ln.via.append(via)
    for nid, cs in node_conds.items():
        g.nodes[nid].condition = disj(cs)
    for rid, cs in res_conds.items():
        g.resources[rid].condition = disj(cs)
    for (rid, typ), cs in type_conds.items():
        g.resources[rid].types[typ] = disj(cs)
    for lid, cs in link_conds.items():
        g.links[lid].condition = disj(cs)
    param_conds: dict[str, list[Formula]] = {}
    for p in params:
        if p.condition == FALSE:
            continue
        rid = f"param:{p.name}"
        res = g.resources.get(rid)
        if res is None:
            res = g.resources[rid] = Resource(rid, "parameter", p.name, FALSE)
        param_conds.setdefault(rid, []).append(p.condition)
        if res.value is None:
            res.value = p.value
        if p.location is not None and p.location not in res.locations:
            res.locations.append(p.location)
    for rid, cs in param_conds.items():
        r = g.resources[rid]
        r.condition = disj([r.condition] + cs)
    where = (", ".join(os.path.basename(s) for s in hints.sources) or "a HAROS project file")
    for node in g.nodes.values():
        if not node.known:
            node.note = (f"no hints for {node.package}/{node.type} in {where} and no sources of it in the "
                         "workspace: the topics and services it uses are unknown")
    unknown = sorted({f"{n.package}/{n.type}" for n in g.nodes.values() if not n.known})
    if unknown:
        g.notes.append(f"{len(unknown)} node type(s) whose topics are unknown (no sources in the workspace, no "
                       "hints): " + ", ".join(unknown[:12]) + (", …" if len(unknown) > 12 else ""))
    dyn = sorted({r.name for r in g.resources.values() if r.dynamic})
    if dyn:
        g.notes.append(f"{len(dyn)} name(s) computed at run time (shown with {{expression}}; a project file's "
                       "`values:` hint gives their value): " + ", ".join(dyn[:8]) + (", …" if len(dyn) > 8 else ""))
    return g


def build_graph(analysis, hints: Optional[ProjectHints] = None,
                configs: Optional[Iterable[str]] = None, sources: Optional[dict] = None) -> Graph:
    """The graph of every product of a symbolically loaded launch file (``LaunchAnalysis``)."""
    insts, params = instances_of_analysis(analysis)
    g = assemble(analysis.path, insts, params, hints, configs, sources)
    g.notes.extend(outside_notes(analysis.includes, lambda i: (i.outside, i.file, i.children)))
    return g


def outside_notes(includes, fields) -> list[str]:
    """A note per include outside the workspace (not read: what it starts is not drawn); the
    one rule of docs/architecture.md, "Includes outside the workspace"."""
    out: list[str] = []
    todo = list(includes or [])
    while todo:
        outside, file, children = fields(todo.pop(0))
        if outside and file:
            note = f"{file} is outside the workspace: not read, so the nodes it starts are not drawn"
            if note not in out:
                out.append(note)
        todo.extend(children or [])
    return out


def build_product_graph(result, hints: Optional[ProjectHints] = None, launch: str = "",
                        configs: Optional[Iterable[str]] = None, sources: Optional[dict] = None) -> Graph:
    """The graph of one product, from what roslaunch loads for it (``LoadResult``)."""
    insts, params = instances_of_result(result)
    g = assemble(launch, insts, params, hints, configs, sources)
    g.notes.extend(outside_notes(getattr(result, "includes", None),
                                 lambda i: (i.get("outside", False), i.get("file"), i.get("includes"))))
    return g
