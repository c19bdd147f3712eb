"""The check pipeline shared by ``tvl-lsp --check`` and the language server.

Pure: no LSP here; files are read through ``read_file(path) -> str | None`` callbacks.

    check_paths(paths, read_file=None, jobs=None) -> list[Diagnostic]
        Discover ``.tvl``, ``.launch``, ``.launch.xml`` and HAROS project files under ``paths``
        (files or folders), pair launch files with models (see :mod:`tvl_lsp.project.workspace`),
        analyse everything and return every diagnostic, deduplicated and sorted.  Large trees
        are analysed in parallel processes (``jobs``: None = one per CPU, 1 = serially); the
        output does not depend on ``jobs``.  With a custom ``read_file`` the work stays in this
        process (callbacks do not cross process boundaries).

    check_document(path, text=None, read_file=None, roots=None, timeout=None, workspace=None)
        -> list[Diagnostic]
        Every diagnostic of ONE document, for the server: a model gets its parse diagnostics
        and anomalies; a launch file gets its own load-time diagnostics, its pairing's marker
        problems and the cross-checks against each model it is paired with (or alone); a
        HAROS project file gets its YAML / missing-file diagnostics.  ``text`` is the current
        (possibly unsaved) content; ``roots`` are the workspace folders (default: found from
        ``path`` by :func:`tvl_lsp.project.workspace.find_workspace_root`); pass a ``workspace``
        (:func:`tvl_lsp.project.workspace.load_workspace`) to skip the file discovery.  ``timeout``
        bounds the model anomaly search (seconds).

    pairing_of(path, workspace=None, text=None) -> list[Pairing]
        Which model(s) configure a launch file and by which rule (for hovers / code lenses).

    check_model(path, text, read_file) / check_launch(path, text, pairings, root, read_file)
        The two per-file steps the above are made of.
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Callable, Iterable, Optional, Sequence

from ..base.diagnostics import Diagnostic, Related, Severity
from ..base.files import unreadable_reason
from . import budget
from .workspace import (Files, Pairing, Workspace, default_read_file, discover_files, find_workspace_root,
                        is_launch, is_model, is_xml_launch_candidate, is_yaml, launch_root_text, load_workspace,
                        norm)

ReadFile = Callable[[str], Optional[str]]

# below this many files a process pool costs more than it saves
PARALLEL_MIN_FILES = 24
LAUNCH_BATCH = 6


# ------------------------------------------------------------------ per-file steps

@dataclass
class _ModelInfo:
    path: str
    model: object
    diagnostics: list[Diagnostic]
    analysis: object  # ModelAnalysis
    has_errors: bool


SAT_RESERVE = 0.3  # CPU seconds of a file's budget kept from its anomaly search (to report)


def _load_model(path: str, read_file: ReadFile, text: Optional[str] = None,
                anomalies: bool = True, timeout: Optional[float] = 10.0,
                progress: Optional[budget.Progress] = None) -> Optional[_ModelInfo]:
    from . import models
    if text is None:
        text = read_file(path)
    if text is None:
        return None
    # parsed and encoded once per text in this process (the server's counts reuse it)
    res, analysis = models.load(path, text, read_file)
    diags = list(res.diagnostics)
    has_errors = any(d.severity == Severity.ERROR for d in diags)
    if progress is not None:  # final: reported even if the budget runs out in the anomaly search
        progress.diagnostics = list(diags)
        progress.done = "its syntax and type checks"
        progress.rest = "the search for anomalies (void model, dead and false-optional features)"
    if anomalies and res.model.root is not None:
        left = budget.remaining()
        hard = None if left is None else max(0.0, left - SAT_RESERVE)
        try:
            diags += analysis.anomalies(time_budget=timeout, hard_budget=hard)
        except Exception as exc:  # an analysis bug must not hide the parse diagnostics (_internal
            # raises a MemoryError again: the file's budget, reported with what progress holds)
            diags.append(_internal(path, f"model analysis failed: {exc!r}"))
    return _ModelInfo(path, res.model, diags, analysis, has_errors)


def _unreadable(path: str) -> Optional[Diagnostic]:
    """A ``file-unreadable`` error for a file the pipeline found but must not or cannot read
    (a device, a FIFO, a file over the size cap; see :mod:`base.files`), or None when it
    vanished (a file deleted since it was found is not a problem of the workspace)."""
    from ..base.text import Pos, Span
    why = unreadable_reason(path)
    if why is None or not os.path.lexists(path):
        return None
    return Diagnostic(FILE_UNREADABLE, Severity.ERROR, path, Span(Pos(0, 0), Pos(0, 0)),
                      f"{os.path.basename(path)} is not read: {why}")


def _internal(path: str, msg: str) -> Diagnostic:
    """An ``internal-error`` for a failure being handled; a ``MemoryError`` is not a bug but the
    file's memory budget, so it is raised again (:func:`budget.limited` reports it)."""
    import sys
    if isinstance(sys.exc_info()[1], MemoryError):
        raise sys.exc_info()[1]
    from ..base.text import Pos, Span
    return Diagnostic("internal-error", Severity.ERROR, path, Span(Pos(0, 0), Pos(0, 0)), msg)


