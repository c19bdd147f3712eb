"""The HAROS project file's ``rules``: queries over the computation graph, evaluated on the graph of
every product at once, as HAROS-TVL shows them in its issues list (thesis, Figure 22: "Query
found: this query is depending on Random and Teleop").

A rule is ``{name, description, tags, query}``; the query is HAROS's PyFlwor::

    for n in <configs/nodes> where len(n.reads) > 0 return n

Each element the query returns becomes a problem whose presence condition is the element's
condition and the condition under which the ``where`` clause holds (the links it counts have
conditions of their own), so the configurator filters it by the decisions like any other
problem.  Queries outside the part of PyFlwor evaluated here -- ``for V in <PATH> [where E]
return V`` with ``PATH`` one of ``nodes``, ``topics``, ``services``, ``parameters`` (optionally
under ``configs/``), and ``E`` built from ``and``, ``or``, ``not``, comparisons, ``in``,
``len(V.collection)`` and ``V.attribute`` -- are listed as not evaluated, with the reason.

Attributes: every element has ``name``, ``kind``, ``condition``; a node ``namespace``,
``package``, ``type``, and the collections ``publishers`` (its publish links), ``subscribers``,
``servers``, ``clients``, ``reads``, ``writes``; a topic ``publishers`` and ``subscribers`` (the
links), a service ``servers`` and ``clients``, a parameter ``reads``, ``writes`` and ``value``.
A link has ``node``, ``topic`` / ``service`` / ``param``, ``type`` and ``name``.
"""

from __future__ import annotations

import ast
import itertools
import re
from dataclasses import dataclass, field
from typing import Any, Iterable, Optional

from ..base import formula as fm
from ..base.diagnostics import Diagnostic, Related, Severity, register
from ..base.text import Pos, Span

HAROS_RULE = "haros-rule"
HAROS_RULE_NOT_EVALUATED = "haros-rule-not-evaluated"
register(HAROS_RULE, Severity.WARNING, "A HAROS project rule's query finds this element.", "configurator")
register(HAROS_RULE_NOT_EVALUATED, Severity.INFORMATION,
         "A HAROS project rule whose query tvl-lsp does not evaluate.", "configurator")

MAX_RESULTS = 200          # results of one rule listed
MAX_COUNT_TERMS = 5000     # subsets a len() comparison may expand to

_QUERY = re.compile(r"^\s*for\s+([A-Za-z_]\w*)\s+in\s+<\s*([\w/]+)\s*>\s*(?:where\s+(.*?))?\s*return\s+(.*?)\s*$",
                    re.S)
_PATHS = {"nodes": "node", "topics": "topic", "services": "service", "parameters": "parameter",
          "params": "parameter"}
_COLLECTIONS = {
    "node": {"publishers": "publish", "subscribers": "subscribe", "servers": "service", "clients": "client",
             "reads": "read", "writes": "write"},
    "topic": {"publishers": "publish", "subscribers": "subscribe"},
    "service": {"servers": "service", "clients": "client"},
    "parameter": {"reads": "read", "writes": "write"},
}


@dataclass
class Rule:
    key: str
    name: str
    description: str
    query: str
    path: str
    span: Span
    tags: list[str] = field(default_factory=list)


class NotEvaluated(Exception):
    """The query uses something this evaluator does not know (the message says what)."""


# ------------------------------------------------------------------ reading the rules

def _span(node) -> Span:
    s, e = node.start_mark, node.end_mark
    return Span(Pos(s.line, s.column), Pos(e.line, e.column))


