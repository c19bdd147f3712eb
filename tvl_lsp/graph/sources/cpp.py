"""Facts of one C++ file, read with tree-sitter (:func:`cpp_facts`): the ROS call sites (roscpp,
rclcpp, actionlib, rclcpp_action, image_transport, message_filters) with their name, type and
callback expressions (:mod:`.values`), and what other files of the same program need to
resolve them: constants and ``#define`` s, class members and what constructors and methods set
them to, function signatures (callback types), aliases, and the arguments classes are
constructed with.  The facts are plain JSON data, cached by the file's content; the linker
(:mod:`.link`) puts the files of one program together.

tree-sitter parses half-edited files: what it cannot parse is an ``ERROR`` node that the walk
passes through.  Nothing here raises on bad input.
"""

from __future__ import annotations

import re
from typing import Optional

from . import apis, treesit
from .cpp_helpers import (_C_STRING_WRITERS, _callee, _declarator_name, _define_ir, _fcall, _format_ir,
                          _function_declarator, _function_type_param, _is_nodehandle, _is_nodeish_type,
                          _is_string_type, _nodekind, _ptype, _string_value, _value_type, _vexing)

VERSION = 11
MAX_CALLS = 5000
MAX_RECORDS = 4000

_AS_TYPE = {"as_double": "double", "as_int": "int", "as_bool": "bool", "as_string": "string",
            "as_double_array": "double[]", "as_integer_array": "int[]", "as_bool_array": "bool[]",
            "as_string_array": "string[]", "as_byte_array": "int[]"}
_CLIENT = re.compile(r"client", re.I)
_PLACEHOLDER = re.compile(r"^(?:(?:boost|std)::placeholders::|::)?_(\d)$")
_NODEISH = re.compile(r"^(?:\*?this|n|nh|pnh|nh_?|n_|node|node_|priv_nh_?|private_nh_?|nh_priv_?|nh_private_?|"
                      r"private_node_handle_?|node_handle_?|nodehandle_?|.*_nh_?|nh_.*|.*node_handle.*|.*_node_?|"
                      r"node_ptr_?|parent_?|parent_node_?|it_?|\w+_it_?|image_transport_?|\w*_transport_?)$", re.I)
_BLOCKS = ("if_statement", "for_statement", "for_range_loop", "while_statement", "do_statement",
           "switch_statement", "case_statement", "catch_clause", "try_statement", "conditional_expression",
           "lambda_expression")


class _Fn:
    __slots__ = ("name", "cls", "params", "locals", "depth")

    def __init__(self, name: str, cls: Optional[str], params: dict):
        self.name = name
        self.cls = cls
        self.params = params        # name -> (index, type text)
        self.locals: dict = {}      # name -> {"t": type, "ir": expr, "d": block depth, "lt": lambda param type}
        self.depth = 0


