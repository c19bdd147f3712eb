"""ROS 2 launch frontends: XML (``launch_xml``) and YAML (``launch_yaml``) files as entities with
exact source ranges.

An :class:`Entity` answers the questions launch's frontend ``Entity`` answers (``get_attr``
with launch's type handling, sub-entity lists, ``children``, "was everything read?") so that
:mod:`.actions` can mirror launch's ``parse`` methods one by one; it also knows where every
attribute, value and tag is in the source.  XML goes through the secure parser of
:mod:`tvl_lsp.launch.xml` (no entities, no DTD, no network); YAML through PyYAML's safe
composer.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

import yaml
from ...base import yamlsafe
from . import coerce as C

from ...base.diagnostics import Diagnostic, Severity
from ...base.text import LineIndex, Span
from ..model import Attr, Element, Subst
from ..xml import MAX_TEXT, XML_SYNTAX, XML_TOO_LARGE, XElement, parse_xml
from . import subst as S

LIST = "list-of-entities"   # get_attr(name, data_type=LIST): launch's List[Entity]


class FrontendError(Exception):
    """What launch raises while reading an entity (TypeError, AttributeError, ValueError,
    RuntimeError): ``kind`` is the exception class name, ``span`` where it is."""

    def __init__(self, kind: str, message: str, span: Span):
        super().__init__(message)
        self.kind = kind
        self.span = span


@dataclass
class RAttr:
    """One attribute (XML) or scalar key (YAML) of an entity."""
    name: str
    value: Any                 # XML: str; YAML: the typed value PyYAML gives
    name_span: Span
    value_span: Span
    _offsets: Optional[list[int]] = None   # decoded index -> raw offset (None: value_start + i)
    _start: int = 0
    _exact: bool = True
    _index: Optional[LineIndex] = None

    def span_of(self, i: int, j: int) -> Span:
        """The source range of characters i..j of the (decoded) string value."""
        idx = self._index
        if idx is None or not self._exact:
            return self.value_span
        if self._offsets is not None:
            offs = self._offsets
            i = min(max(i, 0), len(offs) - 1)
            j = min(max(j, 0), len(offs) - 1)
            return idx.span(offs[i], offs[j])
        return idx.span(self._start + i, self._start + j)


# ------------------------------------------------------------------ type handling (launch's)

def _yaml_scalar(text: str):
    try:
        return yamlsafe.safe_load(text)
    except Exception:
        raise ValueError(text)


def valid_value(value, can_be_str: bool) -> bool:
    """launch's is_instance_of_valid_type."""
    return C.valid_value(value, can_be_str)


def coerce(value, data_type, can_be_str: bool = True):
    """launch's get_typed_value (coerce_to_type; a list, from an attribute with a ``-sep``,
    item by item) for the data types frontends ask for: ValueError where launch raises one."""
    if isinstance(value, list):
        if data_type is not None and not isinstance(data_type, C.ListOf):
            raise ValueError(f"Cannot convert input '{value}' of type '{type(value)}' to '{_type_name(data_type)}'")
        item = data_type.item if isinstance(data_type, C.ListOf) else None
        out = [C.coerce(x, item, can_be_str=can_be_str) for x in value]
        if not C.valid_value(out, can_be_str):
            raise ValueError(f"cannot convert value to {item}. Got value=`{value}`")
        return out
    return C.coerce(value, data_type, can_be_str=can_be_str)


def _type_name(t) -> str:
    return C.type_text(t)


# ------------------------------------------------------------------ entities

