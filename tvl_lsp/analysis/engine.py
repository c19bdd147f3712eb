"""The one facade the CLI, the cross-file checks and the server call.

    a = ModelAnalysis(model)                 # or ModelAnalysis.from_dimacs(text, path)
    a.is_void()
    a.anomalies(time_budget=10.0)            # -> list[Diagnostic]
    a.count(include=("Kobuki",), exclude=(), formula=None, timeout=None, cancel=None)  # -> int
    a.count_result(...)                      # -> Count(value, engine, seconds)
    a.feature_counts()                       # -> {feature name: number of products with it}
    a.feature_counts_result(include, exclude)  # -> FeatureCounts (one pass over the d-DNNF)
    a.sample(t=2) / a.sample(uniform=10, seed=1)  # -> ([{name: bool}], engine)
    a.twise_sample(t=3, budget=60)            # -> ([{name: bool}], SampleResult: complete, coverage)
    a.find_product(formula, include, exclude, smallest=True)  # -> {name: bool} | None
    a.propagate({"Kobuki": True, "Teleop": False})            # -> Propagation
    for product in a.enumerate(limit=100): ...                # -> {name: bool}

Feature names are the short names when unique, else the long names ("Root.A.B"), as
:meth:`Encoding.feature_by_name` resolves them.  Counts are Python ints, answered by the
counting service (:mod:`.counting`: d4's d-DNNF, pyganak as the fallback).
"""

from __future__ import annotations

import functools
import threading
import time
from typing import TYPE_CHECKING, Iterable, Iterator, Mapping, Optional

from ..base.diagnostics import Diagnostic, Related, Severity, register
from ..tvl import model as M
from ..base import formula as fm
from .counting.errors import CancelLike, CountCancelled, CountTimeout
from .counting.service import CNFCounter, Count, FeatureCounts
from .encode import Element, Encoding, encode
# solve (the SAT-based analyses, pysat's totalizer) and configure are imported when first used:
# counting a model needs neither (0.01-0.02 s of a cold `tvl-lsp count`)
if TYPE_CHECKING:
    from .solve import Analyzer, Explanation

VOID_MODEL = register("void-model", Severity.ERROR,
                      "The feature model has no product: no selection of features satisfies it.", "analysis")
DEAD_FEATURE = register("dead-feature", Severity.WARNING,
                        "A feature that no product can select.", "analysis")
MIN_DETECTION = 2.0  # seconds the search for dead / false-optional features gets at least
ANOMALY_BUDGET = register("anomaly-budget", Severity.INFORMATION,
                          "The search for dead and false-optional features ran out of its time budget.", "analysis")
FALSE_OPTIONAL = register("false-optional", Severity.WARNING,
                          "An optional feature that is selected in every product that selects its parent.",
                          "analysis")
REDUNDANT_CONSTRAINT = register("redundant-constraint", Severity.INFORMATION,
                                "A constraint already implied by the rest of the model.", "analysis")
ALWAYS_FALSE_CONSTRAINT = register("always-false-constraint", Severity.ERROR,
                                   "A constraint that no selection of features allowed by the feature tree satisfies.", "analysis")


def _locked(fn):
    """python-sat solvers are not thread-safe: one analysis answers one request at a time."""
    @functools.wraps(fn)
    def wrapper(self, *args, **kwargs):
        with self._lock:
            return fn(self, *args, **kwargs)
    return wrapper


def _reported(e: Element) -> bool:
    """An attribute value or constraint the front end has reported as an error (a value outside its
    domain): encoded, but what it causes is not reported again."""
    return e.kind in ("attribute", "constraint") and getattr(e.obj, "reported_error", False)


def _impossible_group(e: Element, fmt: str) -> bool:
    """A group whose bounds the front end rejects: lower above upper (TVL, UVL), or above its number of
    children (TVL's cardinality-exceeds-children; in UVL that is an anomaly, not an error)."""
    g = e.obj
    if e.kind != "group-lower" or not isinstance(g, M.Group):
        return False
    return (g.hi is not None and g.lo > g.hi) or (fmt == "tvl" and g.lo > len(g.children))


