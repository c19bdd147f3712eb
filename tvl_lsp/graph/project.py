"""Projection: the graph of the products that remain under some decisions.

    logic = GraphLogic(encoding, free_names, analysis)   # the model (or None) and free args
    g2 = project(graph, logic, {"Teleop": True, "Random": False}, count=True)

Every element's presence condition is specialised to the decisions (and the features they
force, and the model): an element no remaining product has is dropped; one every remaining
product has gets the condition ``None`` (drawn solid); the others keep a simplified condition
(drawn dashed).  With every feature decided, the result is exactly that product's graph.

The SAT questions go to the SAT service, :class:`~tvl_lsp.analysis.solve.PairLogic`
(the model's CNF plus Tseitin-encoded conditions); counts to
:meth:`tvl_lsp.analysis.engine.ModelAnalysis.count` (exact, cached).
"""

from __future__ import annotations

import copy
import dataclasses
import itertools
from typing import Iterable, Mapping, Optional

from ..base import formula as fm
from ..analysis.solve import PairLogic
from .model import Graph

MAX_SIMPLIFY_SIZE = 40
MAX_BRUTE_VARS = 20


class NoProducts(Exception):
    """No product satisfies the decisions (``conflict``: a minimal set of them, when known)."""

    def __init__(self, message: str, conflict: Optional[list[str]] = None):
        super().__init__(message)
        self.conflict = conflict


class UnknownFeature(ValueError):
    pass


class GraphLogic:
    """The products a graph is about: a model's (``encoding``; None: no model, every name a
    free boolean) with the launch file's other free args (``free_names``)."""

    def __init__(self, encoding=None, free_names: Iterable[str] = (), analysis=None):
        self.enc = encoding
        self.analysis = analysis
        self.free = [n for n in free_names if encoding is None or encoding.feature_by_name(n) is None]
        self.pair = PairLogic(encoding, self.free)

    def close(self) -> None:
        self.pair.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def is_feature(self, name: str) -> bool:
        return self.enc is not None and self.enc.feature_by_name(name) is not None

    def known(self, name: str) -> bool:
        return self.is_feature(name) or name in self.free

    def names(self) -> list[str]:
        """Every name a decision can be about."""
        out = [self.enc.name_of(f) for f in self.enc.features] if self.enc is not None else []
        return out + list(self.free)

    def decision_formula(self, decisions: Mapping[str, bool]) -> fm.Formula:
        return fm.conj(fm.Var(k) if v else fm.neg(fm.Var(k)) for k, v in decisions.items())

    def sat(self, f: fm.Formula) -> bool:
        return self.pair.sat(f)

    def witness(self, f: fm.Formula) -> Optional[dict[str, bool]]:
        return self.pair.witness(f)

    # ------------------------------------------------------------------ counting
    def count(self, f: fm.Formula, decisions: Mapping[str, bool], timeout: Optional[float] = 10.0) -> Optional[int]:
        """Products satisfying ``f`` and the decisions (None: not countable here / in time)."""
        d = self.decision_formula(decisions)
        vs = fm.variables(f) | fm.variables(d)
        if self.enc is not None and self.analysis is not None and all(self.is_feature(v) for v in vs):
            inc = [k for k, v in decisions.items() if v]
            exc = [k for k, v in decisions.items() if not v]
            try:
                if f == fm.FALSE:
                    return 0
                return self.analysis.count(include=inc, exclude=exc, formula=None if f == fm.TRUE else f,
                                           timeout=timeout)
            except Exception:
                return None
        if self.enc is not None:
            return None  # conditions over args that are not features: not products of the model
        # no model: assignments of the free args
        g = fm.conj([f, d])
        vs = sorted(fm.variables(g))
        if len(vs) > MAX_BRUTE_VARS:
            return None
        n = sum(1 for bits in itertools.product((False, True), repeat=len(vs))
                if fm.evaluate(g, dict(zip(vs, bits))))
        return n * 2 ** (len(set(self.free) - set(vs)))


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


