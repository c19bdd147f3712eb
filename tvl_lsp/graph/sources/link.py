"""Putting the facts of one program's files together: names resolved across files (constants of
headers, members set in constructors defined elsewhere, the arguments a class is constructed
with), node handle namespaces composed, types normalised (template arguments, callback
signatures found in any file, aliases), and endpoints made (:func:`link_cpp`, :func:`link_py`).
"""

from __future__ import annotations

import re
from typing import Callable, Iterable, Optional

from . import apis
from .model import Endpoint
from .types import CppScope, python_type, split_template
from .values import Resolver, Value, agree, finish, join_values, text_of

MAX_ENDPOINTS = 20000


class _CppIndex:
    def __init__(self, files: list[tuple[str, dict]]):
        self.consts: dict[str, list] = {}
        self.members: dict[str, dict[str, list]] = {}
        self.mtypes: dict[str, dict[str, str]] = {}
        self.funcs: dict[str, list] = {}
        self.aliases: dict[str, str] = {}
        self.using_ns: list[str] = []
        self.ctors: dict[str, list] = {}
        self.fcalls: dict[str, list] = {}
        self.nh_memo: dict[str, Value] = {}
        self.pdefaults: dict[str, dict] = {}
        for _, f in files:
            for k, v in f.get("consts", {}).items():
                lst = self.consts.setdefault(k, [])
                if v not in lst:
                    lst.append(v)
            for k, v in f.get("gsets", []):
                lst = self.consts.setdefault(k, [])
                if v not in lst:
                    lst.append(v)
            for c, mem in f.get("members", {}).items():
                d = self.members.setdefault(c, {})
                for m, irs in mem.items():
                    d.setdefault(m, []).extend(irs)
            for c, mem in f.get("mtypes", {}).items():
                self.mtypes.setdefault(c, {}).update(mem)
            for k, d in f.get("pdefaults", {}).items():
                self.pdefaults.setdefault(k, {}).update(d)
            for k, sigs in f.get("funcs", {}).items():
                self.funcs.setdefault(k, []).extend(sigs)
            for k, v in f.get("aliases", {}).items():
                self.aliases.setdefault(k, v)
            for k, v in f.get("using_decls", {}).items():
                self.aliases.setdefault(k, v)
            for u in f.get("using_ns", []):
                if u not in self.using_ns:
                    self.using_ns.append(u)
            for c in f.get("ctors", []) + f.get("binits", []):
                self.ctors.setdefault(_base_name(c["t"]), []).append(c)
            for c in f.get("fcalls", []):
                self.fcalls.setdefault(c["f"], []).append(c)
        for _, f in files:   # a member constructed in an initializer list: ``sub_(nh, "x")``
            for c in f.get("minits", []):
                mt = self.member_type(c["cls"], c["m"])
                if mt and not re.search(r"[&*]|ptr\b|Ptr\b|ptr<", mt):   # (a reference or pointer: no construction)
                    b = _base_name(mt)
                    if b != c["m"]:
                        self.ctors.setdefault(b, []).append(c)

    def alias_lookup(self, cls: Optional[str], ns: list[str]) -> Callable[[str], Optional[str]]:
        def look(head: str) -> Optional[str]:
            keys = []
            if cls:
                keys.append("::".join(ns + [cls, head]))
                keys.append(f"{cls}::{head}")
            for i in range(len(ns), 0, -1):
                keys.append("::".join(ns[:i] + [head]))
            keys.append(head)
            for k in keys:
                v = self.aliases.get(k)
                if v is not None:
                    return v
            return None
        return look

    def member_type(self, cls: Optional[str], name: str) -> Optional[str]:
        if not cls:
            return None
        return self.mtypes.get(cls, {}).get(name)


