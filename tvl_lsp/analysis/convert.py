"""Conversions between model formats: TVL <-> UVL, and TVL / UVL (and DIMACS) -> DIMACS.

    convert_model(model, target) -> Conversion(text, notes, exact)

The product count is preserved: what the target says directly (the tree, the groups, boolean
constraints) is written as such; what it cannot say is *compiled* into constraints over the
features that mean exactly the same products:

- TVL -> UVL: a group whose optional children weaken its cardinality, a ``shared`` feature (a
  UVL tree has one parent per feature), constraints over attributes or with aggregates become
  boolean constraints (a group's meaning is written out; an attribute constraint is projected
  onto the features it involves by enumerating their selections, up to
  :data:`MAX_COMPILE_FEATURES` of them);
- UVL -> TVL: a feature with several groups (TVL has one group per feature) keeps one ``allOf``
  group and states the ``or`` / ``alternative`` / ``[n..m]`` blocks as ``ifIn:`` constraints
  (a sum of ``(F ? 1 : 0)`` terms for counting bounds);
- -> DIMACS: the encoding of the analyses, with every auxiliary variable defined as a function
  of the features (Tseitin definitions; cardinalities with a pairwise or a fully defined
  counter encoding), so that counting all the variables of the CNF counts the products.

Names are adapted to the target's lexical rules (and made unique); what the target has no place
for (UVL attributes other than numbers and booleans in TVL, TVL computed attributes in UVL,
UVL arithmetic constraints in TVL) is kept as a comment or data entry and said in the notes.
``exact`` is False when something could not be converted without changing the products (the
notes say what).
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, field
from typing import Iterable, Optional

from ..tvl import model as M
from .encode import Element, Encoding, _Builder, _chain, _clean, encode

MAX_COMPILE_FEATURES = 14
MAX_GROUP_CLAUSES = 20000
PAIRWISE_MAX = 64  # at-most-one groups up to this size are written pairwise in DIMACS


class ConvertError(Exception):
    pass


@dataclass
class Conversion:
    text: str
    notes: list[str] = field(default_factory=list)
    exact: bool = True


def target_of(path: str) -> Optional[str]:
    from .formats import model_format
    return model_format(path)


def convert_model(model: M.Model, target: str, encoding: Optional[Encoding] = None) -> Conversion:
    """The text of ``model`` in ``target`` ("tvl", "uvl" or "dimacs")."""
    if model.root is None:
        raise ConvertError("the model has no root feature")
    enc = encoding or encode(model)
    if target == "dimacs":
        return _Dimacs(model, enc).run()
    if target in ("tvl", "uvl"):
        return _Tree(model, enc, target).run()
    raise ConvertError(f"unknown target format {target!r} (tvl, uvl or dimacs)")


# ====================================================================== names

def _tvl_keywords() -> set[str]:
    from ..tvl.lexer import KEYWORDS
    return set(KEYWORDS)


def _uvl_keywords() -> set[str]:
    from ..uvl.lexer import HYPHENATED, KEYWORDS
    return set(KEYWORDS) | set(HYPHENATED)


_TVL_NAME = re.compile(r"[\w$]+\Z")
_UVL_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_#§%?\\'äüöß;]*\Z")


def _feature_names(model: M.Model, target: str, notes: list[str]) -> dict[M.Feature, str]:
    """Each feature's name in the target (unquoted), unique."""
    out: dict[M.Feature, str] = {}
    taken: set[str] = set()
    renamed: list[tuple[str, str]] = []
    counts: dict[str, int] = {}
    for f in model.features:
        counts[f.name] = counts.get(f.name, 0) + 1
    kws = _tvl_keywords() if target == "tvl" else _uvl_keywords() if target == "uvl" else set()
    for f in model.features:
        base = f.name if counts[f.name] == 1 else f.long_name.replace(".", "_")
        if target == "tvl":
            n = re.sub(r"[^\w$]", "_", base) or "F"
            if n.isdigit() or not n[0].isalpha():
                n = "F" + n if not n.startswith("_") else "F" + n
            if n[0].islower():
                n = n[0].upper() + n[1:]
            if n in kws:
                n += "_"
        elif target == "uvl":
            n = base.replace(".", "_").replace('"', "_").replace("\n", " ") or "F"
        else:
            n = base.replace("\n", " ").strip() or f"_{len(out) + 1}"
        cand = n
        k = 2
        while cand in taken:
            cand = f"{n}_{k}"
            k += 1
        taken.add(cand)
        out[f] = cand
        if cand != f.name:
            renamed.append((f.long_name if counts[f.name] > 1 else f.name, cand))
    if renamed:
        shown = ", ".join(f"{a} -> {b}" for a, b in renamed[:6]) + (" …" if len(renamed) > 6 else "")
        why = {"tvl": "TVL names begin with an upper-case letter, are made of letters, digits and _, "
                      "and are not keywords",
               "uvl": "UVL feature names are unique and cannot contain '.' or '\"'",
               "dimacs": "names must be unique"}[target]
        notes.append(f"{len(renamed)} feature(s) renamed ({why}): {shown}")
    return out


