"""Pure helpers for the server's features: look-ups in parsed models and launch analyses,
and the model facts (counts, anomalies) computed in a worker process.  No pygls here.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Iterable, Optional

from ..base import formula as fm
from ..base.text import Pos, Span
from ..tvl import model as M

log = logging.getLogger("tvl_lsp.facts")

# the kinds of model documents (TVL, UVL, DIMACS): hover, code lens, outline, configurator, ...
MODEL_KINDS = ("tvl", "uvl", "dimacs")


# ------------------------------------------------------------------ model facts

@dataclass
class ModelFacts:
    total: Optional[int] = None
    per_feature: dict[str, int] = field(default_factory=dict)   # feature (name_of) -> products
    core: set[str] = field(default_factory=set)
    dead: set[str] = field(default_factory=set)
    false_optional: set[str] = field(default_factory=set)
    error: Optional[str] = None
    seconds: float = 0.0
    # set when computed with ``wait``: "compiling" (d4 still compiles the model in the
    # background: ask again) or "fallback" (d4 cannot count it: ask without ``wait``, where a
    # slow pyganak count blocks nothing)
    pending: Optional[str] = None
    # read back from the disk (stored_model_facts) for a model that reads no other file and
    # parses without error: the hover of each feature declaration (hover_rows), which a
    # server answers before its own parse of the text
    hover: Optional[list] = None
    # the time budget ran out (a busy machine, a hard model): not an answer -- a host may try
    # again with a longer budget, and says so meanwhile (``retry``: the budget of that retry)
    timed_out: bool = False
    retry: Optional[float] = None


def formula_names(model: M.Model) -> list[str]:
    """The model's features by the names formulas use (a launch file's args): the short name
    when no other feature has it, else the long name (``Encoding.name_of``)."""
    from collections import Counter
    short = Counter(f.name for f in model.features)
    return [f.name if short[f.name] == 1 else f.long_name for f in model.features]


def _names(items) -> set[str]:
    out = set()
    for x in items or ():
        if isinstance(x, str):
            out.add(x)
        elif hasattr(x, "long_name"):
            out.add(x.name)
            out.add(x.long_name)
        elif hasattr(x, "feature"):
            out |= _names([x.feature])
        elif hasattr(x, "name"):
            out.add(str(x.name))
    return out


def _engine(path: str, sources: dict[str, str]):
    from . import models
    return models.load(path, sources[path], sources.get)[1]


def compute_model_facts(path: str, sources: dict[str, str], timeout: float,
                        wait: Optional[float] = None, compile: bool = True) -> ModelFacts:
    """Total count, per-feature counts and anomalies of the model at ``path`` (``sources``:
    its text and the texts of the files it includes).  The model is parsed and encoded once per
    process (:mod:`.models`: the check of the same text shares it).  With ``wait``, the
    compilation runs in the background (d4 in its child process, ``timeout`` seconds at most)
    and the answer comes within about ``wait`` seconds: ``pending="compiling"`` until the
    circuit is ready (call again), ``pending="fallback"`` when d4 cannot count the model.
    Without ``compile`` (with ``wait``), never start d4: count from a circuit in memory or
    in the disk cache (another process compiles it), else ``pending="compiling"``."""
    t0 = time.perf_counter()
    facts = ModelFacts()
    try:
        eng = _engine(path, sources)
        if wait is not None and eng.model.root is not None:
            svc = eng.counter
            if not compile and svc.d4_usable() and not svc.ready() and not svc.on_disk():
                return ModelFacts(pending="compiling", seconds=time.perf_counter() - t0)
            from .workspace import norm
            st = svc.start(timeout, owner=norm(path))
            if st.state == "compiling":
                # read back from the counting cache (compiled before): no d4 run, only the
                # circuit to parse, so wait for it rather than queue the counts again
                st = svc.wait(timeout if svc.on_disk() else wait)
            log.debug("facts of %s: %s after %.2f s", path, st.state, time.perf_counter() - t0)
            if st.state in ("compiling", "idle"):
                return ModelFacts(pending="compiling", seconds=time.perf_counter() - t0)
            if st.state in ("failed", "unusable"):
                return ModelFacts(pending="fallback", seconds=time.perf_counter() - t0)
        t_end = time.monotonic() + timeout
        # every feature's count in one pass over the compiled model (d4), or one projected
        # count per feature (pyganak) as far as the budget goes
        r = eng.feature_counts_result(timeout=timeout)
        facts.total = r.total
        facts.timed_out = not r.complete  # (some features' counts are missing)
        enc = eng.encoding
        for f, v in enc.var_of_feature.items():
            n = r.counts[v]
            if n is not None:
                facts.per_feature[f.long_name] = n
                facts.per_feature.setdefault(f.name, n)
        from_counts = None
        if r.complete and r.total:  # core and dead straight from the counts
            facts.core = {eng.name(f) for f, v in enc.var_of_feature.items() if r.total and r.counts[v] == r.total}
            facts.dead = {eng.name(f) for f, v in enc.var_of_feature.items() if r.counts[v] == 0}
            from_counts = false_optional_from_counts(eng, r.counts)
        else:
            facts.core = set(eng.core_features())
            facts.dead = set(eng.dead_features())
        if time.monotonic() < t_end:
            facts.false_optional = (from_counts if from_counts is not None
                                    else set(eng.false_optional_features()))
            if r.complete and facts.total is not None:
                # complete and exact: kept on disk by content, so reopening the model reads
                # them back (stored_model_facts) instead of parsing and counting again
                _store(path, sources, facts, _self_contained_rows(path, sources, facts))
    except Exception as e:  # a timeout or a model the engine refuses: say so, never crash
        from ..analysis.counting.errors import CountTimeout
        facts.error = f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
        facts.timed_out = isinstance(e, CountTimeout)
    facts.seconds = time.perf_counter() - t0
    log.debug("facts of %s: %s in %.2f s", path, facts.error or "counted", facts.seconds)
    return facts


def false_optional_from_counts(eng, counts: list) -> Optional[set[str]]:
    """The false-optional features (optional in a group of their parent, yet in every product
    that has the parent) from every feature's count: a feature with one parent implies it, so
    it is in every product with its parent exactly when both counts are equal (and not 0: a
    dead feature is not false-optional).  None when a feature with several parents is
    optional somewhere (the solver decides those): the counts do not say which parent."""
    enc = eng.encoding
    var = enc.var_of_feature
    out = set()
    for p in enc.features:
        vp = var.get(p)
        if vp is None:
            continue
        for g in p.groups:
            for gc in g.children:
                f = gc.feature
                vf = var.get(f)
                if not gc.optional or vf is None:
                    continue
                if f.shared_parents:
                    return None
                n = counts[vf]
                if n is None or counts[vp] is None:
                    return None
                if n and n == counts[vp]:
                    out.add(eng.name(f))
    return out


def _self_contained_rows(path: str, sources: dict[str, str], facts: ModelFacts) -> Optional[list]:
    """:func:`hover_rows` when the model's parse read no other file and has no error (then
    its text alone decides it: a server may answer from them before parsing), else None."""
    from . import models
    reads: dict[str, Optional[str]] = {}

    def recording(p: str) -> Optional[str]:
        reads[p] = sources.get(p)
        return reads[p]
    try:
        res = models.load(path, sources[path], recording)[0]
        if reads or getattr(res, "errors", None) or res.model is None:
            return None
        return hover_rows(res.model, path, facts)
    except Exception:  # noqa: BLE001 (no rows: the server parses first, as without a store)
        return None


def _store(path: str, sources: dict[str, str], facts: ModelFacts, rows: Optional[list] = None) -> None:
    from . import factstore
    try:
        factstore.store(path, sources, {"total": facts.total, "per_feature": facts.per_feature,
                                        "core": facts.core, "dead": facts.dead,
                                        "false_optional": facts.false_optional, "hover": rows})
    except Exception:  # noqa: BLE001 (the store is an optimisation: never fail the count)
        pass


def stored_model_facts(path: str, sources: dict[str, str]) -> Optional[ModelFacts]:
    """The facts :func:`compute_model_facts` stored for exactly this content (the model's
    text and the texts of the files it read), or None: no parse, no encoding, no circuit.
    A damaged or foreign file is ignored (and removed)."""
    from . import factstore
    t0 = time.perf_counter()
    try:
        fields = factstore.load(path, sources)
    except Exception:  # noqa: BLE001 (an unreadable store is a miss)
        return None
    if fields is None:
        return None
    return ModelFacts(total=fields["total"], per_feature=fields["per_feature"], core=fields["core"],
                      dead=fields["dead"], false_optional=fields["false_optional"],
                      hover=fields.get("hover"), seconds=time.perf_counter() - t0)


def count_under(path: str, sources: dict[str, str], formula, timeout: float) -> Optional[int]:
    """Products of the model in which ``formula`` (over feature names) holds; None when the
    formula names something the model has no feature for (e.g. a launch file's arg whose
    feature an edit removed)."""
    eng = _engine(path, sources)
    known = {eng.name(f) for f in eng.model.features} | {f.name for f in eng.model.features}
    if not set(fm.variables(formula)) <= known:
        return None
    return _as_int(eng.count(formula=formula, timeout=timeout))


def _get(obj, name):
    if obj is None:
        return None
    if isinstance(obj, dict):
        return obj.get(name)
    return getattr(obj, name, None)


def _as_int(v) -> Optional[int]:
    if v is None:
        return None
    if isinstance(v, bool):
        return int(v)
    if isinstance(v, int):
        return v
    for attr in ("count", "value", "total"):
        x = getattr(v, attr, None)
        if isinstance(x, int) and not isinstance(x, bool):
            return x
    try:
        return int(v)
    except (TypeError, ValueError):
        return None


def percent(n: int, total: int) -> str:
    if not total:
        return "0 %"
    p = 100 * n / total
    if p in (0, 100) or p >= 1:
        return f"{p:.0f} %" if abs(p - round(p)) < 0.05 else f"{p:.1f} %"
    return f"{p:.2g} %"


# ------------------------------------------------------------------ hover text

def count_line(facts, f: M.Feature) -> str:
    if facts is None:
        return "products: counting… (hover again in a moment)"
    if getattr(facts, "retry", None) and facts.total is None:
        return (f"products: not counted yet ({facts.error}); counting again in the background with "
                f"{facts.retry:g} s (hover again in a moment)")
    if facts.error and facts.total is None:
        return f"products: not counted ({facts.error})"
    total = facts.total
    if f.is_root or f.parent is None:
        return f"**{total} products** in total" if total is not None else "products: unknown"
    n = facts.per_feature.get(f.long_name, facts.per_feature.get(f.name))
    if n is None or total is None:
        return "products: unknown"
    return f"in **{n} of {total} products** ({percent(n, total)})"


def feature_markdown(f: M.Feature, facts) -> str:
    kind = "root feature" if (f.is_root or f.parent is None) else "feature"
    lines = [f"**{kind}** `{f.long_name}`", ""]
    if f.parent is not None:
        parents = ", ".join(f"`{p.name}`" for p in f.parents)
        lines.append(f"- parent: {parents}")
        g = f.parent.group_of(f)
        if g is not None:
            opt = "optional" if g.keyword else "optional (`opt`)"  # (UVL groups say it with their keyword)
            if g.kind == "allOf":
                role = opt if f.optional else "mandatory (selected with its parent)"
            else:
                role = opt if f.optional else "counted by the group's cardinality"
            lines.append(f"- in the group `{group_text(g)}` of `{f.parent.name}`: {role}")
    else:
        lines.append("- the root: selected in every product")
    for g in f.groups:
        kids = ", ".join(("opt " if c.optional and not g.keyword else "") + c.feature.name for c in g.children)
        lines.append(f"- group `{group_text(g)}` over {kids}")
    if facts is not None and not (f.is_root or f.parent is None):
        flags = []
        for label, names in (("core (in every product)", facts.core), ("dead (in no product)", facts.dead),
                             ("false-optional (declared optional, yet in every product with its parent)",
                              facts.false_optional)):
            if f.long_name in names or f.name in names:
                flags.append(label)
        if flags:
            lines.append("- " + "; ".join(flags))
    for a in f.attributes:
        extra = ""
        if getattr(a, "uvl_text", None) is not None:  # a UVL attribute: its text, not analysed
            lines.append(f"- attribute `{' '.join(a.uvl_text.split())[:80]}` (not analysed)")
            continue
        if a.value is not None:
            extra = " (computed)"
        elif a.domain is not None:
            extra = " (in a domain)"
        lines.append(f"- attribute `{a.type} {a.name}`{extra}")
    if f.constraints:
        lines.append(f"- {len(f.constraints)} constraint(s)")
    lines.append("")
    lines.append(count_line(facts, f))
    return "\n".join(lines)


def hover_rows(model: M.Model, path: str, facts: ModelFacts) -> list[list]:
    """``[start line, start col, end line, end col, markdown]`` for every feature declared in
    the file ``path``: what the hover on its name says with these facts.  Only names no other
    occurrence overlaps (:func:`name_at` answers them with their feature wherever the
    position is in them); one pass over the model's occurrences."""
    from ..tvl import symbols
    occ = sorted({(sp.start, sp.end, id(t)): (sp, t, d) for p, sp, t, d in symbols.occurrences(model)
                  if p == path and sp is not None}.values(), key=lambda x: (x[0].start, x[0].end))
    rows = []
    reach = None  # the furthest end of the occurrences before
    for i, (sp, t, decl) in enumerate(occ):
        overlaps = (reach is not None and reach >= sp.start) or (
            i + 1 < len(occ) and occ[i + 1][0].start <= sp.end)
        reach = sp.end if reach is None or sp.end > reach else reach
        if decl and isinstance(t, M.Feature) and not overlaps:
            rows.append([sp.start.line, sp.start.col, sp.end.line, sp.end.col, feature_markdown(t, facts)])
    return rows


