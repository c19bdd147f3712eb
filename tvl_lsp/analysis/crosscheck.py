"""Cross-file, variability-aware checks of a launch file against the model that configures it.

Pure: no LSP here.  Entry point::

    cross_check(launch: LaunchAnalysis, model: Model | None, encoding: Encoding | None = None,
                *, launch_text: str | None = None, model_path: str | None = None) -> list[Diagnostic]

It returns the diagnostics *of the launch file* for this pairing (the model's own diagnostics
are the model's, see :func:`tvl_lsp.project.check.check_model`):

- ``missing-arg``: a feature with no top-level ``<arg>`` (on the ``<launch>`` start tag; related:
  the feature; ``data = {"feature": NAME}``; a fix inserting ``<arg name="NAME"/>``);
- ``unmatched-arg``: a top-level ``<arg>`` naming no feature (the closest feature suggested);
- every load-time error fact of the launch front end (``undefined-arg``, ``duplicate-arg``,
  ``unset-arg``, ``invalid-condition``, ``duplicate-node``, ...) whose condition holds in some
  product of the model, with a witness; facts no product can trigger are dropped; a fact inside
  an included file is reported on the ``<include>`` of this file (related: where it is); an
  "unset" arg whose every declaration has a default (whose evaluation failed, e.g. an unset
  ``$(env)``: roslaunch stops there, and that is reported) is not reported again;
- an ``undefined-arg`` message also names the further undeclared ``$(arg)`` of the same value
  (roslaunch, and the launch front end, stop at the first);
- ``dead-element``: an element that no product loads (only the topmost of a dead subtree);
- ``constant-condition``: an ``if`` / ``unless`` with the same value in every product where it is
  evaluated (i.e. where the element's parent is loaded); not reported inside dead elements.

Feature args map to features by name (a feature's short name, or its long name when the short
one is ambiguous).  Top-level args that name no feature — and, in a launch file without a
model, its top-level args (see :func:`tvl_lsp.project.check.free_top_args`) — are free booleans.  A *witness* is a product with the fewest selected features (free
args counted too) in which the problem shows, given as name -> bool over every feature and free
top-level arg, ready to be passed to roslaunch as ``name:=true|false``.  roslaunch stops at the
first error it meets, so the witness of a fact is, when there is one, the smallest product in
which no earlier error fact holds (facts come in roslaunch's processing order): run with it,
roslaunch raises that very error.  Among the smallest, the witness is canonical (features
declared first are preferred), whatever was asked before.

The SAT questions go to :class:`~tvl_lsp.analysis.solve.PairLogic` (the SAT service,
``solve.py``): one incremental solver per pairing over the model's CNF plus a Tseitin encoding
of each queried formula, asserted through an assumption, and a totalizer over the product
variables for the smallest witness.  A fresh PairLogic per pairing keeps the answers
independent of what was asked before, so the output is the same whether files are checked
serially or in parallel.
"""

from __future__ import annotations

import difflib
import os
import re
from typing import Optional

from ..base.diagnostics import Diagnostic, Fix, Related, Severity, TextEdit, register
from ..base.text import LineIndex, Pos, Span
from ..base import formula as fm
from .solve import PairLogic

MISSING_ARG = register(
    "missing-arg", Severity.WARNING,
    "A feature of the model has no top-level <arg> in the launch file it configures.", "cross")
UNMATCHED_ARG = register(
    "unmatched-arg", Severity.WARNING,
    "A top-level <arg> of a generic launch file names no feature of its model.", "cross")
DEAD_ELEMENT = register(
    "dead-element", Severity.WARNING,
    "An element of the launch file is loaded by no product of the model.", "cross")
UNSET_ARG = "unset-arg"  # registered by the launch front end (tvl_lsp.launch.ros1.rules)
CONSTANT_CONDITION = register(
    "constant-condition", Severity.INFORMATION,
    "An if/unless condition has the same value in every product where it is evaluated.", "cross")

