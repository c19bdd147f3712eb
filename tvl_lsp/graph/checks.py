"""Variability-aware checks of the computation graph: one finding per problem, each with the
smallest product in which it shows (a *witness*) and the ``<node>`` tags, hint entries and
``<remap>`` tags involved as related locations.

    graph_diagnostics(graph, logic, analysis=None, model_name=None) -> list[Diagnostic]

- ``topic-without-publisher`` (warning): a topic some node subscribes to in a product where no
  node publishes it;
- ``topic-without-subscriber`` (information): a topic published in a product where no node
  subscribes to it;
- ``topic-type-mismatch`` (warning): two message types on one topic (or two service types on
  one service) in one product;
- ``remap-unused`` (warning): a ``<remap>`` whose ``from`` is no name the nodes it applies to use,
  in a product where it applies to some node.

"Some product where" is a SAT question over the model and the presence conditions (the
cross-check's PairLogic); the witness is the product with the fewest selected features.
What a node uses is known from its sources (:mod:`tvl_lsp.graph.sources`) or its hints; nodes
known from neither use unknown names: a product where such a node is loaded still gets a
finding about a topic nobody *known* publishes, with the unknown nodes named in the message;
a name computed at run time (dynamic) may be any topic that matches it, so it counts as the
other side of every such topic, and no finding is about a dynamic name itself;
``remap-unused`` is only reported where what every node the remap applies to uses is known.
Findings link to the calls in the sources (and to the hint entries) as related locations.
Findings are anchored in the analysed launch file: on the ``<node>`` / ``<remap>`` tag, or on
the ``<include>`` that loads the file where it is (related: the tag itself).
"""

from __future__ import annotations

import os
from typing import Optional

from ..base import formula as fm
from ..base.diagnostics import Diagnostic, Related, Severity, register
from .model import Graph, Link, Location
from .logic import GraphLogic
from .project import _simplifier, graph_variables

TOPIC_WITHOUT_PUBLISHER = register(
    "topic-without-publisher", Severity.WARNING,
    "A topic is subscribed to in some product where no node publishes it.", "graph")
TOPIC_WITHOUT_SUBSCRIBER = register(
    "topic-without-subscriber", Severity.INFORMATION,
    "A topic is published in some product where no node subscribes to it.", "graph")
TOPIC_TYPE_MISMATCH = register(
    "topic-type-mismatch", Severity.WARNING,
    "Two message types are used on one topic (or two service types on one service) in some product.", "graph")
REMAP_UNUSED = register(
    "remap-unused", Severity.WARNING,
    "A <remap> whose `from` matches no name the nodes it applies to use, in some product.", "graph")

MAX_COND_TEXT = 160
VERBS = {"publish": "publishes", "subscribe": "subscribes to", "service": "provides", "client": "calls",
         "read": "reads", "write": "writes"}
MAX_RELATED = 12


def _cond_text(f: fm.Formula) -> str:
    s = str(f)
    return s if len(s) <= MAX_COND_TEXT else s[: MAX_COND_TEXT - 1] + "…"


def _selected(w: dict[str, bool]) -> str:
    on = [k for k, v in w.items() if v]
    return "{" + ", ".join(on) + "}" if on else "{} (nothing selected)"


def _when(cond: fm.Formula, w: dict[str, bool]) -> str:
    if cond == fm.TRUE:
        return " (in every product)"
    return f" (when {_cond_text(cond)}; e.g. in the product {_selected(w)})"


def _names(xs: list[str], limit: int = 4) -> str:
    xs = list(dict.fromkeys(xs))
    s = ", ".join(xs[:limit])
    return s + (f" and {len(xs) - limit} more" if len(xs) > limit else "")