def _simplifier(logic: GraphLogic, base: fm.Formula):
    """Simplify formulas relative to ``base`` (the decisions) and the model, for display: in
    negation normal form, a literal the context decides becomes a constant, a conjunct the
    others imply and a disjunct that implies the others go.  Bounded: large formulas are
    returned as they are."""
    cache: dict[fm.Formula, fm.Formula] = {}

    def sat(*fs: fm.Formula) -> bool:
        return logic.sat(fm.conj(list(fs)))

    def go(f: fm.Formula, ctx: fm.Formula) -> fm.Formula:
        if isinstance(f, fm.Const):
            return f
        if isinstance(f, (fm.Var, fm.Not)):
            if not sat(ctx, f):
                return fm.FALSE
            if not sat(ctx, fm.neg(f)):
                return fm.TRUE
            return f
        args = list(f.args)
        if isinstance(f, fm.And):
            for _ in range(2):
                for i in range(len(args)):
                    args[i] = go(args[i], fm.conj([ctx] + args[:i] + args[i + 1:]))
                g = fm.conj(args)
                if not isinstance(g, fm.And):
                    return g
                args = list(g.args)
            i = 0
            while i < len(args) and len(args) > 1:
                if not sat(ctx, *(args[:i] + args[i + 1:]), fm.neg(args[i])):
                    del args[i]
                else:
                    i += 1
            return fm.conj(args)
        for i in range(len(args)):
            args[i] = go(args[i], fm.conj([ctx, fm.neg(fm.disj(args[:i] + args[i + 1:]))]))
        g = fm.disj(args)
        if not isinstance(g, fm.Or):
            return g
        args = list(g.args)
        i = 0
        while i < len(args) and len(args) > 1:
            if not sat(ctx, args[i], fm.neg(fm.disj(args[:i] + args[i + 1:]))):
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


def check_decisions(logic: GraphLogic, decisions: Mapping[str, bool]) -> None:
    unknown = [k for k in decisions if not logic.known(k)]
    if unknown:
        import difflib
        names = logic.names()
        parts = []
        for k in unknown:
            m = difflib.get_close_matches(k, names, n=1)
            parts.append(f"`{k}`" + (f" (did you mean `{m[0]}`?)" if m else ""))
        raise UnknownFeature("unknown feature " + ", ".join(parts))
    d = logic.decision_formula(decisions)
    if not logic.sat(d):
        conflict = None
        if logic.analysis is not None and all(logic.is_feature(k) for k in decisions):
            try:
                conflict = logic.analysis.propagate(dict(decisions), count=False).conflict
            except Exception:
                conflict = None
        what = ", ".join(conflict) if conflict else ", ".join(
            ("" if v else "!") + k for k, v in decisions.items())
        raise NoProducts(f"no product satisfies these decisions (conflict: {what})", conflict)


def project(graph: Graph, logic: GraphLogic, decisions: Optional[Mapping[str, bool]] = None,
            count: bool = False, simplify: bool = True, count_timeout: Optional[float] = 10.0) -> Graph:
    """The graph of the products that satisfy ``decisions`` (feature / free arg -> selected).
    Raises :class:`UnknownFeature` or :class:`NoProducts`."""
    decisions = dict(decisions or {})
    check_decisions(logic, decisions)
    d = logic.decision_formula(decisions)
    # the names every remaining product gives the same value
    used: set[str] = set()
    for el in list(graph.nodes.values()) + list(graph.resources.values()) + list(graph.links.values()):
        if el.condition is not None:
            used |= fm.variables(el.condition)
    env: dict[str, fm.Formula] = {k: (fm.TRUE if v else fm.FALSE) for k, v in decisions.items()}
    for v in sorted(used - set(decisions)):
        if not logic.sat(fm.conj([d, fm.Var(v)])):
            env[v] = fm.FALSE
        elif not logic.sat(fm.conj([d, fm.neg(fm.Var(v))])):
            env[v] = fm.TRUE
    simp = _simplifier(logic, d) if simplify else (lambda f: f)
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
        elif not logic.sat(fm.conj([d, g])):
            out = GONE
        elif not logic.sat(fm.conj([d, fm.neg(g)])):
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
        out.products = logic.count(fm.TRUE, decisions, count_timeout)
        for el in list(out.nodes.values()) + list(out.resources.values()) + list(out.links.values()):
            if el.condition is None:
                el.count = out.products
            else:
                el.count = logic.count(el.condition, decisions, count_timeout)
    return out