def hover_at(rows: list, pos: Pos) -> Optional[tuple[str, Span]]:
    """(markdown, span) of the row of :func:`hover_rows` whose span contains ``pos``."""
    for r in rows:
        if (r[0], r[1]) <= (pos.line, pos.col) <= (r[2], r[3]):
            return r[4], Span(Pos(r[0], r[1]), Pos(r[2], r[3]))
    return None


# ------------------------------------------------------------------ TVL look-ups

def _walk_expr(e) -> Iterable:
    stack = [e]
    while stack:
        x = stack.pop()
        if x is None:
            continue
        yield x
        for attr in ("operand", "left", "right", "cond", "then", "other", "lo", "hi"):
            c = getattr(x, attr, None)
            if isinstance(c, M.Expr):
                stack.append(c)
        for attr in ("args", "items"):
            cs = getattr(x, attr, None)
            if isinstance(cs, list):
                stack.extend(c for c in cs if isinstance(c, M.Expr))


def model_exprs(model: M.Model) -> Iterable[M.Expr]:
    for f in model.features:
        for c in f.constraints:
            yield from _walk_expr(c.expr)
        for a in f.attributes:
            for e in (a.value, a.domain, a.if_in_value, a.if_in_domain, a.if_out_value, a.if_out_domain):
                if e is not None:
                    yield from _walk_expr(e)
        if f.group is not None:
            for e in (f.group.lo_expr, f.group.hi_expr):
                if e is not None:
                    yield from _walk_expr(e)
    for c in model.constants:
        yield from _walk_expr(c.value)


