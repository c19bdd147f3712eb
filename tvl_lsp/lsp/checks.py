"""The server's entry into the pure check pipeline (``tvl_lsp.project.check``), the same functions
``tvl-lsp --check`` uses, so the editor and CI never disagree.  No pygls here: these run
in worker threads on plain data (text + a reader over a snapshot of the open documents).
"""

from __future__ import annotations

import logging
import os
from pathlib import Path
from typing import Callable, Optional, Sequence

from ..base.diagnostics import Diagnostic
from ..base.files import read_text_or_none

log = logging.getLogger("tvl_lsp.server")

Reader = Callable[[str], Optional[str]]

LAUNCH_SUFFIXES = (".launch", ".launch.xml", ".test", ".launch.yaml", ".launch.yml", "_launch.xml",
                   "_launch.yaml", "_launch.yml", ".launch.py", "_launch.py")


def file_kind(path: str) -> Optional[str]:
    """"tvl", "uvl", "dimacs", "launch" or None: which front end the server analyses a document
    with (the first three are models: project.facts.MODEL_KINDS)."""
    p = path.lower()
    if p.endswith(".tvl"):
        return "tvl"
    if p.endswith(".uvl"):
        return "uvl"
    if p.endswith((".dimacs", ".cnf")):
        return "dimacs"
    if p.endswith(LAUNCH_SUFFIXES) or p.endswith(".xml") and "launch" in p:
        return "launch"
    return None


def _root_for(path: str, roots: Sequence[str]) -> Optional[str]:
    best = None
    for r in roots:
        try:
            Path(path).relative_to(r)
        except ValueError:
            continue
        if best is None or len(r) > len(best):
            best = r
    return best


def parse_document(kind: str, path: str, text: str, read: Reader, roots: Sequence[str],
                   features: Optional[Sequence[str]] = None):
    """The front end's result for a document: a TvlResult (model) or a LaunchAnalysis
    (``features``: those of the paired model, the free args of its symbolic analysis as in
    ``--check``, with the file's own boolean top-level args)."""
    if kind in ("tvl", "uvl", "dimacs"):
        from ..analysis.formats import parse_any_model
        return parse_any_model(text, path, read_file=read, fmt=kind)
    if kind == "launch":
        from ..launch import analyse_any
        root = _root_for(path, roots)
        if features is not None:
            from ..project.check import free_top_args
            known = set(features)
            features = list(features) + [n for n in free_top_args(text, path, root, read, paired=True)
                                         if n not in known]
        return analyse_any(text, path, workspace_root=root, read_file=read, features=features)
    return None


def full_check(kind: str, path: str, text: str, read: Reader, roots: Sequence[str],
               budget: float, workspace=None) -> list[Diagnostic]:
    """Every diagnostic of the document, solver-backed ones included: exactly what
    ``tvl-lsp --check`` reports for it."""
    from ..project import check
    return list(check.check_document(path, text, read_file=read, roots=list(roots) or None,
                                     timeout=budget, workspace=workspace))


def quick_check(kind: str, path: str, text: str, read: Reader, roots: Sequence[str],
                workspace=None) -> list[Diagnostic]:
    """What :func:`full_check` reports that needs no SAT question (``check_document`` without
    its solver): a subset of it, computed in the server process (a thread) in milliseconds.
    ``workspace``: the server's (its files, packages and project files, parsed once per
    change of the workspace rather than once per keystroke)."""
    from ..project import check
    return list(check.check_document(path, text, read_file=read, roots=list(roots) or None, solver=False,
                                     cpu_budget=None, workspace=workspace))


