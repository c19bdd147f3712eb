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
