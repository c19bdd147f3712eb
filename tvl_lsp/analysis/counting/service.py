"""The counting service: one CNF, counted on its features, by knowledge compilation.

    svc = CNFCounter(nvars, clauses, n_features)          # features are variables 1..n_features
    svc.count()                       -> Count(value, engine, seconds)
    svc.count([3, -7])                -> under decisions (literals over the features)
    svc.feature_counts([3])           -> FeatureCounts(total, counts[v] for v in 1..n, engine)
    svc.sample_uniform(10, seed=1)    -> [[literals of features], ...]
    svc.circuit()                     -> the compiled d-DNNF (compiles once, then cached)

How a count is answered:

1. **d4**: the CNF is compiled once into a d-DNNF (in a child process, bounded in time and
   cancellable; tiny CNFs in-process), cached in memory and on disk by content
   (:mod:`.cache`), and every query is a pass over the circuit (:mod:`.circuit`): the total,
   counts under decisions, and every feature's count in one pass.  The circuit counts
   assignments of *all* variables of the CNF, which is the count of products only when the
   auxiliary variables (numbers above ``n_features``) are determined by the features.  The
   caller says so with ``determined`` (the TVL encoding's Tseitin and counter variables are;
   attribute values may not be: :meth:`Encoding.aux_determined` checks it); auxiliary
   variables that occur in no clause are left out of the counted universe.
2. **pyganak** (projected model counting on the features, :mod:`.projected`): when the
   auxiliary variables are not determined, when d4 fails, or when d4 runs out of its share of
   the time budget (three quarters of it; pyganak gets the rest).

Every result says which engine answered.  Uniform sampling draws from the compiled circuit;
t-wise sampling needs no compilation (:mod:`tvl_lsp.analysis.sampling`: a warm SAT solver).
"""

from __future__ import annotations

import logging
import os
import random
import threading
from collections import OrderedDict
import time
from dataclasses import dataclass, field
from typing import Callable, Iterable, Optional, Sequence

from . import cache as C
from .circuit import Circuit, NNFError
from .errors import CancelLike, CountCancelled, CountTimeout, EngineFailed, is_cancelled

Progress = Optional[Callable[[str], None]]

# compile in this process below these sizes when there is no time budget and no cancel token
# (a child process costs ~0.3 s, seconds on a loaded machine; d4 takes milliseconds on feature
# models this small); with a budget or a token, in a child process that can be killed (a hard
# random CNF of 120 variables keeps d4 busy for minutes), except the tiny CNFs of typical robot
# models (the language server's worker process is itself killed when it overruns)
INPROCESS_MAX_VARS = 400
INPROCESS_MAX_CLAUSES = 4000
INPROCESS_BUDGETED_VARS = 150
PYGANAK_INPROCESS_VARS = 100  # with a budget: bigger CNFs go to a killable child process
PASSES_KEPT = 16  # passes kept per CNF (each: one count per feature)
D4_SHARE = 0.75  # of a time budget, the part d4 gets before pyganak takes over
MIN_FALLBACK_BUDGET = 0.2  # seconds: less is not worth starting pyganak's process
REDUCE_SHARE = 0.1  # of d4's time budget, the most the optional reductions (backbone...) take
REDUCTION_TAG = "c tvl-lsp-reduction "

# parsed circuits kept in memory: at most 8, and 8 million characters of d4's NNF text in all
# (a parsed circuit takes 25-50 bytes per character: freebsd-8.0.0's, 14 M characters, 330 MB)
MAX_CIRCUIT_CHARS = 8_000_000
MEMORY = C.MemoryCache(8, MAX_CIRCUIT_CHARS)
_log = logging.getLogger("tvl_lsp.counting")
DISK = C.DiskCache()
# d4 failures, remembered for this process: key -> (reason, budget it had)
_FAILED: dict[str, tuple[str, Optional[float]]] = {}
_COMPILE_LOCKS: dict[str, threading.Lock] = {}
_LOCKS_LOCK = threading.Lock()


@dataclass
class Count:
    value: int
    engine: str          # "d4" | "pyganak" | "trivial"
    seconds: float = 0.0
    cached: bool = False
    note: str = ""       # why the fallback answered, when it did