_ARG_REF = re.compile(r"\$\((?:arg|var)\s+([^\s)]+)\s*\)")   # roslaunch's $(arg X), ros2's $(var X)
_STRINGY = re.compile(r"""(==|!=|\bin\b)\s*['"\[]|['"]\s*(==|!=)""")
_EVAL_ARG_REF = re.compile(r"arg\(\s*['\"]([^'\"]+)['\"]\s*\)")
_VAR_DEFAULT = re.compile(r"\$\(var\s+([^\s)]+)\s+[^)]")   # ros2's $(var X default)
MAX_COND_TEXT = 160
MAX_EXPLAIN_FEATURES = 2000


# ------------------------------------------------------------------ helpers

def _cond_text(f: fm.Formula) -> str:
    s = str(f)
    return s if len(s) <= MAX_COND_TEXT else s[: MAX_COND_TEXT - 1] + "…"


def _selected(w: dict[str, bool]) -> str:
    on = [k for k, v in w.items() if v]
    return "{" + ", ".join(on) + "}" if on else "{} (nothing selected)"


def _rename_arg_fixes(launch, path: str, span: Span, name: str, sug: Optional[str]) -> list[Fix]:
    """The quick fix of an undeclared ``$(arg name)`` whose name is close to a declared arg or
    a feature (the "did you mean" of the message): rename it in that substitution."""
    if not sug:
        return []
    for e in launch.elements:
        if e.path != path:
            continue
        for s in e.substitutions:
            if s.span != span or s.kind not in ("arg", "var") or s.args[:1] != (name,):
                continue
            head = f"$({s.kind} "
            if span.start.line != span.end.line or span.end.col - span.start.col != len(head) + len(name) + 1:
                return []   # spaces or a line break inside: leave it to the user
            col = span.start.col + len(head)
            return [Fix(f"Change to `{sug}`", (TextEdit(path, Span.of(span.start.line, col, span.start.line,
                                                                      col + len(name)), sug),), preferred=True)]
    return []


def _closest(name: str, candidates: list[str]) -> Optional[str]:
    if not candidates:
        return None
    low = {c.lower(): c for c in candidates}
    if name.lower() in low:
        return low[name.lower()]
    m = difflib.get_close_matches(name, candidates, n=1, cutoff=0.6)
    if m:
        return m[0]
    m = difflib.get_close_matches(name.lower(), list(low), n=1, cutoff=0.6)
    return low[m[0]] if m else None


def _start_tag(e) -> Span:
    """The element's start tag, '<' to '>' (the launch front end's Element.span)."""
    return e.span


def _has_cond(e) -> bool:
    return "if" in e.attrs or "unless" in e.attrs


# the launch classes of a Python launch file's elements (their tags are the XML front end's)
_PY_CLASS = {"node": "Node", "node_container": "ComposableNodeContainer", "composable_node": "ComposableNode",
             "include": "IncludeLaunchDescription", "group": "GroupAction", "arg": "DeclareLaunchArgument",
             "let": "SetLaunchConfiguration", "executable": "ExecuteProcess", "timer": "TimerAction",
             "push_ros_namespace": "PushRosNamespace", "set_remap": "SetRemap", "set_parameter": "SetParameter",
             "load_composable_node": "LoadComposableNodes", "opaque_function": "OpaqueFunction",
             "event_handler": "RegisterEventHandler", "log": "LogInfo"}


def _is_py(path: str) -> bool:
    return path.endswith(".py")


def _cond_shown(e, attr) -> str:
    """The condition as the file writes it: ``if="$(var x)"``, or a Python file's
    ``condition=IfCondition(...)``."""
    if _is_py(e.path):
        c = e.attrs.get("condition")
        if c is not None:
            return f"condition={c.value}"
    return f'{attr.name}="{attr.value}"'


PYTHON_CLASSES = _PY_CLASS  # (for the hosts: hover)


def _describe_element(e) -> str:
    if _is_py(e.path):
        cls = _PY_CLASS.get(e.tag, e.tag)
        name = e.attrs.get("name")
        return f"{cls}(name='{name.value}')" if name is not None else f"{cls}(...)"
    name = e.attrs.get("name")
    if name is not None:
        return f'<{e.tag} name="{name.value}">'
    f = e.attrs.get("file")
    if f is not None:
        return f'<{e.tag} file="{f.value}">'
    return f"<{e.tag}>"