def _resolver_cpp(ix: _CppIndex) -> Resolver:
    def const(name: str, cls: Optional[str], nss: list) -> Optional[list]:
        name = name.lstrip(":")
        keys = [name]
        if cls:
            keys.insert(0, f"{cls}::{name}")
        for i in range(len(nss), 0, -1):
            keys.append("::".join(list(nss[:i]) + [name]))
        parts = name.split("::")
        if len(parts) > 2:
            keys.append("::".join(parts[-2:]))
        for k in keys:
            v = ix.consts.get(k)
            if v:
                return v
        return None

    def member(cls: str, name: str) -> Optional[list]:
        return _reachable(ix, ix.members.get(cls, {}).get(name))

    def arg(cls: Optional[str], fn: str, idx: int, name: str = "", default=None) -> Optional[list]:
        if default is None:     # declared in a header: Robot(const std::string& topic = "robot_state");
            default = ix.pdefaults.get(f"{cls}::{fn}" if cls else fn, {}).get(f"{idx}:{name}")
        out = []
        for c in _calls(ix, cls, fn, idx, name):
            if idx < len(c):
                out.append(c[idx])
            elif default is not None:
                out.append(default)
        return out or None

    return Resolver(const, member, arg, ix.member_type)


def _base_name(t: str) -> str:
    return split_template(t or "")[0].replace(" ", "").rstrip("*&").split("::")[-1]


def _overload(ix: _CppIndex, cls: Optional[str], fn: str, idx: int, name: str) -> Optional[list]:
    """The signature ([[type, name], ...]) of the overload of ``cls::fn`` whose parameter ``idx``
    is called ``name`` (None when the program does not show it)."""
    sigs = ix.funcs.get(f"{cls}::{fn}" if cls else fn, [])
    for sig in sigs:
        if idx < len(sig) and sig[idx][1] == name:
            return sig
    return None


def _calls(ix: _CppIndex, cls: Optional[str], fn: str, idx: int, name: str = "") -> list[list]:
    """The argument lists the program calls function ``fn`` (a method of ``cls``, its
    constructor when ``fn == cls``) with, leaving out the calls that are surely of another
    function of that name: a method of another class (by the receiver's type, the qualifier, or
    the calling class's own method), or another overload (a node handle passed where the
    parameter is none, or the other way round; more arguments than the parameters)."""
    ctor = bool(cls) and fn == cls
    recs = ix.ctors.get(fn, []) if ctor else ix.fcalls.get(fn, [])
    sig = _overload(ix, cls, fn, idx, name) if name else None
    out = []
    for c in recs:
        args = c["args"]
        if sig is not None:
            if len(args) > len(sig):
                continue
            dflt = ix.pdefaults.get(f"{cls}::{fn}" if cls else fn, {})
            if any(f"{j}:{sig[j][1]}" not in dflt for j in range(len(args), len(sig))):
                continue    # too few arguments for this overload
            nk = c.get("nk") or []
            if any(k is not None and j < len(sig) and _param_is_node(sig[j][0]) is not None
                   and k != _param_is_node(sig[j][0]) for j, k in enumerate(nk)):
                continue
        if cls and not ctor and not _same_class(ix, c, cls, fn):
            continue
        out.append(args)
    return out


def _param_is_node(t: str) -> Optional[bool]:
    t = (t or "").replace("const", "").replace("&", "").replace("*", "").strip()
    if not t or "auto" in t or re.fullmatch(r"[A-Z]\w{0,2}|\w*T", t):
        return None     # a template parameter: anything
    return bool(re.search(r"NodeHandle|rclcpp::Node\b|LifecycleNode|\bNode\b|node_interfaces|ImageTransport", t))


def _same_class(ix: _CppIndex, c: dict, cls: str, fn: str) -> bool:
    """Whether a call record may call method ``fn`` of class ``cls``."""
    q = c.get("q")
    if q:
        last = q.split("::")[-1].split("<")[0]
        return last == cls or f"{last}::{fn}" not in ix.funcs
    if c.get("r"):
        rt = c.get("rt")
        if not rt and c.get("rm"):
            rt = ix.member_type(c["rm"][0], c["rm"][1])
        if not rt:
            return True
        words = set(re.findall(r"\w+", rt))
        return cls in words or not any(f"{w}::{fn}" in ix.funcs for w in words)
    own = c.get("c")
    return not own or own == cls or f"{own}::{fn}" not in ix.funcs


