"""The workspace's sources for the graph: what the programs of the packages a launch file starts
use, read from their C++ and Python sources (:mod:`tvl_lsp.graph.sources`), shared by the check
pipeline (:mod:`.check`), ``tvl-lsp graph`` and the server (:mod:`.graph`)."""

from __future__ import annotations


def extraction_for(root: str, read_file=None, packages=None):
    """What the sources of the workspace's packages make their programs use (None when the
    workspace has no package); ``packages``: only those (the packages of a launch file's nodes);
    unsaved editor texts (a reader's ``texts``) are read as they are."""
    from ..graph.sources import extract
    texts = getattr(read_file, "texts", None)
    try:
        ex = extract([root], texts=texts, only=set(packages) if packages is not None else None)
    except (OSError, ValueError, RecursionError, MemoryError):
        return None
    return ex if ex.packages else None


def node_packages(analysis) -> set:
    """The packages of the nodes a launch analysis loads (in some product)."""
    return {nf.pkg for nf in getattr(analysis, "nodes", []) if getattr(nf, "pkg", None)}
