"""The actions only Python launch files have, each with the ``walk`` the ROS 2 walker calls
(``Walker.action`` hands an action it does not know to its ``walk`` method):

- :class:`OpaqueA` -- ``OpaqueFunction``: its function is interpreted with the launch context
  of the walk, ``context.launch_configurations[...]`` and ``LaunchConfiguration(...).perform``
  giving the walker's values.  Where a value has several cases (the symbolic walk), the
  function runs once per combination of the cases it reads ("worlds", at most
  :data:`MAX_WORLDS`), each under its condition; the actions it returns are walked as if
  written there.
- :class:`EventA` -- ``RegisterEventHandler(OnProcessStart/OnProcessExit/...)``: its actions
  start only when a process does something at run time.  They are analysed (their nodes carry
  the event), but listed apart from what the launch starts itself.
- :class:`UnknownA` -- an entity tvl-lsp cannot know: the concrete load declines there, the
  symbolic analysis notes it and treats every launch configuration as unknown after it.
- :class:`UnsetA` -- ``UnsetLaunchConfiguration``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ...base.diagnostics import Severity, register
from ...base.formula import FALSE, conj, disj, neg
from ..model import Attr, Element
from ..ros2 import actions as A
from ..ros2.frontend import substitutions_of
from .classes import BoundFunc
from .values import Decline, Func, LaunchCtx, PyError, Unknown

MAX_WORLDS = 32
PYTHON_ERROR = register("python-error", Severity.ERROR, "Python code of a launch file raises an exception when "
                        "ros2 launch runs it.", "launch")


def declined(w, el: Element, sc, cond, where, reason: str) -> None:
    """Decline at ``where`` (path, span) or, failing that, at the element."""
    if cond == FALSE:
        return
    path, span = el.path, el.tag_span or el.span
    if where is not None and where[0] == el.path:
        span = where[1]
    w.decline(path, span, reason, cond)
    if not w.concrete:
        sc.opaque = disj([sc.opaque, cond])


@dataclass
class UnknownA(A.Action):
    reason: str = ""

    def walk(self, w, el: Element, sc, cond, emap) -> None:
        declined(w, el, sc, cond, None, f"tvl-lsp cannot know this action: {self.reason}")


@dataclass
class UnsetA(A.Action):
    name: Any = None

    def walk(self, w, el: Element, sc, cond, emap) -> None:
        for cn, n in w.ev(self.name, sc, cond, el):
            nc = neg(cn)
            old = sc.configs.get(n)
            if old is None:
                continue
            sc.configs[n] = [(conj([c, nc]), v) for c, v in old if conj([c, nc]) != FALSE]
            if not sc.configs[n]:
                del sc.configs[n]


@dataclass
class EventA(A.Action):
    event: str = ""
    target: str = ""
    actions: list = field(default_factory=list)
    reason: str = ""

    @property
    def label(self) -> str:
        return f"{self.event}({self.target})" if self.target else self.event

    def walk(self, w, el: Element, sc, cond, emap) -> None:
        events = w.__dict__.setdefault("py_events", [])
        rec = {"event": self.event, "target": self.target, "source": el.path, "line": el.span.start.line + 1,
               "condition": cond, "nodes": [], "not_analysed": self.reason or None}
        events.append(rec)
        if self.reason and not w.concrete:
            w.note("launch-not-analysable", f"{self.label}: {self.reason}", el.path, el.tag_span or el.span)
        if not self.actions:
            return
        if w.concrete:
            # the oracle never fires events: their actions are walked after the launch, apart
            w.__dict__.setdefault("py_deferred", []).append((self, el, sc.copy(), cond, emap, rec))
            hooks = w.__dict__.setdefault("post_walk", [])
            if run_deferred_events not in hooks:
                hooks.append(run_deferred_events)
            return
        run_event(w, self, sc.copy(), cond, emap, rec)


def run_event(w, ev: EventA, sc, cond, emap, rec) -> None:
    saved = getattr(w, "event_label", None)
    w.event_label = ev.label
    before = len(w.nodes)
    try:
        w.run(ev.actions, sc, cond, emap)
    finally:
        w.event_label = saved
        rec["nodes"].extend(w.nodes[before:])


def run_deferred_events(w) -> None:
    """The concrete load: analyse the event handlers' actions after the launch (their errors are
    not the launch's: the events may never happen)."""
    from ..ros2.values import Stop
    pending = w.__dict__.pop("py_deferred", [])
    for ev, el, sc, cond, emap, rec in pending:
        err, nfacts = w.error, len(w.facts)
        try:
            run_event(w, ev, sc, cond, emap, rec)
        except Stop:
            rec["not_analysed"] = w.error.message if w.error is not None else "stopped"
        finally:
            w.error = err
            del w.facts[nfacts:]


