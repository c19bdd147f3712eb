"""The diagnostic codes of the TVL front end's semantic checks (model building, name
resolution, types); the syntax codes are registered in ``tvl_lsp.tvl``."""

from __future__ import annotations

from ..base.diagnostics import Severity, register

E, W = Severity.ERROR, Severity.WARNING

C_FIRST_NOT_ROOT = register("first-not-root", E, "The first feature declared must be the root.", "tvl")
C_ROOT_LONG = register("root-long-name", E, "The root feature's name cannot be a dotted name.", "tvl")
C_LONG_IN_GROUP = register("long-name-in-group", E, "A child declared in a group cannot have a dotted name.", "tvl")
C_ROOT_NAME_REUSED = register("root-name-reused", E, "A feature has the same name as the root.", "tvl")
C_DUP_FEATURE = register("duplicate-feature", E, "Two children of a group have the same name.", "tvl")
C_DUP_SHARED = register("duplicate-child", E, "A shared child has the name of another child of the same feature.", "tvl")
C_MULTI_GROUPS = register("multiple-groups", E, "A feature has more than one decomposition group.", "tvl")
C_UNKNOWN = register("unknown-name", E, "A name designates no feature, attribute, constant or type.", "tvl")
C_AMBIGUOUS = register("ambiguous-name", E, "A short feature name designates several features.", "tvl")
C_CARD_BOUNDS = register("cardinality-bounds", E, "Invalid group cardinality bounds.", "tvl")
C_CARD_EXCEEDS = register("cardinality-exceeds-children", E, "A group's lower bound exceeds its number of children.", "tvl")
C_CARD_UPPER = register("cardinality-upper-unreachable", W, "A group's upper bound exceeds its number of children.", "tvl")
C_TYPE = register("type-error", E, "An expression has the wrong type.", "tvl")
C_NAMING = register("naming-convention", W, "Features begin with an upper-case letter; attributes, types and constants with a lower-case one.", "tvl")
C_DUP_ATTR = register("duplicate-attribute", E, "A feature declares two attributes with the same name.", "tvl")
C_DUP_DECL = register("duplicate-declaration", E, "Two types or constants have the same name.", "tvl")
C_NAME_CONFLICT = register("name-conflict", E, "A name is used for two different kinds of things.", "tvl")
C_DOMAIN = register("invalid-domain", E, "An attribute or type domain is invalid.", "tvl")
C_OUT_OF_DOMAIN = register("value-out-of-domain", E, "A value lies outside the attribute's domain.", "tvl")
C_UNKNOWN_TYPE = register("unknown-type", E, "An attribute's type is not declared.", "tvl")
C_NOT_STRUCT = register("not-a-struct", E, "Field refinements on an attribute whose type is not a struct.", "tvl")
C_UNKNOWN_FIELD = register("unknown-field", E, "A struct refinement names a field the struct does not have.", "tvl")
C_PARENT_SHARED = register("parent-in-shared", E, "The keyword 'parent' used in a shared feature (it has several parents).", "tvl")
C_CYCLE = register("shared-cycle", E, "Shared features make the feature hierarchy cyclic.", "tvl")
C_TYPE_AS_VALUE = register("type-as-value", E, "A type name used as a value.", "tvl")
C_BAD_TYPE_DECL = register("invalid-type-declaration", E, "A type declaration the reference does not allow.", "tvl")
C_ENUM_NO_VALUES = register("enum-without-values", W, "An enum attribute without its values.", "tvl")
C_DUP_PART = register("duplicate-attribute-part", E, "An attribute gives its value or domain twice.", "tvl")
C_REF_REJECTS = register("reference-rejects", W, "Accepted and analysed, but the TVL reference parser rejects it.", "tvl")
