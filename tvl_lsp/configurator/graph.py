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


    def statuses(self, decisions: Mapping[str, bool], logic) -> dict[str, str]:
        return project(self, decisions_formula(decisions), logic)

    def close(self) -> None:
        pass


# ------------------------------------------------------------------ issue #16's graph

_EDGE_DIRECTION = {"publish": True, "client": True, "write": True, "action_client": True,  # node -> resource
                   "subscribe": False, "service": False, "read": False, "action_server": False}


def _loc16(x: Optional[dict]) -> Optional[dict]:
    if not x or "file" not in x:
        return None
    r = x.get("range") or {}
    s, e = r.get("start") or {}, r.get("end") or {}
    return {"path": x["file"], "line": s.get("line", 0), "col": s.get("character", 0),
            "endLine": e.get("line", s.get("line", 0)), "endCol": e.get("character", s.get("character", 0))}


class PackageGraph:
    """The graph of :mod:`tvl_lsp.graph` (issue #16: topics from the HAROS project's hints, remaps
    under their conditions), in the configurator's shape; projected by that package."""

    source = "tvl_lsp.graph"

    def __init__(self, ctx, to_json, workspace=None):
        self.ctx = ctx
        self._to_json = to_json
        self._all = to_json(ctx.project({}))
        self.workspace = workspace
        # includes tvl-lsp could not follow (a package outside the workspace): placeholders
        self.placeholders: dict[str, tuple[dict, fm.Formula]] = {}
        for fact in _unfollowed(getattr(ctx.analysis, "includes", None) or []):
            el = fact.element
            text = el.attrs["file"].value if "file" in el.attrs else (fact.file or "?")
            pkg = fact.package
            eid = "include:" + (fact.file or text)
            label = (pkg + "/" if pkg else "") + (fact.file or text).replace("\\", "/").rsplit("/", 1)[-1]
            why = (f"package {pkg} is not in the workspace" if pkg and workspace is not None
                   and pkg not in workspace.packages else "tvl-lsp could not follow it")
            if eid in self.placeholders:
                e, c = self.placeholders[eid]
                self.placeholders[eid] = (e, fm.disj([c, fact.condition]))
                continue
            self.placeholders[eid] = ({"id": eid, "kind": "include", "name": text, "label": label,
                                       "location": _loc(el.path, el.span),
                                       "details": {"file": text, "package": pkg,
                                                   "not followed": why + ": the nodes it starts are not shown"}},
                                      fact.condition)

    @staticmethod
    def load(launch_path: str, model_path: Optional[str], workspace, read_file,
             project_files=None) -> Optional["PackageGraph"]:
        try:
            from ..graph import to_json
            from ..project.graph import load_graph
        except ImportError:
            return None
        ctx = load_graph(launch_path, read_file=read_file, workspace=workspace, model=model_path,
                         project_files=project_files)
        return PackageGraph(ctx, to_json, workspace)

    def to_json(self, model_valid=None) -> dict:
        j = self._all
        els: list[dict] = []
        for n in j.get("nodes", []):
            det = {"package": n.get("package"), "type": n.get("type"), "namespace": n.get("namespace")}
            if n.get("note"):
                det["note"] = n["note"]
            if n.get("hints"):
                det["hints"] = ", ".join(f"{h.get('label', '')}" for h in n["hints"] if h)
            label = n["name"].rsplit("/", 1)[-1] or n["name"]
            if "#" in n["id"]:  # one name, nodes of several types (in different products): say which
                label += f" ({n.get('type')})"
            els.append({"id": n["id"], "kind": "node", "name": n["name"], "label": label,
                        "condition": n.get("condition"), "location": _loc16((n.get("locations") or [None])[0]),
                        "details": det})
        for key, kind in (("topics", "topic"), ("services", "service"), ("actions", "action"), ("parameters", "param")):
            for r in j.get(key, []):
                det = {}
                if r.get("type"):
                    det["type"] = r["type"]
                elif r.get("types"):
                    det["types"] = ", ".join(f"{t['type']} when {t['condition'] or 'always'}" for t in r["types"])
                if "value" in r and r["value"] is not None:
                    det["value"] = r["value"]
                if r.get("dynamic"):
                    det["dynamic"] = "computed at run time: {…} stands for what is not known before"
                els.append({"id": r["id"], "kind": kind, "name": r["name"], "label": r["name"],
                            "condition": r.get("condition"),
                            "location": _loc16((r.get("locations") or [None])[0]), "details": det})
        edges = []
        for ln in j.get("links", []):
            out = _EDGE_DIRECTION.get(ln["kind"], True)
            via = (ln.get("via") or [None])[0] or {}
            loc = _loc16(via.get("remap")) or _loc16(via.get("hint")) or _loc16(via.get("source"))
            edges.append({"id": ln["id"], "source": ln["node_id"] if out else ln["resource_id"],
                          "target": ln["resource_id"] if out else ln["node_id"], "kind": ln["kind"],
                          "condition": ln.get("condition"), "location": loc})
        for eid, (e, c) in self.placeholders.items():
            valid = c == fm.TRUE or (model_valid is not None and model_valid(c))
            els.append(dict(e, condition=None if valid else str(c)))
        out = {"elements": els, "edges": edges, "source": self.source, "notes": j.get("notes", [])}
        if not j.get("topics") and not j.get("services") and j.get("nodes"):
            out["noTopics"] = self.no_topics_hint(j)
        return out

    def no_topics_hint(self, j: dict) -> dict:
        """What would add topics to a graph that has none: node hints for these node types, or
        their packages' sources in the workspace."""
        types = sorted({f"{n.get('package')}/{n.get('type')}" for n in j.get("nodes", []) if not n.get("hinted")})
        pkgs = sorted({n.get("package") for n in j.get("nodes", []) if n.get("package")})
        here = [x for x in pkgs if self.workspace is not None and x in self.workspace.packages]
        away = [x for x in pkgs if x not in here]
        return {"types": types, "sourcesHere": here, "sourcesAway": away,
                "projectFiles": list(j.get("hints") or [])}

    @property
    def ids(self) -> list[str]:
        j = self._all
        return ([x["id"] for x in j.get("nodes", [])] + [x["id"] for k in ("topics", "services", "actions", "parameters")
                                                         for x in j.get(k, [])] + [x["id"] for x in j.get("links", [])])

    def statuses(self, decisions: Mapping[str, bool], logic=None) -> dict[str, str]:
        j = self._to_json(self.ctx.project(dict(decisions)))
        present = {x["id"]: x.get("condition") for k in ("nodes", "topics", "services", "actions", "parameters", "links")
                   for x in j.get(k, [])}
        out = {i: ("absent" if i not in present else "certain" if present[i] is None else "possible")
               for i in self.ids}
        if self.placeholders and logic is not None:
            decided = decisions_formula(decisions)
            for eid, (_, c) in self.placeholders.items():
                out[eid] = _status(c, decided, logic)
        return out

    def close(self) -> None:
        self.ctx.close()