from ..base.diagnostics import register as _register  # noqa: E402

INTERNAL_ERROR = _register("internal-error", Severity.ERROR,
                           "The check of a file failed inside tvl-lsp (a bug: please report it).", "workspace")
FILE_UNREADABLE = _register(
    "file-unreadable", Severity.ERROR,
    "A file in the workspace that tvl-lsp must not read (a device, a FIFO, a socket) or that is over the size cap.",
    "workspace")
FILE_NOT_CHECKED = _register(
    "file-not-checked", Severity.ERROR,
    "A file named on the command line that --check does not check (not a model, launch file or HAROS project file).",
    "workspace")
MODEL_NOT_CHECKABLE = _register(
    "paired-model-invalid", Severity.INFORMATION,
    "The launch file's model has syntax errors: the checks against it wait until they are fixed.", "cross")

# errors after which the model's structure may be incomplete (features missing or misplaced):
# checking a launch file against it would report args "naming no feature" that are fine
STRUCTURAL = frozenset({"syntax-error", "illegal-character", "unterminated-comment", "unterminated-string",
                        "nesting-too-deep", "file-too-large", "include-missing", "include-cycle",
                        "first-not-root", "multiple-groups"})


def check_model(path: str, text: Optional[str] = None, read_file: Optional[ReadFile] = None,
                timeout: Optional[float] = 10.0, progress: Optional[budget.Progress] = None) -> list[Diagnostic]:
    """A model's own diagnostics: syntax, types, and anomalies (void model, dead and
    false-optional features, ...)."""
    info = _load_model(path, read_file or default_read_file, text, True, timeout, progress)
    if info is None:
        d = _unreadable(path)
        return [d] if d else []
    return info.diagnostics


def _launch_own(analysis) -> list[Diagnostic]:
    """The launch file's diagnostics that hold whatever the pairing: unconditional ones."""
    return list(analysis.diagnostics)


