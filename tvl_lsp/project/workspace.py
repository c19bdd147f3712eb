"""The workspace: which files there are, which ROS packages, and which model configures which
launch file.

Pure: no LSP here.  Files are read through a ``read_file(path) -> str | None`` callback (the
server passes one that prefers the editor's unsaved buffers); only :func:`discover_files` and
:func:`find_workspace_root` look at the file system's directory structure.

Files
    ``*.tvl``, ``*.uvl`` and ``*.dimacs`` (models), ``*.launch`` / ``*.launch.xml`` (roslaunch and
    ros2/launch files), ``*.launch.yaml`` / ``*_launch.xml`` / ``*_launch.yaml`` (ros2/launch files), HAROS project files
    (a ``*.yaml`` / ``*.yml`` whose top level has ``configurations``) and ``package.xml``
    (ROS packages: its ``<name>`` names the folder it is in).  The folders ``.git``, ``build``,
    ``devel``, ``install`` and ``node_modules`` are skipped, and so are hidden folders (``.venv``,
    ``.tox``, ...) and ``__pycache__``.

Pairing a launch file with a model — the first rule that applies wins:

1. ``haros-project``: a HAROS-TVL project file names both, as the thesis writes it::

       configurations:
           {lf: turtlerand/launch/generic.launch, tvl: turtlerand/launch/generic.tvl}

   ``configurations`` may be one such mapping, a list of them, or a mapping from
   configuration names to them; paths are relative to the package folders (``turtlerand/…``
   is ``launch/generic.launch`` inside the package named ``turtlerand``), falling back to the
   project file's folder.  A plain HAROS project's ``configurations: NAME: launch: [...]``
   names launch files but pairs no model.  A launch file that several project files pair with
   different models gets one :class:`Pairing` per model.
2. ``marker``: a comment in the launch file::

       <!-- tvl-lsp: model=../models/robot.tvl -->

   In a YAML launch file: ``# tvl-lsp: model=../models/robot.tvl``.
   The path is relative to the launch file's folder (``$(find pkg)/...`` and
   ``$(find-pkg-share pkg)/...`` also work);
   ``model=none`` turns pairing off for the file (it is then checked alone).
3. ``same-stem``: ``robot.tvl`` (else ``robot.uvl``) in the same folder as ``robot.launch`` /
   ``robot.launch.xml`` / ``robot.launch.yaml``.

A model is a TVL (``.tvl``), UVL (``.uvl``) or DIMACS (``.dimacs``) file wherever a rule names it:
``tvl: pkg/robot.uvl`` in a project file, ``model=robot.uvl`` in a marker.

A launch file that none of these pair is checked alone (``Pairing.model is None``,
``rule == "none"``).  Problems with project files or markers (malformed YAML, a named file that
does not exist) are diagnostics on the project file / marker, never exceptions.
"""

from __future__ import annotations

import difflib
import os
import re
from dataclasses import dataclass, field
from typing import Callable, Iterable, Optional

from ..base.diagnostics import Diagnostic, Severity, register
from ..base.files import find_root, read_bytes, read_head, read_text_or_none, unreadable_reason
from ..base.text import LineIndex, Pos, Span
from ..graph.hints import ProjectHints, parse_hints
from ..launch.dialects import LAUNCH_SUFFIXES as _LAUNCH_SUFFIXES
from ..launch.xml import skip_prolog, strip_comments
from ..launch.dialects import launch_stem as _launch_stem

ReadFile = Callable[[str], Optional[str]]

INVALID_PROJECT = register(
    "invalid-project", Severity.ERROR,
    "A HAROS project file is malformed (YAML syntax, or a configuration that is not lf/tvl or launch).",
    "workspace")
PROJECT_FILE_NOT_FOUND = register(
    "project-file-not-found", Severity.ERROR,
    "A launch file or model named in a HAROS project file does not exist.", "workspace")
MARKER_MODEL_NOT_FOUND = register(
    "marker-model-not-found", Severity.ERROR,
    "The model named by a `<!-- tvl-lsp: model=... -->` marker does not exist.", "workspace")