def _reachable(ix: _CppIndex, irs: Optional[list]) -> Optional[list]:
    """The ways a member is set, without those made in a constructor the program never calls
    (``SlamGMapping(nh, pnh) : private_nh_(pnh)`` where it only constructs ``SlamGMapping()``);
    all of them when none would be left."""
    if not irs or len(irs) < 2:
        return irs
    keep = [x for x in irs if not _from_uncalled_ctor(ix, x)]
    return keep or irs


def _from_uncalled_ctor(ix: _CppIndex, x) -> bool:
    if not (isinstance(x, list) and x and x[0] == "ctor" and x[1] is None):
        return False
    for a in x[2]:
        if isinstance(a, list) and a and a[0] == "nhref":
            a = a[1]
        if isinstance(a, list) and len(a) > 5 and a[0] == "arg" and a[1] and a[1] == a[2]:
            if not _calls(ix, a[1], a[2], a[3], a[4]):
                return True
    return False


def _nh_namespace(r: Resolver, ix: _CppIndex, e, depth: int = 0) -> Value:
    """The namespace of the ROS 1 node handle an expression designates ("" for the node's).
    Each expression is worked out once per program (members set in many places that refer to
    each other would otherwise be followed along every path: exponential), and an expression
    met again while it is being worked out (a handle made from itself) is dynamic."""
    if depth > 12 or not isinstance(e, list) or not e:
        return Value("")
    key = repr(e)
    got = ix.nh_memo.get(key)
    if got is not None:
        return got if got is not _BUSY else Value.dyn(text_of(e))
    ix.nh_memo[key] = _BUSY
    v = _nh_namespace_of(r, ix, e, depth)
    ix.nh_memo[key] = v
    return v


_BUSY = Value("\0busy")


def _nh_namespace_of(r: Resolver, ix: _CppIndex, e, depth: int) -> Value:
    k = e[0]
    if k == "nh":
        return r.evaluate(e[1])
    if k == "nhref":
        return _nh_namespace(r, ix, e[1], depth + 1)
    if k == "ctor":
        args = e[2]
        if not args:
            return Value("")
        first = args[0]
        if first and first[0] == "nhref" or _is_nh_expr(ix, first):
            parent = _nh_namespace(r, ix, first, depth + 1)
            if len(args) > 1 and args[1] and args[1][0] in ("s", "cat", "id", "arg", "mem", "param", "node"):
                child = r.evaluate(args[1])
                return join_values(parent, child) if not child.text.startswith("/") else child
            return parent
        v = r.evaluate(first)
        return v
    if k in ("id", "mem"):
        cls, name = (e[2], e[1]) if k == "id" else (e[1], e[2])
        irs = _reachable(ix, ix.members.get(cls, {}).get(name)) if cls else None
        if irs:
            vals = [_nh_namespace(r, ix, x, depth + 1) for x in irs]
            return agree(vals, name)
        if cls and name in ix.mtypes.get(cls, {}):
            return Value("")  # a member node handle never set: the default one
        got = r.const(name, cls, e[3] if k == "id" and len(e) > 3 else [])
        if got:
            return agree([_nh_namespace(r, ix, x, depth + 1) for x in got], name)
        return Value("")
    if k == "arg":
        cls, fn, idx = e[1], e[2], e[3]
        calls = _calls(ix, cls, fn, idx, e[4] if len(e) > 4 else "")
        vals = [_nh_namespace(r, ix, c[idx], depth + 1) for c in calls if idx < len(c)]
        if not vals:
            return Value("")  # called from elsewhere (a plugin's initialize, another program): the node's
        return agree(vals, e[4])
    if k == "dyn":
        t = e[1]
        if re.search(r"getPrivateNodeHandle|getMTPrivateNodeHandle", t):
            return Value("~")
        if re.search(r"getNodeHandle|getMTNodeHandle", t) or t in ("this",):
            return Value("")
        if re.match(r"^[\w:]*NodeHandle\(\)$", t.replace(" ", "")):
            return Value("")
        return Value.dyn(t)
    return r.evaluate(e)