def name_at(model: M.Model, path: str, pos: Pos):
    """(target, span) of the name at ``pos``: a feature / attribute / constant / type
    declaration or a resolved reference; None when there is none."""
    try:
        from ..tvl import symbols
        hit = symbols.name_at(model, path, pos)
        if hit is not None:
            return hit if isinstance(hit, tuple) else (hit, None)
    except (ImportError, AttributeError):
        pass
    for f in model.features:
        for p, s in f.decl_spans or [(f.path, f.name_span)]:
            if p == path and s.contains(pos):
                return f, s
        for a in f.attributes:
            if a.path == path and a.name_span.contains(pos):
                return a, a.name_span
    for c in model.constants:
        if c.path == path and c.name_span.contains(pos):
            return c, c.name_span
    for t in model.types:
        if t.path == path and t.name_span.contains(pos):
            return t, t.name_span
    for e in model_exprs(model):
        if isinstance(e, M.Name) and e.path == path and e.span.contains(pos):
            # the part under the cursor
            for i, ps in enumerate(e.part_spans):
                if ps.contains(pos):
                    if e.feature is not None and e.target is not None and i == len(e.parts) - 1:
                        return e.target, ps
                    tgt = e.feature or e.target
                    return tgt, ps
            return e.target, e.span
    return None


