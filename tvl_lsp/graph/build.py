"""Building the computation graph: of all products at once (from the symbolic load of a launch
file), or of one product (from the concrete load, as roslaunch loads it).

    build_graph(analysis: LaunchAnalysis, hints: ProjectHints, configs=None) -> Graph
    build_product_graph(result: LoadResult, hints: ProjectHints, launch, configs=None) -> Graph

Both go through :func:`assemble` over *node instances*: a ``<node>`` as loaded under a
condition, with its resolved name and the remaps that apply to it (each under its own
condition).  A node's links come from its hints (:mod:`tvl_lsp.graph.hints`): each hinted
name is resolved in the node's namespace and remapped by :func:`tvl_lsp.graph.names.remap_cases`,
one case per remap that may apply.  Nodes without hints get no links and a note.
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
        insts.append(Instance(nf.name, nf.pkg, nf.type, nf.namespace, nf.condition, remaps, loc))
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


def assemble(launch: str, instances: Iterable[Instance], params: Iterable[ParamInstance],
             hints: Optional[ProjectHints], configs: Optional[Iterable[str]] = None) -> Graph:
    hints = hints or ProjectHints()
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
        used: set[str] = set()
        if hs:
            node.hinted = True
            for h in hs:
                loc = Location(h.path, h.span, f"hints for {h.key}")
                if loc not in node.hints:
                    node.hints.append(loc)
        for h in hs:
            for e in h.entries:
                rkind = RESOURCE_OF_KIND[e.kind]
                used.add(N.resolve(e.name, inst.name))
                hint_loc = Location(e.path, e.span, f"{h.key}: {e.kind} {e.name}")
                for c, rname, origin in N.remap_cases(e.name, inst.name, inst.remaps):
                    lc = conj([inst.condition, c])
                    if lc == FALSE:
                        continue
                    rid = f"{RESOURCE_PREFIX[rkind]}:{rname}"
                    if rid not in g.resources:
                        g.resources[rid] = Resource(rid, rkind, rname, FALSE)
                    res_conds.setdefault(rid, []).append(lc)
                    if e.type:
                        type_conds.setdefault((rid, e.type), []).append(lc)
                    key = (nid, e.kind, rid)
                    link_types.setdefault(key, set()).add(e.type)
                    pending.append((key, e.type, Via(e.name, e.type, lc, hint_loc, origin)))
        # how each remap applies to this node (remap-unused)
        for f, t, c, origin in inst.remaps:
            if origin is None or not f or not t or f.startswith("__"):
                continue
            rc = conj([inst.condition, c])
            if rc == FALSE:
                continue
            rf = N.resolve(f, inst.name)
            g.remap_uses.setdefault(origin, []).append(
                RemapUse(nid, rf, N.resolve(t, inst.name), rc, rf in used, bool(hs)))
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
    for node in g.nodes.values():
        if not node.hinted:
            node.note = (f"no hints for {node.package}/{node.type} in "
                         + (", ".join(os.path.basename(s) for s in hints.sources) or "a HAROS project file")
                         + ": the topics and services it uses are unknown")
    unhinted = sorted({f"{n.package}/{n.type}" for n in g.nodes.values() if not n.hinted})
    if unhinted:
        g.notes.append(f"{len(unhinted)} node type(s) without hints (their topics are unknown): "
                       + ", ".join(unhinted[:12]) + (", …" if len(unhinted) > 12 else ""))
    return g


def build_graph(analysis, hints: Optional[ProjectHints] = None,
                configs: Optional[Iterable[str]] = None) -> Graph:
    """The graph of every product of a symbolically loaded launch file (``LaunchAnalysis``)."""
    insts, params = instances_of_analysis(analysis)
    g = assemble(analysis.path, insts, params, hints, configs)
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
                        configs: Optional[Iterable[str]] = None) -> Graph:
    """The graph of one product, from what roslaunch loads for it (``LoadResult``)."""
    insts, params = instances_of_result(result)
    g = assemble(launch, insts, params, hints, configs)
    g.notes.extend(outside_notes(getattr(result, "includes", None),
                                 lambda i: (i.get("outside", False), i.get("file"), i.get("includes"))))
    return g
