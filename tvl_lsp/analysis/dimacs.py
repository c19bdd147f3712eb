"""Import a DIMACS CNF as a flat TVL model.

The model is a root (named after the file) with every variable as an optional child
(``group [0..*]``, so the group adds no clause) and every clause as a plain constraint
``a || !b || ...`` whose span is the clause's line in the file.  Variables are named from
``c <index> <name>`` comments; a variable without a comment gets the name ``_<index>`` so
that the encoding keeps *every* variable of the CNF.

Why the counts agree: the encoder numbers the root 1 and DIMACS variable ``i`` as ``i + 1``;
the root is forced true and the child -> root links hold whenever the root does, so the
flat model's products are exactly the CNF's models.  All the DIMACS files in
``shared/models/dimacs`` name every one of their variables (checked: as many
``c <index> <name>`` lines as declared variables, names unique), and the clauses are asserted
without auxiliary variables, so projecting on the features is projecting on all variables.
"""

from __future__ import annotations

import os
import re
from typing import Optional

from ..base.text import Span, Pos
from ..tvl import model as M


class DimacsError(ValueError):
    pass


def parse_dimacs(text: str, errors: Optional[list] = None) -> tuple[int, list[list[int]], dict[int, str], list[int]]:
    """(declared variables, clauses, names by index, line number of each clause).

    Raises :class:`DimacsError` on the first malformed line, unless ``errors`` is a list: then
    each problem is appended to it as ``(line, start column, end column, message)`` and the
    line's bad tokens are skipped."""
    nvars = 0
    names: dict[int, str] = {}
    clauses: list[list[int]] = []
    lines_of: list[int] = []
    cur: list[int] = []
    cur_line = 0
    seen_p = False

    def bad(ln: int, c0: int, c1: int, msg: str) -> None:
        if errors is None:
            raise DimacsError(f"line {ln + 1}: {msg}")
        if len(errors) < 100:
            errors.append((ln, c0, c1, msg))

    for ln, line in enumerate(text.splitlines()):
        s = line.strip()
        if not s:
            continue
        if s[0] == "c":
            parts = s.split(None, 2)
            if len(parts) == 3 and parts[1].isdigit():
                names[int(parts[1])] = parts[2].strip()
            continue
        if s[0] == "p":
            parts = s.split()
            lead = len(line) - len(line.lstrip())
            if len(parts) < 4 or parts[1] != "cnf" or not parts[2].isdigit() or not parts[3].isdigit():
                bad(ln, lead, len(line.rstrip()), f"bad problem line {s!r}: expected 'p cnf VARIABLES CLAUSES'")
                continue
            if seen_p:
                bad(ln, lead, len(line.rstrip()), "a second problem line")
            seen_p = True
            nvars = int(parts[2])
            continue
        if s[0] == "%":
            break
        col = 0
        for tok in s.split():
            col = line.index(tok, col)
            try:
                x = int(tok)
            except ValueError:
                bad(ln, col, col + len(tok), f"{tok!r} is not a literal (a signed variable number, 0 ends a clause)")
                col += len(tok)
                continue
            col += len(tok)
            if not cur:
                cur_line = ln
            if x == 0:
                clauses.append(cur)
                lines_of.append(cur_line)
                cur = []
            else:
                cur.append(x)
    if cur:
        clauses.append(cur)
        lines_of.append(cur_line)
    return nvars, clauses, names, lines_of


def _or_tree(items: list[M.Expr], span: Span, path: str) -> M.Expr:
    if not items:
        return M.BoolLit(False, span=span, path=path)
    while len(items) > 1:  # balanced, so no recursion gets deep
        nxt = []
        for i in range(0, len(items) - 1, 2):
            nxt.append(M.Binary("||", items[i], items[i + 1], span=span, path=path, type="bool"))
        if len(items) % 2:
            nxt.append(items[-1])
        items = nxt
    return items[0]


class _ClauseConstraint(M.Constraint):
    """A DIMACS clause as a constraint.  The encoder reads ``clause``; the expression (an OR
    tree of literal nodes) is built only when something asks for it (a conversion, a hover):
    10^5-10^6 clauses of trees were most of a big DIMACS model's time and memory."""

    def __init__(self, clause: list[int], lit, owner: M.Feature, span: Span, path: str):
        self.kind = "plain"
        self.owner = owner
        self.span = span
        self.path = path
        self.clause = clause
        self._lit = lit
        self._expr: Optional[M.Expr] = None

    @property
    def expr(self) -> M.Expr:  # type: ignore[override]
        if self._expr is None:
            self._expr = _or_tree([self._lit(x) for x in self.clause], self.span, self.path)
        return self._expr

    @expr.setter
    def expr(self, value: M.Expr) -> None:
        self._expr = value