def build(launch, model_path: Optional[str] = None, workspace=None, read_file=None, project_files=None):
    """The graph of every product of the analysed launch file ``launch`` (a LaunchAnalysis):
    issue #16's when :mod:`tvl_lsp.graph` is installed (node hints from ``project_files``, else
    from the workspace's HAROS project files), else the interim one."""
    try:
        got = PackageGraph.load(launch.path, model_path, workspace, read_file, project_files)
    except Exception:  # the interim graph rather than none
        got = None
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


def _status(cond: fm.Formula, decided: fm.Formula, logic) -> str:
    if not logic.sat(fm.conj([decided, cond])):
        return "absent"
    if not logic.sat(fm.conj([decided, fm.neg(cond)])):
        return "certain"
    return "possible"


def _unfollowed(facts) -> list:
    """The include facts (at any depth) tvl-lsp did not follow."""
    out, todo = [], list(facts)
    while todo:
        f = todo.pop(0)
        if not f.followed and f.condition != fm.FALSE:
            out.append(f)
        todo.extend(f.children)
    return out


def project(graph: Graph, decided: fm.Formula, logic) -> dict[str, str]:
    """{element or edge id: certain | possible | absent} under the decisions (``decided``: their
    conjunction as a formula; ``logic``: a PairLogic over the model)."""
    return {eid: _status(cond, decided, logic) for eid, cond in graph.conditions.items()}


def decisions_formula(decisions: Mapping[str, bool]) -> fm.Formula:
    return fm.conj([fm.var(k) if v else fm.neg(fm.var(k)) for k, v in decisions.items()])
