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
from itertools import chain, repeat
from typing import Optional

from ..base.text import Span, Pos
from ..tvl import model as M
from .encode import Element
from .labels import line_text


# (the reader lives apart so that counting a DIMACS file loads no TVL model or parser)
from .dimacs_read import DimacsError, MAX_VARIABLES, _parse, _shift, parse_dimacs  # noqa: E402,F401


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


class _Clauses:
    """What the clause constraints of one model share: their owner, file, literal nodes and the
    length of each line of the file."""

    __slots__ = ("owner", "path", "lit", "line_lens")

    def __init__(self, owner: M.Feature, path: str, lit, line_lens: list[int]):
        self.owner = owner
        self.path = path
        self.lit = lit
        self.line_lens = line_lens


class ClauseConstraint(M.Constraint):
    """A DIMACS clause as a constraint.  The encoder reads ``lits``: the clause over the
    encoder's variables (the root is 1, DIMACS variable ``i`` is ``i + 1``), shared with the
    encoding rather than copied; ``clause`` (the DIMACS literals, signed indexes into
    ``Model.features``) is made from it when asked for.  The expression (an OR tree of literal
    nodes) is built only when something asks for it (a conversion, a hover): 10^5-10^6 clauses
    of trees were most of a big DIMACS model's time and memory.  For the same reason the span
    (the clause's first line, whole) is made when asked for, and what all the clauses share is
    in one :class:`_Clauses`; assigning ``span``, ``owner``, ``path`` or ``clause`` still works
    (the value is kept on the instance)."""

    __slots__ = ("lits", "_line", "_ctx", "_expr")
    kind = "plain"
    has_errors = False

    def __init__(self, lits: list[int], line: int, ctx: _Clauses):
        self.lits = lits
        self._line = line
        self._ctx = ctx
        self._expr: Optional[M.Expr] = None

    @property
    def clause(self) -> list[int]:  # type: ignore[override]
        return [x - 1 if x > 0 else x + 1 for x in self.lits]

    @clause.setter
    def clause(self, value: list[int]) -> None:
        self.lits = [x + 1 if x > 0 else x - 1 for x in value]

    @property
    def line_lens(self) -> list[int]:
        """The length of each line of the file (:func:`.labels.line_text` reads the lines by them)."""
        return self._ctx.line_lens

    @property
    def span(self) -> Span:  # type: ignore[override]
        try:
            return self._span_set
        except AttributeError:
            ln = self._line
            lens = self._ctx.line_lens
            return Span(Pos(ln, 0), Pos(ln, lens[ln] if ln < len(lens) else 0))

    @span.setter
    def span(self, value: Span) -> None:
        self._span_set = value

    @property
    def owner(self) -> M.Feature:  # type: ignore[override]
        try:
            return self._owner_set
        except AttributeError:
            return self._ctx.owner

    @owner.setter
    def owner(self, value: M.Feature) -> None:
        self._owner_set = value

    @property
    def path(self) -> str:  # type: ignore[override]
        try:
            return self._path_set
        except AttributeError:
            return self._ctx.path

    @path.setter
    def path(self, value: str) -> None:
        self._path_set = value

    @property
    def expr(self) -> M.Expr:  # type: ignore[override]
        if self._expr is None:
            self._expr = _or_tree([self._ctx.lit(x) for x in self.clause], self.span, self.path)
        return self._expr

    @expr.setter
    def expr(self, value: M.Expr) -> None:
        self._expr = value


_SLOTS = {k: Element.__dict__[k] for k in ("label", "path", "span", "negation")}


def _lazy(name: str, make):
    """A property over Element's slot ``name`` that is filled by ``make(element)`` when first read."""
    slot = _SLOTS[name]

    def get(self):
        try:
            return slot.__get__(self, Element)
        except AttributeError:
            value = make(self)
            slot.__set__(self, value)
            return value
    return property(get, slot.__set__)


class ClauseElement(Element):
    """The element of a DIMACS clause (``Constraint.clause``): its label, negation, path and
    span are made when first read (an explanation, a redundancy check), not for each of
    10^5-10^6 clauses; they are what :meth:`Encoding._encode_constraints` gives an ordinary
    constraint."""

    __slots__ = ("_ctx",)

    def __init__(self, c: M.Constraint, clauses: list[list[int]], ctx: tuple):
        self.kind = "constraint"
        self.obj = c
        self.clauses = clauses
        self.selector = 0
        self._ctx = ctx  # (model, the encoding's line cache)

    label = _lazy("label", lambda e: f"constraint `{line_text(e._ctx[0], e.obj, e._ctx[1]) or 'constraint'}`")
    path = _lazy("path", lambda e: e.obj.path)
    span = _lazy("span", lambda e: e.obj.span)
    negation = _lazy("negation", lambda e: ([-x for x in e.clauses[0]] if len(e.clauses) == 1
                                            else [False] if not e.clauses else None))


