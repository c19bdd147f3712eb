"""The variability-aware computation graph: plain data, no LSP types.

Every element and link carries its *presence condition*: a formula over the launch file's
feature args (:mod:`tvl_lsp.base.formula`) that holds in exactly the products where the
element exists.  After a projection (:func:`tvl_lsp.graph.project`) a condition of ``None``
means "in every remaining product".

Ids are stable: computed from names on the graph of all products, kept by every projection,
so a user interface can keep its layout while decisions change.

- node ``node:/ns/name`` (``node:/ns/name#pkg/type`` when one name is used by nodes of several
  types in different products);
- topic ``topic:/name``, service ``service:/name``, action ``action:/name``, parameter ``param:/name``;
- link ``KIND:NODE-ID>RESOURCE-ID`` (``#type`` appended when the same node uses the same
  resource in the same way with two types).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from ..base.formula import Formula
from ..base.text import Span

LINK_KINDS = ("publish", "subscribe", "service", "client", "action_server", "action_client", "read", "write")
RESOURCE_OF_KIND = {"publish": "topic", "subscribe": "topic", "service": "service", "client": "service",
                    "action_server": "action", "action_client": "action", "read": "parameter", "write": "parameter"}


@dataclass(frozen=True)
class Location:
    """Where something is written: a file, a range, and what it is (for related locations)."""
    path: str
    span: Span
    label: str


@dataclass
class GraphNode:
    id: str
    name: str          # resolved global name, /ns/name
    package: str
    type: str
    namespace: str     # /ns/
    condition: Optional[Formula]
    hinted: bool = False
    note: Optional[str] = None
    locations: list[Location] = field(default_factory=list)  # the <node> tags
    hints: list[Location] = field(default_factory=list)      # the hint keys (pkg/type, /name)
    count: Optional[int] = None
    # each <node> tag with the condition under which it loads this node
    occurrences: list[tuple[Location, Formula]] = field(default_factory=list)
    # what it uses was read from its package's sources (tvl_lsp.graph.sources)
    extracted: bool = False

    @property
    def known(self) -> bool:
        """Whether the names it uses are known (from hints, or from its sources)."""
        return self.hinted or self.extracted


@dataclass
class Resource:
    """A topic, service, action or parameter."""
    id: str
    kind: str          # topic | service | action | parameter
    name: str
    condition: Optional[Formula]
    # message / service / parameter types: type -> condition (links that use it)
    types: dict[str, Optional[Formula]] = field(default_factory=dict)
    value: Optional[str] = None   # parameters set by the launch file (first value)
    locations: list[Location] = field(default_factory=list)  # <param> / <rosparam> tags
    count: Optional[int] = None
    # a name the code computes at run time: ``{expression}`` stands for what is not known
    dynamic: bool = False

    @property
    def type(self) -> Optional[str]:
        """The one type every link agrees on (None: unknown, or several)."""
        return next(iter(self.types)) if len(self.types) == 1 else None


@dataclass
class Via:
    """One way a link arises: a hint entry or a call in the node's sources, resolved (and maybe
    remapped) under a condition."""
    name: str                     # the name as the node's code writes it (the hint)
    type: Optional[str]
    condition: Optional[Formula]
    hint: Optional[Location]      # the hint entry
    remap: Optional[Location]     # the <remap> that produced the resolved name (None: not remapped)
    source: Optional[Location] = None   # the call in the sources (tvl_lsp.graph.sources)


@dataclass
class Link:
    id: str
    node: str          # node id
    resource: str      # resource id
    kind: str          # publish | subscribe | service | client | read | write
    condition: Optional[Formula]
    type: Optional[str] = None
    via: list[Via] = field(default_factory=list)
    count: Optional[int] = None


@dataclass(frozen=True)
class RemapUse:
    """A ``<remap>`` applying to a node under ``condition``; ``used``: the node (per its hints
    and sources) uses a name that resolves to the remap's ``from``; ``hinted``: what the node
    uses is known (hints or sources, no dynamic name: otherwise whether it uses the name is
    unknown)."""
    node: str          # node id
    from_: str         # resolved in the node's namespace
    to: str
    condition: Formula
    used: bool
    hinted: bool


@dataclass
class Graph:
    """The graph of a set of products of one launch file."""
    launch: str
    nodes: dict[str, GraphNode] = field(default_factory=dict)
    resources: dict[str, Resource] = field(default_factory=dict)
    links: dict[str, Link] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    hint_sources: list[str] = field(default_factory=list)
    decisions: dict[str, bool] = field(default_factory=dict)
    products: Optional[int] = None   # how many products the graph covers (when counted)
    model: Optional[str] = None
    # each <remap> that applies to some node: how it applies (for the remap-unused check)
    remap_uses: dict[Location, list["RemapUse"]] = field(default_factory=dict)

    def topics(self) -> list[Resource]:
        return [r for r in self.resources.values() if r.kind == "topic"]

    def services(self) -> list[Resource]:
        return [r for r in self.resources.values() if r.kind == "service"]

    def actions(self) -> list[Resource]:
        return [r for r in self.resources.values() if r.kind == "action"]

    def parameters(self) -> list[Resource]:
        return [r for r in self.resources.values() if r.kind == "parameter"]

    def links_of(self, resource_id: str, kinds: tuple[str, ...] = LINK_KINDS) -> list[Link]:
        """The links to a resource (indexed on first use: do not add links afterwards)."""
        idx = self.__dict__.get("_by_resource")
        if idx is None or idx[0] != len(self.links):
            by: dict[str, list[Link]] = {}
            for ln in self.links.values():
                by.setdefault(ln.resource, []).append(ln)
            idx = self.__dict__["_by_resource"] = (len(self.links), by)
        return [ln for ln in idx[1].get(resource_id, ()) if ln.kind in kinds]

    def links_from(self, node_id: str) -> list[Link]:
        idx = self.__dict__.get("_by_node")
        if idx is None or idx[0] != len(self.links):
            by: dict[str, list[Link]] = {}
            for ln in self.links.values():
                by.setdefault(ln.node, []).append(ln)
            idx = self.__dict__["_by_node"] = (len(self.links), by)
        return list(idx[1].get(node_id, ()))