SKIP_DIRS = frozenset({".git", "build", "devel", "install", "log", "node_modules"})
# roslaunch's .launch / .launch.xml; ros2/launch's .launch.xml, .launch.yaml and *_launch.xml / *_launch.yaml
LAUNCH_SUFFIXES = _LAUNCH_SUFFIXES
MODEL_SUFFIXES = (".tvl", ".uvl", ".dimacs")  # (a ".cnf" is a model when named explicitly)
YAML_SUFFIXES = (".yaml", ".yml")
MAX_PROJECT_BYTES = 2_000_000

RULE_PROJECT = "haros-project"
RULE_MARKER = "marker"
RULE_STEM = "same-stem"
RULE_NONE = "none"


def is_launch(path: str) -> bool:
    return path.endswith(LAUNCH_SUFFIXES)


def is_model(path: str) -> bool:
    return path.endswith(MODEL_SUFFIXES)


def is_yaml(path: str) -> bool:
    return path.endswith(YAML_SUFFIXES)


def launch_stem(path: str) -> str:
    return _launch_stem(path)


def default_read_file(path: str) -> Optional[str]:
    """The text of a regular file within the size cap, else None (see :mod:`base.files`)."""
    return read_text_or_none(path)


def norm(path: str) -> str:
    return os.path.normpath(os.path.abspath(path))


# ------------------------------------------------------------------ discovery

@dataclass
class Files:
    models: list[str] = field(default_factory=list)
    launches: list[str] = field(default_factory=list)
    yamls: list[str] = field(default_factory=list)
    manifests: list[str] = field(default_factory=list)  # package.xml
    # .xml / .test files whose root element is not <launch> (URDF, SDF, ...): not launch files
    skipped_xml: list[str] = field(default_factory=list)

    def extend(self, other: "Files") -> None:
        self.models += other.models
        self.launches += other.launches
        self.yamls += other.yamls
        self.manifests += other.manifests
        self.skipped_xml += other.skipped_xml

    def dedupe(self) -> "Files":
        return Files(*(sorted(set(lst)) for lst in
                       (self.models, self.launches, self.yamls, self.manifests, self.skipped_xml)))


def is_xml_launch_candidate(path: str) -> bool:
    """A ``.xml`` / ``.test`` file that may be a launch file (rostest files, launch files named
    ``*.xml``): it is one when its root element is ``<launch>``."""
    return path.endswith((".xml", ".test")) and os.path.basename(path) != "package.xml"


def launch_root_text(text: str) -> bool:
    """Whether an XML text's root element is ``<launch>`` (the XML declaration, comments and a
    DOCTYPE before it skipped)."""
    head = skip_prolog(text[:65536])
    return head.startswith("<launch") and (len(head) == 7 or not head[7].isalnum())


def _looks_like_launch(path: str) -> bool:
    """An ``.xml`` / ``.test`` file whose root element is ``<launch>``."""
    if not is_xml_launch_candidate(path):
        return False
    head = read_head(path, 16384)
    if head is None:
        return False
    return launch_root_text(head.decode("utf-8", "replace"))


def _classify(path: str, out: Files, explicit: bool = False) -> None:
    base = os.path.basename(path)
    if is_model(path) or (explicit and path.endswith(".cnf")):
        out.models.append(path)
    elif is_launch(path):
        out.launches.append(path)
    elif is_xml_launch_candidate(path):
        # named explicitly, an XML / rostest file is checked as the launch file it is said to be
        # (roslaunch rejects one whose root is not <launch>: so does the check); found by walking
        # a folder, only one with a <launch> root is
        (out.launches if explicit or _looks_like_launch(path) else out.skipped_xml).append(path)
    elif is_yaml(path):
        out.yamls.append(path)
    elif base == "package.xml":
        out.manifests.append(path)