@dataclass
class FeatureCounts:
    total: int
    counts: list[int]    # counts[v] = products with feature v (index 0 unused)
    engine: str
    seconds: float = 0.0
    complete: bool = True  # False: a budget ran out, counts of 0.. are missing (None entries)
    note: str = ""


@dataclass
class Compiled:
    circuit: Circuit
    key: str
    path: Optional[str]
    seconds: float
    source: str          # "memory" | "disk" | "d4"


@dataclass
class CompileStatus:
    """Where the compilation of a CNF stands: ``ready`` (the circuit is in memory: every count is
    a pass), ``compiling`` (in the background), ``failed`` (d4 failed or ran out of its budget:
    counts go to pyganak), ``unusable`` (the auxiliary variables are not determined by the
    features: pyganak counts) or ``idle`` (not started)."""
    state: str
    seconds: float = 0.0   # since the compilation started
    message: str = ""      # progress while compiling, the reason when failed


class _Job:
    """A compilation in a background thread (d4 itself runs in a child process that the
    thread waits for, so the thread holds no CPU and a cancel kills the child)."""

    def __init__(self, owner: Optional[str]):
        self.owner = owner
        self.cancel = threading.Event()
        self.done = threading.Event()
        self.error: Optional[str] = None
        self.started = time.monotonic()
        self.progress = ""


_JOBS: dict[str, _Job] = {}
_JOBS_LOCK = threading.Lock()


def _lock_for(key: str) -> threading.Lock:
    with _LOCKS_LOCK:
        lk = _COMPILE_LOCKS.get(key)
        if lk is None:
            lk = _COMPILE_LOCKS[key] = threading.Lock()
        return lk


class _Counted:
    """The count d4 reported for a reduced CNF, as the circuit :class:`.simplify.LiftedCircuit`
    lifts (its total only)."""

    def __init__(self, n: int):
        self.n = n

    def count(self, lits=()) -> int:
        return self.n