def _arg_inserter(launch, text: Optional[str], model_name: Optional[str]):
    """feature -> the fixes that add its argument to the launch file (none when there is no
    place for it)."""
    if text is not None and _is_py(launch.path):
        from ..launch.ros2py.editing import declare_argument_planner
        try:
            insert = declare_argument_planner(text, launch.path, launch)
        except (SyntaxError, ValueError, RecursionError):
            insert = None

        def python_fix(feature: str, long_name: str) -> list[Fix]:
            edits = insert(feature, f"feature {long_name} of {model_name}") if insert is not None else None
            if not edits:
                return []
            return [Fix(f"Add DeclareLaunchArgument('{feature}')", tuple(edits), preferred=True)]
        return python_fix
    return lambda feature, long_name: _insert_arg_fix(launch, text, feature)


def _insert_arg_fix(launch, text: Optional[str], feature: str) -> list[Fix]:
    if text is None or launch.root is None or _is_py(launch.path):
        return []   # (a Python file's DeclareLaunchArgument is another fix)
    idx = LineIndex(text)
    top_args = [c for c in launch.root.children if c.tag == "arg"]
    ros2 = getattr(launch, "dialect", "ros1") == "ros2"
    yaml_file = launch.path.endswith((".yaml", ".yml"))
    if yaml_file:
        # after the last top-level `- arg:` entry (its whole line), or after `launch:`
        if top_args:
            line = max(c.span.end.line for c in top_args)
            for c in top_args:
                for a in c.attrs.values():
                    line = max(line, a.value_span.end.line)
            lt = idx.line_text(top_args[-1].span.start.line)
            indent = lt[: len(lt) - len(lt.lstrip())]
        else:
            line = launch.root.span.start.line
            indent = "  "
        at = Pos(line, len(idx.line_text(line)))
        new = f'\n{indent}- arg: {{name: {feature}, default: "false"}}'
        title = f'Add `- arg: {{name: {feature}, default: "false"}}`'
        return [Fix(title, (TextEdit(launch.path, Span(at, at), new),), preferred=True)]
    if top_args:
        after = top_args[-1].span.end
        last = top_args[-1]
        if ros2 and last.children:
            # an <arg> with <choice> children: after its end tag's line
            end_line = max(ch.span.end.line for ch in last.children) + 1
            if end_line < len(idx.starts):
                after = Pos(end_line, len(idx.line_text(end_line)))
        line_text = idx.line_text(top_args[-1].span.start.line)
        indent = line_text[: len(line_text) - len(line_text.lstrip())]
    else:
        after = _start_tag(launch.root).end
        indent = "  "
    tag = f'<arg name="{feature}" default="false"/>' if ros2 else f'<arg name="{feature}"/>'
    edit = TextEdit(launch.path, Span(after, after), f'\n{indent}{tag}')
    return [Fix(f'Add {tag}', (edit,), preferred=True)]


# ------------------------------------------------------------------ the check