def read_dimacs(text: str, path: str = "model.dimacs"):
    """The flat model of a DIMACS file and its diagnostics (malformed lines, names given to two
    variables); never raises on bad input."""
    from ..base.diagnostics import Diagnostic, Related, Severity, register
    errors: list = []
    model = dimacs_to_model(text, path, errors)
    syntax = register("syntax-error", Severity.ERROR, "the text does not follow the TVL grammar", "tvl")
    dup = register("duplicate-feature-name", Severity.ERROR, "two features of a UVL model have the same name", "uvl")
    diags = [Diagnostic(syntax, Severity.ERROR, path, Span(Pos(ln, c0), Pos(ln, c1)), msg)
             for ln, c0, c1, msg in errors]
    first: dict[str, M.Feature] = {}
    for f in model.features[1:]:
        if f.name in first and f.name_span != Span(Pos(0, 0), Pos(0, 0)):
            other = first[f.name]
            diags.append(Diagnostic(dup, Severity.ERROR, path, f.name_span,
                                    f"two variables are named '{f.name}': commands that take a feature name "
                                    "cannot tell them apart", related=[Related(path, other.name_span, "the other one")]))
        first.setdefault(f.name, f)
    return model, diags


def dimacs_to_model(text: str, path: str = "model.dimacs", errors: Optional[list] = None) -> M.Model:
    nvars, clauses, names, lines_of = parse_dimacs(text, errors)
    maxvar = max([nvars] + [abs(x) for c in clauses for x in c])
    if not nvars:  # no problem line: the comments may name more variables
        maxvar = max([maxvar] + [i for i in names if i <= 10 * maxvar + 1000])
    zero = Span(Pos(0, 0), Pos(0, 0))
    stem = re.sub(r"\W", "_", os.path.splitext(os.path.basename(path))[0]) or "model"
    if stem[0].isdigit():
        stem = "_" + stem
    taken = set(names.values())
    root_name = stem
    while root_name in taken:
        root_name = "_" + root_name
    root = M.Feature(root_name, zero, zero, path, is_root=True)
    model = M.Model(path=path, root=root, features=[root], sources={path: text}, format="dimacs")
    group = M.Group("card", root, zero, zero, path, lo=0, hi=None)
    root.group = group
    feats: list[M.Feature] = [root]
    for i in range(1, maxvar + 1):
        name = names.get(i)
        if name is None:
            name = f"_{i}"
            while name in taken:
                name = "_" + name
        f = M.Feature(name, zero, zero, path, parent=root)
        feats.append(f)
        group.children.append(M.GroupChild(f, True, False, zero, path))
    model.features = feats
    line_lens = [len(x) for x in text.splitlines()]
    # one shared (immutable in practice) literal node per signed variable: the big models have
    # 10^5 literals; literal nodes carry no span (the constraint's span is the clause's line)
    lit_nodes: dict[int, M.Expr] = {}

    def lit(x: int) -> M.Expr:
        node = lit_nodes.get(x)
        if node is None:
            f = feats[abs(x)]
            pos = lit_nodes.get(abs(x))
            if pos is None:
                pos = lit_nodes[abs(x)] = M.Name([f.name], target=f, path=path, type="bool")
            node = pos if x > 0 else M.Unary("!", pos, path=path, type="bool")
            lit_nodes[x] = node
        return node

    for c, ln in zip(clauses, lines_of):
        span = Span(Pos(ln, 0), Pos(ln, line_lens[ln] if ln < len(line_lens) else 0))
        root.constraints.append(_ClauseConstraint(c, lit, root, span, path))
    # feature name spans: the ``c i name`` comment line when there is one
    for ln, line in enumerate(text.splitlines()):
        if line.startswith("c "):
            parts = line.split(None, 2)
            if len(parts) == 3 and parts[1].isdigit() and int(parts[1]) <= maxvar:
                f = feats[int(parts[1])]
                start = line.index(parts[2], len(parts[0]) + len(parts[1]) + 1)
                f.name_span = f.span = Span(Pos(ln, start), Pos(ln, start + len(parts[2].rstrip())))
    return model