def depends_on(ls, doc, changed: str) -> bool:
    """Should ``doc`` be re-checked when the file ``changed`` changes?  A launch file depends
    on its paired models and on the launch files it may include; a model on the launch files
    paired with it (so that both sides stay consistent in the editor)."""
    ck = file_kind(changed)
    if doc.kind == "launch":
        if ck in ("tvl", "uvl", "dimacs"):
            return _norm(changed) in {_norm(m) for m in ls.models_for_launch(doc.path)}
        if ck is None and is_node_source(changed):
            # a node's source (or build file): the graph checks read it; same workspace only
            return ls.workspace_root_for(changed) == ls.workspace_root_for(doc.path)
        return ck == "launch"
    if doc.kind in ("tvl", "uvl", "dimacs") and ck == "launch":
        return _norm(doc.path) in {_norm(m) for m in ls.models_for_launch(changed)}
    return False


def is_node_source(path: str) -> bool:
    """A C++ / Python source, or a build file, of a ROS package (a package.xml above it)."""
    import os
    from ..graph.sources import source_language
    base = os.path.basename(path)
    if source_language(path) is None and base not in ("CMakeLists.txt", "setup.py", "setup.cfg"):
        return False
    d = os.path.dirname(_norm(path))
    for _ in range(30):
        hit = _PKG_DIRS.get(d)
        if hit is None:
            hit = _PKG_DIRS[d] = os.path.isfile(os.path.join(d, "package.xml"))
            if len(_PKG_DIRS) > 20000:
                _PKG_DIRS.clear()
        if hit:
            return True
        nd = os.path.dirname(d)
        if nd == d:
            return False
        d = nd
    return False


_PKG_DIRS: dict[str, bool] = {}


def _norm(p: str) -> str:
    import os
    return os.path.normpath(os.path.abspath(p))


# ------------------------------------------------------------------ worker process side

class SnapshotReader:
    """A picklable reader: the open documents' texts as they were, then the disk."""

    def __init__(self, texts: dict[str, str]):
        self.texts = texts

    def __call__(self, path: str) -> Optional[str]:
        p = str(Path(path))
        if p in self.texts:
            return self.texts[p]
        # regular files within the size cap only: a FIFO named *.launch in the workspace blocked
        # every check, a link to /dev/zero was read without bound (issue #28)
        return read_text_or_none(p)


_LAST_EPOCH: list = [None]


def full_check_worker(kind: str, path: str, text: str, texts: dict[str, str], roots: Sequence[str],
                      budget: float, epoch: int) -> list[Diagnostic]:
    """:func:`full_check` in the server's check process (solver calls hold the GIL, so
    they must not run in the process that answers hovers)."""
    from ..project import check
    if _LAST_EPOCH[0] != epoch:
        check.invalidate_workspaces()
        _LAST_EPOCH[0] = epoch
    read = SnapshotReader(texts)
    import time
    t0 = time.perf_counter()
    if kind in ("tvl", "uvl", "dimacs"):  # (every model format: project.facts.MODEL_KINDS)
        _start_compiling(path, text, read, budget)
    out = full_check(kind, path, text, read, roots, budget, None)
    log.debug("check of %s: %d diagnostics in %.2f s", path, len(out), time.perf_counter() - t0)
    return out


def fixes_worker(path: str, text: str, texts: dict[str, str], keys: list, budget: float):
    """The checked quick fixes of the model's findings ``keys`` (``tvl_lsp.project.fixes``) in the
    check process, which has parsed and analysed this text for its check already."""
    from ..project.fixes import fixes_for
    return fixes_for(path, text, SnapshotReader(texts), [tuple(k) for k in keys], budget)


def _start_compiling(path: str, text: str, read: Reader, budget: float) -> None:
    """Start d4 on the model (in the background: its own process) before the anomaly search,
    so the counts the server asks for next (hover, code lens) are ready sooner; the check
    parses and encodes the model once for both (tvl_lsp.project.models)."""
    try:
        from ..project import models
        res, analysis = models.load(path, text, read)
        if res.model is not None and res.model.root is not None and not res.errors:
            analysis.counter.start(budget, owner=os.path.normpath(os.path.abspath(path)))
    except Exception:  # noqa: BLE001 (the check reports what is wrong with the model)
        log.debug("no background compilation of %s", path, exc_info=True)
