"""Phase 3 of model building: attribute values (``is``, ``ifIn:``, ``ifOut:``) and constraints
are resolved (names to features, attributes, constants, enum values, struct fields) and typed,
with the reference's type rules and domain checks.  :class:`ExprRules` is a mixin of
:class:`~tvl_lsp.tvl.build.ModelBuilder`."""

from __future__ import annotations

from typing import Optional

from ..base.diagnostics import Related
from . import model as m
from .codes import C_UNKNOWN, C_AMBIGUOUS, C_TYPE, C_OUT_OF_DOMAIN, C_PARENT_SHARED, C_TYPE_AS_VALUE, C_REF_REJECTS
from .raw import RawAttr, RawConstraint


class ExprRules:
    """Name resolution and typing of expressions (a mixin of the model builder)."""

    # ------------------------------------------------------------ phase 3: expressions
    def attr_values(self, f: Optional[m.Feature], a: m.Attribute, ra: RawAttr) -> None:
        before = len(self.diags)
        self._attr_values(f, a, ra)
        errs = [d for d in self.diags[before:] if d.severity == 1]
        if any(d.code != C_OUT_OF_DOMAIN for d in errs):
            a.has_errors = True  # reported: the analyses leave it out rather than guess
        elif errs:
            # a value outside the domain is well defined: it makes the feature dead (counts say so),
            # but the anomalies it causes are not reported a second time
            a.reported_error = True

    def _attr_values(self, f: Optional[m.Feature], a: m.Attribute, ra: RawAttr) -> None:
        base = self.base_type(a)
        for slot in ("value", "if_in_value", "if_out_value"):
            e = getattr(a, slot)
            if e is None:
                continue
            t = self.expr(e, f)
            self.check_value_in(a, e, t, base, slot)
        for slot in ("if_in_domain", "if_out_domain"):
            d = getattr(a, slot)
            if d is None:
                continue
            dom = a.domain if a.domain is not None else (a.type_decl.domain if a.type_decl else None)
            self.set_members(d, f, a, report_out=False)
            if dom is not None and not self.is_restriction(dom, d):
                self.diag(C_OUT_OF_DOMAIN, d._s, d._e, f"this set is not inside the domain of '{a.name}'")

    def domain_of(self, a: m.Attribute) -> Optional[m.Expr]:
        if a.domain is not None:
            return a.domain
        fd = getattr(a, "struct_field", None)
        if fd is not None and fd.domain is not None:
            return fd.domain
        if a.type_decl is not None:
            return a.type_decl.domain
        return None

    def check_value_in(self, a: m.Attribute, e: m.Expr, t: Optional[str], base: str, slot: str) -> None:
        if t is None:
            return
        word = {"value": "is", "if_in_value": "ifIn: is", "if_out_value": "ifOut: is"}[slot]
        dom = self.domain_of(a)
        tb = t.split(":")[0]
        if base == "struct" or base == "?":
            if base == "struct":
                self.diag(C_TYPE, e._s, e._e, f"struct attribute '{a.name}' cannot have a value")
            return
        if dom is not None and not self.value_in_domain(e, tb, dom, base):
            self.diag(C_OUT_OF_DOMAIN, e._s, e._e,
                      f"the value of '{a.name}' ({word}) lies outside its domain")
            return
        if dom is None and not (tb == base or (tb == "int" and base == "real")):
            self.diag(C_TYPE, e._s, e._e, f"'{a.name}' is {base} but this value is {tb}")

    def value_in_domain(self, e: m.Expr, tb: str, dom: m.Expr, base: str) -> bool:
        if base in ("int", "real"):
            if tb not in ("int", "real") or (base == "int" and tb != "int"):
                return False
            if not isinstance(e, (m.IntLit, m.RealLit)):
                return True
            if isinstance(e, m.IntLit) and e.value == 0:
                return True  # the reference never checks the integer 0 against a domain
            v = float(e.value)
            if isinstance(dom, m.SetLit):
                return any(isinstance(x, (m.IntLit, m.RealLit)) and float(x.value) == v for x in dom.items)
            if isinstance(dom, m.RangeLit):
                lo = None if getattr(dom.lo, "star", False) else getattr(dom.lo, "value", None)
                hi = None if getattr(dom.hi, "star", False) else getattr(dom.hi, "value", None)
                return (lo is None or v >= lo) and (hi is None or v <= hi)
            return True
        if base == "enum":
            if tb != "enum":
                return False
            if isinstance(e, m.Name) and len(e.parts) == 1 and isinstance(dom, m.SetLit):
                return any(isinstance(x, m.Name) and x.text == e.text for x in dom.items)
            return True
        return tb == base

    def constraint(self, f: m.Feature, rc: RawConstraint) -> None:
        c = m.Constraint(expr=rc.expr, kind=rc.kind, owner=f, span=self.sp(rc.start, rc.end),
                         path=self.smap.path(rc.start))
        f.constraints.append(c)
        before = len(self.diags)
        t = self.expr(rc.expr, f)
        if t is not None and t != "bool":
            if isinstance(rc.expr, m.Name) and getattr(rc.expr, "enum_fallback", False) and rc.expr.target is None:
                self._need(rc.expr, "bool", "a constraint")
            else:
                self.diag(C_TYPE, rc.expr._s, rc.expr._e,
                          f"a constraint must be a boolean expression; this one is {self._tname(t)}")
        errs = [d for d in self.diags[before:] if d.severity == 1]
        if any(d.code != C_OUT_OF_DOMAIN for d in errs):
            # reported: the analyses leave it out rather than guess what it means
            c.has_errors = True
        elif errs:
            c.reported_error = True  # encoded, but what it causes is not reported a second time

    @staticmethod
    def _tname(t: Optional[str]) -> str:
        if t is None:
            return "unknown"
        if t.startswith("enum"):
            return "an enum value"
        if t.startswith("struct"):
            return "a struct"
        return {"int": "an int", "real": "a real", "bool": "a boolean", "set": "a set"}.get(t, t)

    # resolution ------------------------------------------------------------
    def resolve(self, n: m.Name, cur: Optional[m.Feature]) -> Optional[str]:
        parts = n.parts
        ps = n.part_spans
        path = n.path
        head = parts[0]

        def err(code, i, msg, data=None, related=None):
            self.diag_at(code, path, ps[i], msg, data=data, related=related)
            return None

        def parent_of(f: m.Feature, i: int):
            if f.shared_parents:
                return err(C_PARENT_SHARED, i, f"'{f.name}' is shared (it has several parents): 'parent' is not allowed here")
            if f.parent is None:
                return err(C_UNKNOWN, i, f"'{f.name}' is the root: it has no parent")
            return f.parent

        feat: Optional[m.Feature] = None
        attr: Optional[m.Attribute] = None
        pts = n.part_targets
        del pts[:]
        if cur is None and head in ("this", "parent"):
            return err(C_UNKNOWN, 0, f"'{head}' can only be used inside a feature")
        if len(parts) == 1:
            if head == "this":
                n.target = cur
                pts.append(cur)
                return "bool"
            if head == "parent":
                p = parent_of(cur, 0)
                if p is None:
                    return None
                n.target = p
                pts.append(p)
                return "bool"
            if head == "root":
                n.target = self.root
                pts.append(self.root)
                return "bool"
            if head[:1].isupper() and head in self.table:
                f = self.table[head]
                if f is None:
                    cands = self.by_name.get(head, [])
                    paths = [self.non_ambiguous_path(x) for x in cands]
                    return err(C_AMBIGUOUS, 0, f"'{head}' is ambiguous: several features have this name; write one of "
                               + ", ".join(f"'{p}'" for p in paths), data={"candidates": paths},
                               related=[Related(x.path, x.name_span, self.non_ambiguous_path(x)) for x in cands[:10]])
                n.target = f
                pts.append(f)
                return "bool"
            if not head[:1].isupper() and cur is not None:
                a = next((x for x in cur.attributes if x.name == head), None)
                if a is not None:
                    n.target = a
                    n.feature = cur
                    pts.append(a)
                    return self.attr_type(a)
            if head in self.constants:
                c = self.constants[head]
                n.target = c
                pts.append(c)
                return c.type
            if head in self.types:
                return err(C_TYPE_AS_VALUE, 0, f"'{head}' is a type, not a value")
            # the reference reads any other single name as an enum value
            evs = self.enum_values_named(head)
            n.target = evs[0] if evs else None
            pts.append(n.target)
            n.enum_fallback = True
            n.context_feature = cur
            if n.target is None:  # for a "did you mean" if it turns out to be used as something else
                n.fallback_candidates = ([x.name for x in cur.attributes] if cur is not None else []) \
                    + list(self.constants) + list(self.table)
            return "enum"
        # dotted names
        i0 = 1
        if head == "parent":
            feat = parent_of(cur, 0)
        elif head == "this":
            feat = cur
        elif head == "root":
            feat = self.root
        elif head[:1].isupper():
            if head not in self.table:
                return err(C_UNKNOWN, 0, f"no feature named '{head}'." + self._suggest(head, self.table.keys()),
                           data={"name": head, "suggestions": self._close(head, self.table.keys())})
            feat = self.table[head]
            if feat is None:
                cands = self.by_name.get(head, [])
                paths = [self.non_ambiguous_path(x) + "." + ".".join(parts[1:]) for x in cands]
                return err(C_AMBIGUOUS, 0, f"'{head}' is ambiguous: several features have this name; write one of "
                           + ", ".join(f"'{p}'" for p in paths), data={"candidates": paths},
                           related=[Related(x.path, x.name_span, self.non_ambiguous_path(x)) for x in cands[:10]])
        else:
            if cur is None:
                return err(C_UNKNOWN, 0, f"no attribute '{head}' here")
            attr = next((x for x in cur.attributes if x.name == head), None)
            if attr is None:
                return err(C_UNKNOWN, 0, f"feature '{cur.name}' has no attribute '{head}'."
                           + self._suggest(head, [x.name for x in cur.attributes] + list(self.table.keys())),
                           data={"name": head, "suggestions": self._close(head, [x.name for x in cur.attributes])})
            feat = cur
        if feat is None and attr is None:
            return None
        pts.append(attr if attr is not None else feat)
        for i in range(i0, len(parts)):
            p = parts[i]
            if attr is not None:
                # struct field
                sub = self.struct_field(attr, p)
                if sub is None or i != len(parts) - 1:
                    return err(C_UNKNOWN, i, f"'{attr.name}' has no field '{p}'")
                attr = sub
                pts.append(sub)
                continue
            if p == "parent":
                feat = parent_of(feat, i)
                if feat is None:
                    return None
                pts.append(feat)
            elif p[:1].isupper():
                kids = {c.feature.name: c.feature for c in (feat.group.children if feat.group else [])}
                if p not in kids:
                    return err(C_UNKNOWN, i, f"feature '{feat.name}' has no child named '{p}'."
                               + self._suggest(p, kids.keys()), data={"name": p, "suggestions": self._close(p, kids.keys())})
                feat = kids[p]
                pts.append(feat)
            else:
                a = next((x for x in feat.attributes if x.name == p), None)
                if a is None:
                    return err(C_UNKNOWN, i, f"feature '{feat.name}' has no attribute '{p}'."
                               + self._suggest(p, [x.name for x in feat.attributes]), data={"name": p, "suggestions": self._close(p, [x.name for x in feat.attributes])})
                attr = a
                pts.append(a)
        if attr is not None:
            n.target = attr
            n.feature = feat
            return self.attr_type(attr)
        n.target = feat
        return "bool"

    def struct_field(self, attr: m.Attribute, name: str) -> Optional[m.Attribute]:
        if name in attr.field_refinements:
            return attr.field_refinements[name]
        td = attr.type_decl
        if td is not None and td.base == "struct":
            return next((x for x in td.fields if x.name == name), None)
        return None

    def attr_type(self, a: m.Attribute) -> str:
        b = self.base_type(a)
        if b == "enum":
            return "enum:" + (a.type_decl.name if a.type_decl else a.long_name)
        if b == "struct":
            return "struct:" + a.type
        if b == "?":
            return None
        return b

    def enum_values_named(self, name: str) -> list[m.EnumValue]:
        idx = getattr(self, "_enum_index", None)
        if idx is None:  # built once, after phase 1 declared every enum value
            idx = {}
            for td in self.types.values():
                for v in td.enum_values:
                    idx.setdefault(v.name, []).append(v)
            for f in self.model.features:
                for a in f.attributes:
                    for v in a.enum_values:
                        idx.setdefault(v.name, []).append(v)
            self._enum_index = idx
        return idx.get(name, [])

    # typing ------------------------------------------------------------------
    BOOL_OPS = {"&&", "||", "->", "<-", "<->", "requires", "excludes"}
    CMP_OPS = {">=", "<=", ">", "<"}
    ARITH_OPS = {"+", "-", "*", "/"}

    def expr(self, e: m.Expr, cur: Optional[m.Feature]) -> Optional[str]:
        """Type-check ``e`` (iteratively over the tree: deep input must not recurse)."""
        # post-order traversal with an explicit stack
        stack = [(e, False)]
        while stack:
            node, done = stack.pop()
            if not done:
                stack.append((node, True))
                for ch in self._children(node):
                    stack.append((ch, False))
                continue
            node.type = self._type_of(node, cur)
        return e.type

    @staticmethod
    def _children(node: m.Expr) -> list[m.Expr]:
        if isinstance(node, m.Binary):
            return [node.left, node.right]
        if isinstance(node, m.Unary):
            return [node.operand]
        if isinstance(node, m.Ternary):
            return [node.cond, node.then, node.other]
        if isinstance(node, m.Aggregate):
            return list(node.args)
        if isinstance(node, m.SetLit):
            return []  # typed by the 'in' operator
        if isinstance(node, m.RangeLit):
            return []
        return []

    def _bad(self, node: m.Expr, msg: str) -> None:
        self.diag(C_TYPE, node._s, node._e, msg)

    def _need(self, node: m.Expr, want: str, ctx: str) -> bool:
        t = node.type
        if t is None:
            return False
        tb = t.split(":")[0]
        ok = (tb == want) or (want == "num" and tb in ("int", "real"))
        if not ok:
            if self._unresolved(node):
                self._report_unresolved(node)
            else:
                self._bad(node, f"{ctx} expects {'a number' if want == 'num' else 'a boolean' if want == 'bool' else want}, "
                                f"but this is {self._tname(t)}")
            return False
        return True

    def _type_of(self, node: m.Expr, cur: Optional[m.Feature]) -> Optional[str]:
        if getattr(node, "too_deep", False):
            return None
        if isinstance(node, m.IntLit):
            return "int"
        if isinstance(node, m.RealLit):
            return "real"
        if isinstance(node, m.BoolLit):
            return "bool"
        if isinstance(node, m.Name):
            return self.resolve(node, cur)
        if isinstance(node, m.Unary):
            if node.op == "!":
                return "bool" if self._need(node.operand, "bool", "'!'") else None
            if node.operand.type is None:
                return None
            if not self._need(node.operand, "num", f"'{node.op}'"):
                return None
            return node.operand.type
        if isinstance(node, m.Ternary):
            self._need(node.cond, "bool", "the condition of '?:'")
            a, b = node.then.type, node.other.type
            if a is None or b is None:
                return None
            return self._unify(node, a, b, "the branches of '?:'")
        if isinstance(node, m.Binary):
            op = node.op
            l, r = node.left, node.right
            if op in self.BOOL_OPS:
                ok1 = self._need(l, "bool", f"'{op}'")
                ok2 = self._need(r, "bool", f"'{op}'")
                return "bool" if (ok1 and ok2) or (l.type is None or r.type is None) else None
            if op in self.ARITH_OPS:
                if l.type is None or r.type is None:
                    return None
                ok1 = self._need(l, "num", f"'{op}'")
                ok2 = self._need(r, "num", f"'{op}'")
                if not (ok1 and ok2):
                    return None
                return "int" if l.type == "int" and r.type == "int" else "real"
            if op in self.CMP_OPS:
                if l.type is None or r.type is None:
                    return "bool"
                if self._two_enum_values(node, l, r) or self._domains_differ(node, l, r):
                    return "bool"
                lb, rb = l.type.split(":")[0], r.type.split(":")[0]
                if lb == "enum" and rb == "enum":
                    return "bool"
                if self._need(l, "num", f"'{op}'") and self._need(r, "num", f"'{op}'") \
                        and not self._two_numbers(node, l, r):
                    self._domain_compare(l, r)
                    self._domain_compare(r, l)
                return "bool"
            if op in ("==", "!="):
                if l.type is None or r.type is None:
                    return "bool"
                if self._two_enum_values(node, l, r) or self._domains_differ(node, l, r):
                    return "bool"
                for side, other in ((l, r), (r, l)):
                    if self._unresolved(side) and not other.type.startswith("enum"):
                        self._report_unresolved(side)
                        return "bool"
                if self._unify(node, l.type, r.type, f"'{op}'") is not None and self._two_numbers(node, l, r):
                    return "bool"
                self._domain_compare(l, r)
                self._domain_compare(r, l)
                return "bool"
            if op == "in":
                self.set_members(r, cur, l.target if isinstance(l, m.Name) and isinstance(l.target, m.Attribute) else None,
                                 l.type)
                return "bool"
        if isinstance(node, m.Aggregate):
            return self._aggregate(node, cur)
        return None

    @staticmethod
    def _enum_literal(node) -> bool:
        return isinstance(node, m.Name) and getattr(node, "enum_fallback", False)

    def _two_enum_values(self, node: m.Binary, l: m.Expr, r: m.Expr) -> bool:
        """The reference reads a single name that is no attribute of the constraint's feature,
        no constant and no feature as an enum value -- and rejects comparing two enum values
        ("You cannot compare two enum values").  Reported once: on the names that are no enum
        value (an attribute of another feature, or nothing), else on the comparison."""
        if not (self._enum_literal(l) and self._enum_literal(r)):
            return False
        unresolved = [x for x in (l, r) if x.target is None]
        for x in unresolved:
            self._report_unresolved(x)
        if not unresolved:
            self._bad(node, f"'{l.text} {node.op} {r.text}' compares two enum values (TVL reads a name that is no "
                            "attribute of this feature as an enum value): one side must be an attribute")
        return True

    def _two_numbers(self, node: m.Binary, l: m.Expr, r: m.Expr) -> bool:
        """The reference compares numbers only when one side names an attribute ("you cannot
        compare two numerical values": 1 + 1 == 2, p + 1 <= 2, abs(p) < 3, sum(...) <= 10)."""
        if not (l.type and r.type and l.type.split(":")[0] in ("int", "real") and r.type.split(":")[0] in ("int", "real")):
            return False
        if any(isinstance(x, m.Name) and isinstance(x.target, m.Attribute) for x in (l, r)):
            return False
        # the team's choice (tests/data/tvl/reference/diverge_arithmetic_comparison.tvl): analysed and
        # counted, with a warning for models that must also pass the reference
        self.diag(C_REF_REJECTS, node._s, node._e,
                  f"'{node.op}' compares two computed numbers: tvl-lsp analyses it, but the TVL reference parser "
                  "rejects it (\"you cannot compare two numerical values\"); for a model it must read too, write "
                  "the computation into an attribute (e.g. int total is ...;) and compare that")
        return False

    def _domains_differ(self, node: m.Binary, l: m.Expr, r: m.Expr) -> bool:
        """The reference compares two attributes only when their domains are the same: enum
        values in the same order, or the same set of numbers ("haven't the same values domain")."""
        if not (isinstance(l, m.Name) and isinstance(l.target, m.Attribute)
                and isinstance(r, m.Name) and isinstance(r.target, m.Attribute)):
            return False
        a, b = l.target, r.target
        ba, bb = self.base_type(a), self.base_type(b)
        if ba == "enum" and bb == "enum":
            va = [v.name for v in (a.enum_values or (a.type_decl.enum_values if a.type_decl else []))]
            vb = [v.name for v in (b.enum_values or (b.type_decl.enum_values if b.type_decl else []))]
            if not va or not vb or va == vb:
                return False
            self._bad(node, f"'{l.text}' and '{r.text}' cannot be compared: their enum values differ "
                            f"({{{', '.join(va)}}} and {{{', '.join(vb)}}}; TVL compares enum attributes only when "
                            "they list the same values in the same order)")
            return True
        if ba in ("int", "real") and bb in ("int", "real"):
            da, db = _values_of(self.domain_of(a)), _values_of(self.domain_of(b))
            if da is None or db is None or da == db:
                return False
            self._bad(node, f"'{l.text}' and '{r.text}' cannot be compared: their domains differ (TVL compares two "
                            "number attributes only when they have the same domain)")
            return True
        return False

    @staticmethod
    def _unresolved(node) -> bool:
        """A single name the reference would read as an enum value, though no enum has it."""
        return isinstance(node, m.Name) and getattr(node, "enum_fallback", False) and node.target is None

    def _report_unresolved(self, node: m.Name) -> None:
        if node.text in self.table:
            self.diag_at(C_UNKNOWN, node.path, node.span,
                         f"'{node.text}' is a feature, but TVL reads a name that does not begin with an "
                         f"upper-case letter as an attribute or an enum value: rename the feature to use it "
                         f"in a constraint", data={"name": node.text})
            return
        owners = [f for f in self.model.features if any(a.name == node.text for a in f.attributes)]
        if owners:
            cur = getattr(node, "context_feature", None)
            o = owners[0]
            ref = ("parent." if cur is not None and cur.parent is o else
                   "root." if o is self.root else self.non_ambiguous_path(o) + ".") + node.text
            where = f"not of {cur.name}" if cur is not None else "not visible here"
            self.diag_at(C_UNKNOWN, node.path, node.span,
                         f"'{node.text}' is an attribute of {o.name}, {where}: TVL reads it here as an enum value; "
                         f"write '{ref}'", data={"name": node.text, "suggestions": [ref]},
                         related=[Related(a.path, a.name_span, f"{o.name}.{a.name}")
                                  for a in o.attributes if a.name == node.text])
            return
        cands = getattr(node, "fallback_candidates", None) or (list(self.table) + list(self.constants))
        self.diag_at(C_UNKNOWN, node.path, node.span,
                     f"no feature, attribute, constant or enum value is named '{node.text}'."
                     + self._suggest(node.text, cands),
                     data={"name": node.text, "suggestions": self._close(node.text, cands)})

    def _unify(self, node, a: str, b: str, ctx: str) -> Optional[str]:
        ab, bb = a.split(":")[0], b.split(":")[0]
        if ab == bb:
            return a
        if {ab, bb} == {"int", "real"}:
            return "real"
        self._bad(node, f"{ctx}: cannot compare {self._tname(a)} with {self._tname(b)}")
        return None

    def _domain_compare(self, attr_side: m.Expr, val_side: m.Expr) -> None:
        if not (isinstance(attr_side, m.Name) and isinstance(attr_side.target, m.Attribute)):
            return
        a = attr_side.target
        dom = self.domain_of(a)
        if dom is None or val_side.type is None:
            return
        base = self.base_type(a)
        if isinstance(val_side, (m.IntLit, m.RealLit)) or (isinstance(val_side, m.Name) and getattr(val_side, "enum_fallback", False)):
            if not self.value_in_domain(val_side, val_side.type.split(":")[0], dom, base):
                self.diag(C_OUT_OF_DOMAIN, val_side._s, val_side._e,
                          f"'{val_side.text if isinstance(val_side, m.Name) else val_side.value}' is not in the domain of '{a.name}'")
            elif isinstance(val_side, m.Name) and base == "enum":
                ev = next((v for v in (a.enum_values or (a.type_decl.enum_values if a.type_decl else [])) if v.name == val_side.text), None)
                if ev is not None:
                    val_side.target = ev
                    val_side.part_targets = [ev]

    def set_members(self, s: m.Expr, cur, attr: Optional[m.Attribute], left_type: Optional[str] = None,
                    report_out: bool = True) -> None:
        s.type = "set"
        items = s.items if isinstance(s, m.SetLit) else [s.lo, s.hi] if isinstance(s, m.RangeLit) else []
        for it in items:
            if getattr(it, "star", False):
                continue
            self.expr(it, cur)
        if left_type is not None:
            lb = left_type.split(":")[0]
            for it in items:
                if getattr(it, "star", False) or it.type is None:
                    continue
                ib = it.type.split(":")[0]
                if not (ib == lb or {ib, lb} == {"int", "real"}):
                    self._bad(it, f"'in': this member is {self._tname(it.type)} but the left side is {self._tname(left_type)}")
        if attr is not None:
            dom = self.domain_of(attr)
            if dom is not None and isinstance(s, m.SetLit):
                base = self.base_type(attr)
                for it in items:
                    if it.type is None:
                        continue
                    if isinstance(it, (m.IntLit, m.RealLit)) or (isinstance(it, m.Name) and getattr(it, "enum_fallback", False)):
                        if not self.value_in_domain(it, it.type.split(":")[0], dom, base):
                            if report_out:
                                self.diag(C_OUT_OF_DOMAIN, it._s, it._e,
                                          f"'{it.text if isinstance(it, m.Name) else it.value}' is not in the domain "
                                          f"of '{attr.name}'")
                        elif isinstance(it, m.Name):
                            ev = next((v for v in (attr.enum_values or (attr.type_decl.enum_values if attr.type_decl else [])) if v.name == it.text), None)
                            if ev is not None:
                                it.target = ev
                                it.part_targets = [ev]

    def _aggregate(self, node: m.Aggregate, cur: Optional[m.Feature]) -> Optional[str]:
        f = node.func
        if f == "count":
            node.owner = cur
            return "int"
        boolean = f in ("and", "or", "xor")
        if node.over is not None:
            node.owner = cur
            if cur is None:
                self._bad(node, f"'{node.over}' can only be used inside a feature")
                return None
            kids = cur.children
            types = set()
            attrs = []
            for k in kids:
                a = next((x for x in k.attributes if x.name == node.attr), None)
                if a is not None:
                    attrs.append(a)
                    t = self.attr_type(a)
                    if t:
                        types.add(t.split(":")[0])
            if not attrs:
                self.diag_at(C_UNKNOWN, node.path, node.attr_span or node.span,
                             f"no child of '{cur.name}' has an attribute '{node.attr}'", data={"name": node.attr})
                return None
            node.child_attrs = attrs
            if boolean:
                if types - {"bool"}:
                    self._bad(node, f"'{f}' aggregates booleans but '{node.attr}' is not bool")
                    return None
                return "bool"
            if types - {"int", "real"}:
                self._bad(node, f"'{f}' aggregates numbers but '{node.attr}' is not a number")
                return None
            return "real" if "real" in types else "int"
        ts = [a.type for a in node.args]
        if any(t is None for t in ts):
            return "bool" if boolean else None
        if boolean:
            ok = all(self._need(a, "bool", f"'{f}(...)'") for a in node.args)
            return "bool" if ok else None
        ok = all(self._need(a, "num", f"'{f}(...)'") for a in node.args)
        if not ok:
            return None
        return "real" if any(t == "real" for t in ts) else "int"


def _values_of(dom: Optional[m.Expr]):
    """A number domain as a comparable value: a frozenset of its values, ('range', lo, hi) for a
    long or unbounded interval; None when unknown (no domain, or not made of literals)."""
    if isinstance(dom, m.SetLit):
        vals = []
        for x in dom.items:
            if not isinstance(x, (m.IntLit, m.RealLit)):
                return None
            vals.append(float(x.value))
        return frozenset(vals)
    if isinstance(dom, m.RangeLit):
        lo = None if getattr(dom.lo, "star", False) else getattr(dom.lo, "value", None)
        hi = None if getattr(dom.hi, "star", False) else getattr(dom.hi, "value", None)
        if lo is None or (hi is not None and not isinstance(hi, (int, float))) or not isinstance(lo, (int, float)):
            return None
        if hi is not None and float(hi) - float(lo) <= 4096 and float(lo).is_integer():
            return frozenset(float(v) for v in range(int(lo), int(hi) + 1))
        return ("range", float(lo), None if hi is None else float(hi))
    return None
