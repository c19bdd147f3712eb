"""ROS 2 launch files as actions: the ``parse`` methods of launch and launch_ros, tag by tag.

:func:`parse_description` turns the root entity of a launch file into a list of actions, as
launch does when it loads the file (before anything runs): the same attributes are read, in
the same order, with the same type handling, and the same mistakes refuse the file (an
unknown tag or attribute, a missing attribute, a malformed or unknown substitution, ``if``
with ``unless``, ...).  Where launch stops at the first mistake, this module records each one
with its exact range and goes on with the next action, so that an editor sees them all; the
first one (``Unit.error``) is what ``ros2 launch`` reports.
"""

from __future__ import annotations

import functools
import shlex
from dataclasses import dataclass, field
from typing import Any, Optional, Union

from ...base.text import Span
from . import subst as S
from . import coerce as C
from .frontend import LIST, Entity, FrontendError, RAttr

Parts = list  # list[S.Part]

# substitution name -> (min args, max args or None, the message launch raises otherwise)
SUBSTITUTIONS: dict[str, tuple[int, Optional[int], str, str]] = {
    "var": (1, 2, "TypeError", "var substitution expects 1 or 2 arguments"),
    "env": (1, 2, "TypeError", "env substitution expects 1 or 2 arguments"),
    "eval": (1, 2, "TypeError", "eval substitution expects 1 or 2 arguments"),
    "not": (1, 1, "TypeError", "not substitution expects 1 argument"),
    "and": (2, 2, "TypeError", "and substitution expects 2 arguments"),
    "or": (2, 2, "TypeError", "and substitution expects 2 arguments"),
    "any": (0, None, "", ""),
    "all": (0, None, "", ""),
    "equals": (2, 2, "TypeError", "and substitution expects 2 arguments"),
    "not-equals": (2, 2, "TypeError", "and substitution expects 2 arguments"),
    "if": (2, 3, "TypeError", "if substitution expects from 2 or 3 arguments"),
    "dirname": (0, 0, "TypeError", "dirname substitution doesn't expect arguments"),
    "filename": (0, 0, "TypeError", "filename substitution doesn't expect arguments"),
    "anon": (1, 1, "TypeError", "anon substitution expects 1 argument"),
    "command": (1, 2, "ValueError", "command substitution expects 1 or 2 arguments"),
    "find-exec": (1, 1, "AttributeError", "find-exec substitution expects 1 argument"),
    "file-content": (1, 1, "AttributeError", "file content substitutions expect 1 argument"),
    "launch_log_dir": (0, 0, "TypeError", "launch_log_dir substitution doesn't expect arguments"),
    "log_dir": (0, 0, "TypeError", "log_dir substitution doesn't expect arguments"),
    "find-pkg-prefix": (1, 1, "AttributeError", "find package substitutions expect 1 argument"),
    "find-pkg-share": (1, 1, "AttributeError", "find package substitutions expect 1 argument"),
    "exec-in-pkg": (2, 2, "AttributeError", "exec-in-package substitution expects 2 arguments"),
    "param": (1, 2, "TypeError", "param substitution expects 1 or 2 arguments"),
}

TAGS = ("executable", "shutdown", "reset_env", "arg", "log", "unset_env", "reset", "include", "append_env",
        "set_env", "group", "timer", "let", "set_parameter", "ros_timer", "load_composable_node",
        "node_container", "set_ros_log_dir", "set_parameters_from_file", "set_remap", "node",
        "set_use_sim_time", "push_ros_namespace", "push-ros-namespace")



@functools.lru_cache(maxsize=256)
def _shlex_split(text: str) -> tuple[str, ...]:
    """shlex.split, remembered: the symbolic walk reads a node's command line once per case
    (a 2,000-character ``args`` took 1 ms of shlex's character loop each time)."""
    return tuple(shlex.split(text))

class LoadError(Exception):
    """A mistake that makes launch refuse the file: ``kind`` is the exception launch raises."""

    def __init__(self, kind: str, message: str, span: Span, path: str = "", prefix: str = ""):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.span = span
        self.path = path
        self.prefix = prefix   # what launch writes before the message (lark's VisitError)

    @property
    def launch_text(self) -> str:
        return self.prefix + self.message


