"""What the configurator does with whole sets of decisions: why a feature is implied, a set of
decisions replaced at once (a loaded configuration, an undo), and the configuration completed
(the smallest product, or one drawn at random).  Pure: the hosts call these through :mod:`.api`.

    why(s, {"Amcl": True}, "Lidar")
    # {"feature": "Lidar", "value": True, "byDecisions": {"Amcl": True},
    #  "because": [{"label": "Amcl requires Lidar", ...}],
    #  "text": "included because you included Amcl: Amcl requires Lidar"}
"""

from __future__ import annotations

from typing import Mapping, Optional

from .session import Refusal, Session, SessionError

MAX_BECAUSE = 6  # model elements listed in one explanation


def _verb_past(v: bool) -> str:
    return "included" if v else "excluded"


def _lits(s: Session, decisions: Mapping[str, bool]) -> dict[int, str]:
    enc = s.analysis.encoding
    out: dict[int, str] = {}
    for name, val in decisions.items():
        v = enc.var(name)
        out[v if val else -v] = name
    return out


def why(s: Session, decisions: Mapping[str, bool], feature: str) -> dict:
    """Why ``feature`` has the value the decisions imply: the smallest set of your decisions that
    forces it and the parts of the model that make them force it.  ``implied: false`` when the
    feature is open or is your own decision."""
    from ..analysis.solve import decide
    decisions = s.check_decisions(decisions)
    name = s.feature(feature)
    if name in decisions:
        v = decisions[name]
        return {"feature": name, "value": v, "implied": False, "byDecisions": {}, "because": [],
                "text": f"{_verb_past(v)}: your decision"}
    st = s.state(decisions)
    if name not in st["implied"]:
        return {"feature": name, "value": None, "implied": False, "byDecisions": {}, "because": [],
                "text": "open: some remaining products include it, some do not"}
    value = bool(st["implied"][name])
    enc = s.analysis.encoding
    lits = _lits(s, decisions)
    var = enc.var(name)
    probe = -var if value else var
    with s._lock:
        core, _ = decide(enc, list(lits) + [probe])
    core = [x for x in (core or []) if x != probe]
    mine = {lits[x]: x > 0 for x in core if x in lits}
    inc = [k for k, v in mine.items() if v] + ([name] if not value else [])
    exc = [k for k, v in mine.items() if not v] + ([name] if value else [])
    with s._lock:
        elements = s.analysis.explain(include=inc, exclude=exc) or []
    because = [{"label": e.label, "location": s._loc(e.path, e.span)} for e in elements[:MAX_BECAUSE]]
    labels = "; ".join(b["label"] for b in because) + ("; …" if len(elements) > MAX_BECAUSE else "")
    if mine:
        cause = " and ".join(f"{'included' if v else 'excluded'} {k}" for k, v in mine.items())
        text = f"{_verb_past(value)} because you {cause}"
    else:
        text = f"{_verb_past(value)} in every product of the model"
    if labels:
        text += ": " + labels
    return {"feature": name, "value": value, "implied": True, "byDecisions": mine, "because": because,
            "text": text}


def replace(s: Session, decisions: Mapping[str, bool]) -> tuple[dict[str, bool], Optional[Refusal]]:
    """Take ``decisions`` as a whole (a loaded configuration, an undo): (them, None) when some
    product respects them, else (the largest prefix that does, a refusal naming the first
    decision that conflicts with the ones before it)."""
    decisions = s.check_decisions(decisions)
    with s._lock:
        p = s.analysis.propagate(decisions, count=False)
    if p.ok:
        s._remember_state(dict(decisions), p)
        return dict(decisions), None
    kept: dict[str, bool] = {}
    for k, v in decisions.items():
        new, refusal = s.decide(kept, k, v)
        if refusal is not None:
            return kept, refusal
        kept = new
    return kept, None


def complete(s: Session, decisions: Mapping[str, bool], how: str = "minimal",
             seed: Optional[int] = None) -> tuple[dict[str, bool], dict]:
    """Decide every open feature: ``minimal`` (the product with the fewest features that
    respects the decisions; MaxSAT) or ``random`` (a product drawn uniformly at random among the
    remaining ones from the compiled model; any product when the model cannot be compiled).
    Returns (decisions + the completion, {added: {feature: bool}, how, engine})."""
    decisions = s.check_decisions(decisions)
    st = s.state(decisions)
    inc = [k for k, v in decisions.items() if v]
    exc = [k for k, v in decisions.items() if not v]
    engine = "maxsat"
    if how == "minimal":
        with s._lock:
            product = s.analysis.find_product(include=inc, exclude=exc, smallest=True)
    elif how == "random":
        product = None
        if s.compile_status().state == "ready":
            from ..analysis.counting.errors import CountCancelled, CountTimeout
            try:
                with s._count_lock:
                    got, engine = s.analysis.sample(uniform=1, seed=seed, include=inc, exclude=exc, timeout=10)
                product = got[0] if got else None
            except (CountTimeout, CountCancelled, ValueError):
                product = None
        if product is None:
            engine = "sat"
            product = _random_product(s, decisions, seed)
    else:
        raise SessionError("complete: how must be minimal or random")
    if product is None:
        raise SessionError("no product respects your decisions")
    added = {n: bool(product.get(n, False)) for n in st["open"]}
    new = dict(decisions)
    new.update(added)
    new, refusal = replace(s, new)
    if refusal is not None:  # cannot happen for a product; say so rather than half-complete
        raise SessionError(f"the completion was refused: {refusal.message}")
    return new, {"added": added, "how": how, "engine": engine}


def _random_product(s: Session, decisions: Mapping[str, bool], seed: Optional[int]) -> Optional[dict[str, bool]]:
    """A product respecting ``decisions`` found by a SAT solver whose phases are drawn at random
    (the model is not compiled: a random product, not a uniform one)."""
    import random

    from ..analysis.solve import new_solver
    enc = s.analysis.encoding
    rng = random.Random(seed)
    lits = list(_lits(s, decisions))
    solver = new_solver(enc.clauses())
    try:
        try:
            solver.set_phases([v if rng.random() < 0.5 else -v for v in range(1, enc.n_features + 1)])
        except NotImplementedError:
            pass
        if not solver.solve(assumptions=lits):
            return None
        m = solver.get_model()
    finally:
        solver.delete()
    return {enc.name_of(f): m[v - 1] > 0 for f, v in enc.var_of_feature.items()}
