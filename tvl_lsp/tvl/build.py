"""Model building, name resolution and the reference's semantic checks.

Mirrors TVLParser's ``FeaturesSymbolTable`` (three phases):

1. features and attributes are created in file order (a reopening ``A { }`` / ``A.B { }`` may
   only name a feature declared before it; a short name is ambiguous once two features carry
   it); attribute domains and group cardinalities are checked;
2. ``shared`` children are attached (the DAG must stay acyclic);
3. attribute values (``is``, ``ifIn:``, ``ifOut:``) and constraints are resolved and typed.

Phases 1 and 2 are here; phase 3 (names and types in expressions) is ``resolve.py``, the codes
``codes.py``.

Where the reference is lenient (it only *prints* a message for duplicate children and does not
enforce upper-case names for children in a group) the corresponding diagnostic is a warning.
"""

from __future__ import annotations

import difflib
from typing import Iterable, Optional

from ..base.diagnostics import Diagnostic, Fix, Related, Severity, TextEdit
from ..base.text import Span
from . import model as m
from .codes import (E, W, C_FIRST_NOT_ROOT, C_ROOT_LONG, C_LONG_IN_GROUP, C_ROOT_NAME_REUSED, C_DUP_FEATURE,
                    C_DUP_SHARED, C_MULTI_GROUPS, C_UNKNOWN, C_AMBIGUOUS, C_CARD_BOUNDS, C_CARD_EXCEEDS,
                    C_CARD_UPPER, C_TYPE, C_NAMING, C_DUP_ATTR, C_DUP_DECL, C_NAME_CONFLICT, C_DOMAIN,
                    C_UNKNOWN_TYPE, C_NOT_STRUCT, C_UNKNOWN_FIELD, C_CYCLE, C_BAD_TYPE_DECL, C_ENUM_NO_VALUES,
                    C_DUP_PART)
from .parser import SourceMap
from .raw import (RawAttr, RawBody, RawChild, RawConst, RawConstraint, RawData, RawFeatureDecl, RawGroup,
                  RawType)
from .resolve import ExprRules