def check_launch(path: str, text: Optional[str], pairings: Sequence[Pairing], root: Optional[str],
                 read_file: Optional[ReadFile] = None, models: Optional[dict] = None,
                 timeout: Optional[float] = 10.0, hints=None, configs: Optional[list[str]] = None,
                 partial: bool = False, solver: bool = True) -> list[Diagnostic]:
    """A launch file's diagnostics: its own, the cross-checks of each pairing, and, with node
    ``hints`` (:meth:`Workspace.hints_for`: a project file names it), the computation graph's
    checks, on the hints and the workspace's sources.  ROS 1 or ROS 2,
    by the file's dialect; ``partial``: a ROS 2 file other launch files include (see
    :func:`tvl_lsp.launch.ros2.analyse_launch2`), for its check without a model.  Without
    ``solver``: only the diagnostics that need no SAT question (see :func:`cross_check`)."""
    from ..analysis.crosscheck import cross_check
    from ..launch import analyse_any, dialect_of
    read_file = read_file or default_read_file
    if text is None:
        text = read_file(path)
    if text is None:
        d = _unreadable(path)
        return [d] if d else []
    models = {} if models is None else models
    out: list[Diagnostic] = []
    done_alone = False
    dialect = dialect_of(path, text)
    free_cache: dict = {}

    def tops(paired: bool = False) -> list[str]:
        if paired not in free_cache:
            free_cache[paired] = free_top_args(text, path, root, read_file, paired=paired)
        return list(free_cache[paired])
    for p in pairings or [Pairing(path, None, "none")]:
        info = None
        if p.model is not None:
            if p.model not in models:
                models[p.model] = _load_model(p.model, read_file, None, anomalies=False, timeout=timeout)
            info = models[p.model]
        if info is None:
            if done_alone:
                continue
            done_alone = True
        pairings_of_choices = None
        selectors = None
        if info is not None:
            enc = info.analysis.encoding
            features = [enc.name_of(f) for f in enc.features]
            features += [n for n in tops(paired=True) if enc.feature_by_name(n) is None]
            if dialect.ros2:
                from ..analysis.choices import pair_choices
                from ..launch.ros2 import choice_args
                pairings_of_choices = pair_choices(choice_args(text, path), enc)
                selectors = {k: p.selectors for k, p in pairings_of_choices.items() if p.selectors is not None}
                features = [f for f in features if f not in pairings_of_choices]
        else:
            # a Python launch file's free arguments come from the analysis itself (its file is
            # interpreted once); an XML / YAML file's from a parse
            features = tops() if not path.endswith(".py") else None
        try:
            la = analyse_any(text, path, workspace_root=root, read_file=read_file, features=features,
                             choices=selectors, dialect=dialect, partial=partial and info is None,
                             lenient=info is None)
        except Exception as exc:
            out.append(_internal(path, f"launch analysis failed: {exc!r}"))
            continue
        out += _launch_own(la)
        broken = [d for d in (info.diagnostics if info is not None else []) if d.code in STRUCTURAL]
        if broken or (info is not None and info.model.root is None):
            from ..base.text import Pos, Span
            span = la.root.span if la.root is not None else Span(Pos(0, 0), Pos(0, 0))
            first = broken[0] if broken else None
            out.append(Diagnostic(
                MODEL_NOT_CHECKABLE, Severity.INFORMATION, path, span,
                f"{os.path.basename(p.model)} has syntax errors: the checks of this launch file against it "
                "(args, dead elements, duplicates per product) resume when they are fixed",
                related=[Related(first.path, first.span, first.message)] if first else []))
            # what fails whatever the args still holds
            from ..base.formula import TRUE
            out += [Diagnostic(f.code, f.severity, f.path, f.span, f.message,
                               [r if isinstance(r, Related) else Related(*r) for r in f.related])
                    for f in la.facts if f.condition == TRUE and f.path == path]
            continue
        try:
            if info is not None:
                cur = cross_check(la, info.model, info.analysis.encoding, launch_text=text, model_path=p.model,
                                  analysis=info.analysis, choices=pairings_of_choices, solver=solver)
                out += [_note_pairing(d, p, root or os.path.dirname(path)) for d in cur]
            else:
                out += cross_check(la, None, None, launch_text=text, solver=solver)
        except Exception as exc:
            out.append(_internal(path, f"cross-check failed: {exc!r}"))
        if solver and hints is not None and (hints or hints.sources):
            out += _graph_findings(la, hints, configs, info, features, p, root or os.path.dirname(path), read_file)
    return out


def _graph_findings(la, hints, configs, info, features: list[str], p: Pairing, root: str,
                    read_file=None) -> list[Diagnostic]:
    """The computation graph's checks (tvl_lsp.graph.checks) of one pairing: what the nodes use
    comes from the workspace's sources and the node hints."""
    from ..graph import GraphLogic, build_graph, graph_diagnostics
    from .sources import extraction_for, node_packages
    try:
        ex = extraction_for(root, read_file, node_packages(la))
        g = build_graph(la, hints, configs, ex.by_node_type() if ex is not None else None)
        if not any(n.known for n in g.nodes.values()):
            return []
        enc = info.analysis.encoding if info is not None else None
        with GraphLogic(enc, features, info.analysis if info is not None else None) as logic:
            found = graph_diagnostics(g, logic, la)
        return [_note_pairing(d, p, root) for d in found] if info is not None else found
    except Exception as exc:
        return [_internal(la.path, f"graph check failed: {exc!r}")]



