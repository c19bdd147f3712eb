"""One configurator session: a feature model, the launch files it configures, and the logic
behind every click.  Pure (no LSP, no HTTP): the browser host (:mod:`tvl_lsp.ui`) and the
language server's ``tvl-lsp.configurator`` command both call it through :mod:`.api`.

Decisions are a plain ``{feature: included?}`` dict owned by the host; every method takes
them and never keeps them, so one session serves any number of views.

    s = Session.open("ws/src/robot/launch/generic.tvl")     # or the generic launch file
    s.model_json()                        # the feature tree, the all-products graph, problems
    new, refusal = s.decide({}, "Random", True)            # refusal: None, or why not
    s.state(new)                          # user vs implied decisions, problems and graph status
    s.counts(new)                         # remaining products and every feature's count
    s.plan_generation(new, "current")     # the configuration launch file(s) to write
"""

from __future__ import annotations

import os
import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Mapping, Optional

from ..base import formula as fm
from ..base.diagnostics import Severity
from ..project.workspace import default_read_file, find_workspace_root, is_launch, is_model, load_workspace, norm
from ..analysis.counting.errors import CountCancelled, CountTimeout
from . import graph as graphmod, problems as problemsmod

ReadFile = Callable[[str], Optional[str]]

MODES = ("current", "completions", "sample", "all")
COMPILE_BUDGET = 300.0  # seconds d4 may take to compile a model in the background
SAMPLE_BUDGET = 60.0    # seconds for a pairwise sample


class SessionError(ValueError):
    """The path cannot be configured (no model, a model with errors, unknown feature...)."""


@dataclass
class Refusal:
    """Why a decision was refused: the user's decisions it conflicts with (a minimal set) and
    the parts of the model that forbid the combination (a minimal explanation)."""
    feature: str
    value: bool
    conflicts_with: dict[str, bool] = field(default_factory=dict)
    because: list[dict] = field(default_factory=list)   # {label, path, line, col}
    message: str = ""

    def to_json(self) -> dict:
        return {"feature": self.feature, "value": self.value, "conflictsWith": self.conflicts_with,
                "because": self.because, "message": self.message}


def _verb(value: bool) -> str:
    return "include" if value else "exclude"


def _key(decisions: Mapping[str, bool]) -> tuple:
    return tuple(sorted(decisions.items()))


