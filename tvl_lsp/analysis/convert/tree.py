"""TVL and UVL text of a model (see :mod:`tvl_lsp.analysis.convert`)."""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, field
from typing import Optional

from ...tvl import model as M
from ..encode import Element, Encoding
from .common import (MAX_COMPILE_FEATURES, MAX_GROUP_CLAUSES, Conversion, _base, _binom, _clause_expr, _definitions,
                     _esc, _feature_names, _fold2, _fold_not, _normal, _print, _project, _pure_vars, _src,
                     _tvl_keywords, _UVL_NAME, _uvl_keywords, _uvl_ref)


# ====================================================================== TVL / UVL

@dataclass
class _Block:
    kind: str           # mandatory optional or alternative card
    lo: int = 0
    hi: Optional[int] = None
    children: list[M.Feature] = field(default_factory=list)


class TreeWriter:
    """TVL or UVL text of a model (see the module notes)."""

    def __init__(self, model: M.Model, enc: Encoding, target: str):
        self.model = model
        self.enc = enc
        self.target = target
        self.notes: list[str] = []
        self.exact = True
        self.names = _feature_names(model, target, self.notes)
        self.blocks: dict[M.Feature, list[_Block]] = {f: [] for f in model.features}
        self.compile_elems: list[Element] = []
        # constraints written in a feature's body (TVL) / the constraints section (UVL)
        self.cons: dict[M.Feature, list[str]] = {f: [] for f in model.features}
        self.comments: dict[M.Feature, list[str]] = {f: [] for f in model.features}
        self.tail_comments: list[str] = []
        self.struct_clauses: list[list[int]] = []

    def name(self, f: M.Feature) -> str:
        n = self.names[f]
        return _uvl_ref(n) if self.target == "uvl" else n

    # ------------------------------------------------------------ structure
    def run(self) -> Conversion:
        m = self.model
        relocated = {f for f in m.features if f.shared_parents}
        elems_by_obj: dict[int, list[Element]] = {}
        for e in self.enc.elements:
            elems_by_obj.setdefault(id(e.obj), []).append(e)
        root = m.root
        for f in m.features:
            self._groups_of(f, relocated, elems_by_obj)
        if relocated:
            moved = sorted(relocated, key=m.features.index)
            opt_block = next((b for b in self.blocks[root] if b.kind == "optional"), None)
            if self.target == "uvl" and opt_block is not None:
                opt_block.children += moved
            elif self.target == "uvl":
                self.blocks[root].append(_Block("optional", children=moved))
            else:  # TVL: optional children of the root's one group
                allof = next((b for b in self.blocks[root] if b.kind == "allof"), None)
                if allof is None:
                    allof = _Block("allof")
                    self.blocks[root].insert(0, allof)
                allof.children += moved
                self._opt = getattr(self, "_opt", set()) | set(moved)
            for f in relocated:
                self.compile_elems += [e for e in elems_by_obj.get(id(f), []) if e.kind == "parent-link"]
            self.notes.append(f"{len(relocated)} shared feature(s) placed under the root, their parents stated as "
                              f"constraints: {', '.join(f.name for f in list(relocated)[:5])}")
        self._constraints(elems_by_obj)
        self._attributes()
        self._compile()
        text = self._write_uvl() if self.target == "uvl" else self._write_tvl()
        return Conversion(text, self.notes, self.exact)

    def _groups_of(self, f: M.Feature, relocated: set, elems_by_obj) -> None:
        groups = f.groups
        if not groups:
            return
        tvl = self.target == "tvl"
        plain: list[tuple[M.Feature, bool]] = []   # (child, optional) of allOf groups
        other: list[M.Group] = []
        complex_groups: list[M.Group] = []
        for g in groups:
            declared = [c for c in g.children if not c.shared and c.feature.parent is f and c.feature not in relocated]
            n = len(g.children)
            has_odd = len(declared) != n
            if g.kind == "allOf" and not has_odd and g.lo >= n:
                plain += [(c.feature, c.optional) for c in declared]
                continue
            mand = [c for c in g.children if not c.optional]
            opt = [c for c in g.children if c.optional]
            if not has_odd and not opt:
                other.append(g)
                continue
            need = g.lo - len(opt)
            if not has_odd and need <= 0 and (g.hi is None or g.hi >= n):
                plain += [(c.feature, True) for c in declared]
                continue
            # a group the target cannot say as such: its children are optional, its meaning
            # is stated as constraints
            plain += [(c.feature, True) for c in declared]
            complex_groups.append(g)
            cl = self._group_clauses(g)
            if cl is None:
                self.exact = False
                self.notes.append(f"NOT converted exactly: the group {g.text} of {f.name} needs more than "
                                  f"{MAX_GROUP_CLAUSES} constraints; its children are left optional")
            else:
                self.struct_clauses += cl
        blocks = self.blocks[f]
        if tvl and other and (plain or len(other) > 1):
            # TVL: one group per feature
            for g in other:
                plain += [(c.feature, True) for c in g.children]
                self._state_group(f, g)
            other = []
        mand = [c for c, o in plain if not o]
        opts = [c for c, o in plain if o]
        if tvl:
            if plain:
                blocks.append(_Block("allof", children=[c for c, _ in plain]))
                self._opt = getattr(self, "_opt", set()) | set(opts)
            for g in other:
                self._add_block(f, g, blocks)
        else:
            if mand:
                blocks.append(_Block("mandatory", children=mand))
            if opts:
                blocks.append(_Block("optional", children=opts))
            for g in other:
                self._add_block(f, g, blocks)
        if complex_groups:
            self.notes.append(f"group(s) of {f.name} stated as constraints: {self.target.upper()} has no group "
                              "with these cardinalities and optional or shared children")

    def _add_block(self, f: M.Feature, g: M.Group, blocks: list) -> None:
        if g.children:
            blocks.append(self._block_of(g))
        elif g.lo > 0:  # an empty group that needs children: its feature is dead
            v = self.enc.var_of_feature
            self.struct_clauses.append([-v[f]])

    def _group_clauses(self, g: M.Group, force_children: bool = False) -> Optional[list[list[int]]]:
        """A group's meaning as clauses over its feature and children (TVL semantics: optional
        children always count towards the lower bound); None when too many."""
        v = self.enc.var_of_feature
        p = v[g.owner]
        kids = list(dict.fromkeys(c.feature for c in g.children if c.feature in v))
        opt = {c.feature for c in g.children if c.optional}
        if g.kind == "allOf" and not force_children:
            return [[-p, v[k]] for k in kids if k not in opt]
        mand = [k for k in kids if k not in opt]
        out: list[list[int]] = []
        need = g.lo - len([k for k in kids if k in opt])
        if need > len(mand):
            out.append([-p])
        elif need > 0:
            size = len(mand) - need + 1
            if _binom(len(mand), size) > MAX_GROUP_CLAUSES:
                return None
            out += [[-p] + [v[k] for k in ks] for ks in itertools.combinations(mand, size)]
        if g.hi is not None and g.hi < len(kids):
            if _binom(len(kids), g.hi + 1) > MAX_GROUP_CLAUSES:
                return None
            out += [[-p] + [-v[k] for k in ks] for ks in itertools.combinations(kids, g.hi + 1)]
        return out

    @staticmethod
    def _block_of(g: M.Group) -> _Block:
        kids = [c.feature for c in g.children]
        n = len(kids)
        if g.kind == "allOf":
            return _Block("mandatory", children=kids)
        if g.lo == 1 and g.hi == 1:
            return _Block("alternative", 1, 1, kids)
        if g.lo == 1 and (g.hi is None or g.hi >= n):
            return _Block("or", 1, None, kids)
        return _Block("card", g.lo, g.hi, kids)

    def _state_group(self, f: M.Feature, g: M.Group) -> None:
        """TVL: an or / alternative / [n..m] block that is not the feature's only group, as
        ``ifIn:`` constraints of the feature (its children are optional in the one group)."""
        cl = self._group_clauses(g, force_children=True)
        if cl is None:
            self.exact = False
            self.notes.append(f"NOT converted exactly: the group {g.text} of {f.name} needs more than "
                              f"{MAX_GROUP_CLAUSES} constraints; its children are left optional")
            return
        v = self.enc.var_of_feature
        feat_of = {x: ff for ff, x in v.items()}
        p = v[f]
        self.cons[f].append(f"// the '{g.keyword or g.text}' group of {f.name} (TVL has one group per feature):")
        for c in cl:
            rest = [x for x in c if x != -p]
            e = M.BoolLit(False) if not rest else _clause_expr(rest, feat_of)
            self.cons[f].append(f"ifIn: {_print(e, 'tvl', self.name)};")

    # ------------------------------------------------------------ constraints
    def _constraints(self, elems_by_obj) -> None:
        syntax = self.target
        for f in self.model.features:
            for c in f.constraints:
                e = _normal(c.expr)
                if e is not None and c.kind != "plain":
                    e = _fold2("->", M.Name([f.name], target=f) if c.kind == "ifIn"
                               else _fold_not(M.Name([f.name], target=f)), e)
                if e is None:
                    els = elems_by_obj.get(id(c), [])
                    if not els:
                        self.notes.append(f"constraint not converted (the analyses do not encode it either): "
                                          f"{_src(self.model, c.path, c.span)}")
                        self._comment(f, "constraint not analysed", _src(self.model, c.path, c.span))
                        continue
                    self.compile_elems += els
                    self._comment(f, "compiled from", _src(self.model, c.path, c.span))
                    continue
                if isinstance(e, M.BoolLit):
                    if e.value:
                        continue
                    e = M.Unary("!", M.Name([self.model.root.name], target=self.model.root))
                text = _print(e, syntax, self.name)
                self.cons[f].append(text + (";" if syntax == "tvl" else ""))
        # attribute elements the analyses encode (values that restrict features)
        for e in self.enc.elements:
            if e.kind == "attribute":
                self.compile_elems.append(e)
        for u in self.model.unanalysed:
            if u.kind == "constraint":
                owner = u.owner or self.model.root
                if self.target == "uvl" and self.model.format == "uvl":
                    self.cons[self.model.root].append(" ".join(u.text.split()))
                else:
                    self._comment(owner, f"UVL constraint not converted ({u.reason})" if u.reason else
                                  "UVL constraint not converted", u.text)
            elif u.kind in ("feature-type", "feature-cardinality") and not (
                    self.target == "uvl" and self.model.format == "uvl"):
                self._comment(u.owner or self.model.root, f"UVL {u.kind.replace('-', ' ')} not converted", u.text)
        n_un = sum(1 for u in self.model.unanalysed if u.kind == "constraint")
        if n_un and not (self.target == "uvl" and self.model.format == "uvl"):
            self.notes.append(f"{n_un} UVL constraint(s) that are not analysed (arithmetic / string level) "
                              "kept as comments")

    def _comment(self, f: M.Feature, what: str, text: str) -> None:
        text = " ".join(text.split())
        self.comments[f].append(f"// {what}: {text}")

    def _compile(self) -> None:
        enc = self.enc
        feat_of = {v: f for f, v in enc.var_of_feature.items()}
        for c in self.struct_clauses:
            self._emit_clause(c, feat_of)
        if not self.compile_elems:
            return
        n = enc.n_features
        # group the elements that share non-functional variables (an attribute's values)
        defs = _definitions(enc)
        pure = _pure_vars(enc)
        comps: list[list[Element]] = []
        by_var: dict[int, int] = {}
        seen = set()
        for e in self.compile_elems:
            if id(e) in seen:
                continue
            seen.add(id(e))
            vs = {abs(x) for c in e.clauses for x in c if abs(x) > n and abs(x) not in pure}
            hit = {by_var[v] for v in vs if v in by_var}
            if not hit:
                comps.append([e])
                k = len(comps) - 1
            else:
                k = min(hit)
                for j in sorted(hit - {k}, reverse=True):
                    comps[k] += comps[j]
                    comps[j] = []
                comps[k].append(e)
                for v, j in list(by_var.items()):
                    if j in hit:
                        by_var[v] = k
            for v in vs:
                by_var[v] = k
        for comp in comps:
            if not comp:
                continue
            clauses = [c for e in comp for c in e.clauses]
            simple = all(abs(x) <= n for c in clauses for x in c)
            if simple:
                out = clauses
            else:
                out = _project(enc, clauses)
            if out is None:
                self.exact = False
                labels = "; ".join(sorted({e.label for e in comp}))[:200]
                self.notes.append(f"NOT converted exactly (more than {MAX_COMPILE_FEATURES} features involved): "
                                  f"{labels}; the converted model may have more products")
                continue
            for c in out:
                self._emit_clause(c, feat_of)
        del defs

    def _emit_clause(self, c: list[int], feat_of) -> None:
        root = self.model.root
        e = M.Unary("!", M.Name([root.name], target=root)) if not c else _clause_expr(c, feat_of)
        self.cons[root].append(_print(e, self.target, self.name) + (";" if self.target == "tvl" else ""))

    # ------------------------------------------------------------ attributes
    def _attributes(self) -> None:
        self.attr_text: dict[M.Feature, list[str]] = {f: [] for f in self.model.features}
        self.data_text: dict[M.Feature, list[str]] = {f: [] for f in self.model.features}
        dropped = 0
        for f in self.model.features:
            if getattr(f, "abstract", False):
                if self.target == "uvl":
                    self.attr_text[f].append("abstract")
                else:
                    self.comments[f].append("// abstract (UVL)")
            for a in f.attributes:
                if self.model.format == "uvl":
                    raw = getattr(a, "uvl_value", None)
                    if self.target == "uvl":
                        self.attr_text[f].append(getattr(a, "uvl_text", a.name))
                        continue
                    lit = _tvl_literal(raw)
                    if lit is not None and re.fullmatch(r"[a-z][\w$]*", a.name) and a.name not in _tvl_keywords():
                        self.attr_text[f].append(f"{lit[0]} {a.name} is {lit[1]};")
                    else:
                        val = getattr(a, "uvl_text", a.name)[len(a.name):].strip() if raw is not None else "true"
                        self.data_text[f].append(f'"{_esc(a.name)}" "{_esc(val)}"')
                    continue
                # TVL attribute
                if self.target == "tvl":
                    continue
                lit = _uvl_literal(a)
                if lit is not None:
                    key = a.name if _UVL_NAME.match(a.name) and a.name not in _uvl_keywords() else f'"{a.name}"'
                    self.attr_text[f].append(f"{key} {lit}")
                else:
                    dropped += 1
                    self._comment(f, "TVL attribute (values constraining features are compiled into constraints)",
                                  _src(self.model, a.path, a.span) or a.name)
            for d in f.data:
                if self.target == "uvl":
                    key = d.key if _UVL_NAME.match(d.key) and d.key not in _uvl_keywords() else f'"{d.key}"'
                    self.attr_text[f].append(f"{key} '{d.value}'" if "'" not in d.value else f'{key} "{d.value}"')
        if dropped:
            self.notes.append(f"{dropped} TVL attribute(s) without a constant value kept as comments "
                              "(their effect on the products, if any, is compiled into constraints)")

    # ------------------------------------------------------------ writers
    def _write_uvl(self) -> str:
        m = self.model
        out: list[str] = []
        out.append(f"// converted by tvl-lsp from {_base(m.path)}")
        out.append("features")
        # iterative depth-first walk: (feature, depth) and block headers
        stack: list[tuple[str, object, int]] = [("f", m.root, 1)]
        while stack:
            kind, x, d = stack.pop()
            ind = "\t" * d
            if kind == "b":
                b: _Block = x  # type: ignore
                out.append(ind + _uvl_kw(b))
                continue
            f: M.Feature = x  # type: ignore
            attrs = self.attr_text[f]
            line = ind + self.name(f) + (" {" + ", ".join(attrs) + "}" if attrs else "")
            for c in self.comments[f]:
                if c.startswith("// compiled from") or c.startswith("// the '"):
                    continue
                out.append(ind + c)
            out.append(line)
            items: list[tuple[str, object, int]] = []
            for b in self.blocks[f]:
                items.append(("b", b, d + 1))
                for c in b.children:
                    items.append(("f", c, d + 2))
            stack.extend(reversed(items))
        cons = [c for f in m.features for c in self.cons[f]]
        compiled = [c for f in m.features for c in self.comments[f] if c.startswith("// compiled from")]
        if cons:
            out.append("constraints")
            for c in compiled:
                out.append("\t" + c)
            for c in cons:
                out.append("\t" + c)
        return "\n".join(out) + "\n"

    def _write_tvl(self) -> str:
        m = self.model
        out: list[str] = [f"// converted by tvl-lsp from {_base(m.path)}"]
        opt = getattr(self, "_opt", set())
        # breadth-first, so that every reopened feature is declared before
        order = []
        seen = set()
        queue = [m.root]
        while queue:
            nxt = []
            for f in queue:
                if f in seen:
                    continue
                seen.add(f)
                order.append(f)
                for b in self.blocks[f]:
                    nxt.extend(b.children)
            queue = nxt
        for f in order:
            body: list[str] = []
            blocks = self.blocks[f]
            if blocks:
                b = blocks[0]
                kids = []
                for c in b.children:
                    o = "opt " if (b.kind == "allof" and c in opt) else ""
                    kids.append(f"    {o}{self.name(c)}")
                kw = {"allof": "allOf", "mandatory": "allOf", "or": "someOf", "alternative": "oneOf"}.get(b.kind)
                if kw is None:
                    kw = f"[{b.lo}..{'*' if b.hi is None else b.hi}]"
                body.append(f"  group {kw} {{")
                body.append(",\n".join(kids))
                body.append("  }")
            for a in self.attr_text[f]:
                body.append("  " + a)
            if self.data_text[f]:
                # the reference separates entries with ';' and ends the last one without
                body.append("  data {")
                body.append(";\n".join("    " + d for d in self.data_text[f]))
                body.append("  }")
            for c in self.comments[f]:
                body.append("  " + c)
            for c in self.cons[f]:
                body.append("  " + c)
            if f is m.root:
                out.append(f"root {self.name(f)} {{")
                out += body
                out.append("}")
            elif body:
                out.append(f"{self.name(f)} {{")
                out += body
                out.append("}")
        return "\n".join(out) + "\n"