def free_top_args(text: str, path: str, workspace_root: Optional[str] = None,
                  read_file: Optional[ReadFile] = None, paired: bool = False) -> list[str]:
    """The top-level args checked as free booleans: every direct ``<arg>`` child of
    ``<launch>`` without ``value`` (a default is only what roslaunch uses when the command
    line does not set it) whose value is only ever used as a boolean -- as a whole ``if`` /
    ``unless`` value or a boolean operand inside ``$(eval)`` -- in this file and in the files
    it passes it to (``<include>`` args, ``pass_all_args``).  An arg also used as a string (a
    name, a file, a parameter value, a string comparison such as ``arg('robot') == 'pmb2'``)
    keeps its default: ``true`` / ``false`` would be meaningless there (see
    :func:`tvl_lsp.launch.ros1.loader.free_args`).  With a model, the features are added to
    these (and those naming no feature are reported as ``unmatched-arg``).  A ROS 2
    file: :func:`tvl_lsp.launch.ros2.free_args2`."""
    from ..launch import free_args_of_file
    ros2 = free_args_of_file(text, path, unused=paired)
    if ros2 is not None:
        return ros2
    from ..launch.ros1.loader import free_args
    return free_args(text, path, workspace_root, read_file)


def _note_pairing(d: Diagnostic, p: Pairing, root: str) -> Diagnostic:
    """Cross-check diagnostics say which pairing they come from (related: the pairing, its
    paths relative to the workspace root, as the Problems panel shows them)."""
    if d.witness is None and d.code not in ("missing-arg", "unmatched-arg", "dead-element", "constant-condition",
                                            "choice-mismatch"):
        return d
    if p.source_path and p.source_span and not any(r.path == p.source_path and r.span == p.source_span
                                                    for r in d.related):
        d.related = list(d.related) + [Related(p.source_path, p.source_span, p.describe(root))]
    return d


# ------------------------------------------------------------------ units of work

@dataclass(frozen=True)
class _Unit:
    model: Optional[str]           # the model this unit is about (None: unpaired launch files)
    model_wanted: bool              # report the model's own diagnostics
    launches: tuple                 # ((launch path, (Pairing, ...), workspace root), ...)
    root: Optional[str]
    timeout: Optional[float] = 10.0
    hints: tuple = ()               # ((launch path, ProjectHints, configuration names | None), ...)
    partial: frozenset = frozenset()  # ROS 2 launch files other launch files include
    cpu_budget: Optional[float] = budget.CPU_SECONDS  # CPU seconds per file (see budget.py)


# A process that ends right after its check (the ``--check`` command) sets KEEP_LAST: the last
# unit's models are then left for the process's end instead of being freed one object at a time
# (0.8-1.2 s of a 200,000-feature model's check).  The previous unit's are freed when the next
# starts, so the peak memory is the same.
KEEP_LAST = False
_KEPT: list = []


def _run_unit(unit: _Unit, read_file: Optional[ReadFile] = None) -> list[Diagnostic]:
    if _KEPT:
        import gc
        _KEPT.clear()
        gc.unfreeze()
    read_file = read_file or default_read_file
    out: list[Diagnostic] = []
    models: dict = {}
    try:
        if unit.model is not None and unit.model_wanted:
            progress = budget.Progress()

            def model_check() -> list[Diagnostic]:
                info = _load_model(unit.model, read_file, None, True, unit.timeout, progress)
                models[unit.model] = info
                if info is not None:
                    return info.diagnostics
                d = _unreadable(unit.model)
                return [d] if d is not None else []
            out += budget.limited(unit.model, model_check, unit.cpu_budget, progress,
                                  keep=_KEPT if KEEP_LAST else None)
        hints = {lf: (h, c) for lf, h, c in unit.hints}
        for lf, pairings, root in unit.launches:
            h, c = hints.get(lf, (None, None))
            try:
                out += budget.limited(lf, lambda: check_launch(lf, None, pairings, root, read_file, models,
                                                               unit.timeout, h, c, partial=lf in unit.partial),
                                      unit.cpu_budget, keep=_KEPT if KEEP_LAST else None)
            except Exception as exc:
                out.append(_internal(lf, f"check failed: {exc!r}"))
    except Exception as exc:
        out.append(_internal(unit.model or "", f"check failed: {exc!r}"))
    if KEEP_LAST:
        _KEPT.append(models)  # (what the checks made was frozen out of the collector by budget.limited)
    return out


