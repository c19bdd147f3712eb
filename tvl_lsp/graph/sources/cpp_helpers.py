"""Small readers of tree-sitter C++ nodes for :mod:`.cpp`: the callee of a call, declarator
names, string literal values, ``#define`` values, and the C++ types of parameters."""

from __future__ import annotations

import re
from typing import Optional

_STRING_TYPES = ("string", "char", "String", "string_view")

def _callee(w, fnode):
    """(receiver node or None, method name, template argument nodes, qualified prefix)"""
    if fnode is None:
        return None, None, [], None
    ty = fnode.type
    if ty == "field_expression":
        recv = fnode.child_by_field_name("argument")
        field = fnode.child_by_field_name("field")
        if field is None:
            return recv, None, [], None
        if field.type == "dependent_name" and field.named_children:  # node->template create_client<T>(...)
            field = field.named_children[0]
        if field.type == "template_method":
            name = field.child_by_field_name("name")
            ta = field.child_by_field_name("arguments")
            return recv, w.t(name) if name is not None else None, _targs(ta), None
        return recv, w.t(field), [], None
    if ty == "identifier":
        return None, w.t(fnode), [], ""
    if ty == "template_function":
        name = fnode.child_by_field_name("name")
        ta = fnode.child_by_field_name("arguments")
        return None, w.t(name) if name is not None else None, _targs(ta), ""
    if ty == "qualified_identifier":
        scope = fnode.child_by_field_name("scope")
        name = fnode.child_by_field_name("name")
        prefix = w.t(scope).replace(" ", "") if scope is not None else ""
        while name is not None and name.type == "qualified_identifier":
            s2 = name.child_by_field_name("scope")
            prefix += "::" + (w.t(s2).replace(" ", "") if s2 is not None else "")
            name = name.child_by_field_name("name")
        if name is None:
            return None, None, [], prefix
        if name.type == "template_function":
            n2 = name.child_by_field_name("name")
            return None, w.t(n2) if n2 is not None else None, _targs(name.child_by_field_name("arguments")), prefix
        return None, w.t(name), [], prefix
    return None, None, [], None


def _targs(ta) -> list:
    if ta is None:
        return []
    return [c for c in ta.named_children if c.type not in ("comment",)]


def _function_declarator(d):
    while d is not None:
        if d.type == "function_declarator":
            return d
        if d.type in ("pointer_declarator", "reference_declarator", "attributed_declarator", "parenthesized_declarator"):
            d = d.child_by_field_name("declarator") or (d.named_children[-1] if d.named_children else None)
            continue
        return None
    return None


def _declarator_name(w, d) -> Optional[str]:
    for _ in range(8):
        if d is None:
            return None
        if d.type in ("identifier", "field_identifier"):
            return w.t(d)
        if d.type == "qualified_identifier":
            return w.t(d).replace(" ", "")
        if d.type in ("pointer_declarator", "reference_declarator", "array_declarator", "init_declarator",
                      "attributed_declarator", "parenthesized_declarator"):
            nxt = d.child_by_field_name("declarator")
            if nxt is None:
                kids = [c for c in d.named_children if c.type in ("identifier", "field_identifier", "qualified_identifier",
                                                                   "pointer_declarator", "reference_declarator",
                                                                   "array_declarator")]
                nxt = kids[0] if kids else None
            d = nxt
            continue
        return None
    return None


def _vexing(fd) -> bool:
    plist = fd.child_by_field_name("parameters")
    if plist is None or not plist.named_children:
        return False
    for p in plist.named_children:
        if p.type != "parameter_declaration" or p.child_by_field_name("declarator") is not None:
            return False
        t = p.child_by_field_name("type")
        if t is None or t.type not in ("type_identifier", "qualified_identifier"):
            return False
    return True


def _string_value(w, n) -> str:
    out = []
    for ch in n.named_children:
        if ch.type == "string_content":
            out.append(w.t(ch))
        elif ch.type == "escape_sequence":
            e = w.t(ch)
            out.append({"\\n": "\n", "\\t": "\t", "\\\\": "\\", '\\"': '"', "\\'": "'"}.get(e, e[1:]))
    return "".join(out)


