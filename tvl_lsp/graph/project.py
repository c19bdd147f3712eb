"""Projection: the graph of the products that remain under some decisions.

    logic = GraphLogic(encoding, free_names, analysis)   # the model (or None) and free args
    g2 = project(graph, logic, {"Teleop": True, "Random": False}, count=True)

Every element's presence condition is specialised to the decisions (and the features they
force, and the model): an element no remaining product has is dropped; one every remaining
product has gets the condition ``None`` (drawn solid); the others keep a simplified condition
(drawn dashed).  With every feature decided, the result is exactly that product's graph.

The questions go to an oracle of :class:`~tvl_lsp.graph.logic.GraphLogic` (a product table
when the products are few enough to list, the SAT service otherwise); counts are exact (the
table, or :meth:`tvl_lsp.analysis.engine.ModelAnalysis.count`).
"""

from __future__ import annotations

import copy
import dataclasses
from typing import Mapping, Optional

from ..base import formula as fm
from .logic import GraphLogic, Oracle
from .model import Graph

MAX_SIMPLIFY_SIZE = 40


class NoProducts(Exception):
    """No product satisfies the decisions (``conflict``: a minimal set of them, when known)."""

    def __init__(self, message: str, conflict: Optional[list[str]] = None):
        super().__init__(message)
        self.conflict = conflict


class UnknownFeature(ValueError):
    pass


def nnf(f: fm.Formula, positive: bool = True) -> fm.Formula:
    """Negation normal form (negations on variables only)."""
    if isinstance(f, fm.Const):
        return f if positive else fm.neg(f)
    if isinstance(f, fm.Var):
        return f if positive else fm.Not(f)
    if isinstance(f, fm.Not):
        return nnf(f.arg, not positive)
    args = [nnf(a, positive) for a in f.args]
    if isinstance(f, fm.And):
        return fm.conj(args) if positive else fm.disj(args)
    return fm.disj(args) if positive else fm.conj(args)


def _size(f: fm.Formula) -> int:
    if isinstance(f, (fm.And, fm.Or)):
        return 1 + sum(_size(a) for a in f.args)
    if isinstance(f, fm.Not):
        return 1 + _size(f.arg)
    return 1


def _simplifier(o: Oracle, base):
    """Simplify formulas relative to the term ``base`` (the decisions; the model is in the
    oracle), for display: in negation normal form, a literal the context decides becomes a
    constant, a conjunct the others imply and a disjunct that implies the others go.  Bounded:
    large formulas are returned as they are."""
    cache: dict[fm.Formula, fm.Formula] = {}
    T, AND, NOT, EMPTY = o.term, o.and_, o.not_, o.empty

    def go(f: fm.Formula, ctx) -> fm.Formula:
        if isinstance(f, fm.Const):
            return f
        if isinstance(f, (fm.Var, fm.Not)):
            t = T(f)
            if EMPTY(AND(ctx, t)):
                return fm.FALSE
            if EMPTY(AND(ctx, NOT(t))):
                return fm.TRUE
            return f
        args = list(f.args)
        if isinstance(f, fm.And):
            for _ in range(2):
                for i in range(len(args)):
                    args[i] = go(args[i], AND(ctx, T(fm.conj(args[:i] + args[i + 1:]))))
                g = fm.conj(args)
                if not isinstance(g, fm.And):
                    return g
                args = list(g.args)
            i = 0
            while i < len(args) and len(args) > 1:
                rest = T(fm.conj(args[:i] + args[i + 1:]))
                if EMPTY(AND(AND(ctx, rest), NOT(T(args[i])))):
                    del args[i]
                else:
                    i += 1
            return fm.conj(args)
        for i in range(len(args)):
            args[i] = go(args[i], AND(ctx, NOT(T(fm.disj(args[:i] + args[i + 1:])))))
        g = fm.disj(args)
        if not isinstance(g, fm.Or):
            return g
        args = list(g.args)
        i = 0
        while i < len(args) and len(args) > 1:
            rest = T(fm.disj(args[:i] + args[i + 1:]))
            if EMPTY(AND(AND(ctx, T(args[i])), NOT(rest))):
                del args[i]
            else:
                i += 1
        return fm.disj(args)

    def simplify(f: fm.Formula) -> fm.Formula:
        if isinstance(f, (fm.Var, fm.Const)):
            return f
        hit = cache.get(f)
        if hit is None:
            g = nnf(f)
            hit = go(g, base) if _size(g) <= MAX_SIMPLIFY_SIZE else f
            if _size(hit) > _size(f):
                hit = f
            cache[f] = hit
        return hit
    return simplify


def graph_variables(graph: Graph) -> set[str]:
    used: set[str] = set()
    for el in list(graph.nodes.values()) + list(graph.resources.values()) + list(graph.links.values()):
        if el.condition is not None:
            used |= fm.variables(el.condition)
    for uses in graph.remap_uses.values():
        for u in uses:
            used |= fm.variables(u.condition)
    return used


