"""Substitutions only Python launch files write, evaluated by the ROS 2 walker (registered in
:data:`tvl_lsp.launch.ros2.substitutions.EXTRA`):

- ``path-join``: ``PathJoinSubstitution([a, b, ...])`` -- ``os.path.join`` of the values;
- ``text``: ``TextSubstitution(text=...)``;
- ``lc-equals`` / ``lc-not-equals``: the ``LaunchConfigurationEquals`` / ``NotEquals``
  conditions -- string equality with the configuration's value (a missing one equals only a
  missing expected value);
- ``py-unknown``: a value the interpreter could not know.  Where it matters (``hard``: a node's
  name, a condition, an included file ...) the concrete load declines there and the symbolic
  analysis notes it; either way its value is unknown (never a guess).
"""

from __future__ import annotations

import itertools
import os

from ...base.formula import FALSE, conj, neg
from ..ros2 import substitutions as SUB
from ..ros2.values import MAX_CASES, OPAQUE, merge, opaque, present


def _path_join(w, sub, v, sc, c, el):
    lists = [w.ev_parts(a, v, sc, c, el) for a in sub.args]
    if not lists:
        return [(c, "")]
    out = []
    n = 1
    for lst in lists:
        n *= max(len(lst), 1)
    if n > MAX_CASES * 4:
        return w.collapse([(c, OPAQUE)], el, v.span() or el.span)
    for combo in itertools.product(*lists):
        cc = conj([c] + [x for x, _ in combo])
        if cc == FALSE:
            continue
        out.append((cc, os.path.join(*[s for _, s in combo])))
    return merge(out)


def _text(w, sub, v, sc, c, el):
    return [(c, sub.args[0][0].text if sub.args and sub.args[0] else "")]


def _lc_equals(w, sub, v, sc, c, el):
    neq = sub.name == "lc-not-equals"
    names = w.ev_parts(sub.args[0], v, sc, c, el)
    out = []
    for cn, n in names:
        expected = w.ev_parts(sub.args[1], v, sc, cn, el) if len(sub.args) > 1 else [(cn, None)]
        for ce, x in expected:
            if opaque(n) or (x is not None and opaque(x)):
                out.append((ce, OPAQUE))
                continue
            vals = sc.configs.get(n, [])
            for cv, val in vals:
                cc = conj([ce, cv])
                if cc == FALSE:
                    continue
                if opaque(val):
                    out.append((cc, OPAQUE))
                    continue
                r = (val == x) if x is not None else False
                out.append((cc, "true" if r != neq else "false"))
            missing = conj([ce, neg(present(vals))])
            if missing != FALSE and sc.opaque != FALSE:
                out.append((conj([missing, sc.opaque]), OPAQUE))
                missing = conj([missing, neg(sc.opaque)])
            if missing != FALSE:
                r = x is None
                out.append((missing, "true" if r != neq else "false"))
    return merge(out)


def _py_unknown(w, sub, v, sc, c, el):
    reason = sub.args[0][0].text if sub.args and sub.args[0] else "a value tvl-lsp cannot know"
    if getattr(sub, "hard", True):
        span = v.sub_span(sub) if v is not None else None
        w.decline(el.path, span or el.tag_span or el.span, f"tvl-lsp cannot know this value: {reason}", c)
    return [(c, OPAQUE)]


def _py_perform(w, sub, v, sc, c, el):
    """An instance of a Substitution subclass of the file: its perform(context), interpreted with
    the arguments' values (once per combination of the values it reads)."""
    from .actions import MAX_WORLDS, World
    from .values import Decline, Func, LaunchCtx, PyError, Unknown
    inst, unit = getattr(sub, "instance", None), getattr(sub, "unit", None)
    fn, _ = inst.cls.lookup("perform") if inst is not None else (None, None)
    if unit is None or not isinstance(fn, Func):
        return [(c, OPAQUE)]
    out = []
    worlds = [()]
    done = 0
    while worlds:
        prefix = worlds.pop(0)
        done += 1
        if done > MAX_WORLDS:
            return merge(out + [(c, OPAQUE)])
        world = World(w, sc, el, c, prefix)
        try:
            r = unit.call_opaque(world, fn, [inst, LaunchCtx()], {}, None)
        except (Decline, PyError):
            r = None
        worlds.extend(world.pending)
        if world.guard == FALSE:
            continue
        if isinstance(r, str) and not isinstance(r, Unknown):
            out.append((world.guard, str(r)))
        else:
            out.append((world.guard, OPAQUE))
    return merge(out)


SUB.EXTRA.update({"path-join": _path_join, "text": _text, "lc-equals": _lc_equals, "lc-not-equals": _lc_equals,
                  "py-unknown": _py_unknown, "py-perform": _py_perform})
