"""Raw declarations: what the parser builds for each statement of a model (features, groups,
children, attributes, constraints, types, constants) before the model builder
(:mod:`.build`) resolves and checks them, and the syntax issues the parser reports."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

from . import model as m
from .lexer import Tok


@dataclass(eq=False)
class RawAttr:
    type_tok: Tok
    name_tok: Tok
    start: int
    end: int
    value: Optional[m.Expr] = None
    domain: Optional[m.Expr] = None
    if_in_value: Optional[m.Expr] = None
    if_in_domain: Optional[m.Expr] = None
    if_out_value: Optional[m.Expr] = None
    if_out_domain: Optional[m.Expr] = None
    refinements: Optional[list["RawAttr"]] = None  # struct-typed attribute with a body
    dup_parts: list[tuple[str, int, int]] = field(default_factory=list)


@dataclass(eq=False)
class RawConstraint:
    kind: str
    expr: m.Expr
    start: int
    end: int


@dataclass(eq=False)
class RawData:
    entries: list[tuple[str, str, int, int]]
    start: int
    end: int


@dataclass(eq=False)
class RawChild:
    optional: bool
    shared: bool
    parts: list[Tok]
    body: Optional["RawBody"]
    start: int
    end: int
    depth: int = 0


@dataclass(eq=False)
class RawGroup:
    kind: str  # oneOf someOf allOf card
    kw_start: int
    kw_end: int
    lo: Optional[Tok]
    hi: Optional[Tok]
    children: list[RawChild]
    start: int
    end: int


@dataclass(eq=False)
class RawBody:
    items: list[Any]
    start: int
    end: int
    depth: int = 0


@dataclass(eq=False)
class RawFeatureDecl:
    is_root: bool
    root_tok: Optional[Tok]
    parts: list[Tok]
    body: RawBody
    start: int
    end: int


@dataclass(eq=False)
class RawType:
    kw: Tok
    name_tok: Tok
    domain: Optional[m.Expr]
    fields: list[RawAttr]
    start: int
    end: int


@dataclass(eq=False)
class RawConst:
    type_tok: Tok
    name_tok: Tok
    value: m.Expr
    start: int
    end: int


@dataclass
class SyntaxIssue:
    code: str
    start: int
    end: int
    message: str
