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
from .sources import extraction_for, node_packages
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
    ex = extraction_for(root, read_file, node_packages(analysis)) if sources else None
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
    now = extraction_for(ctx.extraction_root, read, node_packages(ctx.analysis))
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


# ------------------------------------------------------------------ sources (hover on a name in C++ / Python)

MAX_LAUNCHES = 8        # launch files looked at for one hover


@dataclass
class OtherEnd:
    node: str
    kind: str                 # its link kind (publish, subscribe, ...)
    condition: Optional[str]  # None: whenever this node uses the name


@dataclass
class Running:
    launch: str               # a launch file that starts the program
    node: str                 # the node's name there
    condition: Optional[str]  # when it runs (None: in every product)
    products: Optional[int]   # in how many products
    total: Optional[int]      # of how many
    resource: Optional[str]   # the name the call asks for, resolved there (namespace, remaps)
    others: list[OtherEnd] = field(default_factory=list)


@dataclass
class SourceUse:
    kind: str
    name: str
    type: Optional[str]
    package: str
    executables: list[str]
    dynamic: bool
    span: tuple               # (line, col, end line, end col), 0-based: the name or the call
    running: list[Running] = field(default_factory=list)
    note: Optional[str] = None


_OPPOSITE = {"publish": ("subscribe",), "subscribe": ("publish",), "service": ("client",), "client": ("service",),
             "action_server": ("action_client",), "action_client": ("action_server",), "read": ("write",),
             "write": ("read",)}


def source_info(path: str, line: int, col: int, read_file=None, roots: Optional[Sequence[str]] = None
                ) -> Optional[SourceUse]:
    """The call of a C++ / Python source at (line, col) (0-based, code points) that makes a node
    use a topic, service, action or parameter; for the hover: in which products of the
    workspace's launch files its program runs, and who is on the other end of the name there."""
    from ..graph.sources import LINK_OF_KIND, extract
    from ..launch.ros2.ament import package_of
    path = norm(path)
    read = read_file or default_read_file
    pkg = package_of(path)
    if pkg is None:
        return None
    root = _root_for(path, roots)
    ex = extract([root], texts=getattr(read_file, "texts", None), only={pkg.name})
    hit = None
    exes: list[str] = []
    for x in ex.executables:
        for e in x.endpoints:
            if norm(e.file) != path:
                continue
            if e.name_line is not None and e.name_line - 1 == line and e.name_col <= col <= e.name_end:
                span = (line, e.name_col, line, e.name_end)
            elif (e.line - 1, e.col) <= (line, col) <= (e.end_line - 1, e.end_col):
                span = (e.line - 1, e.col, e.end_line - 1, e.end_col)
            else:
                continue
            if hit is None or (hit[0].line, hit[0].col) == (e.line, e.col) and hit[0].kind == e.kind:
                hit = (e, span)
                if x.kind not in ("library", "source", "test") or not exes:
                    exes.append(x.name)
                for a in x.aliases:
                    exes.append(a)
    if hit is None:
        return None
    e, span = hit
    use = SourceUse(e.kind, e.name, e.type, e.package, list(dict.fromkeys(exes)), e.dynamic, span)
    link_kind = LINK_OF_KIND.get(e.kind)
    ws = load_workspace([root], read)
    launches = []
    for lf in ws.files.launches:
        text = read(lf)
        if not text or e.package not in text:
            continue
        pairings, _ = ws.pair(lf, text)
        named = any(norm(x) == norm(lf) for pf in ws.projects for c in pf.configurations for x, _ in c.launches)
        if named or any(p.model is not None for p in pairings):
            launches.append(lf)
    for lf in launches[:MAX_LAUNCHES]:
        try:
            ctx = cached_graph(lf, read_file, roots)
        except Exception:  # a launch file or model we cannot read now: others still answer
            continue
        _running_in(ctx, use, e, link_kind)
    if len(launches) > MAX_LAUNCHES:
        use.note = f"{len(launches) - MAX_LAUNCHES} more launch file(s) start programs of {e.package}"
    return use


def _running_in(ctx: GraphContext, use: SourceUse, e, link_kind: Optional[str]) -> None:
    from ..base import formula as fm
    from ..graph.project import _simplifier, graph_variables
    g = ctx.graph
    nodes = [n for n in g.nodes.values() if n.package == use.package and n.type in use.executables]
    if not nodes:
        return
    o = ctx.logic.oracle(graph_variables(g))
    top = o.term(fm.TRUE)
    simp = _simplifier(o, top)
    total = ctx.logic.count(fm.TRUE)
    for n in nodes:
        cond = n.condition if n.condition is not None else fm.TRUE
        shown = simp(cond)
        run = Running(ctx.launch, n.name, None if shown == fm.TRUE else str(shown),
                      ctx.logic.count(cond), total, None)
        for ln in g.links_from(n.id):
            if ln.kind != link_kind:
                continue
            if not any(v.source is not None and norm(v.source.path) == norm(e.file)
                       and v.source.span.start.line == e.line - 1 for v in ln.via):
                continue
            res = g.resources[ln.resource]
            run.resource = res.name
            node_simp = _simplifier(o, o.term(ln.condition or fm.TRUE))
            for other in g.links_of(res.id, _OPPOSITE.get(link_kind, ())):
                both = fm.conj([ln.condition or fm.TRUE, other.condition or fm.TRUE])
                if o.empty(o.term(both)):
                    continue
                c = node_simp(other.condition or fm.TRUE)
                run.others.append(OtherEnd(g.nodes[other.node].name, other.kind, None if c == fm.TRUE else str(c)))
            break
        use.running.append(run)