class Entity:
    """One launch entity (an XML element / a YAML mapping entry), launch_xml's and
    launch_yaml's ``Entity`` with positions."""

    def __init__(self, kind: str, tag: str, path: str, span: Span, tag_span: Span,
                 attrs: dict[str, RAttr], parent: Optional["Entity"] = None):
        self.kind = kind              # "xml" | "yaml"
        self.tag = tag
        self.path = path
        self.span = span
        self.tag_span = tag_span
        self.attrs = attrs
        self.parent = parent
        self.text = ""
        # XML: child elements in order; YAML: computed on demand
        self._xchildren: list[Entity] = []
        # YAML: the raw python value (dict / list / scalar) and, for dicts, key -> list of entities
        self._yvalue: Any = None
        self._ylists: dict[str, list[Entity]] = {}
        self._ychildren: Optional[list[Entity]] = None
        self._yorder: list[Entity] = []   # every sub-entity in document order (for elements)
        self._read: set[str] = set()
        self._read_children: set[str] = set()
        self._children_called = False

    def __repr__(self) -> str:
        return f"Entity(<{self.tag}> {self.span.start})"

    # -- launch's Entity API
    def get_attr(self, name: str, data_type=str, optional: bool = False, can_be_str: bool = True):
        if self.kind == "xml":
            return self._xml_get(name, data_type, optional, can_be_str)
        return self._yaml_get(name, data_type, optional, can_be_str)

    def _xml_get(self, name, data_type, optional, can_be_str):
        if data_type == LIST:
            found = [c for c in self._xchildren if c.tag == name]
            if not found:
                if optional:
                    return None
                raise FrontendError("AttributeError", f"Attribute '{name}' of type 'typing.List[launch.frontend."
                                    f"entity.Entity]' not found in Entity '{self.tag}'", self.tag_span)
            self._read_children.add(name)
            return found
        a = self.attrs.get(name)
        if a is None:
            if optional:
                return None
            raise FrontendError("AttributeError", f"Attribute '{name}' of type '{_type_name(data_type)}' not found "
                                f"in Entity '{self.tag}'", self.tag_span)
        self._read.add(name)
        value = a.value
        if name + "-sep" in self.attrs:  # launch_xml splits the value into a list
            self._read.add(name + "-sep")
            value = a.value.split(self.attrs[name + "-sep"].value) if self.attrs[name + "-sep"].value else [a.value]
        try:
            return coerce(value, data_type, can_be_str)
        except ValueError:
            raise FrontendError("TypeError", f"Attribute '{name}' of Entity '{self.tag}' expected to be of type "
                                f"'{_type_name(data_type)}'.'{a.value}' can not be converted to one of those types",
                                a.value_span)

    def _yaml_get(self, name, data_type, optional, can_be_str):
        if not isinstance(self._yvalue, dict) or name not in self._yvalue:
            if optional:
                return None
            raise FrontendError("AttributeError", f"Can not find attribute '{name}' in Entity '{self.tag}'",
                                self.tag_span)
        self._read.add(name)
        data = self._yvalue[name]
        a = self.attrs.get(name)
        where = a.value_span if a is not None else self.tag_span
        if data_type == LIST:
            if isinstance(data, list) and data and isinstance(data[0], dict):
                return self._ylists.get(name, [])
            raise FrontendError("TypeError", f"Attribute '{name}' of Entity '{self.tag}' expected to be a list of "
                                "dictionaries.", where)
        ok = C.is_instance_of(data, data_type, can_be_str)
        if data_type is float and isinstance(data, bool):
            ok = can_be_str and False
        if not ok:
            raise FrontendError("TypeError", f"Attribute '{name}' of Entity '{self.tag}' expected to be of type "
                                f"'{_type_name(data_type)}', got '{type(data)}'", where)
        return data

    def children(self) -> list["Entity"]:
        """launch's ``entity.children`` (XML: every child element; YAML: ``children:`` or the
        list itself)."""
        if self.kind == "xml":
            self._read_children = {c.tag for c in self._xchildren}
            return list(self._xchildren)
        self._children_called = True
        v = self._yvalue
        if not isinstance(v, (dict, list)):
            raise FrontendError("TypeError", f"Expected a dict or list, got {type(v)}:\n---\n{v}\n---", self.tag_span)
        if isinstance(v, dict):
            if "children" not in v:
                raise FrontendError("ValueError", f"Expected entity `{self.tag}` to have children entities.That can "
                                    "be a list of subentities or a dictionary with a `children` list element",
                                    self.tag_span)
            self._read.add("children")
        if self._ychildren is None:
            raise FrontendError("RuntimeError", "Subentities must be a dictionary with only one key, which is the "
                                "entity type", self.tag_span)
        return list(self._ychildren)

    def assert_parsed(self) -> None:
        """launch's ``assert_entity_completely_parsed``."""
        if self.kind == "xml":
            extra = {c.tag for c in self._xchildren} - self._read_children
            if extra:
                first = next(c for c in self._xchildren if c.tag in extra)
                raise FrontendError("ValueError", f"Unexpected nested tag(s) found in `{self.tag}`: {_set(extra)}",
                                    first.tag_span)
            extra = set(self.attrs) - self._read
            if extra:
                first = next(a for k, a in self.attrs.items() if k in extra)
                raise FrontendError("ValueError", f"Unexpected attribute(s) found in `{self.tag}`: {_set(extra)}",
                                    first.name_span)
            return
        v = self._yvalue
        if isinstance(v, list):
            if not self._children_called:
                raise FrontendError("ValueError", f"Unexpected nested entity(ies) found in `{self.tag}`: {v}",
                                    self.tag_span)
            return
        if isinstance(v, dict):
            extra = set(v) - self._read
            if extra:
                a = next((self.attrs[k] for k in v if k in extra and k in self.attrs), None)
                raise FrontendError("ValueError", f"Unexpected key(s) found in `{self.tag}`: {_set(extra)}",
                                    a.name_span if a else self.tag_span)

    def unread_attrs(self) -> list[RAttr]:
        return [a for k, a in self.attrs.items() if k not in self._read]

    # -- positions
    def attr(self, name: str) -> Optional[RAttr]:
        return self.attrs.get(name)

    def aspan(self, name: str) -> Span:
        a = self.attrs.get(name)
        return a.value_span if a is not None else self.tag_span

    def sub_entities(self) -> list["Entity"]:
        """Every sub-entity in document order (for the element model)."""
        return list(self._xchildren) if self.kind == "xml" else list(self._yorder)