MAX_SAME_CODE = 1000  # diagnostics of one code shown per file; the rest are summed up in one


def _dedupe_sort(diags: Iterable[Diagnostic]) -> list[Diagnostic]:
    """Sorted, without duplicates, and at most ``MAX_SAME_CODE`` diagnostics of one code per
    file: a file of 30,000 malformed or repeated tags gets 1,000 of them and one more that says
    how many were left out (on the first one left out), not 30,000 lines."""
    seen = set()
    out = []
    per: dict[tuple, int] = {}
    for d in sorted(diags, key=lambda d: (d.sort_key(), d.severity)):
        key = (d.path, d.span, d.code, d.message)
        if key in seen:
            continue
        seen.add(key)
        k = (d.path, d.code)
        n = per[k] = per.get(k, 0) + 1
        if n <= MAX_SAME_CODE:
            out.append(d)
        elif n == MAX_SAME_CODE + 1:
            out.append(d)  # becomes the summary below, once the total is known
    shown: dict[tuple, int] = {}
    for i, d in enumerate(out):
        k = (d.path, d.code)
        total = per[k]
        shown[k] = shown.get(k, 0) + 1
        if total > MAX_SAME_CODE and shown[k] == MAX_SAME_CODE + 1:
            out[i] = Diagnostic(d.code, d.severity, d.path, d.span,
                                f"... and {total - MAX_SAME_CODE:,} more [{d.code}] in this file, not listed "
                                f"(the first {MAX_SAME_CODE} are)")
    return out


def _not_checked(paths: Sequence[str]) -> list[Diagnostic]:
    """A diagnostic for each file named in ``paths`` that is not checked, saying what it was
    taken to be and why (a folder's walk passes over such files silently): an error -- the
    user asked for a check that does not happen -- but a warning for a Python launch file,
    which is a launch file tvl-lsp does not run."""
    from ..base.text import Pos, Span
    from .workspace import explicit_skip_reason
    out = []
    for p in paths:
        if not os.path.lexists(p) or os.path.isdir(p):
            continue
        why = explicit_skip_reason(p)
        if why is None:
            continue
        code = FILE_UNREADABLE if why.startswith("cannot be read") else FILE_NOT_CHECKED
        sev = Severity.WARNING if p.endswith(".launch.py") else Severity.ERROR
        out.append(Diagnostic(code, sev, norm(p), Span(Pos(0, 0), Pos(0, 0)), f"{os.path.basename(p)} is not "
                              f"checked: {why}"))
    return out


