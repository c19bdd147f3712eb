"""The small expression language extraction writes names in, and its evaluation.

A source file is read once into *facts* (cached by content): for each call site, the name
argument as an expression whose file-local parts (literals, local variables, string
concatenation) are already resolved, and whose other parts are references resolved later, over
every file of the executable (constants and ``#define`` s of headers, members set in a
constructor defined elsewhere, the arguments a constructor or function is called with).

Expressions are JSON-able lists:

- ``["s", text]`` a string; ``["cat", [e, ...]]`` a concatenation;
- ``["id", name, class, namespaces]`` an identifier the file does not define (a member of
  ``class``, a constant of a header, ``ns::NAME``);
- ``["mem", class, name]`` ``this->name`` / ``self.name``;
- ``["arg", class, function, index, name, type]`` a parameter of the enclosing function;
- ``["param", name-expr, default-expr, text]`` the value of a ROS parameter (dynamic);
- ``["ctor", type, [args]]`` a construction (``ros::NodeHandle(nh, "sub")``, ``std::string("x")``);
- ``["nh", namespace-expr]`` a ROS 1 node handle in that namespace;
- ``["node"]`` the node's own name (``ros::this_node::getName()``): ``"~"`` in a name;
- ``["resolved", expr, text]`` a name resolved by the node (``nh.resolveName(x)``): ``expr``
  alone, unknown inside a longer name (its namespace);
- ``["dyn", text]`` anything else (dynamic, with its source text).

:func:`evaluate` turns one into a :class:`Value` (a string, or a pattern with ``{expr}`` holes).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

MAX_DEPTH = 24


@dataclass
class Value:
    text: str                       # the string, with {expr} for each unknown part
    dynamic: bool = False
    exprs: list[str] = field(default_factory=list)
    default: Optional[str] = None   # the default of a parameter the value comes from
    node: bool = False              # starts with the node's own name (a private name)

    @staticmethod
    def dyn(text: str, default: Optional[str] = None) -> "Value":
        t = " ".join(text.split())
        if len(t) > 120:
            t = t[:119] + "…"
        return Value("{" + t + "}", True, [t], default)


def concat(vals: list[Value]) -> Value:
    if len(vals) == 1:
        return vals[0]
    text = "".join(v.text for v in vals)
    dyn = any(v.dynamic for v in vals)
    exprs = [e for v in vals for e in v.exprs]
    node = bool(vals) and vals[0].node
    return Value(text, dyn, exprs, None, node)


def canonical(name: str) -> str:
    """``a//b`` -> ``a/b``, ``~/x`` -> ``~x``, no trailing ``/`` (as ROS canonicalises a name)."""
    if not name:
        return name
    lead = "/" if name.startswith("/") else "~" if name.startswith("~") else ""
    body = name[len(lead):]
    parts = [p for p in body.split("/") if p]
    return lead + "/".join(parts) if (parts or lead) else name


def join_ns(ns: str, name: str) -> str:
    """A name asked of a ROS 1 node handle whose namespace is ``ns`` (``""``: the node's
    namespace, ``"~"``: its private one), as ``ros::NodeHandle::resolveName`` composes them."""
    if not name:
        return ns
    if name.startswith(("/", "~")) or not ns:
        return name
    if ns.startswith("~"):
        return canonical("~" + ns[1:].strip("/") + ("/" if ns[1:].strip("/") else "") + name)
    return canonical(ns.rstrip("/") + "/" + name)


def join_values(ns: Value, name: Value) -> Value:
    if not name.text:
        return ns
    if name.text.startswith(("/", "~")) or not ns.text:
        return name
    text = join_ns(ns.text, name.text)
    return Value(text, ns.dynamic or name.dynamic, ns.exprs + name.exprs, name.default)


def finish(v: Value) -> Value:
    """The name as ROS would canonicalise it."""
    if v.text.startswith(NODE):
        v = node_private(v)
    c = canonical(v.text)
    if c == v.text:
        return v
    return Value(c, v.dynamic, v.exprs, v.default, v.node)


NODE = "\0node\0"   # the node's own name, in a value being built


def node_private(v: Value) -> Value:
    """``getName() + "/x"``: a name under the node's own, i.e. ``~x``; ``getName() + "_x"`` is a
    name beside it, known only when the node is launched (dynamic)."""
    t = v.text
    if not t.startswith(NODE):
        return v
    rest = t[len(NODE):]
    if rest.startswith("/") or rest == "":
        return Value("~" + rest.lstrip("/"), v.dynamic, v.exprs, v.default)
    return Value("{node name}" + rest, True, ["node name"] + v.exprs, v.default)