class _Ctx:
    def __init__(self, graph: Graph, logic: GraphLogic, analysis=None):
        self.g = graph
        self.logic = logic
        self.o = logic.oracle(graph_variables(graph))
        self.launch = graph.launch
        self.simp = _simplifier(self.o, self.o.term(fm.TRUE))
        self.anchor = None
        self._unhinted = None
        if analysis is not None:
            from ..analysis.crosscheck import _include_anchors
            self.anchor = _include_anchors(analysis)

    def find(self, cond: fm.Formula) -> Optional[dict[str, bool]]:
        """The smallest product where ``cond`` holds (None: no product)."""
        if cond == fm.FALSE:
            return None
        t = self.o.term(cond)
        if self.o.empty(t):
            return None
        return self.o.witness(t, cond)

    def holds(self, f: Optional[fm.Formula], w: dict[str, bool]) -> bool:
        return f is None or fm.evaluate(f, w)

    def place(self, loc: Location, w) -> Optional[tuple[str, object, list[Related]]]:
        """(path, span, extra related) in the analysed file for a location anywhere."""
        if loc.path == self.launch:
            return loc.path, loc.span, []
        if self.anchor is None:
            return None
        inc = self.anchor(loc.path, w)
        if inc is None:
            return None
        return self.launch, inc.span, [Related(loc.path, loc.span, f"{loc.label}, in the included file "
                                                                   f"{os.path.basename(loc.path)}")]

    def node_loc(self, node_id: str, w) -> Optional[Location]:
        n = self.g.nodes[node_id]
        for loc, c in n.occurrences:
            if fm.evaluate(c, w):
                return loc
        return n.locations[0] if n.locations else None

    def link_related(self, links: list[Link], w, what: str) -> list[Related]:
        out: list[Related] = []
        for ln in links:
            if not self.holds(ln.condition, w):
                continue
            n = self.g.nodes[ln.node]
            loc = self.node_loc(ln.node, w)
            if loc is not None:
                out.append(Related(loc.path, loc.span, f"{n.name} {what}"))
            for v in ln.via:
                if not self.holds(v.condition, w):
                    continue
                if v.hint is not None:
                    out.append(Related(v.hint.path, v.hint.span, f"hint: {n.package}/{n.type} {VERBS[ln.kind]} "
                                                                 f"`{v.name}`" + (f" [{v.type}]" if v.type else "")))
                if v.source is not None:
                    out.append(Related(v.source.path, v.source.span,
                                       f"{n.package}/{n.type} {VERBS[ln.kind]} `{v.name}`"
                                       + (f" [{v.type}]" if v.type else "") + " here"))
                if v.remap is not None:
                    out.append(Related(v.remap.path, v.remap.span,
                                       f"{v.remap.label} makes `{v.name}` {self.g.resources[ln.resource].name}"))
        return out

    def unhinted_under(self, cond: fm.Formula) -> list[str]:
        """The nodes without hints (their endpoints unknown) that run in some product where
        ``cond`` holds: what a finding over ``cond`` cannot rule out, not only in its witness."""
        if self._unhinted is None:
            self._unhinted = [n for n in self.g.nodes.values() if not n.known and n.condition is not None]
        return sorted(n.name for n in self._unhinted
                      if not self.o.empty(self.o.term(fm.conj([cond, n.condition]))))

    def diag(self, code: str, sev: Severity, anchor_loc: Optional[Location], w, message: str,
             related: list[Related], data: dict) -> Optional[Diagnostic]:
        if anchor_loc is None:
            return None
        placed = self.place(anchor_loc, w)
        if placed is None:
            return None
        path, span, extra = placed
        rel = list(dict.fromkeys(extra + related))[:MAX_RELATED]
        return Diagnostic(code, sev, path, span, message, rel, witness=w, data=data)


def _missing_side(ctx: _Ctx, code: str, have_kind: str, lack_kind: str) -> list[Diagnostic]:
    out = []
    g = ctx.g
    verb = {"subscribe": "subscribes to", "publish": "publishes"}
    dyn_lack = [(ln, _dyn_pattern(g.resources[ln.resource].name)) for t in g.topics() if t.dynamic
                for ln in g.links_of(t.id, (lack_kind,))]
    for r in sorted(g.topics(), key=lambda r: r.name):
        if r.dynamic:
            continue  # its run-time name is unknown: nothing to say
        have = g.links_of(r.id, (have_kind,))
        if not have:
            continue
        # a name computed at run time may be this one: it counts as the other side
        lack = g.links_of(r.id, (lack_kind,)) + [ln for ln, rx in dyn_lack if rx.match(r.name)]
        cond = fm.conj([fm.disj(ln.condition for ln in have), fm.neg(fm.disj(ln.condition for ln in lack))])
        w = ctx.find(cond)
        if w is None:
            continue
        shown = ctx.simp(cond)
        users = [ln for ln in have if ctx.holds(ln.condition, w)]
        who = _names([g.nodes[ln.node].name for ln in users])
        if code == TOPIC_WITHOUT_PUBLISHER:
            msg = f"topic {r.name} is subscribed to by {who} but no node publishes it"
        else:
            msg = f"topic {r.name} is published by {who} but no node subscribes to it"
        msg += _when(shown, w)
        elsewhere = [g.nodes[ln.node].name for ln in lack]
        if elsewhere:
            msg += f"; it has {'publishers' if lack_kind == 'publish' else 'subscribers'} only in other " \
                   f"products: {_names(elsewhere)}"
        unknown = ctx.unhinted_under(cond)
        if unknown:
            msg += (f" (unless a node without hints does: {_names(unknown)} — their sources are not in the "
                    "workspace: add their hints to the HAROS project file)")
        related = ctx.link_related(users, w, f"{'subscribes to' if have_kind == 'subscribe' else 'publishes'} "
                                             f"{r.name}")
        for ln in lack:
            n = g.nodes[ln.node]
            loc = n.locations[0] if n.locations else None
            if loc is not None:
                related.append(Related(loc.path, loc.span, f"{n.name}: {verb[lack_kind]} {r.name} in other products"))
        anchor = ctx.node_loc(users[0].node, w) if users else None
        d = ctx.diag(code, Severity.WARNING if code == TOPIC_WITHOUT_PUBLISHER else Severity.INFORMATION,
                     anchor, w, msg, related, {"topic": r.name, "condition": str(cond)})
        if d is not None:
            out.append(d)
    return out