_DEFINE_STR = re.compile(r'^(?:"(?:[^"\\]|\\.)*"\s*)+$')


def _define_ir(v: str):
    if _DEFINE_STR.match(v):
        return ["s", "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', v))]
    if re.fullmatch(r"[A-Za-z_]\w*", v):
        return ["id", v, None, []] if v not in ("true", "false") else ["lit", "bool", v]
    if re.fullmatch(r"[-+]?(?:0[xX][0-9a-fA-F]+|\d+)[uUlL]*", v):
        return ["lit", "int", v]
    if re.fullmatch(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?[fF]?", v):
        return ["lit", "double", v]
    if re.fullmatch(r'(?:[A-Za-z_]\w*|"(?:[^"\\]|\\.)*")(?:\s+(?:[A-Za-z_]\w*|"(?:[^"\\]|\\.)*"))+', v):
        parts = re.findall(r'[A-Za-z_]\w*|"(?:[^"\\]|\\.)*"', v)
        return ["cat", [["s", p[1:-1]] if p.startswith('"') else ["id", p, None, []] for p in parts]]
    return None


def _is_nodehandle(t: str) -> bool:
    return "NodeHandle" in t and "::Ptr" not in t


def _is_nodeish_type(t: str) -> bool:
    return bool(re.search(r"NodeHandle|rclcpp::Node\b|LifecycleNode|\bNode\b|NodeT|node_interfaces|ImageTransport", t or ""))


def _is_string_type(t: str) -> bool:
    base = t.replace("const", "").replace("&", "").replace("*", "").strip().split("::")[-1]
    return base in _STRING_TYPES


def _ptype(t: Optional[str]) -> Optional[str]:
    """A parameter's type from the C++ type of the variable it is read into."""
    if not t:
        return None
    s = re.sub(r"\b(const|static|constexpr|volatile)\b|[&*]", " ", t).strip()
    s = " ".join(s.split())
    m = re.match(r"(?:std::)?vector\s*<\s*(.+)\s*>$", s)
    if m:
        if m.group(1).strip() in ("uint8_t", "std::uint8_t", "unsigned char", "char"):
            return "byte[]"
        inner = _ptype(m.group(1))
        return inner + "[]" if inner else None
    base = s.split("::")[-1].strip()
    if base in ("double", "float"):
        return "double"
    if base in ("int", "long", "long long", "unsigned", "unsigned int", "unsigned char", "unsigned short",
                "unsigned long", "short", "size_t", "int8_t", "uint8_t",
                "int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t", "long int", "unsigned long",
                "std::size_t"):
        return "int"
    if base == "bool":
        return "bool"
    if base in ("string", "char", "basic_string<char>"):
        return "string"
    return None


def _function_type_param(t: str) -> Optional[str]:
    m = re.search(r"function\s*<\s*[\w:]+\s*\((.*)\)\s*>", t)
    if not m:
        return None
    inner = m.group(1)
    depth = 0
    for i, ch in enumerate(inner):
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
        elif ch == "," and depth == 0:
            return inner[:i].strip()
    return inner.strip() or None


def _nodekind(w, a) -> Optional[bool]:
    """Whether an argument surely is a node (handle) (True), surely is not (False: a literal, a
    variable of another declared type), or cannot be told here (None)."""
    ty = a.type
    t = w.t(a).strip()
    if ty in ("string_literal", "raw_string_literal", "concatenated_string", "number_literal", "true", "false",
              "null", "nullptr", "char_literal", "binary_expression", "initializer_list"):
        return False
    if ty == "this" or t in ("this", "*this", "shared_from_this()", "this->shared_from_this()"):
        return True
    if ty == "call_expression":
        return True if w.nodeish(a) else None
    if ty in ("pointer_expression", "identifier", "type_identifier"):   # (type_identifier: Foo f(a, b);)
        name = t.lstrip("*&").strip()
        fn = w.fn
        if fn is not None and re.fullmatch(r"\w+", name):
            loc = fn.locals.get(name)
            if loc is not None:
                lt = loc["t"] or ""
                if not lt or "auto" in lt:
                    return None
                return _is_nodeish_type(lt)
            p = fn.params.get(name)
            if p is not None and p[1] and "auto" not in p[1] and not re.fullmatch(r"[A-Z]\w*", p[1].strip()):
                return _is_nodeish_type(p[1])   # (a template parameter T: cannot be told)
    return None

def _fcall(w, m, recv, prefix, argn, irs) -> dict:
    """A call of a function of the project's: its arguments, and what tells which function of
    that name it is (the receiver's type, the class it is called from, its qualifier)."""
    rec = {"f": m, "args": irs, "nk": [w.nodekind(a) for a in argn], "c": w.cur_cls}
    if prefix:
        rec["q"] = prefix
    if recv is not None:
        rec["r"] = True
        ri = w.recv_ir(recv)
        if ri.get("t"):
            rec["rt"] = ri["t"]
        elif ri.get("ir") and ri["ir"][0] in ("id", "mem"):
            ir = ri["ir"]
            rec["rm"] = [ir[2], ir[1]] if ir[0] == "id" else [ir[1], ir[2]]
    return rec


_C_STRING_WRITERS = {"sprintf", "snprintf", "strcpy", "strncpy", "strcat", "strncat", "sscanf", "memcpy", "memset",
                     "vsprintf", "vsnprintf", "strftime"}
_CONVERSION = re.compile(r"%[-+ #0]*(?:\d+|\*)?(?:\.(?:\d+|\*))?(?:hh|h|ll|l|j|z|t|L)?([diouxXeEfFgGaAcspn%])")


def _format_ir(w, m: str, argn: list):
    """The value a C string function leaves in its first argument: ``sprintf(buf, "in%02d", i)``
    is ``"in" + {i}``; anything but a printf with a literal format is a run-time value."""
    fi = {"sprintf": 1, "snprintf": 2}.get(m)
    if fi is None or fi >= len(argn) or argn[fi].type not in ("string_literal", "concatenated_string"):
        return ["dyn", w.t(argn[0])]
    fmt = _string_value(w, argn[fi]) if argn[fi].type == "string_literal" else None
    if fmt is None:
        return ["dyn", w.t(argn[0])]
    parts, rest, pos = [], argn[fi + 1:], 0
    for mt in _CONVERSION.finditer(fmt):
        if mt.start() > pos:
            parts.append(["s", fmt[pos:mt.start()]])
        pos = mt.end()
        if mt.group(1) == "%":
            parts.append(["s", "%"])
            continue
        if "*" in mt.group(0) or not rest:
            return ["dyn", w.t(argn[0])]
        a = rest.pop(0)
        ir = w.ir(a)
        parts.append(ir if mt.group(1) == "s" and ir and ir[0] in ("s", "cat") else ["dyn", w.t(a)])
    if pos < len(fmt):
        parts.append(["s", fmt[pos:]])
    return ["cat", parts] if len(parts) != 1 else parts[0]


_MATH_CONST = re.compile(r"\bM_(?:PI|PI_2|PI_4|E|SQRT2|LN2)\b")


def _arith_type(t: str) -> Optional[str]:
    """The type of an arithmetic expression of literals (``M_PI / 180.0``, ``2 * 3``)."""
    u = _MATH_CONST.sub("1.0", t)
    toks = re.findall(r"0[xX][0-9a-fA-F]+[uUlL]*|\d+\.?\d*(?:[eE][-+]?\d+)?[fFuUlL]*|\.\d+(?:[eE][-+]?\d+)?[fF]?"
                      r"|[A-Za-z_]\w*|\S", u)
    if not toks:
        return None
    if any(not (x[0].isdigit() or x[0] == "." or x in "+-*/()") for x in toks):
        # variables beside a floating literal (1.0 / frequency_): double, as C++ converts them; not
        # where a function is called (its return type could be anything)
        floating = any(x[0].isdigit() and ("." in x or "e" in x.lower()) and not x.lower().startswith("0x")
                       or re.fullmatch(r"\.\d.*", x) for x in toks)
        calls = any(re.fullmatch(r"[A-Za-z_]\w*", a) and b == "(" for a, b in zip(toks, toks[1:]))
        if floating and not calls and all(x[0].isdigit() or x[0] in "._" or x[0].isalpha() or x in "+-*/():>"
                                          for x in toks):
            return "double"
        return None
    return "double" if any("." in x or ("e" in x.lower() and not x.lower().startswith("0x")) for x in toks) \
        or "/" in toks else "int"
_PARAM_TYPE_ENUM = re.compile(r"(?:^|::)PARAMETER_(BOOL|INTEGER|DOUBLE|STRING|BYTE_ARRAY|BOOL_ARRAY|INTEGER_ARRAY|"
                              r"DOUBLE_ARRAY|STRING_ARRAY)$")
_PARAM_ENUM_TYPES = {"BOOL": "bool", "INTEGER": "int", "DOUBLE": "double", "STRING": "string", "BYTE_ARRAY": "byte[]",
                     "BOOL_ARRAY": "bool[]", "INTEGER_ARRAY": "int[]", "DOUBLE_ARRAY": "double[]",
                     "STRING_ARRAY": "string[]"}


def _value_type(w, a) -> Optional[str]:
    """The C++ type of a value written in the source (a literal, a variable, a cast...); ``@x``:
    member ``x``'s (known when linking)."""
    ty = a.type
    t = w.t(a).strip()
    if ty == "number_literal":
        return "double" if re.search(r"[.eE]", t) and not t.lower().startswith("0x") else "int"
    if ty in ("true", "false"):
        return "bool"
    if ty in ("string_literal", "raw_string_literal", "concatenated_string"):
        return "string"
    if ty == "unary_expression" and a.named_children and a.named_children[-1].type == "number_literal":
        return w.value_type(a.named_children[-1])
    if ty in ("binary_expression", "parenthesized_expression"):
        return _arith_type(t)
    if ty in ("qualified_identifier", "identifier"):
        pm = _PARAM_TYPE_ENUM.search(t)
        if pm:      # declare_parameter("x", rclcpp::PARAMETER_STRING): a declared type, no value
            return _PARAM_ENUM_TYPES.get(pm.group(1))
    if ty in ("compound_literal_expression",) or (ty == "call_expression" and t.startswith(("std::vector", "vector"))):
        m = re.match(r"(?:std::)?vector\s*<\s*([\w: ]+)\s*>", t)
        if m:
            return _ptype(f"std::vector<{m.group(1)}>")
        if re.match(r"(?:std::)?string\s*[{(]", t):
            return "string"
    if ty == "call_expression":
        fnode = a.child_by_field_name("function")
        ft = w.t(fnode) if fnode is not None else ""
        if ft in ("std::string", "string") or re.search(r"(\.|->)\s*(c_str|str|string)$", ft):
            return "string"
        cm = re.match(r"(?:static_cast|[\w:]*numeric_cast)\s*<\s*([\w: <>]+?)\s*>$", ft.replace("\n", " "))
        if cm:
            return _ptype(cm.group(1))
        if ft.endswith("ParameterValue"):
            args = a.child_by_field_name("arguments")
            if args is not None and args.named_children:
                return w.value_type(args.named_children[0])
        return None
    if ty == "identifier":
        fn = w.fn
        if fn is not None and t in fn.locals:
            return _ptype(fn.locals[t]["t"])
        if fn is not None and t in fn.params:
            return _ptype(fn.params[t][1])
        return "@" + t  # a member: its type is known when linking
    if ty == "field_expression":
        arg = a.child_by_field_name("argument")
        field = a.child_by_field_name("field")
        if arg is not None and field is not None and w.t(arg) == "this":
            return "@" + w.t(field)
        if re.search(r"\.(linear|angular|position|orientation|translation|rotation|point|vector)\.[xyzw]$", t):
            return "double"  # a geometry_msgs field (float64)
        if arg is not None and field is not None and arg.type == "identifier" and \
                w.t(field).isidentifier() and w.t(a)[len(w.t(arg)):].lstrip().startswith("."):
            # settings.rate / config_.rate: the field's type in the struct's declaration
            var = w.t(arg)
            vt = w.var_type(arg)
            return f"@{var}.{w.t(field)}" if vt is None else f"@:{vt}.{w.t(field)}"
    if ty == "initializer_list":
        kids = a.named_children
        if kids:
            inner = w.value_type(kids[0])
            return inner + "[]" if inner and not inner.startswith("@") else None
    return None