def references(model: M.Model, target) -> list[tuple[str, Span]]:
    """Every place ``target`` is named in the model (declarations included)."""
    try:
        from ..tvl import symbols
        refs = symbols.references(model, target)
        return [(r[0], r[1]) if isinstance(r, tuple) else (r.path, r.span) for r in refs]
    except (ImportError, AttributeError):
        pass
    out: list[tuple[str, Span]] = []
    if isinstance(target, M.Feature):
        out.extend(target.decl_spans or [(target.path, target.name_span)])
    elif hasattr(target, "name_span"):
        out.append((target.path, target.name_span))
    for e in model_exprs(model):
        if not isinstance(e, M.Name):
            continue
        if e.target is target and e.part_spans:
            out.append((e.path, e.part_spans[-1]))
        elif e.feature is target and e.part_spans:
            # the feature part of ``Feature.attr``
            out.append((e.path, e.part_spans[max(0, len(e.part_spans) - 2)]))
    return list(dict.fromkeys(out))  # without repeats, in order


def group_text(g: M.Group) -> str:
    return g.text


# ------------------------------------------------------------------ launch look-ups

def own_elements(analysis, path: str) -> list:
    return [e for e in analysis.elements if e.path == path and e.include_depth == 0]


def element_at(analysis, path: str, pos: Pos):
    best = None
    for e in own_elements(analysis, path):
        if e.span.contains(pos) and (best is None or best.span.start <= e.span.start):
            best = e
    return best


