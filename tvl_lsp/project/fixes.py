"""Checked quick fixes for model anomalies (#30): the function both hosts call (the editor's code
actions, ``tvl-lsp --check --fix``).

    fixes_for(path, text, read_file=None, keys=None, budget=20.0) -> FixReport
        For each anomaly finding of the model (void model, always-false and redundant constraints,
        dead and false-optional features; only those whose :func:`finding_key` is in ``keys``
        when given), the fixes that were *checked*: each candidate (from
        :mod:`tvl_lsp.analysis.fixes`) is applied to the text, the text is parsed and analysed
        again -- the model check of ``tvl-lsp --check`` -- and the fix is offered only when its
        finding is gone and no finding is new.  When a fix leaves new findings that further fixes
        settle (a feature made mandatory leaves the constraint that forced it redundant: it is
        removed too; a void model's constraint removed leaves a feature dead or false-optional),
        the fix goes on with them (two levels at most) and its title says every step.  Only
        when a finding has no clean fix at all, the fixes that add no error are offered, their
        title saying what follows.  Each fix is a :class:`~tvl_lsp.base.diagnostics.Fix` whose
        edits turn the text into the checked one; the first clean one is preferred.
    fix_file(path, text, read_file=None, codes=None, budget=60.0) -> FixRun
        Every finding fixed in turn (errors first), each fix checked on the text the previous
        ones left: the text with all of them, what each did, the findings left.
    finding_key(diagnostic, text) -> tuple
        What identifies a finding across edits (positions move; a feature's name, a
        constraint's text do not).

The cost is bounded: a re-check is one parse and one anomaly search of the model (milliseconds
for the models people write, ~0.5 s for embtoolkit's 1,179 features); candidate texts are
checked once each (a constraint removal that fixes several findings is checked once); the
work stops at ``budget`` seconds and says which findings it did not reach.  Results are kept by
content (the same text and files give the same fixes without any work).
"""

from __future__ import annotations

import difflib
import hashlib
import threading
import time
from collections import Counter, OrderedDict
from dataclasses import dataclass, field, replace
from typing import Callable, Iterable, Optional

from ..base.diagnostics import Diagnostic, Fix, Severity, TextEdit
from ..base.text import LineIndex

ReadFile = Callable[[str], Optional[str]]

VOID, DEAD, FALSE_OPT = "void-model", "dead-feature", "false-optional"
REDUNDANT, ALWAYS_FALSE = "redundant-constraint", "always-false-constraint"
ANOMALY_CODES = (VOID, ALWAYS_FALSE, DEAD, FALSE_OPT, REDUNDANT)  # the order fix_file works in
FORMATS = ("tvl", "uvl")
DEPTH = 2          # levels of follow-up fixes a fix may take along
MAX_OFFERS = 6     # fixes offered per finding


def finding_key(d: Diagnostic, text: Optional[str] = None) -> tuple:
    """A finding's identity across edits of its file (``text``: the file's text, for the
    constraint codes)."""
    data = d.data or {}
    if d.code == VOID:
        return (VOID,)
    if d.code == DEAD and "feature" in data:
        return (DEAD, data["feature"])
    if d.code == FALSE_OPT and "feature" in data:
        return (FALSE_OPT, data["feature"], data.get("parent"))
    if d.code in (REDUNDANT, ALWAYS_FALSE) and text is not None:
        from ..analysis.fixes import source_text
        return (d.code, source_text(text, d.span))
    return (d.code, d.path, d.message)


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()


# ------------------------------------------------------------------ one model text, checked

@dataclass
class State:
    """A model text and its check: every diagnostic of the model, keyed."""
    text: str
    diagnostics: list[Diagnostic]
    keys: Counter
    severity: dict
    result: object      # ModelResult
    analysis: object    # ModelAnalysis
    complete: bool      # the anomaly search finished (no anomaly-budget, within the deadline)
    derived: bool = False  # analysed on the previous text's encoding (see Checker.removal_state)
    signature: Optional[tuple] = None  # (analysis.fixes.signature of its model, once asked)

    def findings(self, codes: Iterable[str] = ANOMALY_CODES) -> list[Diagnostic]:
        codes = set(codes)
        return [d for d in self.diagnostics if d.code in codes]


