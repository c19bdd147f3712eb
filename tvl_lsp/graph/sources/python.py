"""Facts of one Python module, read with tree-sitter (:func:`py_facts`): rospy, rclpy, actionlib
and message_filters call sites with their name and type expressions (:mod:`.values`), module
constants, what methods set ``self.x`` to, the arguments classes and functions are called with,
and the module's imports (to follow a node spread over modules of its package, and to read
``String`` as ``std_msgs/String`` after ``from std_msgs.msg import String``).

tree-sitter reads Python 2 (``print "x"``) and half-edited files; nothing here raises on bad input.
"""

from __future__ import annotations

import re
from typing import Optional

from . import apis, treesit
from .types import python_type

VERSION = 6
MAX_CALLS = 5000
MAX_RECORDS = 4000
_BLOCKS = ("if_statement", "for_statement", "while_statement", "try_statement", "with_statement",
           "conditional_expression", "lambda", "match_statement", "except_clause", "elif_clause", "else_clause")
_FMT = re.compile(r"%(?:\([^)]*\))?[-#0 +]*\d*(?:\.\d+)?[sdifrxXeEgGc%]")
_BRACE = re.compile(r"\{([^{}]*)\}")


class _Fn:
    __slots__ = ("name", "cls", "params", "locals", "depth")

    def __init__(self, name: str, cls: Optional[str], params: dict):
        self.name = name
        self.cls = cls
        self.params = params
        self.locals: dict = {}
        self.depth = 0