def cross_check(launch, model=None, encoding=None, *, launch_text: Optional[str] = None,
                model_path: Optional[str] = None, logic: Optional[PairLogic] = None,
                analysis=None, choices=None, solver: bool = True) -> list[Diagnostic]:
    """Diagnostics of ``launch`` (a LaunchAnalysis) paired with ``model`` (or alone).
    ``analysis``: the model's :class:`~tvl_lsp.analysis.engine.ModelAnalysis`, to explain dead
    elements by the parts of the model that exclude them.  ``choices``: the ROS 2 ``<choice>``
    args' pairings (:func:`tvl_lsp.analysis.choices.pair_choices`; computed when None).
    Without ``solver``, only the checks that need no SAT question (``missing-arg``,
    ``unmatched-arg``, the ``<choice>`` pairings, ``unset-arg``): exactly those diagnostics of
    the full check, in milliseconds (the language server shows them before its solver-backed
    check is done)."""
    out: list[Diagnostic] = []
    path = launch.path
    model_name = None
    if model is not None:
        model_name = os.path.basename(model_path or model.path)
        if encoding is None:
            from .encode import encode
            encoding = encode(model)

    feature_args = list(launch.feature_args)
    free_args = list(getattr(launch, "free_args", None) or [])

    if model is not None and encoding is not None:
        features = list(encoding.features)
        by_arg = {}   # arg name -> feature
        for a in feature_args:
            f = encoding.feature_by_name(a.name)
            if f is not None and a.name not in by_arg:
                by_arg[a.name] = f
        matched_features = set(id(f) for f in by_arg.values())
        launch_choices = getattr(launch, "choices", None) or {}
        if launch_choices:
            from .choices import choice_diagnostics, covered_features, pair_choices
            if choices is None:
                choices = pair_choices({k: v[0] for k, v in launch_choices.items()}, encoding)
            # an alternative group's children are selected through the group's arg
            matched_features |= covered_features(choices)
            out += choice_diagnostics(launch, choices, model_name)
        unmatched_feature_names = [encoding.name_of(f) for f in features if id(f) not in matched_features]
        all_feature_names = [encoding.name_of(f) for f in features]
        paired_choices = {k for k, p in (choices or {}).items() if p.kind is not None}
        for a in feature_args:
            if a.name in by_arg or a.name in paired_choices:
                continue
            sug = _closest(a.name, unmatched_feature_names)
            also = None if sug else _closest(a.name, all_feature_names)
            msg = f"{'argument' if _is_py(path) else 'arg'} `{a.name}` names no feature of {model_name}"
            fixes = []
            if sug:
                msg += f"; did you mean `{sug}`?"
                fixes = [Fix(f"Rename to `{sug}`", (TextEdit(path, a.name_span, sug),), preferred=True)]
            elif also:
                msg += f" (`{also}` already has its arg)"
            elif _is_py(path):
                msg += " (in a generic launch file the declared arguments are exactly the features; "\
                       "declare other arguments inside a GroupAction)"
            else:
                msg += " (in a generic launch file the top-level args are exactly the features; "\
                       "move other args into a <group>)"
            out.append(Diagnostic(UNMATCHED_ARG, Severity.WARNING, path, a.name_span, msg,
                                  data={"arg": a.name, "suggestion": sug}, fixes=fixes))
        root_span = _start_tag(launch.root) if launch.root is not None else Span(Pos(0, 0), Pos(0, 0))
        insert_arg = _arg_inserter(launch, launch_text, model_name)
        for f in features if getattr(launch, "complete", True) else []:   # (a part not followed may declare it)
            if id(f) in matched_features:
                continue
            name = encoding.name_of(f)
            nested = [e for e in launch.elements if e.tag == "arg" and e.path == path
                      and "name" in e.attrs and e.attrs["name"].value == f.name]
            hint = (f" (the <arg name=\"{f.name}\"> on line {nested[0].span.start.line + 1} is inside "
                    f"<{nested[0].parent.tag}>: feature args are direct children of <launch>)"
                    if nested and nested[0].parent is not None else "")
            if _is_py(path):
                hint = (f" (the DeclareLaunchArgument('{f.name}') on line {nested[0].span.start.line + 1} is "
                        "inside a GroupAction: feature arguments are declared in the LaunchDescription itself)"
                        if nested and nested[0].parent is not None and nested[0].parent.tag != "launch" else "")
                what = f"no DeclareLaunchArgument('{f.name}') in its LaunchDescription"
            else:
                what = f"no top-level <arg name=\"{f.name}\"/>"
            out.append(Diagnostic(
                MISSING_ARG, Severity.WARNING, path, root_span,
                f"feature `{name}` of {model_name} has {what}: "
                f"configurations cannot select or deselect it{hint}",
                related=[Related(f.path, f.name_span, f"feature `{name}` is declared here")],
                data={"feature": f.name}, fixes=insert_arg(f.name, f.long_name)))
    if model is not None and encoding is not None:
        free = [n for n in free_args if encoding.feature_by_name(n) is None]
    else:
        free = free_args

    # a launch file checked alone: a free arg without default that the load uses makes roslaunch
    # run with the file's defaults fail (with a model, the top-level args are its features, set
    # by its configurations; one that names no feature is already unmatched-arg)
    decl = {a.name: a for a in feature_args}
    for name in (getattr(launch, "required_args", None) or ()) if model is None else ():
        a = decl.get(name)
        if a is None:
            continue
        out.append(Diagnostic(
            UNSET_ARG, Severity.WARNING, path, a.name_span,
            f"'{name}' has no default: roslaunch fails unless it is given on the command line ({name}:=true or "
            f"{name}:=false); tvl-lsp checks the file with both values", data={"arg": name}))

    if not solver:
        return out
    own_logic = logic is None
    if logic is None:
        logic = PairLogic(encoding if model is not None else None, free)
    try:
        if model is not None and logic.void():
            # a void model has no product: the model reports void-model; nothing else is true
            return out
        out += _facts(launch, logic, model_name)
        out += _dead_and_constant(launch, logic, model_name, model is not None, analysis)
    finally:
        if own_logic:
            logic.close()
    return out