class Checker:
    """Checks model texts of one file the way ``--check`` does (parse, then the anomaly search),
    each text once."""

    def __init__(self, path: str, read_file: Optional[ReadFile], deadline: Optional[float]):
        from .workspace import default_read_file
        self.path = path
        self.read_file = read_file or default_read_file
        self.deadline = deadline
        self._states: dict[str, Optional[State]] = {}
        self.checks = 0

    def left(self) -> Optional[float]:
        return None if self.deadline is None else self.deadline - time.monotonic()

    def expired(self) -> bool:
        left = self.left()
        return left is not None and left <= 0

    def _reader(self, text: str) -> ReadFile:
        path, base = self.path, self.read_file

        def read(p: str) -> Optional[str]:
            return text if p == path else base(p)
        return read

    def state(self, text: str, shared: bool = False, explain: bool = False) -> Optional[State]:
        """The check of ``text`` (None when the time ran out first); ``shared``: through the
        process's model cache (the text the editor or ``--check`` has parsed already);
        ``explain``: with the findings' explanations (their messages), else without."""
        key = (_sha(text), explain)
        hit = self._states.get(key)
        if hit is not None and not hit.derived:
            return hit
        if self.expired():
            return None
        path = self.path
        read = self._reader(text)
        if shared:
            from . import models
            res, analysis = models.load(path, text, read)
        if not shared or res.model.path != path:  # (cached under another spelling of the path)
            from ..analysis.engine import ModelAnalysis
            from ..analysis.formats import parse_any_model
            res = parse_any_model(text, path, read_file=read)
            analysis = ModelAnalysis(res.model)
        diags = list(res.diagnostics)
        if res.model.root is not None:
            left = self.left()
            # (a void model's explanation is its only finding's: the fixes start from it)
            explain = explain or analysis.is_void()
            diags += analysis.anomalies(time_budget=left, hard_budget=left, explain=explain)
        st = self._made(text, diags, res, analysis, False)
        self._states[key] = st
        return st

    def _made(self, text: str, diags: list[Diagnostic], res, analysis, derived: bool) -> State:
        from ..analysis.engine import ANOMALY_BUDGET
        self.checks += 1
        keys: Counter = Counter()
        sev: dict = {}
        for d in diags:
            k = finding_key(d, text if d.path == self.path else None)
            keys[k] += 1
            sev[k] = min(sev.get(k, d.severity), d.severity)
        complete = not any(d.code == ANOMALY_BUDGET for d in diags) and not self.expired()
        return State(text, diags, keys, sev, res, analysis, complete, derived)

    def removal_state(self, st0: State, step: "Step") -> Optional[State]:
        """The check of ``step.text``, a text that differs from ``st0``'s by removed constraints
        (``step.spans``): parsed again, and when the parse says the same model minus those
        constraints, analysed on ``st0``'s encoding without their clauses (what the brief
        calls the same CNF minus a constraint: no second encoding), else checked in full."""
        hit = self._states.get((_sha(step.text), False))
        if hit is not None:
            return hit
        if st0.derived or not st0.complete or not step.spans or self.expired():
            return self.state(step.text)
        import copy
        from ..analysis.cnf import Element
        from ..analysis.engine import ModelAnalysis
        from ..analysis.fixes import signature
        from ..analysis.formats import parse_any_model
        from ..tvl import model as M
        path, text = self.path, step.text
        read = self._reader(text)
        old_read = self._reader(st0.text)
        res = parse_any_model(text, path, read_file=read)
        old = st0.result.model
        removed = set(step.spans)
        if st0.signature is None:
            st0.signature = signature(old, lambda p: old_read(p) or "")
        f_old, c_old = st0.signature
        f_new, c_new = signature(res.model, lambda p: read(p) or "")
        kept = [c for p, sp, c in c_old if not (p == path and sp in removed)]
        if (res.model.root is None or f_old != f_new or kept != [c for _, _, c in c_new]
                or len(kept) != len(c_old) - len(removed)):
            return self.state(text)
        enc0 = st0.analysis.encoding

        def gone(e) -> bool:
            return (e.kind == "constraint" and isinstance(e.obj, M.Constraint) and e.obj.path == path
                    and e.obj.span in removed)
        enc = copy.copy(enc0)
        # (copies: the analysis numbers its own selectors on them)
        enc.elements = [Element(e.kind, e.label, e.path, e.span, e.obj, e.clauses, 0, e.negation)
                        for e in enc0.elements if not gone(e)]
        if len(enc0.elements) - len(enc.elements) != len(removed):
            return self.state(text)
        enc._clauses = enc._key = enc._determined = None
        analysis = ModelAnalysis(old, enc)
        left = self.left()
        found = analysis.anomalies(time_budget=left, hard_budget=left, explain=False)
        # each finding where the new text has its feature or constraint
        where: dict = {}
        for fo, fn in zip(old.features, res.model.features):
            where[(fo.path, fo.name_span)] = fn.name_span
        kept_at = [(p, sp) for p, sp, _ in c_old if not (p == path and sp in removed)]
        for (po, so), (pn, sn, _) in zip(kept_at, c_new):
            where[(po, so)] = sn
        moved = []
        for d in found:
            if d.path != path:
                moved.append(d)
                continue
            sp = where.get((d.path, d.span))
            if sp is None:
                return self.state(text)
            moved.append(replace(d, span=sp, related=[]))
        diags = list(res.diagnostics) + moved
        st = self._made(text, diags, res, analysis, True)
        self._states[(_sha(text), False)] = st
        return st