class Resolver:
    """Evaluates expressions against the facts of one executable; ``lookup_*`` are given by the
    language's linker."""

    def __init__(self, const: Callable[[str, Optional[str], list], Optional[list]],
                 member: Callable[[str, str], Optional[list]],
                 arg: Callable[[Optional[str], str, int], Optional[list]],
                 member_type: Callable[[str, str], Optional[str]] = lambda c, n: None):
        self.const = const
        self.member = member
        self.arg = arg
        self.member_type = member_type
        self.active: set = set()
        # each reference is evaluated once per program: a member set in many places from
        # other members would otherwise be followed along every path (exponential)
        self.memo: dict = {}

    def evaluate(self, e, depth: int = 0) -> Value:
        if not isinstance(e, list) or not e:
            return Value.dyn("?")
        if depth > MAX_DEPTH:
            return Value.dyn(text_of(e))
        k = e[0]
        if k == "s":
            return Value(e[1])
        if k == "cat":
            v = concat([Value.dyn(x[2]) if x and x[0] == "resolved" else self.evaluate(x, depth + 1) for x in e[1]])
            return node_private(v) if v.node else v
        if k == "resolved":
            return self.evaluate(e[1], depth + 1)
        if k == "opts":
            return Value.dyn(e[3])
        if k == "node":
            return Value(NODE, node=True)
        if k == "param":
            d = e[2]
            default = None
            if d is not None:
                dv = self.evaluate(d, depth + 1)
                default = None if dv.dynamic else dv.text
            text = e[3]
            if "(" in text:  # used where it is read: named after the parameter
                nv = self.evaluate(e[1], depth + 1)
                if not nv.dynamic and nv.text:
                    text = nv.text.lstrip("~/")
            return Value.dyn(text, default)
        if k == "ctor":
            args = e[2]
            if args:
                return self.evaluate(args[0], depth + 1)
            return Value("")
        if k == "nh":
            return self.evaluate(e[1], depth + 1)
        if k == "lit":
            return Value.dyn(e[2])
        key = (k, repr(e[1:]))
        if key in self.memo:
            return self.memo[key]
        if key in self.active:
            return Value.dyn(text_of(e))
        self.active.add(key)
        try:
            got = self._lookup(e)
            if got is None:
                v = Value.dyn(text_of(e))
            else:
                v = agree([self.evaluate(x, depth + 1) for x in got], text_of(e))
        finally:
            self.active.discard(key)
        self.memo[key] = v
        return v

    def _lookup(self, e) -> Optional[list]:
        k = e[0]
        if k == "id":
            name, cls, nss = e[1], e[2], e[3] if len(e) > 3 else []
            if cls and "::" not in name and "." not in name:
                m = self.member(cls, name)
                if m:
                    return m
            return self.const(name, cls, nss or [])
        if k == "mem":
            return self.member(e[1], e[2]) if e[1] else None
        if k == "arg":
            if len(e) > 6:
                return self.arg(e[1], e[2], e[3], e[4], e[6])
            return self.arg(e[1], e[2], e[3], e[4] if len(e) > 4 else "")
        return None


def agree(vals: list[Value], text: str) -> Value:
    """One value when every way the expression can be set gives the same one, else dynamic."""
    if not vals:
        return Value.dyn(text)
    first = vals[0]
    if all(v.text == first.text and v.dynamic == first.dynamic for v in vals[1:]):
        return first
    defaults = {v.default for v in vals}
    return Value.dyn(text, defaults.pop() if len(defaults) == 1 else None)


def text_of(e) -> str:
    """A readable text for an expression (the source text where it was kept)."""
    if not isinstance(e, list) or not e:
        return "?"
    k = e[0]
    if k == "s":
        return '"' + e[1] + '"'
    if k == "cat":
        return " + ".join(text_of(x) for x in e[1])
    if k == "id":
        return e[1]
    if k == "mem":
        return e[2]
    if k == "arg":
        return e[4]
    if k in ("param", "dyn"):
        return e[-1] if k == "dyn" else e[3]
    if k == "ctor":
        return f"{e[1] or ''}({', '.join(text_of(x) for x in e[2])})"
    if k == "nh":
        return text_of(e[1])
    if k == "node":
        return "node name"
    if k == "lit":
        return e[2]
    if k == "resolved":
        return e[2]
    return "?"