class CNFCounter:
    def __init__(self, nvars: int, clauses: Sequence[Sequence[int]], n_features: int,
                 determined: bool = True, label: str = "model", d4_options: Optional[dict] = None,
                 inprocess: bool = False, reduce: bool = True):
        self.nvars = max(nvars, n_features)
        self.clauses = [list(c) for c in clauses]
        self.n_features = n_features
        self.determined = determined
        self.label = label
        self.d4_options = d4_options
        # the CNF is made smaller (exactly: :mod:`.simplify`) before d4 compiles it
        self.reduce = reduce and os.environ.get("TVL_LSP_NO_REDUCE", "") in ("", "0")
        # compile in this process whatever the size when there is no budget (the command line:
        # Ctrl-C still works, see d4.compile_inprocess); never in the language server
        self.inprocess = inprocess
        lits: set[int] = set()
        add = lits.update
        for c in self.clauses:
            add(c)
        used = {abs(x) for x in lits}
        self.universe = sorted(set(range(1, n_features + 1)) | used)
        # auxiliary variables that occur in no clause double d4's count each
        self.unused_aux = self.nvars - len(self.universe)
        # (a reduced CNF's circuit is stored apart: the d-DNNF file of the CNF itself stays one
        # other tools read, e.g. ddnnife)
        self.key = C.cnf_key(self.nvars, self.clauses, extra=repr(sorted((d4_options or {}).items()))
                             + (" reduced-1" if self.reduce else ""))
        self.last_engine: Optional[str] = None
        # the last passes: (circuit id, literals) -> (total, counts), most recent last
        self._passes: "OrderedDict[tuple, tuple]" = OrderedDict()
        self._passes_lock = threading.Lock()

    # ------------------------------------------------------------------ engines
    @property
    def trivially_unsat(self) -> bool:
        """An empty clause (d4 and pyganak settle every other unsatisfiable CNF themselves)."""
        got = self.__dict__.get("_trivially_unsat")
        if got is None:  # the clauses do not change: looked at once (every click asks)
            got = self.__dict__["_trivially_unsat"] = any(not c for c in self.clauses)
        return got

    def d4_usable(self) -> bool:
        return self.determined and self._failure() is None

    def _failure(self, timeout: Optional[float] = None, any_budget: bool = True) -> Optional[str]:
        """Why d4 is not tried again for this CNF in this process (it failed, or ran out of a
        budget at least ``timeout``; ``any_budget``: whatever the budget), or None.  A circuit
        another process has put in the disk cache meanwhile (a count retried in the
        background with a longer budget) wins over a remembered failure."""
        failed = _FAILED.get(self.key)
        if failed is None:
            return None
        if not (any_budget or failed[1] is None or (timeout is not None and timeout <= failed[1])):
            return None
        if DISK.has(self.key):
            _FAILED.pop(self.key, None)
            return None
        return failed[0]

    def compiled(self, timeout: Optional[float] = None, cancel: CancelLike = None,
                 progress: Progress = None, need_nnf: bool = False) -> tuple[Optional[str], int, str]:
        """Make sure the d-DNNF exists: (NNF text if it was read or made here, else None;
        the d4 count over all variables, -1 when unknown; where it came from: "memory" |
        "disk" | "d4").  With ``need_nnf``, a count alone on disk is not enough.
        Raises CountTimeout, CountCancelled or EngineFailed."""
        got = MEMORY.get(self.key)
        if got is not None:
            return None, -1, "memory"
        failed = self._failure(timeout, any_budget=False)
        if failed is not None:
            raise EngineFailed(failed)
        with _lock_for(self.key):
            if MEMORY.get(self.key) is not None:
                return None, -1, "memory"
            n = DISK.get_count(self.key)
            if n is not None and (not need_nnf or DISK.has(self.key)):
                return None, n, "disk"
            if is_cancelled(cancel):
                raise CountCancelled()
            if progress:
                progress(f"compiling {self.label} with d4")
            try:
                text, n = self._compile(timeout, cancel, progress)
            except CountTimeout as e:
                _FAILED[self.key] = (str(e), timeout)
                raise
            except EngineFailed as e:
                _FAILED[self.key] = (str(e), None)
                raise
            except (ImportError, OSError, RuntimeError, MemoryError) as e:
                from ...base.safewrite import reason
                why = reason(e) if isinstance(e, OSError) else f"{type(e).__name__}: {e}"
                _FAILED[self.key] = (f"d4 failed: {why}", None)
                raise EngineFailed(_FAILED[self.key][0]) from None
            if text is not None and DISK.path(self.key) is None:
                self._load(text)
            return text, n, "d4"

    def _compile(self, timeout, cancel, progress) -> tuple[Optional[str], int]:
        """Compile (the reduced CNF when ``self.reduce``) and store the result on disk: (the
        stored text when it is not in the disk cache, else None; the count over all variables).
        The stored text of a reduced CNF is a ``c tvl-lsp-reduction`` line (the way back to the
        original variables, :class:`.simplify.Reduction`) followed by the reduced CNF's NNF."""
        t0 = time.monotonic()
        nvars, clauses, head, red = self.nvars, self.clauses, "", None
        if self.reduce:
            from .simplify import reduce_cnf, LiftedCircuit
            # (auxiliary variables are not eliminated: that keeps the count of the features
            # only, and the circuit counts every variable -- the same number only when the
            # caller's ``determined`` is right)
            red = reduce_cnf(self.nvars, self.clauses, self.n_features, self.universe,
                             deadline=None if timeout is None else t0 + timeout * REDUCE_SHARE)
            head = REDUCTION_TAG + red.to_json().decode() + "\n"
            nvars, clauses = red.k, red.clauses
            if red.void:
                nvars, clauses = 0, [[]]
            if timeout is not None:
                timeout = max(0.0, timeout - (time.monotonic() - t0))

        def lifted(n: int) -> int:
            if red is None or red.void:
                return n
            return LiftedCircuit(_Counted(n), red, self.universe).count() << self.unused_aux

        # (where d4 runs follows the CNF's own size, as without the reduction)
        small = self.nvars <= INPROCESS_MAX_VARS and len(self.clauses) <= INPROCESS_MAX_CLAUSES
        tiny = self.nvars <= INPROCESS_BUDGETED_VARS and len(self.clauses) <= 10 * INPROCESS_BUDGETED_VARS
        from .d4 import inprocess_ok
        if (tiny or (timeout is None and cancel is None and (self.inprocess or small))) and inprocess_ok(tiny):
            from .d4 import compile_inprocess
            text, n = compile_inprocess(nvars, clauses, self.d4_options, interruptible=self.inprocess, tiny=tiny)
            text, n = head + text, lifted(n)
            DISK.put(self.key, text, n)
            return text, n
        # (under a memory limit always here: d4 sizes itself to its own limits)
        from .d4 import compile_cnf
        from ...base.files import read_text
        tmp = DISK.tmp_path(self.key)
        try:
            rep = compile_cnf(nvars, clauses, tmp, timeout=timeout, cancel=cancel,
                              progress=progress, options=self.d4_options)
            n = lifted(rep["count"])
            if head:  # the reduction's line first: stored through the cache's writer
                text = head + read_text(tmp, C.NNF_MAX_BYTES)
                DISK.put(self.key, text, n)
                return text, n
            digest = tuple(rep["nnf"]) if isinstance(rep.get("nnf"), list) else None
            if DISK.adopt(self.key, tmp, n, digest) is None:
                return read_text(tmp, C.NNF_MAX_BYTES), n  # no disk cache: keep it in memory
            return None, n
        finally:
            if os.path.lexists(tmp):
                try:
                    os.unlink(tmp)
                except OSError:
                    pass

    def _load(self, text: str, from_disk: bool = False) -> Optional[Circuit]:
        try:
            if text.startswith(REDUCTION_TAG):
                from .simplify import LiftedCircuit, Reduction
                first, _, body = text.partition("\n")
                red = Reduction.from_json(first[len(REDUCTION_TAG):].encode(), self.nvars)
                if red is None:
                    raise NNFError("the stored reduction is not one of this CNF's")
                inner = None if red.void or not red.k else Circuit(body, red.k)
                circ = LiftedCircuit(inner, red, self.universe)
            else:
                circ = Circuit(text, self.nvars, self.universe)
        except NNFError as e:
            DISK.discard(self.key)
            if from_disk:
                return None  # damaged (a writer died, a disk error): compile again
            _FAILED[self.key] = (f"d4 wrote an unreadable d-DNNF: {e}", None)
            raise EngineFailed(_FAILED[self.key][0]) from e
        MEMORY.put(self.key, circ, len(text))
        return circ

    def circuit(self, timeout: Optional[float] = None, cancel: CancelLike = None,
                progress: Progress = None) -> Compiled:
        """The compiled d-DNNF, parsed (from memory, disk, or d4).  Raises CountTimeout,
        CountCancelled or EngineFailed."""
        t0 = time.perf_counter()
        for _ in range(3):
            text, _, source = self.compiled(timeout, cancel, progress, need_nnf=True)
            circ = MEMORY.get(self.key)
            if circ is None:
                from_disk = text is None
                if from_disk:
                    text = DISK.get(self.key)
                if text is None:  # evicted meanwhile by another process: compile again
                    DISK.discard(self.key)
                    continue
                circ = self._load(text, from_disk)
                if circ is None:
                    continue
            p = DISK.path(self.key)
            return Compiled(circ, self.key, str(p) if p else None, time.perf_counter() - t0, source)
        raise EngineFailed("the compiled d-DNNF could not be read back from the cache")

    def feature_counts_if_ready(self, assumptions: Sequence[int] = ()) -> Optional[FeatureCounts]:
        """:meth:`feature_counts` when the compiled circuit is in memory (one pass, no
        compiling, no waiting), else None."""
        circ = MEMORY.get(self.key) if self.d4_usable() and not self.trivially_unsat else None
        if circ is None:
            return None
        return self._pass(circ, self._check_lits(assumptions))

    def _pass(self, circ: Circuit, lits: list[int]) -> FeatureCounts:
        """One pass over the circuit under ``lits``; the last PASSES_KEPT answers are kept (a
        configurator click asks the same decisions twice -- what they force, then every count --
        and an undo returns to decisions asked before)."""
        t0 = time.perf_counter()
        memo_key = (id(circ), frozenset(lits))
        with self._passes_lock:
            hit = self._passes.get(memo_key)
            if hit is not None:
                self._passes.move_to_end(memo_key)
        if hit is not None:
            total, positive = hit
        else:
            r = circ.counts(lits)
            total, positive = r.total, r.positive[: self.n_features + 1]
            with self._passes_lock:
                self._passes[memo_key] = (total, positive)
                while len(self._passes) > PASSES_KEPT:
                    self._passes.popitem(last=False)
        return FeatureCounts(total, list(positive), "d4", time.perf_counter() - t0)

    def on_disk(self) -> bool:
        """Is the compiled d-DNNF in the disk cache (ready after a read, no d4 run)?"""
        return DISK.has(self.key)

    # ------------------------------------------------------------------ in the background
    def ready(self) -> bool:
        """Is the compiled circuit in memory (every count a pass, no waiting)?"""
        return MEMORY.get(self.key) is not None

    def start(self, timeout: Optional[float] = None, owner: Optional[str] = None) -> CompileStatus:
        """Make the circuit ready without waiting for it: compile (or read from the disk cache)
        in a background thread, with ``timeout`` seconds for d4, and return the status at once.
        One compilation per CNF whatever the number of callers.  ``owner`` (e.g. a model's
        path): a newer CNF started for the same owner cancels the older one's compilation (the
        model changed; its d4 process is killed)."""
        if self.ready():
            return CompileStatus("ready")
        if not self.determined:
            return CompileStatus("unusable", message="the encoding has auxiliary variables the features "
                                                     "do not determine: pyganak counts")
        with _JOBS_LOCK:
            if owner is not None:
                for k, j in list(_JOBS.items()):
                    if k != self.key and j.owner == owner and not j.done.is_set():
                        j.cancel.set()
            job = _JOBS.get(self.key)
            if job is not None and (not job.done.is_set() or job.error is not None):
                return self._status_of(job)
            failed = self._failure(timeout, any_budget=False)
            if failed is not None:
                return CompileStatus("failed", message=failed)
            job = _JOBS[self.key] = _Job(owner)

        def progress(msg: str) -> None:
            job.progress = msg

        def run() -> None:
            try:
                comp = self.circuit(timeout, job.cancel, progress)
                _log.debug("%s: circuit ready in %.2f s (%s)", self.label, comp.seconds, comp.source)
            except (CountTimeout, EngineFailed) as e:
                job.error = str(e)
            except CountCancelled:
                with _JOBS_LOCK:  # a later start compiles again
                    if _JOBS.get(self.key) is job:
                        del _JOBS[self.key]
            except Exception as e:  # noqa: BLE001 (reported as a failure, never raised in a thread)
                job.error = f"{type(e).__name__}: {e}"
            finally:
                job.done.set()

        threading.Thread(target=run, name=f"tvl-compile-{self.label}", daemon=True).start()
        return CompileStatus("compiling", 0.0, f"compiling {self.label} with d4")

    def gave_up(self) -> Optional[str]:
        """Why d4 stopped compiling this CNF when it ran out of its time budget (None: it did
        not): a host then stops asking for counts rather than trying pyganak on every request."""
        failed = _FAILED.get(self.key)
        return failed[0] if failed is not None and failed[1] is not None else None

    def status(self) -> CompileStatus:
        """The status without starting anything."""
        if self.ready():
            return CompileStatus("ready")
        if not self.determined:
            return CompileStatus("unusable")
        with _JOBS_LOCK:
            job = _JOBS.get(self.key)
        if job is not None:
            return self._status_of(job)
        failed = _FAILED.get(self.key)
        return CompileStatus("failed", message=failed[0]) if failed else CompileStatus("idle")

    def _status_of(self, job: _Job) -> CompileStatus:
        dt = time.monotonic() - job.started
        if not job.done.is_set():
            return CompileStatus("compiling", dt, job.progress or f"compiling {self.label} with d4")
        if job.error is not None:
            return CompileStatus("failed", dt, job.error)
        return CompileStatus("ready", dt) if self.ready() else CompileStatus("idle", dt)

    def wait(self, timeout: Optional[float] = None) -> CompileStatus:
        """Wait (at most ``timeout`` seconds) for a compilation started with :meth:`start`."""
        with _JOBS_LOCK:
            job = _JOBS.get(self.key)
        if job is not None:
            job.done.wait(timeout)
        return self.status()

    def _check_lits(self, assumptions: Sequence[int]) -> list[int]:
        out = []
        for x in assumptions:
            if not x or abs(x) > self.n_features:
                raise ValueError(f"decision {x} is not a feature literal")
            out.append(int(x))
        return out

    # ------------------------------------------------------------------ counts
    def count(self, assumptions: Sequence[int] = (), timeout: Optional[float] = None,
              cancel: CancelLike = None, progress: Progress = None) -> Count:
        """Products with the given feature literals."""
        t0 = time.perf_counter()
        lits = self._check_lits(assumptions)
        if self.trivially_unsat:
            return self._done(Count(0, "trivial", time.perf_counter() - t0))
        note = ""
        if self.d4_usable():
            try:
                if not lits:
                    _, n, source = self.compiled(self._d4_budget(timeout), cancel, progress)
                    if n >= 0:
                        return self._done(Count(n >> self.unused_aux, "d4", time.perf_counter() - t0,
                                                source != "d4"))
                comp = self.circuit(self._d4_budget(timeout), cancel, progress)
                n = comp.circuit.count(lits)
                return self._done(Count(n, "d4", time.perf_counter() - t0, comp.source != "d4"))
            except (CountTimeout, EngineFailed) as e:
                note = str(e)
        elif not self.determined:
            note = "the encoding has auxiliary variables the features do not determine"
        else:
            note = _FAILED.get(self.key, ("d4 failed",))[0]
        left = None if timeout is None else timeout - (time.perf_counter() - t0)
        if left is not None and left < MIN_FALLBACK_BUDGET:
            raise CountTimeout(f"no answer within {timeout:g} s ({note})")
        n = self._pyganak(lits, left, cancel)
        return self._done(Count(n, "pyganak", time.perf_counter() - t0, note=note))

    def feature_counts(self, assumptions: Sequence[int] = (), timeout: Optional[float] = None,
                       cancel: CancelLike = None, progress: Progress = None,
                       backbone: Optional[Callable[[], dict[int, bool]]] = None,
                       order: Optional[Iterable[int]] = None) -> FeatureCounts:
        """The number of products with each feature (within the decisions), in one pass over
        the compiled circuit; one projected count per open feature with pyganak (the features
        numbered in ``order`` first, then the others, as far as the time budget goes)."""
        t0 = time.perf_counter()
        lits = self._check_lits(assumptions)
        n = self.n_features
        if self.trivially_unsat:
            return FeatureCounts(0, [0] * (n + 1), "trivial", time.perf_counter() - t0)
        note = ""
        if self.d4_usable():
            try:
                comp = self.circuit(self._d4_budget(timeout), cancel, progress)
                r = self._pass(comp.circuit, lits)
                self.last_engine = "d4"
                r.seconds = time.perf_counter() - t0
                return r
            except (CountTimeout, EngineFailed) as e:
                note = str(e)
        elif not self.determined:
            note = "the encoding has auxiliary variables the features do not determine"
        # pyganak: a count per feature, the backbone settles core and dead ones for free
        deadline = None if timeout is None else t0 + timeout
        total = self._pyganak(lits, self._left(deadline), cancel)
        counts: list = [None] * (n + 1)
        counts[0] = 0
        fixed = {abs(x): x > 0 for x in lits}
        bb = {}
        if total and backbone is not None and not lits:
            bb = backbone()
        complete = True
        first = [v for v in (order or ()) if 1 <= v <= n]
        for k, v in enumerate(dict.fromkeys(first + list(range(1, n + 1))), 1):
            if v in fixed:
                counts[v] = total if fixed[v] else 0
            elif not total:
                counts[v] = 0
            elif v in bb:
                counts[v] = total if bb[v] else 0
            else:
                left = self._left(deadline)
                if left is not None and left <= 0:
                    complete = False
                    break
                try:
                    counts[v] = self._pyganak(lits + [v], left, cancel)
                except CountTimeout:
                    complete = False
                    break
            if progress and k % 50 == 0:
                progress(f"counting feature {k} of {n} with pyganak")
        self.last_engine = "pyganak"
        return FeatureCounts(total, counts, "pyganak", time.perf_counter() - t0, complete, note)

    # ------------------------------------------------------------------ sampling
    def sample_uniform(self, amount: int, seed: Optional[int] = None, assumptions: Sequence[int] = (),
                       timeout: Optional[float] = None, cancel: CancelLike = None) -> tuple[list[list[int]], str]:
        """``amount`` products drawn uniformly at random (with replacement) among those with
        the given literals: (list of feature-literal lists, engine).  Exact uniformity: each
        product with probability 1/count."""
        lits = self._check_lits(assumptions)
        rng = random.Random(seed)
        n = self.n_features
        if self.trivially_unsat:
            return [], "trivial"
        if self.d4_usable():
            try:
                comp = self.circuit(self._d4_budget(timeout), cancel)
                out = []
                for _ in range(amount):
                    s = comp.circuit.sample(rng, lits)
                    if s is None:
                        return [], "d4"
                    out.append([x for x in s if abs(x) <= n])
                return out, "d4"
            except (CountTimeout, EngineFailed):
                pass
        # self-reduction with projected counts: feature by feature, in proportion
        deadline = None if timeout is None else time.monotonic() + timeout
        out = []
        for _ in range(amount):
            cur = list(lits)
            total = self._pyganak(cur, self._left_m(deadline), cancel)
            if not total:
                return [], "pyganak"
            fixed = {abs(x) for x in cur}
            for v in range(1, n + 1):
                if v in fixed:
                    continue
                with_v = self._pyganak(cur + [v], self._left_m(deadline), cancel)
                if rng.randrange(total) < with_v:
                    cur.append(v)
                    total = with_v
                else:
                    cur.append(-v)
                    total = total - with_v
            out.append(sorted(cur, key=abs))
        return out, "pyganak"

    # ------------------------------------------------------------------ helpers
    def _done(self, c: Count) -> Count:
        self.last_engine = c.engine
        return c

    @staticmethod
    def _d4_budget(timeout: Optional[float]) -> Optional[float]:
        return None if timeout is None else timeout * D4_SHARE

    @staticmethod
    def _left(deadline: Optional[float]) -> Optional[float]:
        return None if deadline is None else deadline - time.perf_counter()

    @staticmethod
    def _left_m(deadline: Optional[float]) -> Optional[float]:
        if deadline is None:
            return None
        left = deadline - time.monotonic()
        if left <= 0:
            raise CountTimeout("no answer within the time budget")
        return left

    def _pyganak(self, lits: Sequence[int], timeout: Optional[float], cancel: CancelLike) -> int:
        from .projected import count_cnf, query_key
        if timeout is not None and timeout <= 0:
            raise CountTimeout("no answer within the time budget")
        key = query_key(self.key, False, lits)
        projection = None if self.nvars == self.n_features else list(range(1, self.n_features + 1))
        # pyganak cannot be interrupted in-process: with a budget or a cancel token, only CNFs
        # small enough to be instant are counted here
        inprocess = False if (timeout is not None or cancel is not None) and self.nvars > PYGANAK_INPROCESS_VARS \
            else None
        return count_cnf(self.nvars, self.clauses + [[x] for x in lits], projection,
                         timeout=timeout, cancel=cancel, key=key, inprocess=inprocess)


def forget_failures() -> None:
    """Forget remembered d4 failures and finished background compilations (tests)."""
    _FAILED.clear()
    with _JOBS_LOCK:
        for k, j in list(_JOBS.items()):
            if j.done.is_set():
                del _JOBS[k]


def cancel_all(wait: Optional[float] = None) -> None:
    """Cancel every background compilation (a host that stops); with ``wait``, wait at most that
    many seconds for their d4 processes to be killed and reaped."""
    with _JOBS_LOCK:
        jobs = list(_JOBS.values())
        for j in jobs:
            j.cancel.set()
    if wait:
        deadline = time.monotonic() + wait
        for j in jobs:
            j.done.wait(max(0.0, deadline - time.monotonic()))


def cancel_owned(owner: str, wait: Optional[float] = None) -> int:
    """Cancel the background compilations started for ``owner`` (e.g. a configurator closed);
    how many were running."""
    with _JOBS_LOCK:
        jobs = [j for j in _JOBS.values() if j.owner == owner and not j.done.is_set()]
        for j in jobs:
            j.cancel.set()
    if wait:
        deadline = time.monotonic() + wait
        for j in jobs:
            j.done.wait(max(0.0, deadline - time.monotonic()))
    return len(jobs)