# ------------------------------------------------------------------ candidate steps

@dataclass(frozen=True)
class Step:
    text: str
    phrase: str      # lower case, "remove the constraint `A -> !B;`"
    kind: str        # "remove" | "mandatory" | "group"
    constraints: tuple = ()   # the constraints it removes (their text)
    redundant: bool = False   # ... which the model implies anyway
    spans: tuple = ()         # ... where they are in the text before the step


TITLE_TEXT = 60  # characters of a constraint a title shows


def _short(text: str) -> str:
    return text if len(text) <= TITLE_TEXT else text[:TITLE_TEXT - 1].rstrip() + "…"


def _constraints_phrase(names: list[str], redundant: bool = False) -> str:
    quoted = [f"`{_short(n)}`" for n in names]
    if len(quoted) == 1:
        return f"remove the {'redundant ' if redundant else ''}constraint {quoted[0]}"
    if len(quoted) > 4:
        return f"remove the constraints {', '.join(quoted[:3])} and {len(quoted) - 3} more"
    return f"remove the constraints {', '.join(quoted[:-1])} and {quoted[-1]}"


def _remove_all(text: str, fmt: str, spans: list) -> Optional[str]:
    from ..analysis.fixes import remove_constraint
    for sp in sorted(spans, key=lambda s: (s.start, s.end), reverse=True):
        text = remove_constraint(text, fmt, sp)
        if text is None:
            return None
    return text


def _removal_steps(st: State, path: str, sets: list[list]) -> list[Step]:
    from ..analysis.fixes import source_text
    fmt = st.result.model.format
    out = []
    for elems in sets:
        new = _remove_all(st.text, fmt, [e.span for e in elems])
        if new is not None and new != st.text:
            names = [source_text(st.text, e.span) for e in elems]
            out.append(Step(new, _constraints_phrase(names), "remove", tuple(names), False,
                            tuple(e.span for e in elems)))
    return out


def _structural_steps(st: State, path: str, extra: list[int], deadline: Optional[float]) -> list[Step]:
    """Edits of the feature tree that the explanation of ``extra`` points at: a ``[n..m]`` group
    asking for more children than it has."""
    from ..analysis.fixes import relax_group
    from ..tvl import model as M
    an = st.analysis
    with an._lock:
        ex = an.analyzer.explain(extra, deadline=deadline)
    out = []
    for e in (ex.elements if ex else []):
        if e.kind == "group-lower" and e.path == path and isinstance(e.obj, M.Group):
            r = relax_group(st.text, e.obj)
            if r is not None:
                out.append(Step(r[0], r[1], "group"))
    return out


