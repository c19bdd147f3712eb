"""Outputs of a (projected) graph: JSON (the schema in ``docs/graph.md``), Graphviz DOT drawn as
HAROS draws computation graphs, and Mermaid for Markdown documents.

Colours as HAROS's visualiser: ROS nodes white, topics green, services blue, parameters
purple; elements and links present in only some of the products are dashed, with their
condition in the tooltip and under the label.
"""

from __future__ import annotations

import copy
import os
from typing import Optional

from ..base import formula as fm
from .model import Graph, Location

SCHEMA_VERSION = 1
OUTGOING = ("publish", "client", "action_client", "write")   # drawn node -> resource
MAX_LABEL_CONDITION = 60

FILL = {"node": "#ffffff", "topic": "#a3d977", "service": "#8cb8f0", "action": "#f5c08a", "parameter": "#c9a3e6"}


def cond_text(c: Optional[fm.Formula]) -> Optional[str]:
    return None if c is None else str(c)


def view(g: Graph, services: bool = True, actions: bool = True, parameters: bool = True,
         leaf_topics: bool = True) -> Graph:
    """The graph without some kinds of resources (and their links); ``leaf_topics=False`` also
    leaves out the topics only published or only subscribed to (rqt_graph's "hide leaf
    topics": what the thesis's figures show)."""
    keep_kind = {"topic": True, "service": services, "action": actions, "parameter": parameters}
    res = {k: r for k, r in g.resources.items() if keep_kind.get(r.kind, True)}
    if not leaf_topics:
        pubs = {ln.resource for ln in g.links.values() if ln.kind == "publish"}
        subs = {ln.resource for ln in g.links.values() if ln.kind == "subscribe"}
        res = {k: r for k, r in res.items() if r.kind != "topic" or (k in pubs and k in subs)}
    out = copy.copy(g)
    out.resources = res
    out.links = {k: ln for k, ln in g.links.items() if ln.resource in res}
    out.__dict__.pop("_by_resource", None)
    out.__dict__.pop("_by_node", None)
    return out


def _loc(loc: Location) -> dict:
    s, e = loc.span.start, loc.span.end
    return {"file": loc.path, "range": {"start": {"line": s.line, "character": s.col},
                                        "end": {"line": e.line, "character": e.col}},
            "label": loc.label}


def to_json(g: Graph) -> dict:
    """The graph as plain JSON data (see docs/graph.md for the schema)."""
    def counted(d: dict, el) -> dict:
        if el.count is not None or g.products is not None:
            d["count"] = el.count
        return d

    nodes = []
    for n in sorted(g.nodes.values(), key=lambda n: (n.name, n.id)):
        d = {"id": n.id, "name": n.name, "package": n.package, "type": n.type, "namespace": n.namespace,
             "condition": cond_text(n.condition), "hinted": n.hinted, "extracted": n.extracted,
             "locations": [_loc(x) for x in n.locations], "hints": [_loc(x) for x in n.hints]}
        if n.note:
            d["note"] = n.note
        nodes.append(counted(d, n))

    def resources(kind: str) -> list[dict]:
        out = []
        for r in sorted((r for r in g.resources.values() if r.kind == kind), key=lambda r: r.name):
            d = {"id": r.id, "name": r.name, "condition": cond_text(r.condition)}
            if r.dynamic:
                d["dynamic"] = True
            if kind != "parameter" or r.types:
                d["type"] = r.type
                d["types"] = [{"type": t, "condition": cond_text(c)} for t, c in sorted(r.types.items())]
            if kind == "parameter":
                d["value"] = r.value
                d["locations"] = [_loc(x) for x in r.locations]
            out.append(counted(d, r))
        return out

    links = []
    for ln in sorted(g.links.values(), key=lambda x: (g.nodes[x.node].name, x.kind, g.resources[x.resource].name,
                                                     x.id)):
        res = g.resources[ln.resource]
        d = {"id": ln.id, "node": g.nodes[ln.node].name, "node_id": ln.node, "topic": res.name,
             "resource_id": ln.resource, "resource_kind": res.kind, "kind": ln.kind, "type": ln.type,
             "condition": cond_text(ln.condition),
             "via": [{"name": v.name, "type": v.type, "condition": cond_text(v.condition),
                      "hint": _loc(v.hint) if v.hint else None,
                      "remap": _loc(v.remap) if v.remap else None,
                      "source": _loc(v.source) if v.source else None} for v in ln.via]}
        links.append(counted(d, ln))
    out = {"version": SCHEMA_VERSION, "launch": g.launch, "model": g.model, "hints": list(g.hint_sources),
           "decisions": dict(g.decisions)}
    if g.products is not None:
        out["products"] = g.products
    out.update({"nodes": nodes, "topics": resources("topic"), "services": resources("service"),
                "actions": resources("action"), "parameters": resources("parameter"), "links": links,
                "notes": list(g.notes)})
    return out


