"""The products a graph is about, and the questions the graph asks of them.

    logic = GraphLogic(encoding, free_names, model_analysis)   # encoding None: no model
    o = logic.oracle(variables)        # answers about formulas over these names
    o.empty(o.term(f))                 # no product satisfies f
    o.witness(o.term(f))               # the smallest product satisfying f (name -> bool)
    o.count(o.term(f))                 # how many products satisfy f (None: not countable)

Two ways to answer, the same answers:

- a **product table** when the products are few enough to list (``TABLE_LIMIT``; the thesis's
  models have 4 to 2,304): every product (or, for larger models, every assignment of just the
  names the graph uses) is one bit of a Python integer, a formula's *term* is the set of products
  where it holds, and every question is a few integer operations — thousands of elements and
  findings cost milliseconds.  Rows are ordered smallest product first (fewest selected features,
  then the features declared first), so a witness is the lowest set bit;
- the **SAT service** otherwise (:class:`~tvl_lsp.analysis.crosscheck.PairLogic`: the model's
  CNF and Tseitin-encoded conditions), one solver call per question.
"""

from __future__ import annotations

import itertools
import time
from typing import Iterable, Optional

from ..base import formula as fm

TABLE_LIMIT = 50_000       # rows of a product table
TABLE_SECONDS = 2.0        # time to build one
MAX_FREE_EXPANSION = 12    # free (non-feature) args expanded in a table


class GraphLogic:
    """The products: a model's (``encoding``; None: no model, every name a free boolean) with
    the launch file's other free args (``free_names``)."""

    def __init__(self, encoding=None, free_names: Iterable[str] = (), analysis=None, *,
                 table_limit: int = TABLE_LIMIT, full_table: bool = True):
        """``table_limit``: most rows of a product table (0: always the SAT service);
        ``full_table``: try a table of every product before one of the names used."""
        self.enc = encoding
        self.table_limit = table_limit
        self.analysis = analysis
        self.free = [n for n in dict.fromkeys(free_names)
                     if encoding is None or encoding.feature_by_name(n) is None]
        self._pair = None
        self._full: Optional[_Table] = None
        self._full_tried = not full_table
        self._projected: dict[frozenset, Optional[_Table]] = {}
        self._count_cache: dict = {}
        self.count_timeout: Optional[float] = 10.0

    # ------------------------------------------------------------------ basics
    @property
    def pair(self):
        if self._pair is None:
            from ..analysis.solve import PairLogic
            self._pair = PairLogic(self.enc, self.free)
        return self._pair

    def close(self) -> None:
        if self._pair is not None:
            self._pair.close()
            self._pair = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def is_feature(self, name: str) -> bool:
        return self.enc is not None and self.enc.feature_by_name(name) is not None

    def known(self, name: str) -> bool:
        return self.is_feature(name) or name in self.free

    def names(self) -> list[str]:
        """Every name a decision can be about, features first (declaration order)."""
        out = [self.enc.name_of(f) for f in self.enc.features] if self.enc is not None else []
        return out + list(self.free)

    def canonical(self, name: str) -> str:
        if self.enc is not None:
            f = self.enc.feature_by_name(name)
            if f is not None:
                return self.enc.name_of(f)
        return name

    def decision_formula(self, decisions) -> fm.Formula:
        return fm.conj(fm.Var(k) if v else fm.neg(fm.Var(k)) for k, v in decisions.items())

    # ------------------------------------------------------------------ oracles
    def oracle(self, variables: Iterable[str] = ()) -> "Oracle":
        """An oracle for formulas over ``variables`` (names of features / free args)."""
        vs = frozenset(self.canonical(v) for v in variables)
        t = self._table(vs)
        return TableOracle(self, t) if t is not None else SatOracle(self)

    def _table(self, vs: frozenset) -> Optional["_Table"]:
        if self.table_limit <= 0:
            return None
        if not self._full_tried:
            self._full_tried = True
            self._full = _build_table(self, None)
        if self._full is not None:
            return self._full
        if vs not in self._projected:
            self._projected[vs] = _build_table(self, sorted(vs, key=self._order))
        return self._projected[vs]

    def _order(self, name: str) -> tuple:
        names = self.names()
        return (names.index(name) if name in names else len(names), name)

    # ------------------------------------------------------------------ SAT helpers (fallback)
    def sat(self, f: fm.Formula) -> bool:
        return self.pair.sat(f)

    def witness(self, f: fm.Formula) -> Optional[dict[str, bool]]:
        return self.pair.witness(f)

    def count(self, f: fm.Formula) -> Optional[int]:
        """Products of the model satisfying ``f`` by the counting service (None: ``f`` reads
        names that are not features, or no answer in time)."""
        if f == fm.FALSE:
            return 0
        vs = fm.variables(f)
        if self.enc is None or self.analysis is None or not all(self.is_feature(v) for v in vs):
            return None
        if f in self._count_cache:
            return self._count_cache[f]
        try:
            n = self.analysis.count(formula=None if f == fm.TRUE else f, timeout=self.count_timeout)
        except Exception:
            n = None
        self._count_cache[f] = n
        return n


class _Table:
    """Rows of truth values over ``names``; row i is bit i of every term."""

    def __init__(self, names: list[str], rows: list[tuple], full: bool, weight_free: int):
        self.names = names
        self.index = {n: i for i, n in enumerate(names)}
        self.n = len(rows)
        self.all = (1 << self.n) - 1
        self.rows = rows
        self.full = full                  # one row per product (x free-arg assignments)
        self.weight_free = weight_free    # rows per model product (2 ** free args expanded)
        self.var_mask: dict[str, int] = {}
        for j, name in enumerate(names):
            bits = "".join("1" if rows[i][j] else "0" for i in range(self.n - 1, -1, -1))
            self.var_mask[name] = int(bits, 2) if bits else 0