def candidate_steps(st: State, path: str, d: Diagnostic, deadline: Optional[float]) -> list[Step]:
    """The edits that may fix the finding ``d`` of the checked text ``st`` (not checked yet)."""
    from ..analysis.fixes import correction_sets, make_mandatory, source_text
    model = st.result.model
    fmt = model.format
    if fmt not in FORMATS or d.path != path:
        return []
    an = st.analysis
    enc = an.encoding
    data = d.data or {}
    if d.code in (REDUNDANT, ALWAYS_FALSE):
        new = _remove_all(st.text, fmt, [d.span])
        if new is None:
            return []
        name = source_text(st.text, d.span)
        return [Step(new, _constraints_phrase([name], redundant=d.code == REDUNDANT), "remove", (name,),
                     d.code == REDUNDANT, (d.span,))]
    if d.code == DEAD:
        f = enc.feature_by_name(data.get("feature", ""))
        if f is None:
            return []
        extra = [enc.var_of_feature[f]]
        return (_removal_steps(st, path, correction_sets(an, extra, path, deadline=deadline))
                + _structural_steps(st, path, extra, deadline))
    if d.code == FALSE_OPT:
        f = enc.feature_by_name(data.get("feature", ""))
        p = enc.feature_by_name(data.get("parent") or "")
        if f is None or p is None:
            return []
        out = []
        if f.path == path and p.path == path:
            mm = make_mandatory(st.text, fmt, p, f)
            if mm is not None:
                out.append(Step(mm[0], mm[1], "mandatory"))
        v = enc.var_of_feature
        out += _removal_steps(st, path, correction_sets(an, [v[p], -v[f]], path, deadline=deadline))
        return out
    if d.code == VOID:
        return (_removal_steps(st, path, correction_sets(an, [], path, deadline=deadline))
                + _structural_steps(st, path, [], deadline))
    return []


# ------------------------------------------------------------------ checked offers

@dataclass
class Offer:
    steps: list[Step]
    state: State
    target: tuple
    new: Counter          # findings the fix adds (none when clean)
    fixed: Counter        # findings it removes (the target among them)

    @property
    def clean(self) -> bool:
        return not self.new

    @property
    def new_errors(self) -> bool:
        return any(self.state.severity.get(k) == Severity.ERROR for k in self.new)


