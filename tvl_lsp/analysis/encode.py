"""TVL model -> CNF, with the reference semantics (TVLParser v20100804).

Variables ``1..n`` are the features in declaration order (``Encoding.var_of_feature``); every
other variable (attribute values, Tseitin definitions, cardinality counters) comes after them.
A *product* is a selection of features, so counts are projected on ``1..n``.

Semantics encoded (one :class:`Element` per piece of the model, so that explanations can name
the pieces):

- the root is selected (element ``root``);
- a child implies its parent, a shared feature implies the OR of its parents (``parent-link``);
- a group ``[i..j]`` of feature P with mandatory children M and optional children O applies
  only when P is selected and accepts a selected set S iff ``|S| <= j`` and
  ``|S & M| + |O| >= i`` (optional children always win over the cardinality).  The upper bound
  is one ``group`` element (a sequential counter whose counter variables are defined by Tseitin
  clauses, never a pairwise blow-up for big groups); the lower bound is one ``mandatory`` element per child
  when every mandatory child is needed (``allOf``), else a ``group-lower`` element;
- constraints are global (even inside an optional feature); ``ifIn: e`` is ``F -> e`` and
  ``ifOut: e`` is ``!F -> e``;
- bool attributes are variables, enum and bounded int attributes are one-hot over their finite
  domain (a direct encoding: exact, and fine for the small domains TVL models use; python-sat's
  ``pysat.pb`` needs ``pindakaas`` which is not a dependency), ``is`` / ``in`` become
  ``attribute`` elements, aggregates over ``children`` / ``selectedChildren`` are expanded;
- what needs reals, unbounded ints or too big a domain is left out and recorded in
  ``Encoding.not_encoded`` (reported once per constraint as ``constraint-not-encoded``).

Tseitin definitions (``x <-> a && b``) are *hard* clauses: they define auxiliary variables
functionally, so they never conflict and never change a projected count.  The cardinality
counters are built from them too, so every auxiliary variable except attribute values is a
function of the features: counting all variables (d4) counts the products.  Attribute values
may be left free by the model; :meth:`Encoding.aux_determined` checks whether they are.  The clauses that
assert something about the model belong to an element and are guarded by the element's
selector literal in the explanation solver.
"""

from __future__ import annotations

import hashlib
from itertools import count as _count
from operator import eq as _eq
from typing import Optional

from ..base.diagnostics import Diagnostic, Related, Severity, register
from ..base.text import Span, ZERO_SPAN
from ..tvl import model as M
from ..base import formula as fm
from .cnf import Element, _Builder, _clean  # noqa: F401 (Element and _Builder: used from here by others)
from .distribute import _ALIAS, DistributeMixin, Lit, NotEncodable, _chain, _check_read  # noqa: F401
from .labels import line_text, source_text  # noqa: F401 (source_text: used from here by others)

CONSTRAINT_NOT_ENCODED = register(
    "constraint-not-encoded", Severity.INFORMATION,
    "A constraint needs reals, unbounded integers or too large a domain: the analyses ignore it.",
    "analysis")

# the direct (one-hot) encoding of integer terms gives up beyond this many value pairs
MAX_VALUE_PAIRS = 20000
MAX_DOMAIN = 4096
# a constraint is distributed into at most this many clauses before Tseitin variables are used
DISTRIBUTE_MAX = 16