def _uvl_kw(b: _Block) -> str:
    if b.kind in ("mandatory", "optional", "or", "alternative"):
        return b.kind
    if b.hi is not None and b.hi == b.lo:
        return f"[{b.lo}]"
    return f"[{b.lo}..{'*' if b.hi is None else b.hi}]"



def _tvl_literal(raw) -> Optional[tuple[str, str]]:
    if raw is None:
        return ("bool", "true")
    if raw.kind == "bool":
        return ("bool", "true" if raw.value else "false")
    if raw.kind == "int":
        return ("int", str(raw.value))
    if raw.kind == "float":
        return ("real", repr(float(raw.value)))
    return None


def _uvl_literal(a: M.Attribute) -> Optional[str]:
    if a.domain is not None or a.if_in_value is not None or a.if_out_value is not None \
            or a.if_in_domain is not None or a.if_out_domain is not None:
        return None
    v = a.value
    if isinstance(v, M.BoolLit):
        return "true" if v.value else "false"
    if isinstance(v, M.IntLit):
        return str(v.value)
    if isinstance(v, M.RealLit):
        return v.text or repr(v.value)
    if isinstance(v, M.Unary) and v.op == "-" and isinstance(v.operand, (M.IntLit, M.RealLit)):
        return "-" + str(v.operand.value)
    return None