def _is_nh_expr(ix: _CppIndex, e) -> bool:
    if not isinstance(e, list) or not e:
        return False
    if e[0] in ("nh", "nhref"):
        return True
    if e[0] == "ctor" and e[1] and "NodeHandle" in e[1]:
        return True
    if e[0] == "arg":
        return "NodeHandle" in (e[5] or "")
    if e[0] in ("id", "mem"):
        cls, name = (e[2], e[1]) if e[0] == "id" else (e[1], e[2])
        t = ix.member_type(cls, name) or ""
        return "NodeHandle" in t
    return False


def _first_param(ix: _CppIndex, desc, ctx: str) -> tuple[Optional[str], Optional[str], list]:
    """(type text of a callback's message parameter, class, namespaces) from a callback descriptor."""
    if not desc:
        return None, None, []
    k = desc[0]
    if k == "lt":
        return desc[1], desc[3] if len(desc) > 3 else None, desc[2]
    index = 0
    if k == "bind":
        index = desc[2]
        desc = desc[1]
        if not desc or desc[0] != "fn":
            return (desc[1], None, desc[2]) if desc and desc[0] == "lt" else (None, None, [])
    if desc[0] != "fn":
        return None, None, []
    name, cls, ns = desc[1], desc[2], desc[3]
    parts = name.split("::")
    keys = []
    if len(parts) >= 2:
        keys.append("::".join(parts[-2:]))
        owner = parts[-2]
    else:
        owner = cls
        if cls:
            keys.append(f"{cls}::{name}")
        keys.append(name)
    for key in keys:
        for sig in ix.funcs.get(key, []):
            if not sig:
                continue
            if ctx == "srv":
                for t, _ in sig:
                    if "Request" in t or "ServiceEvent" in t or "request" in _:
                        return t, owner, ns
                if len(sig) >= 2 and index == 0:
                    return sig[-2][0], owner, ns
            if index < len(sig):
                return sig[index][0], owner, ns
    return None, None, []


def _param_type_cpp(ix: _CppIndex, call: dict, scope_cls: Optional[str]) -> Optional[str]:
    t = _param_type_cpp1(ix, call, scope_cls)
    d = call.get("dtype")
    if t is None and d and not d.startswith("@"):
        return d        # param("x", settings.x, 1.0): the default's type where the variable's is unknown
    return t


def _param_type_cpp1(ix: _CppIndex, call: dict, scope_cls: Optional[str]) -> Optional[str]:
    from .cpp_helpers import _ptype
    targs = call.get("targs")
    if targs:
        return _ptype(targs[0])
    v = call.get("vtype")
    if v and v.startswith("@") and "." in v:
        # a struct's field: @var.field (var a member of the class), @:Type.field (a local's type)
        var, _, fld = v[1:].rpartition(".")
        st = var[1:] if var.startswith(":") else ix.member_type(scope_cls, var)
        if not st:
            return None
        base = _base_name(st)
        fields = ix.mtypes.get(base) or ix.mtypes.get(f"{scope_cls}.{var}") or {}
        if not fields and ix.aliases.get(base):
            fields = ix.mtypes.get(_base_name(ix.aliases[base]), {})
        return _ptype(fields.get(fld))
    if v and v.startswith("@"):
        t = _ptype(ix.member_type(scope_cls, v[1:]))
        if t is None:
            for c in ix.consts.get(v[1:], []):
                if c and c[0] == "lit":
                    return c[1]
                if c and c[0] in ("s", "cat"):
                    return "string"     # a string constant (static const char X[] = "...")
        return t
    return v


