"""The launch API in the interpreter: constructing launch objects as ros2/launch's constructors
bind their arguments (positional order, accepted keywords: :mod:`.apitable`), and the few
methods and attributes launch files use on them (``LaunchDescription.add_action``,
``LaunchConfiguration(...).perform(context)``, ...).

A launch object is an :class:`~.values.LObj`: its class name and its arguments by parameter
name.  What it means (an action, a substitution, a condition) is decided when it is turned
into the ROS 2 walker's actions (:mod:`.convert`).
"""

from __future__ import annotations


import os

from . import apitable
from .values import LaunchCtx, LClass, LObj, ModuleNS, PyError, Unknown, marked, type_name

# classes whose instances are substitutions (perform()-able)
SUBSTITUTIONS = {
    "LaunchConfiguration", "TextSubstitution", "PathJoinSubstitution", "PythonExpression", "EnvironmentVariable",
    "FindPackageShare", "FindPackagePrefix", "FindPackage", "FindExecutable", "ExecutableInPackage", "Command",
    "ThisLaunchFileDir", "ThisLaunchFile", "AnonName", "LaunchLogDir", "EqualsSubstitution",
    "NotEqualsSubstitution", "NotSubstitution", "AndSubstitution", "OrSubstitution", "AnySubstitution",
    "AllSubstitution", "IfElseSubstitution", "FileContent", "Parameter", "LocalSubstitution",
    "BooleanSubstitution", "Substitution", "SubstitutionFailure",
}
CONDITIONS = {"IfCondition", "UnlessCondition", "LaunchConfigurationEquals", "LaunchConfigurationNotEquals",
              "Condition"}
SOURCES = {"PythonLaunchDescriptionSource", "XMLLaunchDescriptionSource", "YAMLLaunchDescriptionSource",
           "AnyLaunchDescriptionSource", "FrontendLaunchDescriptionSource", "LaunchDescriptionSource"}


def _params(qual: str) -> dict:
    return apitable.CLASSES.get(qual) or {"pos": [], "req": [], "kw": []}


def construct(interp, cls: LClass, args: list, kwargs: dict, m: ModuleNS, n):
    """``Class(*args, **kwargs)``, bound like the constructor binds it."""
    spec = _params(cls.qual)
    pos = spec["pos"]
    bound: dict = {}
    arg_where: dict = {}
    call_args = list(getattr(n, "args", []) or [])
    call_kws = {k.arg: k for k in getattr(n, "keywords", []) or [] if k.arg is not None}
    star = cls.name in ("AnySubstitution", "AllSubstitution")
    if star:
        bound["args"] = list(args)
    else:
        if len(args) > len(pos):
            raise PyError("TypeError", f"{cls.name}.__init__() takes {len(pos) + 1} positional arguments but "
                          f"{len(args) + 1} were given", m.where(n), sure=True)
        for i, (name, v) in enumerate(zip(pos, args)):
            bound[name] = v
            if i < len(call_args) and m.path == interp.host.unit_path:
                arg_where[name] = (m.where(call_args[i]), None)
    missing = [r for r in spec["req"] if r not in bound and r not in kwargs]
    if cls.name in ("Node", "ComposableNodeContainer", "LifecycleNode") and "executable" not in kwargs:
        missing.append("executable")
    if missing:   # (the constructors take **kwargs: a missing argument is what Python reports first)
        kind = "keyword-only " if missing[0] not in pos else "positional "
        raise PyError("TypeError", f"{cls.name}.__init__() missing 1 required {kind}argument: '{missing[0]}'",
                      m.where(n), sure=True)
    allowed = set(spec["kw"]) | set(pos)
    for k, v in kwargs.items():
        if k not in allowed:
            raise PyError("TypeError", f"{cls.name}.__init__() got an unexpected keyword argument '{k}' "
                          f"({_version(cls.qual)} has no such argument)",
                          m.where(call_kws[k]) if k in call_kws else m.where(n), sure=True)
        if k in bound:
            raise PyError("TypeError", f"{cls.name}.__init__() got multiple values for argument '{k}'",
                          m.where(n), sure=True)
        bound[k] = v
        kn = call_kws.get(k)
        if kn is not None and m.path == interp.host.unit_path:
            arg_where[k] = (m.where(kn.value), m.where(kn))
    o = LObj(cls.name, cls.qual, bound, interp.anchor(m, n))
    o.extra["arg_where"] = arg_where
    o.extra["module"] = m
    check(interp, o, m, n)
    return o