def explicit_skip_reason(path: str) -> Optional[str]:
    """Why ``--check`` does not check a file named on the command line: what the file is taken
    to be and why that is not checked (one line); None when it is checked (a model, a launch
    file, an XML/rostest file with a ``<launch>`` root, a HAROS project file)."""
    base = os.path.basename(path)
    why = unreadable_reason(path)
    if why is not None:
        return f"cannot be read: {why}"
    if is_model(path) or is_launch(path) or is_xml_launch_candidate(path) or path.endswith(".cnf"):
        return None  # (a .cnf named on the command line is read as a DIMACS model; an .xml/.test file as
        # a launch file: one whose root is not <launch> gets roslaunch's own error)
    accepted = ("--check reads only models (.tvl, .uvl, .dimacs), launch files (.launch, .launch.xml, .launch.yaml, "
                ".launch.py, or .xml/.test with a <launch> root) and HAROS project files (YAML with a top-level "
                "`configurations:`)")
    head = read_head(path, 4096)
    if head is None:
        return "cannot be read"
    if path.endswith((".launch.yaml", ".launch.yml")):
        return "taken to be a ROS 2 YAML launch file, which --check does not read yet"
    if is_yaml(path):
        if _looks_like_project(path):
            return None
        return ("taken to be a plain YAML file, not a HAROS project file: it has no top-level "
                "`configurations:`")
    if base == "package.xml":
        return "taken to be a catkin package manifest: it is read for package names, not checked"
    if path.endswith((".xml", ".test")):
        text = skip_prolog(head.decode("utf-8", "replace"))
        m = re.match(r"\s*<([\w:.-]+)", text)
        root = f"<{m.group(1)}>" if m else "no element"
        return f"taken to be XML other than a launch file: its root is {root}, not <launch>"
    if b"\0" in head:
        return "taken to be a binary file; " + accepted
    suffix = os.path.splitext(base)[1]
    kind = f"a {suffix} file" if suffix else "a file without a suffix"
    return f"taken to be {kind}; {accepted}"


def discover_files(paths: Iterable[str]) -> Files:
    """Walk ``paths`` (files or folders) and classify what is found; sorted, absolute."""
    out = Files()
    for p in paths:
        p = norm(p)
        if os.path.isdir(p):
            for dirpath, dirnames, filenames in os.walk(p, followlinks=False):
                dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and not d.startswith(".")
                                     and d != "__pycache__")
                for fn in filenames:
                    _classify(os.path.join(dirpath, fn), out)
        elif os.path.isfile(p):
            _classify(p, out, explicit=True)
        # anything else named explicitly (a device, a FIFO, a broken link) is not read: the
        # command line says why (explicit_skip_reason)
    return out.dedupe()


def find_workspace_root(path: str, max_up: int = 12) -> str:
    """The folder to look for packages and project files in when only ``path`` is given.

    The nearest ancestor holding a catkin marker, ``.git`` or a HAROS project file; failing
    that, the ``src`` folder's parent when ``path`` is inside a ``src`` folder; failing that,
    the folder of ``path`` itself.
    """
    p = norm(path)
    d = p if os.path.isdir(p) else os.path.dirname(p)
    return find_root(d, lambda cur, names: any(n.endswith(YAML_SUFFIXES) and _looks_like_project(os.path.join(cur, n))
                                               for n in names), max_up)


def _looks_like_project(path: str) -> bool:
    try:
        head = read_bytes(path, MAX_PROJECT_BYTES)
    except (OSError, ValueError):
        return False
    return re.search(rb"(?m)^configurations\s*:", head) is not None


# ------------------------------------------------------------------ packages

_NAME_RE = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_COMMENT_RE = re.compile(r"<!--.*?-->", re.S)


def package_name(manifest_text: str) -> Optional[str]:
    m = _NAME_RE.search(strip_comments(manifest_text))
    return m.group(1) if m else None


def find_all_packages(manifests: Iterable[str], read_file: ReadFile = default_read_file) -> dict[str, list[str]]:
    """package name -> every folder with a package.xml of that name (shortest path first)."""
    found: dict[str, list[str]] = {}
    for m in sorted(manifests, key=lambda p: (p.count(os.sep), p)):
        text = read_file(m)
        if text is None:
            continue
        name = package_name(text)
        if name:
            found.setdefault(name, []).append(os.path.dirname(m))
    return found


def find_packages(manifests: Iterable[str], read_file: ReadFile = default_read_file) -> dict[str, str]:
    """package name -> package folder.  With several folders of one name, the shortest path wins
    (as catkin's overlay order would pick the workspace's own over a nested copy)."""
    return {k: v[0] for k, v in find_all_packages(manifests, read_file).items()}