def link_cpp(package: str, executable: str, ros: int, files: list[tuple[str, dict]],
             known: dict, only_class: Optional[str] = None, skip_classes: frozenset = frozenset()
             ) -> list[Endpoint]:
    """The endpoints of one C++ program from the facts of its files."""
    ix = _CppIndex(files)
    r = _resolver_cpp(ix)
    out: list[Endpoint] = []

    def scope(cls: Optional[str], ns: list) -> CppScope:
        return CppScope(ix.alias_lookup(cls, list(ns)), ix.using_ns, ns, known)

    def make(path: str, call: dict, kind: str, name: Value, typ: Optional[str], texpr: Optional[str], api: str,
             ros_v: int) -> Endpoint:
        name = finish(name)
        p = call["pos"]
        npos = call.get("npos")
        e = Endpoint(package, executable, kind, name.text, typ, path, p[0], p[1], p[2], p[3], name.dynamic,
                     _expression(name, call) if name.dynamic else None, api, ros_v or ros,
                     name.default if name.default is not None else _default(call, kind),
                     texpr if typ is None else None)
        if npos and npos[0] == npos[2]:
            e.name_line, e.name_col, e.name_end = npos[0], npos[1], npos[3]
        return e

    for path, f in files:
        for call in f.get("calls", []):
            if only_class and call.get("cls") and call["cls"] != only_class or call.get("cls") in skip_classes:
                continue
            if len(out) >= MAX_ENDPOINTS:
                break
            out.extend(_cpp_call(ix, r, scope, make, path, call, ros))
        for rec in f.get("minits", []):
            mt = ix.member_type(rec["cls"], rec["m"])
            if not mt or (only_class and rec["cls"] != only_class) or rec["cls"] in skip_classes:
                continue
            out.extend(_construction(ix, r, scope, make, path, rec, mt, ros))
        for rec in f.get("ctors", []):
            if only_class and rec.get("cls") and rec["cls"] != only_class or rec.get("cls") in skip_classes:
                continue
            out.extend(_construction(ix, r, scope, make, path, rec, rec["t"], ros))
    param_types(out)
    return out


def _expression(name: Value, call: dict) -> Optional[str]:
    """What a dynamic name depends on: its unknown parts (the argument as written when that is
    all of it)."""
    exprs = list(dict.fromkeys(name.exprs))
    arg = call.get("expr")
    if not exprs or (len(exprs) == 1 and arg and exprs[0] == arg.strip()):
        return arg
    return ", ".join(exprs)


def _default(call: dict, kind: str) -> Optional[str]:
    if kind in ("param_read", "param_declare") and call.get("default") is not None:
        return call["default"]
    return None