def _str_item(x):
    """str() of a plain value, as a constructor normalizes it (an unknown or a launch object stays)."""
    if isinstance(x, (Unknown, LObj)) or isinstance(x, str):
        return x
    if isinstance(x, (bool, int, float)) or x is None:
        return str(x)
    from .values import PathObj
    if isinstance(x, PathObj):   # not Iterable: str(path)
        return x.path
    return x


def normalize(o: LObj) -> None:
    """The constructors that turn plain values into text themselves."""
    if o.cls == "LaunchConfiguration":
        d = o.args.get("default")
        if d is not None and not isinstance(d, (str, LObj, Unknown)):
            items = list(d) if isinstance(d, (list, tuple)) else [d]
            o.args["default"] = [_str_item(x) for x in items]
    elif o.cls in ("EqualsSubstitution", "NotEqualsSubstitution"):
        for k in ("left", "right"):
            v = o.args.get(k)
            if v is None:
                o.args[k] = ""
            elif isinstance(v, bool):
                o.args[k] = str(v).lower()
            elif isinstance(v, (int, float)):
                o.args[k] = str(v)


def _version(qual: str) -> str:
    return "launch_ros 0.28" if qual.startswith("launch_ros") else "launch 3.7.1"


def check(interp, o: LObj, m: ModuleNS, n) -> None:
    """What the constructors check themselves (the file fails to load at once)."""
    normalize(o)
    if o.cls in ("Node", "LifecycleNode", "ComposableNodeContainer", "ComposableNode"):
        _check_params(o.get("parameters"), m, n)
    if o.cls == "DeclareLaunchArgument":
        choices = o.get("choices")
        d = o.get("default_value")
        if isinstance(choices, list) and not choices:
            raise PyError("RuntimeError", "Provided choices arg is empty. Use None to ignore the choice list.",
                          m.where(n), sure=True)
        if isinstance(choices, (list, tuple)) and isinstance(d, str) and all(isinstance(c, str) for c in choices):
            if d not in choices:
                raise PyError("RuntimeError", f'Provided default_value "{d}" is not in provided choices '
                              f'"{list(choices)}".', m.where(n), sure=True)


def _check_params(params, m: ModuleNS, n) -> None:
    """launch_ros' normalize_parameters, which the node's constructor runs: what it refuses."""
    from .values import PathObj

    def bad(msg):
        raise PyError("TypeError", msg, m.where(n), sure=True)

    def value(v, depth=0):
        if depth > 20 or isinstance(v, Unknown):
            return
        if isinstance(v, dict):
            for k, x in v.items():
                value(x, depth + 1)
        elif isinstance(v, LObj):
            if v.cls not in SUBSTITUTIONS and v.cls != "ParameterValue":
                bad(f"Unexpected type for parameter value {v.cls}")
        elif isinstance(v, (str, bool, int, float, bytes)):
            return
        elif isinstance(v, (list, tuple)):
            for x in v:
                if isinstance(x, Unknown):
                    continue
                if not isinstance(x, (str, bool, int, float, LObj, list, tuple)) or \
                        isinstance(x, LObj) and x.cls not in SUBSTITUTIONS:
                    bad(f"Expected 'subvalue' to be one of [<class 'float'>, <class 'int'>, <class 'str'>, "
                        f"<class 'bool'>, ...], but got '{x!r}' of type '{type_name(x)}'")
        elif v is None or isinstance(v, PathObj):
            bad(f"Unexpected type for parameter value {'None' if v is None else repr(v)}")
    if params is None or isinstance(params, Unknown):
        return
    if isinstance(params, str) or not isinstance(params, (list, tuple)):
        bad(f"Expecting list of parameters, got {params!r}" if isinstance(params, (str, int, float, bool))
            else f"Expecting list of parameters, got {type_name(params)}")
    for p in params:
        if isinstance(p, dict):
            value(p)
        elif p is None:
            bad("Expected 'param_file' to be one of [<class 'str'>, ...], but got 'None' of type '<class 'NoneType'>'")