def read_rules(path: str, text: str) -> list[Rule]:
    """The ``rules:`` of one HAROS project file (nothing when it has none or is not YAML)."""
    import yaml

    from ..base import yamlsafe
    try:
        root = yamlsafe.compose(text)
    except (yaml.YAMLError, ValueError):
        return []
    if not isinstance(root, yaml.MappingNode):
        return []
    out = []
    for k, v in root.value:
        if getattr(k, "value", None) != "rules" or not isinstance(v, yaml.MappingNode):
            continue
        for rk, rv in v.value:
            if not isinstance(rv, yaml.MappingNode):
                continue
            fields = {getattr(a, "value", None): b for a, b in rv.value}
            q = fields.get("query")
            if not isinstance(q, yaml.ScalarNode):
                continue
            name = fields.get("name")
            desc = fields.get("description")
            tags = fields.get("tags")
            out.append(Rule(str(rk.value), str(name.value) if isinstance(name, yaml.ScalarNode) else str(rk.value),
                            str(desc.value) if isinstance(desc, yaml.ScalarNode) else "",
                            str(q.value), path, _span(q),
                            [str(t.value) for t in tags.value if isinstance(t, yaml.ScalarNode)]
                            if isinstance(tags, yaml.SequenceNode) else []))
    return out


# ------------------------------------------------------------------ the graph, for queries

@dataclass
class Item:
    """An element of the graph (or a link) as queries see it: attributes and a condition."""
    kind: str
    id: str
    attrs: dict
    condition: fm.Formula
    location: Optional[tuple[str, Span]] = None


def _cond(c: Optional[fm.Formula]) -> fm.Formula:
    return fm.TRUE if c is None else c


def items_of(g) -> dict[str, list[Item]]:
    """Nodes, topics, services and parameters of a :class:`tvl_lsp.graph.Graph` (all products)."""
    by_id: dict[str, Item] = {}
    out: dict[str, list[Item]] = {"node": [], "topic": [], "service": [], "parameter": []}
    for n in g.nodes.values():
        loc = (n.locations[0].path, n.locations[0].span) if n.locations else None
        it = Item("node", n.id, {"name": n.name, "kind": "node", "namespace": n.namespace, "package": n.package,
                                 "type": n.type}, _cond(n.condition), loc)
        by_id[n.id] = it
        out["node"].append(it)
    for r in g.resources.values():
        loc = (r.locations[0].path, r.locations[0].span) if r.locations else None
        attrs = {"name": r.name, "kind": r.kind, "type": r.type}
        if r.kind == "parameter":
            attrs["value"] = r.value
        it = Item(r.kind, r.id, attrs, _cond(r.condition), loc)
        by_id[r.id] = it
        out.setdefault(r.kind, []).append(it)
    for it in by_id.values():
        for coll in _COLLECTIONS.get(it.kind, {}):
            it.attrs[coll] = []
    for ln in g.links.values():
        node, res = by_id.get(ln.node), by_id.get(ln.resource)
        if node is None or res is None:
            continue
        res_key = {"topic": "topic", "service": "service", "parameter": "param"}[res.kind]
        link = Item("link", ln.id, {"node": node, res_key: res, "type": ln.type, "name": res.attrs["name"],
                                    "kind": ln.kind}, _cond(ln.condition))
        for coll, kind in _COLLECTIONS["node"].items():
            if kind == ln.kind:
                node.attrs[coll].append(link)
        for coll, kind in _COLLECTIONS.get(res.kind, {}).items():
            if kind == ln.kind:
                res.attrs[coll].append(link)
    return out


# ------------------------------------------------------------------ evaluation

class _Len:
    """``len(collection)`` of items present under conditions."""

    def __init__(self, conds: list[fm.Formula]):
        self.conds = conds


def _at_least(conds: list[fm.Formula], k: int) -> fm.Formula:
    if k <= 0:
        return fm.TRUE
    if k > len(conds):
        return fm.FALSE
    if k == 1:
        return fm.disj(conds)
    n_terms = 1
    for i in range(k):
        n_terms = n_terms * (len(conds) - i) // (i + 1)
    if n_terms > MAX_COUNT_TERMS:
        raise NotEvaluated(f"len() compared with {k} over {len(conds)} conditional elements")
    return fm.disj(fm.conj(c) for c in itertools.combinations(conds, k))


