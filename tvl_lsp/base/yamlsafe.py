"""YAML within bounds: alias expansion and nesting are limited before anything is constructed.

PyYAML's safe loaders share the object an alias names, so a 400-byte "billion laughs"
document loads quickly, but whatever walks the result afterwards (a parameter tree, a launch
file's actions, node hints) visits every expanded value: hundreds of millions of them.  These
functions compose the document first, measure its *expanded* size (aliases counted as often as
they are used, each node measured once) and depth, and refuse it with :class:`YamlTooBig`
(a ``yaml.YAMLError``, so callers that report YAML errors report it too) beyond
``MAX_NODES`` values or ``MAX_DEPTH`` levels.
"""

from __future__ import annotations

from typing import Any, Optional

import yaml

MAX_NODES = 200_000
MAX_DEPTH = 200


class YamlTooBig(yaml.YAMLError):
    """A YAML document beyond the bounds (an alias bomb, or nesting too deep)."""


def check_node(node: Optional[yaml.Node]) -> None:
    """Raise :class:`YamlTooBig` when ``node`` expands to more than ``MAX_NODES`` values or
    nests deeper than ``MAX_DEPTH`` (an alias that contains itself counts as too deep)."""
    if node is None:
        return
    size: dict[int, int] = {}
    depth: dict[int, int] = {}
    open_: set[int] = set()
    stack: list[tuple[yaml.Node, bool]] = [(node, False)]
    while stack:
        n, done = stack.pop()
        k = id(n)
        if done:
            open_.discard(k)
            kids = _children(n)
            s = 1 + sum(size[id(c)] for c in kids)
            d = 1 + max((depth[id(c)] for c in kids), default=0)
            if s > MAX_NODES:
                raise YamlTooBig(f"the YAML expands to more than {MAX_NODES:,} values (aliases counted as "
                                 "often as they are used): not analysed")
            if d > MAX_DEPTH:
                raise YamlTooBig(f"the YAML is nested more than {MAX_DEPTH} levels deep: not analysed")
            size[k], depth[k] = s, d
            continue
        if k in size:
            continue
        if k in open_:
            raise YamlTooBig("the YAML contains an alias to a node that contains it: not analysed")
        if len(open_) > MAX_DEPTH:
            raise YamlTooBig(f"the YAML is nested more than {MAX_DEPTH} levels deep: not analysed")
        open_.add(k)
        stack.append((n, True))
        for c in _children(n):
            if id(c) not in size:
                stack.append((c, False))


def _children(n: yaml.Node) -> list:
    if isinstance(n, yaml.SequenceNode):
        return list(n.value)
    if isinstance(n, yaml.MappingNode):
        return [x for kv in n.value for x in kv]
    return []


_BOUNDED: dict[type, type] = {}


def bounded_loader(base: type) -> type:
    """A subclass of the loader ``base`` that checks each document (:func:`check_node`)
    before constructing it."""
    cls = _BOUNDED.get(base)
    if cls is None:
        def get_single_data(self):
            node = self.get_single_node()
            if node is None:
                return None
            check_node(node)
            return self.construct_document(node)

        def get_data(self):
            if self.check_node():
                node = self.get_node()
                check_node(node)
                return self.construct_document(node)

        cls = type(f"Bounded{base.__name__}", (base,), {"get_single_data": get_single_data,
                                                        "get_data": get_data})
        _BOUNDED[base] = cls
    return cls


def load(text: str, Loader: type = yaml.SafeLoader) -> Any:
    """``yaml.load(text, Loader)`` within the bounds (``Loader`` must be a safe loader)."""
    try:
        return yaml.load(text, Loader=bounded_loader(Loader))  # noqa: S506 - safe loaders only
    except RecursionError:
        raise YamlTooBig("the YAML is nested too deeply: not analysed") from None


def safe_load(text: str) -> Any:
    """``yaml.safe_load(text)`` within the bounds."""
    return load(text, yaml.SafeLoader)


def compose(text: str, Loader: type = yaml.SafeLoader) -> Optional[yaml.Node]:
    """``yaml.compose(text, Loader)`` within the bounds."""
    try:
        node = yaml.compose(text, Loader=Loader)
    except RecursionError:
        raise YamlTooBig("the YAML is nested too deeply: not analysed") from None
    check_node(node)
    return node
