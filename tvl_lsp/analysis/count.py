"""Compatibility names for code written against the old counting module (the configurator
branch imports its exceptions from here).  New code imports :mod:`tvl_lsp.analysis.counting`:
the service (d4's d-DNNF, pyganak as fallback) is there, and pyganak's projected counter is
:mod:`tvl_lsp.analysis.counting.projected`.  Remove this module once nothing imports it."""

from .counting.errors import CancelLike, CountCancelled, CountTimeout  # noqa: F401
from .counting.projected import CACHE, count_cnf, query_key, simplify  # noqa: F401