class Session:
    def __init__(self, model_path: str, roots: Optional[Iterable[str]] = None,
                 read_file: Optional[ReadFile] = None, launches: Optional[list[str]] = None,
                 project_files: Optional[list[str]] = None):
        from ..project import models
        self.model_path = norm(model_path)
        self.read_file = read_file or default_read_file
        self.roots = [norm(r) for r in roots] if roots else [find_workspace_root(self.model_path)]
        text = self.read_file(self.model_path)
        if text is None:
            raise SessionError(f"cannot read {self.model_path}")
        # parsed and encoded once per text in this process: a second session on the same files
        # (another view, the server's check and counts) shares the analysis and its compiled model
        res, self.analysis = models.load(self.model_path, text, self.read_file)
        errors = [d for d in res.diagnostics if d.severity == Severity.ERROR]
        if res.model is None or res.model.root is None:
            raise SessionError(f"{os.path.basename(self.model_path)} has no root feature")
        if errors:
            d = errors[0]
            raise SessionError(f"{os.path.basename(d.path)}:{d.span.start}: {d.message} "
                               f"(fix the model's errors to configure it)")
        self.model = res.model
        self.sources = dict(res.model.sources or {})
        self.sources[self.model_path] = text
        self.names = [self.analysis.name(f) for f in self.model.features]
        self._by_name = {n: f for n, f in zip(self.names, self.model.features)}
        self._alias = {}
        for n, f in zip(self.names, self.model.features):
            self._alias[n] = n
            self._alias.setdefault(f.long_name, n)
        self.workspace = load_workspace(self.roots, self.read_file)
        if launches is None:
            launches = sorted({p.launch for p in self.workspace.launches_for_model(self.model_path)})
        self.launches = [norm(x) for x in launches]
        self.launch = self.launches[0] if self.launches else None
        self._lock = threading.RLock()
        self._count_lock = threading.Lock()
        self._problem_lock = threading.Lock()
        self._launch_done = False
        self._launch_analysis_ = None
        self._free: list[str] = []
        self.known_extra = set(norm(p) for p in project_files or [])
        self._logic = None
        self.project_files = [norm(p) for p in project_files] if project_files else None
        self._graph = None
        self._graph_lock = threading.Lock()
        self._problems: Optional[list] = None
        self._rule_problems: Optional[list] = None
        self._states: OrderedDict = OrderedDict()
        self._problem_states: OrderedDict = OrderedDict()
        self._graph_states: OrderedDict = OrderedDict()
        self._total: Optional[int] = None
        self.compile_budget = COMPILE_BUDGET
        self.last_plan: dict = {}

    # ------------------------------------------------------------------ opening
    @classmethod
    def open(cls, path: str, roots: Optional[Iterable[str]] = None,
             read_file: Optional[ReadFile] = None, project_files: Optional[list[str]] = None) -> "Session":
        """A session for a model, or for the model paired with a launch file (``project_files``:
        where the graph's node hints are, default: the workspace's HAROS project files)."""
        path = norm(path)
        read_file = read_file or default_read_file
        if is_model(path):
            return cls(path, roots, read_file, project_files=project_files)
        if is_launch(path):
            roots = [norm(r) for r in roots] if roots else [find_workspace_root(path)]
            ws = load_workspace(roots, read_file)
            models = [p.model for p in ws.pair(path, read_file(path))[0] if p.model]
            if not models:
                raise SessionError(f"{os.path.basename(path)} is not paired with a feature model")
            return cls(models[0], roots, read_file, launches=[path], project_files=project_files)
        raise SessionError(f"{path} is neither a TVL model nor a launch file")

    # the launch analysis, the logic over model + free args and the graph are built on first use:
    # the feature diagram does not wait for them
    @property
    def _launch_analysis(self):
        with self._lock:
            if not self._launch_done:
                self._launch_analysis_ = self._analyse_launch(self.launch) if self.launch else None
                self._launch_done = True
            return self._launch_analysis_

    @property
    def logic(self):
        la = self._launch_analysis  # the free args
        with self._lock:
            if self._logic is None:
                from ..analysis.solve import PairLogic
                self._logic = PairLogic(self.analysis.encoding, self._free)
            return self._logic

    @property
    def graph(self):
        with self._graph_lock:
            if self._graph is None:
                la = self._launch_analysis
                self._graph = (graphmod.build(la, self.model_path, self.workspace, self.read_file, self.project_files)
                               if la is not None else graphmod.Graph())
            return self._graph

    @property
    def graph_ready(self) -> bool:
        return self._graph is not None

    def graph_json(self, decisions: Mapping[str, bool]) -> dict:
        """The all-products graph (laid out once by the UI) and its status under ``decisions``."""
        out = self.graph.to_json(model_valid=lambda c: self.logic.valid(c))
        out["status"] = self.state(decisions)["graph"]
        return out

    def _analyse_launch(self, path: str):
        from ..project.check import free_top_args
        from ..launch import analyse_any
        text = self.read_file(path)
        if text is None:
            return None
        enc = self.analysis.encoding
        features = [enc.name_of(f) for f in enc.features]
        self._free = [n for n in free_top_args(text, path, paired=True) if enc.feature_by_name(n) is None]
        try:
            return analyse_any(text, path, workspace_root=self.roots[0], read_file=self.read_file,
                               features=features + self._free)
        except Exception:
            return None

    # ------------------------------------------------------------------ names
    def feature(self, name: str) -> str:
        """The session's name of a feature (short when unique, else long); SessionError if unknown."""
        n = self._alias.get(name)
        if n is None:
            raise SessionError(f"unknown feature {name!r}")
        return n

    def accepted_names(self) -> dict[str, str]:
        """Every name a configuration file may use for a feature (short, long) -> its name here."""
        return dict(self._alias)

    def check_decisions(self, decisions: Mapping[str, bool]) -> dict[str, bool]:
        out = {}
        for k, v in decisions.items():
            if not isinstance(v, bool):
                raise SessionError(f"decision for {k!r} must be true or false")
            out[self.feature(k)] = v
        return out

    # ------------------------------------------------------------------ the model
    def _loc(self, path: str, span) -> Optional[dict]:
        return graphmod._loc(path, span)

    def tree(self) -> dict:
        """The feature tree: each node with its ``kind`` in its parent's group (root, mandatory,
        optional or member) in words true to the model (``kindText``), its own groups."""
        from ..analysis.encode import source_text
        cache: dict = {}

        def node(f, entry=None, g=None, shared: bool = False) -> dict:
            groups = f.groups  # (a UVL feature may have several: its children come from all)
            kind, kind_text = member_kind(entry, g)
            out = {"id": self.analysis.name(f), "name": f.name, "longName": f.long_name,
                   "optional": kind == "optional", "kind": kind, "kindText": kind_text,
                   "location": self._loc(f.path, f.name_span)}
            if shared:
                out["ref"] = True
                out["children"] = []
                return out
            if groups and any(x.children for x in groups):
                first = next(x for x in groups if x.children)
                text = " + ".join(dict.fromkeys(x.text for x in groups if x.children))
                out["group"] = {"kind": first.kind, "lo": first.lo, "hi": first.hi, "text": text,
                                "kinds": sorted({x.kind for x in groups if x.children})}
            out["constraints"] = [source_text(self.model, c.path, c.span, 120, cache) for c in f.constraints]
            out["children"] = [node(c.feature, c, x, c.shared) for x in groups for c in x.children]
            return out

        return node(self.model.root)

    def model_json(self) -> dict:
        return {
            "model": self.model_path,
            "name": self.model.root.name,
            "roots": self.roots,
            "launch": self.launch,
            "launches": self.launches,
            "features": len(self.names),
            "tree": self.tree(),
        }

    def problems_json(self, decisions: Mapping[str, bool]) -> dict:
        """Every problem of the model and its launch files, and its status under ``decisions``
        (checked on first use: it can take seconds on a big model, so it is a request of its own)."""
        return {"problems": [self._problem_json(p) for p in self.problems()],
                "status": self.problem_status(decisions)}

    def problem_status(self, decisions: Mapping[str, bool]) -> Optional[dict[str, str]]:
        """{problem id: possible | certain | excluded}; None while the problems are not checked."""
        if self._problems is None:
            return None
        decisions = self.check_decisions(decisions)
        key = _key(decisions)
        everything = self._problems + (self._rule_problems or [])
        with self._lock:
            hit = self._problem_states.get(key)
            if hit is None or len(hit) != len(everything):
                decided = graphmod.decisions_formula(decisions)
                hit = {x.id: problemsmod.status(x, decisions, self.logic, decided) for x in everything}
                self._problem_states[key] = hit
                while len(self._problem_states) > 64:
                    self._problem_states.popitem(last=False)
            return hit

    # ------------------------------------------------------------------ problems
    def set_problems(self, diags: list) -> None:
        """Problems checked elsewhere (a host may run :func:`check_files` in a worker process)."""
        with self._problem_lock:
            self._problems = [problemsmod.problem_of(i, d) for i, d in enumerate(diags)]

    def problems(self) -> list:
        with self._problem_lock:
            if self._problems is None:
                from ..project.check import check_document
                diags = []
                for p in [self.model_path] + self.launches:
                    try:
                        diags += check_document(p, read_file=self.read_file, roots=self.roots,
                                                workspace=self.workspace)
                    except Exception as exc:  # an analysis bug must not break the configurator
                        from ..project.check import _internal
                        diags.append(_internal(p, f"check failed: {exc!r}"))
                self._problems = [problemsmod.problem_of(i, d) for i, d in enumerate(diags)]
        return self._problems + self.rule_problems()

    def rule_problems(self) -> list:
        """The HAROS project files' ``rules`` evaluated on the graph of every product (or listed
        as not evaluated): problems with the condition of what each query finds."""
        with self._problem_lock:
            if self._rule_problems is None:
                from . import rules
                found = []
                # the rules query launch models: a model configuring no launch file has none
                for path in (self.rule_files() if self.launch else []):
                    text = self.read_file(path)
                    if text and "rules" in text:
                        found += rules.read_rules(path, text)
                g = simp = None
                if found and self.launch:
                    ctx = getattr(self.graph, "ctx", None)
                    g = getattr(ctx, "graph", None)
                    if g is not None:
                        simp = rules.simplifier(ctx.logic, g)
                try:
                    diags = rules.diagnostics(found, g, valid=lambda c: self.logic.valid(c), simplify=simp) \
                        if found else []
                except Exception as exc:  # an evaluator bug must not hide the other problems
                    from ..project.check import _internal
                    diags = [(_internal(found[0].path, f"rules failed: {exc!r}"), None)]
                self._rule_problems = [problemsmod.Problem(f"r{i}", d, c) for i, (d, c) in enumerate(diags)]
            return self._rule_problems

    def rule_files(self) -> list[str]:
        """The project files whose rules apply: ``project_files`` when given, else those naming
        the launch file, else every HAROS project file of the workspace."""
        if self.project_files is not None:
            return list(self.project_files)
        naming = [pf.path for pf in self.workspace.projects for c in pf.configurations
                  if self.launch and any(norm(lf) == self.launch for lf, _ in c.launches)]
        return list(dict.fromkeys(naming)) or [pf.path for pf in self.workspace.projects]

    def _problem_json(self, p) -> dict:
        d = p.diagnostic
        return {"id": p.id, "code": d.code, "severity": d.severity.label, "message": d.message,
                "location": self._loc(d.path, d.span),
                "related": [{"message": r.message, "location": self._loc(r.path, r.span)} for r in d.related],
                "condition": None if p.condition is None else str(p.condition), "witness": p.witness}

    # ------------------------------------------------------------------ decisions
    def decide(self, decisions: Mapping[str, bool], feature: str,
               value: Optional[bool]) -> tuple[dict[str, bool], Optional[Refusal]]:
        """The decisions after including (True) / excluding (False) / resetting (None)
        ``feature``; the decisions unchanged and a :class:`Refusal` when no product
        respects them."""
        decisions = self.check_decisions(decisions)
        name = self.feature(feature)
        new = dict(decisions)
        if value is None:
            new.pop(name, None)
            return new, None
        new[name] = bool(value)
        with self._lock:
            p = self.analysis.propagate(new, count=False)
            if p.ok:
                self._remember_state(new, p)
        if p.ok:
            return new, None
        return decisions, self._refusal(name, bool(value), p.conflict or [name], new)

    def _refusal(self, name: str, value: bool, core: list[str], new: Mapping[str, bool]) -> Refusal:
        others = {k: new[k] for k in core if k != name}
        inc = [k for k in core if new[k]]
        exc = [k for k in core if not new[k]]
        with self._lock:
            elements = self.analysis.explain(include=inc, exclude=exc) or []
        because = [dict(label=e.label, location=self._loc(e.path, e.span)) for e in elements]
        what = f"{_verb(value).capitalize()} {name}"
        if others:
            mine = ", ".join(f"{_verb(v)} {k}" for k, v in others.items())
            msg = f"{what}: refused, it conflicts with your decision{'s' if len(others) > 1 else ''} to {mine}."
        else:
            msg = f"{what}: refused, no product {_verb(value)}s it."
        if because:
            msg += " Because: " + "; ".join(b["label"] for b in because) + "."
        return Refusal(name, value, others, because, msg)

    def state(self, decisions: Mapping[str, bool]) -> dict:
        """User decisions, implied ones, open features, and the status of every graph element
        and (once checked) every problem under them (no counts: see :meth:`counts`)."""
        decisions = self.check_decisions(decisions)
        out = dict(self._core_state(decisions))
        out["graph"] = self.graph_status(decisions)
        out["problems"] = self.problem_status(decisions)
        return out

    def graph_status(self, decisions: dict[str, bool]) -> Optional[dict[str, str]]:
        """{element id: certain | possible | absent}; None while the graph is not built."""
        if self._graph is None:
            return None
        key = _key(decisions)
        with self._lock:
            hit = self._graph_states.get(key)
            if hit is None:
                hit = self._graph.statuses(decisions, self.logic)
                self._graph_states[key] = hit
                while len(self._graph_states) > 64:
                    self._graph_states.popitem(last=False)
            return hit

    def _remember_state(self, decisions: dict[str, bool], p) -> dict:
        out = {"decisions": dict(decisions), "implied": dict(p.forced), "open": list(p.open),
               "complete": not p.open}
        self._states[_key(decisions)] = out
        while len(self._states) > 64:
            self._states.popitem(last=False)
        return out

    def _core_state(self, decisions: dict[str, bool]) -> dict:
        key = _key(decisions)
        with self._lock:
            hit = self._states.get(key)
            if hit is not None:
                self._states.move_to_end(key)
                return hit
            p = self.analysis.propagate(decisions, count=False)
            if not p.ok and not decisions:
                # a void model: it opens (its problems say why), every decision is refused
                out = {"decisions": {}, "implied": {}, "open": list(self.names), "complete": False, "void": True}
                self._states[key] = out
                return out
            if not p.ok:
                raise SessionError("the decisions conflict: " + ", ".join(p.conflict or []))
            return self._remember_state(decisions, p)

    # ------------------------------------------------------------------ counts
    def compile_status(self, start: bool = True):
        """Where the model's compilation stands (:class:`~tvl_lsp.analysis.counting.CompileStatus`);
        with ``start``, start it in the background (d4 in a child process, at most
        :attr:`compile_budget` seconds) if it is not running yet."""
        svc = self.analysis.counter
        return svc.start(self.compile_budget, owner=self.model_path) if start else svc.status()

    def counts(self, decisions: Mapping[str, bool], features: Optional[Iterable[str]] = None,
               timeout: Optional[float] = 10.0, cancel=None, wait: float = 1.0) -> dict:
        """Remaining products and, for ``features`` (default: all, in model order), how many of
        them select each feature -- from the counting service: one pass over the model's
        compiled d-DNNF, whatever the number of features.  The compilation runs in the
        background (started by the first call): when it is not ready within ``wait`` seconds
        the answer comes at once with ``pending: true`` (no counts) and the host asks again.
        Models d4 cannot count (auxiliary variables the features do not determine, d4 failed or
        out of its budget) are counted by pyganak within ``timeout``; what is not counted in
        time is left out (``complete: false``).  Counts are decimal strings (they exceed 2**53)."""
        decisions = self.check_decisions(decisions)
        wanted = list(dict.fromkeys(self.feature(f) for f in features)) if features is not None else list(self.names)
        st = self.compile_status()
        if st.state == "compiling" and wait > 0:
            st = self.analysis.counter.wait(wait)
        if st.state in ("compiling", "idle"):
            return {"decisions": dict(decisions), "total": None if self._total is None else str(self._total),
                    "remaining": None, "features": {}, "complete": False, "pending": True,
                    "status": "compiling", "message": st.message, "seconds": round(st.seconds, 1),
                    "budget": self.compile_budget, "engine": None}
        why = self.analysis.counter.gave_up() if st.state == "failed" else None
        if why is not None:
            # out of its compile budget: no count will come (pyganak would spend the timeout on
            # every click and fail too); the configurator works on without counts
            return {"decisions": dict(decisions), "total": None, "remaining": None, "features": {},
                    "complete": False, "pending": False, "status": "gave-up", "budget": self.compile_budget,
                    "message": f"not counted: d4 could not compile the model within its budget of "
                               f"{self.compile_budget:g} s ({why})", "engine": None}
        inc = [k for k, v in decisions.items() if v]
        exc = [k for k, v in decisions.items() if not v]
        enc = self.analysis.encoding
        order = [enc.var(f) for f in wanted]
        with self._count_lock:
            try:
                r = self.analysis.feature_counts_result(inc, exc, timeout=timeout, cancel=cancel, order=order)
            except (CountTimeout, CountCancelled) as e:
                return {"decisions": dict(decisions), "total": None if self._total is None else str(self._total),
                        "remaining": None, "features": {}, "complete": False, "pending": False,
                        "status": st.state, "message": str(e) or "no answer in time", "engine": None}
            if not decisions:
                self._total = r.total
            elif self._total is None:
                try:
                    self._total = self.analysis.count_result(timeout=timeout, cancel=cancel).value
                except (CountTimeout, CountCancelled):
                    pass
        per = {f: r.counts[v] for f, v in zip(wanted, order) if r.counts[v] is not None}
        return {"decisions": dict(decisions),
                "total": None if self._total is None else str(self._total),
                "remaining": str(r.total),
                "features": {k: str(v) for k, v in per.items()},
                "complete": r.complete and len(per) == len(wanted),
                "pending": False, "status": st.state, "message": r.note, "engine": r.engine}

    # ------------------------------------------------------------------ generation
    def products(self, decisions: Mapping[str, bool], mode: str, limit: int = 100) -> list[dict[str, bool]]:
        return self._products(decisions, mode, limit)[0]

    def _products(self, decisions: Mapping[str, bool], mode: str, limit: int) -> tuple[list[dict[str, bool]], bool]:
        """(products, cut): ``cut`` when there are more than ``limit`` of them."""
        decisions = self.check_decisions(decisions)
        if mode not in MODES:
            raise SessionError(f"mode must be one of {', '.join(MODES)}")
        if mode == "current":
            st = self.state(decisions)
            if not st["complete"]:
                raise SessionError(f"the product is not complete yet: {len(st['open'])} feature(s) are open "
                                   f"({', '.join(st['open'][:5])}{', …' if len(st['open']) > 5 else ''}); "
                                   "decide them or use Complete")
            product = {n: False for n in self.names}
            product.update(st["implied"])
            product.update(decisions)
            return [product], False
        if mode == "sample":
            products = self.pairwise(decisions)
            if len(products) > limit:
                raise SessionError(f"the pairwise sample has {len(products)} configurations, more than the limit "
                                   f"of {limit} files per Generate: decide more features first, or raise the "
                                   "limit (tvl-lsp ui --limit, the server's generate.limit setting)")
            return products, False
        inc = [k for k, v in decisions.items() if v] if mode == "completions" else []
        exc = [k for k, v in decisions.items() if not v] if mode == "completions" else []
        with self._lock:
            got = list(self.analysis.enumerate(limit=limit + 1, include=inc, exclude=exc))
        return got[:limit], len(got) > limit

    def pairwise(self, decisions: Mapping[str, bool], seed: int = 0) -> list[dict[str, bool]]:
        """A pairwise (t = 2) sample of the products that respect ``decisions``: every
        configuration is a product, every valid pair of feature choices is in one of them
        (:mod:`tvl_lsp.analysis.sampling`: a SAT solver, no compilation to wait for)."""
        inc = [k for k, v in decisions.items() if v]
        exc = [k for k, v in decisions.items() if not v]
        try:
            with self._count_lock:
                products, _ = self.analysis.sample(t=2, seed=seed, include=inc, exclude=exc,
                                                   timeout=SAMPLE_BUDGET)
        except ValueError as e:
            raise SessionError(f"no pairwise sample: {e}; decide more features first")
        except (CountTimeout, CountCancelled):
            raise SessionError(f"no pairwise sample within {SAMPLE_BUDGET:g} s: decide more features first")
        return products

    def _available(self, decisions: dict[str, bool], mode: str) -> Optional[int]:
        """How many products ``mode`` covers, when the compiled model says it at once."""
        if mode == "current":
            return 1
        if mode == "sample" or not self.analysis.counter.ready():
            return None
        d = decisions if mode == "completions" else {}
        try:
            with self._count_lock:
                return self.analysis.count_result(include=[k for k, v in d.items() if v],
                                                  exclude=[k for k, v in d.items() if not v], timeout=2).value
        except (CountTimeout, CountCancelled):
            return None

    def file_names(self, products: list[dict[str, bool]], features: list[str], decisions: Mapping[str, bool],
                   prefix: str, suffix: str) -> list[str]:
        """Readable, distinct file names: the product's selected features that not every product
        has (``generic_random-teleop.launch``); when those are too many, your included decisions
        and a number (``generic_amcl-lidar_3.launch``)."""
        import re
        with self._lock:
            core = set(self.analysis.core_features())
        mine = [k for k, v in decisions.items() if v and k not in core]

        def token(f: str) -> str:
            return re.sub(r"[^A-Za-z0-9_]+", "_", f).strip("_").lower() or "_"
        out: list[str] = []
        seen: dict[str, int] = {}
        named: dict[tuple, str] = {}  # products the launch file cannot tell apart: one file
        for i, prod in enumerate(products):
            on = [f for f in features if prod.get(f) and f not in core]
            if tuple(on) in named:
                out.append(named[tuple(on)])
                continue
            body = "-".join(token(f) for f in on) or "base"
            if len(body) > 60:
                head = "-".join(token(f) for f in mine[:3]) or "config"
                more = len(on) - min(3, len(mine))
                body = f"{head}-and-{more}-more" if len(products) == 1 else f"{head}_{i + 1}"
            name = f"{prefix}_{body}"
            n = seen.get(name.casefold(), 0)
            seen[name.casefold()] = n + 1
            named[tuple(on)] = f"{name}{'' if n == 0 else f'_{n + 1}'}{suffix}"
            out.append(named[tuple(on)])
        return out

    def plan_generation(self, decisions: Mapping[str, bool], mode: str, folder: Optional[str] = None,
                        limit: int = 100):
        """(files, out_dir): the configuration launch files for ``mode`` (current product,
        every completion, a pairwise sample, or every product), planned inside the workspace
        -- nothing is written here.  :attr:`last_plan` says how many products there were and
        whether the limit cut them."""
        from ..project.generate import GenerateError, plan_configurations, resolve_folder
        if not self.launch or self._launch_analysis is None:
            raise SessionError(f"{os.path.basename(self.model_path)} is paired with no launch file: choose one "
                               "(the launch file whose top-level args are the model's features)")
        decisions = self.check_decisions(decisions)
        la = self._launch_analysis
        feature_names = set(self.names) | {f.long_name for f in self.model.features} | {f.name for f in self.model.features}
        features = [a.name for a in la.feature_args if a.name in feature_names and getattr(a, "value", None) is None]
        products, cut = self._products(decisions, mode, limit)
        package = self.workspace.package_of(self.launch)
        package_dir = self.workspace.packages.get(package) if package else None
        dialect = getattr(la, "dialect", "ros1")
        prefix = Path(self.launch).name.split(".")[0]
        names = self.file_names(products, features, decisions, prefix, ".launch.xml" if dialect == "ros2" else ".launch")
        try:
            out_dir = resolve_folder(folder, self.launch, self.roots)
            from ..project.generate import ros2_choices
            files = plan_configurations(products, features, self.launch, out_dir, self.roots, package, package_dir,
                                        omit=[self.model.root.name], dialect=dialect,
                                        choices=ros2_choices(la, self.model), names=names)
        except GenerateError as e:
            raise SessionError(str(e))
        self.last_plan = {"products": len(products), "limit": limit, "cut": cut,
                          "available": self._available(decisions, mode) if cut else len(products)}
        return files, out_dir

    # ------------------------------------------------------------------ pairing
    def launch_candidates(self, limit: int = 50) -> list[dict]:
        """The workspace's launch files, those whose top-level ``<arg>`` names are most of the
        model's features first: ``{path, relative, args, matches}`` (for choosing the launch file
        the model configures when no pairing rule names one)."""
        import re
        names = set(self.names) | {f.name for f in self.model.features}
        tag = re.compile(r"<arg\s[^>]*>")
        name = re.compile(r"\bname\s*=\s*[\"']([^\"']+)[\"']")
        out = []
        for lf in self.workspace.files.launches[:2000]:
            text = self.read_file(lf)
            if not text:
                continue
            # the args a command line sets (no `value`): a configuration launch file fixes them
            args = {m.group(1) for t in tag.findall(text) if not re.search(r"\bvalue\s*=", t)
                    for m in [name.search(t)] if m}
            out.append({"path": lf, "relative": self.relative(lf), "args": len(args), "matches": len(args & names)})
        out.sort(key=lambda x: (-x["matches"], x["relative"]))
        return out[:limit]

    # ------------------------------------------------------------------ sources
    def known_files(self) -> set[str]:
        out = set(self.sources) | set(self.launches) | self.known_extra
        g = self.graph.to_json()
        for x in g["elements"] + g["edges"]:
            if x.get("location"):
                out.add(x["location"]["path"])
        if self._launch_analysis is not None:
            out |= {e.path for e in self._launch_analysis.elements}
        for p in self.problems():
            out.add(p.diagnostic.path)
            out |= {r.path for r in p.diagnostic.related}
        return {norm(x) for x in out}

    def excerpt(self, path: str, line: int, context: int = 4) -> dict:
        """Lines around ``line`` (0-based) of a file of this session (inside the workspace)."""
        from ..project.generate import inside
        path = norm(path)
        if path not in self.known_files() or not inside(path, self.roots):
            raise SessionError("not a file of this configuration")
        text = self.sources.get(path) if path in self.sources else self.read_file(path)
        if text is None:
            raise SessionError(f"cannot read {path}")
        lines = text.splitlines()
        lo, hi = max(0, line - context), min(len(lines), line + context + 1)
        return {"path": path, "relative": self.relative(path), "start": lo, "line": line,
                "lines": lines[lo:hi]}

    def relative(self, path: str) -> str:
        for r in self.roots:
            try:
                return Path(path).relative_to(r).as_posix()
            except ValueError:
                continue
        return path