class _Search:
    def __init__(self, checker: Checker, path: str):
        self.checker = checker
        self.path = path
        self._memo: dict[tuple, list[Offer]] = {}

    def offers(self, st: State, d: Diagnostic, depth: int = DEPTH, first: bool = False) -> list[Offer]:
        """Checked fixes of finding ``d`` of ``st``: the clean ones, else those that add no error
        (``first``: stop at the first clean one, in the order of preference)."""
        target = finding_key(d, st.text if d.path == self.path else None)
        memo = (_sha(st.text), target, depth, first)
        if memo in self._memo:
            return self._memo[memo]
        if st.derived:  # (its analysis is the previous text's: candidates need this text's own)
            full = self.checker.state(st.text)
            if full is None:
                return []
            st = full
        out: list[Offer] = []
        seen: set[str] = set()
        expected = st.keys - Counter([target])
        steps = candidate_steps(st, self.path, d, self.checker.deadline)[:MAX_OFFERS * 2]
        # the preferred first: a feature made mandatory (the products stay the same), then the
        # smallest change; else in the order of the explanation
        steps.sort(key=lambda x: (x.kind != "mandatory", max(1, len(x.constraints))))
        if st.keys[(VOID,)]:
            # a void model reports nothing else: what the model has without the constraints of
            # its conflict was hidden by it, not made by the fix (what the conflict's other
            # constraints do once one goes is the fix's, and is settled below)
            base = self._without_conflict(st)
            if base is not None:
                expected = expected | base.keys
        for step in steps:
            if self.checker.expired() or len(out) >= MAX_OFFERS:
                break
            o = self._settle(st, target, expected, [step], depth)
            if o is None:
                continue
            h = _sha(o.state.text)
            if h in seen:
                continue
            seen.add(h)
            out.append(o)
            if first and o.clean:
                break
        clean = [o for o in out if o.clean]
        out = clean or [o for o in out if not o.new_errors]
        out.sort(key=lambda o: (o.steps[0].kind != "mandatory", sum(max(1, len(s.constraints)) for s in o.steps)))
        self._memo[memo] = out
        return out

    def _without_conflict(self, st: State) -> Optional[State]:
        """The check of a void model's text without the constraints of its conflict (those the
        void-model diagnostic names), or None."""
        from ..analysis.fixes import removable
        void = next((x for x in st.diagnostics if x.code == VOID), None)
        if void is None:
            return None
        fmt = st.result.model.format
        spans = {r.span for r in void.related if r.path == self.path}
        cons = [e for e in st.analysis.encoding.elements if removable(e, self.path) and e.span in spans]
        if not cons:
            with st.analysis._lock:
                ex = st.analysis.analyzer.explain([], deadline=self.checker.deadline)
            cons = [e for e in (ex.elements if ex else []) if removable(e, self.path)]
        text = _remove_all(st.text, fmt, [e.span for e in cons]) if cons else None
        base = self.checker.state(text) if text is not None else None
        return base if base is not None and base.complete else None

    def _first(self, st0: State, step: Step) -> Optional[State]:
        """The check of one step's text."""
        if step.kind == "remove":
            return self.checker.removal_state(st0, step)
        return self.checker.state(step.text)

    def _settle(self, st0: State, target: tuple, expected: Counter, steps: list[Step],
                depth: int) -> Optional[Offer]:
        st = self._first(st0, steps[-1])
        before = st0.keys[target]  # (a constraint written twice: one of them goes)
        if st is None or not st.complete or st.keys[target] >= before:
            return None
        for _ in range(3):
            new = st.keys - expected
            if not new or depth <= 0:
                break
            # settle one new finding (a redundant constraint first: removing it keeps the products)
            order = {REDUNDANT: 0, DEAD: 1, FALSE_OPT: 2, ALWAYS_FALSE: 3, VOID: 4}
            news = [x for x in st.diagnostics if x.code in order and x.path == self.path
                    and finding_key(x, st.text) in new]
            if not news:
                break
            nd = min(news, key=lambda x: order[x.code])
            subs = [o for o in self.offers(st, nd, depth - 1, first=True) if o.clean]
            if not subs:
                break
            steps = steps + subs[0].steps
            st = subs[0].state
            if st.keys[target] >= before:
                return None
        new = st.keys - expected
        fixed = st0.keys - st.keys
        return Offer(steps, st, target, new, fixed)


# ------------------------------------------------------------------ titles and edits

def _join(phrases: list[str]) -> str:
    if len(phrases) == 1:
        return phrases[0]
    return ", ".join(phrases[:-1]) + " and " + phrases[-1]


def _names(keys: Iterable[tuple], code: str) -> list[str]:
    return sorted({k[1] for k in keys if k and k[0] == code and len(k) > 1})


def _some(names: list[str], most: int = 3) -> str:
    if len(names) <= most:
        return _join(names) if names else ""
    return ", ".join(names[:most]) + f" and {len(names) - most} more"


def _phrases(steps: list[Step]) -> list[str]:
    """What the steps do; removals one after the other are said at once."""
    out: list[str] = []
    run: list[Step] = []

    def flush():
        if run:
            names = [n for s in run for n in s.constraints]
            out.append(_constraints_phrase(names, redundant=all(s.redundant for s in run)))
            run.clear()
    for s in steps:
        if s.kind == "remove" and s.constraints:
            run.append(s)
        else:
            flush()
            out.append(s.phrase)
    flush()
    return out


def title_of(o: Offer) -> str:
    body = _join(_phrases(o.steps))
    effects = []
    code = o.target[0]
    if code == DEAD or _names(o.fixed, DEAD):
        dead = _names(o.fixed, DEAD)
        if dead:
            effects.append(f"makes {_some(dead)} not dead")
    if code == FALSE_OPT and o.steps[0].kind == "remove":
        effects.append(f"{o.target[1]} becomes really optional")
    if code == ALWAYS_FALSE:
        effects.append("it can never hold")
    if code == VOID or (VOID,) in o.fixed:
        effects.append("the model gets products")
    if o.new:
        effects.append("then " + _describe(o.new))
    t = body[0].upper() + body[1:]
    return t + (f" ({'; '.join(effects)})" if effects else "")