def _set(names: set[str]) -> str:
    return "{" + ", ".join(repr(n) for n in names) + "}"


# ------------------------------------------------------------------ XML

@dataclass
class Document:
    path: str
    text: str
    index: LineIndex
    root: Optional[Entity]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    error: Optional[tuple[str, str, Span]] = None   # (kind, message, span): the file does not load
    kind: str = "xml"


def _xml_entity(x: XElement, path: str, idx: LineIndex, parent: Optional[Entity]) -> Entity:
    attrs = {}
    for k, a in x.attrs.items():
        exact = True
        if a.value_offsets is None and idx.offset(a.value_span.end) - a.value_start != len(a.value):
            exact = False
        attrs[k] = RAttr(k, a.value, a.name_span, a.value_span, a.value_offsets, a.value_start, exact, idx)
    e = Entity("xml", x.tag, path, x.span, x.tag_span or x.span, attrs, parent)
    e.text = x.text
    e._xchildren = [_xml_entity(c, path, idx, e) for c in x.children]
    return e


def _ros2_message(msg: str) -> str:
    return msg.replace("Invalid roslaunch XML syntax", "Invalid launch XML syntax").replace(
        "roslaunch files do not need them", "launch files do not need them")


def parse_xml_launch(text: str, path: str) -> Document:
    doc = parse_xml(text, path)
    diags = [Diagnostic(d.code, d.severity, d.path, d.span, _ros2_message(d.message), d.related)
             for d in doc.diagnostics]
    root = _xml_entity(doc.root, path, doc.index, None) if doc.root is not None else None
    out = Document(path, text, doc.index, root, diags, kind="xml")
    errs = [d for d in diags if d.severity == Severity.ERROR]
    if errs:
        out.error = ("ParseError", errs[0].message, errs[0].span)
    elif root is None:
        out.error = ("ParseError", "the file is not XML", doc.index.span(0, 0))
    return out