def _cpp_call(ix: _CppIndex, r: Resolver, scope, make, path: str, call: dict, ros: int) -> list[Endpoint]:
    kind = call["kind"]
    api = call["api"]
    cls = call.get("cls")
    ns = call.get("ns", [])
    sc = scope(cls, ns)
    ctx = call.get("ctx", "msg")
    recv = call.get("recv")
    rtype = None
    if recv is not None:
        rtype = recv.get("t")
        ir = recv.get("ir")
        if rtype is None and ir and ir[0] in ("id", "mem"):
            c2, n2 = (ir[2], ir[1]) if ir[0] == "id" else (ir[1], ir[2])
            rtype = ix.member_type(c2, n2)
        if rtype:
            rtype = sc.expand(rtype) if "<" not in rtype else rtype
    rt = rtype or ""
    is_it = "ImageTransport" in rt or "image_transport" in rt
    is_mf = "message_filters" in rt or "SubscriberFilter" in rt
    is_pct = "PointCloudTransport" in rt or "point_cloud_transport" in rt
    m = call["m"]
    if m in ("advertise", "subscribe") and is_it:
        api = "image_transport"
    if m == "subscribe" and is_mf:
        api = "message_filters"
    if m in ("advertise", "subscribe") and is_pct:
        api = "point_cloud_transport"
    if api == "roscpp" and m in ("advertise", "subscribe", "param") and rt and not _nh_like(rt) and not is_it \
            and not is_mf and not is_pct:
        return []  # a method of that name on something that is no node handle
    if api == "rclcpp" and kind.startswith("param") and rt and re.search(r"ParameterClient|ParametersClient", rt):
        return []
    ros_v = call.get("ros", 0)
    if api in ("image_transport", "message_filters", "point_cloud_transport"):
        ros_v = 0
    name = r.evaluate(call["name"])
    if call.get("nharg") is not None and ros != 2:
        # filter.subscribe(nh / image transport, "topic", ...): the handle passed first
        na = call["nharg"].get("ir")
        nsv = _nh_namespace(r, ix, na)
        if na and na[0] in ("id", "mem"):
            c2, n2 = (na[2], na[1]) if na[0] == "id" else (na[1], na[2])
            irs = ix.members.get(c2, {}).get(n2) or []
            if irs and all(x and x[0] == "ctor" and "ImageTransport" in (x[1] or "") for x in irs):
                nsv = agree([_nh_namespace(r, ix, (x[2] or [["s", ""]])[0]) for x in irs], n2)
        name = join_values(nsv, name)
    elif ros_v == 1 or (ros_v == 0 and ros == 1) or api in ("roscpp", "image_transport") and ros != 2:
        if recv is not None and not recv.get("free"):
            nsv = _nh_namespace(r, ix, recv.get("ir"))
            if is_it and recv.get("ir") and recv["ir"][0] == "ctor":
                nsv = _nh_namespace(r, ix, (recv["ir"][2] or [["s", ""]])[0])
            name = join_values(nsv, name)
    typ, texpr = None, None
    targs = call.get("targs") or []
    if kind.startswith("param"):
        typ = _param_type_cpp(ix, call, cls)
    elif targs:
        texpr = targs[0]
        typ = sc.normalise(texpr, ctx)
    elif call.get("fixed") or is_it or api == "image_transport":
        typ = call.get("fixed") or "sensor_msgs/Image"
    elif api == "point_cloud_transport":
        typ = "sensor_msgs/PointCloud2"
    elif is_mf:
        base, ta = split_template(rt)
        if ta:
            texpr = ta[0]
            typ = sc.normalise(texpr, ctx)
    if typ is None and not kind.startswith("param") and call.get("cb") is not None:
        t, owner, tns = _first_param(ix, call["cb"], ctx)
        if t:
            texpr = texpr or t
            typ = scope(owner or cls, tns or ns).normalise(t, ctx)
    if typ is None and call.get("tval") is not None:
        v = r.evaluate(call["tval"])
        if not v.dynamic:
            typ = _type_string(v.text)
            texpr = texpr or v.text
    if typ is None and call.get("tvar") is not None:
        pass
    out = [make(path, call, kind, name, typ, texpr, api, ros_v)]
    if call.get("camera") or m in ("advertiseCamera", "subscribeCamera"):
        info = Value(apis.camera_info_topic(name.text), name.dynamic, name.exprs)
        e = make(path, call, kind, info, "sensor_msgs/CameraInfo", None, api, ros_v)
        e.name_line = e.name_col = e.name_end = None
        if typ is None:
            out[0].type = "sensor_msgs/Image"
        out.append(e)
    return out


def _nh_like(t: str) -> bool:
    return bool(re.search(r"NodeHandle|Node\b|node", t))


def _type_string(s: str) -> Optional[str]:
    """``std_msgs/msg/String`` / ``std_msgs/String`` -> ``std_msgs/String``."""
    parts = [p for p in s.strip().split("/") if p]
    if len(parts) == 3 and parts[1] in ("msg", "srv", "action"):
        return f"{parts[0]}/{parts[2]}"
    if len(parts) == 2:
        return f"{parts[0]}/{parts[1]}"
    return None