_LOGIC_OPS = {"&&", "||", "->", "<-", "<->", "requires", "excludes"}
_CMP_OPS = {"==", "!=", "<", "<=", ">", ">="}
# the thesis writes infix and/or; the parser reports them and keeps the words
class Encoding(DistributeMixin):
    """The CNF of a model.  Build with :func:`encode`."""

    def __init__(self, model: M.Model):
        self.model = model
        self.features: list[M.Feature] = list(model.features)
        self.var_of_feature: dict[M.Feature, int] = {f: i + 1 for i, f in enumerate(self.features)}
        self.feature_of_var: dict[int, M.Feature] = {i + 1: f for i, f in enumerate(self.features)}
        self.n_features = len(self.features)
        self.hard: list[list[int]] = []
        self.elements: list[Element] = []
        self.not_encoded: list[tuple[object, str, str, Span, str]] = []  # obj, what, path, span, reason
        self.b = _Builder(self.n_features, self.hard)
        self._attr_terms: dict[int, tuple] = {}
        self._attr_busy: set[int] = set()
        self._by_short: dict[str, list[M.Feature]] = {}
        self._by_long: dict[str, M.Feature] = {}
        for f in self.features:
            self._by_short.setdefault(f.name, []).append(f)
            self._by_long.setdefault(f.long_name, f)
        self._clauses: Optional[list[list[int]]] = None
        self._key: Optional[str] = None
        self._determined: Optional[bool] = None
        self._line_indexes: dict = {}

    # ------------------------------------------------------------------ names
    def feature_by_name(self, name: str) -> Optional[M.Feature]:
        """Short name when unique, else long name ("Root.A.B")."""
        fs = self._by_short.get(name)
        if fs and len(fs) == 1:
            return fs[0]
        return self._by_long.get(name)

    def name_of(self, f: M.Feature) -> str:
        """The name a user (and the formulas) use: the short name when unique, else the long."""
        return f.name if len(self._by_short.get(f.name, ())) == 1 else f.long_name

    def var(self, name: str) -> int:
        f = self.feature_by_name(name)
        if f is None:
            raise KeyError(f"unknown feature {name!r}")
        return self.var_of_feature[f]

    @property
    def nvars(self) -> int:
        return self.b.top

    @property
    def projection(self) -> list[int]:
        return list(range(1, self.n_features + 1))

    # ------------------------------------------------------------------ CNF
    def clauses(self) -> list[list[int]]:
        """All clauses (hard + every element), no selectors: the model's CNF."""
        if self._clauses is None:
            out = list(self.hard)
            for e in self.elements:
                out.extend(e.clauses)
            self._clauses = out
        return self._clauses

    def logical_key(self) -> str:
        """A hash of the CNF and the projection: equal for models that differ only in layout."""
        if self._key is None:
            h = hashlib.sha256()
            h.update(f"{self.n_features} {self.nvars}\n".encode())
            for c in self.clauses():
                h.update((" ".join(map(str, c)) + "\n").encode())
            self._key = h.hexdigest()
        return self._key

    def attribute_vars(self) -> list[int]:
        """The variables that hold attribute values (the only auxiliary variables that are not
        defined by construction: Tseitin and counter variables are functions of them and of
        the features)."""
        out: set[int] = set()
        for term in self._attr_terms.values():
            if term[0] == "bool" and isinstance(term[1], int) and not isinstance(term[1], bool):
                out.add(abs(term[1]))
            elif term[0] == "map":
                out.update(abs(x) for x in term[1].values() if isinstance(x, int) and not isinstance(x, bool))
        return sorted(v for v in out if v > self.n_features)

    def aux_determined(self, time_budget: Optional[float] = 5.0) -> bool:
        """Are all auxiliary variables (those above the features) functions of the features?
        Then counting all variables (d4) counts the products.  See
        :func:`.counting.definability.attributes_determined`."""
        if self._determined is None:
            from .counting.definability import attributes_determined
            self._determined = attributes_determined(self.clauses(), self.n_features, self.nvars,
                                                     self.attribute_vars(), time_budget)
        return self._determined

    def formula_clauses(self, f: fm.Formula, top: Optional[int] = None) -> tuple[list[list[int]], int]:
        """Clauses asserting formula ``f`` (over feature names); returns (clauses, new top)."""
        hard: list[list[int]] = []
        b = _Builder(self.nvars if top is None else top, hard)

        def go(g: fm.Formula) -> Lit:
            if isinstance(g, fm.Const):
                return g.value
            if isinstance(g, fm.Var):
                return self.var(g.name)
            if isinstance(g, fm.Not):
                return b.not_(go(g.arg))
            if isinstance(g, fm.And):
                return b.and_([go(a) for a in g.args])
            if isinstance(g, fm.Or):
                return b.or_([go(a) for a in g.args])
            raise TypeError(g)

        out: list[list[int]] = []
        # a top-level conjunction of disjunctions becomes clauses without auxiliaries
        parts = f.args if isinstance(f, fm.And) else (f,)
        for p in parts:
            lits = [go(a) for a in p.args] if isinstance(p, fm.Or) else [go(p)]
            c = _clean(lits)
            if c is not None:
                out.append(c)
        return hard + out, b.top

    # ------------------------------------------------------------------ diagnostics
    def diagnostics(self) -> list[Diagnostic]:
        out = []
        for obj, what, path, span, reason in self.not_encoded:
            out.append(Diagnostic(
                code=CONSTRAINT_NOT_ENCODED, severity=Severity.INFORMATION, path=path, span=span,
                message=f"This {what} is not taken into account by the analyses and product counts: {reason}."))
        return out

    # ------------------------------------------------------------------ building
    def _add(self, e: Element) -> Element:
        self.elements.append(e)
        self._clauses = None
        self._determined = None
        return e

    def _encode_structure(self) -> None:
        m = self.model
        v = self.var_of_feature
        if m.root is not None and m.root in v:
            r = m.root
            self._add(Element("root", f"{r.name} is the root: it is always selected", r.path, r.name_span,
                              r, [[v[r]]], negation=[-v[r]]))
        add = self.elements.append  # (what _add does, its caches reset once below)
        for f in self.features:
            par = f.parent
            if not f.shared_parents:  # the common case: one parent
                if par is None or par not in v:
                    continue
                vf = v[f]
                vp = v[par]
                add(Element("parent-link", f"{f.name} needs its parent {par.name}", f.path, f.name_span, f,
                            [[-vf, vp]], negation=[vf, -vp]))
                continue
            parents = [p for p in f.parents if p in v]
            if not parents:
                continue
            if len(parents) == 1:
                label = f"{f.name} needs its parent {parents[0].name}"
            else:
                label = f"{f.name} needs one of its parents {', '.join(p.name for p in parents)}"
            add(Element("parent-link", label, f.path, f.name_span, f,
                        [[-v[f]] + [v[p] for p in parents]], negation=[v[f]] + [-v[p] for p in parents]))
        self._clauses = None
        self._determined = None
        for p in self.features:
            if p.group is None and not p.extra_groups:
                continue
            for g in p.groups:  # TVL: at most one; UVL: one per block
                self._encode_group(p, g)

    def _encode_group(self, p: M.Feature, g: M.Group) -> None:
        v = self.var_of_feature
        seen: set = set()
        kids = []
        for c in g.children:
            if c.feature in v and c.feature not in seen:
                seen.add(c.feature)
                kids.append(c)
        pv = v[p]
        lits = [v[c.feature] for c in kids]
        mand = [c for c in kids if not c.optional]
        n_opt = len(kids) - len(mand)
        kw = g.keyword_span if g.keyword_span != ZERO_SPAN else g.span
        gname = g.text

        def names(cs) -> str:
            ns = [c.feature.name for c in cs]
            return ", ".join(ns) if len(ns) <= 5 else ", ".join(ns[:4]) + f" … ({len(ns)} children)"

        if g.hi is not None and g.hi < len(kids):
            cls = [[-pv] + c for c in self.b.at_most(lits, g.hi)]
            self._add(Element("group", f"group {gname} of {p.name}: at most {g.hi} of {names(kids)}",
                              g.path, kw, g, cls))
        need = g.lo - n_opt
        if need <= 0:
            return
        if need > len(mand):
            self._add(Element("group-lower", f"group {gname} of {p.name} cannot be satisfied: "
                              f"it needs {g.lo} children", g.path, kw, g, [[-pv]], negation=[pv]))
        elif need == len(mand):
            for c in mand:
                self._add(Element("mandatory", f"{c.feature.name} is mandatory in {p.name}", c.path,
                                  c.span if c.span != ZERO_SPAN else c.feature.name_span, c,
                                  [[-pv, v[c.feature]]], negation=[pv, -v[c.feature]]))
        else:
            cls = [[-pv] + c for c in self.b.at_least([v[c.feature] for c in mand], need)]
            self._add(Element("group-lower", f"group {gname} of {p.name}: at least {need} of "
                              f"{names(mand)}", g.path, kw, g, cls))

    def _encode_constraints(self) -> None:
        v = self.var_of_feature
        ctx: Optional[tuple] = None
        for f in self.features:
            for c in f.constraints:
                if getattr(c, "has_errors", False):
                    continue  # the front end reported it: no guess at what it means
                lits = getattr(c, "lits", None)
                if lits is not None and c.kind != "ifIn" and c.kind != "ifOut":
                    # a DIMACS clause (:class:`.dimacs.ClauseConstraint`): its literals as they are,
                    # numbered as the features are here (shared); a tight loop: 10^6 of them
                    if ctx is None:
                        ctx, feats = (self.model, self._line_indexes), self.model.features
                        add, negate = self.elements.append, int.__neg__
                        same = all(map(_eq, map(v.__getitem__, feats), _count(1)))
                        self._clauses = self._determined = None
                    cl = lits if same else [v[feats[x - 1]] if x > 0 else -v[feats[-x - 1]] for x in lits]
                    n = len(cl)
                    if n == 2:
                        if cl[0] == cl[1] or cl[0] == -cl[1]:
                            cl = _clean(cl)
                    elif n > 2:
                        seen = set(cl)
                        if len(seen) != n or not seen.isdisjoint(map(negate, cl)):
                            cl = _clean(cl)  # a repeated literal or a tautology
                    add(c.element_type(c, [] if cl is None else [cl], ctx))  # label etc. made when read
                    continue
                if c.kind == "ifIn":
                    prefix: list[Lit] = [-v[f]]
                elif c.kind == "ifOut":
                    prefix = [v[f]]
                else:
                    prefix = []
                if c.clause is not None and not prefix:  # a DIMACS clause: its literals as they are
                    feats = self.model.features
                    cl = _clean([v[feats[x]] if x > 0 else -v[feats[-x]] for x in c.clause])
                    clauses = [] if cl is None else [cl]
                    text = line_text(self.model, c, self._line_indexes) or "constraint"
                else:
                    try:
                        clauses = []
                        self._iff_memo = {}
                        self._assert(c.expr, prefix, True, clauses, f)
                    except NotEncodable as ex:
                        self.not_encoded.append((c, "constraint", c.path, c.span, str(ex)))
                        continue
                    text = source_text(self.model, c.path, c.span, cache=self._line_indexes) or "constraint"
                neg = None
                if len(clauses) == 1:
                    neg = [-x for x in clauses[0]]
                elif not clauses:
                    neg = [False]  # a constraint that always holds: cannot be negated
                prefix_txt = {"ifIn": f"when {f.name} is selected, ", "ifOut": f"when {f.name} is not selected, "}
                self._add(Element("constraint", f"constraint {prefix_txt.get(c.kind, '')}`{text}`",
                                  c.path, c.span, c, clauses, negation=neg))

    def _encode_attributes(self) -> None:
        """Attributes no constraint reads (the constraints pulled in the others already).

        Such an attribute matters only if its own ``is`` / ``in`` parts restrict the features
        (``int a in [1..3] is 5`` makes its owner impossible).  Encode it on the side first: if
        it mentions no feature but its owner and holds both with and without its owner, leave
        it out -- its values are existentially quantified anyway, and big one-hot domains slow
        the projected counts down for nothing."""
        from .sat import BoundedSolver as Solver
        lits = (M.IntLit, M.BoolLit)
        for f in self.features:
            for a in f.attributes:
                if id(a) in self._attr_terms:
                    continue
                if (a.if_in_value is None and a.if_in_domain is None and a.if_out_value is None
                        and a.if_out_domain is None and a.type in ("int", "bool") and not getattr(a, "has_errors", False)):
                    if a.domain is None and isinstance(a.value, lits):
                        continue  # ``int cost is 87;``: one value and no domain restricts nothing
                    d = a.domain
                    if (a.value is None and a.type == "int" and isinstance(d, M.RangeLit)
                            and isinstance(d.lo, M.IntLit) and isinstance(d.hi, M.IntLit)
                            and type(d.lo.value) is int and type(d.hi.value) is int and d.lo.value <= d.hi.value):
                        # ``int c in [0..1000];``: a non-empty range and no value restricts nothing
                        # (3,000 such attributes took minutes to encode on the side, one by one)
                        continue
                saved = (self.b, self.hard, self.elements, dict(self._attr_terms))
                self.hard = []
                self.b = _Builder(saved[0].top, self.hard)
                self.elements = []
                try:
                    self._attr_term(a, f)
                    ok = True
                except NotEncodable:
                    ok = False  # reported when a constraint needs it
                side = self.hard + [c for e in self.elements for c in e.clauses]
                self.b, self.hard, self.elements, self._attr_terms = saved
                self._clauses = None
                if not ok:
                    continue
                ov = self.var_of_feature.get(f)
                feats = {abs(x) for c in side for x in c if abs(x) <= self.n_features}
                if feats <= {ov}:
                    # the side encoding's variables renumbered from 1: the solver allocates
                    # per variable index, and the indices here run up to the whole model's
                    # (one solver per attribute over them was quadratic on big models)
                    ren: dict[int, int] = {}
                    compact = [[(ren.setdefault(abs(x), len(ren) + 1)) * (1 if x > 0 else -1) for x in c]
                               for c in side]
                    cov = ren.get(ov) if ov is not None else None
                    with Solver(name="minisat22", bootstrap_with=compact) as sv:
                        if all(sv.solve(assumptions=[x]) for x in ([cov, -cov] if cov is not None else [])) \
                                and sv.solve():
                            continue
                try:
                    self._attr_term(a, f)
                except NotEncodable:
                    pass

    # ------------------------------------------------------------------ assertions
    def _assert(self, e: M.Expr, prefix: list[Lit], pos: bool, out: list[list[int]], ctx) -> None:
        """Append clauses meaning ``OR(prefix) or (e if pos else !e)``."""
        if isinstance(e, M.BoolLit):
            _check_read(e)
            if e.value != pos:
                c = _clean(prefix)
                if c is not None:
                    out.append(c)
            return
        if isinstance(e, M.Unary) and e.op == "!":
            return self._assert(e.operand, prefix, not pos, out, ctx)
        if isinstance(e, M.Binary):
            op = _ALIAS.get(e.op, e.op)
            if (op == "&&" and pos) or (op == "||" and not pos):
                for x in _chain(e, op):  # a long chain must not recurse
                    self._assert(x, prefix, pos, out, ctx)
                return
            if op in ("->", "requires", "<-"):
                a, b_ = (e.left, e.right) if op != "<-" else (e.right, e.left)
                if pos:
                    return self._assert(b_, prefix + self._disjuncts(a, False, ctx), True, out, ctx)
                self._assert(a, prefix, True, out, ctx)
                self._assert(b_, prefix, False, out, ctx)
                return
            if op == "excludes" and not pos:
                self._assert(e.left, prefix, True, out, ctx)
                self._assert(e.right, prefix, True, out, ctx)
                return
        if isinstance(e, M.Binary):
            # a small CNF by distribution needs no auxiliary variable (A & B | !C is two clauses)
            cnf = self._cnf(e, pos, ctx, DISTRIBUTE_MAX)
            if cnf is not None:
                for cl in cnf:
                    c = _clean(prefix + cl)
                    if c is not None:
                        out.append(c)
                return
            op = _ALIAS.get(e.op, e.op)
            if (op == "||" and pos) or (op == "&&" and not pos):
                # a disjunction with a long conjunction among its parts ("(C1 & .. & Cn) | S",
                # KConfig exports): the conjunction asserted with the other parts in the
                # prefix, n clauses, instead of a Tseitin variable for it and each Ci
                inner = "&&" if pos else "||"
                parts = _chain(e, op)
                width = [len(_chain(x, inner)) if isinstance(x, M.Binary) else 1 for x in parts]
                i = max(range(len(parts)), key=width.__getitem__)
                if width[i] > 1:
                    rest = []
                    for j, x in enumerate(parts):
                        if j != i:
                            rest += self._disjuncts(x, pos, ctx)
                    return self._assert(parts[i], prefix + rest, pos, out, ctx)
        c = _clean(prefix + self._disjuncts(e, pos, ctx))
        if c is not None:
            out.append(c)

    def _disjuncts(self, e: M.Expr, pos: bool, ctx) -> list[Lit]:
        """Literals whose OR means ``e`` (``!e`` when not pos).  Iterative: DIMACS clauses
        can be long."""
        out: list[Lit] = []
        stack = [(e, pos)]
        while stack:
            e, pos = stack.pop()
            if isinstance(e, M.Unary) and e.op == "!":
                stack.append((e.operand, not pos))
                continue
            if isinstance(e, M.Binary):
                op = _ALIAS.get(e.op, e.op)
                if (op == "||" and pos) or (op == "&&" and not pos):
                    stack.append((e.right, pos))
                    stack.append((e.left, pos))
                    continue
                if op in ("->", "requires") and pos:
                    stack.append((e.right, True))
                    stack.append((e.left, False))
                    continue
                if op == "<-" and pos:
                    stack.append((e.left, True))
                    stack.append((e.right, False))
                    continue
                if op == "excludes" and pos:
                    stack.append((e.right, False))
                    stack.append((e.left, False))
                    continue
            x = self._blit(e, ctx)
            out.append(x if pos else self.b.not_(x))
        return out

    # ------------------------------------------------------------------ bool terms
    def _is_bool(self, e: M.Expr) -> bool:
        if e.type is not None:
            return e.type == "bool"
        if isinstance(e, M.BoolLit):
            return True
        if isinstance(e, M.Name):
            t = e.target
            if isinstance(t, M.Feature):
                return True
            if isinstance(t, M.Attribute):
                return self._attr_base(t) == "bool"
            if isinstance(t, M.Constant):
                return t.type == "bool"
            return False
        if isinstance(e, M.Unary):
            return e.op == "!"
        if isinstance(e, M.Binary):
            return _ALIAS.get(e.op, e.op) in _LOGIC_OPS or e.op in _CMP_OPS or e.op == "in"
        if isinstance(e, M.Ternary):
            return self._is_bool(e.then)
        if isinstance(e, M.Aggregate):
            return e.func in ("and", "or", "xor")
        return False

    def _blit(self, e: M.Expr, ctx) -> Lit:
        b = self.b
        if isinstance(e, M.BoolLit):
            _check_read(e)
            return bool(e.value)
        if isinstance(e, M.Name):
            t = e.target
            if isinstance(t, M.Feature):
                if t not in self.var_of_feature:
                    raise NotEncodable(f"unknown feature {e.text}")
                return self.var_of_feature[t]
            if isinstance(t, M.Attribute):
                kind, val = self._attr_term(t, t.owner)
                if kind != "bool":
                    raise NotEncodable(f"{e.text} is not a boolean")
                return val
            if isinstance(t, M.Constant):
                return self._blit(t.value, ctx)
            raise NotEncodable(f"`{e.text}` cannot be interpreted as a boolean")
        if isinstance(e, M.Unary):
            if e.op == "!":
                return b.not_(self._blit(e.operand, ctx))
            raise NotEncodable(f"operator {e.op} on a boolean")
        if isinstance(e, M.Binary):
            op = _ALIAS.get(e.op, e.op)
            if op in ("&&", "||"):  # a long chain must not recurse
                xs = [self._blit(x, ctx) for x in _chain(e, op)]
                return b.and_(xs) if op == "&&" else b.or_(xs)
            if op in ("&&", "||", "->", "<-", "requires", "excludes"):
                l, r = self._blit(e.left, ctx), self._blit(e.right, ctx)
                if op == "&&":
                    return b.and_([l, r])
                if op == "||":
                    return b.or_([l, r])
                if op in ("->", "requires"):
                    return b.or_([b.not_(l), r])
                if op == "<-":
                    return b.or_([l, b.not_(r)])
                return b.not_(b.and_([l, r]))
            if op in ("<->",) or (op in ("==", "!=") and (self._is_bool(e.left) or self._is_bool(e.right))):
                x = b.iff(self._blit(e.left, ctx), self._blit(e.right, ctx))
                return b.not_(x) if op == "!=" else x
            if op in _CMP_OPS:
                return self._compare(op, self._vmap(e.left, ctx), self._vmap(e.right, ctx))
            if op == "in":
                vals = self._set_values(e.right, ctx)
                lhs = self._vmap(e.left, ctx)
                return b.or_([l for k, l in lhs.items() if k in vals])
            raise NotEncodable(f"operator {op} does not give a boolean")
        if isinstance(e, M.Ternary):
            return b.ite(self._blit(e.cond, ctx), self._blit(e.then, ctx), self._blit(e.other, ctx))
        if isinstance(e, M.Aggregate):
            if e.func not in ("and", "or", "xor"):
                raise NotEncodable(f"{e.func}(...) is not a boolean")
            items = self._agg_items(e, ctx, bool_=True)
            if e.func == "and":
                return b.and_([b.or_([b.not_(sel), x]) for sel, x in items])
            lits = [b.and_([sel, x]) for sel, x in items]
            if e.func == "or":
                return b.or_(lits)
            # xor: an odd number of them (parity chain)
            acc: Lit = False
            for x in lits:
                acc = b.or_([b.and_([acc, b.not_(x)]), b.and_([b.not_(acc), x])])
            return acc
        raise NotEncodable("a real-valued or unsupported expression")

    # ------------------------------------------------------------------ value terms
    def _compare(self, op: str, a: dict, c: dict) -> Lit:
        if len(a) * len(c) > MAX_VALUE_PAIRS:
            raise NotEncodable("the integer domains involved are too large")
        fn = {"==": lambda x, y: x == y, "!=": lambda x, y: x != y, "<": lambda x, y: x < y,
              "<=": lambda x, y: x <= y, ">": lambda x, y: x > y, ">=": lambda x, y: x >= y}[op]
        lits = []
        try:
            for va, la in a.items():
                for vc, lc in c.items():
                    if fn(va, vc):
                        lits.append(self.b.and_([la, lc]))
        except TypeError:
            raise NotEncodable("comparison of values of different types")
        return self.b.or_(lits)

    def _combine(self, a: dict, c: dict, fn) -> dict:
        if len(a) * len(c) > MAX_VALUE_PAIRS:
            raise NotEncodable("the integer domains involved are too large")
        acc: dict = {}
        for va, la in a.items():
            for vc, lc in c.items():
                acc.setdefault(fn(va, vc), []).append(self.b.and_([la, lc]))
        return self._merge(acc)

    def _merge(self, acc: dict) -> dict:
        out = {}
        for k, ls in acc.items():
            x = self.b.or_(ls)
            if x is not False:
                out[k] = x
        if len(out) > MAX_DOMAIN:
            raise NotEncodable("the integer domains involved are too large")
        return out

    def _ite_map(self, c: Lit, a: dict, d: dict) -> dict:
        acc: dict = {}
        for k, l in a.items():
            acc.setdefault(k, []).append(self.b.and_([c, l]))
        for k, l in d.items():
            acc.setdefault(k, []).append(self.b.and_([self.b.not_(c), l]))
        return self._merge(acc)

    def _const_value(self, e: M.Expr):
        if isinstance(e, M.IntLit):
            return int(e.value)
        if isinstance(e, M.Unary) and e.op == "-":
            return -self._const_value(e.operand)
        if isinstance(e, M.Name) and isinstance(e.target, M.Constant):
            return self._const_value(e.target.value)
        if isinstance(e, M.Name) and isinstance(e.target, M.EnumValue):
            return e.target.name
        if isinstance(e, M.Name) and e.target is None and len(e.parts) == 1:
            return e.parts[0]  # an enum value the resolver left alone
        if isinstance(e, M.RealLit):
            raise NotEncodable("real numbers")
        raise NotEncodable("a set element that is not a constant")

    def _set_values(self, e: Optional[M.Expr], ctx) -> set:
        if isinstance(e, M.SetLit):
            return {self._const_value(x) for x in e.items}
        if isinstance(e, M.RangeLit):
            lo, hi = self._const_value(e.lo), self._const_value(e.hi)
            if not isinstance(lo, int) or not isinstance(hi, int):
                raise NotEncodable("a range that is not made of integers")
            if hi - lo + 1 > MAX_DOMAIN:
                raise NotEncodable(f"the range [{lo}..{hi}] is too large")
            return set(range(lo, hi + 1))
        raise NotEncodable("a domain that is not a finite set or integer range")

    def _vmap(self, e: M.Expr, ctx) -> dict:
        b = self.b
        if isinstance(e, M.IntLit):
            return {int(e.value): True}
        if isinstance(e, M.RealLit):
            raise NotEncodable("it uses real numbers")
        if isinstance(e, M.BoolLit):
            _check_read(e)
            return {bool(e.value): True}
        if isinstance(e, M.Name):
            t = e.target
            if isinstance(t, M.Attribute):
                kind, val = self._attr_term(t, t.owner)
                if kind == "bool":
                    return self._bool_map(val)
                return val
            if isinstance(t, M.Constant):
                if t.type == "real":
                    raise NotEncodable(f"the constant {t.name} is real")
                return self._vmap(t.value, ctx)
            if isinstance(t, M.EnumValue):
                return {t.name: True}
            if isinstance(t, M.Feature):
                return self._bool_map(self._blit(e, ctx))
            if t is None and len(e.parts) == 1:
                return {e.parts[0]: True}
            raise NotEncodable(f"`{e.text}` has no value")
        if isinstance(e, M.Unary):
            if e.op == "-":
                return self._merge({-k: [l] for k, l in self._vmap(e.operand, ctx).items()})
            if e.op == "abs":
                acc: dict = {}
                for k, l in self._vmap(e.operand, ctx).items():
                    acc.setdefault(abs(k), []).append(l)
                return self._merge(acc)
            if e.op == "!":
                return self._bool_map(self._blit(e, ctx))
        if isinstance(e, M.Binary):
            if e.op in ("+", "-", "*"):
                fn = {"+": lambda x, y: x + y, "-": lambda x, y: x - y, "*": lambda x, y: x * y}[e.op]
                a, c = self._vmap(e.left, ctx), self._vmap(e.right, ctx)
                self._ints(a), self._ints(c)
                return self._combine(a, c, fn)
            if e.op == "/":
                raise NotEncodable("division gives real numbers")
            return self._bool_map(self._blit(e, ctx))
        if isinstance(e, M.Ternary):
            return self._ite_map(self._blit(e.cond, ctx), self._vmap(e.then, ctx), self._vmap(e.other, ctx))
        if isinstance(e, M.Aggregate):
            if e.func in ("and", "or", "xor"):
                return self._bool_map(self._blit(e, ctx))
            if e.func == "avg":
                raise NotEncodable("avg(...) gives real numbers")
            if e.func == "count":
                if e.over is None:
                    raise NotEncodable("count(...) over explicit values")
                items = [(sel, {1: True}) for sel, _ in self._agg_items(e, ctx, bool_=None)]
                return self._sum_items(items)
            # one operand at a time: a sum over thousands of children with big domains stops at
            # the first combination that is too large, before the next operands are encoded
            items = self._int_items(self._agg_items(e, ctx, bool_=False))
            if e.func == "sum":
                return self._sum_items(items)
            if e.func == "mul":
                acc = {1: True}
                for sel, m in items:
                    acc = self._combine(acc, self._ite_map(sel, m, {1: True}), lambda x, y: x * y)
                return acc
            if e.func in ("min", "max"):
                pick = min if e.func == "min" else max
                # none selected: 0 (TVL gives no value; 0 keeps the term total)
                acc2: Optional[dict] = None
                anysel: Lit = False
                for sel, m in items:
                    if acc2 is None:
                        acc2 = self._ite_map(sel, m, {0: True})
                    else:
                        both = self._combine(acc2, m, pick)
                        only_new = m
                        acc2 = self._ite_map(sel, self._ite_map(anysel, both, only_new), acc2)
                    anysel = b.or_([anysel, sel])
                return acc2 if acc2 is not None else {0: True}
            raise NotEncodable(f"aggregate {e.func}")
        raise NotEncodable("an unsupported expression")

    def _int_items(self, items):
        for sel, m in items:
            self._ints(m)
            yield sel, m

    def _ints(self, m: dict) -> None:
        for k in m:
            if isinstance(k, bool) or not isinstance(k, int):
                raise NotEncodable("arithmetic on values that are not integers")

    def _bool_map(self, x: Lit) -> dict:
        return self._merge({True: [x], False: [self.b.not_(x)]})

    def _sum_items(self, items) -> dict:
        acc: dict = {0: True}
        for sel, m in items:
            acc = self._combine(acc, self._ite_map(sel, m, {0: True}), lambda x, y: x + y)
        return acc

    def _agg_items(self, e: M.Aggregate, ctx, bool_):
        """(selected-literal, term) pairs of an aggregate's operands, encoded as they are taken."""
        if e.over is None:
            for a in e.args:
                yield True, self._blit(a, ctx) if bool_ else self._vmap(a, ctx)
            return
        owner = e.owner or ctx
        if owner is None or owner.group is None:
            return
        for gc in owner.group.children:
            ch = gc.feature
            sel: Lit = self.var_of_feature[ch] if e.over == "selectedChildren" else True
            if bool_ is None:
                yield sel, None
                continue
            attr = next((a for a in ch.attributes if a.name == e.attr), None)
            if attr is None:
                raise NotEncodable(f"child {ch.name} has no attribute {e.attr}")
            kind, val = self._attr_term(attr, ch)
            if bool_:
                if kind != "bool":
                    raise NotEncodable(f"{ch.name}.{e.attr} is not a boolean")
                yield sel, val
            else:
                yield sel, (self._bool_map(val) if kind == "bool" else val)

    # ------------------------------------------------------------------ attributes
    def _attr_base(self, a: M.Attribute) -> str:
        if a.type in ("bool", "int", "real", "enum"):
            return a.type
        if a.type_decl is not None:
            return a.type_decl.base
        return "unknown"

    def _attr_term(self, a: M.Attribute, owner: Optional[M.Feature]):
        key = id(a)
        got = self._attr_terms.get(key)
        if got is not None:
            if got[0] == "error":
                raise NotEncodable(got[1])
            return got
        if key in self._attr_busy:
            raise NotEncodable(f"the value of attribute {a.name} depends on itself")
        self._attr_busy.add(key)
        try:
            term = self._build_attr(a, owner)
        except NotEncodable as ex:
            self._attr_terms[key] = ("error", f"attribute {a.long_name}: {ex}")
            raise NotEncodable(f"attribute {a.long_name}: {ex}") from None
        finally:
            self._attr_busy.discard(key)
        self._attr_terms[key] = term
        return term

    def _build_attr(self, a: M.Attribute, owner: Optional[M.Feature]):
        if getattr(a, "has_errors", False):
            raise NotEncodable("it has errors (see them above)")
        b = self.b
        base = self._attr_base(a)
        fv: Lit = self.var_of_feature.get(owner, True) if owner is not None else True
        # (guard literal, value expr, domain expr): guard is a literal that must hold
        parts = []
        if a.value is not None or a.domain is not None:
            parts.append((True, a.value, a.domain))
        if a.if_in_value is not None or a.if_in_domain is not None:
            parts.append((fv, a.if_in_value, a.if_in_domain))
        if a.if_out_value is not None or a.if_out_domain is not None:
            parts.append((b.not_(fv), a.if_out_value, a.if_out_domain))
        ctx = owner
        if base == "bool":
            x = b.new_var()
            term = ("bool", x)
            self._attr_terms[id(a)] = term
            clauses: list[list[int]] = []
            for guard, val, dom in parts:
                if val is not None:
                    self._add_clause_list(clauses, [b.not_(guard), b.iff(x, self._blit(val, ctx))])
                if dom is not None:
                    vals = self._set_values(dom, ctx)
                    self._add_clause_list(clauses, [b.not_(guard)] + [x if v else -x for v in vals if isinstance(v, bool)])
            if clauses:
                self._add(Element("attribute", f"the value of attribute {a.long_name}", a.path, a.span, a, clauses))
            return term
        if base in ("real", "struct"):
            raise NotEncodable(f"its type is {base}")
        if base == "unknown":
            raise NotEncodable("its type is unknown")
        # enum / int: one-hot over a finite domain
        if base == "enum":
            evs = a.enum_values or (a.type_decl.enum_values if a.type_decl else [])
            domain = {ev.name for ev in evs}
            if not domain:
                raise NotEncodable("its enumeration has no values")
            global_dom = True
        else:
            domain = set()
            global_dom = False
            if a.type_decl is not None and a.type_decl.domain is not None:
                domain = self._set_values(a.type_decl.domain, ctx)
                global_dom = True
            covered = {"in": False, "out": False}
            vals_maps = []
            for guard, val, dom in parts:
                if dom is not None:
                    d = self._set_values(dom, ctx)
                elif val is not None:
                    vm = self._vmap(val, ctx)
                    vals_maps.append(vm)
                    d = set(vm)
                else:
                    continue
                if not global_dom:
                    domain |= d
                if guard is True:
                    covered = {"in": True, "out": True}
                elif guard == fv:
                    covered["in"] = True
                else:
                    covered["out"] = True
            if not global_dom and not (covered["in"] and covered["out"]):
                if not (fv is True and covered["in"]):
                    raise NotEncodable("its value is not bounded when "
                                       + ("its feature is not selected" if covered["in"] else "its feature is selected"
                                          if covered["out"] else "it has no value or domain"))
            if len(domain) > MAX_DOMAIN:
                raise NotEncodable("its domain is too large")
            self._ints({k: None for k in domain})
        ordered = sorted(domain, key=lambda x: (str(type(x)), x))
        xs = [b.new_var() for _ in ordered]
        b.exactly_one(xs)
        m = dict(zip(ordered, xs))
        term = ("map", m)
        self._attr_terms[id(a)] = term
        clauses = []
        for guard, val, dom in parts:
            if dom is not None:
                vals = self._set_values(dom, ctx)
                self._add_clause_list(clauses, [b.not_(guard)] + [l for k, l in m.items() if k in vals])
            if val is not None:
                self._add_clause_list(clauses, [b.not_(guard), self._compare("==", m, self._vmap(val, ctx))])
        if clauses:
            self._add(Element("attribute", f"the value of attribute {a.long_name}", a.path, a.span, a, clauses))
        return term

    @staticmethod
    def _add_clause_list(out: list, clause: list) -> None:
        c = _clean(clause)
        if c is not None:
            out.append(c)


def encode(model: M.Model) -> Encoding:
    enc = Encoding(model)
    enc._encode_structure()
    enc._encode_constraints()  # pulls in the attributes the constraints read
    enc._encode_attributes()
    return enc