def _uvl_ref(name: str) -> str:
    if _UVL_NAME.match(name) and name not in _uvl_keywords():
        return name
    return f'"{name}"'


# ====================================================================== clauses -> text

def _clause_expr(clause: list[int], feat_of: dict[int, M.Feature]) -> M.Expr:
    """A clause as ``A && B -> C || D`` (``!(A && B)``, ``C || D``)."""
    neg = [M.Name([feat_of[-x].name], target=feat_of[-x]) for x in clause if x < 0]
    pos = [M.Name([feat_of[x].name], target=feat_of[x]) for x in clause if x > 0]

    def join(op, xs):
        e = xs[0]
        for x in xs[1:]:
            e = M.Binary(op, e, x)
        return e
    if not pos and not neg:
        return M.BoolLit(False)
    if not neg:
        return join("||", pos)
    if not pos:
        return M.Unary("!", join("&&", neg))
    return M.Binary("->", join("&&", neg), join("||", pos))


# ====================================================================== printing expressions

_PREC = {"tvl": {"->": 1, "<->": 2, "||": 3, "&&": 4},
         "uvl": {"<->": 1, "->": 2, "||": 3, "&&": 4}}
_OPTEXT = {"tvl": {"->": "->", "<->": "<->", "||": "||", "&&": "&&", "!": "!"},
           "uvl": {"->": "=>", "<->": "<=>", "||": "|", "&&": "&", "!": "!"}}
_BOOL_OPS = {"&&", "||", "->", "<->", "<-", "requires", "excludes", "and", "or"}


def _normal(e: M.Expr) -> Optional[M.Expr]:
    """``e`` over ! && || -> <-> and feature names only (constants folded); None when it says
    more than that (attributes, numbers, aggregates, ...)."""
    if isinstance(e, M.BoolLit):
        if getattr(e, "too_deep", False):
            return None
        return M.BoolLit(bool(e.value))
    if isinstance(e, M.Name):
        if isinstance(e.target, M.Feature):
            return M.Name([e.target.name], target=e.target)
        return None
    if isinstance(e, M.Unary):
        if e.op != "!":
            return None
        a = _normal(e.operand)
        if a is None:
            return None
        if isinstance(a, M.BoolLit):
            return M.BoolLit(not a.value)
        return M.Unary("!", a)
    if isinstance(e, M.Binary):
        op = {"and": "&&", "or": "||", "requires": "->"}.get(e.op, e.op)
        if op in ("&&", "||"):
            parts = []
            for x in _chain(e, e.op):
                n = _normal(x)
                if n is None:
                    return None
                if isinstance(n, M.BoolLit):
                    if n.value == (op == "||"):
                        return M.BoolLit(op == "||")
                    continue
                parts.append(n)
            if not parts:
                return M.BoolLit(op == "&&")
            out = parts[0]
            for p in parts[1:]:
                out = M.Binary(op, out, p)
            return out
        if op in ("==", "!=") and _is_boolish(e.left) and _is_boolish(e.right):
            l, r = _normal(e.left), _normal(e.right)
            if l is None or r is None:
                return None
            x = _fold2("<->", l, r)
            return x if op == "==" else _fold_not(x)
        if op in ("->", "<-", "<->", "excludes"):
            l, r = _normal(e.left), _normal(e.right)
            if l is None or r is None:
                return None
            if op == "<-":
                l, r = r, l
                op = "->"
            if op == "excludes":
                return _fold_not(_fold2("&&", l, r))
            return _fold2(op, l, r)
        return None
    if isinstance(e, M.Ternary):
        return None
    return None