# ------------------------------------------------------------------ DOT

def _q(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _short(c: str) -> str:
    return c if len(c) <= MAX_LABEL_CONDITION else c[: MAX_LABEL_CONDITION - 1] + "…"


def to_dot(g: Graph, parameters: bool = True) -> str:
    title = os.path.basename(g.launch) or "launch"
    lines = [f"digraph {_q('computation graph of ' + title)} {{",
             '  graph [rankdir=LR, fontname="Helvetica", fontsize=12, labelloc=t, '
             f'label={_q(_title(g))}];',
             '  node [fontname="Helvetica", fontsize=11, penwidth=1.4];',
             '  edge [fontname="Helvetica", fontsize=9];']

    def attrs(kind: str, label: str, cond: Optional[fm.Formula], tip: str) -> str:
        shape = {"node": "box", "topic": "box", "service": "box", "action": "box", "parameter": "box"}[kind]
        style = {"node": "filled", "topic": "rounded,filled", "service": "filled", "action": "rounded,filled",
                 "parameter": "filled"}[kind]
        if cond is not None:
            style += ",dashed"
            label += "\n[" + _short(str(cond)) + "]"
            tip += "\npresent when: " + str(cond)
        else:
            tip += "\npresent in every product" + (" (of these decisions)" if g.decisions else "")
        extra = ', peripheries=2' if kind in ("service", "action") else ""
        return (f"shape={shape}, style={_q(style)}, fillcolor={_q(FILL[kind])}, label={_q(label)}, "
                f"tooltip={_q(tip)}{extra}")

    for n in sorted(g.nodes.values(), key=lambda n: n.name):
        tip = f"ROS node {n.name} ({n.package}/{n.type})" + (f"\n{n.note}" if n.note else "")
        lines.append(f"  {_q(n.id)} [{attrs('node', n.name, n.condition, tip)}];")
    for r in sorted(g.resources.values(), key=lambda r: (r.kind, r.name)):
        if r.kind == "parameter" and not parameters:
            continue
        t = r.type or (" | ".join(sorted(r.types)) if r.types else "?")
        tip = f"{r.kind} {r.name} [{t}]"
        if r.kind == "parameter" and r.value is not None:
            tip += f" = {r.value[:80]}"
        lines.append(f"  {_q(r.id)} [{attrs(r.kind, r.name, r.condition, tip)}];")
    for ln in sorted(g.links.values(), key=lambda x: x.id):
        r = g.resources[ln.resource]
        if r.kind == "parameter" and not parameters:
            continue
        a, b = (ln.node, ln.resource) if ln.kind in OUTGOING else (ln.resource, ln.node)
        ea = []
        tip = f"{g.nodes[ln.node].name} {ln.kind} {r.name}" + (f" [{ln.type}]" if ln.type else "")
        if ln.kind in ("service", "client", "action_server", "action_client"):
            ea.append('arrowhead="dot"' if ln.kind in ("service", "action_server") else 'arrowhead="normal"')
        if ln.condition is not None:
            ea.append('style="dashed"')
            ea.append(f"label={_q(_short(str(ln.condition)))}")
            tip += "\npresent when: " + str(ln.condition)
        ea.append(f"tooltip={_q(tip)}")
        lines.append(f"  {_q(a)} -> {_q(b)} [{', '.join(ea)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _title(g: Graph) -> str:
    t = os.path.basename(g.launch)
    if g.decisions:
        on = [k for k, v in g.decisions.items() if v]
        off = [k for k, v in g.decisions.items() if not v]
        parts = []
        if on:
            parts.append("with " + ", ".join(on))
        if off:
            parts.append("without " + ", ".join(off))
        t += " — " + "; ".join(parts)
    if g.products is not None:
        t += f" ({g.products} product{'s' if g.products != 1 else ''})"
    return t


# ------------------------------------------------------------------ Mermaid

def _m(s: str) -> str:
    """Text inside a quoted Mermaid label: ``&&``, ``||``, ``!`` and parentheses are fine there
    (entity codes such as ``#38;`` are not decoded in every renderer); quotes and angle brackets
    (never in ROS names or feature names, but in hand-written hint types) are replaced."""
    return s.replace('"', "#quot;").replace("<", "‹").replace(">", "›")


def to_mermaid(g: Graph, parameters: bool = True) -> str:
    lines = ["flowchart LR"]
    ids: dict[str, str] = {}

    def mid(key: str, prefix: str) -> str:
        if key not in ids:
            ids[key] = f"{prefix}{sum(1 for v in ids.values() if v.startswith(prefix))}"
        return ids[key]

    conditional: list[str] = []

    def label(name: str, cond: Optional[fm.Formula]) -> str:
        s = _m(name)
        if cond is not None:
            s += "<br/><small>[" + _m(_short(str(cond))) + "]</small>"
        return s

    for n in sorted(g.nodes.values(), key=lambda n: n.name):
        i = mid(n.id, "n")
        lines.append(f'  {i}["{label(n.name, n.condition)}"]:::rosnode')
        if n.condition is not None:
            conditional.append(i)
    shapes = {"topic": ('(["', '"])', "t", "topic"), "service": ('{{"', '"}}', "s", "service"),
              "action": ('[["', '"]]', "a", "action"), "parameter": ('[/"', '"/]', "p", "param")}
    for r in sorted(g.resources.values(), key=lambda r: (r.kind, r.name)):
        if r.kind == "parameter" and not parameters:
            continue
        o, c, pre, cls = shapes[r.kind]
        i = mid(r.id, pre)
        lines.append(f"  {i}{o}{label(r.name, r.condition)}{c}:::{cls}")
        if r.condition is not None:
            conditional.append(i)
    for ln in sorted(g.links.values(), key=lambda x: x.id):
        r = g.resources[ln.resource]
        if r.kind == "parameter" and not parameters:
            continue
        a, b = (ln.node, ln.resource) if ln.kind in OUTGOING else (ln.resource, ln.node)
        if ln.condition is None:
            lines.append(f"  {ids[a]} --> {ids[b]}")
        else:
            lines.append(f'  {ids[a]} -.->|"{_m(_short(str(ln.condition)))}"| {ids[b]}')
    lines += ["  classDef rosnode fill:#ffffff,stroke:#333333,color:#000000",
              "  classDef topic fill:#a3d977,stroke:#333333,color:#000000",
              "  classDef service fill:#8cb8f0,stroke:#333333,color:#000000",
              "  classDef action fill:#f5c08a,stroke:#333333,color:#000000",
              "  classDef param fill:#c9a3e6,stroke:#333333,color:#000000",
              "  classDef conditional stroke-dasharray:5 5"]
    if conditional:
        lines.append(f"  class {','.join(conditional)} conditional")
    return "\n".join(lines) + "\n"