class _Walker:
    def __init__(self, src: bytes):
        self.src = src
        self.ascii = src.isascii()
        self.lines = None if self.ascii else src.split(b"\n")
        self.cls: list[str] = []
        self.fn: Optional[_Fn] = None
        self.imports: dict[str, str] = {}      # local name -> dotted path
        self.wild: list[str] = []              # from pkg.msg import *
        self.f: dict = {"v": VERSION, "calls": [], "consts": {}, "members": {}, "ctors": [], "fcalls": [],
                        "bases": {}, "imports": [], "notes": [], "main": False}

    def t(self, n) -> str:
        return self.src[n.start_byte:n.end_byte].decode("utf-8", "replace")

    def col(self, row: int, byte_col: int) -> int:
        if self.ascii:
            return byte_col
        line = self.lines[row] if row < len(self.lines) else b""
        return len(line[:byte_col].decode("utf-8", "replace"))

    def pos(self, n) -> list:
        s, e = n.start_point, n.end_point
        return [s[0] + 1, self.col(s[0], s[1]), e[0] + 1, self.col(e[0], e[1])]

    @property
    def cur_cls(self) -> Optional[str]:
        if self.fn is not None and self.fn.cls:
            return self.fn.cls
        return self.cls[-1] if self.cls else None

    # ------------------------------------------------------------ walk
    def walk(self, n) -> None:
        h = getattr(self, "v_" + n.type, None)
        if h is not None:
            h(n)
            return
        if self.fn is not None and n.type in _BLOCKS:
            self.fn.depth += 1
            for ch in n.named_children:
                self.walk(ch)
            self.fn.depth -= 1
            return
        for ch in n.named_children:
            self.walk(ch)

    def v_comment(self, n) -> None:
        return

    def v_string(self, n) -> None:
        for ch in n.named_children:
            if ch.type == "interpolation":
                self.walk(ch)

    def v_import_statement(self, n) -> None:
        for ch in n.named_children:
            if ch.type == "dotted_name":
                full = self.t(ch)
                self.imports[full.split(".")[0]] = full.split(".")[0]
                self.imports.setdefault(full, full)
                self.f["imports"].append([full, 0, []])
            elif ch.type == "aliased_import":
                name = ch.child_by_field_name("name")
                alias = ch.child_by_field_name("alias")
                if name is not None and alias is not None:
                    self.imports[self.t(alias)] = self.t(name)
                    self.f["imports"].append([self.t(name), 0, []])

    def _bind(self, local: str, path: str) -> None:
        """``local`` names ``path``; a name imported as two different message types (``if distro ==
        'humble': from geometry_msgs.msg import Twist as CmdVel else: ... TwistStamped as CmdVel``)
        is a type chosen at run time: no type."""
        old = self.imports.get(local)
        if old is not None and old != path and re.search(r"\.(msg|srv|action)\.", old + " " + path):
            self.imports[local] = "?" + local
            return
        self.imports[local] = path

    def v_import_from_statement(self, n) -> None:
        mod = n.child_by_field_name("module_name")
        if mod is None:
            return
        level = 0
        if mod.type == "relative_import":
            prefix = next((c for c in mod.children if c.type == "import_prefix"), None)
            level = len(self.t(prefix)) if prefix is not None else 1
            dn = next((c for c in mod.named_children if c.type == "dotted_name"), None)
            modname = self.t(dn) if dn is not None else ""
        else:
            modname = self.t(mod)
        names = []
        for i, ch in enumerate(n.children):
            if n.field_name_for_child(i) != "name":
                continue
            if ch.type == "dotted_name":
                local = self.t(ch)
                names.append(local)
                self._bind(local, (modname + "." if modname else "") + local if level == 0 else "." * level +
                           (modname + "." if modname else "") + local)
            elif ch.type == "aliased_import":
                name = ch.child_by_field_name("name")
                alias = ch.child_by_field_name("alias")
                if name is not None and alias is not None:
                    names.append(self.t(name))
                    self._bind(self.t(alias), (modname + "." if modname else "") + self.t(name) if level == 0
                               else "." * level + (modname + "." if modname else "") + self.t(name))
        if any(c.type == "wildcard_import" for c in n.named_children):
            names.append("*")
            if level == 0 and modname.split(".")[-1] in ("msg", "srv", "action"):
                self.wild.append(modname)
        self.f["imports"].append([modname, level, names])

    def v_class_definition(self, n) -> None:
        name = n.child_by_field_name("name")
        cname = self.t(name) if name is not None else "<anonymous>"
        sup = n.child_by_field_name("superclasses")
        if sup is not None:
            self.f["bases"][cname] = [self.t(b).split(".")[-1] for b in sup.named_children
                                      if b.type in ("identifier", "attribute")]
        self.cls.append(cname)
        saved, self.fn = self.fn, None
        body = n.child_by_field_name("body")
        if body is not None:
            self.walk(body)
        self.fn = saved
        self.cls.pop()

    def v_function_definition(self, n) -> None:
        name = n.child_by_field_name("name")
        fname = self.t(name) if name is not None else "<lambda>"
        params = {}
        plist = n.child_by_field_name("parameters")
        idx = 0
        in_class = bool(self.cls) and self.fn is None
        if plist is not None:
            for k, p in enumerate(plist.named_children):
                pname = None
                default = None
                if p.type == "identifier":
                    pname = self.t(p)
                elif p.type in ("default_parameter", "typed_default_parameter"):
                    nn = p.child_by_field_name("name")
                    pname = self.t(nn) if nn is not None else None
                    dv = p.child_by_field_name("value")
                    default = self.ir(dv) if dv is not None else None
                elif p.type == "typed_parameter":
                    nn = next((c for c in p.named_children if c.type == "identifier"), None)
                    pname = self.t(nn) if nn is not None else None
                if pname is None:
                    continue
                if in_class and k == 0 and pname in ("self", "cls"):
                    continue
                params[pname] = (idx, "", default)
                idx += 1
        saved = self.fn
        self.fn = _Fn(fname, self.cur_cls if in_class or (saved and saved.cls) else None, params)
        body = n.child_by_field_name("body")
        if body is not None:
            self.walk(body)
        self.fn = saved

    def v_if_statement(self, n) -> None:
        cond = n.child_by_field_name("condition")
        if self.fn is None and cond is not None and "__name__" in self.t(cond) and "__main__" in self.t(cond):
            self.f["main"] = True
            saved = self.fn
            self.fn = _Fn("<main>", None, {})
            for ch in n.named_children:
                self.walk(ch)
            self.fn = saved
            return
        if self.fn is not None:
            self.fn.depth += 1
        for ch in n.named_children:
            self.walk(ch)
        if self.fn is not None:
            self.fn.depth -= 1

    # ------------------------------------------------------------ assignments
    def v_assignment(self, n) -> None:
        left = n.child_by_field_name("left")
        right = n.child_by_field_name("right")
        if left is None or right is None:
            return
        ir = self.ir(right)
        self.assign(left, ir)
        self.walk(right)

    def v_augmented_assignment(self, n) -> None:
        left = n.child_by_field_name("left")
        right = n.child_by_field_name("right")
        if left is None or right is None:
            return
        self.assign(left, ["cat", [self.ir(left), self.ir(right)]])
        self.walk(right)

    def assign(self, left, ir) -> None:
        if ir and ir[0] == "param":
            ir = ir[:3] + [self.t(left).replace("self.", "")[:80]]
        if left.type == "identifier":
            name = self.t(left)
            fn = self.fn
            if fn is None:
                if self.cls:
                    key = f"{self.cls[-1]}.{name}"
                    self.f["consts"].setdefault(key, ir)
                    self.f["members"].setdefault(self.cls[-1], {}).setdefault(name, []).append(ir)
                else:
                    if name in self.f["consts"] and self.f["consts"][name] != ir:
                        self.f["consts"][name] = ["dyn", name]
                    else:
                        self.f["consts"][name] = ir
                return
            loc = fn.locals.get(name)
            if loc is not None and (fn.depth > loc["d"] or fn.depth and loc.get("set")):
                loc["ir"] = ["dyn", name]
                loc["set"] = True
            elif loc is not None and fn.depth < loc["d"]:
                loc["ir"] = ir
                loc["d"] = fn.depth
            elif loc is not None:
                loc["ir"] = ir
                loc["set"] = True
            else:
                fn.locals[name] = {"ir": ir, "d": fn.depth}
        elif left.type == "attribute":
            obj = left.child_by_field_name("object")
            attr = left.child_by_field_name("attribute")
            if obj is not None and attr is not None and self.t(obj) == "self" and self.cur_cls:
                self.f["members"].setdefault(self.cur_cls, {}).setdefault(self.t(attr), []).append(ir)
        elif left.type in ("pattern_list", "tuple_pattern"):
            for ch in left.named_children:
                self.assign(ch, ["dyn", self.t(ch)])

    # ------------------------------------------------------------ expressions
    def ir(self, n, depth: int = 0):
        if depth > 40 or n is None:
            return ["dyn", self.t(n)[:200] if n is not None else "?"]
        ty = n.type
        if ty == "string":
            return self.string_ir(n, depth)
        if ty == "concatenated_string":
            return ["cat", [self.ir(c, depth + 1) for c in n.named_children]]
        if ty == "parenthesized_expression":
            kids = n.named_children
            return self.ir(kids[0], depth + 1) if kids else ["dyn", self.t(n)]
        if ty == "identifier":
            return self.ident(self.t(n))
        if ty == "attribute":
            obj = n.child_by_field_name("object")
            attr = n.child_by_field_name("attribute")
            if obj is not None and attr is not None:
                if self.t(obj) == "self":
                    return ["mem", self.cur_cls, self.t(attr)]
                if attr is not None and self.t(attr) == "value" and obj.type == "call":
                    return self.ir(obj, depth + 1)  # get_parameter('x').value
                if attr is not None and self.t(attr) in ("string_value", "double_value", "integer_value",
                                                         "bool_value") and obj.type == "call":
                    return self.ir(obj, depth + 1)
                if obj.type in ("identifier", "attribute") and re.fullmatch(r"[\w.]+", self.t(n)):
                    return ["id", self.t(n), self.cur_cls, []]
            return ["dyn", self.t(n)[:200]]
        if ty == "binary_operator":
            op = n.child_by_field_name("operator")
            left = n.child_by_field_name("left")
            right = n.child_by_field_name("right")
            o = self.t(op) if op is not None else ""
            if o == "+":
                return ["cat", [self.ir(left, depth + 1), self.ir(right, depth + 1)]]
            if o == "%" and left is not None and left.type == "string":
                fmt = self.ir(left, depth + 1)
                if fmt[0] == "s":
                    vals = list(right.named_children) if right is not None and right.type == "tuple" else [right]
                    return _format_percent(fmt[1], [self.ir(v, depth + 1) for v in vals if v is not None],
                                           self.t(n)[:200])
            return ["dyn", self.t(n)[:200]]
        if ty == "call":
            return self.call_ir(n, depth)
        return ["dyn", self.t(n)[:200]]

    def string_ir(self, n, depth: int):
        parts: list = []
        buf = []
        prefix = self.t(n)[:3].lower()
        for ch in n.named_children:
            if ch.type == "string_content":
                buf.append(self.t(ch))
            elif ch.type == "escape_sequence":
                e = self.t(ch)
                buf.append({"\\n": "\n", "\\t": "\t", "\\\\": "\\", "\\'": "'", '\\"': '"'}.get(e, e) if "r" not in
                           prefix.split("'")[0].split('"')[0] else e)
            elif ch.type == "interpolation":
                if buf:
                    parts.append(["s", "".join(buf)])
                    buf = []
                ex = ch.child_by_field_name("expression")
                parts.append(self.ir(ex, depth + 1) if ex is not None else ["dyn", self.t(ch)])
        if buf or not parts:
            parts.append(["s", "".join(buf)])
        return parts[0] if len(parts) == 1 else ["cat", parts]

    def ident(self, name: str):
        fn = self.fn
        if fn is not None:
            loc = fn.locals.get(name)
            if loc is not None:
                return loc["ir"]
            p = fn.params.get(name)
            if p is not None:
                return ["arg", fn.cls, fn.name, p[0], name, "", p[2]]
        if name in self.imports and "." in self.imports[name] and not self.imports[name].startswith("."):
            return ["id", self.imports[name], self.cur_cls, []]
        return ["id", name, self.cur_cls, []]

    def dotted(self, n) -> Optional[str]:
        """``a.b.c`` of an identifier / attribute chain, with the module's imports applied."""
        t = self.t(n)
        if not re.fullmatch(r"[A-Za-z_][\w.]*", t):
            return None
        head, _, rest = t.partition(".")
        if head in self.imports:
            return self.imports[head] + ("." + rest if rest else "")
        return t

    def call_ir(self, n, depth: int):
        fnode = n.child_by_field_name("function")
        args = n.child_by_field_name("arguments")
        pos, kw = _args(self, args)
        d = self.dotted(fnode) if fnode is not None else None
        last = (d or self.t(fnode) if fnode is not None else "").split(".")[-1]
        if d in ("str", "unicode") and pos:
            return self.ir(pos[0], depth + 1)
        if d in ("rospy.get_name",) or (last == "get_name" and d and d.startswith("rospy")):
            return ["node"]
        if d in ("rospy.get_param", "rospy.get_param_cached") and (pos or "param_name" in kw):
            nm = pos[0] if pos else kw["param_name"]
            dv = pos[1] if len(pos) > 1 else kw.get("default")
            return ["param", self.ir(nm, depth + 1), self.ir(dv, depth + 1) if dv is not None else None,
                    self.t(n)[:200]]
        if last in ("declare_parameter", "get_parameter", "get_parameter_or") and (pos or "name" in kw):
            nm = pos[0] if pos else kw["name"]
            dv = pos[1] if len(pos) > 1 else kw.get("value")
            return ["param", self.ir(nm, depth + 1), self.ir(dv, depth + 1) if dv is not None else None,
                    self.t(n)[:200]]
        if last == "format" and fnode is not None and fnode.type == "attribute":
            obj = fnode.child_by_field_name("object")
            if obj is not None and obj.type == "string":
                fmt = self.ir(obj, depth + 1)
                if fmt[0] == "s":
                    return _format_brace(fmt[1], [self.ir(p, depth + 1) for p in pos],
                                         {k: self.ir(v, depth + 1) for k, v in kw.items()}, self.t(n)[:200])
        return ["dyn", self.t(n)[:200]]

    # ------------------------------------------------------------ calls
    def v_call(self, n) -> None:
        fnode = n.child_by_field_name("function")
        args = n.child_by_field_name("arguments")
        if fnode is None:
            return
        pos, kw = _args(self, args)
        d = self.dotted(fnode)
        spec = None
        if d is not None:
            d2 = apis.PY_MODULE_ALIASES.get(d, d)
            spec = apis.PY_CALLS.get(d2)
        last = self.t(fnode).split(".")[-1] if fnode.type in ("attribute", "identifier") else ""
        if spec is None and fnode.type == "attribute" and last in apis.PY_METHODS:
            obj = fnode.child_by_field_name("object")
            head = self.t(obj).split(".")[0] if obj is not None else ""
            if head not in ("rospy",) and not (last.endswith(("parameter", "parameter_or", "parameters"))
                                                and re.search(r"client", self.t(obj), re.I)):
                spec = apis.PY_METHODS[last]
        if spec is not None and len(self.f["calls"]) < MAX_CALLS:
            self.call_site(n, fnode, spec, pos, kw)
        elif last in ("declare_parameters",) and fnode.type == "attribute" and \
                not re.search(r"client", self.t(fnode.child_by_field_name("object") or fnode), re.I):
            self.declare_parameters(n, fnode, pos, kw)
        elif last == "get_parameters" and fnode.type == "attribute" and pos and pos[0].type == "list" and \
                not re.search(r"client", self.t(fnode.child_by_field_name("object") or fnode), re.I):
            for item in pos[0].named_children[:64]:
                self.call_site(n, fnode, {"api": "rclpy", "kind": "param_read", "name": (0, "name"), "ros": 2},
                               [item], {})
        # records for resolving arguments across modules (constructions with none too: the
        # parameters' defaults are then their values)
        if d is not None and len(self.f["ctors"]) + len(self.f["fcalls"]) < MAX_RECORDS:
            short = d.split(".")[-1]
            irs = [self.ir(p) for p in pos]
            kws = {k: self.ir(v) for k, v in kw.items()}
            if short[:1].isupper() and not (short.isupper() and len(short) > 1):
                self.f["ctors"].append({"c": short, "args": irs, "kw": kws})
            elif (pos or kw) and any(x[0] != "dyn" for x in irs + list(kws.values())):
                self.f["fcalls"].append({"f": short, "args": irs, "kw": kws})
        if fnode.type == "attribute":
            obj = fnode.child_by_field_name("object")
            if obj is not None:
                self.walk(obj)
        if args is not None:
            self.walk(args)

    def _fpos(self, n, fnode) -> list:
        name = fnode.child_by_field_name("attribute") if fnode.type == "attribute" else fnode
        s = (name or n).start_point
        e = n.end_point
        return [s[0] + 1, self.col(s[0], s[1]), e[0] + 1, self.col(e[0], e[1])]

    def call_site(self, n, fnode, spec, pos, kw) -> None:
        name_node = _pick(pos, kw, spec.get("name"))
        type_node = _pick(pos, kw, spec.get("type"))
        if spec.get("mf"):
            # message_filters.Subscriber: ROS 1 (topic, type), ROS 2 (node, type, topic)
            if len(pos) == 2 or pos and pos[0].type in ("string", "concatenated_string", "binary_operator"):
                name_node, type_node = pos[0], (pos[1] if len(pos) > 1 else kw.get("msg_type"))
            else:
                type_node = pos[1] if len(pos) > 1 else kw.get("msg_type")
                name_node = pos[2] if len(pos) > 2 else kw.get("topic")
        if name_node is None:
            return
        call = {"api": spec["api"], "kind": spec["kind"], "ros": spec.get("ros", 0), "name": self.ir(name_node),
                "expr": self.t(name_node)[:200], "npos": self.pos(name_node), "pos": self._fpos(n, fnode),
                "cls": self.cur_cls, "fn": self.fn.name if self.fn else None, "ctx": spec.get("ctx", "msg")}
        if type_node is not None:
            tt = self.t(type_node)
            d = self.dotted(type_node)
            typ = python_type(d, {}, call["ctx"]) if d else None
            if typ is None and d and type_node.type == "identifier" and self.wild and d not in self.imports \
                    and d[:1].isupper():
                # from pkg.srv import *: the type is one of those modules' (checked when linking)
                call["wild"] = [m + "." + d for m in self.wild]
            if typ is None and d and type_node.type == "identifier":
                # a local, a parameter, a member holding the type
                call["tir"] = self.ir(type_node)
                if call["tir"][0] == "id" and "." in call["tir"][1]:
                    call["tir"] = ["pyty", call["tir"][1]]
            elif typ is None and type_node.type == "attribute" and self.t(type_node).startswith("self."):
                call["tir"] = self.ir(type_node)
            call["type"] = typ
            if typ is None:
                call["texpr"] = tt[:120]
        vn = _pick(pos, kw, spec.get("value"))
        if vn is not None:
            call["type"] = apis.py_value_type(vn.type, self.t(vn))
            call["default"] = self.t(vn)[:120]
        elif spec["kind"].startswith("param"):
            call["type"] = None
        self.f["calls"].append(call)

    def declare_parameters(self, n, fnode, pos, kw) -> None:
        ns_node = pos[0] if pos else kw.get("namespace")
        plist = pos[1] if len(pos) > 1 else kw.get("parameters")
        if plist is None or plist.type not in ("list", "tuple"):
            return
        ns = self.ir(ns_node) if ns_node is not None else ["s", ""]
        for item in plist.named_children[:128]:
            if item.type not in ("tuple", "list") or not item.named_children:
                continue
            kids = item.named_children
            name_ir = self.ir(kids[0])
            full = ["cat", [ns, ["s", "."], name_ir]] if ns != ["s", ""] else name_ir
            call = {"api": "rclpy", "kind": "param_declare", "ros": 2, "name": full, "expr": self.t(kids[0])[:200],
                    "npos": self.pos(kids[0]), "pos": self._fpos(n, fnode), "cls": self.cur_cls,
                    "fn": self.fn.name if self.fn else None, "ctx": "msg"}
            if len(kids) > 1:
                call["type"] = apis.py_value_type(kids[1].type, self.t(kids[1]))
                call["default"] = self.t(kids[1])[:120]
            self.f["calls"].append(call)