def check_known(logic: GraphLogic, decisions: Mapping[str, bool]) -> None:
    """Raises UnknownFeature for a decision about a name that is no feature (nor free arg)."""
    unknown = [k for k in decisions if not logic.known(k)]
    if unknown:
        import difflib
        names = logic.names()
        parts = []
        for k in unknown:
            m = difflib.get_close_matches(k, names, n=1)
            parts.append(f"`{k}`" + (f" (did you mean `{m[0]}`?)" if m else ""))
        raise UnknownFeature("unknown feature " + ", ".join(parts))


def check_decisions(logic: GraphLogic, decisions: Mapping[str, bool], o: Optional[Oracle] = None) -> Oracle:
    """The oracle for these decisions; raises UnknownFeature / NoProducts."""
    check_known(logic, decisions)
    o = o or logic.oracle(decisions)
    if o.empty(o.term(logic.decision_formula(decisions))):
        if not decisions:
            raise NoProducts("the model has no product (it is void: tvl-lsp --check explains why)")
        conflict = None
        if logic.analysis is not None and all(logic.is_feature(k) for k in decisions):
            try:
                conflict = logic.analysis.propagate(dict(decisions), count=False).conflict
            except Exception:
                conflict = None
        what = ", ".join(conflict) if conflict else ", ".join(
            ("" if v else "!") + k for k, v in decisions.items())
        raise NoProducts(f"no product satisfies these decisions (conflict: {what})", conflict)
    return o


def project(graph: Graph, logic: GraphLogic, decisions: Optional[Mapping[str, bool]] = None,
            count: bool = False, simplify: bool = True, count_timeout: Optional[float] = 10.0) -> Graph:
    """The graph of the products that satisfy ``decisions`` (feature / free arg -> selected).
    Raises :class:`UnknownFeature` or :class:`NoProducts`."""
    decisions = dict(decisions or {})
    used = graph_variables(graph)
    check_known(logic, decisions)
    logic.count_timeout = count_timeout
    o = logic.oracle(used | set(decisions))
    check_decisions(logic, decisions, o)
    d = logic.decision_formula(decisions)
    dt = o.term(d)
    # the names every remaining product gives the same value
    env: dict[str, fm.Formula] = {k: (fm.TRUE if v else fm.FALSE) for k, v in decisions.items()}
    for v in sorted(used - set(decisions)):
        t = o.term(fm.Var(v))
        if o.empty(o.and_(dt, t)):
            env[v] = fm.FALSE
        elif o.empty(o.and_(dt, o.not_(t))):
            env[v] = fm.TRUE
    simp = _simplifier(o, dt) if simplify else (lambda f: f)
    memo: dict[fm.Formula, object] = {}
    GONE = object()

    def spec(f: Optional[fm.Formula]):
        if f is None:
            return None
        if f in memo:
            return memo[f]
        g = fm.substitute(f, env)
        if g == fm.FALSE:
            out = GONE
        elif g == fm.TRUE:
            out = None
        else:
            t = o.term(g)
            if o.empty(o.and_(dt, t)):
                out = GONE
            elif o.empty(o.and_(dt, o.not_(t))):
                out = None
            else:
                out = simp(g)
        memo[f] = out
        return out

    out = Graph(launch=graph.launch, notes=list(graph.notes), hint_sources=list(graph.hint_sources),
                decisions=dict(decisions), model=graph.model)
    for nid, n in graph.nodes.items():
        c = spec(n.condition)
        if c is GONE:
            continue
        m = copy.copy(n)
        m.condition = c
        out.nodes[nid] = m
    for rid, r in graph.resources.items():
        c = spec(r.condition)
        if c is GONE:
            continue
        m = copy.copy(r)
        m.condition = c
        m.types = {}
        for t, tc in r.types.items():
            s = spec(tc)
            if s is not GONE:
                m.types[t] = s
        out.resources[rid] = m
    for lid, ln in graph.links.items():
        c = spec(ln.condition)
        if c is GONE or ln.node not in out.nodes or ln.resource not in out.resources:
            continue
        m = copy.copy(ln)
        m.condition = c
        m.via = [dataclasses.replace(v, condition=spec(v.condition)) for v in ln.via
                 if spec(v.condition) is not GONE]
        out.links[lid] = m
    for loc, uses in graph.remap_uses.items():
        kept = [u for u in uses if spec(u.condition) is not GONE]
        if kept:
            out.remap_uses[loc] = kept
    if count:
        counted: dict = {}

        def how_many(c: Optional[fm.Formula]) -> Optional[int]:
            f = fm.conj([d, c]) if c is not None else d
            if f not in counted:
                counted[f] = o.count(o.term(f), f)
            return counted[f]
        out.products = how_many(None)
        for el in list(out.nodes.values()) + list(out.resources.values()) + list(out.links.values()):
            el.count = out.products if el.condition is None else how_many(el.condition)
    return out
