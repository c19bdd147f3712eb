"""Plain data produced by the launch front end (no LSP types)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

from ..base.formula import FALSE, Formula
from ..base.diagnostics import Diagnostic, Severity
from ..base.text import Span


@dataclass(frozen=True)
class Attr:
    name: str
    value: str
    name_span: Span
    value_span: Span


@dataclass(frozen=True)
class Subst:
    """One ``$(...)`` inside an attribute value: kind is the command (``arg``, ``find``,
    ``env``, ``optenv``, ``anon``, ``dirname``, ``eval`` or an unknown word), args its
    words, span the whole ``$(...)`` in the source, attr the attribute holding it."""
    kind: str
    args: tuple[str, ...]
    span: Span
    attr: str
    # the exact range of the argument name (X of ``$(var X)``, the 'x' of a Python
    # ``LaunchConfiguration('x')``) when the front end knows it; None: find it in the text
    name_span: Optional[Span] = None


@dataclass(eq=False)
class Element:
    """One XML element as loaded from one file at one include site.

    ``condition`` is the formula over arg names (feature args) under which roslaunch
    processes the element (its own if/unless and those of all its ancestors and of the
    include chain); FALSE if it is never loaded (e.g. children of a non-node tag)."""
    tag: str
    span: Span
    attrs: dict[str, Attr]
    path: str
    condition: Formula = FALSE
    parent: Optional["Element"] = None
    children: list["Element"] = field(default_factory=list)
    substitutions: list[Subst] = field(default_factory=list)
    tag_span: Optional[Span] = None
    text: str = ""
    include_depth: int = 0     # 0: the analysed file; n: n includes deep
    unresolved: bool = False   # <include> whose file is outside the workspace / unknown
    resolved_file: Optional[str] = None  # <include>: the file that was followed

    def __repr__(self) -> str:  # keep reprs short (the tree is cyclic)
        return f"Element(<{self.tag}> {self.path}:{self.span.start} if {self.condition})"


@dataclass
class ArgDecl:
    name: str
    span: Span               # the <arg> start tag
    name_span: Span          # the VALUE of the name attribute
    default: Optional[str] = None
    value: Optional[str] = None
    doc: Optional[str] = None
    path: str = ""
    element: Optional[Element] = None


@dataclass(frozen=True)
class RemapCase:
    """A ``<remap>`` that applies to a node when ``condition`` holds (the node's condition, the
    remap's own if/unless and its scope's; ``False`` where a later remap with the same ``from``
    replaces it, as roslaunch does).  ``from_`` / ``to`` as written (canonicalized, not resolved:
    the node resolves them in its own namespace)."""
    from_: str
    to: str
    condition: Formula
    element: Element


@dataclass
class NodeFact:
    """A node roslaunch loads when ``condition`` holds. ``name`` is the resolved global name
    (``/ns/talker``); when the name depends on an arg value there is one fact per case, with
    the case in the condition. ``is_test``: a <test> tag (not a node for duplicates)."""
    name: str
    pkg: str
    type: str
    namespace: str
    element: Element
    condition: Formula
    path: str = ""
    args: str = ""
    remaps: list[tuple[str, str]] = field(default_factory=list)
    is_test: bool = False
    # every remap that applies in some case, in roslaunch's order, with its condition
    remap_cases: list[RemapCase] = field(default_factory=list)


@dataclass
class ErrorFact:
    """A load-time error roslaunch raises (or a warning it prints) when ``condition`` holds.

    ``condition`` is a formula over the free (feature) args; it already includes the
    element's presence condition ("reached"), so the fact fires exactly for the assignments
    under which roslaunch, processing the file in document order, gets to this check and
    fails it (an earlier error would stop roslaunch first: facts do not model that).
    Facts no assignment can trigger are dropped when the formula has few variables.

    Codes (all registered in :data:`tvl_lsp.base.diagnostics.CODES`, area "launch"):

    - ``undefined-arg``: ``$(arg X)`` evaluated where X is not declared in scope
      (reached and not declared; roslaunch: "requires the 'X' arg to be set" or, inside an
      ``<arg>``, "arg 'X' is not defined");
    - ``unset-arg``: ``$(arg X)`` where X is declared without value/default and nothing
      sets it (a required arg used but never set);
    - ``duplicate-arg``: an ``<arg>`` declared twice in the same scope ("has already been
      declared"); the paired if/unless pattern never triggers it;
    - ``arg-already-set``: ``<arg value=...>`` for an arg that already has a value
      ("cannot override arg");
    - ``arg-value-and-default``: both value and default;
    - ``invalid-condition``: if/unless evaluates to something other than true/false/1/0;
    - ``if-and-unless``: both on one tag;
    - ``duplicate-node``: two nodes with the same resolved name both loaded (c1 and c2;
      ``related`` points at the other node);
    - ``unused-include-arg``: an arg passed to an include that the included file never
      declares ("unused args [x] for include of [f]");
    - ``include-arg-no-value``: an ``<arg>`` inside ``<include>`` without value/default;
    - ``include-not-found`` / ``include-invalid`` / ``include-cycle`` / ``include-too-deep``;
    - ``missing-attribute``, ``invalid-attribute-value``, ``node-name-namespace``,
      ``empty-ns``, ``respawn-and-required``, ``param-value-count``, ``invalid-param``,
      ``command-not-found``, ``file-not-found``, ``invalid-remap``, ``invalid-env``,
      ``invalid-machine``, ``invalid-test``: the checks of roslaunch's XmlLoader, with its
      wording;
    - ``substitution-syntax``, ``unknown-substitution``, ``substitution-arity``,
      ``eval-error``, ``env-not-set``: ``$(...)`` errors;
    - ``package-not-found``: only in the concrete loader (the symbolic analysis marks an
      include of a package outside the workspace ``unresolved`` instead);
    - ``illegal-node-name``, ``launch-if-unless`` (warnings; the latter is an error when
      roslaunch would crash), ``condition-not-analysable`` (information, condition TRUE),
      ``launch-analysis-budget`` (warning).
    """
    code: str
    severity: Severity
    message: str
    path: str
    span: Span
    condition: Formula
    related: list[tuple[str, Span, str]] = field(default_factory=list)
    # the arg a fact is about, where that matters (unset-arg of a free arg); keyword-only, so that
    # subclasses (ROS 2's LaunchFact) keep their positional fields
    arg: Optional[str] = field(default=None, kw_only=True)


@dataclass
class IncludeFact:
    element: Element
    file: Optional[str]        # resolved file name (None if it could not be resolved)
    condition: Formula
    followed: bool
    package: Optional[str] = None
    children: list["IncludeFact"] = field(default_factory=list)
    namespace: str = "/"
    outside: bool = False      # outside the workspace: not read (:func:`outside_reach`)


class Reach:
    """The folders a launch analysis reads in (the workspace and its packages), their links
    resolved once, and the answers for the paths asked about (an include bomb asks thousands
    of times)."""

    def __init__(self, folders):
        import os
        self.folders = list(folders)
        real = set()
        for f in self.folders:
            try:
                real.add(os.path.realpath(f).rstrip(os.sep) or os.sep)
            except (OSError, ValueError):
                pass
        self._prefixes = tuple(sorted(r if r.endswith(os.sep) else r + os.sep for r in real))
        self._roots = real
        self._memo: dict[str, bool] = {}

    def outside(self, path: str) -> bool:
        """An existing file outside the reach (links resolved)?"""
        got = self._memo.get(path)
        if got is None:
            import os
            try:
                real = os.path.realpath(path)
                got = os.path.lexists(path) and not (real in self._roots or real.startswith(self._prefixes))
            except (OSError, ValueError):
                got = False
            if len(self._memo) > 100_000:
                self._memo.clear()
            self._memo[path] = got
        return got


def outside_reach(path: str, reach) -> bool:
    """The one rule for includes outside the workspace, in every command (``--check``, the
    editor, ``tvl-lsp launch``, ``graph``, the configurator): a launch analysis reads a file
    only when it lies -- once its symbolic links are resolved -- in its *reach*: the workspace
    and the folders of the packages ``$(find)`` / ``$(find-pkg-share)`` resolve to (see
    docs/architecture.md, "Includes outside the workspace").  True for an existing file outside
    it (a missing one is ``include-not-found``'s business).  ``reach``: a :class:`Reach`, a
    list of folders, or None (no reach: nothing is outside)."""
    if reach is None:
        return False
    if not isinstance(reach, Reach):
        reach = Reach(reach)
    return reach.outside(path)


def outside_message(shown_name: str, path: str) -> str:
    """``include-outside-workspace``'s message."""
    import os
    how = " (it is a symbolic link to a file outside it)" if os.path.islink(path) else ""
    return (f"'{shown_name}' is outside the workspace{how}: tvl-lsp does not read files outside the workspace "
            "and its packages, so what it starts is not analysed, listed or drawn (move it into a package of "
            "the workspace, or open the workspace that holds it)")


@dataclass
class ParamFact:
    """A parameter roslaunch sets when ``condition`` holds: ``name`` (global, canonical),
    ``value`` as text for people (a ``textfile`` / ``binfile`` by its path, a ``command`` by its
    command line), ``data`` the value roslaunch sets (``int``, ``float``, ``bool``, ``str``,
    lists and dicts from YAML, ...; the path / command line for the three file and command
    sources), ``source``: ``value`` (a ``<param value>``), ``yaml`` (a ``<rosparam>``),
    ``textfile``, ``binfile`` or ``command``.  Facts come in roslaunch's order: for one name
    the last fact that holds wins."""
    name: str
    value: str
    element: Element
    condition: Formula
    data: Any = None
    source: str = "value"


@dataclass
class LaunchAnalysis:
    path: str
    diagnostics: list[Diagnostic]
    feature_args: list[ArgDecl]
    free_args: list[str]                # args treated as free booleans in the symbolic load
    elements: list[Element]
    nodes: list[NodeFact]
    facts: list[ErrorFact]
    includes: list[IncludeFact]
    params: list[ParamFact]
    root: Optional[Element] = None
    dialect: str = "ros1"               # "ros1" (roslaunch) or "ros2" (ros2/launch)
    # ROS 2: top-level args with <choice> values: name -> (values, the <arg> element)
    choices: dict = field(default_factory=dict)
    # free args declared without value or default whose value the load uses: roslaunch run with
    # the file's defaults fails on them (a paired model's features are set by its configurations)
    required_args: list[str] = field(default_factory=list)
    # ROS 2: (path, span) of if/unless values tvl-lsp cannot compute in some case (e.g. a launch
    # configuration a file that includes this one sets): neither dead nor constant
    unknown_conditions: list = field(default_factory=list)
    # False: the front end could not follow all of the file (a Python launch file where it
    # declined): an argument it did not see declared may be declared there
    complete: bool = True


@dataclass
class LoadResult:
    """What roslaunch loads for one assignment of args (first error in ``error``).

    ``params``: name -> the value roslaunch sets (typed, see :class:`ParamFact` ``data``);
    ``param_sources``: name -> ``textfile`` / ``binfile`` / ``command`` for the parameters
    shown by path or command line instead of their content; ``param_text``: name -> the value
    as text for people."""
    nodes: list[dict]
    params: dict[str, Any]
    remaps: list[dict]
    includes: list[dict]
    error: Optional[str]
    error_code: Optional[str] = None
    warnings: list[str] = field(default_factory=list)
    param_sources: dict[str, str] = field(default_factory=dict)
    param_text: dict[str, str] = field(default_factory=dict)


def json_value(v: Any) -> Any:
    """A parameter value as JSON (``tvl-lsp launch --json``): YAML's types as they are,
    ``!!binary`` as ``{"__binary__": length}``, dates as ``{"__date__": iso}``, non-finite
    floats as ``{"__float__": "nan" | "inf" | "-inf"}``, anything else as ``{"__repr__": ...}``."""
    import datetime
    import math
    if isinstance(v, bytes):
        return {"__binary__": len(v)}
    if v is None or isinstance(v, (bool, int, str)):
        return v
    if isinstance(v, float):
        return v if math.isfinite(v) else {"__float__": repr(v)}
    if isinstance(v, (list, tuple)):
        return [json_value(x) for x in v]
    if isinstance(v, dict):
        return {str(k): json_value(x) for k, x in v.items()}
    if isinstance(v, (datetime.date, datetime.datetime)):
        return {"__date__": v.isoformat()}
    return {"__repr__": repr(v)}