def _is_boolish(e: M.Expr) -> bool:
    return isinstance(e, (M.BoolLit, M.Unary)) or (isinstance(e, M.Name) and isinstance(e.target, M.Feature)) \
        or (isinstance(e, M.Binary) and e.op in _BOOL_OPS)


def _fold_not(a: M.Expr) -> M.Expr:
    if isinstance(a, M.BoolLit):
        return M.BoolLit(not a.value)
    return M.Unary("!", a)


def _fold2(op: str, l: M.Expr, r: M.Expr) -> M.Expr:
    lb = l.value if isinstance(l, M.BoolLit) else None
    rb = r.value if isinstance(r, M.BoolLit) else None
    if op == "&&":
        if lb is False or rb is False:
            return M.BoolLit(False)
        return r if lb is True else l if rb is True else M.Binary(op, l, r)
    if op == "||":
        if lb is True or rb is True:
            return M.BoolLit(True)
        return r if lb is False else l if rb is False else M.Binary(op, l, r)
    if op == "->":
        if lb is False or rb is True:
            return M.BoolLit(True)
        if lb is True:
            return r
        if rb is False:
            return _fold_not(l)
        return M.Binary(op, l, r)
    # <->
    if lb is not None and rb is not None:
        return M.BoolLit(lb == rb)
    if lb is not None:
        return r if lb else _fold_not(r)
    if rb is not None:
        return l if rb else _fold_not(l)
    return M.Binary(op, l, r)


def _print(e: M.Expr, syntax: str, name_of) -> str:
    prec = _PREC[syntax]
    ops = _OPTEXT[syntax]

    def go(x: M.Expr, parent: Optional[str]) -> str:
        if isinstance(x, M.Name):
            return name_of(x.target)
        if isinstance(x, M.BoolLit):
            return "true" if x.value else "false"
        if isinstance(x, M.Unary):
            inner = x.operand
            s = go(inner, "!")
            return "!" + (f"({s})" if isinstance(inner, M.Binary) else s)
        assert isinstance(x, M.Binary)
        if x.op in ("&&", "||"):
            parts = _chain(x, x.op)
        else:
            parts = [x.left, x.right]
        strs = []
        for p in parts:
            s = go(p, x.op)
            if isinstance(p, M.Binary) and (prec[p.op] < prec[x.op] or (prec[p.op] == prec[x.op] and
                                                                         not (p.op == x.op and x.op in ("&&", "||")))):
                s = f"({s})"
            strs.append(s)
        return f" {ops[x.op]} ".join(strs)
    return go(e, None)


# ====================================================================== compiling elements

def _pure_vars(enc: Encoding) -> set[int]:
    """Auxiliary variables that are functions of the features (Tseitin ANDs over features and
    such variables)."""
    pure: set[int] = set()
    n = enc.n_features
    for key, a in sorted(((k, v) for k, v in enc.b._and_cache.items()), key=lambda kv: kv[1]):
        if all(abs(x) <= n or abs(x) in pure for x in key):
            pure.add(a)
    return pure


def _definitions(enc: Encoding) -> dict[int, frozenset]:
    return {v: k for k, v in enc.b._and_cache.items()}


def _features_under(enc: Encoding, lits: Iterable[int], defs: dict[int, frozenset]) -> set[int]:
    """Feature variables ``lits`` depend on (through Tseitin definitions)."""
    n = enc.n_features
    out: set[int] = set()
    seen: set[int] = set()
    stack = [abs(x) for x in lits]
    while stack:
        v = stack.pop()
        if v in seen:
            continue
        seen.add(v)
        if v <= n:
            out.add(v)
        elif v in defs:
            stack.extend(abs(x) for x in defs[v])
    return out