def plan(paths: Sequence[str], read_file: Optional[ReadFile] = None,
         timeout: Optional[float] = 10.0) -> tuple[list[_Unit], list[Diagnostic], int]:
    """Discover, pair and split the work into units.  Returns (units, diagnostics found while
    pairing, number of files)."""
    read_file = read_file or default_read_file
    targets = discover_files(paths)
    named = _not_checked(paths)
    roots: dict[str, list[str]] = {}
    for p in paths:
        roots.setdefault(find_workspace_root(p), []).append(p)
    workspaces: list[tuple[str, Workspace]] = []
    for r in sorted(roots):
        try:
            ws = load_workspace([r], read_file)
        except Exception:
            ws = load_workspace([r], read_file, files=Files())
        workspaces.append((r, ws))

    def ws_for(path: str) -> tuple[str, Workspace]:
        best = None
        for r, ws in workspaces:
            if path == r or path.startswith(r.rstrip(os.sep) + os.sep):
                if best is None or len(r) > len(best[0]):
                    best = (r, ws)
        return best or workspaces[0]

    pre: list[Diagnostic] = list(named)
    target_yamls = set(targets.yamls)
    for _, ws in workspaces:
        for pf in ws.projects:
            if pf.path in target_yamls:
                pre += pf.diagnostics
    by_model: dict[str, list] = {}
    alone: list = []
    root_of: dict[str, str] = {}
    hints_of: dict[str, tuple] = {}
    partial_files: set[str] = set()
    for lf in targets.launches:
        r, ws = ws_for(lf)
        root_of[lf] = r
        try:
            h, c = ws.hints_for(lf, named_only=True)
            if h or h.sources:  # hints, or a project file names it (its nodes' sources may say)
                hints_of[lf] = (lf, h, c)
        except Exception as exc:
            pre.append(_internal(lf, f"reading node hints failed: {exc!r}"))
        try:
            pairings, pdiags = ws.pair(lf)
        except Exception as exc:
            pairings, pdiags = [Pairing(lf, None, "none")], [_internal(lf, f"pairing failed: {exc!r}")]
        pre += pdiags
        modelled = [p for p in pairings if p.model is not None]
        if not modelled:
            alone.append((lf, tuple(pairings), r))
            try:
                if ws.is_partial(lf):
                    partial_files.add(lf)
            except Exception as exc:
                pre.append(_internal(lf, f"looking for includers failed: {exc!r}"))
        for p in modelled:
            by_model.setdefault(p.model, []).append((lf, (p,), r))
    target_models = set(targets.models)
    units: list[_Unit] = []
    for m in sorted(set(by_model) | target_models):
        lfs = tuple(by_model.get(m, ()))
        root = root_of[lfs[0][0]] if lfs else ws_for(m)[0]
        units.append(_Unit(m, m in target_models, lfs, root, timeout,
                           tuple(hints_of[x[0]] for x in lfs if x[0] in hints_of)))
    for i in range(0, len(alone), LAUNCH_BATCH):
        batch = tuple(alone[i:i + LAUNCH_BATCH])
        units.append(_Unit(None, False, batch, root_of[batch[0][0]], timeout,
                           tuple(hints_of[x[0]] for x in batch if x[0] in hints_of),
                           frozenset(x[0] for x in batch if x[0] in partial_files)))
    nfiles = len(targets.launches) + len(targets.models) + len(targets.yamls)
    return units, pre, nfiles


def check_paths(paths: Sequence[str], read_file: Optional[ReadFile] = None, jobs: Optional[int] = None,
                timeout: Optional[float] = 10.0, cpu_budget: Optional[float] = None) -> list[Diagnostic]:
    """Check every model, launch file and HAROS project file under ``paths``; ``cpu_budget``:
    CPU seconds per file (default ``budget.CPU_SECONDS``; 0: none)."""
    paths = [norm(p) for p in (paths or ["."])]
    units, out, nfiles = plan(paths, read_file, timeout)
    if cpu_budget is not None:
        from dataclasses import replace
        units = [replace(u, cpu_budget=cpu_budget or None) for u in units]
    auto = jobs is None
    if jobs is None:
        jobs = os.cpu_count() or 1
    jobs = max(1, min(jobs, len(units)))
    if read_file is not None or jobs == 1 or (auto and nfiles < PARALLEL_MIN_FILES):
        for u in units:
            out += _run_unit(u, read_file)
    else:
        # heaviest first (models with many launch files), results merged in submission order
        order = sorted(range(len(units)), key=lambda i: -len(units[i].launches) - (4 if units[i].model else 0))
        results: dict[int, list[Diagnostic]] = {}
        from ..base.children import watch_parent  # (the workers die with this process)
        from ..base.pools import kill_pool
        ex = ProcessPoolExecutor(max_workers=jobs, initializer=watch_parent)
        try:
            futs = {i: ex.submit(_run_unit, units[i]) for i in order}
            for i in order:
                results[i] = futs[i].result()
        except BaseException:  # Ctrl-C, SIGTERM: the workers are killed, not waited for
            kill_pool(ex)
            raise
        ex.shutdown()
        for i in range(len(units)):
            out += results[i]
    return _dedupe_sort(out)


# ------------------------------------------------------------------ the server's entry

_WS_CACHE: dict[tuple, tuple[float, Workspace]] = {}
WS_CACHE_SECONDS = 5.0


