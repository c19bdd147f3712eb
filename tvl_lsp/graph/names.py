"""ROS 1 graph-resource names, resolved as a node resolves them (``rosgraph.names`` / roscpp).

A node named ``/ns/talker`` resolves

- a global name ``/x`` to ``/x``;
- a relative name ``x`` in its namespace: ``/ns/x``;
- a private name ``~x`` under its own name: ``/ns/talker/x``.

Remappings (``from:=to``, what roslaunch passes for each ``<remap>`` in the node's scope) are
resolved the same way, both sides, in the node's namespace; a name is remapped when its
resolved form equals a resolved ``from`` (one step, no chains), the last such remapping
winning — as roscpp and rospy build their remapping tables.
"""

from __future__ import annotations

from typing import Iterable, Optional, Sequence, TypeVar

from ..base.formula import FALSE, TRUE, Formula, conj, disj, neg

T = TypeVar("T")


def canonical(name: str) -> str:
    """Collapse ``//`` and drop a trailing ``/`` (``rosgraph.names.canonicalize_name``)."""
    if not name or name == "/":
        return name
    lead = "/" if name[0] == "/" else ""
    return lead + "/".join(x for x in name.split("/") if x)


def namespace_of(full_name: str) -> str:
    """The namespace of a global name, with a trailing ``/``: ``/a/b`` -> ``/a/``, ``/b`` -> ``/``."""
    full_name = canonical(full_name)
    if not full_name or full_name == "/":
        return "/"
    i = full_name.rfind("/")
    return full_name[: i + 1] if i >= 0 else "/"


def resolve(name: str, node: str) -> str:
    """``name`` as the node called ``node`` (a global name, ``/ns/talker``) resolves it."""
    node = canonical(node if node.startswith("/") else "/" + node)
    if not name:
        return namespace_of(node)
    name = canonical(name)
    if name.startswith("/"):
        return name
    if name.startswith("~"):
        return canonical(node + "/" + name[1:])
    return canonical(namespace_of(node) + name)


def kind(name: str) -> str:
    """``global``, ``private`` or ``relative``."""
    return "global" if name.startswith("/") else "private" if name.startswith("~") else "relative"


def remap_table(remaps: Iterable[tuple[str, str]], node: str) -> dict[str, str]:
    """The node's resolved remapping table from ``(from, to)`` pairs in roslaunch's order."""
    out: dict[str, str] = {}
    for f, t in remaps:
        if not f or not t or f.startswith("__"):
            continue  # __name, __ns, __log ...: special keys, not remappings of names
        out[resolve(f, node)] = resolve(t, node)
    return out


def resolve_remapped(name: str, node: str, remaps: Iterable[tuple[str, str]]) -> str:
    """One product: the name after the node's remappings."""
    r = resolve(name, node)
    return remap_table(remaps, node).get(r, r)


def remap_cases(name: str, node: str, remaps: Sequence[tuple[str, str, Formula, T]]
                ) -> list[tuple[Formula, str, Optional[T]]]:
    """All products at once: ``remaps`` are ``(from, to, condition, origin)`` in roslaunch's
    order, each applying when its condition holds.  Returns ``(condition, resolved name,
    origin of the remap that produced it or None)`` cases that partition the products (the
    conditions are relative: conjoin the node's own)."""
    r = resolve(name, node)
    out: list[tuple[Formula, str, Optional[T]]] = []
    later: Formula = FALSE  # a later remapping of the same name applies
    for f, t, c, origin in reversed(list(remaps)):
        if not f or not t or f.startswith("__") or resolve(f, node) != r:
            continue
        eff = conj([c, neg(later)])
        if eff != FALSE:
            out.append((eff, resolve(t, node), origin))
        later = disj([later, c])
        if later == TRUE:
            break
    rest = neg(later)
    if rest != FALSE:
        out.append((rest, r, None))
    out.reverse()
    return out