def _when(cond: fm.Formula, witness: dict[str, bool]) -> str:
    if cond == fm.TRUE:
        return " (in every product)"
    return f" (when {_cond_text(cond)}; e.g. in the product {_selected(witness)})"


def _undeclared_after_first(launch, known: set[str]) -> dict:
    """``$(arg a) $(arg b)`` with neither declared: roslaunch stops at ``a`` (and the launch
    front end, like it, reports only ``a``), but ``b`` is just as undeclared.  Returns
    span of the reported ``$(arg a)`` -> [(name, span)] of the later undeclared ``$(arg b)`` of
    the same value, for args this file declares nowhere and that are not features / free args
    (the only args a command line sets in a product), so that each gets its own problem."""
    out: dict = {}
    reported = [f for f in launch.facts if f.code in ("undefined-arg", "unset-arg") and f.path == launch.path]
    if not reported:
        return out
    for e in launch.elements:
        if e.path != launch.path or getattr(e, "include_depth", 0) != 0:
            continue
        for attr in e.attrs.values():
            subs = [x for x in e.substitutions if x.attr == attr.name and x.kind in ("arg", "var")
                    and len(x.args) == 1]
            firsts = [f for f in reported if any(f.span == x.span for x in subs)]
            if not firsts:
                continue
            first = min(firsts, key=lambda f: f.span.start)
            later = [(x.args[0], x.span) for x in subs if x.span.start > first.span.start and x.args[0] not in known
                     and "$" not in x.args[0] and not any(f.span == x.span for f in reported)]
            if later:
                got = out.setdefault(first.span, [])
                got += [(n, sp) for n, sp in later if n not in {g for g, _ in got}]
    return out


def _include_anchors(launch):
    """anchor(included file, witness) -> the first <include> element of the analysed file
    through which it is loaded (directly or through further includes) in the witness product
    (the first such <include> at all without a witness)."""
    first: dict[str, list] = {}

    def files(inc) -> list[str]:
        out = [inc.file] if inc.file else []
        for c in inc.children:
            out += files(c)
        return out

    for inc in getattr(launch, "includes", None) or []:
        el = inc.element
        if getattr(el, "include_depth", 0) != 0 or el.path != launch.path:
            continue
        for f in files(inc):
            for key in (f, os.path.abspath(f)):
                if all(e is not el for e, _ in first.setdefault(key, [])):
                    first[key].append((el, inc.condition))

    def anchor(path, witness=None):
        incs = first.get(path) or first.get(os.path.abspath(path)) or []
        if witness is not None:
            # the same file included twice: the <include> that loads it in the witness product
            for el, cond in incs:
                if fm.evaluate(cond, witness):
                    return el
        return incs[0][0] if incs else None
    return anchor


_NO_VALUE_NAME = re.compile(r"\('([^']+)' has none\)")
_MISSING_NAME = re.compile(r"requires the '([^']+)' arg|arg '([^']+)' is not defined|'([^']+)' is not declared"
                           # ROS 2: $(var X) of nothing set; an arg without default
                           r"|named '([^']+)' is set here|arg '([^']+)' has no default|the arg '([^']+)', which")