# ------------------------------------------------------------------ values

@dataclass
class Value:
    """A parsed substitution string, with where it is (``attr``: the attribute holding it)."""
    parts: Parts
    attr: Optional[RAttr] = None
    entity: Optional[Entity] = None

    def span(self) -> Span:
        if self.attr is not None:
            return self.attr.value_span
        return self.entity.tag_span if self.entity is not None else None

    def sub_span(self, sub) -> Span:
        if self.attr is not None:
            return self.attr.span_of(sub.start, sub.end)
        return self.span()

    @property
    def text(self) -> str:
        return S.plain(self.parts)


@dataclass
class Cond:
    kind: str          # "if" | "unless"
    value: Value


@dataclass
class Action:
    tag: str
    entity: Entity
    cond: Optional[Cond] = None


@dataclass
class ArgA(Action):
    name: str = ""
    default: Optional[Value] = None
    description: Optional[str] = None
    choices: Optional[list[str]] = None

    @property
    def described(self) -> str:
        """launch's DeclareLaunchArgument.description."""
        if self.description is None:
            return "no description given" if self.choices is None else "One of: " + str(self.choices)
        d = self.description
        if self.choices is not None:
            if not d.endswith("."):
                d += "."
            d += " Valid choices are: " + str(self.choices)
        return d


@dataclass
class LetA(Action):
    name: Value = None
    value: Value = None


@dataclass
class KeepA:
    name: Value
    value: Value
    entity: Entity


@dataclass
class GroupA(Action):
    scoped: Any = True
    forwarding: Any = True
    keeps: Optional[list[KeepA]] = None
    actions: list[Action] = field(default_factory=list)


@dataclass
class IncArg:
    name: Value
    value: Value
    entity: Entity


@dataclass
class IncludeA(Action):
    file: Value = None
    args: list[IncArg] = field(default_factory=list)


@dataclass
class ParamFileA:
    path: Value
    entity: Entity
    allow_substs: Any = False


@dataclass
class ParamA:
    """``<param name value type>`` or nested ``<param name><param .../></param>``."""
    name: Value
    entity: Entity
    value: Any = None            # Value, a typed scalar/list, or a list of Values
    type: Optional[str] = None
    nested: Optional[list["ParamA"]] = None
    dtype: Any = None            # the data type of ``type`` (coerce.TYPE_IDS): what launch types it as


@dataclass
class RemapA:
    src: Value
    dst: Value
    entity: Entity


@dataclass
class ComposableA:
    entity: Entity
    package: Value = None
    plugin: Value = None
    name: Value = None
    namespace: Optional[Value] = None
    params: list = field(default_factory=list)
    remaps: list[RemapA] = field(default_factory=list)
    cond: Optional[Cond] = None


@dataclass
class ExecA(Action):
    respawn: Optional[Value] = None
    cmd: list[list[S.Part]] = field(default_factory=list)
    cmd_value: Optional[Value] = None
    name: Optional[Value] = None
    cwd: Optional[Value] = None
    env: list[tuple[Value, Value]] = field(default_factory=list)


@dataclass
class NodeA(Action):
    respawn: Optional[Value] = None
    package: Optional[Value] = None
    executable: Value = None
    name: Optional[Value] = None
    namespace: Optional[Value] = None
    args: Optional[Value] = None
    ros_args: Optional[Value] = None
    remaps: list[RemapA] = field(default_factory=list)
    params: list = field(default_factory=list)   # ParamFileA | list[ParamA] (one dict per <param name>)
    composables: list[ComposableA] = field(default_factory=list)


@dataclass
class LoadComposableA(Action):
    target: Value = None
    composables: list[ComposableA] = field(default_factory=list)


@dataclass
class PushNsA(Action):
    namespace: Value = None


@dataclass
class SetRemapA(Action):
    src: Value = None
    dst: Value = None


@dataclass
class SetParamA(Action):
    name: Value = None
    value: Value = None


@dataclass
class SetParamFileA(Action):
    filename: Value = None