def _args(w: _Walker, args) -> tuple[list, dict]:
    pos, kw = [], {}
    if args is None:
        return pos, kw
    for a in args.named_children:
        if a.type == "keyword_argument":
            k = a.child_by_field_name("name")
            v = a.child_by_field_name("value")
            if k is not None and v is not None:
                kw[w.t(k)] = v
        elif a.type in ("list_splat", "dictionary_splat", "comment"):
            continue
        else:
            pos.append(a)
    return pos, kw


def _pick(pos: list, kw: dict, where):
    if where is None:
        return None
    i, k = where
    if k is not None and k in kw:
        return kw[k]
    if i is not None and i < len(pos):
        return pos[i]
    return None


def _format_percent(fmt: str, vals: list, text: str):
    parts = []
    last = 0
    k = 0
    for m in _FMT.finditer(fmt):
        if m.group(0) == "%%":
            continue
        parts.append(["s", fmt[last:m.start()]])
        if k >= len(vals):
            return ["dyn", text]
        parts.append(vals[k])
        k += 1
        last = m.end()
    parts.append(["s", fmt[last:].replace("%%", "%")])
    return ["cat", [p for p in parts if p != ["s", ""]]] if len(parts) > 1 else parts[0]


def _format_brace(fmt: str, vals: list, kws: dict, text: str):
    parts = []
    last = 0
    auto = 0
    for m in _BRACE.finditer(fmt):
        parts.append(["s", fmt[last:m.start()]])
        key = m.group(1).split(":")[0].split("!")[0]
        if key == "":
            if auto >= len(vals):
                return ["dyn", text]
            parts.append(vals[auto])
            auto += 1
        elif key.isdigit():
            if int(key) >= len(vals):
                return ["dyn", text]
            parts.append(vals[int(key)])
        elif key in kws:
            parts.append(kws[key])
        else:
            return ["dyn", text]
        last = m.end()
    parts.append(["s", fmt[last:]])
    return ["cat", [p for p in parts if p != ["s", ""]]] if len(parts) > 1 else parts[0]


def py_facts(src: bytes) -> dict:
    """The facts of one Python module (never raises on bad input)."""
    return treesit.facts("python", _Walker, src)
