"""The computation graph the configurator draws, and its projection under decisions.

:func:`build` makes the graph of *all* products of a generic launch file (the UI lays it out
once, from this); :func:`project` says, for the decisions, which of its elements every remaining
product has (``certain``: drawn solid), some have (``possible``: dashed) or none has
(``absent``: hidden) -- so a click changes styles, never positions.

The graph comes from :mod:`tvl_lsp.graph` (issue #16: topics from the HAROS project's hints,
remaps applied under their conditions) when that package is installed; until then an interim
graph is built from the launch analysis itself: the ROS nodes, the parameters, and the topics
that remaps name (a ``uses`` link: the launch file says which name a node's topic gets, not
whether it publishes or subscribes).

JSON shape (plain dicts)::

    {"elements": [{id, kind: node|topic|param|service, name, label, condition (text|None),
                   location: {path, line, col, endLine, endCol} | None, details: {...}}],
     "edges": [{id, source, target, kind: publish|subscribe|service|client|uses|reads,
                condition, location}],
     "source": "tvl_lsp.graph" | "launch"}
"""

from __future__ import annotations

from typing import Mapping, Optional

from ..base import formula as fm


def _loc(path: str, span) -> Optional[dict]:
    if span is None:
        return None
    return {"path": path, "line": span.start.line, "col": span.start.col,
            "endLine": span.end.line, "endCol": span.end.col}


def _resolve(name: str, ns: str, node: str) -> str:
    if name.startswith("/"):
        return name
    if name.startswith("~"):
        return node.rstrip("/") + "/" + name[1:].lstrip("/")
    return (ns.rstrip("/") + "/" + name) if ns else "/" + name


class Graph:
    """The all-products graph with each element's condition as a formula."""

    def __init__(self):
        self.elements: dict[str, dict] = {}
        self.edges: dict[str, dict] = {}
        self.conditions: dict[str, fm.Formula] = {}
        self.source = "launch"

    def add(self, eid: str, cond: fm.Formula, **data) -> dict:
        if eid in self.elements:
            self.conditions[eid] = fm.disj([self.conditions[eid], cond])
            return self.elements[eid]
        self.elements[eid] = dict(id=eid, **data)
        self.conditions[eid] = cond
        return self.elements[eid]

    def link(self, eid: str, source: str, target: str, kind: str, cond: fm.Formula, location=None) -> None:
        if eid in self.edges:
            self.conditions[eid] = fm.disj([self.conditions[eid], cond])
            return
        self.edges[eid] = {"id": eid, "source": source, "target": target, "kind": kind, "location": location}
        self.conditions[eid] = cond

    def to_json(self, model_valid=None) -> dict:
        """``model_valid(formula) -> bool``: does the formula hold in every product? (Those
        elements get ``condition: None``: present in every product, drawn solid.)"""
        def cond_text(eid: str) -> Optional[str]:
            c = self.conditions[eid]
            if c == fm.TRUE or (model_valid is not None and model_valid(c)):
                return None
            return str(c)
        els = []
        for k, e in self.elements.items():
            e = dict(e, condition=cond_text(k))
            variants = e.pop("variants", None)
            if variants and len(variants) > 1:
                e["details"] = dict(e["details"], variants=variants)
            els.append(e)
        eds = [dict(e, condition=cond_text(k)) for k, e in self.edges.items()]
        return {"elements": els, "edges": eds, "source": self.source}


def _from_graph_package(launch, model_path, workspace):  # pragma: no cover - until #16 lands
    try:
        from .. import graph as g  # noqa: F401  (issue #16)
    except ImportError:
        return None
    return None  # adapter written when the package's API is on main


def build(launch, model_path: Optional[str] = None, workspace=None) -> Graph:
    """The graph of every product of the analysed launch file ``launch`` (a LaunchAnalysis)."""
    got = _from_graph_package(launch, model_path, workspace)
    if got is not None:
        return got
    g = Graph()
    for n in launch.nodes:
        if n.is_test:
            continue
        nid = "node:" + n.name
        known = nid in g.elements
        e = g.add(nid, n.condition, kind="node", name=n.name, label=n.name.rsplit("/", 1)[-1] or n.name,
                  location=_loc(n.element.path, n.element.span),
                  details={"package": n.pkg, "type": n.type, "namespace": n.namespace, "remaps": []})
        # one name, several <node> tags (e.g. one driver per feature): list every variant
        variant = {"package": n.pkg, "type": n.type, "condition": str(n.condition),
                   "location": _loc(n.element.path, n.element.span)}
        e.setdefault("variants", [])
        if not known or variant not in e["variants"]:
            e["variants"].append(variant)
        for child in n.element.children:
            if child.tag != "remap" or "from" not in child.attrs or "to" not in child.attrs:
                continue
            src, dst = child.attrs["from"].value, child.attrs["to"].value
            topic = _resolve(dst, n.namespace, n.name)
            e["details"]["remaps"].append({"from": src, "to": dst, "condition": str(child.condition),
                                           "location": _loc(child.path, child.span)})
            tid = "topic:" + topic
            g.add(tid, child.condition, kind="topic", name=topic, label=topic, location=None,
                  details={"remapped from": src})
            g.link(f"edge:{nid}->{tid}", nid, tid, "uses", child.condition, _loc(child.path, child.span))
    for p in launch.params:
        pid = "param:" + p.name
        g.add(pid, p.condition, kind="param", name=p.name, label=p.name, location=_loc(p.element.path, p.element.span),
              details={"value": p.value})
    return g


def project(graph: Graph, decided: fm.Formula, logic) -> dict[str, str]:
    """{element or edge id: certain | possible | absent} under the decisions (``decided``: their
    conjunction as a formula; ``logic``: a PairLogic over the model)."""
    out: dict[str, str] = {}
    for eid, cond in graph.conditions.items():
        if not logic.sat(fm.conj([decided, cond])):
            out[eid] = "absent"
        elif not logic.sat(fm.conj([decided, fm.neg(cond)])):
            out[eid] = "certain"
        else:
            out[eid] = "possible"
    return out


def decisions_formula(decisions: Mapping[str, bool]) -> fm.Formula:
    return fm.conj([fm.var(k) if v else fm.neg(fm.var(k)) for k, v in decisions.items()])