def nearest_package(name: str, near: str, packages: dict) -> Optional[str]:
    """The folder of package ``name`` closest to the folder ``near`` (longest common path):
    a project file or launch file means the package of its own workspace."""
    cands = packages.get(name)
    if not cands:
        return None
    if isinstance(cands, str):
        return cands

    def score(folder: str) -> tuple:
        try:
            common = os.path.commonpath([folder, near])
        except ValueError:
            common = ""
        return (-len(common), folder.count(os.sep), folder)
    return min(cands, key=score)


# ------------------------------------------------------------------ pairing

@dataclass(frozen=True)
class Pairing:
    """Which model configures a launch file, and which rule said so."""
    launch: str
    model: Optional[str]
    rule: str  # "haros-project" | "marker" | "same-stem" | "none"
    source_path: Optional[str] = None  # the project file / the launch file (marker) / None
    source_span: Optional[Span] = None  # where in source_path the pairing is written
    configuration: Optional[str] = None  # the project file's configuration name, if any

    def describe(self, relto: Optional[str] = None) -> str:
        def rel(p: str) -> str:
            if relto:
                try:
                    return os.path.relpath(p, relto)
                except ValueError:
                    return p
            return p
        if self.model is None:
            return "not paired with a model: its top-level args are free booleans"
        where = ""
        if self.source_path and self.source_span:
            where = f" ({rel(self.source_path)}:{self.source_span.start})"
        how = {RULE_PROJECT: "by a HAROS project file", RULE_MARKER: "by a tvl-lsp marker",
               RULE_STEM: "by the same file name"}.get(self.rule, self.rule)
        return f"paired with {rel(self.model)} {how}{where}"


@dataclass
class ProjectConfiguration:
    name: Optional[str]
    launches: list[tuple[str, Span]]  # resolved path, span of the value in the project file
    model: Optional[tuple[str, Span]]
    span: Span


@dataclass
class ProjectFile:
    path: str
    configurations: list[ProjectConfiguration] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # the node hints (`nodes:` and per-configuration `hints:`, tvl_lsp.graph.hints)
    hints: ProjectHints = field(default_factory=ProjectHints)


def _mark_pos(mark) -> Pos:
    return Pos(mark.line, mark.column)


def _node_span(node) -> Span:
    s, e = node.start_mark, node.end_mark
    # a plain multi-line scalar's end mark can sit past trailing blanks; clamp to start if odd
    if (e.line, e.column) < (s.line, s.column):
        e = s
    return Span(_mark_pos(s), _mark_pos(e))


def _resolve_pkg_path(rel: str, base_dir: str, packages: dict[str, str]) -> tuple[Optional[str], str]:
    """HAROS paths are ``package/path/in/package``.  Returns (path or None, reason)."""
    rel = rel.strip()
    m = re.match(r"\$\(find\s+([^)\s]+)\)/?(.*)$", rel)
    if m:
        pkg, rest = m.group(1), m.group(2)
    else:
        pkg, _, rest = rel.partition("/")
    cands = []
    folder = nearest_package(pkg, base_dir, packages)
    if folder is not None:
        cands.append(os.path.join(folder, rest))
    if not m:
        cands.append(os.path.join(base_dir, rel))
        cands.append(os.path.join(base_dir, "src", rel))
    for c in cands:
        if os.path.isfile(c):
            return norm(c), ""
    if not m and "/" not in rel:
        return None, "there is no such file next to the project file (HAROS paths are package/path/in/package)"
    if pkg not in packages:
        close = difflib.get_close_matches(pkg, sorted(packages), n=1)
        hint = f"; did you mean `{close[0]}`?" if close else ""
        return None, f"no package `{pkg}` in the workspace and no file `{rel}`{hint}"
    return None, f"`{rest}` does not exist in package `{pkg}` ({folder})"