def subst_at(analysis, path: str, pos: Pos):
    for e in own_elements(analysis, path):
        for s in e.substitutions:
            if s.span.contains(pos):
                return e, s
    return None


_ARG_RE = None


def arg_name_span(subst, index) -> Optional[Span]:
    """The span of X in ``$(arg X)`` / ROS 2's ``$(var X)`` (the subst span is the whole
    ``$(...)``); ``index`` is the LineIndex of the file's text."""
    if getattr(subst, "name_span", None) is not None:
        return subst.name_span   # the front end knows it (a Python launch file's string literal)
    import re
    global _ARG_RE
    if _ARG_RE is None:
        _ARG_RE = re.compile(r"\$\(\s*(?:arg|var)\s+([^\s)]+)")
    a, b = index.offset(subst.span.start), index.offset(subst.span.end)
    m = _ARG_RE.match(index.text, a, b)
    if not m:
        return None
    return index.span(m.start(1), m.end(1))


def arg_decls(analysis, path: str, name: str) -> list:
    out = []
    for e in own_elements(analysis, path):
        if e.tag == "arg" and "name" in e.attrs and e.attrs["name"].value == name:
            out.append(e)
    return out


def arg_uses(analysis, path: str, name: str) -> list:
    """(element, subst) for every ``$(arg name)`` (``$(var name)``) in the file."""
    out = []
    for e in own_elements(analysis, path):
        for s in e.substitutions:
            if s.kind in ("arg", "var") and s.args and s.args[0] == name:
                out.append((e, s))
    return out


def included_file(include) -> Optional[str]:
    """The file an include element of the analysed file includes (None: not resolved)."""
    import os
    f = getattr(include, "resolved_file", None)
    return os.path.normpath(f) if f else None


def include_args(analysis, path: str, target: str, name: Optional[str] = None) -> list:
    """The args the file at ``path`` passes to the launch file ``target`` (``<arg>`` children of
    its ``<include>``, the keys of a Python include's ``launch_arguments``): elements, in file
    order (``name``: only those)."""
    import os
    target = os.path.normpath(target)
    out = []
    for e in own_elements(analysis, path):
        if e.tag != "include" or included_file(e) != target:
            continue
        for c in e.children:
            if c.tag == "arg" and "name" in c.attrs and (name is None or c.attrs["name"].value == name):
                out.append(c)
    return out