def is_substitution(v) -> bool:
    return isinstance(v, LObj) and v.cls in SUBSTITUTIONS


def attribute(interp, o: LObj, name: str, m: ModuleNS, n):
    if o.cls == "LaunchDescription" and name in ("add_action", "add_entity", "entities", "describe_sub_entities"):
        if name == "entities":
            return list(o.args.setdefault("initial_entities", []) or [])
        from .values import BoundMethod
        return BoundMethod(o, name, m.where(n))
    if name in ("evaluate", "_predicate_func") and o.cls in CONDITIONS:
        from .values import BoundMethod
        return BoundMethod(o, "evaluate", m.where(n))
    if name == "find" and o.cls in ("FindPackageShare", "FindPackagePrefix", "FindPackage"):
        from .values import BoundMethod
        return BoundMethod(o, name, m.where(n))
    if name == "perform" and o.cls in SUBSTITUTIONS:
        from .values import BoundMethod
        return BoundMethod(o, name, m.where(n))
    if name in o.extra and name not in ("arg_where", "module"):
        return o.extra[name]
    if o.cls == "DeclareLaunchArgument" and name in ("name", "default_value", "description", "choices"):
        v = o.get(name)
        if name == "description" and v is None:
            return "no description given"
        return v
    if o.cls == "LaunchConfiguration" and name == "variable_name":
        return o.get("variable_name")
    if name in ("condition",):
        return o.get("condition")
    if name in ("node_name", "name") and o.cls in ("Node", "LifecycleNode", "ComposableNodeContainer"):
        return Unknown(f"{o.cls}.{name} (known once launched)", m.where(n))
    return Unknown(f"{o.cls}.{name} is not modelled", m.where(n))


def call_method(interp, o: LObj, name: str, args: list, kwargs: dict, m: ModuleNS, n):
    if o.cls == "LaunchDescription":
        ents = o.args.get("initial_entities")
        if ents is None:
            ents = o.args["initial_entities"] = []
        if not isinstance(ents, list):
            ents = o.args["initial_entities"] = list(interp.iterate(ents, m, n))
        if name in ("add_action", "add_entity"):
            if not args:
                raise PyError("TypeError", f"{name}() missing 1 required positional argument", m.where(n))
            ents.append(args[0])
            return None
        if name == "describe_sub_entities":
            return list(ents)
    if name == "perform":
        ctx = args[0] if args else kwargs.get("context")
        return interp.host.perform(ctx, o, m, n)
    if name == "evaluate" and o.cls in CONDITIONS:   # condition.evaluate(context) in an OpaqueFunction
        return evaluate_condition(interp, o, args[0] if args else kwargs.get("context"), m, n)
    if name == "find":   # FindPackageShare(...).find(package_name): the folder, at once
        from .library import package_share
        return package_share(interp, args, kwargs, m, n, prefix=o.cls != "FindPackageShare")
    return Unknown(f"{o.cls}.{name}() is not modelled", m.where(n))


