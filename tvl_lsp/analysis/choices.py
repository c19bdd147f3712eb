"""ROS 2 ``<arg>`` with ``<choice>`` values, paired with the model.

An arg of a generic ROS 2 launch file that lists its values::

    <arg name="Drive" default="Diff">
      <choice value="Diff"/>
      <choice value="Omni"/>
    </arg>

pairs with the part of the model that chooses one value among several:

1. an **alternative group**: the feature ``Drive`` with ``group oneOf { Diff, Omni }`` (or a
   ``[1..1]`` group): the arg's value is the name of the selected child.  The children then need
   no ``<arg>`` of their own (no ``missing-arg`` for them); a configuration passes
   ``Drive:=Omni``;
2. else an **enumerated attribute** named like the arg (its long name ``Robot.drive`` or a
   unique short name ``drive``) of type ``enum ... in {Diff, Omni}``: the arg's value is the
   attribute's value (when a constraint reads the attribute, the model's constraints apply;
   otherwise any value goes with any product).

Checked both ways (``choice-mismatch``): a ``<choice>`` naming no alternative / enumeration
value, and an alternative / value without a ``<choice>`` (a configuration selecting it would make
ros2 launch stop with *Argument ... provided value ... is not valid*).  An arg with ``<choice>``
that pairs with nothing is reported too (its values are then analysed as free choices).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from ..base import formula as fm
from ..base.diagnostics import Diagnostic, Related, Severity, register

CHOICE_MISMATCH = register(
    "choice-mismatch", Severity.WARNING,
    "An <arg> with <choice> values does not match the alternatives or enumeration of its model (ROS 2).", "cross")


@dataclass
class ChoicePairing:
    arg: str
    kind: Optional[str]                       # "group" | "enum" | None (pairs with nothing)
    target: object = None                     # the Feature (group) or Attribute (enum)
    selectors: Optional[list[tuple[fm.Formula, str]]] = None   # formula -> value (None: free choices)
    extra: list[str] = field(default_factory=list)     # <choice> values naming nothing in the model
    missing: list[str] = field(default_factory=list)   # model alternatives / values with no <choice>
    by_value: dict = field(default_factory=dict)       # value -> feature name (group kind)


def value_literal(encoding, name: str) -> Optional[int]:
    """The literal of ``ATTR=VALUE`` (an attribute's long or unique short name, one value of
    its finite domain), when the attribute is encoded (a constraint reads it); else None."""
    if "=" not in name:
        return None
    lhs, _, value = name.partition("=")
    cands = [a for f in encoding.features for a in f.attributes if a.long_name == lhs]
    if not cands:
        cands = [a for f in encoding.features for a in f.attributes if a.name == lhs]
    if len(cands) != 1:
        return None
    term = encoding._attr_terms.get(id(cands[0]))
    if not term or term[0] != "map":
        return None
    for k, lit in term[1].items():
        if str(k) == value:
            return lit
    return None


def _alternatives(f) -> Optional[list]:
    g = getattr(f, "group", None)
    if g is None:
        return None
    if g.kind == "oneOf" or (g.kind == "card" and g.hi == 1):
        return [c.feature for c in g.children]
    return None


def _enum_values(a) -> Optional[list[str]]:
    evs = a.enum_values or (a.type_decl.enum_values if getattr(a, "type_decl", None) else [])
    if a.type == "enum" or (a.type_decl is not None and getattr(a.type_decl, "base", None) == "enum"):
        return [ev.name for ev in evs]
    return None


def pair_choices(choices: dict[str, list[str]], encoding) -> dict[str, ChoicePairing]:
    """How each ``<choice>`` arg pairs with the model (``encoding``: its Encoding)."""
    out: dict[str, ChoicePairing] = {}
    for name, values in choices.items():
        p = ChoicePairing(name, None)
        f = encoding.feature_by_name(name)
        alts = _alternatives(f) if f is not None else None
        if alts is not None:
            names = [c.name for c in alts]
            p.kind, p.target = "group", f
            p.selectors = [(fm.Var(encoding.name_of(c)), c.name) for c in alts if c.name in values]
            p.by_value = {c.name: encoding.name_of(c) for c in alts}
            p.extra = [v for v in values if v not in names]
            p.missing = [n for n in names if n not in values]
        else:
            attrs = [a for ft in encoding.features for a in ft.attributes if a.long_name == name]
            if not attrs:
                attrs = [a for ft in encoding.features for a in ft.attributes if a.name == name]
            attrs = [a for a in attrs if _enum_values(a) is not None]
            if len(attrs) == 1:
                a = attrs[0]
                evs = _enum_values(a)
                p.kind, p.target = "enum", a
                lits = {v: value_literal(encoding, f"{a.long_name}={v}") for v in values if v in evs}
                if lits and all(x is not None for x in lits.values()):
                    p.selectors = [(fm.Var(f"{a.long_name}={v}"), v) for v in values if v in evs]
                p.extra = [v for v in values if v not in evs]
                p.missing = [v for v in evs if v not in values]
        out[name] = p
    return out


def choice_diagnostics(launch, pairings: dict[str, ChoicePairing], model_name: str) -> list[Diagnostic]:
    out = []
    for name, p in pairings.items():
        values, el = launch.choices.get(name, ([], None))
        if el is None:
            continue
        arg_span = el.attrs["name"].value_span if "name" in el.attrs else el.span
        if p.kind is None:
            f_hint = ""
            out.append(Diagnostic(
                CHOICE_MISMATCH, Severity.WARNING, launch.path, arg_span,
                f"arg `{name}` has <choice> values but {model_name} has no alternative group (a feature "
                f"`{name}` with `group oneOf`) nor enumerated attribute `{name}` to pair it with: its values "
                f"are analysed as free choices{f_hint}", data={"arg": name}))
            continue
        where = (f"the alternatives of feature `{p.target.name}`" if p.kind == "group"
                 else f"the values of attribute `{p.target.long_name}`")
        rel = [Related(p.target.path, p.target.name_span, f"{where} are declared here")]
        for v in p.extra:
            span = _choice_span(el, v) or arg_span
            out.append(Diagnostic(CHOICE_MISMATCH, Severity.WARNING, launch.path, span,
                                  f"<choice value=\"{v}\"> of arg `{name}` is none of {where} in {model_name}",
                                  related=rel, data={"arg": name, "value": v}))
        if p.missing:
            miss = ", ".join(f"`{m}`" for m in p.missing)
            out.append(Diagnostic(
                CHOICE_MISMATCH, Severity.WARNING, launch.path, arg_span,
                f"arg `{name}` has no <choice> for {miss} of {where} in {model_name}: the products that select "
                f"it have no value for the arg (and {name}:={p.missing[0]} makes ros2 launch stop: Argument "
                f"\"{name}\" provided value \"{p.missing[0]}\" is not valid)",
                related=rel, data={"arg": name, "missing": list(p.missing)}))
    return out


def _choice_span(el, value: str):
    for c in el.children:
        if c.tag == "choice" and "value" in c.attrs and c.attrs["value"].value == value:
            return c.attrs["value"].value_span
    return None


def covered_features(pairings: dict[str, ChoicePairing]) -> set[int]:
    """ids of the features a group-paired choice arg stands for (its alternatives)."""
    out: set[int] = set()
    for p in pairings.values():
        if p.kind == "group":
            out |= {id(c) for c in (_alternatives(p.target) or [])}
    return out