def _project(enc: Encoding, clauses: list[list[int]], extra_features: Iterable[int] = ()) -> Optional[list[list[int]]]:
    """Clauses over feature variables that allow exactly the feature selections for which
    ``clauses`` (with the encoding's definitions) can hold; None when too many features are
    involved to enumerate."""
    from pysat.solvers import Solver
    defs = _definitions(enc)
    n = enc.n_features
    lits = [x for c in clauses for x in c]
    # non-functional auxiliaries (attribute values) reach features through the hard clauses
    aux = {abs(x) for x in lits if abs(x) > n and abs(x) not in defs}
    hard_rel = [c for c in enc.hard if any(abs(x) in aux for x in c)]
    feats = _features_under(enc, lits + [x for c in hard_rel for x in c], defs) | set(extra_features)
    # the hard clauses mention other attributes' variables: follow them too
    grow = True
    while grow:
        grow = False
        more = {abs(x) for c in hard_rel for x in c if abs(x) > n and abs(x) not in defs} - aux
        if more:
            aux |= more
            hard_rel = [c for c in enc.hard if any(abs(x) in aux for x in c)]
            feats |= _features_under(enc, [x for c in hard_rel for x in c], defs)
            grow = True
    vs = sorted(feats)
    if len(vs) > MAX_COMPILE_FEATURES:
        return None
    out: list[list[int]] = []
    with Solver(name="minisat22", bootstrap_with=list(enc.hard) + clauses) as s:
        for bits in itertools.product((False, True), repeat=len(vs)):
            assign = [v if b else -v for v, b in zip(vs, bits)]
            aset = set(assign)
            if any(all(-x in aset for x in c) for c in out):
                continue  # already excluded
            if s.solve(assumptions=assign):
                continue
            core = list(s.get_core() or assign)
            # shrink the core to a minimal one
            i = 0
            while i < len(core):
                trial = core[:i] + core[i + 1:]
                if trial and not s.solve(assumptions=trial):
                    core = trial
                else:
                    i += 1
            if not core:
                return [[]]
            out.append(sorted((-x for x in core), key=abs))
    return out


# ====================================================================== TVL / UVL

@dataclass
class _Block:
    kind: str           # mandatory optional or alternative card
    lo: int = 0
    hi: Optional[int] = None
    children: list[M.Feature] = field(default_factory=list)


class _Tree:
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


def _binom(n: int, k: int) -> int:
    from math import comb
    return comb(n, k) if 0 <= k <= n else 0


def _uvl_kw(b: _Block) -> str:
    if b.kind in ("mandatory", "optional", "or", "alternative"):
        return b.kind
    if b.hi is not None and b.hi == b.lo:
        return f"[{b.lo}]"
    return f"[{b.lo}..{'*' if b.hi is None else b.hi}]"


def _esc(s: str) -> str:
    """For a TVL string (no escapes): no double quote, no line break."""
    return " ".join(s.replace('"', "'").split())


def _base(path: str) -> str:
    import os
    return os.path.basename(path)


def _src(model: M.Model, path: str, span) -> str:
    from .encode import source_text
    return source_text(model, path, span, limit=400)


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


# ====================================================================== DIMACS