def _construction(ix: _CppIndex, r: Resolver, scope, make, path: str, rec: dict, type_text: str,
                  ros: int) -> list[Endpoint]:
    cls = rec.get("cls")
    ns = rec.get("ns", [])
    sc = scope(cls, ns)
    base, targs = split_template(" ".join(type_text.split()))
    look = ix.alias_lookup(cls, list(ns))
    for _ in range(4):
        if targs:
            break
        # an alias of a template instance (using ActionServer = nav2_util::SimpleActionServer<A>)
        b = base.replace(" ", "").lstrip(":")
        exp = look(b) or look(b.split("::")[-1])
        if not exp:
            break
        base, targs = split_template(" ".join(exp.split()))
    spec = apis.class_spec(base.replace(" ", "").rstrip("*&"))
    if spec is None:
        return []
    args = rec.get("args") or []
    flags = rec.get("nodeish") or [False] * len(args)
    idx = None
    if spec["api"] == "message_filters":
        # message_filters::Subscriber<T>(nh / node, topic, queue / qos): the topic is second
        if len(args) < 2:
            return []
        args_from = 1
    else:
        args_from = 0
    for i, a in enumerate(args):
        if i < args_from:
            continue
        if i < len(flags) and flags[i]:
            continue
        if _is_nh_expr(ix, a) or (a and a[0] == "dyn" and a[1] in ("this", "true", "false")):
            continue
        if a and a[0] == "dyn" and re.fullmatch(r"[\d.]+|true|false|nullptr|NULL", a[1] or ""):
            continue
        idx = i
        break
    if idx is None:
        return []
    name = r.evaluate(args[idx])
    if not name.text and not name.dynamic:
        return []  # message_filters::Subscriber<T>(nh, "", q): not subscribed until subscribe()
    kind = spec["kind"]
    api = spec["api"]
    ros_v = spec.get("ros", 0)
    if ros_v == 1 or (ros_v == 0 and ros == 1):
        # ros 1: a handle passed first gives the namespace
        if idx > 0:
            nsv = _nh_namespace(r, ix, args[0])
            name = join_values(nsv, name)
    typ, texpr = None, None
    if spec.get("fixed"):
        typ = spec["fixed"]
    elif targs:
        texpr = targs[0]
        typ = sc.normalise(texpr, spec.get("ctx", "msg"))
    call = {"pos": rec["pos"], "npos": rec["npos"][idx] if idx < len(rec.get("npos", [])) else None,
            "expr": rec["texts"][idx] if idx < len(rec.get("texts", [])) else text_of(args[idx])}
    return [make(path, call, kind, name, typ, texpr, api, ros_v)]


# ------------------------------------------------------------------ Python

class _PyIndex:
    def __init__(self, files: list[tuple[str, dict]]):
        self.consts: dict[str, list] = {}
        self.members: dict[str, dict[str, list]] = {}
        self.ctors: dict[str, list] = {}
        self.fcalls: dict[str, list] = {}
        self.bases: dict[str, list[str]] = {}
        for _, f in files:
            for k, v in f.get("consts", {}).items():
                lst = self.consts.setdefault(k, [])
                if v not in lst:
                    lst.append(v)
            for c, mem in f.get("members", {}).items():
                d = self.members.setdefault(c, {})
                for m, irs in mem.items():
                    d.setdefault(m, []).extend(irs)
            for c in f.get("ctors", []):
                self.ctors.setdefault(c["c"], []).append((c["args"], c.get("kw") or {}))
            for c in f.get("fcalls", []):
                self.fcalls.setdefault(c["f"], []).append((c["args"], c.get("kw") or {}))
            for c, b in f.get("bases", {}).items():
                self.bases.setdefault(c, b)


