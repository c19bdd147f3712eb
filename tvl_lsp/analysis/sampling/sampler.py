"""The sampling run: preparation, the covering loop, the budget, iterations and ``jobs``."""

from __future__ import annotations

import random
import time
from dataclasses import dataclass, field
from typing import Optional, Sequence

from ..counting.errors import CancelLike, is_cancelled
from ..sat import SolverInterrupted, cpu_limit
from .pairwise import CoverState, LiteralCover, PairCover, Stop, initial_literals, initial_pairs
from .prepare import Prepared, SamplingTimeout, prepare

# with iterations=None, runs while they are cheap: a run's work is about its configurations times
# the representative features (each configuration visits each of them); runs are added up to
# this much work in all (turtlebot pairwise: 23 x 20, 32 runs; busybox: 30 x 790, 4 runs;
# fiasco: 226 x 180, 2; automotive01: 963 x 1,701, 1)
AUTO_WORK = 100_000
AUTO_MAX = 32

# 3-wise bookkeeping is one bitset per pair of literals: beyond this many bytes, refuse (the
# message says how many features to decide first)
MAX_TRIPLE_MEMORY = 2 ** 30


@dataclass
class SampleResult:
    products: list[list[int]]        # literals of features 1..n, one list per configuration
    t: int
    complete: bool                   # every valid interaction is covered
    void: bool = False               # no product at all
    considered: int = 0              # interactions of the representative features not ruled out
                                     # by unit propagation at the start
    invalid: int = 0                 # of those, proven invalid by a SAT call
    left: int = 0                    # not covered, not proven invalid (0 when complete)
    features: int = 0                # features 1..n
    open_features: int = 0           # not core, not dead, not decided
    representatives: int = 0         # open features up to equivalence
    iterations: int = 0              # runs done (the smallest complete one is kept)
    stopped: Optional[str] = None    # why the run stopped before the end
    seconds: float = 0.0
    sat_calls: int = 0
    sizes: list[int] = field(default_factory=list)  # each complete run's size

    @property
    def covered(self) -> int:
        return self.considered - self.invalid - self.left

    @property
    def coverage(self) -> float:
        done = self.covered
        return 1.0 if done + self.left == 0 else done / (done + self.left)


def _cover_class(t: int):
    if t == 1:
        return initial_literals, LiteralCover
    if t == 2:
        return initial_pairs, PairCover
    from .triples import TripleCover, initial_triples
    return initial_triples, TripleCover


def _rng(seed: int, k: int) -> random.Random:
    return random.Random(seed if k == 0 else seed * 1_000_003 + k)


def _one_run(clauses, n: int, t: int, seed: int, k: int, assumptions: Sequence[int],
             deadline: Optional[float], cancel: CancelLike = None) -> SampleResult:
    """One covering run (iteration ``k``), from a fresh preparation (a fresh solver: the run
    does not depend on what ran before it, so ``jobs`` does not change the answer)."""
    t0 = time.monotonic()

    def check() -> None:
        if is_cancelled(cancel):
            raise Stop("cancelled")
        if deadline is not None and time.monotonic() > deadline:
            raise Stop("budget")

    res = SampleResult(products=[], t=t, complete=False, features=n, iterations=1)
    try:
        p = prepare(clauses, n, assumptions, deadline)
    except SamplingTimeout:
        res.stopped = "budget"
        res.seconds = time.monotonic() - t0
        return res
    try:
        res.open_features, res.representatives = p.open_vars, len(p.reps)
        if p.void:
            res.void, res.complete = True, True
            return res
        te = min(t, len(p.reps))
        if te == 0:  # a single product: it covers every valid interaction
            res.products = [list(p.model[:n])]
            res.complete = True
            return res
        init, cls = _cover_class(te)
        if te == 3:
            from .triples import triple_memory
            need = triple_memory(p)
            if need > MAX_TRIPLE_MEMORY:
                raise ValueError(
                    f"3-wise sampling of {len(p.reps)} independent features would need about "
                    f"{need / 2 ** 30:.1f} GB of memory (at most {MAX_TRIPLE_MEMORY / 2 ** 30:g} GB here): decide "
                    "some features first (--include / --exclude), or sample pairwise (--t 2)")
        state: CoverState = init(p)
        res.considered = state.total
        cover = cls(p, state, _rng(seed, k), check)
        try:
            while True:
                check()
                prod = cover.next_configuration()
                if prod is None:
                    break
                state.products.append(prod)
            res.complete = True
        except Stop as ex:
            res.stopped = str(ex)
        except SolverInterrupted:
            res.stopped = "budget"
        res.products = state.products
        res.invalid = state.invalid
        res.left = 0 if res.complete else state.left()
        res.sat_calls = state.sat_calls + p.sat_calls
        return res
    finally:
        p.close()
        res.seconds = time.monotonic() - t0