@dataclass
class OpaqueA(A.Action):
    function: Any = None
    args: Any = None
    kwargs: Any = None
    where: Any = None
    unit: Any = None     # the PyUnit that made it (its host and converter)

    def walk(self, w, el: Element, sc, cond, emap) -> None:
        fn = self.function
        bound = []
        if isinstance(fn, BoundFunc) and isinstance(fn.func, Func):
            # OpaqueFunction(function=obj.method): launch calls it with the context after self
            bound = [fn.self_value]
            fn = fn.func
        if not isinstance(fn, Func):
            why = fn.reason if isinstance(fn, Unknown) else "its function is not a function of the file"
            declined(w, el, sc, cond, None, f"tvl-lsp cannot interpret this OpaqueFunction: {why}")
            return
        args = self.args
        kwargs = self.kwargs
        if isinstance(args, Unknown) or isinstance(kwargs, Unknown) or not isinstance(args, (list, tuple)) or \
                not isinstance(kwargs, dict):
            declined(w, el, sc, cond, None, "the arguments of this OpaqueFunction are unknown")
            return
        unit = self.unit
        worlds: list[tuple] = [()]
        done = 0
        saved = _state(fn, bound)
        while worlds:
            prefix = worlds.pop(0)
            if done:
                _restore(saved)   # each case replays the method from the same object
            done += 1
            if done > MAX_WORLDS:
                declined(w, el, sc, cond, None, f"the OpaqueFunction {fn.name}() reads arguments with more than "
                         f"{MAX_WORLDS} combinations of values: not analysed further")
                return
            world = World(w, sc, el, cond, prefix)
            try:
                result = unit.call_opaque(world, fn, bound + [LaunchCtx()] + list(args), dict(kwargs), self.where)
            except Decline as d:
                declined(w, el, sc, world.guard, d.where, f"in the OpaqueFunction {fn.name}(): {d.reason}")
                worlds.extend(world.pending)
                continue
            except PyError as e:
                if e.sure:
                    # the function raises, launch fails there
                    where = e.where if e.where is not None and e.where[0] == el.path else (el.path, el.tag_span)
                    w.fact(PYTHON_ERROR, f"the OpaqueFunction {fn.name}() raises {e.kind}: {e.message} (ros2 launch "
                           "fails here)", el.path, where[1], world.guard, launch=(e.kind, e.message))
                else:
                    declined(w, el, sc, world.guard, e.where, f"in the OpaqueFunction {fn.name}(): Python would "
                             f"raise {e.kind}: {e.message}")
                worlds.extend(world.pending)
                continue
            worlds.extend(world.pending)
            if world.guard == FALSE:
                continue
            if result is None:
                continue
            if isinstance(result, Unknown) or not isinstance(result, (list, tuple)):
                why = result.reason if isinstance(result, Unknown) else f"it returns a {type(result).__name__}"
                declined(w, el, sc, world.guard, None, f"the OpaqueFunction {fn.name}() returns actions tvl-lsp "
                         f"cannot know: {why}")
                continue
            acts = unit.convert_dynamic(result, self.entity, el, emap, w)
            w.run(acts, sc, world.guard, emap)


def _copy1(d: dict) -> dict:
    return {k: (type(v)(v) if type(v) in (list, dict, set) else v) for k, v in d.items()}


def _state(fn: Func, bound: list) -> list:
    """What an OpaqueFunction's replays must each start from: the globals of its module and the
    attributes of a bound method's object (lists, dicts and sets copied one level)."""
    out = []
    g = getattr(getattr(fn, "module", None), "globals", None)
    if isinstance(g, dict):
        out.append((g, _copy1(g)))
    attrs = getattr(bound[0], "attrs", None) if bound else None
    if isinstance(attrs, dict):
        out.append((attrs, _copy1(attrs)))
    return out


def _restore(saved: list) -> None:
    for d, snap in saved:
        d.clear()
        d.update(_copy1(snap))


class World:
    """One run of an OpaqueFunction: the choices made so far for the values it performs."""

    def __init__(self, w, sc, el, cond, prefix: tuple):
        self.w = w
        self.sc = sc
        self.el = el
        self.guard = cond
        self.prefix = prefix
        self.step = 0
        self.taken: list[int] = []
        self.pending: list[tuple] = []

    def choose(self, cases: list):
        """The case of this world among ``cases`` [(condition, value)], each condition already
        within the world's guard (the other cases become new worlds, replayed from the start)."""
        cases = [(c, v) for c, v in cases if c != FALSE]
        if not cases:
            self.guard = FALSE
            return None
        if self.step < len(self.prefix):
            i = self.prefix[self.step]
        else:
            i = 0
            for j in range(1, len(cases)):
                self.pending.append(tuple(self.taken) + (j,))
        self.taken.append(i)
        self.step += 1
        c, v = cases[min(i, len(cases) - 1)]
        self.guard = c
        return v


def make_element(e, parent: Element, depth: int) -> Element:
    attrs = {k: Attr(k, a.value if isinstance(a.value, str) else str(a.value), a.name_span, a.value_span)
             for k, a in e.attrs.items()}
    return Element(e.tag, e.span, attrs, e.path, FALSE, parent, [], substitutions_of(e), e.tag_span, e.text, depth)


def ensure_elements(e, parent: Element, emap: dict, sink: list) -> None:
    el = emap.get(id(e))
    if el is None:
        el = make_element(e, parent, parent.include_depth)
        emap[id(e)] = el
        sink.append(el)
        parent.children.append(el)
    for k in e.sub_entities():
        ensure_elements(k, el, emap, sink)


__all__ = ["OpaqueA", "EventA", "UnknownA", "UnsetA", "World", "ensure_elements", "run_deferred_events"]