def _facts(launch, logic: PairLogic, model_name: Optional[str]) -> list[Diagnostic]:
    out = []
    known = sorted({e.attrs["name"].value for e in launch.elements if e.tag == "arg" and "name" in e.attrs}
                   | {n for n, _ in logic.names})
    # roslaunch stops at the first error: prefer a witness where no earlier error is raised,
    # so that roslaunch, run with it, raises this one (facts come in roslaunch's order)
    clear = True   # literal: no error fact so far holds
    # args whose every declaration here has a default / value: "unset" only when evaluating that
    # default failed (e.g. $(env X) with X unset) -- roslaunch stops at that failure, which is
    # reported; the "unset" consequences are not
    decls: dict[str, list] = {}
    for e in launch.elements:
        if e.tag == "arg" and "name" in e.attrs and e.path == launch.path:
            decls.setdefault(e.attrs["name"].value, []).append(e)
    valued = {n for n, es in decls.items() if all("default" in e.attrs or "value" in e.attrs for e in es)}
    anchor = _include_anchors(launch)
    declared = {e.attrs["name"].value for e in launch.elements
                if e.tag == "arg" and "name" in e.attrs and e.path == launch.path}
    also_undeclared = _undeclared_after_first(launch, declared | {n for n, _ in logic.names})
    for fact in launch.facts:
        if fact.code in ("unset-arg", "include-arg-no-value") and fact.path == launch.path:
            m = _MISSING_NAME.search(fact.message) or _NO_VALUE_NAME.search(fact.message)
            name = next((g for g in m.groups() if g), None) if m else None
            if name in valued:
                continue
        w = logic.witness(fact.condition, clear) if clear is not False else None
        if w is None:
            w = logic.witness(fact.condition)
        # (an undeclared arg is a warning where the command line may give it, but a witness
        # does not give it: roslaunch run with the witness stops there)
        if (fact.severity == Severity.ERROR or fact.code == "undefined-arg") and clear is not False:
            c = logic.lit(fact.condition)
            clear = logic.and_lits(clear, (not c) if isinstance(c, bool) else -c)
        if w is None:
            continue
        related = [r if isinstance(r, Related) else Related(r[0], r[1], r[2]) for r in fact.related]
        msg = fact.message
        data = {"condition": str(fact.condition)}
        if fact.code == "undefined-arg" and "did you mean" not in msg:
            m = _MISSING_NAME.search(msg)
            if m:
                name = next(g for g in m.groups() if g)
                sug = _closest(name, [n for n in known if n != name])
                if sug:
                    msg += f"; did you mean `{sug}`?"
                    data["suggestion"] = sug
                data["arg"] = name
                # the later undeclared args of the same value: one problem each (roslaunch
                # itself stops at this first one, which the related information says)
                for other, other_span in also_undeclared.get(fact.span, []) if fact.path == launch.path else []:
                    sug2 = _closest(other, [n for n in known if n != other])
                    if getattr(launch, "dialect", "ros1") == "ros2":
                        first_msg = (f"$(var {other}): no <arg> or <let> named '{other}' is set here "
                                     f"(ros2 launch: launch configuration '{other}' does not exist)")
                        stops = f"ros2 launch stops earlier in this value, at `$(var {name})`"
                    else:
                        first_msg = (f"{os.path.basename(launch.path)} requires the '{other}' arg to be set: "
                                     f"'{other}' is not declared in this scope")
                        stops = f"roslaunch stops earlier in this value, at `$(arg {name})`"
                    out.append(Diagnostic(
                        fact.code, fact.severity, fact.path, other_span,
                        first_msg + (f"; did you mean `{sug2}`?" if sug2 else "") + _when(fact.condition, w),
                        related=[Related(fact.path, fact.span, stops)],
                        witness=w, data={"condition": str(fact.condition), "arg": other, "stops_at": name,
                                         **({"suggestion": sug2} if sug2 else {})},
                        fixes=_rename_arg_fixes(launch, fact.path, other_span, other, sug2)))
        path, span = fact.path, fact.span
        if path != launch.path:
            # an error inside an included file, for the args this file passes: reported on the
            # <include> here (the included file checked alone may well be fine)
            inc = anchor(path, w)
            if inc is None:
                continue
            related = [Related(fact.path, fact.span, "the error, in the included file")] + related
            msg = f"in the included file {os.path.basename(fact.path)}: {msg}"
            path, span = launch.path, inc.span
        # the launch model says how bad it is: unset-arg is a warning where the command line can
        # give the value (this file, files included with pass_all_args), an error elsewhere
        sev = fact.severity
        if fact.condition == fm.TRUE and fact.severity >= Severity.INFORMATION:
            if path == fact.path:
                out.append(Diagnostic(fact.code, sev, path, span, msg, related=related))
            continue
        fixes = (_rename_arg_fixes(launch, path, span, data["arg"], data.get("suggestion"))
                 if fact.code == "undefined-arg" and "arg" in data and path == fact.path else [])
        out.append(Diagnostic(fact.code, sev, path, span,
                              msg + _when(fact.condition, w), related=related, witness=w, data=data, fixes=fixes))
    return out


