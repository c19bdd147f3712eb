"""Where names are: which declaration a position designates, and every place a declaration
is named (declarations, reopenings, ``shared`` references and uses in expressions).

    name_at(model, path, pos) -> (target, span) | None
    references(model, target) -> list[(path, span)]
    occurrences(model) -> list[(path, span, target, is_declaration)]
"""

from __future__ import annotations

from typing import Optional

from ..base.text import Pos, Span
from . import model as m


def _walk(e: Optional[m.Expr]):
    if e is None:
        return
    stack = [e]
    while stack:
        x = stack.pop()
        yield x
        if isinstance(x, m.Binary):
            stack += [x.left, x.right]
        elif isinstance(x, m.Unary):
            stack.append(x.operand)
        elif isinstance(x, m.Ternary):
            stack += [x.cond, x.then, x.other]
        elif isinstance(x, m.Aggregate):
            stack += list(x.args)
        elif isinstance(x, m.SetLit):
            stack += list(x.items)
        elif isinstance(x, m.RangeLit):
            stack += [x.lo, x.hi]


def _attr_exprs(a: m.Attribute):
    for slot in ("value", "domain", "if_in_value", "if_in_domain", "if_out_value", "if_out_domain"):
        yield getattr(a, slot)


def _expr_occurrences(e, out):
    for x in _walk(e):
        if isinstance(x, m.Name):
            for i, sp in enumerate(x.part_spans):
                tgt = x.part_targets[i] if i < len(x.part_targets) else None
                if tgt is not None:
                    out.append((x.path, sp, tgt, False))
        elif isinstance(x, m.Aggregate) and x.attr_span is not None:
            for a in getattr(x, "child_attrs", []) or []:
                out.append((x.path, x.attr_span, a, False))


def occurrences(model: m.Model) -> list:
    cached = getattr(model, "_occurrences", None)
    if cached is not None:
        return cached
    out: list = []
    for td in model.types:
        out.append((td.path, td.name_span, td, True))
        _expr_occurrences(td.domain, out)
        for ev in td.enum_values:
            out.append((ev.path, ev.span, ev, True))
        for fd in td.fields:
            _attr_occurrences(fd, out)
    for c in model.constants:
        out.append((c.path, c.name_span, c, True))
        _expr_occurrences(c.value, out)
    for f in model.features:
        for p, sp in f.decl_spans:
            out.append((p, sp, f, True))
        for a in f.attributes:
            _attr_occurrences(a, out)
        for c in f.constraints:
            _expr_occurrences(c.expr, out)
        if f.group is not None:
            _expr_occurrences(f.group.lo_expr, out)
            _expr_occurrences(f.group.hi_expr, out)
    model._occurrences = out
    return out


def _attr_occurrences(a: m.Attribute, out):
    out.append((a.path, a.name_span, a, True))
    if a.type_span is not None and a.type_decl is not None:
        out.append((a.path, a.type_span, a.type_decl, False))
    for ev in a.enum_values:
        out.append((ev.path, ev.span, ev, True))
    for e in _attr_exprs(a):
        _expr_occurrences(e, out)
    for sub in a.field_refinements.values():
        fd = getattr(sub, "struct_field", None)
        out.append((sub.path, sub.name_span, fd if fd is not None else sub, False))
        for e in _attr_exprs(sub):
            _expr_occurrences(e, out)


def name_at(model: m.Model, path: str, pos: Pos) -> Optional[tuple[object, Span]]:
    """The feature / attribute / constant / type / enum value named at ``pos`` in ``path``."""
    best = None
    for p, sp, tgt, _decl in occurrences(model):
        if p == path and sp.start <= pos <= sp.end:
            if best is None or (sp.end.line - sp.start.line, sp.end.col - sp.start.col) < (
                    best[1].end.line - best[1].start.line, best[1].end.col - best[1].start.col):
                best = (tgt, sp)
    return best


def references(model: m.Model, target, include_declarations: bool = True) -> list[tuple[str, Span]]:
    """Every place ``target`` is named, in source order (declarations first if asked)."""
    seen = set()
    out = []
    for p, sp, tgt, decl in occurrences(model):
        if tgt is target and (include_declarations or not decl):
            k = (p, sp)
            if k not in seen:
                seen.add(k)
                out.append(k)
    out.sort(key=lambda x: (x[0], x[1].start))
    return out