class ModelAnalysis:
    def __init__(self, model: M.Model, encoding: Optional[Encoding] = None):
        self._lock = threading.RLock()
        self.model = model
        self._enc = encoding
        self._an: Optional[Analyzer] = None
        self._counter: Optional[CNFCounter] = None

    @classmethod
    def from_dimacs(cls, text: str, path: str = "model.dimacs") -> "ModelAnalysis":
        from .dimacs import dimacs_to_model
        return cls(dimacs_to_model(text, path))

    @classmethod
    def from_file(cls, path: str, text: Optional[str] = None) -> "ModelAnalysis":
        """A .tvl, .uvl or .dimacs model (what it could read of it: see
        :func:`tvl_lsp.analysis.formats.parse_any_model` for its diagnostics)."""
        from .formats import parse_any_model
        if text is None:
            from ..base.files import read_text
            text = read_text(path)
        return cls(parse_any_model(text, path).model)

    # ------------------------------------------------------------------ basics
    @property
    @_locked
    def encoding(self) -> Encoding:
        if self._enc is None:
            self._enc = encode(self.model)
        return self._enc

    @property
    def analyzer(self) -> Analyzer:
        if self._an is None:
            from .solve import Analyzer
            self._an = Analyzer(self.encoding)
        return self._an

    def name(self, f: M.Feature) -> str:
        return self.encoding.name_of(f)

    def _lits(self, include: Iterable[str] = (), exclude: Iterable[str] = ()) -> list[int]:
        enc = self.encoding
        return [enc.var(n) for n in include] + [-enc.var(n) for n in exclude]

    def _product(self, model: list[int]) -> dict[str, bool]:
        enc = self.encoding
        return {self.name(f): model[v - 1] > 0 for f, v in enc.var_of_feature.items()}

    @_locked
    def is_void(self) -> bool:
        return self.analyzer.is_void()

    @_locked
    def core_features(self) -> list[str]:
        return [self.name(f) for f in self.analyzer.core()]

    @_locked
    def dead_features(self) -> list[str]:
        return [self.name(f) for f in self.analyzer.dead()]

    @_locked
    def false_optional_features(self) -> list[str]:
        return [self.name(f) for f, _ in self.analyzer.false_optional()]

    @_locked
    def explain(self, include: Iterable[str] = (), exclude: Iterable[str] = (),
                formula: Optional[fm.Formula] = None) -> Optional[list[Element]]:
        """The minimal set of model elements that forbids the given partial configuration
        (and formula); None when some product allows it."""
        an = self.analyzer
        extra = self._lits(include, exclude)
        side: list[list[int]] = []
        if formula is not None:
            an.selector_solver  # selectors numbered first
            top = max(an.selector_solver.nof_vars(), self.encoding.nvars + len(self.encoding.elements)) + 1
            cls, top2 = self.encoding.formula_clauses(formula, top)
            g = top2 + 1  # guard: the formula's clauses only hold under g
            side = [c + [-g] for c in cls]
            for c in side:
                an.selector_solver.add_clause(c)
            extra.append(g)
        ex = an.explain(extra, side_clauses=side)
        return ex.elements if ex else None

    # ------------------------------------------------------------------ anomalies
    @_locked
    def anomalies(self, time_budget: Optional[float] = 10.0, hard_budget: Optional[float] = None,
                  explain: bool = True) -> list[Diagnostic]:
        """Void model, dead and false-optional features, redundant and always-false constraints,
        each explained.  ``time_budget``: seconds for the explanations (finding the anomalies gets
        at least ``MIN_DETECTION``); ``hard_budget``: seconds from now (the encoding included)
        that nothing passes, the search stops and says so (a caller's own budget).
        ``explain=False``: the same findings without their explanations (what a quick fix's
        re-check needs: ``project.fixes``), explaining only where an explanation decides
        whether a finding is reported."""
        t0 = time.monotonic()
        enc = self.encoding
        an = self.analyzer
        start = time.monotonic()
        hard_by = None if hard_budget is None else t0 + hard_budget
        deadline = None if time_budget is None else start + time_budget
        if hard_by is not None and (deadline is None or hard_by < deadline):
            deadline = hard_by
        out: list[Diagnostic] = list(enc.diagnostics())
        wanted = explain

        def related(ex: Optional[Explanation]) -> list[Related]:
            if ex is None:
                return []
            return [Related(e.path, e.span, e.label) for e in ex.elements]

        def because(ex: Optional[Explanation]) -> str:
            if not wanted:
                return ""
            if ex is None:
                return " (no explanation: the time budget ran out)"
            labels = [e.label for e in ex.elements]
            s = "; ".join(labels[:4]) + ("; …" if len(labels) > 4 else "")
            return f" Because: {s}." if labels else ""

        # (an explanation decides whether a finding caused by an element the front end reported
        # is reported again)
        filtering = any(_reported(e) or _impossible_group(e, self.model.format) for e in enc.elements)

        def explain(extra, among=None, needed=False) -> Optional[Explanation]:
            if not wanted and not (needed and filtering):
                return None
            if deadline is not None and time.monotonic() > deadline:
                return None
            return an.explain(extra, deadline=deadline, among=among)

        root = self.model.root
        if an.is_void():
            ex = explain([], needed=True)
            rpath = root.path if root else self.model.path
            rspan = root.name_span if root else None
            from ..base.text import ZERO_SPAN
            if ex is not None and any(_impossible_group(e, self.model.format) or _reported(e) for e in ex.elements):
                # the front end has reported the group's bounds as an error already (cardinality-bounds,
                # cardinality-exceeds-children): one error for one mistake
                return out
            out.append(Diagnostic(VOID_MODEL, Severity.ERROR, rpath, rspan or ZERO_SPAN,
                                  "This feature model has no product: no selection of features satisfies it."
                                  + because(ex), related=related(ex)))
            _, always_false = an.redundant_and_always_false(deadline=deadline)
            for e in always_false:
                structure = [x.selector for x in enc.elements if x.kind != "constraint"]
                ex = explain([], among=structure + [e.selector])
                out.append(Diagnostic(ALWAYS_FALSE_CONSTRAINT, Severity.ERROR, e.path, e.span,
                                      "This constraint can never hold with the feature tree." + because(ex),
                                      related=related(ex)))
            return out
        v = enc.var_of_feature
        # the budget is the explanations'; finding the anomalies gets at least MIN_DETECTION s
        # (milliseconds on ordinary models), then stops and says so rather than overrun
        detect_by = None if time_budget is None else start + max(time_budget, MIN_DETECTION)
        by_hard = hard_by is not None and (detect_by is None or hard_by < detect_by)
        if by_hard:
            detect_by = hard_by
        detect_secs = max(0.0, detect_by - start) if detect_by is not None else 0.0
        if by_hard:
            budget_txt = f"what the file's CPU budget left after reading and encoding it, {detect_secs:.2g} s"
        else:
            budget_txt = f"{detect_secs:.3g} s"
        bb = an.backbone(detect_by)
        fo = (an.false_optional(detect_by) if self.model.format != "dimacs" else []) if bb is not None else None
        if bb is None or fo is None:
            from ..base.text import ZERO_SPAN
            out.append(Diagnostic(
                ANOMALY_BUDGET, Severity.INFORMATION, root.path if root else self.model.path,
                root.name_span if root else ZERO_SPAN,
                f"The search for {'dead and ' if bb is None else ''}false-optional features ran out of its "
                f"time budget ({budget_txt}) on this model of {enc.n_features:,} features: "
                f"{'none are' if bb is None else 'false-optional features are not'} reported "
                "(the editor's count.timeBudget setting, or `--budget` for `--check`, raises the budget)"))
        for f in (an.dead() if bb is not None else []):
            ex = explain([v[f]], needed=True)
            if ex is not None and any(_reported(e) for e in ex.elements):
                continue  # caused by a value the front end reported as an error
            out.append(Diagnostic(DEAD_FEATURE, Severity.WARNING, f.path, f.name_span,
                                  f"Feature {self.name(f)} is dead: no product can select it." + because(ex),
                                  related=related(ex), data={"feature": self.name(f)}))
        # a DIMACS model has no hierarchy: "optional" means nothing there
        for f, p in (fo or []):
            ex = explain([v[p], -v[f]])
            out.append(Diagnostic(FALSE_OPTIONAL, Severity.WARNING, f.path, f.name_span,
                                  f"Feature {self.name(f)} is declared optional but every product that "
                                  f"selects {self.name(p)} also selects it." + because(ex),
                                  related=related(ex), data={"feature": self.name(f), "parent": self.name(p)}))
        redundant, _ = an.redundant_and_always_false(deadline=deadline)
        allsel = [e.selector for e in enc.elements]
        for e in redundant:
            if e.negation == [False]:
                out.append(Diagnostic(REDUNDANT_CONSTRAINT, Severity.INFORMATION, e.path, e.span,
                                      "This constraint always holds: it constrains nothing."))
                continue
            ex = explain([x for x in (e.negation or []) if x is not True],
                         among=[x for x in allsel if x != e.selector])
            out.append(Diagnostic(REDUNDANT_CONSTRAINT, Severity.INFORMATION, e.path, e.span,
                                  "This constraint is redundant: the rest of the model already implies it."
                                  + because(ex), related=related(ex)))
        return out

    # ------------------------------------------------------------------ counting
    @property
    def counter(self) -> CNFCounter:
        """The counting service for this model's CNF (compiled once, on first use)."""
        with self._lock:
            if self._counter is None:
                enc = self.encoding
                root = self.model.root.name if self.model.root is not None else "model"
                self._counter = CNFCounter(enc.nvars, enc.clauses(), enc.n_features,
                                           determined=enc.aux_determined(), label=root)
            return self._counter

    def count_result(self, include: Iterable[str] = (), exclude: Iterable[str] = (),
                     formula: Optional[fm.Formula] = None, timeout: Optional[float] = None,
                     cancel: CancelLike = None, progress=None) -> Count:
        """The exact number of products with the included features, without the excluded
        ones, satisfying ``formula`` (over feature names), and which engine answered.
        Raises CountTimeout / CountCancelled."""
        assumptions = self._lits(include, exclude)
        svc = self.counter
        if formula is None:
            return svc.count(assumptions, timeout=timeout, cancel=cancel, progress=progress)
        t0 = time.perf_counter()
        cubes = self._cubes(formula)
        if cubes is not None:
            total = 0
            engine = None
            for cube in cubes:
                left = None if timeout is None else max(0.05, timeout - (time.perf_counter() - t0))
                c = svc.count(assumptions + cube, timeout=left, cancel=cancel, progress=progress)
                total += c.value
                engine = c.engine if engine in (None, c.engine, "trivial") else engine
            return Count(total, engine or "trivial", time.perf_counter() - t0)
        # too many cubes: count the CNF and the formula's clauses together
        enc = self.encoding
        extra, top = enc.formula_clauses(formula)
        both = CNFCounter(top, enc.clauses() + extra, enc.n_features, determined=svc.determined,
                          label=svc.label)
        return both.count(assumptions, timeout=timeout, cancel=cancel, progress=progress)

    def count(self, include: Iterable[str] = (), exclude: Iterable[str] = (),
              formula: Optional[fm.Formula] = None, timeout: Optional[float] = None,
              cancel: CancelLike = None) -> int:
        """Exact number of products (see :meth:`count_result`)."""
        return self.count_result(include, exclude, formula, timeout, cancel).value

    def _cubes(self, formula: fm.Formula, limit: int = 4096) -> Optional[list[list[int]]]:
        """Disjoint cubes (lists of feature literals) whose union is the formula's models, by
        Shannon expansion on its variables; None when there would be more than ``limit``."""
        enc = self.encoding
        names = fm.variables(formula)
        var = {n: enc.var(n) for n in names}  # KeyError for an unknown feature
        freq: dict[str, int] = {}

        def walk(f):
            stack = [f]
            while stack:
                g = stack.pop()
                if isinstance(g, fm.Var):
                    freq[g.name] = freq.get(g.name, 0) + 1
                elif isinstance(g, fm.Not):
                    stack.append(g.arg)
                elif isinstance(g, (fm.And, fm.Or)):
                    stack.extend(g.args)
        walk(formula)
        order = sorted(names, key=lambda n: (-freq.get(n, 0), n))
        out: list[list[int]] = []
        stack: list[tuple[fm.Formula, list[int], int]] = [(formula, [], 0)]
        while stack:
            f, cube, k = stack.pop()
            if isinstance(f, fm.Const):
                if f.value:
                    out.append(cube)
                    if len(out) > limit:
                        return None
                continue
            rest = fm.variables(f)
            while order[k] not in rest:
                k += 1
            name = order[k]
            v = var[name]
            stack.append((fm.substitute(f, {name: fm.FALSE}), cube + [-v], k + 1))
            stack.append((fm.substitute(f, {name: fm.TRUE}), cube + [v], k + 1))
            if len(stack) > 4 * limit:
                return None
        return out

    def feature_counts_result(self, include: Iterable[str] = (), exclude: Iterable[str] = (),
                              timeout: Optional[float] = None, cancel: CancelLike = None,
                              progress=None, order: Optional[Iterable[int]] = None) -> FeatureCounts:
        """Every feature's number of products (within the decisions): one pass over the
        compiled d-DNNF; ``counts[v]`` for the feature numbered ``v`` (None: not counted in
        time, pyganak only, which counts the features numbered in ``order`` first)."""
        svc = self.counter

        def backbone() -> dict[int, bool]:
            with self._lock:
                return dict(self.analyzer.backbone())
        return svc.feature_counts(self._lits(include, exclude), timeout=timeout, cancel=cancel,
                                  progress=progress, backbone=backbone, order=order)

    def feature_counts(self, timeout: Optional[float] = None, cancel: CancelLike = None,
                       include: Iterable[str] = (), exclude: Iterable[str] = ()) -> dict[str, int]:
        """Number of products containing each feature (dead: 0, core: the total).  With a
        timeout, features not counted in time are left out of the result."""
        try:
            r = self.feature_counts_result(include, exclude, timeout=timeout, cancel=cancel)
        except CountTimeout:
            return {}
        enc = self.encoding
        return {self.name(f): r.counts[v] for f, v in enc.var_of_feature.items() if r.counts[v] is not None}

    # ------------------------------------------------------------------ sampling
    def sample(self, t: Optional[int] = None, uniform: Optional[int] = None, seed: Optional[int] = 0,
               include: Iterable[str] = (), exclude: Iterable[str] = (), timeout: Optional[float] = None,
               cancel: CancelLike = None) -> tuple[list[dict[str, bool]], str]:
        """Products as {feature name: selected}: ``uniform`` of them drawn uniformly at random
        (with replacement), or a ``t``-wise covering sample (t = 1, 2, 3: see
        :meth:`twise_sample`).  Returns (products, engine).  Raises CountTimeout when the
        ``timeout`` (seconds) ends before the sample is complete, CountCancelled."""
        if uniform is not None:
            svc = self.counter
            prods, engine = svc.sample_uniform(uniform, seed=seed, assumptions=self._lits(include, exclude),
                                               timeout=timeout, cancel=cancel)
            return [self._named(p) for p in prods], engine
        if t is None:
            raise ValueError("say t (t-wise) or uniform (how many)")
        prods, r = self.twise_sample(t, seed=seed or 0, include=include, exclude=exclude, budget=timeout,
                                     cancel=cancel)
        if not r.complete:
            if r.stopped == "cancelled":
                raise CountCancelled()
            raise CountTimeout(f"no complete {t}-wise sample within {timeout:g} s")
        return prods, "sat"

    def twise_sample(self, t: int = 2, seed: int = 0, include: Iterable[str] = (), exclude: Iterable[str] = (),
                     budget: Optional[float] = None, cancel: CancelLike = None,
                     iterations: Optional[int] = None, jobs: int = 1):
        """A ``t``-wise covering sample (t = 1, 2, 3) of the products with the included and
        without the excluded features (:mod:`.sampling`: a warm SAT solver, no compilation):
        (products as {feature name: selected}, :class:`.sampling.SampleResult`).  When the
        ``budget`` (seconds) runs out the sample is partial: ``result.complete`` is False and
        the result says the coverage reached and the interactions left."""
        from .sampling import sample
        enc = self.encoding
        with self._lock:
            clauses = enc.clauses()
        r = sample(clauses, enc.n_features, t=t, seed=seed, assumptions=self._lits(include, exclude),
                   budget=budget, cancel=cancel, iterations=iterations, jobs=jobs)
        return [self._named(p) for p in r.products], r

    def _named(self, p: list[int]) -> dict[str, bool]:
        enc = self.encoding
        if not hasattr(self, "_names_by_var"):
            self._names_by_var = {v: self.name(f) for f, v in enc.var_of_feature.items()}
        names = self._names_by_var
        return {names[abs(x)]: x > 0 for x in sorted(p, key=abs) if abs(x) in names}

    # ------------------------------------------------------------------ products
    def _extra(self, formula: Optional[fm.Formula]) -> list[list[int]]:
        return self.encoding.formula_clauses(formula)[0] if formula is not None else []

    def enumerate(self, limit: Optional[int] = 100, include: Iterable[str] = (), exclude: Iterable[str] = (),
                  formula: Optional[fm.Formula] = None) -> Iterator[dict[str, bool]]:
        """Products one by one (each a {feature name: selected} dict), at most ``limit``."""
        from .solve import products
        for m in products(self.encoding, self._lits(include, exclude), self._extra(formula), limit):
            yield self._product(m)

    def find_product(self, formula: Optional[fm.Formula] = None, include: Iterable[str] = (),
                     exclude: Iterable[str] = (), smallest: bool = True) -> Optional[dict[str, bool]]:
        """A product satisfying the formula and the partial configuration (the one with the
        fewest selected features when ``smallest``), or None when there is none."""
        from .solve import smallest_product
        m = smallest_product(self.encoding, self._lits(include, exclude), self._extra(formula), smallest)
        return None if m is None else self._product(m)

    # ------------------------------------------------------------------ configuration
    def propagate(self, decisions: Mapping[str, bool], count: bool = True,
                  timeout: Optional[float] = 5.0):
        from .configure import propagate
        return propagate(self, decisions, count=count, timeout=timeout)