def _compare_len(n: _Len, op: str, k: Any) -> fm.Formula:
    if isinstance(k, bool) or not isinstance(k, int):
        raise NotEvaluated("len() compared with something other than a whole number")
    ge = lambda m: _at_least(n.conds, m)  # noqa: E731
    if op == ">":
        return ge(k + 1)
    if op == ">=":
        return ge(k)
    if op == "<":
        return fm.neg(ge(k))
    if op == "<=":
        return fm.neg(ge(k + 1))
    if op == "==":
        return fm.conj([ge(k), fm.neg(ge(k + 1))])
    if op == "!=":
        return fm.neg(fm.conj([ge(k), fm.neg(ge(k + 1))]))
    raise NotEvaluated(f"len() with {op}")


_OPS = {ast.Gt: ">", ast.GtE: ">=", ast.Lt: "<", ast.LtE: "<=", ast.Eq: "==", ast.NotEq: "!="}
_FLIP = {">": "<", ">=": "<=", "<": ">", "<=": ">=", "==": "==", "!=": "!="}


def _truth(v: Any) -> fm.Formula:
    if isinstance(v, fm.Formula):
        return v
    if isinstance(v, _Len):
        return _at_least(v.conds, 1)
    if isinstance(v, list):
        return fm.disj(x.condition for x in v) if v else fm.FALSE
    return fm.TRUE if v else fm.FALSE


def _eval(node: ast.AST, env: dict[str, Item]) -> Any:
    if isinstance(node, ast.Constant) and isinstance(node.value, (str, int, float, bool, type(None))):
        return node.value
    if isinstance(node, ast.Name):
        if node.id in env:
            return env[node.id]
        if node.id in ("True", "False", "None"):
            return {"True": True, "False": False, "None": None}[node.id]
        raise NotEvaluated(f"unknown name `{node.id}`")
    if isinstance(node, ast.Attribute):
        base = _eval(node.value, env)
        if not isinstance(base, Item):
            raise NotEvaluated(f"`.{node.attr}` of something that is not a graph element")
        if node.attr not in base.attrs:
            raise NotEvaluated(f"`{base.kind}.{node.attr}` (tvl-lsp's graph has no such attribute)")
        return base.attrs[node.attr]
    if isinstance(node, ast.Call):
        if isinstance(node.func, ast.Name) and node.func.id == "len" and len(node.args) == 1 and not node.keywords:
            v = _eval(node.args[0], env)
            if isinstance(v, list):
                return _Len([x.condition for x in v])
            if isinstance(v, str):
                return len(v)
            raise NotEvaluated("len() of something that is not a collection")
        raise NotEvaluated(f"the call `{ast.unparse(node)}`")
    if isinstance(node, ast.BoolOp):
        parts = [_truth(_eval(v, env)) for v in node.values]
        return fm.conj(parts) if isinstance(node.op, ast.And) else fm.disj(parts)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
        return fm.neg(_truth(_eval(node.operand, env)))
    if isinstance(node, ast.Compare):
        left = _eval(node.left, env)
        parts = []
        for op, right_node in zip(node.ops, node.comparators):
            right = _eval(right_node, env)
            parts.append(_compare(left, op, right))
            left = right
        return fm.conj(parts)
    raise NotEvaluated(f"`{ast.unparse(node)}`")


def _compare(a: Any, op: ast.cmpop, b: Any) -> fm.Formula:
    if isinstance(op, (ast.In, ast.NotIn)):
        if isinstance(b, list):
            raise NotEvaluated("`in` over a collection of graph elements")
        if not isinstance(a, str) or not isinstance(b, str):
            raise NotEvaluated("`in` between values that are not text")
        got = a in b
        return fm.TRUE if got == isinstance(op, ast.In) else fm.FALSE
    sym = _OPS.get(type(op))
    if sym is None:
        raise NotEvaluated(f"the comparison {type(op).__name__}")
    if isinstance(a, _Len):
        return _compare_len(a, sym, b)
    if isinstance(b, _Len):
        return _compare_len(b, _FLIP[sym], a)
    if isinstance(a, (Item, list)) or isinstance(b, (Item, list)):
        raise NotEvaluated("a comparison of graph elements")
    try:
        got = {">": lambda: a > b, ">=": lambda: a >= b, "<": lambda: a < b, "<=": lambda: a <= b,
               "==": lambda: a == b, "!=": lambda: a != b}[sym]()
    except TypeError:
        raise NotEvaluated(f"a comparison of {type(a).__name__} with {type(b).__name__}") from None
    return fm.TRUE if got else fm.FALSE