def link_py(package: str, executable: str, ros: int, files: list[tuple[str, dict]],
            known: Optional[dict] = None) -> list[Endpoint]:
    """The endpoints of one Python program from the facts of its modules."""
    ix = _PyIndex(files)

    def member(cls: str, name: str) -> Optional[list]:
        seen = 0
        c = cls
        while c and seen < 6:
            got = ix.members.get(c, {}).get(name)
            if got:
                return got
            bs = ix.bases.get(c) or []
            c = bs[0] if bs else None
            seen += 1
        return None

    def const(name: str, cls: Optional[str], nss: list) -> Optional[list]:
        keys = [name]
        if cls:
            keys.insert(0, f"{cls}.{name}")
        if "." in name:
            keys.append(name.split(".")[-1])
        for k in keys:
            v = ix.consts.get(k)
            if v:
                return v
        return None

    def arg(cls: Optional[str], fn: str, idx: int, name: str = "", default=None) -> Optional[list]:
        calls = ix.ctors.get(cls, []) if cls and fn == "__init__" else ix.fcalls.get(fn, [])
        out = []
        for pos, kw in calls:
            if name and name in kw:
                out.append(kw[name])
            elif isinstance(idx, int) and idx < len(pos):
                out.append(pos[idx])
            elif default is not None:
                out.append(default)
            else:
                return None  # a call we cannot follow (*args, **kwargs): unknown
        return out or None

    r = Resolver(const, member, arg)
    out: list[Endpoint] = []
    for path, f in files:
        for call in f.get("calls", []):
            if len(out) >= MAX_ENDPOINTS:
                break
            name = finish(r.evaluate(call["name"]))
            typ = call.get("type")
            texpr = call.get("texpr")
            if typ is None and call.get("wild"):
                typ = _wild_type(call["wild"], call.get("ctx", "msg"), known or {})
            if typ is None and call.get("tir") is not None:
                tv = _py_type_of(r, call["tir"], call.get("ctx", "msg"))
                typ = tv
            kind = call["kind"]
            p = call["pos"]
            e = Endpoint(package, executable, kind, name.text, typ, path, p[0], p[1], p[2], p[3], name.dynamic,
                         _expression(name, call) if name.dynamic else None, call["api"], call.get("ros") or ros,
                         name.default if name.default is not None else call.get("default"),
                         texpr if typ is None else None)
            npos = call.get("npos")
            if npos and npos[0] == npos[2]:
                e.name_line, e.name_col, e.name_end = npos[0], npos[1], npos[3]
            out.append(e)
    param_types(out)
    return out


def _wild_type(cands: list[str], ctx: str, known: dict) -> Optional[str]:
    """``from a.srv import *`` (and maybe ``from b.msg import *``), then ``X``: the module that
    defines ``X`` (by the workspace's interfaces), or the only candidate."""
    types = [python_type(c, {}, ctx) for c in cands]
    types = [t for t in types if t]
    defined = [t for t in types if t.split("/")[1] in known.get(t.split("/")[0], ())]
    if len(defined) == 1:
        return defined[0]
    # a package of the workspace that does not define it is not where it comes from
    types = [t for t in types if t.split("/")[0] not in known]
    if len(types) == 1:
        return types[0]
    return None


def _py_type_of(r: Resolver, e, ctx: str) -> Optional[str]:
    """A type passed through a variable, member or argument (``self.msg_type``)."""
    if not isinstance(e, list) or not e:
        return None
    if e[0] == "pyty":
        return python_type(e[1], {}, ctx)
    got = r._lookup(e) if e[0] in ("id", "mem", "arg") else None
    if not got:
        return None
    types = {_py_type_of(r, x, ctx) for x in got[:8]}
    return types.pop() if len(types) == 1 else None


def param_types(eps: list[Endpoint]) -> None:
    """A parameter read, written or deleted without a type of its own has the type its program
    declares or reads it with elsewhere (one type only)."""
    known: dict[str, set] = {}
    for e in eps:   # (a dynamic name with its {expression}: the same expression, e.g. in a loop)
        if e.kind.startswith("param") and e.kind != "param_search" and e.type:
            known.setdefault(e.name, set()).add(e.type)
    for e in eps:
        if e.kind.startswith("param") and e.kind != "param_search" and e.type is None:
            ts = known.get(e.name)
            if ts and len(ts) == 1:
                e.type = next(iter(ts))


def dedupe(endpoints: Iterable[Endpoint]) -> list[Endpoint]:
    seen = set()
    out = []
    for e in endpoints:
        k = e.key()
        if k in seen:
            continue
        seen.add(k)
        out.append(e)
    return out
