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

from ..base.text import Span, Pos
from ..tvl import model as M


class DimacsError(ValueError):
    pass


def parse_dimacs(text: str) -> tuple[int, list[list[int]], dict[int, str], list[int]]:
    """(declared variables, clauses, names by index, line number of each clause)."""
    nvars = 0
    names: dict[int, str] = {}
    clauses: list[list[int]] = []
    lines_of: list[int] = []
    cur: list[int] = []
    cur_line = 0
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
            if len(parts) < 4 or parts[1] != "cnf":
                raise DimacsError(f"line {ln + 1}: bad problem line {s!r}")
            nvars = int(parts[2])
            continue
        if s[0] == "%":
            break
        for tok in s.split():
            try:
                x = int(tok)
            except ValueError:
                raise DimacsError(f"line {ln + 1}: {tok!r} is not a literal") from None
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


def dimacs_to_model(text: str, path: str = "model.dimacs") -> M.Model:
    nvars, clauses, names, lines_of = parse_dimacs(text)
    maxvar = max([nvars] + [abs(x) for c in clauses for x in c] + list(names))
    zero = Span(Pos(0, 0), Pos(0, 0))
    stem = re.sub(r"\W", "_", os.path.splitext(os.path.basename(path))[0]) or "model"
    if stem[0].isdigit():
        stem = "_" + stem
    taken = set(names.values())
    root_name = stem
    while root_name in taken:
        root_name = "_" + root_name
    root = M.Feature(root_name, zero, zero, path, is_root=True)
    model = M.Model(path=path, root=root, features=[root], sources={path: text})
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
        items = [lit(x) for x in c]
        root.constraints.append(M.Constraint(_or_tree(items, span, path), "plain", root, span, path))
    # feature name spans: the ``c i name`` comment line when there is one
    for ln, line in enumerate(text.splitlines()):
        if line.startswith("c "):
            parts = line.split(None, 2)
            if len(parts) == 3 and parts[1].isdigit() and int(parts[1]) <= maxvar:
                f = feats[int(parts[1])]
                start = line.index(parts[2], len(parts[0]) + len(parts[1]) + 1)
                f.name_span = f.span = Span(Pos(ln, start), Pos(ln, start + len(parts[2].rstrip())))
    return model