def invalidate_workspaces() -> None:
    """Forget cached workspaces (call when files are created, deleted or renamed)."""
    _WS_CACHE.clear()


def _workspace(roots: Sequence[str], read_file: ReadFile) -> Workspace:
    key = tuple(sorted(norm(r) for r in roots))
    now = time.monotonic()
    hit = _WS_CACHE.get(key)
    if hit is not None and now - hit[0] < WS_CACHE_SECONDS:
        files = hit[1].files
        return load_workspace(key, read_file, files=files)
    ws = load_workspace(key, read_file)
    _WS_CACHE[key] = (now, ws)
    return ws


def _roots_for(path: str, roots: Optional[Sequence[str]]) -> list[str]:
    if roots:
        inside = [norm(r) for r in roots if norm(path).startswith(norm(r).rstrip(os.sep) + os.sep)]
        if inside:
            return [max(inside, key=len)]
    return [find_workspace_root(path)]


def pairing_of(path: str, workspace: Optional[Workspace] = None, text: Optional[str] = None,
               roots: Optional[Sequence[str]] = None, read_file: Optional[ReadFile] = None) -> list[Pairing]:
    path = norm(path)
    read_file = read_file or default_read_file
    ws = workspace or _workspace(_roots_for(path, roots), read_file)
    return ws.pair(path, text)[0]


def check_document(path: str, text: Optional[str] = None, read_file: Optional[ReadFile] = None,
                   roots: Optional[Sequence[str]] = None, timeout: Optional[float] = 10.0,
                   workspace: Optional[Workspace] = None,
                   cpu_budget: Optional[float] = budget.CPU_SECONDS, solver: bool = True) -> list[Diagnostic]:
    """Every diagnostic of the document at ``path`` (see the module docstring), within the
    per-file budget (:mod:`budget`: past it, one ``analysis-budget-exceeded`` error).

    Without ``solver``: only what needs no SAT question -- a model's front-end diagnostics
    (syntax, types), a launch file's own diagnostics, its pairing's and the solver-free
    cross-checks (``missing-arg``, ``unmatched-arg``...) -- a subset of the full answer
    computed in milliseconds: the language server publishes it before its solver-backed
    check is done."""
    path = norm(path)
    progress = budget.Progress()
    return budget.limited(path, lambda: _check_document(path, text, read_file, roots, timeout, workspace,
                                                        progress, solver),
                          cpu_budget, progress)


def _check_document(path: str, text: Optional[str], read_file: Optional[ReadFile],
                    roots: Optional[Sequence[str]], timeout: Optional[float],
                    workspace: Optional[Workspace], progress: Optional[budget.Progress] = None,
                    solver: bool = True) -> list[Diagnostic]:
    base_read = read_file or default_read_file

    def read(p: str) -> Optional[str]:
        if text is not None and norm(p) == path:
            return text
        return base_read(p)
    read.texts = getattr(base_read, "texts", None)  # unsaved sources (the graph checks read them)

    if text is None:
        text = read(path)
    if text is None:
        d = _unreadable(path)
        return [d] if d else []
    if is_model(path):
        if not solver:
            info = _load_model(path, read, text, anomalies=False)
            return _dedupe_sort(info.diagnostics if info is not None else [])
        return _dedupe_sort(check_model(path, text, read, timeout, progress))
    if is_launch(path) or (is_xml_launch_candidate(path) and launch_root_text(text)):
        rts = _roots_for(path, roots)
        ws = workspace or _workspace(rts, read)
        pairings, pdiags = ws.pair(path, text)
        hints, configs = ws.hints_for(path, named_only=True)
        try:
            partial = ws.is_partial(path, text)
        except Exception:
            partial = False
        out = list(pdiags) + check_launch(path, text, pairings, rts[0], read, None, timeout, hints, configs,
                                          partial=partial, solver=solver)
        return _dedupe_sort(d for d in out if d.path == path)
    if is_yaml(path):
        from .workspace import parse_project
        ws = workspace or _workspace(_roots_for(path, roots), read)
        pf = parse_project(path, text, ws.all_packages or ws.packages)
        return _dedupe_sort(pf.diagnostics if pf else [])
    return []
