"""The typed TVL model: what the parser builds and what the analyses read.

Every element carries the :class:`~tvl_lsp.base.text.Span` of its source and the path of the
file it was written in (``include`` makes models span several files).

Design notes
- A feature's *identity* is its object; ``Feature.long_name`` ("Root.A.B") is unique for
  non-shared features and is what the analyses use as the variable name.  Features are
  stored in declaration order in ``Model.features``.
- A TVL feature has at most one decomposition group (``Feature.group``); a child in a group is a
  :class:`GroupChild` which says whether it is optional and whether it is a ``shared`` reference
  to a feature declared elsewhere (a shared feature has several parents).  A UVL feature may have
  several groups (``mandatory`` and ``optional`` and ``alternative`` blocks under one feature):
  the first is ``Feature.group``, the others are in ``Feature.extra_groups``; code that walks
  groups uses ``Feature.groups`` (all of them) and ``Feature.children``.
- Expressions are a small AST; names are resolved by the resolver, which fills
  ``Name.target`` with the Feature / Attribute / Constant / EnumValue it designates
  (``None`` when unresolved: a diagnostic has been reported).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Union

from ..base.text import Span, ZERO_SPAN


# ---------------------------------------------------------------- expressions

@dataclass(eq=False)
class Expr:
    span: Span = field(default=ZERO_SPAN, kw_only=True)
    path: str = field(default="", kw_only=True)
    # the type the checker inferred: "bool", "int", "real", "enum:<name>", "struct:<name>", "set", None
    type: Optional[str] = field(default=None, kw_only=True)


@dataclass(eq=False)
class BoolLit(Expr):
    value: bool


@dataclass(eq=False)
class IntLit(Expr):
    value: int


@dataclass(eq=False)
class RealLit(Expr):
    value: float
    text: str = ""


@dataclass(eq=False)
class Name(Expr):
    """A (possibly dotted) reference: ``A``, ``A.B.price``, ``root.X``, ``this.a``, ``parent``."""
    parts: list[str]
    part_spans: list[Span] = field(default_factory=list)
    # filled by the resolver:
    target: Optional["Target"] = None
    # for a dotted name whose head designates a feature and whose tail is an attribute
    # (or a struct field path), the feature part is in ``feature`` and ``target`` is the attribute.
    feature: Optional["Feature"] = None
    # (added) what each part designates, parallel to ``parts`` (filled by the resolver)
    part_targets: list = field(default_factory=list)

    @property
    def text(self) -> str:
        return ".".join(self.parts)


@dataclass(eq=False)
class Unary(Expr):
    op: str  # "!", "-", "abs"
    operand: Expr


@dataclass(eq=False)
class Binary(Expr):
    # "?:" is not here (see Ternary). ops: "<-" "->" "<->" "||" "&&" "==" "!=" "in"
    # ">=" "<" ">" "<=" "+" "-" "*" "/" "requires" "excludes"
    op: str
    left: Expr
    right: Expr


@dataclass(eq=False)
class Ternary(Expr):
    cond: Expr
    then: Expr
    other: Expr


@dataclass(eq=False)
class Aggregate(Expr):
    """``sum mul min max avg and or xor`` over ``args`` or over ``children.attr`` /
    ``selectedChildren.attr`` (``over`` set, ``attr`` the attribute name, ``args`` empty).
    ``count(children|selectedChildren)`` is ``func == "count"`` with ``attr is None``."""
    func: str
    args: list[Expr] = field(default_factory=list)
    over: Optional[str] = None  # "children" | "selectedChildren" | None
    attr: Optional[str] = None
    attr_span: Optional[Span] = None
    # filled by the resolver when ``over`` is set: the owner feature whose children are meant
    owner: Optional["Feature"] = None


@dataclass(eq=False)
class SetLit(Expr):
    """``{a, b, c}``"""
    items: list[Expr]


@dataclass(eq=False)
class RangeLit(Expr):
    """``[lo..hi]``"""
    lo: Expr
    hi: Expr


# ---------------------------------------------------------------- declarations

@dataclass(eq=False)
class EnumValue:
    name: str
    span: Span
    path: str
    enum_of: Union["TypeDecl", "Attribute", None] = None


@dataclass(eq=False)
class TypeDecl:
    """``int|real|enum NAME in SET;``, ``int|real|bool NAME;`` or ``struct NAME { fields }``."""
    name: str
    base: str  # "int" | "real" | "bool" | "enum" | "struct"
    span: Span  # the whole declaration
    name_span: Span
    path: str
    domain: Optional[Expr] = None  # SetLit or RangeLit for ``in SET``
    enum_values: list[EnumValue] = field(default_factory=list)
    fields: list["Attribute"] = field(default_factory=list)  # struct fields


@dataclass(eq=False)
class Constant:
    name: str
    type: str  # "int" | "real" | "bool"
    value: Expr
    span: Span
    name_span: Span
    path: str


@dataclass(eq=False)
class Attribute:
    """``TYPE NAME [is e | in SET] [, ifIn: ...] [, ifOut: ...];``

    ``type`` is "bool", "int", "real", "enum" or the name of a declared type; ``type_decl`` is
    filled by the resolver for declared types.  For ``ifIn:`` / ``ifOut:`` parts, the value
    (``is``) or domain (``in``) applies only when the owner feature is selected / not selected.
    """
    name: str
    type: str
    span: Span
    name_span: Span
    path: str
    owner: Optional["Feature"] = None  # None for struct fields
    type_decl: Optional[TypeDecl] = None
    value: Optional[Expr] = None       # ``is e``
    domain: Optional[Expr] = None      # ``in SET``
    if_in_value: Optional[Expr] = None
    if_in_domain: Optional[Expr] = None
    if_out_value: Optional[Expr] = None
    if_out_domain: Optional[Expr] = None
    enum_values: list[EnumValue] = field(default_factory=list)  # for ``enum NAME in {a, b}``
    # struct-typed attribute: refinements of its fields (field name -> Attribute)
    field_refinements: dict[str, "Attribute"] = field(default_factory=dict)
    # (added) where the type name is written (None for field refinements)
    type_span: Optional[Span] = None

    @property
    def long_name(self) -> str:
        return f"{self.owner.long_name}.{self.name}" if self.owner else self.name


@dataclass(eq=False)
class Constraint:
    """``e;`` (kind "plain"), ``ifIn: e;`` ("ifIn") or ``ifOut: e;`` ("ifOut")."""
    expr: Expr
    kind: str
    owner: "Feature"
    span: Span
    path: str
    # a DIMACS clause (signed indexes into ``Model.features``) when the constraint is one: the
    # encoder takes it as it is instead of walking ``expr`` (10^5 clauses in industrial models)
    clause: Optional[list[int]] = None


@dataclass(eq=False)
class GroupChild:
    feature: "Feature"
    optional: bool
    shared: bool
    span: Span  # the child's declaration (or the ``shared X`` reference)
    path: str


@dataclass(eq=False)
class Group:
    """``group oneOf|someOf|allOf|[i..j] { children }``.

    ``lo``/``hi`` are the resolved bounds (``hi is None`` means ``*``); for the keyword forms
    they are derived from the number of children (oneOf [1..1], someOf [1..*], allOf [n..n]).
    """
    kind: str  # "oneOf" | "someOf" | "allOf" | "card"
    owner: "Feature"
    span: Span  # from ``group`` to the closing brace
    keyword_span: Span  # the ``oneOf`` / ``[i..j]`` part
    path: str
    children: list[GroupChild] = field(default_factory=list)
    lo: int = 0
    hi: Optional[int] = None
    lo_expr: Optional[Expr] = None  # for card groups: IntLit, Name (constant) or None for *
    hi_expr: Optional[Expr] = None
    # the group's keyword as written in a UVL model ("optional", "alternative", "[1..3]"); "" in TVL
    keyword: str = ""

    @property
    def text(self) -> str:
        """How the group is written: the UVL keyword, or TVL's ``oneOf`` / ``[i..j]``."""
        if self.keyword:
            return self.keyword
        if self.kind == "card":
            return f"[{self.lo}..{'*' if self.hi is None else self.hi}]"
        return self.kind