def member_kind(entry, group) -> tuple[str, str]:
    """(kind, words) of a feature in its parent's group: ``root``, ``mandatory``, ``optional``
    (an ``opt`` child, or a UVL ``optional`` group: optionality prevails over the group) or
    ``member`` (of a oneOf / someOf / cardinality group, which decides)."""
    if entry is None or group is None:
        return "root", "root (in every product)"
    n = len(group.children)
    if group.kind == "allOf":
        if entry.optional:
            return "optional", "optional"
        return "mandatory", "mandatory (whenever its parent is included)"
    if entry.optional:
        return "optional", f"optional (in a {group.text} group: optionality prevails)"
    if group.kind == "oneOf":
        return "member", f"group member: {group.text}, exactly one of {n}"
    if group.kind == "someOf":
        return "member", f"group member: {group.text}, at least one of {n}"
    hi = "any number" if group.hi is None else str(group.hi)
    return "member", f"group member: {group.text}, {group.lo} to {hi} of {n}"


def check_files(paths: list[str], roots: list[str]) -> list:
    """The diagnostics of the given model / launch files (for :meth:`Session.set_problems`)."""
    from ..project.check import _internal, check_document
    out = []
    for p in paths:
        try:
            out += check_document(p, roots=roots)
        except Exception as exc:
            out.append(_internal(p, f"check failed: {exc!r}"))
    return out


def configurable_models(roots: Iterable[str], read_file: Optional[ReadFile] = None) -> list[dict]:
    """Every model of the workspace with the launch files it configures (for a picker)."""
    ws = load_workspace([norm(r) for r in roots], read_file)
    out = []
    for m in sorted(ws.files.models):
        out.append({"model": m, "launches": sorted({p.launch for p in ws.launches_for_model(m)})})
    return out