def _describe(keys: Counter) -> str:
    parts = []
    dead = _names(keys, DEAD)
    if dead:
        parts.append(f"{_some(dead)} {'is' if len(dead) == 1 else 'are'} dead")
    fo = _names(keys, FALSE_OPT)
    if fo:
        parts.append(f"{_some(fo)} {'is' if len(fo) == 1 else 'are'} false-optional")
    red = [k for k in keys if k[0] == REDUNDANT]
    if red:
        parts.append(f"{len(red)} constraint{'s are' if len(red) > 1 else ' is'} redundant")
    other = sum(n for k, n in keys.items() if k[0] not in (DEAD, FALSE_OPT, REDUNDANT))
    if other:
        parts.append(f"{other} other finding{'s' if other > 1 else ''}")
    return _join(parts)


def _line_offsets(idx: LineIndex, n: int, i: int) -> int:
    return idx.starts[i] if i < len(idx.starts) else n


def text_edits(path: str, old: str, new: str) -> tuple[TextEdit, ...]:
    """Edits turning ``old`` into ``new``: whole lines where lines differ, trimmed to the
    characters that differ (one edit per changed region, in order)."""
    from ..analysis.fixes import _lines
    a, b = _lines(old), _lines(new)
    lo = 0
    while lo < len(a) and lo < len(b) and a[lo] == b[lo]:
        lo += 1
    hi = 0
    while hi < len(a) - lo and hi < len(b) - lo and a[-1 - hi] == b[-1 - hi]:
        hi += 1
    idx = LineIndex(old)
    out = []
    sm = difflib.SequenceMatcher(None, a[lo:len(a) - hi], b[lo:len(b) - hi], autojunk=False)
    for tag, i1, i2, j1, j2 in sm.get_opcodes():
        if tag == "equal":
            continue
        s = _line_offsets(idx, len(old), lo + i1)
        e = _line_offsets(idx, len(old), lo + i2)
        seg, rep = old[s:e], "".join(b[lo + j1:lo + j2])
        p = 0
        while p < len(seg) and p < len(rep) and seg[p] == rep[p]:
            p += 1
        q = 0
        while q < len(seg) - p and q < len(rep) - p and seg[-1 - q] == rep[-1 - q]:
            q += 1
        a0, a1, ins = s + p, e - q, rep[p:len(rep) - q]
        if not ins and a1 > a0:
            a0, a1 = _slide(old, a0, a1, s)
        out.append(TextEdit(path, idx.span(a0, a1), ins))
    return tuple(out)


