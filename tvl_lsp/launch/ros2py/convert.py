"""Launch objects of a Python launch file as the ROS 2 walker's actions.

The XML and YAML front ends turn entities into the actions of :mod:`..ros2.actions`, whose
values are substitution parts; this module does the same for the objects the interpreter
built: ``Node(...)`` becomes a ``NodeA``, ``LaunchConfiguration('x')`` a ``$(var x)`` part,
``PythonExpression([...])`` an ``$(eval ...)`` part, and so on, so that the walker gives
launch's semantics once for the three dialects.  Each action gets an entity (one per place in
the file: a ``Node(...)`` call made in a loop is one element) with attributes whose ranges point
at the Python expressions they come from, and the ``LaunchConfiguration`` names it uses as
:class:`~tvl_lsp.launch.model.Subst` entries with the exact range of the name.

Python-only constructs become actions with their own ``walk`` (:mod:`.actions`): an
``OpaqueFunction``, an event handler, and whatever cannot be known (an unknown entity).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

from ...base.text import Span
from ..model import Subst
from ..ros2 import actions as A
from ..ros2 import subst as S
from ..ros2.frontend import Entity, RAttr
from .launchapi import CONDITIONS, SOURCES, SUBSTITUTIONS
from .classes import PyInstance
from .values import LObj, PathObj, SStr, Unknown, Where


class PyEntity(Entity):
    """An entity of a Python launch file: a place in the file that makes a launch action."""

    def __init__(self, tag: str, path: str, span: Span, parent: Optional["PyEntity"] = None):
        super().__init__("py", tag, path, span, span, {}, parent)
        self.kids: list[PyEntity] = []
        self.substs: list[Subst] = []

    def sub_entities(self) -> list["Entity"]:
        return list(self.kids)

    def __repr__(self) -> str:
        return f"PyEntity({self.tag} {self.span.start})"


@dataclass
class PyValue(A.Value):
    """A value of a Python launch file: its range is the expression it comes from, each
    substitution part knows its own (``part.where``)."""
    where_span: Optional[Span] = None
    typed: bool = False   # a parameter value launch_ros types with YAML even when it is plain text

    def span(self) -> Span:
        if self.where_span is not None:
            return self.where_span
        return self.entity.tag_span if self.entity is not None else None

    def sub_span(self, sub) -> Span:
        w = getattr(sub, "where", None)
        if w is not None and self.entity is not None and w[0] == self.entity.path:
            return w[1]
        return self.span()


def _text(s: str) -> S.Text:
    return S.Text(s, 0, 0)


def _sub(name: str, args: list, where: Optional[Where], hard: bool = True) -> S.Sub:
    sub = S.Sub(name, args, 0, 0)
    sub.where = where
    sub.hard = hard
    return sub


class Converter:
    """Turns the launch objects of one file into actions and entities."""

    def __init__(self, path: str, root: PyEntity):
        self.path = path
        self.root = root
        self.unit = None   # the PyUnit (an instance's perform() is interpreted through it)
        self.entities: dict = {}
        self.substs_seen: set = set()
        self.cur: Optional[PyEntity] = None
        self.depth = 0

    # ------------------------------------------------------------------ entities
    def entity(self, o, tag: str, parent: Optional[PyEntity]) -> PyEntity:
        where = getattr(o, "where", None)
        if where is None or where[0] != self.path:
            where = (self.path, (parent or self.root).span)
        key = (where[1], tag)
        e = self.entities.get(key)
        if e is None:
            p = parent or self.root
            e = PyEntity(tag, self.path, where[1], p)
            p.kids.append(e)
            self.entities[key] = e
        return e

    def attr(self, e: PyEntity, o: LObj, name: str, value: Any, shown: Optional[str] = None,
             span: Optional[Span] = None) -> None:
        """Attribute ``name`` of entity ``e`` (for hover, references, the cross-check's ranges)."""
        if name in e.attrs:
            return
        aw = o.extra.get("arg_where", {}).get(name) if isinstance(o, LObj) else None
        vspan = span or (aw[0][1] if aw and aw[0][0] == self.path else e.tag_span)
        nspan = aw[1][1] if aw and aw[1] is not None and aw[1][0] == self.path else vspan
        if span is not None:
            nspan = span if not (aw and aw[1]) else nspan
        text = shown if shown is not None else (value if isinstance(value, str) else "")
        e.attrs[name] = RAttr(name, str(text), nspan, vspan, None, 0, False, None)
        e._read.add(name)

    def add_subst(self, kind: str, args: tuple, span: Span, attr: str, name_span: Optional[Span]) -> None:
        e = self.cur or self.root
        key = (id(e), span, attr)
        if key in self.substs_seen:
            return
        self.substs_seen.add(key)
        e.substs.append(Subst(kind, args, span, attr, name_span=name_span))

    # ------------------------------------------------------------------ values
    def value(self, v, e: PyEntity, o: Optional[LObj], name: str, hard: bool = True,
              typed: bool = False) -> PyValue:
        prev = self.cur
        self.cur = e
        try:
            parts = self.parts(v, hard, name)
        finally:
            self.cur = prev
        aw = o.extra.get("arg_where", {}).get(name) if isinstance(o, LObj) else None
        span = aw[0][1] if aw and aw[0][0] == self.path else None
        if span is None:
            w = getattr(v, "where", None) if isinstance(v, (LObj, SStr, Unknown)) else None
            if w is not None and w[0] == self.path:
                span = w[1]
        if o is not None and name:
            self.attr(e, o, name, S.plain(parts), span=span)
        return PyValue(parts, None, e, span, typed)

    def parts(self, v, hard: bool, attr: str = "", depth: int = 0) -> list:
        if depth > 40:
            return [self.unknown(Unknown("a value nested too deeply"), hard)]
        if isinstance(v, str):
            if isinstance(v, SStr) and v.where is not None:
                pass
            return [_text(str(v))]
        if isinstance(v, Unknown):
            return [self.unknown(v, hard)]
        if isinstance(v, LObj):
            if v.cls in SUBSTITUTIONS:
                return [self.sub(v, hard, attr, depth)]
            return [self.unknown(Unknown(f"a {v.cls} where launch expects a string or a substitution", v.where),
                                 hard)]
        if isinstance(v, (list, tuple)):
            out: list = []
            for x in v:
                if isinstance(x, (list, tuple)):
                    out.append(self.unknown(Unknown("a nested list where launch expects a string or a substitution"),
                                            hard))
                    continue
                out.extend(self.parts(x, hard, attr, depth + 1))
            return out or [_text("")]
        if isinstance(v, PyInstance):
            if v.cls.derives_from("Substitution"):
                sub = _sub("py-perform", [], self.where_of(v), hard)
                sub.instance = v
                sub.unit = self.unit
                return [sub]
            return [self.unknown(Unknown(f"a {v.cls.name} where launch expects a string or a substitution"), hard)]
        if isinstance(v, PathObj):
            return [self.unknown(Unknown("a pathlib.Path where launch 3.7.1 expects a string or a substitution "
                                         "(newer launch versions accept it)"), hard)]
        what = "None" if v is None else type(v).__name__
        return [self.unknown(Unknown(f"a {what} where launch expects a string or a substitution (launch raises "
                                     "TypeError)"), hard)]

    def where_of(self, v) -> Optional[Where]:
        return None

    def unknown(self, u: Unknown, hard: bool) -> S.Sub:
        w = u.where if u.where is not None and u.where[0] == self.path else None
        return _sub("py-unknown", [[_text(u.reason)]], w, hard)

    def sub(self, o: LObj, hard: bool, attr: str, depth: int) -> S.Sub:
        c = o.cls
        g = o.get
        w = o.where

        def p(x):
            return self.parts(x, hard, attr, depth + 1)
        if c == "LaunchConfiguration":
            name = g("variable_name")
            args = [p(name)]
            if g("default") is not None:
                args.append(p(g("default")))
            if isinstance(name, str) and w is not None and w[0] == self.path:
                nw = name.where if isinstance(name, SStr) else None
                self.add_subst("var", (str(name),), w[1], attr, nw[1] if nw and nw[0] == self.path else None)
            return _sub("var", args, w, hard)
        if c == "TextSubstitution":
            t = g("text")
            if isinstance(t, str):
                return _sub("text", [[_text(str(t))]], w, hard)
            return self.unknown(Unknown("TextSubstitution of a value tvl-lsp cannot know", w), hard)
        if c == "PathJoinSubstitution":
            items = g("substitutions")
            if not isinstance(items, (list, tuple)):
                return self.unknown(Unknown("PathJoinSubstitution of a value tvl-lsp cannot know", w), hard)
            return _sub("path-join", [p(x) for x in items], w, hard)
        if c == "PythonExpression":
            args = [p(g("expression"))]
            mods = g("python_modules")
            if mods is not None:
                if isinstance(mods, (list, tuple)) and all(isinstance(x, str) for x in mods):
                    args.append([_text(",".join(str(x) for x in mods))])
                elif isinstance(mods, str):
                    args.append([_text(str(mods))])
                else:
                    return self.unknown(Unknown("PythonExpression's python_modules", w), hard)
            return _sub("eval", args, w, hard)
        if c == "EnvironmentVariable":
            args = [p(g("name"))]
            if g("default_value") is not None:
                args.append(p(g("default_value")))
            return _sub("env", args, w, hard)
        if c in ("FindPackageShare", "FindPackagePrefix"):
            return _sub("find-pkg-share" if c == "FindPackageShare" else "find-pkg-prefix", [p(g("package"))], w,
                        hard)
        if c == "FindExecutable":
            return _sub("find-exec", [p(g("name"))], w, hard)
        if c == "ExecutableInPackage":
            return _sub("exec-in-pkg", [p(g("executable")), p(g("package"))], w, hard)
        if c == "Command":
            return _sub("command", [p(g("command"))], w, hard)
        if c == "ThisLaunchFileDir":
            return _sub("dirname", [], w, hard)
        if c == "ThisLaunchFile":
            return _sub("filename", [], w, hard)
        if c == "AnonName":
            return _sub("anon", [p(g("name"))], w, hard)
        if c == "LaunchLogDir":
            return _sub("launch_log_dir", [], w, hard)
        if c in ("EqualsSubstitution", "NotEqualsSubstitution"):
            return _sub("equals" if c == "EqualsSubstitution" else "not-equals", [p(g("left")), p(g("right"))], w,
                        hard)
        if c == "NotSubstitution":
            return _sub("not", [p(g("value"))], w, hard)
        if c in ("AndSubstitution", "OrSubstitution"):
            return _sub("and" if c == "AndSubstitution" else "or", [p(g("left")), p(g("right"))], w, hard)
        if c in ("AnySubstitution", "AllSubstitution"):
            return _sub("any" if c == "AnySubstitution" else "all", [p(x) for x in g("args") or []], w, hard)
        if c == "IfElseSubstitution":
            return _sub("if", [p(g("condition")), p(g("if_value") if g("if_value") is not None else ""),
                               p(g("else_value") if g("else_value") is not None else "")], w, hard)
        if c == "FileContent":
            return _sub("file-content", [p(g("path"))], w, hard)
        if c == "Parameter":
            args = [p(g("name"))]
            if g("default") is not None:
                args.append(p(g("default")))
            return _sub("param", args, w, hard)
        return self.unknown(Unknown(f"the substitution {c} is not modelled", w), hard)

    def cond(self, v, e: PyEntity, o: LObj) -> Optional[A.Cond]:
        if v is None:
            return None
        if isinstance(v, LObj) and v.cls in ("IfCondition", "UnlessCondition"):
            val = self.value(v.get("predicate_expression"), e, None, "condition")
            aw = o.extra.get("arg_where", {}).get("condition")
            if aw and aw[0][0] == self.path:
                val.where_span = aw[0][1]
            self._cond_attr(e, o, "if" if v.cls == "IfCondition" else "unless", val)
            return A.Cond("if" if v.cls == "IfCondition" else "unless", val)
        if isinstance(v, LObj) and v.cls in ("LaunchConfigurationEquals", "LaunchConfigurationNotEquals"):
            name = v.get("launch_configuration_name")
            exp = v.get("expected_value")
            prev = self.cur
            self.cur = e
            try:
                args = [self.parts(name, True, "condition")]
                if exp is not None:
                    args.append(self.parts(exp, True, "condition"))
                if isinstance(name, str) and v.where is not None and v.where[0] == self.path:
                    nw = name.where if isinstance(name, SStr) else None
                    self.add_subst("var", (str(name),), v.where[1], "condition",
                                   nw[1] if nw and nw[0] == self.path else None)
            finally:
                self.cur = prev
            kind = "lc-equals" if v.cls == "LaunchConfigurationEquals" else "lc-not-equals"
            aw = o.extra.get("arg_where", {}).get("condition")
            span = aw[0][1] if aw and aw[0][0] == self.path else None
            val = PyValue([_sub(kind, args, v.where)], None, e, span)
            # shown as the XML equivalent (what the checks and messages read)
            shown = f"$({'equals' if kind == 'lc-equals' else 'not-equals'} $(var {S.plain(args[0])}) " + \
                (S.plain(args[1]) if len(args) > 1 else "") + ")"
            self._cond_attr(e, o, "if", val, shown)
            return A.Cond("if", val)
        u = v if isinstance(v, Unknown) else Unknown(
            f"the condition {v.cls if isinstance(v, LObj) else type(v).__name__} is not modelled",
            getattr(v, "where", None))
        val = PyValue([self.unknown(u, True)], None, e, None)
        self._cond_attr(e, o, "if", val)
        return A.Cond("if", val)

    def _cond_attr(self, e: PyEntity, o: LObj, name: str, val: PyValue, shown: Optional[str] = None) -> None:
        """``if`` / ``unless`` as the XML front end has them (what the checks read: ``$(var x)``),
        and ``condition``: the Python text, for messages."""
        aw = o.extra.get("arg_where", {}).get("condition")
        if aw and aw[0][0] == self.path and name not in e.attrs:
            nspan = aw[1][1] if aw[1] is not None else aw[0][1]
            e.attrs[name] = RAttr(name, shown or S.plain(val.parts), nspan, aw[0][1], None, 0, False, None)
            e._read.add(name)
            src = _source(o, aw[0][1])
            if src is not None:
                e.attrs["condition"] = RAttr("condition", src, nspan, aw[0][1], None, 0, False, None)
                e._read.add("condition")

    # ------------------------------------------------------------------ actions
    def actions(self, ents, parent: Optional[PyEntity]) -> list:
        out: list = []
        if isinstance(ents, Unknown):
            out.append(self.unknown_action(ents, parent))
            return out
        if isinstance(ents, LObj) and ents.cls == "LaunchDescription":
            ents = ents.get("initial_entities") or []
        if not isinstance(ents, (list, tuple)):
            out.append(self.unknown_action(Unknown(f"a {type(ents).__name__} where launch expects a list of "
                                                   "actions"), parent))
            return out
        for x in ents:
            self.depth += 1
            try:
                if self.depth > 60:
                    out.append(self.unknown_action(Unknown("actions nested too deeply to analyse"), parent))
                    continue
                if isinstance(x, LObj) and x.cls == "LaunchDescription":
                    out.extend(self.actions(x.get("initial_entities") or [], parent))
                    continue
                a = self.action(x, parent)
                if a is not None:
                    out.append(a)
            finally:
                self.depth -= 1
        return out

    def unknown_action(self, u: Unknown, parent: Optional[PyEntity]):
        from .actions import UnknownA
        e = self.entity(u, "py_unknown", parent)
        return UnknownA("py_unknown", e, None, reason=u.reason)

    def action(self, o, parent: Optional[PyEntity]):
        if not isinstance(o, LObj):
            if isinstance(o, Unknown):
                return self.unknown_action(o, parent)
            if isinstance(o, PyInstance):
                return self.unknown_action(Unknown(f"an action of the class {o.cls.name} defined in Python (its "
                                                   "execute() is not modelled)", o.cls.where), parent)
            what = "None" if o is None else type(o).__name__
            return self.unknown_action(Unknown(f"a {what} in the list of actions (launch fails on it)"), parent)
        fn = getattr(self, "a_" + o.cls, None)
        if fn is None:
            if o.cls in SUBSTITUTIONS or o.cls in CONDITIONS or o.cls in SOURCES:
                return self.unknown_action(Unknown(f"a {o.cls} in the list of actions (it is no action)", o.where),
                                           parent)
            return self.unknown_action(Unknown(f"the action {o.cls} is not modelled", o.where), parent)
        return fn(o, parent)

    def _name_attr(self, e: PyEntity, o: LObj, key: str, v) -> None:
        """A name given as a literal: its attribute points between the quotes."""
        nw = v.where if isinstance(v, SStr) and v.where and v.where[0] == self.path else None
        aw = o.extra.get("arg_where", {}).get(key)
        if nw is not None:
            e.attrs[key] = RAttr(key, str(v), aw[1][1] if aw and aw[1] else nw[1], nw[1], None, 0, False, None)
            e._read.add(key)
        elif isinstance(v, str):
            self.attr(e, o, key, str(v))

    def a_DeclareLaunchArgument(self, o: LObj, parent):
        e = self.entity(o, "arg", parent)
        name = o.get("name")
        if not isinstance(name, str):
            return self.unknown_action(name if isinstance(name, Unknown) else
                                       Unknown("an argument name that is not a string", o.where), parent)
        self._name_attr(e, o, "name", name)
        cond = self.cond(o.get("condition"), e, o)
        d = o.get("default_value")
        default = self.value(d, e, o, "default") if d is not None else None
        desc = o.get("description")
        ch = o.get("choices")
        a = A.ArgA("arg", e, cond, str(name), default, str(desc) if isinstance(desc, str) else None)
        if desc is not None and isinstance(desc, str):
            self.attr(e, o, "description", str(desc))
        if isinstance(ch, (list, tuple)) and all(isinstance(x, str) for x in ch):
            a.choices = [str(x) for x in ch]
        elif ch is not None:
            return self.unknown_action(Unknown("choices tvl-lsp cannot know", o.where), parent)
        return a

    def a_SetLaunchConfiguration(self, o: LObj, parent):
        e = self.entity(o, "let", parent)
        cond = self.cond(o.get("condition"), e, o)
        self._name_attr(e, o, "name", o.get("name"))
        return A.LetA("let", e, cond, self.value(o.get("name"), e, o, "name"), self.value(o.get("value"), e, o,
                                                                                          "value"))

    def a_UnsetLaunchConfiguration(self, o: LObj, parent):
        from .actions import UnsetA
        e = self.entity(o, "unset", parent)
        cond = self.cond(o.get("condition"), e, o)
        return UnsetA("unset", e, cond, name=self.value(o.get("name"), e, o, "name"))

    def _keeps(self, confs, e: PyEntity, o: LObj) -> Optional[list]:
        if confs is None:
            return None
        if not isinstance(confs, dict):
            return [A.KeepA(self.value(Unknown("launch_configurations tvl-lsp cannot know"), e, o, ""),
                            self.value(Unknown("launch_configurations tvl-lsp cannot know"), e, o, ""), e)]
        return [A.KeepA(self.value(k, e, o, ""), self.value(v, e, o, ""), e) for k, v in confs.items()]

    def a_GroupAction(self, o: LObj, parent):
        e = self.entity(o, "group", parent)
        cond = self.cond(o.get("condition"), e, o)
        scoped = o.get("scoped", True)
        fwd = o.get("forwarding", True)
        if not isinstance(scoped, bool) or not isinstance(fwd, bool):
            return self.unknown_action(Unknown("GroupAction's scoped / forwarding tvl-lsp cannot know", o.where),
                                       parent)
        g = A.GroupA("group", e, cond, scoped, fwd, self._keeps(o.get("launch_configurations"), e, o))
        g.actions = self.actions(o.get("actions"), e)
        return g

    def a_ResetLaunchConfigurations(self, o: LObj, parent):
        e = self.entity(o, "reset", parent)
        return A.ResetA("reset", e, self.cond(o.get("condition"), e, o),
                        self._keeps(o.get("launch_configurations"), e, o))

    def a_IncludeLaunchDescription(self, o: LObj, parent):
        e = self.entity(o, "include", parent)
        cond = self.cond(o.get("condition"), e, o)
        src = o.get("launch_description_source")
        kind = "any"
        if isinstance(src, LObj) and src.cls in SOURCES:
            if src.cls == "LaunchDescriptionSource":
                return self.unknown_action(Unknown("an include of a launch description made in Python "
                                                   "(LaunchDescriptionSource) is not modelled", o.where), parent)
            kind = {"PythonLaunchDescriptionSource": "py", "XMLLaunchDescriptionSource": "xml",
                    "YAMLLaunchDescriptionSource": "yaml"}.get(src.cls, "any")
            path = src.get("launch_file_path")
            file = self.value(path, e, src, "launch_file_path")
            self.attr(e, o, "file", S.plain(file.parts), span=file.span())
        else:
            file = self.value(src, e, o, "launch_description_source")
            self.attr(e, o, "file", S.plain(file.parts), span=file.span())
        inc = A.IncludeA("include", e, cond, file)
        inc.source_kind = kind
        args = o.get("launch_arguments")
        if args is None:
            return inc
        if isinstance(args, dict):
            return self.unknown_action(Unknown("launch_arguments given as a dict (launch iterates it as names "
                                               "only): use .items()", o.where), parent)
        if isinstance(args, Unknown) or not isinstance(args, (list, tuple)):
            u = args if isinstance(args, Unknown) else Unknown("launch_arguments tvl-lsp cannot know", o.where)
            return self.unknown_action(u, parent)
        for pair in args:
            if not isinstance(pair, (list, tuple)) or len(pair) != 2:
                u = pair if isinstance(pair, Unknown) else Unknown("a launch argument that is not a (name, value) "
                                                                   "pair", o.where)
                return self.unknown_action(u, parent)
            k, v = pair
            ae = self.entity_for_arg(k, e, o)
            self._name_attr_plain(ae, k)
            prev = self.cur
            self.cur = ae
            try:
                nv = PyValue(self.parts(k, True, "name"), None, ae, ae.attrs["name"].value_span if "name" in ae.attrs
                             else None)
                vv = PyValue(self.parts(v, True, "value"), None, ae, _where_span(v, self.path))
            finally:
                self.cur = prev
            if "value" not in ae.attrs:
                sp = _where_span(v, self.path) or ae.tag_span
                ae.attrs["value"] = RAttr("value", S.plain(vv.parts), sp, sp, None, 0, False, None)
            inc.args.append(A.IncArg(nv, vv, ae))
        return inc

    def entity_for_arg(self, k, parent: PyEntity, o: LObj) -> PyEntity:
        w = k.where if isinstance(k, SStr) and k.where and k.where[0] == self.path else None
        span = w[1] if w else parent.span
        key = (span, "arg", id(parent)) if w else (parent.span, "arg", str(k), id(parent))
        e = self.entities.get(key)
        if e is None:
            e = PyEntity("arg", self.path, span, parent)
            parent.kids.append(e)
            self.entities[key] = e
        return e

    def _name_attr_plain(self, e: PyEntity, k) -> None:
        if "name" in e.attrs:
            return
        if isinstance(k, str):
            w = k.where if isinstance(k, SStr) and k.where and k.where[0] == self.path else None
            sp = w[1] if w else e.tag_span
            e.attrs["name"] = RAttr("name", str(k), sp, sp, None, 0, False, None)
            e._read.add("name")

    # -- nodes
    def remaps(self, v, e: PyEntity, o: LObj) -> list:
        if v is None:
            return []
        if isinstance(v, Unknown) or not isinstance(v, (list, tuple)):
            u = v if isinstance(v, Unknown) else Unknown("remappings tvl-lsp cannot know", o.where)
            bad = self.value(u, e, o, "remappings")
            return [A.RemapA(bad, bad, e)]
        out = []
        for pair in v:
            if not isinstance(pair, (list, tuple)) or len(pair) != 2:
                u = pair if isinstance(pair, Unknown) else Unknown("a remapping that is not a (from, to) pair",
                                                                   o.where)
                bad = self.value(u, e, o, "")
                out.append(A.RemapA(bad, bad, e))
                continue
            out.append(A.RemapA(self.value(pair[0], e, None, ""), self.value(pair[1], e, None, ""), e))
        if out:
            self.attr(e, o, "remappings", ", ".join(f"{S.plain(r.src.parts)}:={S.plain(r.dst.parts)}" for r in out))
        return out

    def params(self, v, e: PyEntity, o: LObj) -> list:
        from .params import convert_params
        return convert_params(self, v, e, o)

    def cmdline(self, v, e: PyEntity, o: LObj, name: str) -> Optional[PyValue]:
        if v is None:
            return None
        if isinstance(v, (list, tuple)):
            parts: list = []
            for i, x in enumerate(v):
                if i:
                    parts.append(_text(" "))
                parts.extend(self.parts(x, False, name))
            val = PyValue(parts, None, e, None)
            self.attr(e, o, name, S.plain(parts))
            return val
        return self.value(v, e, o, name, hard=False)

    def a_Node(self, o: LObj, parent, tag: str = "node"):
        e = self.entity(o, tag, parent)
        a = A.NodeA(tag, e, self.cond(o.get("condition"), e, o))
        a.kind = {"LifecycleNode": "lifecycle_node"}.get(o.cls, tag)
        pkg = o.get("package")
        a.package = self.value(pkg, e, o, "package") if pkg is not None else None
        a.executable = self.value(o.get("executable"), e, o, "executable")
        if o.get("name") is not None:
            a.name = self.value(o.get("name"), e, o, "name")
            self._name_attr(e, o, "name", o.get("name"))
        if o.get("namespace") is not None:
            a.namespace = self.value(o.get("namespace"), e, o, "namespace")
        a.remaps = self.remaps(o.get("remappings"), e, o)
        a.params = self.params(o.get("parameters"), e, o)
        a.args = self.cmdline(o.get("arguments"), e, o, "arguments")
        a.ros_args = self.cmdline(o.get("ros_arguments"), e, o, "ros_arguments")
        if tag == "node_container":
            comps = o.get("composable_node_descriptions")
            a.composables = self.composables(comps, e, o)
        return a

    a_LifecycleNode = a_Node

    def a_ComposableNodeContainer(self, o: LObj, parent):
        return self.a_Node(o, parent, "node_container")

    def composables(self, comps, e: PyEntity, o: LObj) -> list:
        if comps is None:
            return []
        if isinstance(comps, Unknown) or not isinstance(comps, (list, tuple)):
            u = comps if isinstance(comps, Unknown) else Unknown("composable nodes tvl-lsp cannot know", o.where)
            return [self.bad_composable(u, e)]
        out = []
        for c in comps:
            if not isinstance(c, LObj) or c.cls != "ComposableNode":
                u = c if isinstance(c, Unknown) else Unknown("a composable node description tvl-lsp does not model",
                                                             getattr(c, "where", None))
                out.append(self.bad_composable(u, e))
                continue
            ce = self.entity(c, "composable_node", e)
            ca = A.ComposableA(ce)
            ca.package = self.value(c.get("package"), ce, c, "package")
            ca.plugin = self.value(c.get("plugin"), ce, c, "plugin")
            if c.get("name") is not None:
                ca.name = self.value(c.get("name"), ce, c, "name")
                self._name_attr(ce, c, "name", c.get("name"))
            if c.get("namespace") is not None:
                ca.namespace = self.value(c.get("namespace"), ce, c, "namespace")
            ca.cond = self.cond(c.get("condition"), ce, c)
            ca.params = self.params(c.get("parameters"), ce, c)
            ca.remaps = self.remaps(c.get("remappings"), ce, c)
            out.append(ca)
        return out

    def bad_composable(self, u: Unknown, e: PyEntity):
        ce = self.entity(u, "composable_node", e)
        ca = A.ComposableA(ce)
        bad = self.value(u, ce, None, "")
        ca.package, ca.plugin, ca.name = bad, bad, bad
        return ca

    def a_LoadComposableNodes(self, o: LObj, parent):
        e = self.entity(o, "load_composable_node", parent)
        a = A.LoadComposableA("load_composable_node", e, self.cond(o.get("condition"), e, o))
        t = o.get("target_container")
        if isinstance(t, LObj) and t.cls in ("ComposableNodeContainer", "Node"):
            t = t.get("name") if t.get("name") is not None else Unknown("the container's name")
        a.target = self.value(t, e, o, "target_container", hard=False)
        a.composables = self.composables(o.get("composable_node_descriptions"), e, o)
        return a

    def a_PushROSNamespace(self, o: LObj, parent):
        e = self.entity(o, "push_ros_namespace", parent)
        return A.PushNsA("push_ros_namespace", e, self.cond(o.get("condition"), e, o),
                         self.value(o.get("namespace"), e, o, "namespace"))

    a_PushRosNamespace = a_PushROSNamespace

    def a_SetRemap(self, o: LObj, parent):
        e = self.entity(o, "set_remap", parent)
        return A.SetRemapA("set_remap", e, self.cond(o.get("condition"), e, o), self.value(o.get("src"), e, o, "src"),
                           self.value(o.get("dst"), e, o, "dst"))

    def a_SetParameter(self, o: LObj, parent):
        e = self.entity(o, "set_parameter", parent)
        v = o.get("value")
        if isinstance(v, (bool, int, float)) and not isinstance(v, str):
            v = "true" if v is True else "false" if v is False else repr(v)
        return A.SetParamA("set_parameter", e, self.cond(o.get("condition"), e, o),
                           self.value(o.get("name"), e, o, "name"), self.value(v, e, o, "value", hard=False))

    def a_SetParametersFromFile(self, o: LObj, parent):
        e = self.entity(o, "set_parameters_from_file", parent)
        return A.SetParamFileA("set_parameters_from_file", e, self.cond(o.get("condition"), e, o),
                               self.value(o.get("filename"), e, o, "filename", hard=False))

    def a_SetEnvironmentVariable(self, o: LObj, parent):
        e = self.entity(o, "set_env", parent)
        return A.EnvA("set_env", e, self.cond(o.get("condition"), e, o), self.value(o.get("name"), e, o, "name"),
                      self.value(o.get("value"), e, o, "value"))

    def a_UnsetEnvironmentVariable(self, o: LObj, parent):
        e = self.entity(o, "unset_env", parent)
        return A.EnvA("unset_env", e, self.cond(o.get("condition"), e, o), self.value(o.get("name"), e, o, "name"))

    def a_AppendEnvironmentVariable(self, o: LObj, parent):
        e = self.entity(o, "append_env", parent)
        a = A.EnvA("append_env", e, self.cond(o.get("condition"), e, o), self.value(o.get("name"), e, o, "name"),
                   self.value(o.get("value"), e, o, "value"))
        pre = o.get("prepend", False)
        a.prepend = pre if isinstance(pre, bool) else self.value(pre, e, o, "prepend")
        sep = o.get("separator")
        if sep is not None:
            a.separator = self.value(sep, e, o, "separator")
        return a

    def a_ResetEnvironment(self, o: LObj, parent):
        e = self.entity(o, "reset_env", parent)
        return A.SimpleA("reset_env", e, self.cond(o.get("condition"), e, o))

    def a_LogInfo(self, o: LObj, parent):
        e = self.entity(o, "log", parent)
        return A.LogA("log", e, self.cond(o.get("condition"), e, o), self.value(o.get("msg"), e, o, "msg",
                                                                              hard=False))

    def a_TimerAction(self, o: LObj, parent, tag: str = "timer"):
        e = self.entity(o, tag, parent)
        period = o.get("period")
        if isinstance(period, bool) or not isinstance(period, (int, float)):
            period = self.value(period, e, o, "period", hard=False)
        t = A.TimerA(tag, e, self.cond(o.get("condition"), e, o), period)
        t.actions = self.actions(o.get("actions"), e)
        return t

    def a_RosTimer(self, o: LObj, parent):
        return self.a_TimerAction(o, parent, "ros_timer")

    a_ROSTimer = a_RosTimer

    def a_ExecuteProcess(self, o: LObj, parent):
        e = self.entity(o, "executable", parent)
        a = A.ExecA("executable", e, self.cond(o.get("condition"), e, o))
        cmd = o.get("cmd")
        if isinstance(cmd, Unknown) or not isinstance(cmd, (list, tuple)):
            u = cmd if isinstance(cmd, Unknown) else Unknown("an ExecuteProcess command tvl-lsp cannot know",
                                                             o.where)
            a.cmd = [self.parts(u, False, "cmd")]
        else:
            prev = self.cur
            self.cur = e
            try:
                a.cmd = [self.parts(x, False, "cmd") for x in cmd]
            finally:
                self.cur = prev
        flat = [p for w in a.cmd for p in w]
        a.cmd_value = PyValue(flat, None, e, _arg_span(o, "cmd", self.path))
        self.attr(e, o, "cmd", " ".join(S.plain(w) for w in a.cmd))
        if o.get("name") is not None:
            a.name = self.value(o.get("name"), e, o, "name", hard=False)
        if o.get("cwd") is not None:
            a.cwd = self.value(o.get("cwd"), e, o, "cwd", hard=False)
        return a

    def a_Shutdown(self, o: LObj, parent):
        e = self.entity(o, "shutdown", parent)
        r = o.get("reason")
        return A.SimpleA("shutdown", e, self.cond(o.get("condition"), e, o),
                         [self.value(r, e, o, "reason", hard=False)] if r is not None else [])

    def _simple(self, tag: str, keys=()):
        def fn(o: LObj, parent):
            e = self.entity(o, tag, parent)
            vals = [self.value(o.get(k), e, o, k, hard=False) for k in keys if o.get(k) is not None]
            return A.SimpleA(tag, e, self.cond(o.get("condition"), e, o), vals)
        return fn

    def a_SetUseSimTime(self, o, parent):
        return self._simple("set_use_sim_time")(o, parent)

    def a_SetROSLogDir(self, o, parent):
        return self._simple("set_ros_log_dir")(o, parent)

    def a_EmitEvent(self, o, parent):
        return self._simple("emit_event")(o, parent)

    def a_UnregisterEventHandler(self, o, parent):
        return self._simple("unregister_event_handler")(o, parent)

    def a_LifecycleTransition(self, o, parent):
        return self._simple("lifecycle_transition")(o, parent)

    def a_OpaqueFunction(self, o: LObj, parent):
        from .actions import OpaqueA
        e = self.entity(o, "opaque_function", parent)
        fn = o.get("function")
        self.attr(e, o, "function", getattr(fn, "name", "") if not isinstance(fn, Unknown) else "")
        return OpaqueA("opaque_function", e, self.cond(o.get("condition"), e, o), function=fn,
                       args=o.get("args") or [], kwargs=o.get("kwargs") or {}, where=o.where)

    def a_RegisterEventHandler(self, o: LObj, parent):
        from .actions import EventA
        e = self.entity(o, "event_handler", parent)
        h = o.get("event_handler")
        cond = self.cond(o.get("condition"), e, o)
        if not isinstance(h, LObj):
            return EventA("event_handler", e, cond, event="?", target="", actions=[],
                          reason=h.reason if isinstance(h, Unknown) else "an event handler tvl-lsp does not model")
        key = {"OnProcessStart": "on_start", "OnProcessExit": "on_exit", "OnShutdown": "on_shutdown",
               "OnExecutionComplete": "on_completion", "OnProcessIO": "on_stdout", "OnStateTransition": "entities",
               "OnIncludeLaunchDescription": "entities"}.get(h.cls)
        self.attr(e, o, "event", h.cls, shown=h.cls)
        target = h.get("target_action") or h.get("target_lifecycle_node")
        tname = _describe_target(target)
        if key is None:
            return EventA("event_handler", e, cond, event=h.cls, target=tname, actions=[],
                          reason=f"the event handler {h.cls} is not modelled")
        acts = h.get(key)
        if h.cls == "OnProcessIO" and acts is None:
            acts = h.get("on_stderr")
        if acts is None or isinstance(acts, (list, tuple, LObj)) and not isinstance(acts, Unknown):
            lst = [acts] if isinstance(acts, LObj) else list(acts or [])
            if all(isinstance(x, LObj) or isinstance(x, Unknown) for x in lst):
                return EventA("event_handler", e, cond, event=h.cls, target=tname, actions=self.actions(lst, e))
        return EventA("event_handler", e, cond, event=h.cls, target=tname, actions=[],
                      reason="the handler's actions are made by a function when the event happens (not analysed)")

    def a_OnShutdown(self, o, parent):
        return self.unknown_action(Unknown("an event handler outside RegisterEventHandler", o.where), parent)


def _source(o: LObj, span: Span, limit: int = 200) -> Optional[str]:
    """The text of the file at ``span`` (one line, shortened) -- an argument as written."""
    m = o.extra.get("module")
    if m is None:
        return None
    idx = m.index
    text = idx.text[idx.offset(span.start):idx.offset(span.end)]
    text = " ".join(text.split())
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _describe_target(t) -> str:
    if isinstance(t, LObj):
        for k in ("name", "executable", "cmd"):
            v = t.get(k)
            if isinstance(v, str):
                return f"{t.cls}({v})"
            if isinstance(v, LObj) and v.cls == "LaunchConfiguration" and isinstance(v.get("variable_name"), str):
                return f"{t.cls}($(var {v.get('variable_name')}))"
        return t.cls
    return ""


def _where_span(v, path: str) -> Optional[Span]:
    w = getattr(v, "where", None) if isinstance(v, (SStr, LObj, Unknown)) else None
    return w[1] if w and w[0] == path else None


def _arg_span(o: LObj, name: str, path: str) -> Optional[Span]:
    aw = o.extra.get("arg_where", {}).get(name)
    return aw[0][1] if aw and aw[0][0] == path else None


__all__ = ["Converter", "PyEntity", "PyValue"]