class _Walker:
    def __init__(self, src: bytes):
        self.src = src
        self.ascii = src.isascii()
        self.lines = src.split(b"\n") if not self.ascii else None
        self.ns: list[str] = []
        self.cls: list[str] = []
        self.fn: Optional[_Fn] = None
        self.hints: dict[int, str] = {}   # call start -> parameter type (get_parameter(..).as_double())
        self.juxt: dict[int, list] = {}   # argument start -> the macros written after it (A_S X_S)
        self.f: dict = {"v": VERSION, "calls": [], "consts": {}, "aliases": {}, "using_decls": {}, "using_ns": [],
                        "members": {}, "mtypes": {}, "funcs": {}, "ctors": [], "fcalls": [], "includes": [],
                        "minits": [], "binits": [], "gsets": [], "pdefaults": {}, "notes": []}

    # ------------------------------------------------------------ helpers
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

    def scope_prefix(self) -> str:
        parts = list(self.ns) + ([self.cls[-1]] if self.cls else [])
        return "::".join(parts)

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

    def v_string_literal(self, n) -> None:
        return

    def v_preproc_include(self, n) -> None:
        p = n.child_by_field_name("path")
        if p is not None:
            self.f["includes"].append(self.t(p).strip('"<>'))

    def v_preproc_def(self, n) -> None:
        name = n.child_by_field_name("name")
        val = n.child_by_field_name("value")
        if name is None or val is None:
            return
        ir = _define_ir(self.t(val).strip())
        if ir is not None:
            self.f["consts"].setdefault(self.t(name), ir)

    def v_namespace_definition(self, n) -> None:
        name = n.child_by_field_name("name")
        parts = self.t(name).replace(" ", "").split("::") if name is not None else []
        self.ns.extend(parts)
        body = n.child_by_field_name("body")
        if body is not None:
            self.walk(body)
        for _ in parts:
            self.ns.pop()

    def v_class_specifier(self, n, cname: Optional[str] = None) -> None:
        name = n.child_by_field_name("name")
        body = n.child_by_field_name("body")
        if body is None:
            return
        if cname is None:
            cname = self.t(name).split("<")[0].split("::")[-1].strip() if name is not None else "<anonymous>"
        self.cls.append(cname)
        saved, self.fn = self.fn, None
        self.walk(body)
        self.fn = saved
        self.cls.pop()

    v_struct_specifier = v_class_specifier

    def v_alias_declaration(self, n) -> None:
        name = n.child_by_field_name("name")
        typ = n.child_by_field_name("type")
        if name is not None and typ is not None:
            self._alias(self.t(name), self.t(typ))

    def _alias(self, name: str, target: str) -> None:
        pre = self.scope_prefix()
        self.f["aliases"][(pre + "::" if pre else "") + name] = " ".join(target.split())
        self.f["aliases"].setdefault(name, " ".join(target.split()))

    def v_type_definition(self, n) -> None:
        typ = n.child_by_field_name("type")
        if typ is None:
            return
        for i, ch in enumerate(n.children):
            if n.field_name_for_child(i) == "declarator" and ch.type == "type_identifier":
                if typ.type in ("struct_specifier", "class_specifier") and typ.child_by_field_name("name") is None:
                    self.v_class_specifier(typ, self.t(ch))     # typedef struct { int rate; } Config;
                else:
                    self._alias(self.t(ch), self.t(typ))

    def v_using_declaration(self, n) -> None:
        text = " ".join(self.t(n).split())
        m = re.match(r"using\s+namespace\s+([\w:]+)", text)
        if m:
            self.f["using_ns"].append(m.group(1).strip(":"))
            return
        m = re.match(r"using\s+(?:typename\s+)?([\w:]+)\s*;?$", text)
        if m:
            q = m.group(1).strip(":")
            self.f["using_decls"][q.split("::")[-1]] = q

    def v_namespace_alias_definition(self, n) -> None:
        name = n.child_by_field_name("name")
        if name is None:
            return
        target = None
        for ch in n.named_children:
            if ch.type in ("nested_namespace_specifier", "namespace_identifier", "qualified_identifier") and ch != name:
                target = self.t(ch)
        if target:
            self.f["aliases"][self.t(name)] = target.replace(" ", "")

    # ------------------------------------------------------------ functions
    def v_function_definition(self, n) -> None:
        decl = n.child_by_field_name("declarator")
        fd = _function_declarator(decl)
        if fd is None:
            for ch in n.named_children:
                self.walk(ch)
            return
        qname = self.t(fd.child_by_field_name("declarator")).replace(" ", "")
        parts = qname.split("::")
        if len(parts) >= 2:
            cls = parts[-2].split("<")[0]
        else:
            cls = self.cls[-1] if self.cls else None
        short = parts[-1]
        params = self._params(fd)
        key = f"{cls}::{short}" if cls else short
        self._sig(key, params)
        saved = self.fn
        self.fn = _Fn(short, cls, {p[0]: (i, p[1], p[2]) for i, p in enumerate(params) if p[0]})
        for ch in n.named_children:
            if ch.type == "field_initializer_list":
                self._initializers(ch, cls)
        body = n.child_by_field_name("body")
        if body is not None:
            self.walk(body)
        self.fn = saved

    def _sig(self, key: str, params: list) -> None:
        """A function's signature, and its parameters' defaults (a header's declaration often has
        them: ``Robot(const std::string& topic = "robot_state")``)."""
        self.f["funcs"].setdefault(key, []).append([[p[1], p[0]] for p in params])
        for i, p in enumerate(params):
            if p[2] is not None and p[0]:
                self.f["pdefaults"].setdefault(key, {})[f"{i}:{p[0]}"] = p[2]

    def _params(self, fd) -> list[tuple[str, str]]:
        out = []
        plist = fd.child_by_field_name("parameters")
        if plist is None:
            return out
        for p in plist.named_children:
            if p.type not in ("parameter_declaration", "optional_parameter_declaration",
                              "variadic_parameter_declaration"):
                continue
            typ = p.child_by_field_name("type")
            d = p.child_by_field_name("declarator")
            tt = self._decl_type(p, typ, d)
            dv = p.child_by_field_name("default_value")
            out.append((_declarator_name(self, d) or "", tt, self.ir(dv) if dv is not None else None))
        return out

    def _decl_type(self, owner, typ, d) -> str:
        """The declared type with its qualifiers, pointer and reference marks."""
        pre = " ".join(self.t(c) for c in owner.children if c.type == "type_qualifier")
        tt = self.t(typ) if typ is not None else ""
        if d is not None:
            dt = d.type
            if dt in ("pointer_declarator", "abstract_pointer_declarator"):
                tt += "*"
            elif dt in ("reference_declarator", "abstract_reference_declarator"):
                tt += "&"
        return (pre + " " + tt).strip()

    def _initializers(self, lst, cls) -> None:
        for fi in lst.named_children:
            if fi.type != "field_initializer":
                continue
            name = None
            args = None
            for ch in fi.named_children:
                if ch.type in ("field_identifier", "identifier", "qualified_identifier", "template_method"):
                    name = self.t(ch).split("::")[-1].split("<")[0]
                elif ch.type in ("argument_list", "initializer_list"):
                    args = ch
            if name is None or args is None or not cls:
                continue
            argn = list(args.named_children)
            irs = [self.ir(a) for a in argn]
            self.f["members"].setdefault(cls, {}).setdefault(name, []).append(["ctor", None, irs])
            if argn and name != cls and len(self.f["binits"]) < MAX_RECORDS:
                # (when ``name`` is a base class: ``Derived(nh) : Base(nh, 1)`` constructs a Base)
                self.f["binits"].append({"t": name, "args": irs, "nk": [self.nodekind(a) for a in argn]})
            if len(self.f["minits"]) < MAX_RECORDS and argn:
                self.f["minits"].append({"cls": cls, "m": name, "args": irs, "nodeish": [self.nodeish(a) for a in argn],
                                         "nk": [self.nodekind(a) for a in argn],
                                         "texts": [self.t(a)[:200] for a in argn], "pos": self.pos(fi),
                                         "npos": [self.pos(a) for a in argn], "ns": list(self.ns)})
            for a in argn:
                self.walk(a)

    # ------------------------------------------------------------ declarations
    def v_field_declaration(self, n) -> None:
        cls = self.cls[-1] if self.cls else None
        typ = n.child_by_field_name("type")
        if typ is not None and typ.type in ("struct_specifier", "class_specifier") and \
                typ.child_by_field_name("body") is not None:
            # struct { int rate; } config_;  (its fields' types, for getParam("rate", config_.rate))
            if typ.child_by_field_name("name") is None:
                first = next((_declarator_name(self, ch) for i, ch in enumerate(n.children)
                              if n.field_name_for_child(i) == "declarator"), None)
                if first and cls:
                    anon = f"{cls}.{first}"
                    self.v_class_specifier(typ, anon)
                    for i, ch in enumerate(n.children):
                        if n.field_name_for_child(i) == "declarator" and _declarator_name(self, ch):
                            self.f["mtypes"].setdefault(cls, {})[_declarator_name(self, ch)] = anon
                    return
            else:
                self.v_class_specifier(typ)
        static = any(c.type == "storage_class_specifier" and self.t(c) == "static" for c in n.children)
        default = n.child_by_field_name("default_value")
        for i, ch in enumerate(n.children):
            if n.field_name_for_child(i) != "declarator":
                continue
            fd = _function_declarator(ch)
            if fd is not None:
                name = self.t(fd.child_by_field_name("declarator")).split("::")[-1]
                key = f"{cls}::{name}" if cls else name
                self._sig(key, self._params(fd))
                continue
            name = _declarator_name(self, ch)
            if not name or not cls:
                continue
            self.f["mtypes"].setdefault(cls, {})[name] = self._decl_type(n, typ, ch)
            if default is not None:
                ir = self.ir(default)
                self.f["members"].setdefault(cls, {}).setdefault(name, []).append(ir)
                if static or "const" in self.t(n).split("=")[0]:
                    self._const(name, ir, cls)
                self.walk(default)
        # a member function body inside the class
        for ch in n.named_children:
            if ch.type == "function_definition":
                self.walk(ch)

    def _const(self, name: str, ir, cls: Optional[str] = None) -> None:
        pre = "::".join(list(self.ns) + ([cls] if cls else []))
        c = self.f["consts"]
        c.setdefault(name, ir)
        if pre:
            c.setdefault(pre + "::" + name, ir)
        if cls:
            c.setdefault(cls + "::" + name, ir)

    def v_declaration(self, n) -> None:
        typ = n.child_by_field_name("type")
        tt = self.t(typ) if typ is not None else ""
        for i, ch in enumerate(n.children):
            if n.field_name_for_child(i) != "declarator":
                continue
            self._declarator(n, typ, tt, ch)

    def _declarator(self, n, typ, tt: str, d) -> None:
        value = None
        dd = d
        if d.type == "init_declarator":
            dd = d.child_by_field_name("declarator")
            value = d.child_by_field_name("value")
        fd = _function_declarator(dd) if dd is not None else None
        if fd is not None and value is None:
            if self.fn is not None and _vexing(fd):
                # Type name(arg, ...): a variable constructed with arguments (the "most vexing parse")
                name = self.t(fd.child_by_field_name("declarator"))
                self._local_or_global(n, typ, tt, name, dd, fd.child_by_field_name("parameters"), vexing=True)
                return
            name = self.t(fd.child_by_field_name("declarator")).replace(" ", "")
            parts = name.split("::")
            cls = parts[-2] if len(parts) >= 2 else (self.cls[-1] if self.cls else None)
            key = f"{cls}::{parts[-1]}" if cls else parts[-1]
            self._sig(key, self._params(fd))
            return
        name = _declarator_name(self, dd) if dd is not None else None
        if not name:
            if value is not None:
                self.walk(value)
            return
        self._local_or_global(n, typ, tt, name, dd, value)

    def _local_or_global(self, n, typ, tt: str, name: str, dd, value, vexing: bool = False) -> None:
        full_t = self._decl_type(n, typ, dd)
        if value is not None and value.type == "call_expression" and _ptype(full_t):
            # double rate = declare_parameter("rate", ...): the parameter's type is the variable's
            self.hints.setdefault(value.start_byte, _ptype(full_t))
        args = None
        if value is not None and value.type in ("argument_list", "initializer_list"):
            args = list(value.named_children)
        elif vexing and value is not None:
            args = [p.child_by_field_name("type") or p for p in value.named_children]
        if args is not None:
            irs = [self.ir(a) for a in args]
            if _is_nodehandle(tt):
                irs = [["nhref", x] if self.nodeish(a) and k == 0 else x for k, (a, x) in enumerate(zip(args, irs))]
            ir = ["ctor", tt, irs] if not _is_string_type(tt) else (irs[0] if irs else ["s", ""])
            self._construction(tt, args, irs, dd)
        elif value is not None and (value.type in ("null", "nullptr") or self.t(value).strip() in ("NULL", "nullptr", "0")) \
                and ("*" in full_t or "Ptr" in full_t or "ptr" in full_t):
            ir = None   # a null pointer: the handle it will point to is set later
        elif value is not None:
            ir = self.ir(value)
            if value.type in ("new_expression",) or (value.type == "call_expression" and "make_" in self.t(value)[:60]):
                pass  # walked below (a construction of its own)
        elif _is_nodehandle(tt):
            ir = ["ctor", tt, []]
        else:
            ir = None
            if self.fn is not None and re.match(r"[A-Z]\w*$", tt.split("::")[-1]) and "*" not in full_t and \
                    "&" not in full_t and len(self.f["binits"]) < MAX_RECORDS:
                self.f["binits"].append({"t": tt, "args": [], "nk": []})   # Robot robot;: its defaults
        if self.fn is not None and "::" not in name:
            entry = {"t": full_t, "ir": ir, "d": self.fn.depth}
            if value is not None and value.type == "lambda_expression":
                entry["lt"] = self._lambda_param(value)
            if ir is None and not _is_nodehandle(tt):
                entry["ir"] = ["dyn", name]
            self.fn.locals[name] = entry
        elif ir is not None:
            if "::" in name:  # const std::string Class::NAME = "x";
                self.f["consts"].setdefault(name, ir)
                self.f["consts"].setdefault("::".join(name.split("::")[-2:]), ir)
                self.f["consts"].setdefault(name.split("::")[-1], ir)
            else:
                self._const(name, ir)
        if value is not None and args is None:
            self.walk(value)
        elif args is not None:
            for a in args:
                self.walk(a)

    def _construction(self, tt: str, args, irs, where) -> None:
        if len(self.f["ctors"]) >= MAX_RECORDS:
            return
        self.f["ctors"].append({"t": " ".join(tt.split()), "args": irs, "nodeish": [self.nodeish(a) for a in args],
                                "nk": [self.nodekind(a) for a in args],
                                "texts": [self.t(a)[:200] for a in args], "pos": self.pos(where),
                                "npos": [self.pos(a) for a in args], "ns": list(self.ns), "cls": self.cur_cls,
                                "fn": self.fn.name if self.fn else None})

    def v_new_expression(self, n) -> None:
        typ = n.child_by_field_name("type")
        args = n.child_by_field_name("arguments")
        if typ is not None:
            argn = list(args.named_children) if args is not None else []
            self._construction(self.t(typ), argn, [self.ir(a) for a in argn], n)
        if args is not None:
            self.walk(args)

    def v_lambda_expression(self, n) -> None:
        if self.fn is None:
            self.fn = _Fn("<lambda>", self.cur_cls, {})
            body = n.child_by_field_name("body")
            if body is not None:
                self.walk(body)
            self.fn = None
            return
        self.fn.depth += 1
        body = n.child_by_field_name("body")
        if body is not None:
            self.walk(body)
        self.fn.depth -= 1

    def _lambda_param(self, lam) -> Optional[str]:
        d = lam.child_by_field_name("declarator")
        if d is None:
            return None
        plist = d.child_by_field_name("parameters")
        if plist is None:
            return None
        for p in plist.named_children:
            if p.type in ("parameter_declaration", "optional_parameter_declaration"):
                return self._decl_type(p, p.child_by_field_name("type"), p.child_by_field_name("declarator"))
        return None

    # ------------------------------------------------------------ assignments
    def v_assignment_expression(self, n) -> None:
        left = n.child_by_field_name("left")
        right = n.child_by_field_name("right")
        op = n.child_by_field_name("operator")
        if left is None or right is None:
            return
        ir = self.ir(right)
        if op is not None and self.t(op) == "+=":
            ir = ["cat", [self.ir(left), ir]]
        self.assign(left, ir)
        self.walk(right)

    def assign(self, left, ir) -> None:
        lt = left.type
        if ir and ir[0] == "param":
            ir = ir[:3] + [self.t(left).replace("this->", "")[:80]]
        if lt == "identifier":
            name = self.t(left)
            fn = self.fn
            if fn is not None and name in fn.locals:
                loc = fn.locals[name]
                if fn.depth > loc.get("d", 0) or loc.get("set", False) and fn.depth:
                    loc["ir"] = ["dyn", name]
                else:
                    loc["ir"] = ir
                loc["set"] = True
                return
            if fn is not None and name in fn.params:
                return
            cls = self.cur_cls
            if cls:
                self.f["members"].setdefault(cls, {}).setdefault(name, []).append(ir)
            elif fn is not None and len(self.f["gsets"]) < MAX_RECORDS:
                self.f["gsets"].append([name, ir])   # a global set in a function: g_nh = new ros::NodeHandle()
        elif lt == "field_expression":
            arg = left.child_by_field_name("argument")
            field = left.child_by_field_name("field")
            if arg is not None and field is not None and self.t(arg) == "this" and self.cur_cls:
                self.f["members"].setdefault(self.cur_cls, {}).setdefault(self.t(field), []).append(ir)
            elif arg is not None and field is not None and arg.type == "identifier" and self.fn is not None \
                    and self.t(arg) in self.fn.locals and self.t(left)[len(self.t(arg)):].lstrip().startswith("."):
                # desc.name = "min_neighbors"; declare_parameter(desc.name, ...): a local struct's field
                key = f"{self.t(arg)}.{self.t(field)}"
                fn = self.fn
                loc = fn.locals.get(key)
                if loc is None:
                    fn.locals[key] = {"t": None, "ir": ir, "d": fn.depth, "set": True}
                elif fn.depth > loc.get("d", 0) or fn.depth:
                    loc["ir"] = ["dyn", key]
                else:
                    loc["ir"] = ir

    # ------------------------------------------------------------ expressions
    def ir(self, n, depth: int = 0):
        if depth > 40:
            return ["dyn", self.t(n)[:200]]
        more = self.juxt.get(n.start_byte)
        if more and n.type in ("identifier", "string_literal", "qualified_identifier"):
            head = self.juxt.pop(n.start_byte)
            try:
                return ["cat", [self.ir(n, depth + 1)] + [self.ir(c, depth + 1) for c in head]]
            finally:
                self.juxt[n.start_byte] = head
        ty = n.type
        if ty == "string_literal":
            return ["s", _string_value(self, n)]
        if ty == "raw_string_literal":
            c = next((ch for ch in n.named_children if ch.type == "raw_string_content"), None)
            return ["s", self.t(c) if c is not None else ""]
        if ty == "user_defined_literal":
            c = next((ch for ch in n.named_children if ch.type in ("string_literal", "raw_string_literal")), None)
            return self.ir(c, depth + 1) if c is not None else ["dyn", self.t(n)]
        if ty == "concatenated_string":
            return ["cat", [self.ir(ch, depth + 1) for ch in n.named_children]]
        if ty in ("parenthesized_expression", "cast_expression", "pointer_expression", "reference_expression"):
            inner = n.child_by_field_name("value") or n.child_by_field_name("argument")
            if inner is None:
                kids = n.named_children
                inner = kids[-1] if kids else None
            return self.ir(inner, depth + 1) if inner is not None else ["dyn", self.t(n)]
        if ty in ("identifier", "type_identifier"):
            return self.ident(self.t(n))
        if ty == "qualified_identifier" and any(c.type == "::" and c.start_byte == c.end_byte for c in n.children):
            # PREFIX_S NAME_S: two string macros side by side, read with a missing "::"
            return ["cat", [["id", self.t(c), self.cur_cls, list(self.ns)] if c.type == "namespace_identifier"
                            else self.ir(c, depth + 1) for c in n.named_children]]
        if ty == "qualified_identifier":
            return ["id", self.t(n).replace(" ", "").lstrip(":"), self.cur_cls, list(self.ns)]
        if ty == "field_expression":
            arg = n.child_by_field_name("argument")
            field = n.child_by_field_name("field")
            if arg is not None and field is not None and self.t(arg) == "this":
                return ["mem", self.cur_cls, self.t(field)]
            if arg is not None and field is not None and arg.type == "identifier" and self.fn is not None:
                loc = self.fn.locals.get(f"{self.t(arg)}.{self.t(field)}")
                if loc is not None and loc["ir"] is not None and self.t(n)[len(self.t(arg)):].lstrip()[:1] == ".":
                    return loc["ir"]
            return ["dyn", self.t(n)]
        if ty == "binary_expression":
            op = n.child_by_field_name("operator")
            if op is not None and self.t(op) == "+":
                return ["cat", [self.ir(n.child_by_field_name("left"), depth + 1),
                                self.ir(n.child_by_field_name("right"), depth + 1)]]
            return ["dyn", self.t(n)]
        if ty == "initializer_list":
            kids = n.named_children
            return self.ir(kids[0], depth + 1) if kids else ["s", ""]
        if ty == "call_expression":
            return self.call_ir(n, depth)
        if ty == "this":
            return ["dyn", "this"]
        if ty in ("number_literal", "true", "false"):
            vt = self.value_type(n)
            return ["lit", vt, self.t(n)] if vt else ["dyn", self.t(n)]
        return ["dyn", self.t(n)[:200]]

    def ident(self, name: str):
        fn = self.fn
        if fn is not None:
            loc = fn.locals.get(name)
            if loc is not None:
                return loc["ir"] if loc["ir"] is not None else ["dyn", name]
            p = fn.params.get(name)
            if p is not None:
                return ["arg", fn.cls, fn.name, p[0], name, p[1], p[2]] if p[2] is not None else \
                    ["arg", fn.cls, fn.name, p[0], name, p[1]]
        return ["id", name, self.cur_cls, list(self.ns)]

    def call_ir(self, n, depth: int):
        fnode = n.child_by_field_name("function")
        args = n.child_by_field_name("arguments")
        argn = self.arglist(args)
        recv, m, targs, prefix = _callee(self, fnode)
        if m in ("string", "basic_string", "string_view", "QString", "String") and prefix in ("std", "", None, "ros"):
            return self.ir(argn[0], depth + 1) if argn else ["s", ""]
        if (m == "getName" and prefix == "ros::this_node") or \
                (m == "get_fully_qualified_name" and (recv is None or self.t(recv) == "this")):
            return ["node"]
        if m in ("resolve_topic_or_service_name", "resolveName", "resolve_name", "remap_name",
                 "expand_topic_or_service_name") and argn:
            # the name as the node resolves it (absolute): the same graph name used alone, but
            # its namespace is not known inside a longer name
            return ["resolved", self.ir(argn[0], depth + 1), self.t(n)[:200]]
        if m == "clean" and argn:
            return self.ir(argn[0], depth + 1)
        if m == "create" and prefix and prefix.split("::")[-1] in ("SubscribeOptions", "AdvertiseOptions",
                                                                  "AdvertiseServiceOptions") and argn:
            # ros::SubscribeOptions::create<T>("topic", ...): n.subscribe(ops) uses its topic and type
            return ["opts", self.ir(argn[0], depth + 1), [self.t(x) for x in targs], self.t(n)[:200]]
        if m in ("getNodeHandle", "getMTNodeHandle", "get_node_handle"):
            return ["nh", ["s", ""]]
        if m in ("getPrivateNodeHandle", "getMTPrivateNodeHandle"):
            return ["nh", ["s", "~"]]
        if m == "NodeHandle":
            irs = [self.ir(a, depth + 1) for a in argn]
            if argn and self.nodeish(argn[0]):
                irs[0] = ["nhref", irs[0]]
            return ["ctor", "ros::NodeHandle", irs]
        if m in ("c_str", "as_string", "get_value", "value", "data", "str", "toStdString", "string") and recv is not None \
                and not argn:
            if m == "str" and recv.type != "call_expression":
                return ["dyn", self.t(n)[:200]]
            return self.ir(recv, depth + 1)
        if m in apis.PARAM_VALUE_CALLS and argn:
            name_i = 1 if m in apis.NODE_FIRST or (len(argn) > 1 and self.nodeish(argn[0])
                                                    and argn[0].type != "string_literal") else 0
            if len(argn) > name_i:
                d = None
                if m in ("param", "declare_parameter", "get_parameter_or", "declare_parameter_if_not_declared") \
                        and len(argn) > name_i + 1:
                    d = self.ir(argn[-1], depth + 1)
                    if d[0] == "ctor" and d[2]:
                        d = d[2][0]
                return ["param", self.ir(argn[name_i], depth + 1), d, self.t(n)[:200]]
        return ["dyn", self.t(n)[:200]]

    def nodeish(self, a) -> bool:
        """Whether an argument is a node (handle) rather than a name."""
        t = self.t(a).strip()
        if a.type in ("this",) or t in ("this", "*this", "shared_from_this()", "this->shared_from_this()"):
            return True
        if a.type == "string_literal" or a.type == "concatenated_string":
            return False
        if a.type == "call_expression":
            return bool(re.search(r"(shared_from_this|get_node_\w+_interface|getNodeHandle|getPrivateNodeHandle|"
                                  r"getMTNodeHandle|getMTPrivateNodeHandle|NodeHandle|lock|get_node|node)\s*\(", t)
                        or re.search(r"pointer_cast\s*<[^>]*Node[^>]*>|\b(node|parent|nh)\w*\s*(\.|->)\s*lock\s*\(", t, re.I))
        if a.type in ("pointer_expression", "field_expression", "identifier", "qualified_identifier", "type_identifier"):
            name = t.lstrip("*&").split("->")[-1].split(".")[-1]
            fn = self.fn
            if fn is not None:
                loc = fn.locals.get(name)
                if loc is not None:
                    if _is_nodeish_type(loc["t"]):
                        return True
                    if "auto" in (loc["t"] or "") or not loc["t"]:
                        init = str(loc.get("ir"))
                        return bool(re.search(r"shared_from_this|[Nn]ode|NodeHandle|lock\(", init)) or \
                            bool(_NODEISH.match(name))
                    return False
                p = fn.params.get(name)
                if p is not None:
                    return _is_nodeish_type(p[1]) or bool(_NODEISH.match(name)) and "string" not in p[1]
            return bool(_NODEISH.match(name))
        return False

    def nodekind(self, a) -> Optional[bool]:
        return _nodekind(self, a)

    def arglist(self, args) -> list:
        """The arguments of a call; ``f(PREFIX_S NAME_S, 1)`` (two string macros side by side, which
        tree-sitter reads as an argument and an error) is one argument, their concatenation."""
        if args is None:
            return []
        out = []
        for ch in args.named_children:
            if ch.type == "ERROR" and out and ch.named_children and \
                    all(c.type in ("identifier", "string_literal", "qualified_identifier") for c in ch.named_children) \
                    and b"," not in self.src[out[-1].end_byte:ch.start_byte]:
                self.juxt.setdefault(out[-1].start_byte, []).extend(ch.named_children)
                continue
            if ch.type != "comment":
                out.append(ch)
        return out

    # ------------------------------------------------------------ calls
    def v_call_expression(self, n) -> None:
        fnode = n.child_by_field_name("function")
        args = n.child_by_field_name("arguments")
        argn = self.arglist(args)
        recv, m, targs, prefix = _callee(self, fnode)
        if m == "reset" and recv is not None and len(argn) == 1 and argn[0].type == "new_expression":
            typ = argn[0].child_by_field_name("type")
            args2 = argn[0].child_by_field_name("arguments")
            a2 = list(args2.named_children) if args2 is not None else []
            irs = [self.ir(a) for a in a2]
            if typ is not None and "NodeHandle" in self.t(typ) and a2 and self.nodeish(a2[0]):
                irs[0] = ["nhref", irs[0]]
            self.assign(recv, ["ctor", self.t(typ) if typ is not None else None, irs])
        if m in _C_STRING_WRITERS and recv is None and argn and argn[0].type == "identifier":
            # sprintf(buf, "joint%u_name", i): buf is what the format makes of the arguments
            self.assign(argn[0], _format_ir(self, m, argn))
        if m in _AS_TYPE and recv is not None and recv.type == "call_expression":
            self.hints[recv.start_byte] = _AS_TYPE[m]
        if m in apis.PARAM_METHODS and recv is not None and self._param_client(recv):
            m = None  # a parameters client: another node's parameters
        if m in ("set_parameter", "set_parameters", "set_parameters_atomically") and argn and \
                len(self.f["calls"]) < MAX_CALLS:
            self._set_parameters(n, fnode, argn[0])
        if m is not None:
            spec = apis.cpp_spec(m, prefix, len(argn))
            if spec is not None and len(self.f["calls"]) < MAX_CALLS:
                self._call_site(n, fnode, recv, m, targs, prefix, argn, spec)
            if m in apis.OUT_PARAM_CALLS and argn:
                k = apis.OUT_PARAM_CALLS[m]
                name_i = 0
                if len(argn) > k:
                    self.assign(argn[k], ["param", self.ir(argn[name_i]), self.ir(argn[k + 1]) if len(argn) > k + 1
                                          else None, self.t(n)[:200]])
            if m in ("make_shared", "make_unique", "allocate_shared") and targs:
                self._construction(self.t(targs[0]), argn, [self.ir(a) for a in argn], n)
            elif argn and len(self.f["fcalls"]) < MAX_RECORDS and m not in apis.NOT_USER_FUNCS:
                irs = [self.ir(a) for a in argn]
                if any(x[0] not in ("dyn",) for x in irs):
                    self.f["fcalls"].append(_fcall(self, m, recv, prefix, argn, irs))
        if fnode is not None and fnode.type in ("field_expression",):
            a = fnode.child_by_field_name("argument")
            if a is not None:
                self.walk(a)
        for a in argn:
            self.walk(a)

    def _call_site(self, n, fnode, recv, m, targs, prefix, argn, spec) -> None:
        name_i = spec["name"]
        if m == "subscribe" and len(argn) > 1 and argn[0].type != "string_literal" and (
                self.nodeish(argn[0]) or argn[1].type in ("string_literal", "concatenated_string", "raw_string_literal")):
            name_i = 1  # message_filters::Subscriber::subscribe(nh, topic, queue)
            spec = dict(spec, api="message_filters", cb=None, ros=0, nharg=True)
        if spec.get("skip_nodes"):
            while name_i < len(argn) - 1 and self.nodeish(argn[name_i]):
                name_i += 1
            if spec.get("type_after_name"):
                spec = dict(spec, type_arg=name_i + 1)
            if spec.get("value_after_name"):
                spec = dict(spec, value=name_i + 1)
        if name_i >= len(argn):
            return
        name_node = argn[name_i]
        opts = self.ir(name_node) if len(argn) == 1 and spec["api"] == "roscpp" else None
        if opts is not None and opts[0] == "opts":
            # n.subscribe(ops) / n.advertise(ops): the topic and type of the options
            targs = targs or []
            call = {"m": m, "api": spec["api"], "kind": spec["kind"], "ros": 1, "name": opts[1],
                    "expr": self.t(name_node)[:200], "npos": self.pos(name_node), "pos": self._mpos(n, fnode),
                    "cls": self.cur_cls, "fn": self.fn.name if self.fn else None, "ns": list(self.ns),
                    "ctx": spec.get("ctx", "msg"), "prefix": prefix or "", "targs": opts[2]}
            if recv is not None:
                call["recv"] = self.recv_ir(recv)
            self.f["calls"].append(call)
            return
        call = {"m": m, "api": spec["api"], "kind": spec["kind"], "ros": spec.get("ros", 0),
                "name": self.ir(name_node), "expr": self.t(name_node)[:200], "npos": self.pos(name_node),
                "pos": self._mpos(n, fnode), "cls": self.cur_cls, "fn": self.fn.name if self.fn else None,
                "ns": list(self.ns), "ctx": spec.get("ctx", "msg"), "prefix": prefix or ""}
        if recv is not None:
            call["recv"] = self.recv_ir(recv)
        elif spec["api"] in ("roscpp",) and prefix in ("ros::param", "ros::service"):
            call["recv"] = {"ir": ["nh", ["s", ""]], "t": "ros::NodeHandle", "free": True}
        if targs:
            call["targs"] = [self.t(x) for x in targs]
        ti = spec.get("type_arg")
        if ti is not None and ti < len(argn):
            call["tval"] = self.type_ir(argn[ti])
        cbi = spec.get("cb")
        if cbi is not None and cbi < len(argn):
            call["cb"] = self.cb_ir(argn[cbi])
            if cbi + 1 < len(argn) and spec["kind"] == "subscribe":
                call["cbobj"] = self.t(argn[cbi + 1])[:80]
        vi = spec.get("value")
        if vi is not None and vi < len(argn):
            call["vtype"] = self.value_type(argn[vi])
        if m in apis.DEFAULT_AT and len(argn) > name_i + 1 and (m != "declare_parameter" or name_i == 0):
            di = len(argn) - 1 if apis.DEFAULT_AT[m] == "last" else name_i + 1
            call["default"] = self.t(argn[di])[:120]
            if not call.get("vtype"):
                call["vtype"] = self.value_type(argn[di])
            elif call["vtype"].startswith("@") and di != vi:
                call["dtype"] = self.value_type(argn[di])   # when the variable's type is not found
        if spec["kind"].startswith("param") and not call.get("vtype") and n.start_byte in self.hints:
            call["vtype"] = self.hints[n.start_byte]
        if spec.get("nharg"):
            call["nharg"] = self.recv_ir(argn[0].child_by_field_name("argument") or argn[0]
                                         if argn[0].type == "pointer_expression" else argn[0])
        if spec.get("fixed"):
            call["fixed"] = spec["fixed"]
        if spec.get("camera"):
            call["camera"] = True
        tv = spec.get("tvar")
        if tv is not None and tv < len(argn) and not targs:
            vt = self.var_type(argn[tv])
            if vt:
                call["targs"] = [vt]
        self.f["calls"].append(call)

    def _param_client(self, recv) -> bool:
        """Whether a receiver is a parameters client (``SyncParametersClient``...)."""
        t = self.t(recv)
        if _CLIENT.search(t):
            return True
        fn = self.fn
        if recv.type == "identifier" and fn is not None and t in fn.locals:
            loc = fn.locals[t]
            return bool(re.search(r"ParametersClient", (loc.get("t") or "") + " " + str(loc.get("ir"))))
        return False

    def _set_parameters(self, n, fnode, arg) -> None:
        """``set_parameter(rclcpp::Parameter("name", value))`` and ``set_parameters({...})``."""
        items = list(arg.named_children) if arg.type == "initializer_list" else [arg]
        if arg.type == "initializer_list" and items and items[0].type in ("string_literal", "concatenated_string"):
            items = [arg]   # set_parameter({"name", value}): one Parameter, braced
        for it in items[:64]:
            if it.type == "initializer_list":
                args = list(it.named_children)
                if not args or args[0].type not in ("string_literal", "concatenated_string", "identifier"):
                    continue
            else:
                if it.type != "call_expression":
                    continue
                f2 = it.child_by_field_name("function")
                a2 = it.child_by_field_name("arguments")
                if f2 is None or a2 is None or not self.t(f2).replace(" ", "").endswith("Parameter"):
                    continue
                args = list(a2.named_children)
            if not args:
                continue
            call = {"m": "set_parameter", "api": "rclcpp", "kind": "param_write", "ros": 2,
                    "name": self.ir(args[0]), "expr": self.t(args[0])[:200], "npos": self.pos(args[0]),
                    "pos": self._mpos(n, fnode), "cls": self.cur_cls, "fn": self.fn.name if self.fn else None,
                    "ns": list(self.ns), "ctx": "msg", "prefix": ""}
            if len(args) > 1:
                call["vtype"] = self.value_type(args[1])
            self.f["calls"].append(call)

    def _mpos(self, call, fnode) -> list:
        """The call's position: from its method name (where a reader looks for it) to its end."""
        name = fnode
        if fnode is not None:
            if fnode.type == "field_expression":
                name = fnode.child_by_field_name("field")
            elif fnode.type == "qualified_identifier":
                name = fnode.child_by_field_name("name") or fnode
        s = (name or call).start_point
        e = call.end_point
        return [s[0] + 1, self.col(s[0], s[1]), e[0] + 1, self.col(e[0], e[1])]

    def recv_ir(self, recv) -> dict:
        t = None
        text = self.t(recv)
        if recv.type == "identifier":
            fn = self.fn
            name = text
            if fn is not None and name in fn.locals:
                loc = fn.locals[name]
                return {"ir": loc["ir"], "t": loc["t"], "text": text}
            if fn is not None and name in fn.params:
                idx, ty = fn.params[name][:2]
                return {"ir": ["arg", fn.cls, fn.name, idx, name, ty], "t": ty, "text": text}
            return {"ir": ["id", name, self.cur_cls, list(self.ns)], "t": t, "text": text}
        if recv.type == "field_expression":
            arg = recv.child_by_field_name("argument")
            field = recv.child_by_field_name("field")
            if arg is not None and field is not None and self.t(arg) == "this":
                return {"ir": ["mem", self.cur_cls, self.t(field)], "t": None, "text": text}
        if recv.type == "pointer_expression":
            inner = recv.child_by_field_name("argument")
            if inner is not None:
                return self.recv_ir(inner)
        if recv.type == "parenthesized_expression" and recv.named_children:
            return self.recv_ir(recv.named_children[0])
        return {"ir": self.ir(recv), "t": t, "text": text}

    def var_type(self, a) -> Optional[str]:
        t = self.t(a).strip()
        fn = self.fn
        if fn is not None and t in fn.locals:
            return fn.locals[t]["t"]
        if fn is not None and t in fn.params:
            return fn.params[t][1]
        return None

    def type_ir(self, a) -> list:
        """A type passed as a value (a generic publisher's "std_msgs/msg/String")."""
        return self.ir(a)

    def value_type(self, a) -> Optional[str]:
        return _value_type(self, a)

    def cb_ir(self, a):
        ty = a.type
        t = self.t(a).strip()
        if ty == "lambda_expression":
            return ["lt", self._lambda_param(a), list(self.ns), self.cur_cls]
        if ty == "pointer_expression":
            inner = a.child_by_field_name("argument")
            if inner is not None:
                return ["fn", self.t(inner).replace(" ", "").lstrip(":"), self.cur_cls, list(self.ns)]
        if ty in ("identifier", "qualified_identifier"):
            fn = self.fn
            if fn is not None and t in fn.locals:
                loc = fn.locals[t]
                if loc.get("lt"):
                    return ["lt", loc["lt"], list(self.ns), self.cur_cls]
                ft = _function_type_param(loc.get("t") or "")
                if ft:
                    return ["lt", ft, list(self.ns), self.cur_cls]
                return None
            return ["fn", t.replace(" ", "").lstrip(":"), self.cur_cls, list(self.ns)]
        if ty == "call_expression":
            fnode = a.child_by_field_name("function")
            args = a.child_by_field_name("arguments")
            ft = self.t(fnode).replace(" ", "") if fnode is not None else ""
            argn = list(args.named_children) if args is not None else []
            if ft.split("::")[-1] == "bind" and argn:
                target = self.cb_ir(argn[0])
                rest = argn[1:]
                if rest and not _PLACEHOLDER.match(self.t(rest[0]).replace(" ", "")) and \
                        target and target[0] == "fn" and ("::" in target[1] or self.t(rest[0]).strip() in ("this", "*this")):
                    rest = rest[1:]
                for i, r in enumerate(rest):
                    pm = _PLACEHOLDER.match(self.t(r).replace(" ", ""))
                    if pm and pm.group(1) == "1":
                        return ["bind", target, i]
                return None
            if ft.startswith(("std::function", "boost::function")):
                return self.cb_ir(argn[0]) if argn else None
        if ty == "field_expression":
            field = a.child_by_field_name("field")
            arg = a.child_by_field_name("argument")
            if field is not None and arg is not None and self.t(arg) == "this":
                return ["memcb", self.cur_cls, self.t(field)]
        return None


def cpp_facts(src: bytes) -> dict:
    """The facts of one C++ source (never raises on bad input)."""
    return treesit.facts("cpp", _Walker, src)