@dataclass
class EnvA(Action):
    """set_env / unset_env / append_env."""
    name: Value = None
    value: Optional[Value] = None
    prepend: Any = None
    separator: Optional[Value] = None


@dataclass
class LogA(Action):
    message: Value = None


@dataclass
class TimerA(Action):
    period: Any = None
    actions: list[Action] = field(default_factory=list)


@dataclass
class SimpleA(Action):
    """Actions without effect on what is launched (shutdown, set_use_sim_time, set_ros_log_dir,
    reset_env): their substitutions are still evaluated."""
    values: list[Value] = field(default_factory=list)


@dataclass
class ResetA(Action):
    keeps: Optional[list[KeepA]] = None


Action_ = Union[Action]


# ------------------------------------------------------------------ the parser

class Parser:
    def __init__(self, path: str):
        self.path = path
        self.errors: list[LoadError] = []

    # -- substitutions
    def subst(self, e: Entity, name: str, raw) -> Value:
        """launch's ``parser.parse_substitution(value)`` of attribute ``name`` of ``e``."""
        a = e.attrs.get(name) if name else None
        text = raw if isinstance(raw, str) else str(raw)
        try:
            parts = S.parse(text)
        except S.SubstSyntaxError as ex:
            span = a.span_of(ex.pos, ex.pos + 1) if a is not None else e.tag_span
            raise LoadError("UnexpectedCharacters", f"invalid substitution in '{text}': {ex}", span, self.path)
        v = Value(parts, a, e)
        self.check_subs(parts, v)
        return v

    def check_subs(self, parts: Parts, v: Value) -> None:
        for sub in S.walk(parts):
            spec = SUBSTITUTIONS.get(sub.name)
            span = v.sub_span(sub)
            # lark wraps what the substitution's parse method raises
            rule = {"'": "single_quoted_substitution", '"': "double_quoted_substitution"}.get(sub.quote, "substitution")
            wrap = f'Error trying to process rule "{rule}":\n\n'
            if spec is None:
                raise LoadError("VisitError", f"Unknown substitution: {sub.name}", span, self.path, wrap)
            lo, hi, kind, msg = spec
            n = len(sub.args)
            if n < lo or (hi is not None and n > hi):
                raise LoadError("VisitError", msg, span, self.path, wrap)

    def opt_subst(self, e: Entity, name: str) -> Optional[Value]:
        raw = e.get_attr(name, optional=True)
        return None if raw is None else self.subst(e, name, raw)

    def req_subst(self, e: Entity, name: str) -> Value:
        return self.subst(e, name, e.get_attr(name))

    def escape(self, raw) -> str:
        return S.unescape(raw if isinstance(raw, str) else str(raw))

    # -- Action.parse: if / unless
    def condition(self, e: Entity) -> Optional[Cond]:
        ifc = e.get_attr("if", optional=True)
        unc = e.get_attr("unless", optional=True)
        if ifc is not None and unc is not None:
            raise LoadError("RuntimeError", "if and unless conditions can't be used simultaneously", e.tag_span,
                            self.path)
        if ifc is not None:
            return Cond("if", self.subst(e, "if", ifc))
        if unc is not None:
            return Cond("unless", self.subst(e, "unless", unc))
        return None

    # -- the description
    def description(self, root: Entity) -> list[Action]:
        if root.tag != "launch":
            raise LoadError("RuntimeError", "Expected 'launch' as root tag", root.tag_span, self.path)
        try:
            root.get_attr("deprecated", optional=True)
            kids = root.children()
        except FrontendError as ex:
            raise LoadError(ex.kind, str(ex), ex.span, self.path)
        return self.actions(kids)

    def actions(self, entities: list[Entity]) -> list[Action]:
        out = []
        for c in entities:
            a = self.action(c)
            if a is not None:
                out.append(a)
        return out

    def action(self, e: Entity) -> Optional[Action]:
        """One action; a mistake is recorded (and the action skipped)."""
        try:
            fn = getattr(self, "p_" + e.tag.replace("-", "_"), None) if e.tag in TAGS else None
            if fn is None:
                raise LoadError("RuntimeError", f"Unrecognized entity of the type: {e.tag}", e.tag_span, self.path)
            a = fn(e)
            e.assert_parsed()
            return a
        except FrontendError as ex:
            self.errors.append(LoadError(ex.kind, str(ex), ex.span, self.path))
        except LoadError as ex:
            self.errors.append(ex)
        return None

    # -- tags (launch)
    def p_arg(self, e: Entity) -> ArgA:
        cond = self.condition(e)
        name = self.escape(e.get_attr("name"))
        default = self.opt_subst(e, "default")
        desc = e.get_attr("description", optional=True)
        choices = e.get_attr("choice", data_type=LIST, optional=True)
        a = ArgA("arg", e, cond, name, default, self.escape(desc) if desc is not None else None)
        if choices is not None:
            a.choices = [self.escape(c.get_attr("value")) for c in choices]
            if not a.choices:
                raise LoadError("RuntimeError", "Provided choices arg is empty. Use None to ignore the choice list.",
                                e.tag_span, self.path)
        return a

    def p_let(self, e: Entity) -> LetA:
        name = self.req_subst(e, "name")
        value = self.req_subst(e, "value")
        return LetA("let", e, self.condition(e), name, value)

    def keeps(self, e: Entity) -> Optional[list[KeepA]]:
        ks = e.get_attr("keep", data_type=LIST, optional=True)
        if ks is None:
            return None
        out = [KeepA(self.req_subst(k, "name"), self.req_subst(k, "value"), k) for k in ks]
        for k in ks:
            k.assert_parsed()
        return out

    def p_group(self, e: Entity) -> GroupA:
        cond = self.condition(e)
        scoped = e.get_attr("scoped", data_type=bool, optional=True)
        forwarding = e.get_attr("forwarding", data_type=bool, optional=True)
        keeps = self.keeps(e)
        g = GroupA("group", e, cond, True if scoped is None else scoped,
                   True if forwarding is None else forwarding, keeps)
        g.actions = self.actions([c for c in e.children() if c.tag != "keep"])
        return g

    def p_reset(self, e: Entity) -> ResetA:
        cond = self.condition(e)
        return ResetA("reset", e, cond, self.keeps(e))

    def p_include(self, e: Entity) -> IncludeA:
        cond = self.condition(e)
        inc = IncludeA("include", e, cond, self.req_subst(e, "file"))
        args = e.get_attr("arg", data_type=LIST, optional=True)
        if args is not None:
            inc.args = [IncArg(self.req_subst(a, "name"), self.req_subst(a, "value"), a) for a in args]
            for a in args:
                a.assert_parsed()
        return inc

    def cmdline(self, e: Entity, name: str, raw) -> list[list[S.Part]]:
        """ExecuteProcess._parse_cmdline: text around substitutions is split with shlex."""
        v = self.subst(e, name, raw)
        out: list[list[S.Part]] = []
        arg: list[S.Part] = []
        for sub in v.parts:
            if isinstance(sub, S.Text):
                try:
                    tokens = _shlex_split(sub.text)
                except ValueError as ex:
                    raise LoadError("ValueError", str(ex), v.span(), self.path)
                if not tokens:
                    out.append(arg)
                    arg = []
                    continue
                if sub.text[0].isspace() and arg:
                    out.append(arg)
                    arg = []
                arg.append(S.Text(tokens[0], sub.start, sub.end))
                if len(tokens) > 1:
                    out.append(arg)
                    arg = [S.Text(tokens[-1], sub.start, sub.end)]
                if len(tokens) > 2:
                    out.extend([S.Text(x, sub.start, sub.end)] for x in tokens[1:-1])
                if sub.text[-1].isspace():
                    out.append(arg)
                    arg = []
            else:
                arg.append(sub)
        if arg:
            out.append(arg)
        return out

    def exec_common(self, e: Entity, a: Union[ExecA, NodeA], with_cmd: bool) -> None:
        a.cond = self.condition(e)
        if with_cmd:
            raw = e.get_attr("cmd")
            a.cmd = self.cmdline(e, "cmd", raw)
            a.cmd_value = Value(S.parse(raw), e.attrs.get("cmd"), e)
        a_cwd = self.opt_subst(e, "cwd")
        name = self.opt_subst(e, "name")
        if isinstance(a, ExecA):
            a.cwd, a.name = a_cwd, name
        on_exit = e.get_attr("on_exit", optional=True)
        if on_exit is not None and on_exit != "shutdown":
            raise LoadError("ValueError", "Attribute on_exit of Entity node expected to be shutdown but got "
                            f"`{on_exit}`Other on_exit actions not yet supported", e.aspan("on_exit"), self.path)
        self.opt_subst(e, "launch-prefix")
        self.opt_subst(e, "output")
        a.respawn = self.opt_subst(e, "respawn")   # typed as a bool when the process starts (nodes.py)
        e.get_attr("respawn_max_retries", data_type=int, optional=True)
        for k in ("respawn_delay", "sigkill_timeout", "sigterm_timeout"):
            v = e.get_attr(k, data_type=float, optional=True)
            if isinstance(v, str):  # not a number (a substitution too): launch compares it with 0.0
                raise LoadError("TypeError", "'<' not supported between instances of 'str' and 'float'",
                                e.aspan(k), self.path)
            if v is not None and v < 0.0:
                raise LoadError("ValueError", f"Attribute {k} of Entity node expected to be a non-negative value "
                                f"but got `{v}`", e.aspan(k), self.path)
        e.get_attr("shell", data_type=bool, optional=True)
        e.get_attr("emulate_tty", data_type=bool, optional=True)
        env = e.get_attr("env", data_type=LIST, optional=True)
        if env is not None:
            pairs = [(self.req_subst(x, "name"), self.req_subst(x, "value")) for x in env]
            for x in env:
                x.assert_parsed()
            if isinstance(a, ExecA):
                a.env = pairs

    def p_executable(self, e: Entity) -> ExecA:
        a = ExecA("executable", e)
        self.exec_common(e, a, True)
        return a

    def p_node(self, e: Entity, tag: str = "node") -> NodeA:
        a = NodeA(tag, e)
        self.exec_common(e, a, False)
        args = e.get_attr("args", optional=True)
        if args is not None:
            self.cmdline(e, "args", args)
            a.args = self.subst(e, "args", args)
        ros_args = e.get_attr("ros_args", optional=True)
        if ros_args is not None:
            self.cmdline(e, "ros_args", ros_args)
            a.ros_args = self.subst(e, "ros_args", ros_args)
        nn = self.opt_subst(e, "node-name")
        name = self.opt_subst(e, "name")
        a.name = name if name is not None else nn
        self.opt_subst(e, "exec_name")
        a.package = self.opt_subst(e, "pkg")
        a.executable = self.req_subst(e, "exec")
        a.namespace = self.opt_subst(e, "namespace")
        a.remaps = self.remaps(e)
        params = e.get_attr("param", data_type=LIST, optional=True)
        if params is not None:
            a.params = self.params(params)
        return a

    def remaps(self, e: Entity) -> list[RemapA]:
        rs = e.get_attr("remap", data_type=LIST, optional=True)
        if rs is None:
            return []
        out = [RemapA(self.req_subst(r, "from"), self.req_subst(r, "to"), r) for r in rs]
        for r in rs:
            r.assert_parsed()
        return out

    def params(self, params: list[Entity]) -> list:
        """Node.parse_nested_parameters."""
        out = []
        for p in params:
            frm = p.get_attr("from", optional=True)
            allow = p.get_attr("allow_substs", data_type=bool, optional=True)
            name = p.get_attr("name", optional=True)
            if frm is not None and name is not None:
                raise LoadError("RuntimeError", "name and from attributes are mutually exclusive", p.tag_span,
                                self.path)
            if frm is not None:
                if isinstance(allow, str):
                    allow = self.subst(p, "allow_substs", allow)
                else:
                    allow = bool(allow)
                p.assert_parsed()
                out.append(ParamFileA(self.subst(p, "from", frm), p, allow))
                continue
            if name is not None:
                if allow is not None:
                    raise LoadError("RuntimeError", "'allow_substs' can only be used together with 'from' attribute",
                                    p.aspan("allow_substs"), self.path)
                out.append(self.nested_params([p]))
                continue
            raise LoadError("ValueError", "param Entity should have name or from attribute", p.tag_span, self.path)
        return out

    def nested_params(self, params: list[Entity]) -> list[ParamA]:
        out = []
        for p in params:
            name = self.req_subst(p, "name")
            type_id = p.get_attr("type", data_type=None, optional=True)
            data_type = _data_type(type_id, p, self.path) if type_id is not None else None
            value = p.get_attr("value", data_type=data_type, optional=True)
            nested = p.get_attr("param", data_type=LIST, optional=True)
            p.assert_parsed()
            if value is not None and nested:
                raise LoadError("RuntimeError", "nested parameters and value attributes are mutually exclusive",
                                p.tag_span, self.path)
            if type_id is not None and nested:
                raise LoadError("RuntimeError", "nested parameters and type attributes are mutually exclusive",
                                p.tag_span, self.path)
            if value is not None:
                # parse_if_substitutions, then ParameterValue(value, value_type): a list mixes no
                # plain strings with other scalars; a value without substitutions must be of the
                # type given (what has substitutions is typed when the node runs: nodes.py)
                if isinstance(value, str):
                    value = self.subst(p, "value", value)
                elif isinstance(value, list):
                    value = [self.subst(p, "value", x) if isinstance(x, str) else x for x in value]
                    self.param_typed(p, lambda: C.uniform(value, _item_kind), "ValueError")
                self.param_typed(p, lambda: self._normalize(value, data_type), "TypeError")
                out.append(ParamA(name, p, value, type_id if isinstance(type_id, str) else None, dtype=data_type))
            elif nested:
                out.append(ParamA(name, p, None, None, self.nested_params(nested)))
            else:
                raise LoadError("RuntimeError", "either a value attribute or nested params are needed", p.tag_span,
                                self.path)
        return out

    def param_typed(self, p: Entity, check, kind: str) -> None:
        """Run a check of launch's typing of a ``<param>`` value; its error refuses the file."""
        try:
            check()
        except (ValueError, TypeError) as ex:
            raise LoadError(kind, str(ex), p.aspan("value"), self.path) from None

    @staticmethod
    def _normalize(value, data_type) -> None:
        """``normalize_typed_substitution`` of a parsed ``<param value>``."""
        if isinstance(value, Value):
            if S.is_text(value.parts):
                C.normalize_scalar(S.plain(value.parts), data_type)
            return
        if isinstance(value, list):
            if data_type is not None and not isinstance(data_type, C.ListOf):
                raise TypeError("The provided value resolves to a list, though the required type is a scalar. "
                                f"Got value='{value}', data_type='{C.type_text(data_type)}'.")
            return
        C.normalize_scalar(value, data_type)

    def composable(self, e: Entity) -> ComposableA:
        c = ComposableA(e)
        c.package = self.req_subst(e, "pkg")
        c.plugin = self.req_subst(e, "plugin")
        c.name = self.req_subst(e, "name")
        c.cond = self.condition(e)
        c.namespace = self.opt_subst(e, "namespace")
        params = e.get_attr("param", data_type=LIST, optional=True)
        if params is not None:
            c.params = self.params(params)
        c.remaps = self.remaps(e)
        extra = e.get_attr("extra_arg", data_type=LIST, optional=True)
        if extra is not None:
            for x in extra:
                self.req_subst(x, "name")
                self.req_subst(x, "value")
            for x in extra:
                x.assert_parsed()
        e.assert_parsed()
        return c

    def p_node_container(self, e: Entity) -> NodeA:
        a = self.p_node(e, "node_container")
        comps = e.get_attr("composable_node", data_type=LIST, optional=True)
        if comps is not None:
            a.composables = [self.composable(c) for c in comps]
        return a

    def p_load_composable_node(self, e: Entity) -> LoadComposableA:
        a = LoadComposableA("load_composable_node", e, self.condition(e))
        a.target = self.req_subst(e, "target")
        a.composables = [self.composable(c) for c in e.get_attr("composable_node", data_type=LIST)]
        return a

    def p_push_ros_namespace(self, e: Entity) -> PushNsA:
        cond = self.condition(e)
        return PushNsA(e.tag, e, cond, self.req_subst(e, "namespace"))

    def p_set_remap(self, e: Entity) -> SetRemapA:
        cond = self.condition(e)
        return SetRemapA("set_remap", e, cond, self.req_subst(e, "from"), self.req_subst(e, "to"))

    def p_set_parameter(self, e: Entity) -> SetParamA:
        cond = self.condition(e)
        return SetParamA("set_parameter", e, cond, self.req_subst(e, "name"), self.req_subst(e, "value"))

    def p_set_parameters_from_file(self, e: Entity) -> SetParamFileA:
        cond = self.condition(e)
        return SetParamFileA("set_parameters_from_file", e, cond, self.req_subst(e, "filename"))

    def p_set_env(self, e: Entity) -> EnvA:
        cond = self.condition(e)
        return EnvA("set_env", e, cond, self.req_subst(e, "name"), self.req_subst(e, "value"))

    def p_unset_env(self, e: Entity) -> EnvA:
        cond = self.condition(e)
        return EnvA("unset_env", e, cond, self.req_subst(e, "name"))

    def p_append_env(self, e: Entity) -> EnvA:
        cond = self.condition(e)
        a = EnvA("append_env", e, cond, self.req_subst(e, "name"), self.req_subst(e, "value"))
        prepend = e.get_attr("prepend", data_type=bool, optional=True)
        if isinstance(prepend, str):
            prepend = self.subst(e, "prepend", prepend)
        a.prepend = prepend
        a.separator = self.opt_subst(e, "separator")
        return a

    def p_reset_env(self, e: Entity) -> SimpleA:
        return SimpleA("reset_env", e, self.condition(e))

    def p_log(self, e: Entity) -> LogA:
        cond = self.condition(e)
        return LogA("log", e, cond, self.req_subst(e, "message"))

    def p_timer(self, e: Entity, tag: str = "timer") -> TimerA:
        cond = self.condition(e)
        period = e.get_attr("period", data_type=float)
        if isinstance(period, str):
            period = self.subst(e, "period", period)
            if S.is_text(period.parts):  # TimerAction(period='abc'): float('abc') in its constructor
                raise LoadError("ValueError", f"could not convert string to float: {S.plain(period.parts)!r}",
                                e.aspan("period"), self.path)
        t = TimerA(tag, e, cond, period)
        t.actions = self.actions(e.children())
        if tag == "timer":
            c = e.get_attr("cancel_on_shutdown", data_type=bool, optional=True)
            if isinstance(c, str):
                self.subst(e, "cancel_on_shutdown", c)
        return t

    def p_ros_timer(self, e: Entity) -> TimerA:
        return self.p_timer(e, "ros_timer")

    def p_shutdown(self, e: Entity) -> SimpleA:
        cond = self.condition(e)
        reason = e.get_attr("reason", optional=True)
        vals = [self.subst(e, "reason", reason)] if reason else []
        return SimpleA("shutdown", e, cond, vals)

    def p_set_use_sim_time(self, e: Entity) -> SimpleA:
        cond = self.condition(e)
        return SimpleA("set_use_sim_time", e, cond, [self.req_subst(e, "value")])

    def p_set_ros_log_dir(self, e: Entity) -> SimpleA:
        cond = self.condition(e)
        return SimpleA("set_ros_log_dir", e, cond, [self.req_subst(e, "new_log_dir")])


def _item_kind(x):
    """The type parse_if_substitutions records for a list item (None: it has substitutions)."""
    if isinstance(x, Value):
        return str if S.is_text(x.parts) else None
    return type(x)


def _data_type(type_id, p: Entity, path: str):
    """launch's get_data_type_from_identifier (``yaml``: no type, YAML rules)."""
    try:
        return C.data_type_of(type_id)
    except ValueError as ex:
        raise LoadError("ValueError", str(ex), p.aspan("type"), path) from None


def parse_description(root: Entity, path: str) -> tuple[list[Action], list[LoadError]]:
    """The actions of a launch file and every mistake that makes launch refuse it."""
    p = Parser(path)
    try:
        acts = p.description(root)
    except LoadError as ex:
        return [], [ex]
    return acts, p.errors