def _explain(analysis, enc, cond: fm.Formula) -> tuple[str, list[Related]]:
    """Why no product satisfies ``cond``: the model's parts that exclude it (engine's MUS)."""
    if analysis is None or enc is None or enc.n_features > MAX_EXPLAIN_FEATURES:
        return "", []
    if any(enc.feature_by_name(n) is None for n in fm.variables(cond)):
        return "", []
    try:
        elements = analysis.explain(formula=cond)
    except Exception:
        return "", []
    if not elements:
        return "", []
    labels = [e.label for e in elements]
    text = " Because: " + "; ".join(labels[:4]) + ("; …" if len(labels) > 4 else "") + "."
    return text, [Related(e.path, e.span, e.label) for e in elements]


def _dead_and_constant(launch, logic: PairLogic, model_name: Optional[str], modelled: bool,
                       analysis=None) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    root = launch.root
    if root is None:
        return out
    enc = logic.enc

    def feature_related(cond: fm.Formula) -> list[Related]:
        if enc is None:
            return []
        out = []
        for name in sorted(fm.variables(cond))[:6]:
            f = enc.feature_by_name(name)
            if f is not None:
                out.append(Related(f.path, f.name_span, f"feature `{name}` is declared here"))
        return out

    # spans of load-time problems (and untranslatable conditions) in this file: an element whose
    # if/unless value has one is not "dead" or "constant" -- roslaunch fails on it, or we cannot tell
    trouble = [f.span for f in launch.facts if f.path == launch.path]
    trouble += [s for p, s in getattr(launch, "unknown_conditions", ()) if p == launch.path]

    # args a user can set on the command line although they are not free booleans here: a
    # declaration with a default (roslaunch lets the command line override it).  A condition
    # that reads one of them is only "dead" / "constant" for its default value: not reported.
    # (a ROS 2 arg with <choice> values is analysed for each of them: not just its default)
    free_set = set(getattr(launch, "free_args", None) or ()) | set(getattr(launch, "choices", None) or ())
    overridable = {e.attrs["name"].value for e in launch.elements
                   if e.tag == "arg" and "name" in e.attrs and "default" in e.attrs and "value" not in e.attrs
                   and e.path == launch.path} - free_set

    # a configuration read with a default that no <arg> declares is set from the command line just
    # as well (ros2 launch sets any name:=value it is given): its default is not the only value
    declared_here = {e.attrs["name"].value for e in launch.elements
                     if e.tag in ("arg", "let") and "name" in e.attrs and e.path == launch.path}
    for e in launch.elements:
        if e.path != launch.path:
            continue
        for key in ("if", "unless"):
            a = e.attrs.get(key)
            if a is not None:
                overridable |= {n for n in _VAR_DEFAULT.findall(a.value) if n not in declared_here} - free_set

    def reads(value: str) -> set[str]:
        names = set(_ARG_REF.findall(value)) | set(_EVAL_ARG_REF.findall(value)) | set(_VAR_DEFAULT.findall(value))
        if "$(eval" in value:
            names |= set(re.findall(r"[A-Za-z_]\w*", value))
        return names

    def reads_overridable(value: str) -> bool:
        return bool(reads(value) & overridable)

    # an arg whose value is computed from an overridable one is as good as overridable (ROS 1
    # <arg value>, ROS 2 <let value>)
    computed = [(e.attrs["name"].value, e.attrs["value"].value) for e in launch.elements
                if e.tag in ("arg", "let") and "name" in e.attrs and "value" in e.attrs and e.path == launch.path]
    grew = True
    while grew:
        grew = False
        for name, value in computed:
            if name not in overridable and name not in free_set and reads_overridable(value):
                overridable.add(name)
                grew = True

    def troubled(e) -> bool:
        # a load-time problem in any attribute of the element (e.g. a group's ns reading an
        # unset arg): roslaunch fails on the element there, its condition says nothing more
        for a in e.attrs.values():
            vs = getattr(a, "value_span", None)
            if vs is not None and any(vs.start <= s.start and s.end <= vs.end for s in trouble):
                return True
        for key in ("if", "unless"):
            a = e.attrs.get(key)
            if a is None:
                continue
            if reads_overridable(a.value):
                return True
            if not modelled and "$(eval" in a.value and _STRINGY.search(a.value):
                return True  # free args are booleans; a string comparison means they are not
            if any(w in a.value for w in ("$(env", "$(optenv", "$(find", "$(anon", "$(dirname")):
                return True
            vs = a.value_span
            if any(vs.start <= s.start and s.end <= vs.end for s in trouble):
                return True
            st = _start_tag(e)
            if any(s == st for s in trouble):
                return True
            # e.g. if-and-unless, reported on the tag name: roslaunch fails on the element
            ts = getattr(e, "tag_span", None)
            if ts is not None and any(s == ts for s in trouble):
                return True
        return False

    def visit(e, parent) -> None:
        if getattr(e, "include_depth", 0) != 0 or e.path != launch.path:
            return
        if parent is not None and _has_cond(e) and troubled(e):
            return
        cond = e.condition
        if not logic.sat(cond):
            if parent is not None and _has_cond(e) and logic.sat(parent.condition):
                attr = e.attrs.get("if") or e.attrs.get("unless")
                if modelled:
                    why = (f"no product of {model_name} satisfies its condition {_cond_text(cond)}"
                           if cond != fm.FALSE else f"its condition is false in every product of {model_name}")
                else:
                    why = (f"its condition {_cond_text(cond)} holds for no values of the file's args"
                           if cond != fm.FALSE else "its condition is false whatever the file's args")
                because, rel = _explain(analysis, enc, cond) if modelled and cond != fm.FALSE else ("", [])
                out.append(Diagnostic(
                    DEAD_ELEMENT, Severity.WARNING, e.path, _start_tag(e),
                    f'{_describe_element(e)} is never loaded: {why} ({_cond_shown(e, attr)}).{because}',
                    related=feature_related(cond) + rel, data={"condition": str(cond)}))
            return
        if parent is not None and _has_cond(e):
            pc = parent.condition
            if logic.valid(fm.implies(pc, cond)):
                for key in ("if", "unless"):
                    attr = e.attrs.get(key)
                    if attr is None:
                        continue
                    value = "true" if key == "if" else "false"
                    everywhere = pc == fm.TRUE or logic.valid(pc)
                    if modelled:
                        scope = f"in every product of {model_name}" + ("" if everywhere else " that loads its parent")
                    else:
                        scope = "whatever the file's args" + ("" if everywhere else " wherever its parent is loaded")
                    eff = "always loads" if key == "if" else "never skips"
                    because, rel = _explain(analysis, enc, fm.conj([pc, fm.neg(cond)])) if modelled else ("", [])
                    out.append(Diagnostic(
                        CONSTANT_CONDITION, Severity.INFORMATION, e.path, attr.value_span,
                        f'{_cond_shown(e, attr)} is always {value} {scope}: it {eff} '
                        f"{_describe_element(e)}, so the condition can be removed.{because}",
                        related=feature_related(cond) + rel,
                        data={"condition": str(cond), "value": key == "if"}))
        for c in e.children:
            visit(c, e)

    visit(root, None)
    return out