@dataclass(eq=False)
class DataEntry:
    key: str
    value: str
    span: Span
    path: str


@dataclass(eq=False)
class Feature:
    name: str
    span: Span       # the declaration that introduced it (name to end of body)
    name_span: Span  # the name in that declaration
    path: str
    parent: Optional["Feature"] = None           # the declaring parent (None for the root)
    shared_parents: list["Feature"] = field(default_factory=list)  # extra parents via ``shared``
    group: Optional[Group] = None
    attributes: list[Attribute] = field(default_factory=list)
    constraints: list[Constraint] = field(default_factory=list)
    data: list[DataEntry] = field(default_factory=list)
    # every place the feature is named in a declaration position: first declaration,
    # reopenings (``A { }``, ``A.B { }``, ``root A``) and ``shared`` references.
    decl_spans: list[tuple[str, Span]] = field(default_factory=list)
    is_root: bool = False
    # UVL: the feature's second and later groups (see the module notes)
    extra_groups: list[Group] = field(default_factory=list)

    @property
    def long_name(self) -> str:
        names = []
        f: Optional[Feature] = self
        while f is not None:
            names.append(f.name)
            f = f.parent
        return ".".join(reversed(names))

    @property
    def parents(self) -> list["Feature"]:
        return ([self.parent] if self.parent else []) + self.shared_parents

    @property
    def groups(self) -> list[Group]:
        """Every decomposition group of the feature (TVL: at most one)."""
        if not self.extra_groups:
            return [self.group] if self.group is not None else []
        return ([self.group] if self.group is not None else []) + self.extra_groups

    @property
    def children(self) -> list["Feature"]:
        if not self.extra_groups:
            return [c.feature for c in self.group.children] if self.group else []
        return [c.feature for g in self.groups for c in g.children]

    def child_entry(self, child: "Feature") -> Optional[GroupChild]:
        for g in self.groups:
            for c in g.children:
                if c.feature is child:
                    return c
        return None

    def group_of(self, child: "Feature") -> Optional[Group]:
        """The group of this feature in which ``child`` is a child."""
        for g in self.groups:
            for c in g.children:
                if c.feature is child:
                    return g
        return None

    @property
    def optional(self) -> bool:
        """Optional in its declaring parent's group (the root is mandatory)."""
        if self.parent is None:
            return False
        e = self.parent.child_entry(self)
        return bool(e and e.optional)


