"""The computation graph of one launch file in its workspace: what ``tvl-lsp graph``, the check
pipeline and the server's hover / ``tvl-lsp.graph`` command share.

    ctx = load_graph(launch_path, text=None, read_file=None, roots=None, workspace=None,
                     model=None, project_files=None)
    ctx.project({"Teleop": True}, count=True)   # -> Graph (tvl_lsp.graph), then to_json / to_dot
    ctx.diagnostics()                           # the graph checks (topic-without-publisher, ...)
    ctx.close()

The model is the launch file's pairing (:mod:`tvl_lsp.project.workspace`), unless ``model`` names one.
What each node uses comes from its package's sources in the workspace
(:mod:`tvl_lsp.graph.sources`) and from hints: those of ``project_files`` if given, else from
the HAROS project files whose configurations name the launch file, else from every project
file of the workspace (their ``nodes:`` sections; see :mod:`tvl_lsp.graph.hints`).  Pure: no
LSP here.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Iterable, Mapping, Optional, Sequence

from ..analysis.engine import ModelAnalysis
from ..base.diagnostics import Diagnostic
from ..graph import (Graph, GraphLogic, ProjectHints, build_graph, graph_diagnostics, parse_hints, project)
from .workspace import Workspace, default_read_file, find_workspace_root, load_workspace, norm


class GraphError(Exception):
    """The graph cannot be built (a file that cannot be read, a model with syntax errors)."""


@dataclass
class GraphContext:
    launch: str
    model_path: Optional[str]
    analysis: object                    # LaunchAnalysis
    graph: Graph
    logic: GraphLogic
    hints: ProjectHints
    model_analysis: Optional[ModelAnalysis] = None
    configs: Optional[list[str]] = None
    features: list[str] = field(default_factory=list)
    extraction: object = None           # tvl_lsp.graph.sources.Extraction (None: sources not read)
    extraction_root: Optional[str] = None

    def project(self, decisions: Optional[Mapping[str, bool]] = None, count: bool = False,
                count_timeout: Optional[float] = 10.0) -> Graph:
        """The graph of the products satisfying ``decisions`` (raises UnknownFeature / NoProducts)."""
        return project(self.graph, self.logic, decisions or {}, count=count, count_timeout=count_timeout)

    def diagnostics(self) -> list[Diagnostic]:
        return graph_diagnostics(self.graph, self.logic, self.analysis)

    def close(self) -> None:
        self.logic.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def hints_for(ws: Workspace, launch: str, read_file=default_read_file,
              project_files: Optional[Iterable[str]] = None) -> tuple[ProjectHints, Optional[list[str]]]:
    """The hints that apply to ``launch`` (:meth:`Workspace.hints_for`), or those of the given
    ``project_files``; and the names of the configurations whose per-node-name hints apply
    (None: all)."""
    if project_files is None:
        return ws.hints_for(launch)
    out = ProjectHints()
    for f in (norm(p) for p in project_files):
        text = read_file(f)
        if text is None:
            raise GraphError(f"cannot read the project file {f}")
        out = out.merge(parse_hints(f, text))
    return out, None


def free_args_of(text: str, path: str) -> list[str]:
    from .check import free_top_args
    return free_top_args(text, path)


def extraction_for(root: str, read_file=None):
    """What the sources of the workspace's packages make their programs use (None when the
    workspace has no package); unsaved editor texts (a reader's ``texts``) are read as they are."""
    from ..graph.sources import extract
    texts = getattr(read_file, "texts", None)
    try:
        ex = extract([root], texts=texts)
    except (OSError, ValueError, RecursionError, MemoryError):
        return None
    return ex if ex.packages else None


def load_graph(launch: str, text: Optional[str] = None, read_file=None, roots: Optional[Sequence[str]] = None,
               workspace: Optional[Workspace] = None, model: Optional[str] = None,
               project_files: Optional[Iterable[str]] = None, env: Optional[Mapping[str, str]] = None,
               sources: bool = True) -> GraphContext:
    """Pair, parse, load symbolically and build the graph of ``launch`` (see the module doc);
    ``sources``: read what the nodes use from the workspace's sources too."""
    from ..launch import analyse_any
    path = norm(launch)
    base_read = read_file or default_read_file

    def read(p: str) -> Optional[str]:
        if text is not None and norm(p) == path:
            return text
        return base_read(p)

    if text is None:
        text = read(path)
    if text is None:
        raise GraphError(f"cannot read {launch}")
    if workspace is None:
        root = _root_for(path, roots)
        workspace = load_workspace([root], read)
    else:
        root = workspace.roots[0] if workspace.roots else find_workspace_root(path)
    model_path = norm(model) if model else None
    if model_path is None:
        pairings, _ = workspace.pair(path, text)
        model_path = next((p.model for p in pairings if p.model is not None), None)
    ma = None
    enc = None
    features: list[str] = []
    if model_path is not None:
        mtext = read(model_path)
        if mtext is None:
            raise GraphError(f"cannot read the model {model_path}")
        from . import models
        # the parse is shared; the analysis is the graph's own: its solver calls (many, on big
        # models) must not hold the lock of the analysis a configurator's clicks use
        res, _ = models.load(model_path, mtext, read)
        ma = ModelAnalysis(res.model)
        from .check import STRUCTURAL
        if res.model.root is None or any(d.code in STRUCTURAL for d in res.diagnostics):
            raise GraphError(f"{os.path.basename(model_path)} has syntax errors: fix them first "
                             "(tvl-lsp --check lists them)")
        enc = ma.encoding
        features = [enc.name_of(f) for f in enc.features]
    free = [n for n in free_args_of(text, path) if enc is None or enc.feature_by_name(n) is None]
    analysis = analyse_any(text, path, workspace_root=root, read_file=read, features=features + free, env=env)
    hints, configs = hints_for(workspace, path, read, project_files)
    ex = extraction_for(root, read_file) if sources else None
    graph = build_graph(analysis, hints, configs, ex.by_node_type() if ex is not None else None)
    graph.model = model_path
    logic = GraphLogic(enc, features + free, ma)
    ctx = GraphContext(path, model_path, analysis, graph, logic, hints, ma, configs, features + free)
    ctx.extraction = ex
    ctx.extraction_root = root if sources else None
    return ctx


def _root_for(path: str, roots: Optional[Sequence[str]]) -> str:
    if roots:
        inside = [norm(r) for r in roots if path.startswith(norm(r).rstrip(os.sep) + os.sep)]
        if inside:
            return max(inside, key=len)
    return find_workspace_root(path)



# ------------------------------------------------------------------ the server's entries

class _RecordingReader:
    """A reader that remembers what it read (to know when a cached graph is stale)."""

    def __init__(self, read):
        self.read = read
        self.seen: dict[str, Optional[str]] = {}
        self.texts = getattr(read, "texts", None)   # unsaved editor texts (sources read them)

    def __call__(self, path: str) -> Optional[str]:
        t = self.read(path)
        self.seen[norm(path)] = t
        return t


_CACHE: dict[tuple, tuple[dict, GraphContext]] = {}
CACHE_SIZE = 8


def cached_graph(path: str, read_file=None, roots: Optional[Sequence[str]] = None) -> GraphContext:
    """:func:`load_graph`, reusing the last context of ``path`` while every file it read (the
    launch file, its includes, the model, the project files) has the same text."""
    read = read_file or default_read_file
    key = (norm(path), tuple(sorted(norm(r) for r in roots or ())))
    hit = _CACHE.get(key)
    if hit is not None:
        seen, ctx = hit
        if all(read(p) == t for p, t in seen.items()) and _same_sources(ctx, read):
            return ctx
        _CACHE.pop(key, None)
        ctx.close()
    rec = _RecordingReader(read)
    ctx = load_graph(path, read_file=rec, roots=roots)
    if rec.seen.get(norm(path)) is None:
        rec.seen[norm(path)] = read(path)
    for pf in ctx.hints.sources:
        rec.seen.setdefault(norm(pf), read(pf))
    while len(_CACHE) >= CACHE_SIZE:
        _, (_, old) = _CACHE.popitem()
        old.close()
    _CACHE[key] = (rec.seen, ctx)
    return ctx


def sources_signature(ex) -> Optional[str]:
    """A digest of what an extraction found (its programs and endpoints)."""
    if ex is None:
        return None
    import hashlib
    h = hashlib.sha1()
    for x in ex.executables:
        h.update(f"{x.package}/{x.name}/{x.kind}\0".encode())
        for e in x.endpoints:
            h.update(repr(sorted(e.row().items())).encode())
    return h.hexdigest()


def _same_sources(ctx: GraphContext, read) -> bool:
    """Whether the workspace's sources still say what they said when ``ctx`` was built (only
    changed files are parsed again: see tvl_lsp.graph.sources.cache)."""
    if ctx.extraction_root is None:
        return True
    now = extraction_for(ctx.extraction_root, read)
    if sources_signature(now) == sources_signature(ctx.extraction):
        return True
    return False


def graph_document(path: str, read_file=None, roots: Optional[Sequence[str]] = None,
                   decisions: Optional[Mapping[str, bool]] = None, count: bool = False) -> dict:
    """The ``tvl-lsp.graph`` command: the graph's JSON (docs/graph.md) for these decisions, or
    ``{"error": message, "conflict": [features] | None}``."""
    from ..graph import NoProducts, UnknownFeature, to_json
    try:
        ctx = cached_graph(path, read_file, roots)
        g = ctx.project(decisions or {}, count=count)
    except (GraphError, UnknownFeature) as ex:
        return {"error": str(ex), "conflict": None}
    except NoProducts as ex:
        return {"error": str(ex), "conflict": ex.conflict}
    return to_json(g)


@dataclass
class NodeUse:
    kind: str                 # publish | subscribe | service | client | read | write
    name: str                 # resolved name
    type: Optional[str]
    condition: Optional[str]  # relative to the node being loaded (None: whenever it is)
    written: list[str]        # the names as the hints (or the sources) write them
    remap: Optional[str]      # the <remap> that renamed it
    sources: list[str] = field(default_factory=list)   # where the sources ask for it ("turtle.cpp:55")


@dataclass
class NodeInfo:
    name: str
    package: str
    type: str
    hinted: bool
    note: Optional[str]
    uses: list[NodeUse]
    hints: list[str]          # where the hints are ("haros.yaml:12")
    hints_available: bool = True  # the workspace has node hints (or sources) at all
    extracted: bool = False   # what it uses was read from its sources


def node_info(path: str, span_start, read_file=None, roots: Optional[Sequence[str]] = None) -> list[NodeInfo]:
    """The graph nodes a ``<node>`` tag of ``path`` (its start at ``span_start``) loads, with the
    topics, services and parameters each uses and when (for the hover)."""
    from ..base import formula as fm
    from ..graph.project import _simplifier, graph_variables
    ctx = cached_graph(path, read_file, roots)
    g = ctx.graph
    o = ctx.logic.oracle(graph_variables(g))
    out = []
    for n in g.nodes.values():
        occ = [c for loc, c in n.occurrences if loc.path == norm(path) and loc.span.start == span_start]
        if not occ:
            continue
        here = fm.disj(occ)
        base = o.term(here)
        if o.empty(base):
            continue
        simp = _simplifier(o, base)
        uses = []
        for ln in sorted(g.links_from(n.id), key=lambda x: (x.kind, g.resources[x.resource].name)):
            c = fm.conj([here, ln.condition]) if ln.condition is not None else here
            t = o.term(c)
            if o.empty(t):
                continue
            rel = None if o.empty(o.and_(base, o.not_(t))) else str(simp(ln.condition))
            remaps = [v.remap.label for v in ln.via if v.remap is not None]
            srcs = sorted({f"{os.path.basename(v.source.path)}:{v.source.span.start.line + 1}"
                           for v in ln.via if v.source is not None})
            uses.append(NodeUse(ln.kind, g.resources[ln.resource].name, ln.type, rel,
                                sorted({v.name for v in ln.via}), remaps[0] if remaps else None, srcs))
        hints = [f"{os.path.basename(h.path)}:{h.span.start.line + 1}" for h in n.hints]
        out.append(NodeInfo(n.name, n.package, n.type, n.known, n.note, uses, hints,
                            bool(ctx.hints) or ctx.extraction is not None, n.extracted))
    return out