class _Dimacs:
    """A CNF whose models are exactly the products (every auxiliary variable is a function of
    the features), with FeatureIDE's ``c <var> <name>`` lines."""

    def __init__(self, model: M.Model, enc: Encoding):
        self.model = model
        self.enc = enc
        self.notes: list[str] = []
        self.exact = True

    def run(self) -> Conversion:
        enc = self.enc
        n = enc.n_features
        names = _feature_names(self.model, "dimacs", self.notes)
        pure = _pure_vars(enc)
        defs = _definitions(enc)
        out: list[list[int]] = []
        # our own builder for cardinalities: functional definitions only
        top = max(enc.nvars, n)
        hard: list[list[int]] = []
        b = _Builder(top, hard)
        impure: list[Element] = []
        used_defs: set[int] = set()
        for e in enc.elements:
            if e.kind in ("group", "group-lower"):
                out += self._group(e, b)
                continue
            vs = {abs(x) for c in e.clauses for x in c if abs(x) > n}
            if vs <= pure:
                out += e.clauses
                used_defs |= vs
            else:
                impure.append(e)
        if impure:
            by = {}
            for e in impure:
                by.setdefault(e.kind, []).append(e)
            clauses = [c for e in impure for c in e.clauses]
            proj = _project(enc, clauses)
            if proj is None:
                self.exact = False
                self.notes.append("NOT converted exactly: attribute constraints over more than "
                                  f"{MAX_COMPILE_FEATURES} features are left out; the CNF may have more models")
            else:
                out += proj
        # Tseitin definitions of the auxiliaries used (and of the ones they use)
        need = set(used_defs)
        stack = list(used_defs)
        while stack:
            v = stack.pop()
            for x in defs.get(v, ()):
                if abs(x) > n and abs(x) not in need:
                    need.add(abs(x))
                    stack.append(abs(x))
        for v in sorted(need):
            key = defs[v]
            for x in key:
                out.append([-v, x])
            out.append([v] + [-x for x in key])
        out += hard
        # renumber: features 1..n, then the auxiliaries in order of first use
        ren: dict[int, int] = {}
        nxt = n
        final = []
        for c in out:
            cc = []
            for x in c:
                v = abs(x)
                if v > n:
                    if v not in ren:
                        nxt += 1
                        ren[v] = nxt
                    v = ren[v]
                cc.append(v if x > 0 else -v)
            final.append(cc)
        feats = enc.features
        lines = [f"c {i} {names[f]}" for i, f in enumerate(feats, start=1)]
        if nxt > n:
            lines.append(f"c variables {n + 1}..{nxt} are auxiliary: each is defined by the features "
                         "(the models of this CNF are the products)")
        lines.append(f"p cnf {nxt} {len(final)}")
        lines += [" ".join(map(str, c)) + " 0" for c in final]
        return Conversion("\n".join(lines) + "\n", self.notes, self.exact)

    def _group(self, e: Element, b: _Builder) -> list[list[int]]:
        """A group's bound with a functional encoding (no free auxiliary variable)."""
        g: M.Group = e.obj
        v = self.enc.var_of_feature
        p = v[g.owner]
        seen = set()
        kids = []
        for c in g.children:
            if c.feature in v and c.feature not in seen:
                seen.add(c.feature)
                kids.append(c)
        if e.kind == "group":  # at most hi of all children
            lits = [v[c.feature] for c in kids]
            return [[-p] + c for c in _at_most(b, lits, g.hi)]
        mand = [c for c in kids if not c.optional]
        need = g.lo - (len(kids) - len(mand))
        if need > len(mand):
            return [[-p]]
        return [[-p] + c for c in _at_least(b, [v[c.feature] for c in mand], need)]


def _counter(b: _Builder, lits: list[int], k: int) -> list:
    """``c[j]`` (j = 1..k) is true iff at least j of ``lits`` are (defined, not just implied)."""
    c: list = [True] + [False] * k
    for x in lits:
        new = [True]
        for j in range(1, k + 1):
            new.append(b.or_([c[j], b.and_([c[j - 1], x])]))
        c = new
    return c


def _at_most(b: _Builder, lits: list[int], k: int) -> list[list[int]]:
    n = len(lits)
    if k >= n:
        return []
    if k <= 0:
        return [[-x] for x in lits]
    if k == 1 and n <= PAIRWISE_MAX:
        return [[-lits[i], -lits[j]] for i in range(n) for j in range(i + 1, n)]
    c = _counter(b, lits, k + 1)
    x = c[k + 1]
    return [] if x is False else [[]] if x is True else [[-x]]


def _at_least(b: _Builder, lits: list[int], k: int) -> list[list[int]]:
    n = len(lits)
    if k <= 0:
        return []
    if k > n:
        return [[]]
    if k == 1:
        return [list(lits)]
    if k == n:
        return [[x] for x in lits]
    c = _counter(b, lits, k)
    x = c[k]
    return [] if x is True else [[]] if x is False else [[x]]