def _worker(args) -> SampleResult:
    clauses, n, t, seed, k, assumptions, deadline = args
    return _one_run(clauses, n, t, seed, k, assumptions, deadline)


def sample(clauses: Sequence[Sequence[int]], n: int, t: int = 2, seed: int = 0,
           assumptions: Sequence[int] = (), budget: Optional[float] = None, cancel: CancelLike = None,
           iterations: Optional[int] = None, jobs: int = 1) -> SampleResult:
    """A ``t``-wise sample (t = 1, 2, 3) of the CNF ``clauses`` whose features are variables
    ``1..n``, among the products with ``assumptions``.  ``budget``: seconds (wall clock) for
    the whole call; when it runs out the result is partial (``complete`` False, ``left`` the
    interactions not covered yet).  ``iterations``: independent runs (seeds derived from
    ``seed``), the smallest complete sample is kept (None: as many as are cheap, from the size
    of the first: :data:`AUTO_WORK`); ``jobs`` runs them in parallel processes (the answer does
    not depend on it)."""
    if t not in (1, 2, 3):
        raise ValueError("t-wise sampling supports t = 1, 2 and 3")
    t0 = time.monotonic()
    deadline = None if budget is None else t0 + budget
    runs: list[SampleResult] = []
    with cpu_limit(None if budget is None else budget * max(1, jobs) + 1.0):
        first = _one_run(clauses, n, t, seed, 0, assumptions, deadline, cancel)
        runs.append(first)
        if iterations is None:
            work = max(1, len(first.products) * first.representatives)
            iterations = max(1, min(AUTO_MAX, AUTO_WORK // work))
        if first.complete and not first.void and iterations > 1:
            if jobs <= 1:
                for k in range(1, iterations):
                    if deadline is not None and time.monotonic() > deadline:
                        break
                    r = _one_run(clauses, n, t, seed, k, assumptions, deadline, cancel)
                    if not r.complete:
                        break
                    runs.append(r)
            else:
                runs += [r for r in _parallel(clauses, n, t, seed, range(1, iterations), assumptions, deadline,
                                              jobs) if r.complete]
    best = _pick(runs)
    best.iterations = len(runs)
    best.sizes = [len(r.products) for r in runs if r.complete]
    best.seconds = time.monotonic() - t0
    best.sat_calls = sum(r.sat_calls for r in runs)
    return best


def _pick(runs: list[SampleResult]) -> SampleResult:
    done = [r for r in runs if r.complete]
    if done:
        return min(done, key=lambda r: len(r.products))  # min keeps the first of equals
    return runs[0]


def _parallel(clauses, n, t, seed, ks, assumptions, deadline, jobs) -> list[SampleResult]:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    cl = [list(c) for c in clauses]
    ctx = multiprocessing.get_context("spawn")  # no fork of a process with solver threads
    with ProcessPoolExecutor(max_workers=min(jobs, len(ks)), mp_context=ctx) as ex:
        futs = [ex.submit(_worker, (cl, n, t, seed, k, list(assumptions), deadline)) for k in ks]
        return [f.result() for f in futs]