Target = Union[Feature, Attribute, Constant, EnumValue, TypeDecl]


@dataclass(eq=False)
class Unanalysed:
    """Something a model says that the analyses leave out (kept for converters and hovers)."""
    kind: str      # "constraint" | "attribute" | "feature-type" | "feature-cardinality" | ...
    text: str      # its source text
    span: Span
    path: str
    owner: Optional["Feature"] = None
    reason: str = ""


@dataclass(eq=False)
class Include:
    path_text: str
    span: Span
    path: str  # the including file
    resolved: Optional[str] = None  # absolute path of the included file


@dataclass(eq=False)
class Model:
    path: str  # the main file
    root: Optional[Feature] = None
    features: list[Feature] = field(default_factory=list)  # declaration order, root first
    types: list[TypeDecl] = field(default_factory=list)
    constants: list[Constant] = field(default_factory=list)
    includes: list[Include] = field(default_factory=list)
    # every file that contributed text: path -> text (the main file and included ones)
    sources: dict[str, str] = field(default_factory=dict)
    # the format the model was read from: "tvl", "uvl" or "dimacs"
    format: str = "tvl"
    # what the front end read but the analyses leave out (UVL attributes, arithmetic and
    # string constraints, ...), each reported as ``not-analysed``
    unanalysed: list["Unanalysed"] = field(default_factory=list)

    def feature(self, name: str) -> Optional[Feature]:
        """Look a feature up by long name ("Root.A.B") or, when unique, short name."""
        for f in self.features:
            if f.long_name == name:
                return f
        found = [f for f in self.features if f.name == name]
        return found[0] if len(found) == 1 else None

    def features_named(self, name: str) -> list[Feature]:
        return [f for f in self.features if f.name == name]

    @property
    def constraints(self) -> list[Constraint]:
        return [c for f in self.features for c in f.constraints]

    @property
    def attributes(self) -> list[Attribute]:
        return [a for f in self.features for a in f.attributes]
