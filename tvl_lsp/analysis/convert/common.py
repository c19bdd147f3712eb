"""What the writers share: names in the target syntax, boolean expressions (normal form and
printing), and compiling encoded elements into clauses over the features."""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, field
from typing import Iterable, Optional

from ...tvl import model as M
from ..encode import Encoding, _chain

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



# ====================================================================== names

def _tvl_keywords() -> set[str]:
    from ...tvl.lexer import KEYWORDS
    return set(KEYWORDS)


def _uvl_keywords() -> set[str]:
    from ...uvl.lexer import HYPHENATED, KEYWORDS
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
    from ..sat import BoundedSolver as Solver
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


def _binom(n: int, k: int) -> int:
    from math import comb
    return comb(n, k) if 0 <= k <= n else 0


def _esc(s: str) -> str:
    """For a TVL string (no escapes): no double quote, no line break."""
    return " ".join(s.replace('"', "'").split())


def _base(path: str) -> str:
    import os
    return os.path.basename(path)


def _src(model: M.Model, path: str, span) -> str:
    from ..encode import source_text
    return source_text(model, path, span, limit=400)