def _python(expr: str) -> ast.AST:
    text = " ".join(expr.split())
    try:
        return ast.parse(text, mode="eval").body
    except SyntaxError:
        raise NotEvaluated(f"`{text}` is not an expression tvl-lsp reads") from None


def evaluate(rule: Rule, items: dict[str, list[Item]]) -> list[tuple[Item, fm.Formula]]:
    """The elements the rule's query returns, each with the condition under which it does
    (raises NotEvaluated)."""
    m = _QUERY.match(rule.query)
    if not m:
        raise NotEvaluated("not of the form `for V in <PATH> [where ...] return V`")
    var, path, where, ret = m.groups()
    parts = [p for p in path.split("/") if p]
    if parts and parts[0] == "configs":
        parts = parts[1:]
    if len(parts) != 1 or parts[0] not in _PATHS:
        raise NotEvaluated(f"the path <{path}> (tvl-lsp evaluates <configs/nodes>, topics, services, parameters)")
    if ret.strip() != var:
        raise NotEvaluated(f"`return {ret.strip()}` (tvl-lsp lists the elements a query returns: `return {var}`)")
    cond_ast = _python(where) if where else None
    out = []
    for it in items.get(_PATHS[parts[0]], []):
        c = it.condition
        if cond_ast is not None:
            c = fm.conj([c, _truth(_eval(cond_ast, {var: it}))])
        if c != fm.FALSE:
            out.append((it, c))
    return out


def simplifier(logic, g):
    """A function simplifying conditions over the graph's names against the model (for
    display), from the graph's logic; the identity when that fails."""
    try:
        from ..graph.project import _simplifier, graph_variables
        o = logic.oracle(graph_variables(g))
        return _simplifier(o, o.term(fm.TRUE))
    except Exception:  # display only
        return lambda f: f


def diagnostics(rules: Iterable[Rule], g, valid=None, simplify=None) -> list[tuple[Diagnostic, Optional[fm.Formula]]]:
    """One diagnostic per (rule, element found), with its condition; one per rule not evaluated.
    ``valid(formula)``: does it hold in every product? (its condition is then dropped);
    ``simplify(formula)``: an equivalent, shorter formula."""
    out: list[tuple[Diagnostic, Optional[fm.Formula]]] = []
    items = items_of(g) if g is not None else None
    for r in rules:
        head = f"rule {r.name}" + (f": {r.description}" if r.description else "")
        try:
            if items is None:
                raise NotEvaluated("the computation graph, which could not be built")
            found = evaluate(r, items)
        except (NotEvaluated, RecursionError) as e:
            msg = f"{head} -- not evaluated: the query uses {e}" if isinstance(e, NotEvaluated) else \
                f"{head} -- not evaluated: the query is nested too deeply"
            out.append((Diagnostic(HAROS_RULE_NOT_EVALUATED, Severity.INFORMATION, r.path, r.span, msg,
                                   data={"rule": r.key}), None))
            continue
        for it, c in found[:MAX_RESULTS]:
            cond = None if c == fm.TRUE or (valid is not None and valid(c)) else c
            if cond is not None and simplify is not None:
                cond = simplify(cond)
            when = "in every product" if cond is None else f"when {cond}"
            related = [Related(it.location[0], it.location[1], f"{it.kind} {it.attrs['name']}")] if it.location else []
            d = Diagnostic(HAROS_RULE, Severity.WARNING, r.path, r.span,
                           f"{head} -- {it.kind} {it.attrs['name']} ({when})", related=related,
                           data={"rule": r.key, "element": it.id, "tags": r.tags})
            out.append((d, cond))
        if len(found) > MAX_RESULTS:
            out.append((Diagnostic(HAROS_RULE, Severity.INFORMATION, r.path, r.span,
                                   f"{head} -- {len(found) - MAX_RESULTS} more elements found, not listed",
                                   data={"rule": r.key}), None))
    return out
