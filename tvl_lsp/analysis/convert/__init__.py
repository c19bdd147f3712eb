"""Conversions between model formats: TVL <-> UVL, and TVL / UVL (and DIMACS) -> DIMACS.

    convert_model(model, target) -> Conversion(text, notes, exact)

The product count is preserved: what the target says directly (the tree, the groups, boolean
constraints) is written as such; what it cannot say is *compiled* into constraints over the
features that mean exactly the same products:

- TVL -> UVL: a group whose optional children weaken its cardinality, a ``shared`` feature (a
  UVL tree has one parent per feature), constraints over attributes or with aggregates become
  boolean constraints (a group's meaning is written out; an attribute constraint is projected
  onto the features it involves by enumerating their selections, up to
  :data:`MAX_COMPILE_FEATURES` of them);
- UVL -> TVL: a feature with several groups (TVL has one group per feature) keeps one ``allOf``
  group and states the ``or`` / ``alternative`` / ``[n..m]`` blocks as ``ifIn:`` constraints
  (a sum of ``(F ? 1 : 0)`` terms for counting bounds);
- -> DIMACS: the encoding of the analyses, with every auxiliary variable defined as a function
  of the features (Tseitin definitions; cardinalities with a pairwise or a fully defined
  counter encoding), so that counting all the variables of the CNF counts the products.

Names are adapted to the target's lexical rules (and made unique); what the target has no place
for (UVL attributes other than numbers and booleans in TVL, TVL computed attributes in UVL,
UVL arithmetic constraints in TVL) is kept as a comment or data entry and said in the notes.
``exact`` is False when something could not be converted without changing the products (the
notes say what).
"""

from __future__ import annotations

from typing import Optional

from ...tvl import model as M
from ..encode import Encoding, encode
from .common import MAX_COMPILE_FEATURES, MAX_GROUP_CLAUSES, PAIRWISE_MAX, Conversion, ConvertError

__all__ = ["convert_model", "Conversion", "ConvertError", "target_of", "MAX_COMPILE_FEATURES",
           "MAX_GROUP_CLAUSES", "PAIRWISE_MAX"]


def target_of(path: str) -> Optional[str]:
    from ..formats import model_format
    return model_format(path)


def convert_model(model: M.Model, target: str, encoding: Optional[Encoding] = None) -> Conversion:
    """The text of ``model`` in ``target`` ("tvl", "uvl" or "dimacs")."""
    if model.root is None:
        raise ConvertError("the model has no root feature")
    enc = encoding or encode(model)
    if target == "dimacs":
        from .cnf import DimacsWriter
        return DimacsWriter(model, enc).run()
    if target in ("tvl", "uvl"):
        from .tree import TreeWriter
        return TreeWriter(model, enc, target).run()
    raise ConvertError(f"unknown target format {target!r} (tvl, uvl or dimacs)")