class ModelBuilder(ExprRules):
    def __init__(self, smap: SourceMap, items: list, model: m.Model, diags: list[Diagnostic]):
        self.smap = smap
        self.items = items
        self.model = model
        self.diags = diags
        self.types: dict[str, m.TypeDecl] = {}
        self.constants: dict[str, m.Constant] = {}
        self.table: dict[str, Optional[m.Feature]] = {}
        self.by_name: dict[str, list[m.Feature]] = {}
        self.root: Optional[m.Feature] = None
        self.enum_values: dict[str, list[m.EnumValue]] = {}
        self.pending_shared: list[tuple[m.Feature, RawChild, m.Group]] = []
        self.pending_attrs: list[tuple[m.Feature, m.Attribute, RawAttr]] = []
        self.pending_constraints: list[tuple[m.Feature, RawConstraint]] = []
        self.cycle_edges_reported = False
        self.sp = smap.span  # (start offset, end offset) -> Span

    # ------------------------------------------------------------ diagnostics

    def diag(self, code: str, s: int, e: int, msg: str, sev: Optional[Severity] = None, related=None,
             fixes=None, data=None):
        from ..base.diagnostics import CODES
        sev = sev if sev is not None else CODES[code].severity
        path, span = self.smap.path(s), self.sp(s, e)
        if fixes is None and data and "suggestions" in data:
            fixes = self._fixes(path, span, data["suggestions"])
        self.diags.append(Diagnostic(code, sev, path, span, msg,
                                     related=list(related or []), fixes=list(fixes or []), data=data))

    def diag_at(self, code: str, path: str, span: Span, msg: str, sev: Optional[Severity] = None,
                related=None, data=None, fixes=None):
        from ..base.diagnostics import CODES
        sev = sev if sev is not None else CODES[code].severity
        if fixes is None and data and "suggestions" in data:
            fixes = self._fixes(path, span, data["suggestions"])
        self.diags.append(Diagnostic(code, sev, path, span, msg, related=list(related or []), data=data,
                                     fixes=list(fixes or [])))

    @staticmethod
    def _fixes(path: str, span: Span, names: list[str]) -> list[Fix]:
        return [Fix(f"Change to '{n}'", (TextEdit(path, span, n),), i == 0 and len(names) == 1)
                for i, n in enumerate(names)]

    @staticmethod
    def _close(name: str, candidates: Iterable[str]) -> list[str]:
        return difflib.get_close_matches(name, sorted(set(candidates) - {name}), n=3, cutoff=0.6)

    @staticmethod
    def _suggest(name: str, candidates: Iterable[str]) -> str:
        close = difflib.get_close_matches(name, sorted(set(candidates) - {name}), n=3, cutoff=0.6)
        if not close:
            return ""
        return " Did you mean " + " or ".join(f"'{c}'" for c in close) + "?"

    # ------------------------------------------------------------ entry
    def run(self) -> None:
        for it in self.items:
            if isinstance(it, RawType):
                self.add_type(it)
        for it in self.items:
            if isinstance(it, RawConst):
                self.add_const(it)
        first = True
        for it in self.items:
            if isinstance(it, RawFeatureDecl):
                self.feature_decl(it, first)
                first = False
        self.check_type_enum_conflicts()
        self.attach_shared()
        self.detect_cycles()
        for f, attr, raw in self.pending_attrs:
            self.attr_values(f, attr, raw)
        for f, rc in self.pending_constraints:
            self.constraint(f, rc)
        self.model.root = self.root

    # ------------------------------------------------------------ types and constants
    def add_type(self, rt: RawType) -> None:
        name = rt.name_tok.value
        path = self.smap.path(rt.start)
        kw = rt.kw.value
        td = m.TypeDecl(name=name, base=kw if kw in ("int", "real", "bool", "enum", "struct") else kw,
                        span=self.sp(rt.start, rt.end), name_span=self.sp(rt.name_tok.start, rt.name_tok.end),
                        path=path, domain=rt.domain)
        if name[:1].isupper():
            self.diag(C_NAMING, rt.name_tok.start, rt.name_tok.end,
                      f"type name '{name}' must begin with a lower-case letter", sev=E)
        if name in self.types:
            prev = self.types[name]
            self.diag(C_DUP_DECL, rt.name_tok.start, rt.name_tok.end, f"type '{name}' is declared twice",
                      related=[Related(prev.path, prev.name_span, "first declared here")])
        else:
            self.types[name] = td
        self.model.types.append(td)
        if kw == "struct":
            seen: dict[str, m.Attribute] = {}
            for rf in rt.fields:
                a = self.make_attr(rf, None)
                if a is None:
                    continue
                if a.name in seen:
                    self.diag(C_DUP_ATTR, rf.name_tok.start, rf.name_tok.end,
                              f"struct '{name}' has two fields named '{a.name}'")
                    continue
                seen[a.name] = a
                td.fields.append(a)
                self.pending_attrs.append((None, a, rf))
            return
        if kw == "enum" and rt.domain is None:
            self.diag(C_BAD_TYPE_DECL, rt.kw.start, rt.name_tok.end,
                      f"enum type '{name}' needs its values: enum {name} in {{a, b}};")
        if kw == "bool" and rt.domain is not None:
            self.diag(C_BAD_TYPE_DECL, rt.kw.start, rt.end, f"a bool type cannot have a domain")
        if rt.domain is not None:
            vals = self.check_domain(kw, rt.domain, name, None)
            for v in vals:
                ev = m.EnumValue(v[0], v[1], path, td)
                td.enum_values.append(ev)

    def add_const(self, rc: RawConst) -> None:
        name = rc.name_tok.value
        ty = rc.type_tok.value
        c = m.Constant(name=name, type=ty, value=rc.value, span=self.sp(rc.start, rc.end),
                       name_span=self.sp(rc.name_tok.start, rc.name_tok.end), path=self.smap.path(rc.start))
        if name[:1].isupper():
            self.diag(C_NAMING, rc.name_tok.start, rc.name_tok.end,
                      f"constant name '{name}' must begin with a lower-case letter", sev=E)
        if name in self.constants or name in self.types:
            self.diag(C_DUP_DECL, rc.name_tok.start, rc.name_tok.end,
                      f"'{name}' is already declared as a {'constant' if name in self.constants else 'type'}")
        else:
            self.constants[name] = c
        self.model.constants.append(c)
        if ty == "enum":
            self.diag(C_BAD_TYPE_DECL, rc.type_tok.start, rc.type_tok.end, "a constant cannot be of type enum")
        vt = self.literal_type(rc.value)
        if vt is None:
            self.diag(C_TYPE, rc.value._s, rc.value._e, f"the value of constant '{name}' must be a literal")
        elif not (vt == ty or (vt == "int" and ty == "real")):
            self.diag(C_TYPE, rc.value._s, rc.value._e,
                      f"constant '{name}' is declared {ty} but its value is {vt}")
        rc.value.type = vt

    @staticmethod
    def literal_type(e: m.Expr) -> Optional[str]:
        if isinstance(e, m.IntLit):
            return "int"
        if isinstance(e, m.RealLit):
            return "real"
        if isinstance(e, m.BoolLit) and not getattr(e, "too_deep", False):
            return "bool"
        return None

    # ------------------------------------------------------------ domains
    def check_domain(self, ty: str, dom: m.Expr, owner: str, feature_ctx) -> list[tuple[str, Span, int, int]]:
        """Check an ``in SET`` domain of type ``ty``; returns the enum values it declares."""
        out = []
        if isinstance(dom, m.RangeLit):
            dom.type = "set"
            if ty == "enum" or ty == "bool":
                self.diag(C_DOMAIN, dom._s, dom._e, f"'{owner}': an {ty} domain must list its values, not an interval")
                return out
            lo, hi = dom.lo, dom.hi
            for b in (lo, hi):
                if getattr(b, "star", False):
                    if b is lo:
                        self.diag(C_DOMAIN, b._s, b._e, f"'{owner}': the lower bound of an interval cannot be *")
                    continue
                bt = self.literal_type(b)
                b.type = bt
                if bt not in ("int", "real") or (ty == "int" and bt != "int"):
                    self.diag(C_DOMAIN, b._s, b._e,
                              f"'{owner}' is {ty}: the interval bound must be an {ty} literal")
                    return out
            if not getattr(hi, "star", False) and not getattr(lo, "star", False) and hi.value < lo.value:
                self.diag(C_DOMAIN, dom._s, dom._e,
                          f"'{owner}': empty interval, the upper bound {hi.value} is smaller than the lower bound {lo.value}")
            return out
        if not isinstance(dom, m.SetLit):
            return out
        dom.type = "set"
        seen: dict = {}
        for it in dom.items:
            if ty in ("int", "real"):
                lt = self.literal_type(it)
                it.type = lt
                if lt not in ("int", "real") or (ty == "int" and lt != "int"):
                    if isinstance(it, m.Name) and len(it.parts) == 1 and lt is None:
                        what = f"'{it.text}'"
                    else:
                        what = "this value"
                    self.diag(C_DOMAIN, it._s, it._e,
                              f"the domain of '{owner}' is {ty}: {what} is not an {ty} literal")
                    continue
                key = float(it.value)
                if lt == "int" and it.value == 0:
                    # TVLParser v20100804 rejects the integer 0 in a set domain ("a set expression may
                    # only contain simple values"), though not in an interval or a value
                    self.diag(C_DOMAIN, it._s, it._e,
                              f"the TVL reference parser does not accept 0 in a set domain ('{owner}'): leave the "
                              f"domain out (the value parts already say it) or use an interval such as [0..n]")
                    continue
            else:
                if not (isinstance(it, m.Name) and len(it.parts) == 1):
                    self.diag(C_DOMAIN, it._s, it._e,
                              f"the domain of '{owner}' is enum: its members must be plain names")
                    continue
                nm = it.parts[0]
                it.type = "enum"
                if nm in ("this", "parent", "root"):
                    self.diag(C_DOMAIN, it._s, it._e, f"'{nm}' cannot be an enum value")
                    continue
                if nm in self.constants or nm in self.types or (self.table.get(nm, None) is not None or nm in self.table):
                    kind = "constant" if nm in self.constants else "type" if nm in self.types else "feature"
                    self.diag(C_NAME_CONFLICT, it._s, it._e,
                              f"enum value '{nm}' of '{owner}' is also the name of a {kind}")
                key = nm
                out.append((nm, it.span, it._s, it._e))
            if key in seen:
                self.diag(C_DOMAIN, it._s, it._e, f"the domain of '{owner}' lists {it.text if isinstance(it, m.Name) else key} twice")
            seen[key] = it
        return out

    def check_type_enum_conflicts(self) -> None:
        for td in self.types.values():
            for ev in td.enum_values:
                if ev.name in self.table:
                    fs = self.by_name.get(ev.name, [])
                    rel = [Related(f.path, f.name_span, "the feature") for f in fs[:3]]
                    self.diag_at(C_NAME_CONFLICT, ev.path, ev.span,
                                 f"enum value '{ev.name}' of type '{td.name}' is also the name of a feature",
                                 related=rel)

    # ------------------------------------------------------------ features
    def _new_feature(self, name: str, tok_s: int, tok_e: int, s: int, e: int, parent) -> m.Feature:
        path = self.smap.path(tok_s)
        f = m.Feature(name=name, span=self.sp(s, e), name_span=self.sp(tok_s, tok_e), path=path, parent=parent)
        f.decl_spans.append((path, f.name_span))
        self.model.features.append(f)
        return f

    def _register(self, f: m.Feature) -> None:
        if f.name in self.table:
            self.table[f.name] = None
        else:
            self.table[f.name] = f
        self.by_name.setdefault(f.name, []).append(f)

    def non_ambiguous_path(self, f: m.Feature) -> str:
        names = [f.name]
        cur = f
        while self.table.get(cur.name) is None and cur.parent is not None:
            cur = cur.parent
            names.append(cur.name)
        return ".".join(reversed(names))

    def lookup_head(self, tok, for_what: str) -> Optional[m.Feature]:
        """Resolve the first part of a reopening / shared path (reference ``getFeatureSymbol``)."""
        name = tok.value
        if tok.type == "ROOT" or name == "root":
            return self.root
        if name not in self.table:
            self.diag(C_UNKNOWN, tok.start, tok.end,
                      f"no feature named '{name}' is declared before this {for_what}." + self._suggest(name, self.table.keys()),
                      data={"name": name, "suggestions": self._close(name, self.table.keys())})
            return None
        f = self.table[name]
        if f is None:
            paths = [self.non_ambiguous_path(x) for x in self.by_name.get(name, [])]
            self.diag(C_AMBIGUOUS, tok.start, tok.end,
                      f"'{name}' is ambiguous: several features have this name; write one of "
                      + ", ".join(f"'{p}'" for p in paths),
                      related=[Related(x.path, x.name_span, self.non_ambiguous_path(x)) for x in self.by_name.get(name, [])[:10]],
                      data={"candidates": paths})
            return None
        return f

    def descend(self, f: m.Feature, parts, for_what: str, include_shared=False) -> Optional[m.Feature]:
        for t in parts:
            kids = {c.feature.name: c.feature for c in (f.group.children if f.group else [])
                    if c is not None and (include_shared or not c.shared)}
            if t.value not in kids:
                self.diag(C_UNKNOWN, t.start, t.end,
                          f"feature '{f.name}' has no child named '{t.value}'." + self._suggest(t.value, kids.keys()),
                          data={"name": t.value, "suggestions": self._close(t.value, kids.keys())})
                return None
            f = kids[t.value]
        return f

    def feature_decl(self, d: RawFeatureDecl, first: bool) -> None:
        parts = d.parts
        head = parts[0]
        if first:
            if not d.is_root:
                self.diag(C_FIRST_NOT_ROOT, head.start, parts[-1].end,
                          f"the first feature must be the root: write 'root {'.'.join(t.value for t in parts)}'",
                          fixes=[Fix("declare it as the root", (TextEdit(self.smap.path(head.start), self.sp(head.start, head.start), "root "),), True)])
            if len(parts) > 1 or head.type != "ID":
                self.diag(C_ROOT_LONG, head.start, parts[-1].end, "the root feature's name must be a single name")
            name_tok = parts[-1]
            if not name_tok.value[:1].isupper():
                self.diag(C_NAMING, name_tok.start, name_tok.end,
                          f"feature name '{name_tok.value}' must begin with an upper-case letter", sev=E)
            root = self._new_feature(name_tok.value, name_tok.start, name_tok.end, d.start, d.end, None)
            root.is_root = True
            self.root = root
            self.model.root = root
            self._register(root)
            self.body(root, d.body)
            return
        if self.root is None:
            return
        # a reopening
        if head.type == "ID" and not head.value[:1].isupper():
            self.diag(C_NAMING, head.start, head.end,
                      f"'{head.value}' is not a feature name: feature names begin with an upper-case letter", sev=E)
            return
        if head.type in ("THIS", "PARENT"):
            self.diag(C_UNKNOWN, head.start, head.end, f"'{head.value}' cannot start a feature declaration")
            return
        f = self.lookup_head(head, "declaration")
        if f is None:
            return
        f = self.descend(f, parts[1:], "declaration")
        if f is None:
            return
        path = self.smap.path(head.start)
        f.decl_spans.append((path, self.sp(parts[-1].start, parts[-1].end)))
        self.body(f, d.body)

    def body(self, f: m.Feature, body: RawBody) -> None:
        # the reference handles attributes first, then the group; constraints in phase 3
        for it in body.items:
            if isinstance(it, RawAttr):
                self.feature_attr(f, it)
        for it in body.items:
            if isinstance(it, RawGroup):
                if f.group is not None:
                    g = f.group
                    self.diag(C_MULTI_GROUPS, it.start, it.kw_end,
                              f"feature '{f.name}' already has a group; a feature has at most one",
                              related=[Related(g.path, g.keyword_span, "its group")])
                    continue
                self.group(f, it)
            elif isinstance(it, RawConstraint):
                self.pending_constraints.append((f, it))
            elif isinstance(it, RawData):
                for k, v, s, e in it.entries:
                    f.data.append(m.DataEntry(k, v, self.sp(s, e), self.smap.path(s)))

    def group(self, f: m.Feature, rg: RawGroup) -> None:
        path = self.smap.path(rg.start)
        g = m.Group(kind=rg.kind, owner=f, span=self.sp(rg.start, rg.end),
                    keyword_span=self.sp(rg.kw_start, rg.kw_end), path=path)
        f.group = g
        names: dict[str, m.GroupChild] = {}
        for rc in rg.children:
            if rc.shared:
                # attached in phase 2; counts for the cardinality
                g.children.append(None)  # placeholder keeps the order
                self.pending_shared.append((f, rc, g, len(g.children) - 1))
                continue
            parts = rc.parts
            nt = parts[-1]
            if len(parts) > 1 or nt.type != "ID":
                self.diag(C_LONG_IN_GROUP, parts[0].start, nt.end,
                          f"'{'.'.join(t.value for t in parts)}': a child in a group is declared with a single name")
                if nt.type != "ID":
                    continue
            name = nt.value
            if self.root is not None and name == self.root.name:
                self.diag(C_ROOT_NAME_REUSED, nt.start, nt.end, f"'{name}' is the name of the root feature")
            if not name[:1].isupper():
                self.diag(C_NAMING, nt.start, nt.end,
                          f"feature name '{name}' should begin with an upper-case letter; "
                          f"TVL reads a lower-case name in a constraint as an attribute", sev=W)
            if name in names:
                prev = names[name]
                self.diag(C_DUP_FEATURE, nt.start, nt.end,
                          f"feature '{f.name}' already has a child named '{name}' (TVL rejects a model whose "
                          f"feature has two children with one name); this one is ignored",
                          related=[Related(prev.path, prev.feature.name_span, "the first one")])
                continue
            child = self._new_feature(name, nt.start, nt.end, rc.start, rc.end, f)
            gc = m.GroupChild(child, rc.optional, False, child.span, child.path)
            names[name] = gc
            g.children.append(gc)
            if rc.body is not None:
                self.body(child, rc.body)
            self._register(child)
        self.cardinality(f, g, rg)

    def _bound(self, tok, f: m.Feature, n: int, which: str) -> tuple[Optional[int], Optional[m.Expr], bool]:
        """-> (value, expr, is_star)"""
        sp = self.sp(tok.start, tok.end)
        path = self.smap.path(tok.start)
        if tok.type == "TIMES":
            return n, None, True
        if tok.type == "INT":
            e = m.IntLit(int(tok.value), span=sp, path=path, type="int")
            return int(tok.value), e, False
        name = tok.value
        e = m.Name([name], part_spans=[sp], span=sp, path=path)
        c = self.constants.get(name)
        if c is None:
            self.diag(C_CARD_BOUNDS, tok.start, tok.end,
                      f"the {which} bound of the group of '{f.name}' names no constant '{name}'."
                      + self._suggest(name, self.constants.keys()))
            return None, e, False
        e.target = c
        e.part_targets = [c]
        e.type = c.type
        if c.type != "int" or not isinstance(c.value, m.IntLit):
            self.diag(C_CARD_BOUNDS, tok.start, tok.end,
                      f"the {which} bound of the group of '{f.name}': constant '{name}' is not an integer")
            return None, e, False
        return c.value.value, e, False

    def cardinality(self, f: m.Feature, g: m.Group, rg: RawGroup) -> None:
        n = len(g.children)
        if rg.kind == "oneOf":
            lo, hi, hi_star = 1, 1, False
        elif rg.kind == "someOf":
            lo, hi, hi_star = 1, n, True
        elif rg.kind == "allOf":
            lo, hi, hi_star = n, n, False
        else:
            lo, g.lo_expr, _ = self._bound(rg.lo, f, n, "lower")
            hi, g.hi_expr, hi_star = self._bound(rg.hi, f, n, "upper")
            if rg.lo.type == "TIMES":
                g.lo_expr = None
        g.lo = lo if lo is not None else 0
        g.hi = None if hi_star else hi
        if lo is None or hi is None:
            return
        ks, ke = rg.kw_start, rg.kw_end
        if lo < 0 or hi < 0:
            self.diag(C_CARD_BOUNDS, ks, ke, f"the cardinality of the group of '{f.name}' has a negative bound")
            return
        if hi < lo:
            self.diag(C_CARD_BOUNDS, ks, ke,
                      f"the cardinality [{lo}..{hi}] of the group of '{f.name}': the upper bound is smaller than the lower bound")
            return
        if n < lo:
            self.diag(C_CARD_EXCEEDS, ks, ke,
                      f"the group of '{f.name}' requires at least {lo} children but has only {n}")
            return
        if n < hi and not hi_star:
            self.diag(C_CARD_UPPER, ks, ke,
                      f"the group of '{f.name}' allows up to {hi} children but has only {n}")

    # ------------------------------------------------------------ attributes
    def make_attr(self, ra: RawAttr, owner: Optional[m.Feature]) -> Optional[m.Attribute]:
        name = ra.name_tok.value
        ty = ra.type_tok.value
        a = m.Attribute(name=name, type=ty, span=self.sp(ra.start, ra.end),
                        name_span=self.sp(ra.name_tok.start, ra.name_tok.end), path=self.smap.path(ra.start),
                        owner=owner, value=ra.value, domain=ra.domain, if_in_value=ra.if_in_value,
                        if_in_domain=ra.if_in_domain, if_out_value=ra.if_out_value, if_out_domain=ra.if_out_domain)
        if ra.type_tok.end > ra.type_tok.start:
            a.type_span = self.sp(ra.type_tok.start, ra.type_tok.end)
        for slot, s, e in ra.dup_parts:
            self.diag(C_DUP_PART, s, e, f"attribute '{name}' already has this part")
        if name[:1].isupper():
            self.diag(C_NAMING, ra.name_tok.start, ra.name_tok.end,
                      f"attribute name '{name}' must begin with a lower-case letter", sev=E)
        if ty not in ("int", "real", "bool", "enum"):
            td = self.types.get(ty)
            if td is None:
                self.diag(C_UNKNOWN_TYPE, ra.type_tok.start, ra.type_tok.end,
                          f"type '{ty}' of attribute '{name}' is not declared." + self._suggest(ty, self.types.keys()),
                          data={"name": ty, "suggestions": self._close(ty, self.types.keys())})
            else:
                a.type_decl = td
        base = self.base_type(a)
        if ra.refinements is not None:
            if a.type_decl is None or a.type_decl.base != "struct":
                if a.type_decl is not None or ty in ("int", "real", "bool", "enum"):
                    self.diag(C_NOT_STRUCT, ra.type_tok.start, ra.type_tok.end,
                              f"'{name}' has field refinements but its type '{ty}' is not a struct")
            else:
                fields = {x.name: x for x in a.type_decl.fields}
                for rr in ra.refinements:
                    fname = rr.name_tok.value
                    if fname not in fields:
                        self.diag(C_UNKNOWN_FIELD, rr.name_tok.start, rr.name_tok.end,
                                  f"struct '{ty}' has no field '{fname}'." + self._suggest(fname, fields.keys()))
                        continue
                    if fname in a.field_refinements:
                        self.diag(C_DUP_ATTR, rr.name_tok.start, rr.name_tok.end,
                                  f"field '{fname}' of '{name}' is refined twice")
                        continue
                    fd = fields[fname]
                    sub = m.Attribute(name=fname, type=fd.type, span=self.sp(rr.start, rr.end),
                                      name_span=self.sp(rr.name_tok.start, rr.name_tok.end),
                                      path=self.smap.path(rr.start), owner=owner, type_decl=fd.type_decl,
                                      value=rr.value, domain=rr.domain, if_in_value=rr.if_in_value,
                                      if_in_domain=rr.if_in_domain, if_out_value=rr.if_out_value,
                                      if_out_domain=rr.if_out_domain)
                    sub.struct_field = fd
                    sub.struct_owner = a
                    a.field_refinements[fname] = sub
                    if rr.domain is not None:
                        self._attr_domain(sub, rr, fname)
                    self.pending_attrs.append((owner, sub, rr))
        elif base == "struct" and (ra.domain is not None):
            self.diag(C_DOMAIN, ra.domain._s, ra.domain._e, f"struct attribute '{name}' cannot have a domain")
        if ra.domain is not None and base != "struct":
            self._attr_domain(a, ra, name)
        elif base == "enum" and ty == "enum":
            # the reference accepts it (the attribute then has no value to take)
            self.diag(C_ENUM_NO_VALUES, ra.name_tok.start, ra.name_tok.end,
                      f"enum attribute '{name}' lists no values: write enum {name} in {{a, b}};")
        return a

    def _attr_domain(self, a: m.Attribute, ra: RawAttr, name: str) -> None:
        base = self.base_type(a)
        before = len(self.diags)
        vals = self.check_domain(base, ra.domain, name, None)
        if any(d.severity == 1 for d in self.diags[before:]):
            a.has_errors = True
        for v in vals:
            a.enum_values.append(m.EnumValue(v[0], v[1], self.smap.path(v[2]), a))
        td = a.type_decl
        if td is not None and td.domain is not None and base in ("int", "real", "enum"):
            # a declared type's domain may only be restricted
            if not self.is_restriction(td.domain, ra.domain):
                self.diag(C_DOMAIN, ra.domain._s, ra.domain._e,
                          f"the domain of '{name}' must be a subset of the domain of its type '{td.name}'")

    def is_restriction(self, outer: m.Expr, inner: m.Expr) -> bool:
        def members(e):
            if isinstance(e, m.SetLit):
                out = []
                for it in e.items:
                    if isinstance(it, m.IntLit) and it.value == 0 and e is inner:
                        continue  # the reference never checks the integer 0 against a domain
                    if isinstance(it, (m.IntLit, m.RealLit)):
                        out.append(float(it.value))
                    elif isinstance(it, m.Name):
                        out.append(it.text)
                return out
            return None
        om, im = members(outer), members(inner)
        if om is not None and im is not None:
            return all(x in om for x in im)
        if isinstance(outer, m.RangeLit):
            lo = None if getattr(outer.lo, "star", False) else getattr(outer.lo, "value", None)
            hi = None if getattr(outer.hi, "star", False) else getattr(outer.hi, "value", None)
            vals = im if im is not None else [
                None if getattr(inner.lo, "star", False) else getattr(inner.lo, "value", None),
                None if getattr(inner.hi, "star", False) else getattr(inner.hi, "value", None)]
            for v in vals:
                if isinstance(v, str):
                    return False
                if v is None:
                    if hi is not None:
                        return False
                    continue
                if (lo is not None and v < lo) or (hi is not None and v > hi):
                    return False
            return True
        if om is not None and isinstance(inner, m.RangeLit):
            return False
        return True

    def base_type(self, a: m.Attribute) -> str:
        if a.type in ("int", "real", "bool", "enum"):
            return a.type
        if a.type_decl is not None:
            return a.type_decl.base
        return "?"

    def feature_attr(self, f: m.Feature, ra: RawAttr) -> None:
        name = ra.name_tok.value
        if name in self.types:
            self.diag(C_NAME_CONFLICT, ra.name_tok.start, ra.name_tok.end,
                      f"attribute '{name}' of '{f.name}' has the name of a type")
        if name in self.constants:
            self.diag(C_NAME_CONFLICT, ra.name_tok.start, ra.name_tok.end,
                      f"attribute '{name}' of '{f.name}' has the name of a constant")
        prev = next((x for x in f.attributes if x.name == name), None)
        a = self.make_attr(ra, f)
        if a is None:
            return
        if prev is not None:
            self.diag(C_DUP_ATTR, ra.name_tok.start, ra.name_tok.end,
                      f"feature '{f.name}' already has an attribute '{name}'",
                      related=[Related(prev.path, prev.name_span, "the first one")])
            return
        f.attributes.append(a)
        self.pending_attrs.append((f, a, ra))

    # ------------------------------------------------------------ phase 2
    def attach_shared(self) -> None:
        for f, rc, g, idx in self.pending_shared:
            parts = rc.parts
            target = self.lookup_head(parts[0], "shared reference")
            if target is not None:
                target = self.descend(target, parts[1:], "shared reference", include_shared=True)
            if target is None:
                continue
            if any(c is not None and c.feature.name == target.name for c in g.children):
                self.diag(C_DUP_SHARED, parts[-1].start, parts[-1].end,
                          f"feature '{f.name}' already has a child named '{target.name}'")
                continue
            gc = m.GroupChild(target, rc.optional, True, self.sp(rc.start, rc.end), self.smap.path(rc.start))
            g.children[idx] = gc
            if f not in target.shared_parents and f is not target.parent:
                target.shared_parents.append(f)
            target.decl_spans.append((self.smap.path(parts[-1].start), self.sp(parts[-1].start, parts[-1].end)))
        for f in self.model.features:
            if f.group is not None and any(c is None for c in f.group.children):
                f.group.children = [c for c in f.group.children if c is not None]

    def detect_cycles(self) -> None:
        if self.root is None:
            return
        WHITE, GREY, BLACK = 0, 1, 2
        color: dict[int, int] = {}
        # iterative DFS over the child relation (shared children included)
        stack = [(self.root, 0)]
        path: list[m.Feature] = []
        while stack:
            f, i = stack.pop()
            if i == 0:
                color[id(f)] = GREY
                path.append(f)
            kids = f.group.children if f.group else []
            if i < len(kids):
                stack.append((f, i + 1))
                c = kids[i]
                st = color.get(id(c.feature), WHITE)
                if st == GREY:
                    cyc = path[path.index(c.feature):] + [c.feature]
                    self.diag_at(C_CYCLE, c.path, c.span,
                                 "shared feature makes the hierarchy cyclic: " + " -> ".join(x.name for x in cyc))
                    f.group.children.remove(c)
                    if f in c.feature.shared_parents:
                        c.feature.shared_parents.remove(f)
                    stack[-1] = (f, i)  # retry same index (list shrank)
                elif st == WHITE:
                    stack.append((c.feature, 0))
            else:
                color[id(f)] = BLACK
                path.pop()