# ------------------------------------------------------------------ YAML

_YAML_SYNTAX = XML_SYNTAX  # the code of a file that is not well-formed (XML or YAML)


def _mark_offset(idx: LineIndex, mark) -> int:
    return min(getattr(mark, "index", 0), len(idx.text))


def _scalar_attr(name: str, key_node, node, idx: LineIndex, text: str, loader) -> RAttr:
    ks, ke = _mark_offset(idx, key_node.start_mark), _mark_offset(idx, key_node.end_mark)
    name_span = idx.span(ks, ke)
    value = _construct(node, loader)
    vs, ve = _mark_offset(idx, node.start_mark), _mark_offset(idx, node.end_mark)
    exact = False
    start = vs
    if isinstance(node, yaml.ScalarNode):
        style = node.style
        if style in ("'", '"'):
            start, ve2 = vs + 1, ve - 1
            raw = text[start:ve2]
            exact = raw == node.value
            ve = ve2
        elif style is None:
            raw = text[vs:ve]
            exact = raw == node.value
        else:
            # block scalars: the value starts on the next line
            exact = False
    return RAttr(name, value, name_span, idx.span(start, ve), None, start, exact, idx)


def _construct(node, loader):
    try:
        return loader.construct_object(node, deep=True)
    except Exception:
        return getattr(node, "value", None)


def _yaml_entity(tag: str, key_node, node, path: str, idx: LineIndex, text: str, loader,
                 parent: Optional[Entity], depth: int = 0) -> Entity:
    ks = _mark_offset(idx, key_node.start_mark) if key_node is not None else _mark_offset(idx, node.start_mark)
    ke = _mark_offset(idx, key_node.end_mark) if key_node is not None else ks
    tag_span = idx.span(ks, ke)
    e = Entity("yaml", tag, path, tag_span, tag_span, {}, parent)
    e._yvalue = _construct(node, loader)
    if depth > 60:
        return e
    if isinstance(node, yaml.MappingNode):
        seen: dict[str, Any] = {}
        for k, v in node.value:
            if not isinstance(k, yaml.ScalarNode):
                continue
            name = k.value
            seen[name] = (k, v)
        for name, (k, v) in seen.items():
            if isinstance(v, yaml.SequenceNode) and v.value and all(isinstance(c, yaml.MappingNode) for c in v.value):
                if name == "children":
                    kids = _yaml_children(v, path, idx, text, loader, e, depth)
                    e._ychildren = kids
                    e._yorder.extend(x for x in kids or [] if x is not None)
                else:
                    lst = [_yaml_entity(name, k, c, path, idx, text, loader, e, depth + 1) for c in v.value]
                    e._ylists[name] = lst
                    e._yorder.extend(lst)
                # a list is also an attribute (for spans of type errors)
                e.attrs[name] = RAttr(name, e._yvalue.get(name) if isinstance(e._yvalue, dict) else None,
                                      idx.span(_mark_offset(idx, k.start_mark), _mark_offset(idx, k.end_mark)),
                                      idx.span(_mark_offset(idx, v.start_mark), _mark_offset(idx, v.end_mark)),
                                      None, 0, False, idx)
            else:
                e.attrs[name] = _scalar_attr(name, k, v, idx, text, loader)
    elif isinstance(node, yaml.SequenceNode):
        kids = _yaml_children(node, path, idx, text, loader, e, depth)
        e._ychildren = kids
        e._yorder.extend(x for x in kids or [] if x is not None)
    return e


def _yaml_children(seq, path, idx, text, loader, parent, depth):
    out = []
    for item in seq.value:
        if not isinstance(item, yaml.MappingNode) or len(item.value) != 1:
            return None  # launch: "Subentities must be a dictionary with only one key"
        k, v = item.value[0]
        name = k.value if isinstance(k, yaml.ScalarNode) else str(k)
        out.append(_yaml_entity(name, k, v, path, idx, text, loader, parent, depth + 1))
    return out