def parse_project(path: str, text: str, packages: dict) -> Optional[ProjectFile]:
    """Parse a HAROS project file.  ``None`` if the YAML is not a project file at all (valid
    YAML without ``configurations``); malformed YAML that looks like one gets a diagnostic."""
    import yaml

    from ..base import yamlsafe

    pf = ProjectFile(path=path)
    base_dir = os.path.dirname(path)

    def diag(code: str, span: Span, msg: str, sev: Severity = Severity.ERROR) -> None:
        pf.diagnostics.append(Diagnostic(code, sev, path, span, msg))

    try:
        root = yamlsafe.compose(text)
    except yaml.YAMLError as exc:
        if not re.search(r"(?m)^configurations\s*:", text):
            return None
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        pos = _mark_pos(mark) if mark is not None else Pos(0, 0)
        idx = LineIndex(text)
        end = idx.pos(idx.offset(pos) + 1)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        diag(INVALID_PROJECT, Span(pos, max(end, pos)), f"the HAROS project file is not valid YAML: {problem}")
        return pf
    except Exception as exc:  # recursion limits and the like: never crash on bad input
        if not re.search(r"(?m)^configurations\s*:", text):
            return None
        diag(INVALID_PROJECT, Span(Pos(0, 0), Pos(0, 0)), f"the HAROS project file cannot be read: {exc}")
        return pf

    if not isinstance(root, yaml.MappingNode):
        return None
    confs = None
    for k, v in root.value:
        if isinstance(k, yaml.ScalarNode) and k.value == "configurations":
            confs = (k, v)
    if confs is None:
        return None
    key_node, node = confs

    def scalars(n, what: str) -> list:
        if isinstance(n, yaml.ScalarNode):
            if n.value.strip() == "":
                diag(INVALID_PROJECT, _node_span(n), f"`{what}` is empty")
                return []
            return [n]
        if isinstance(n, yaml.SequenceNode):
            out = []
            for item in n.value:
                if isinstance(item, yaml.ScalarNode) and item.value.strip():
                    out.append(item)
                else:
                    diag(INVALID_PROJECT, _node_span(item), f"each item of `{what}` must be a file path")
            return out
        diag(INVALID_PROJECT, _node_span(n), f"`{what}` must be a file path or a list of file paths")
        return []

    def resolve(n, what: str) -> Optional[str]:
        p, why = _resolve_pkg_path(n.value, base_dir, packages)
        if p is None:
            diag(PROJECT_FILE_NOT_FOUND, _node_span(n), f"{what} `{n.value.strip()}` not found: {why}")
        return p

    def config(n, name: Optional[str], name_node=None) -> None:
        span = _node_span(name_node if name_node is not None else n)
        if not isinstance(n, yaml.MappingNode):
            diag(INVALID_PROJECT, _node_span(n),
                 "a configuration must be a mapping with `lf` and `tvl` (HAROS-TVL) or `launch` (HAROS)")
            return
        keys = {k.value: (k, v) for k, v in n.value if isinstance(k, yaml.ScalarNode)}
        launch_key = "lf" if "lf" in keys else "launch" if "launch" in keys else None
        launches: list[tuple[str, Span]] = []
        model = None
        if launch_key is not None:
            for s in scalars(keys[launch_key][1], launch_key):
                p = resolve(s, "launch file")
                if p is not None:
                    if not is_launch(p):
                        diag(INVALID_PROJECT, _node_span(s), f"`{s.value.strip()}` is not a launch file (.launch, .launch.xml)",
                             Severity.WARNING)
                    launches.append((p, _node_span(s)))
        if "tvl" in keys:
            ss = scalars(keys["tvl"][1], "tvl")
            if len(ss) > 1:
                diag(INVALID_PROJECT, _node_span(keys["tvl"][1]), "`tvl` names one model, not a list")
            if ss:
                p = resolve(ss[0], "model")
                if p is not None:
                    model = (p, _node_span(ss[0]))
        if launch_key == "lf" and "tvl" not in keys:
            close = difflib.get_close_matches("tvl", [k for k in keys if k != "lf"], n=1, cutoff=0.5)
            hint = f" (is `{close[0]}` a typo for `tvl`?)" if close else ""
            diag(INVALID_PROJECT, _node_span(keys["lf"][0]), f"a HAROS-TVL configuration with `lf` needs `tvl`, the model{hint}")
        if launch_key is None:
            where = _node_span(name_node) if name_node is not None else _node_span(n)
            if "tvl" in keys:
                diag(INVALID_PROJECT, _node_span(keys["tvl"][0]), "a configuration with `tvl` needs `lf`, the launch file")
            else:
                diag(INVALID_PROJECT, where, "a configuration needs `lf` and `tvl` (HAROS-TVL) or `launch` (HAROS)")
        pf.configurations.append(ProjectConfiguration(name, launches, model, span))

    if isinstance(node, yaml.MappingNode):
        keys = [k.value for k, _ in node.value if isinstance(k, yaml.ScalarNode)]
        if any(k in ("lf", "tvl", "launch") for k in keys):
            config(node, None)
        else:
            for k, v in node.value:
                config(v, k.value if isinstance(k, yaml.ScalarNode) else None, k)
    elif isinstance(node, yaml.SequenceNode):
        for item in node.value:
            config(item, None)
    elif isinstance(node, yaml.ScalarNode) and node.value == "":
        diag(INVALID_PROJECT, _node_span(key_node), "`configurations` is empty", Severity.WARNING)
    else:
        diag(INVALID_PROJECT, _node_span(node), "`configurations` must be a mapping or a list of configurations")
    pf.hints = parse_hints(path, text)
    pf.diagnostics += pf.hints.diagnostics
    return pf