def _build_table(logic: GraphLogic, projected: Optional[list[str]]) -> Optional[_Table]:
    """Every product (``projected`` None) or every assignment of the ``projected`` names that
    some product has; None when there are more than TABLE_LIMIT or it takes too long."""
    deadline = time.monotonic() + TABLE_SECONDS
    enc = logic.enc
    free = list(logic.free) if projected is None else [n for n in projected if n in logic.free]
    if len(free) > MAX_FREE_EXPANSION:
        return None
    if enc is not None:
        feats = [enc.name_of(f) for f in enc.features] if projected is None else \
            [n for n in projected if logic.is_feature(n)]
        fvars = [enc.var(n) for n in feats]
        from ..analysis.sat import BoundedSolver as Solver
        s = Solver(name="minisat22", bootstrap_with=enc.clauses())
        rows: list[tuple] = []
        try:
            while s.solve():
                m = s.get_model()
                row = tuple(m[v - 1] > 0 for v in fvars)
                rows.append(row)
                if len(rows) * (1 << len(free)) > logic.table_limit or time.monotonic() > deadline:
                    return None
                if not fvars:
                    break
                s.add_clause([-v if val else v for v, val in zip(fvars, row)])
        finally:
            s.delete()
    else:
        feats = []
        rows = [()]
    if free:
        if len(rows) * (1 << len(free)) > logic.table_limit:
            return None
        rows = [r + tuple(bits) for r in rows for bits in itertools.product((False, True), repeat=len(free))]
    names = feats + free
    # smallest product first: fewest selected, then the names declared first selected
    rows.sort(key=lambda r: (sum(r), tuple(not x for x in r)))
    return _Table(names, rows, projected is None, 1 << len(free))


# ------------------------------------------------------------------ oracles

class Oracle:
    """Terms stand for sets of products; ``term`` maps a formula to its term."""

    def term(self, f: fm.Formula):
        raise NotImplementedError

    def and_(self, a, b):
        raise NotImplementedError

    def not_(self, a):
        raise NotImplementedError

    def empty(self, a) -> bool:
        raise NotImplementedError

    def witness(self, a, formula: fm.Formula) -> Optional[dict[str, bool]]:
        raise NotImplementedError

    def count(self, a, formula: fm.Formula) -> Optional[int]:
        raise NotImplementedError

    def full(self, a) -> bool:
        """Every product is in ``a``."""
        return self.empty(self.not_(a))


class SatOracle(Oracle):
    """Terms are formulas; questions go to the SAT service."""

    def __init__(self, logic: GraphLogic):
        self.logic = logic
        self._sat: dict[fm.Formula, bool] = {}

    def term(self, f):
        return f

    def and_(self, a, b):
        return fm.conj([a, b])

    def not_(self, a):
        return fm.neg(a)

    def empty(self, a) -> bool:
        if a == fm.FALSE:
            return True
        if a == fm.TRUE:
            return not self._is_sat(fm.TRUE)
        return not self._is_sat(a)

    def _is_sat(self, a) -> bool:
        hit = self._sat.get(a)
        if hit is None:
            hit = self._sat[a] = self.logic.sat(a)
        return hit

    def witness(self, a, formula):
        return self.logic.witness(a)

    def count(self, a, formula):
        return self.logic.count(a)


class TableOracle(Oracle):
    """Terms are sets of rows of a product table (Python integers)."""

    def __init__(self, logic: GraphLogic, table: _Table):
        self.logic = logic
        self.t = table
        self._memo: dict[fm.Formula, int] = {}

    def term(self, f: fm.Formula) -> int:
        hit = self._memo.get(f)
        if hit is not None:
            return hit
        t = self.t
        if isinstance(f, fm.Const):
            out = t.all if f.value else 0
        elif isinstance(f, fm.Var):
            name = self.logic.canonical(f.name)
            m = t.var_mask.get(name)
            if m is None:
                raise KeyError(f"{f.name} is not a name of this product table")
            out = m
        elif isinstance(f, fm.Not):
            out = t.all & ~self.term(f.arg)
        elif isinstance(f, fm.And):
            out = t.all
            for a in f.args:
                out &= self.term(a)
                if not out:
                    break
        else:
            out = 0
            for a in f.args:
                out |= self.term(a)
        self._memo[f] = out
        return out

    def and_(self, a, b):
        return a & b

    def not_(self, a):
        return self.t.all & ~a

    def empty(self, a) -> bool:
        return a == 0

    def full(self, a) -> bool:
        return a == self.t.all

    def witness(self, a, formula):
        if not a:
            return None
        if not self.t.full:
            return self.logic.witness(formula)
        i = (a & -a).bit_length() - 1
        row = self.t.rows[i]
        return {n: row[j] for j, n in enumerate(self.t.names)}

    def count(self, a, formula):
        """Products of the model (not free-arg assignments) in ``a``."""
        if self.t.full:
            if self.logic.enc is not None and any(not self.logic.is_feature(v) for v in fm.variables(formula)):
                return None
            return bin(a).count("1") // self.t.weight_free if self.logic.enc is not None else bin(a).count("1")
        return self.logic.count(formula)