def _dyn_pattern(name: str):
    import re
    parts = re.split(r"(\{[^{}]*\})", name)
    return re.compile("^" + "".join(".+" if p.startswith("{") else re.escape(p) for p in parts) + "$")


def _type_mismatch(ctx: _Ctx) -> list[Diagnostic]:
    out = []
    g = ctx.g
    for r in sorted(list(g.topics()) + list(g.services()), key=lambda r: (r.kind, r.name)):
        if len(r.types) < 2 or r.dynamic:
            continue
        types = sorted(r.types)
        found = None
        for i, t1 in enumerate(types):
            for t2 in types[i + 1:]:
                c = fm.conj([r.types[t1] or fm.TRUE, r.types[t2] or fm.TRUE])
                if c != fm.FALSE and not ctx.o.empty(ctx.o.term(c)):
                    found = (t1, t2, c)
                    break
            if found:
                break
        if found is None:
            continue
        t1, t2, c = found
        w = ctx.find(c)
        if w is None:
            continue
        links = [ln for ln in g.links_of(r.id) if ctx.holds(ln.condition, w) and ln.type]
        by_type: dict[str, list[str]] = {}
        for ln in links:
            by_type.setdefault(ln.type, []).append(f"{g.nodes[ln.node].name} ({ln.kind})")
        parts = [f"{t} by {_names(by_type.get(t, []), 3)}" for t in sorted(by_type)]
        what = "message" if r.kind == "topic" else "service"
        msg = (f"{r.kind} {r.name} is used with {len(by_type)} {what} types: " + "; ".join(parts)
               + ": ROS refuses connections between them" + _when(ctx.simp(c), w))
        anchor_link = next((ln for ln in links if ln.type == t1), links[0] if links else None)
        anchor = ctx.node_loc(anchor_link.node, w) if anchor_link else None
        related = ctx.link_related(links, w, f"uses {r.name}")
        d = ctx.diag(TOPIC_TYPE_MISMATCH, Severity.WARNING, anchor, w, msg, related,
                     {"topic": r.name, "types": sorted(by_type), "condition": str(c)})
        if d is not None:
            out.append(d)
    return out


def _remap_unused(ctx: _Ctx) -> list[Diagnostic]:
    out = []
    g = ctx.g
    for loc, uses in sorted(g.remap_uses.items(), key=lambda kv: (kv[0].path, kv[0].span)):
        if not any(u.hinted for u in uses):
            continue
        applies = fm.disj(u.condition for u in uses)
        used = fm.disj(u.condition for u in uses if u.used)
        unknown = fm.disj(u.condition for u in uses if not u.hinted)
        cond = fm.conj([applies, fm.neg(used), fm.neg(unknown)])
        w = ctx.find(cond)
        if w is None:
            continue
        here = [u for u in uses if fm.evaluate(u.condition, w)]
        nodes = [g.nodes[u.node] for u in here]
        frm = here[0].from_ if here else ""
        uses_text = []
        for n in nodes:
            names = sorted({v.name for ln in g.links_from(n.id) for v in ln.via})
            uses_text.append(f"{n.name} uses " + (", ".join(f"`{x}`" for x in names[:6]) if names else "no names"))
        msg = (f"{loc.label} changes nothing: no node it applies to uses {frm} — "
               + "; ".join(uses_text[:4]) + _when(ctx.simp(cond), w))
        related = []
        for n in nodes:
            nl = ctx.node_loc(n.id, w)
            if nl is not None:
                related.append(Related(nl.path, nl.span, f"{n.name}: the remap applies to it"))
            for h in n.hints:
                related.append(Related(h.path, h.span, f"the names {n.package}/{n.type} uses"))
        d = ctx.diag(REMAP_UNUSED, Severity.WARNING, loc, w, msg, related,
                     {"from": frm, "condition": str(cond)})
        if d is not None:
            out.append(d)
    return out


def graph_diagnostics(graph: Graph, logic: GraphLogic, analysis=None) -> list[Diagnostic]:
    """The graph checks of one launch file (``graph``: built from ``analysis``, not projected)."""
    if not any(n.known for n in graph.nodes.values()):
        return []
    ctx = _Ctx(graph, logic, analysis)
    out: list[Diagnostic] = []
    out += _missing_side(ctx, TOPIC_WITHOUT_PUBLISHER, "subscribe", "publish")
    out += _missing_side(ctx, TOPIC_WITHOUT_SUBSCRIBER, "publish", "subscribe")
    out += _type_mismatch(ctx)
    out += _remap_unused(ctx)
    return out