MARKER_RE = re.compile(
    r"<!--\s*tvl-lsp\s*:\s*model\s*=\s*(?:\"(?P<q>[^\"]*)\"|'(?P<s>[^']*)'|(?P<p>[^\s\"'>]+?))\s*-->"
    # a YAML launch file's comment: # tvl-lsp: model=robot.tvl
    r"|(?m:^[ \t]*#\s*tvl-lsp\s*:\s*model\s*=\s*(?:\"(?P<q2>[^\"\n]*)\"|'(?P<s2>[^'\n]*)'|(?P<p2>[^\s\"']+))[ \t]*$)")


def find_marker(text: str) -> Optional[tuple[str, int, int]]:
    """The ``<!-- tvl-lsp: model=PATH -->`` marker: (PATH, start offset, end offset of PATH)."""
    m = MARKER_RE.search(text)
    if not m:
        return None
    g = next(k for k in ("q", "s", "p", "q2", "s2", "p2") if m.group(k) is not None)
    return m.group(g), m.start(g), m.end(g)


@dataclass
class Workspace:
    """Everything known about a tree of files.  Build it with :func:`load_workspace`."""
    roots: tuple[str, ...]
    files: Files
    packages: dict[str, str]            # name -> folder (the shortest path of that name)
    projects: list[ProjectFile]
    read_file: ReadFile = default_read_file
    all_packages: dict[str, list[str]] = field(default_factory=dict)
    # launch path -> pairings from project files (rule 1), in project-file order
    project_pairings: dict[str, list[Pairing]] = field(default_factory=dict)

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return [d for p in self.projects for d in p.diagnostics]

    def package_of(self, path: str) -> Optional[str]:
        """The name of the package whose folder contains ``path``."""
        best = None
        for name, folder in self.packages.items():
            if path.startswith(folder + os.sep) and (best is None or len(folder) > len(self.packages[best])):
                best = name
        return best

    def pair(self, launch: str, text: Optional[str] = None) -> tuple[list[Pairing], list[Diagnostic]]:
        """Pairings of one launch file (``text`` = its current content, e.g. an unsaved buffer),
        and diagnostics about its marker.  Always at least one Pairing (rule ``none`` when alone)."""
        launch = norm(launch)
        if launch in self.project_pairings:
            return list(self.project_pairings[launch]), []
        if text is None:
            text = self.read_file(launch) or ""
        diags: list[Diagnostic] = []
        mk = find_marker(text)
        if mk is not None:
            ref, s, e = mk
            idx = LineIndex(text)
            span = idx.span(s, e)
            if ref.strip().lower() == "none":
                return [Pairing(launch, None, RULE_MARKER, launch, span)], []
            m = re.match(r"\$\((?:find|find-pkg-share)\s+([^)\s]+)\)/?(.*)$", ref)
            if m:
                folder = nearest_package(m.group(1), os.path.dirname(launch), self.all_packages or self.packages)
                cand = norm(os.path.join(folder, m.group(2))) if folder else None
            else:
                cand = norm(os.path.join(os.path.dirname(launch), ref))
            if cand and self._exists(cand):
                return [Pairing(launch, cand, RULE_MARKER, launch, span)], []
            why = (f"package `{m.group(1)}` is not in the workspace" if m and not self.packages.get(m.group(1))
                   else f"`{ref}` does not exist")
            diags.append(Diagnostic(MARKER_MODEL_NOT_FOUND, Severity.ERROR, launch, span,
                                    f"the model named by this tvl-lsp marker was not found: {why}"))
        for suffix in (".tvl", ".uvl"):
            stem = os.path.join(os.path.dirname(launch), launch_stem(launch) + suffix)
            if self._exists(stem):
                return [Pairing(launch, stem, RULE_STEM)], diags
        return [Pairing(launch, None, RULE_NONE)], diags

    def _exists(self, path: str) -> bool:
        return path in self._model_set or os.path.isfile(path)

    @property
    def _model_set(self) -> set[str]:
        s = getattr(self, "_models_cache", None)
        if s is None:
            s = set(self.files.models)
            object.__setattr__(self, "_models_cache", s)
        return s

    def hints_for(self, launch: str, named_only: bool = False) -> tuple[ProjectHints, Optional[list[str]]]:
        """The node hints that apply to ``launch``: those of the project files whose
        configurations name it (with those configurations' names, for per-node-name hints);
        when none names it, those of every project file of the workspace (configurations:
        None, all) -- or none with ``named_only`` (the check pipeline: a launch file no project
        names is a fragment, included by the applications that are named)."""
        launch = norm(launch)
        naming = [(pf, c) for pf in self.projects for c in pf.configurations
                  if any(norm(lf) == launch for lf, _ in c.launches)]
        if not naming and named_only:
            return ProjectHints(), None
        files = list(dict.fromkeys(pf.path for pf, _ in naming)) if naming else [pf.path for pf in self.projects]
        configs = [c.name for _, c in naming if c.name] if naming else None
        out = ProjectHints()
        for pf in self.projects:
            if pf.path in files and pf.hints:
                out = out.merge(pf.hints)
        if naming:  # the project files that name it, with hints or not (the graph checks run for it)
            out.sources = list(dict.fromkeys(out.sources + files))
        return out, configs

    def included_launch_names(self) -> set[str]:
        """Base names of the launch files some launch file of the workspace includes."""
        got = getattr(self, "_included_cache", None)
        if got is None:
            from ..launch import include_targets
            got = set()
            for lf in self.files.launches:
                text = self.read_file(lf)
                if text:
                    got |= include_targets(text)
            object.__setattr__(self, "_included_cache", got)
        return got

    def is_partial(self, launch: str, text: Optional[str] = None) -> bool:
        """A ROS 2 launch file that another launch file includes: it may read launch
        configurations its includers set (ros2/launch does not scope them) without declaring
        them.  Checked on its own, such reads are not errors (see ``analyse_launch2``)."""
        if os.path.basename(launch) not in self.included_launch_names():
            return False
        from ..launch import dialect_of
        return dialect_of(launch, text).ros2

    def launches_for_model(self, model: str) -> list[Pairing]:
        """Every pairing of a launch file of this workspace with ``model``."""
        model = norm(model)
        out = []
        for lf in self.files.launches:
            for p in self.pair(lf)[0]:
                if p.model == model:
                    out.append(p)
        return out