def perform_fresh(host, v, m: ModuleNS, n, depth: int = 0):
    """``sub.perform(LaunchContext())`` with a context the file made itself (outside any launch):
    it has no launch configurations and the process's environment.  What needs more (a
    command, an expression, a configuration without default...) is unknown or launch's error."""
    from .values import PathObj
    if depth > 32:
        return Unknown("a substitution nested too deep", m.where(n))
    if isinstance(v, Unknown):
        return v
    if isinstance(v, str):
        return str(v)
    if isinstance(v, (list, tuple)):
        out = []
        for x in v:
            r = perform_fresh(host, x, m, n, depth + 1)
            if isinstance(r, Unknown):
                return r
            out.append(r)
        return "".join(out)
    if isinstance(v, PathObj):
        return v.path
    if not isinstance(v, LObj):
        return Unknown(f"performing a {type_name(v)}", m.where(n))

    def sub(name):
        return perform_fresh(host, v.get(name), m, n, depth + 1)
    if v.cls == "TextSubstitution":
        return sub("text")
    if v.cls == "LaunchConfiguration":
        name = sub("variable_name")
        if isinstance(name, Unknown):
            return name
        d = v.get("default")
        if d is None:   # a new context holds no launch configuration
            raise PyError("SubstitutionFailure", f"launch configuration '{name}' does not exist", m.where(n),
                          sure=True)
        if isinstance(d, (bool, int, float)):
            return str(d)
        return perform_fresh(host, d, m, n, depth + 1)
    if v.cls == "EnvironmentVariable":
        name = sub("name")
        if isinstance(name, Unknown):
            return name
        d = v.get("default_value")
        if d is not None:
            d = perform_fresh(host, d, m, n, depth + 1)
        val = host.env.get(name)
        if val is not None:
            return val
        if not host.concrete:
            return Unknown(f"the environment variable {name} (not set here; it may be when launching)", m.where(n))
        if isinstance(d, Unknown):
            return d
        if d is None:
            raise PyError("SubstitutionFailure", f"environment variable '{name}' does not exist", m.where(n),
                          sure=True)
        return d
    if v.cls in ("FindPackageShare", "FindPackagePrefix"):
        pkg = sub("package")
        if isinstance(pkg, Unknown):
            return pkg
        r = host.package_dir(pkg, share=v.cls == "FindPackageShare", where=m.where(n))
        if isinstance(r, str) and not isinstance(r, Unknown) and marked(r):
            return Unknown(f"the folder of the package {pkg} (not found here)", m.where(n))
        return r
    if v.cls == "PathJoinSubstitution":
        parts = v.get("substitutions")
        if not isinstance(parts, (list, tuple)):
            return Unknown("a PathJoinSubstitution of a non-list", m.where(n))
        out = []
        for x in parts:
            r = perform_fresh(host, x, m, n, depth + 1)
            if isinstance(r, Unknown):
                return r
            out.append(r)
        return os.path.join(*out) if out else ""
    return Unknown(f"{v.cls}.perform() with a LaunchContext the file made", m.where(n))


def evaluate_condition(interp, o: LObj, ctx, m: ModuleNS, n):
    """A condition's value with the launch context (IfCondition: launch's
    evaluate_condition_expression of the performed text)."""
    if o.cls in ("IfCondition", "UnlessCondition"):
        v = interp.host.perform(ctx, o.get("predicate_expression"), m, n)
        if isinstance(v, Unknown):
            return v
        lv = str(v).strip().lower()
        if lv not in ("true", "1", "false", "0"):
            raise PyError("InvalidConditionExpressionError", "invalid condition expression, expected one of "
                          f"[true, 1, false, 0] but got '{lv}'", m.where(n), sure=True)
        r = lv in ("true", "1")
        return r if o.cls == "IfCondition" else not r
    if o.cls in ("LaunchConfigurationEquals", "LaunchConfigurationNotEquals"):
        cur = interp.host.launch_configuration(o.get("launch_configuration_name"), None, m, n)
        exp = o.get("expected_value")
        if exp is not None and not isinstance(exp, str):
            exp = interp.host.perform(ctx, exp, m, n)
        if isinstance(cur, Unknown) or isinstance(exp, Unknown):
            return cur if isinstance(cur, Unknown) else exp
        r = (cur == exp) if cur is not None else exp is None
        return r if o.cls == "LaunchConfigurationEquals" else not r
    return Unknown(f"the condition {o.cls}", m.where(n))


def subscript(interp, o: LObj, key, m: ModuleNS, n):
    return Unknown(f"an item of a {o.cls}", m.where(n))


def iterate(interp, o: LObj, m: ModuleNS, n):
    if o.cls == "LaunchDescription":
        return list(o.args.get("initial_entities") or [])
    raise PyError("TypeError", f"'{o.cls}' object is not iterable", m.where(n))


def binop(interp, op, a, b, m: ModuleNS, n):
    """Substitutions have no operators: Python raises TypeError (the file does not load)."""
    import ast
    sym = {ast.Add: "+", ast.Div: "/", ast.Mod: "%", ast.Mult: "*", ast.Sub: "-"}.get(type(op), "?")
    raise PyError("TypeError", f"unsupported operand type(s) for {sym}: '{type_name(a)}' and '{type_name(b)}'",
                  m.where(n), sure=True)


def make_context() -> LaunchCtx:
    return LaunchCtx()


__all__ = ["construct", "attribute", "call_method", "subscript", "iterate", "binop", "is_substitution",
           "evaluate_condition", "perform_fresh", "SUBSTITUTIONS", "CONDITIONS", "SOURCES"]