def parse_yaml_launch(text: str, path: str) -> Document:
    idx = LineIndex(text)
    out = Document(path, text, idx, None, [], kind="yaml")
    if len(text) > MAX_TEXT:
        msg = f"the file has {len(text):,} characters; tvl-lsp analyses launch files of at most {MAX_TEXT:,} characters"
        out.diagnostics.append(Diagnostic(XML_TOO_LARGE, Severity.ERROR, path, idx.span(0, 0), msg))
        out.error = ("ParseError", msg, idx.span(0, 0))
        return out
    try:
        node = yamlsafe.compose(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        off = _mark_offset(idx, mark) if mark is not None else 0
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        msg = f"Invalid launch YAML syntax: {problem}"
        span = idx.span(off, min(off + 1, len(text)))
        out.diagnostics.append(Diagnostic(_YAML_SYNTAX, Severity.ERROR, path, span, msg))
        out.error = ("ParseError", msg, span)
        return out
    except Exception as exc:  # recursion and the like: never crash on bad input
        msg = f"Invalid launch YAML: {exc}"
        out.diagnostics.append(Diagnostic(_YAML_SYNTAX, Severity.ERROR, path, idx.span(0, 0), msg))
        out.error = ("ParseError", msg, idx.span(0, 0))
        return out
    loader = yaml.SafeLoader("")
    if node is None or not isinstance(node, yaml.MappingNode) or len(node.value) != 1:
        span = idx.span(0, min(len(text), len(idx.line_text(0))))
        if node is None:
            msg = "the file is empty: a YAML launch file is `launch:` followed by a list of actions"
        elif not isinstance(node, yaml.MappingNode):
            msg = "a YAML launch file is a mapping with the single key `launch`"
        else:
            msg = "Expected only one root"
        out.diagnostics.append(Diagnostic("no-launch-root", Severity.ERROR, path, span, msg))
        out.error = ("RuntimeError", msg, span)
        return out
    k, v = node.value[0]
    name = k.value if isinstance(k, yaml.ScalarNode) else str(k)
    out.root = _yaml_entity(name, k, v, path, idx, text, loader, None)
    return out


def is_yaml_path(path: str) -> bool:
    return path.endswith((".yaml", ".yml"))


def parse_launch_file(text: str, path: str) -> Document:
    """An XML or YAML launch file (by its name, as launch picks the parser first)."""
    if is_yaml_path(path):
        return parse_yaml_launch(text, path)
    return parse_xml_launch(text, path)


# ------------------------------------------------------------------ the shared element model

def substitutions_of(e: Entity) -> list[Subst]:
    if e.kind == "py":
        return list(getattr(e, "substs", []))  # the Python front end lists them itself
    out: list[Subst] = []
    for k, a in e.attrs.items():
        if not isinstance(a.value, str) or "$(" not in a.value:
            continue
        try:
            parts = S.parse(a.value)
        except S.SubstSyntaxError:
            continue
        for sub in S.walk(parts):
            out.append(Subst(sub.name, tuple(S.plain(x) for x in sub.args), a.span_of(sub.start, sub.end), k))
    return out


def make_elements(e: Entity, path: str, parent: Optional[Element], depth: int, emap: dict, sink: list) -> Element:
    """Elements for an entity tree (one per include site); ``emap`` maps id(entity) to its element."""
    attrs = {}
    for k, a in e.attrs.items():
        v = a.value
        if isinstance(v, bool):
            v = "true" if v else "false"
        elif isinstance(v, (int, float)):
            v = str(v)
        elif not isinstance(v, str):
            continue  # sub-entity lists and other structures
        attrs[k] = Attr(k, v, a.name_span, a.value_span)
    from ...base.formula import FALSE
    el = Element(e.tag, e.span, attrs, path, FALSE, parent, [], substitutions_of(e), e.tag_span, e.text, depth)
    emap[id(e)] = el
    sink.append(el)
    for c in e.sub_entities():
        el.children.append(make_elements(c, path, el, depth, emap, sink))
    return el