ClauseConstraint.element_type = ClauseElement  # what the encoder makes of one


def read_dimacs(text: str, path: str = "model.dimacs"):
    """The flat model of a DIMACS file and its diagnostics (malformed lines, names given to two
    variables); never raises on bad input."""
    from ..base.diagnostics import Diagnostic, Related, Severity, register
    errors: list = []
    model = dimacs_to_model(text, path, errors)
    syntax = register("syntax-error", Severity.ERROR, "The text does not follow the grammar of the model's language.", "tvl")
    dup = register("duplicate-feature-name", Severity.ERROR, "Two features of a UVL model have the same name.", "uvl")
    too_large = register("file-too-large", Severity.ERROR, "A file too large to analyse.", "tvl")
    diags = [Diagnostic(too_large if e[4:] == ("file-too-large",) else syntax, Severity.ERROR, path,
                        Span(Pos(e[0], e[1]), Pos(e[0], e[2])), e[3]) for e in errors]
    first: dict[str, M.Feature] = {}
    for f in model.features[1:]:
        if f.name in first and f.name_span != Span(Pos(0, 0), Pos(0, 0)):
            other = first[f.name]
            diags.append(Diagnostic(dup, Severity.ERROR, path, f.name_span,
                                    f"two variables are named '{f.name}': commands that take a feature name "
                                    "cannot tell them apart", related=[Related(path, other.name_span, "the other one")]))
        first.setdefault(f.name, f)
    return model, diags




def _too_large_at(text: str, nvars: int, clauses, lines_of, line_lens) -> tuple[int, int, int]:
    """(line, start, end) of what makes the model too large: its problem line, or the first
    clause with a variable past the cap (clauses are over the encoder's numbers: ``x + 1``)."""
    if nvars > MAX_VARIABLES:
        for ln, line in enumerate(text.splitlines()):
            if line.lstrip().startswith("p"):
                return ln, len(line) - len(line.lstrip()), len(line.rstrip())
    for c, ln in zip(clauses, lines_of):
        if any(abs(x) - 1 > MAX_VARIABLES for x in c):
            return ln, 0, line_lens[ln] if ln < len(line_lens) else 0
    return 0, 0, 0


def dimacs_to_model(text: str, path: str = "model.dimacs", errors: Optional[list] = None) -> M.Model:
    # the clauses over the encoder's variables (see ClauseConstraint)
    nvars, clauses, names, lines_of, line_lens, c_lines = _parse(text, errors, True)
    maxvar = max(nvars, max(chain.from_iterable(clauses), default=1) - 1,
                 -min(chain.from_iterable(clauses), default=-1) - 1)
    if not nvars:  # no problem line: the comments may name more variables
        maxvar = max([maxvar] + [i for i in names if i <= 10 * maxvar + 1000])
    if maxvar > MAX_VARIABLES:
        # ``p cnf 1000000000 1`` (or one literal 2^63) asked for a feature per variable: gigabytes
        msg = (f"the model has {maxvar:,} variables: models of more than {MAX_VARIABLES:,} variables are "
               "not analysed")
        if errors is None:
            raise DimacsError(msg)
        errors.append(_too_large_at(text, nvars, clauses, lines_of, line_lens) + (msg, "file-too-large"))
        clauses, lines_of, names, maxvar = [], [], {}, 0
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

    ctx = _Clauses(root, path, lit, line_lens)
    root.constraints.extend(map(ClauseConstraint, clauses, lines_of, repeat(ctx)))
    # feature name spans: the ``c i name`` comment line when there is one
    for ln, line in c_lines:
        parts = line.split(None, 2)
        if len(parts) == 3 and parts[1].isdigit() and int(parts[1]) <= maxvar:
            f = feats[int(parts[1])]
            start = line.index(parts[2], len(parts[0]) + len(parts[1]) + 1)
            f.name_span = f.span = Span(Pos(ln, start), Pos(ln, start + len(parts[2].rstrip())))
    return model