def text_at(index, span: Span) -> str:
    return index.text[index.offset(span.start):index.offset(span.end)]


# ------------------------------------------------------------------ configurator (worker process)

class UnknownFeatures(KeyError):
    """Decisions on features the model does not have (e.g. kept by a host while the model was
    edited): ``args[0]`` says which."""


def _unknown(eng, decisions: dict[str, bool]) -> Optional[str]:
    known = {eng.name(f) for f in eng.model.features} | {f.name for f in eng.model.features}
    unknown = sorted(k for k in decisions if k not in known)
    return f"unknown feature(s): {', '.join(unknown)}" if unknown else None


def _split(eng, decisions: dict[str, bool]) -> tuple[list[str], list[str]]:
    """(included, excluded) names; :class:`UnknownFeatures` when the model lacks one."""
    error = _unknown(eng, decisions)
    if error:
        raise UnknownFeatures(error)
    return [k for k, v in decisions.items() if v], [k for k, v in decisions.items() if not v]


def configure(path: str, sources: dict[str, str], decisions: dict[str, bool], timeout: float) -> dict:
    """Propagate the configurator's decisions: forced features, conflict, remaining count."""
    eng = _engine(path, sources)
    error = _unknown(eng, decisions)
    if error:
        return {"error": error, "decisions": decisions}
    p = eng.propagate(decisions, count=True, timeout=timeout)
    return {
        "decisions": dict(p.decisions),
        "forced": dict(sorted(p.forced.items())),
        "conflict": p.conflict,
        "remaining": p.count,
        "remainingText": None if p.count is None else str(p.count),
        "open": list(p.open),
    }


def list_products(path: str, sources: dict[str, str], decisions: dict[str, bool], limit: int,
                  timeout: float) -> dict:
    eng = _engine(path, sources)
    inc, exc = _split(eng, decisions)
    names = [eng.name(f) for f in eng.model.features]
    prods = []
    for p in eng.enumerate(limit=limit, include=inc, exclude=exc):
        prods.append([n for n in names if p.get(n)])
    try:
        total = eng.count(include=inc, exclude=exc, timeout=timeout)
    except Exception:
        total = None
    return {"products": prods, "remaining": total, "remainingText": None if total is None else str(total),
            "truncated": total is not None and total > len(prods)}


def sample_products(path: str, sources: dict[str, str], decisions: dict[str, bool], t: int = 2, seed: int = 0,
                    budget: Optional[float] = None, iterations: Optional[int] = None, jobs: int = 1):
    """A ``t``-wise sample of the products respecting the decisions: (products, None), or
    (products so far, the :class:`~tvl_lsp.analysis.sampling.SampleResult`) when the budget
    stopped it first."""
    eng = _engine(path, sources)
    inc, exc = _split(eng, decisions)
    products, r = eng.twise_sample(t, seed=seed, include=inc, exclude=exc, budget=budget, iterations=iterations,
                                   jobs=jobs)
    return products, (None if r.complete else r)


def generation_products(path: str, sources: dict[str, str], decisions: dict[str, bool], mode: str,
                        limit: int, t: int = 2, seed: int = 0) -> list[dict[str, bool]]:
    """Products to write configuration files for: ``one`` (the smallest product respecting the
    decisions), ``completions`` (every product respecting them), ``all`` (every product) or
    ``sample`` (a ``t``-wise covering sample of the products respecting them)."""
    eng = _engine(path, sources)
    inc, exc = _split(eng, decisions)
    if mode == "sample":
        products, _ = eng.sample(t=t, seed=seed, include=inc, exclude=exc)
        return products
    if mode == "one":
        p = eng.find_product(include=inc, exclude=exc)
        return [p] if p is not None else []
    if mode == "all":
        inc, exc = [], []
    return list(eng.enumerate(limit=limit, include=inc, exclude=exc))