def load_workspace(roots: Iterable[str], read_file: Optional[ReadFile] = None,
                   files: Optional[Files] = None) -> Workspace:
    """Discover files under ``roots`` (unless ``files`` is given), find packages and read the
    HAROS project files."""
    read_file = read_file or default_read_file
    roots = tuple(sorted({norm(r) for r in roots}))
    files = files if files is not None else discover_files(roots)
    all_packages = find_all_packages(files.manifests, read_file)
    packages = {k: v[0] for k, v in all_packages.items()}
    projects: list[ProjectFile] = []
    for y in files.yamls:
        try:
            if os.path.getsize(y) > MAX_PROJECT_BYTES:
                continue
        except OSError:
            pass
        text = read_file(y)
        if text is None or "configurations" not in text:
            continue
        pf = parse_project(y, text, all_packages)
        if pf is not None:
            projects.append(pf)
    ws = Workspace(roots, files, packages, projects, read_file, all_packages)
    for pf in projects:
        for c in pf.configurations:
            for lf, span in c.launches:
                if c.model is None:
                    continue
                lst = ws.project_pairings.setdefault(lf, [])
                if all(p.model != c.model[0] for p in lst):
                    lst.append(Pairing(lf, c.model[0], RULE_PROJECT, pf.path, span, c.name))
    return ws