def _word_start(text: str, i: int) -> bool:
    return ((i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")) and i < len(text)
            and not text[i].isspace())


def _slide(text: str, a: int, b: int, lo: int) -> tuple[int, int]:
    """A deletion of ``text[a:b]`` moved to the leftmost equivalent place (same result) where it
    starts a word: ``Payment => Shop, `` rather than ``Shop, Payment => ``."""
    best = (a, b) if _word_start(text, a) else None
    while a > lo and text[a - 1] == text[b - 1]:
        a, b = a - 1, b - 1
        if _word_start(text, a):
            best = (a, b)
    return best if best is not None else (a, b)


def apply_edits(text: str, edits: Iterable[TextEdit]) -> str:
    """``text`` with the (non-overlapping) edits applied."""
    idx = LineIndex(text)
    out = text
    for e in sorted(edits, key=lambda e: (e.span.start, e.span.end), reverse=True):
        a, b = idx.offset(e.span.start), idx.offset(e.span.end)
        out = out[:a] + e.new_text + out[b:]
    return out


def _fix(path: str, st0: State, o: Offer, preferred: bool) -> Fix:
    return Fix(title_of(o), text_edits(path, st0.text, o.state.text), preferred=preferred)


# ------------------------------------------------------------------ the entry points

def _guarded(search: "_Search", st: State, d: Diagnostic, first: bool = False) -> list[Offer]:
    """``search.offers``; a failure (a bug) costs that finding its fixes, not the others' (a
    MemoryError is the caller's budget and goes up)."""
    try:
        return search.offers(st, d, first=first)
    except MemoryError:
        raise
    except Exception:  # noqa: BLE001
        import logging
        logging.getLogger("tvl_lsp.fixes").exception("quick fixes of %s failed", d.code)
        return []


@dataclass
class FixReport:
    fixes: dict = field(default_factory=dict)    # finding key -> [Fix] (checked; [] = none found)
    unreached: list = field(default_factory=list)  # finding keys the budget did not reach
    complete: bool = True                          # every finding was reached
    checks: int = 0
    seconds: float = 0.0


_CACHE: "OrderedDict[tuple, FixReport]" = OrderedDict()
_LOCK = threading.Lock()
CACHE_SIZE = 16


def fixes_for(path: str, text: str, read_file: Optional[ReadFile] = None, keys: Optional[Iterable[tuple]] = None,
              budget: Optional[float] = 20.0) -> FixReport:
    """Checked fixes of the model's findings (see the module docstring)."""
    from .workspace import norm
    path = norm(path)
    t0 = time.monotonic()
    wanted = None if keys is None else {tuple(k) for k in keys}
    ck = (path, _sha(text), None if wanted is None else tuple(sorted(map(repr, wanted))))
    with _LOCK:
        hit = _CACHE.get(ck)
        if hit is None and wanted is not None:
            # a report on every finding of this text answers a request for some of them
            whole = _CACHE.get((path, ck[1], None))
            if whole is not None and whole.complete:
                hit = whole
        if hit is not None:
            return hit
    checker = Checker(path, read_file, None if budget is None else t0 + budget)
    report = FixReport()
    st0 = checker.state(text, shared=True)
    if st0 is None or st0.result.model.format not in FORMATS or not st0.complete:
        report.unreached = [] if st0 is None else [finding_key(d, text) for d in st0.findings()]
        report.complete = st0 is not None and st0.result.model.format not in FORMATS
        return report
    search = _Search(checker, path)
    todo = [d for d in st0.findings() if d.path == path]
    todo.sort(key=lambda d: ANOMALY_CODES.index(d.code))
    for d in todo:
        k = finding_key(d, text)
        if wanted is not None and k not in wanted:
            continue
        if checker.expired():
            report.unreached.append(k)
            continue
        offers = _guarded(search, st0, d)
        first_clean = next((i for i, o in enumerate(offers) if o.clean), None)
        report.fixes[k] = [_fix(path, st0, o, i == first_clean) for i, o in enumerate(offers)]
    report.checks = checker.checks
    report.seconds = time.monotonic() - t0
    report.complete = not report.unreached
    if not report.unreached:
        with _LOCK:
            _CACHE[ck] = report
            while len(_CACHE) > CACHE_SIZE:
                _CACHE.popitem(last=False)
    return report


@dataclass
class FixRun:
    text: str                                          # the text with every fix applied
    applied: list = field(default_factory=list)        # (finding key, title) in the order applied
    unfixed: list = field(default_factory=list)        # findings no fix was found for (of the new text)
    left: list = field(default_factory=list)           # findings not reached (the budget ran out)
    unreached: bool = False                            # the budget ran out first
    checks: int = 0


def fix_file(path: str, text: str, read_file: Optional[ReadFile] = None, codes: Optional[Iterable[str]] = None,
             budget: Optional[float] = 60.0) -> FixRun:
    """Fix every finding (of ``codes``), one after the other, each fix checked on the text the
    previous ones left; errors first.  The result adds no finding to the text's, and each
    applied fix removed its own."""
    from .workspace import norm
    path = norm(path)
    codes = set(ANOMALY_CODES if codes is None else codes) & set(ANOMALY_CODES)
    checker = Checker(path, read_file, None if budget is None else time.monotonic() + budget)
    st = checker.state(text, shared=True)
    run = FixRun(text)
    if st is None or st.result.model.format not in FORMATS:
        run.unreached = st is None
        return run
    search = _Search(checker, path)
    given_up: set = set()
    batched = False
    while True:
        if not st.complete:
            run.unreached = True
            break
        if not batched and DEAD in codes and not st.keys[(VOID,)]:
            batched = True
            st = _revive_all(checker, st, path, run)
        todo = [d for d in st.findings(codes) if d.path == path and finding_key(d, st.text) not in given_up]
        if not todo:
            break
        todo.sort(key=lambda d: ANOMALY_CODES.index(d.code))
        d = todo[0]
        k = finding_key(d, st.text)
        if checker.expired():
            run.unreached = True
            break
        offers = [o for o in _guarded(search, st, d, first=True) if not o.new_errors]
        if not offers:
            given_up.add(k)
            continue
        o = offers[0]
        run.applied.append((k, title_of(o)))
        st = o.state
    run.text = st.text
    run.unfixed = [d for d in st.findings(codes) if d.path == path and finding_key(d, st.text) in given_up]
    run.left = [d for d in st.findings(codes) if d.path == path and finding_key(d, st.text) not in given_up]
    run.checks = checker.checks
    return run


BATCH_MIN = 4  # dead features from which fix_file revives them all at once


def _revive_all(checker: Checker, st: State, path: str, run: FixRun) -> State:
    """Every dead feature's first fix (a set of constraints to remove: SAT questions on the
    model's selector solver, no re-check each) applied at once and checked once.  Sound: in a
    model that has products, removing constraints only adds products, so every feature revived
    alone stays revived, and no dead or false-optional feature, redundant or always-false
    constraint can appear; the check confirms it (else nothing is applied here and the findings
    are fixed one by one)."""
    from ..analysis.fixes import correction_sets, source_text
    dead = [d for d in st.findings((DEAD,)) if d.path == path]
    if len(dead) < BATCH_MIN or st.derived or st.result.model.format not in FORMATS:
        return st
    enc = st.analysis.encoding
    chosen: dict[int, tuple[list, list[str]]] = {}   # id(first element) -> (elements, features)
    for d in dead:
        if checker.expired():
            return st
        name = (d.data or {}).get("feature", "")
        f = enc.feature_by_name(name)
        if f is None:
            continue
        sets = correction_sets(st.analysis, [enc.var_of_feature[f]], path, limit=1, deadline=checker.deadline)
        if not sets:
            continue
        elems = sets[0]
        key = tuple(sorted(id(e) for e in elems))
        chosen.setdefault(key, (elems, []))[1].append(name)
    if not chosen:
        return st
    removed = {id(e): e for elems, _ in chosen.values() for e in elems}
    spans = [e.span for e in removed.values()]
    new = _remove_all(st.text, st.result.model.format, spans)
    if new is None:
        return st
    names = [source_text(st.text, sp) for sp in spans]
    after = checker.removal_state(st, Step(new, _constraints_phrase(names), "remove", tuple(names), False,
                                           tuple(spans)))
    if after is None or not after.complete or (after.keys - st.keys) or any(
            after.keys[(DEAD, n)] for _, feats in chosen.values() for n in feats):
        return st
    for elems, feats in chosen.values():
        phrase = _constraints_phrase([source_text(st.text, e.span) for e in elems])
        run.applied.append(((DEAD, feats[0]), f"{phrase[0].upper()}{phrase[1:]} (makes {_some(sorted(feats))} not dead)"))
    return after


def compute_fixes(path: str, sources: dict, keys: Optional[list], budget: float) -> FixReport:
    """:func:`fixes_for` on the texts ``sources`` (path -> text: the document and the unsaved
    files it reads), for a worker process."""
    from .workspace import default_read_file, norm

    def read(p: str) -> Optional[str]:
        t = sources.get(p)
        if t is None:
            t = sources.get(norm(p))
        return t if t is not None else default_read_file(p)
    text = sources.get(path)
    if text is None:
        text = sources.get(norm(path))
    if text is None:
        return FixReport()
    return fixes_for(path, text, read, [tuple(k) for k in keys] if keys is not None else None, budget)
