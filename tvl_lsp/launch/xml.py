"""Secure XML parsing of roslaunch files with exact source ranges.

lxml checks well-formedness (entities are never resolved, no DTD is loaded, nothing touches
the network, huge trees are refused); a small scanner over the raw text finds the exact
position of every start tag, attribute name and attribute value, and the two are matched in
document order.  Columns are code points (see :mod:`tvl_lsp.base.text`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from lxml import etree

from ..base.diagnostics import Diagnostic, Severity, register
from ..base.text import LineIndex, Pos, Span

XML_SYNTAX = register("xml-syntax", Severity.ERROR, "The file is not well-formed XML.", "launch")
XML_ENTITY = register("xml-entity-declaration", Severity.ERROR,
                      "The file declares XML entities (refused: entities are never expanded).", "launch")
XML_TOO_LARGE = register("launch-file-too-large", Severity.ERROR,
                         "The file is too large to analyse.", "launch")
XML_TOO_DEEP = register("launch-too-deep", Severity.ERROR,
                        "Elements are nested too deeply to analyse.", "launch")

MAX_TEXT = 2_000_000       # characters (the biggest real launch files have ~20,000; the front ends
                           # spend a few microseconds per character of a value: YAML, shlex, $(...))
MAX_DEPTH = 100            # element nesting analysed
MAX_ELEMENTS = 10_000      # elements analysed (real launch files have hundreds at most)
MAX_ATTRIBUTES = 1_000     # attributes read per element (roslaunch's tags take a dozen at most;
                           # lxml lists an element's attributes in quadratic time: 40,000 take 6 s)


@dataclass
class XAttr:
    name: str
    value: str
    name_span: Span
    value_span: Span          # inside the quotes
    value_offsets: list[int] | None = None  # decoded index -> raw offset (None: identity from value start)
    value_start: int = 0      # raw offset of the first character inside the quotes


@dataclass
class XElement:
    tag: str
    span: Span                     # the start tag, '<' to '>'
    attrs: dict[str, XAttr]
    children: list["XElement"] = field(default_factory=list)
    text: str = ""                 # direct text and CDATA children, concatenated
    line: int = 0
    tag_span: Span | None = None   # the tag name inside the start tag
    content_start: int = -1        # raw offset just after the start tag (-1: unknown)


@dataclass
class XmlDoc:
    path: str
    text: str
    index: LineIndex
    root: XElement | None
    diagnostics: list[Diagnostic]
    refused: bool = False          # entity declarations: nothing analysed


# ---------------------------------------------------------------- raw scanner

_NAME = re.compile(r"[^\s/>=<\"']+")
_WS = re.compile(r"\s*")
_ENTITY_REF = re.compile(r"&(#x[0-9A-Fa-f]+|#[0-9]+|[A-Za-z_][\w.-]*);")
_PREDEF = {"lt": "<", "gt": ">", "amp": "&", "quot": '"', "apos": "'"}


@dataclass
class _RawTag:
    name: str
    start: int
    end: int
    name_start: int
    attrs: list[tuple[str, int, int, int, int]]  # name, name_start, name_end, vstart, vend


def _scan(text: str) -> list[_RawTag]:
    """Start tags in document order (comments, CDATA, PIs and DOCTYPE skipped)."""
    out: list[_RawTag] = []
    i = 0
    n = len(text)
    find = text.find
    while True:
        i = find("<", i)
        if i < 0 or i + 1 >= n:
            break
        c = text[i + 1]
        if text.startswith("<!--", i):
            j = find("-->", i + 4)
            i = n if j < 0 else j + 3
            continue
        if text.startswith("<![CDATA[", i):
            j = find("]]>", i + 9)
            i = n if j < 0 else j + 3
            continue
        if c == "?":
            j = find("?>", i + 2)
            i = n if j < 0 else j + 2
            continue
        if c == "!":
            # DOCTYPE, possibly with an internal subset [...]
            j = i + 2
            depth = 0
            while j < n:
                ch = text[j]
                if ch == "[":
                    depth += 1
                elif ch == "]":
                    depth -= 1
                elif ch == ">" and depth <= 0:
                    break
                elif ch in "\"'":
                    k = find(ch, j + 1)
                    j = n if k < 0 else k
                j += 1
            i = j + 1
            continue
        if c == "/":
            j = find(">", i + 2)
            i = n if j < 0 else j + 1
            continue
        m = _NAME.match(text, i + 1)
        if not m:
            i += 1
            continue
        tag = _RawTag(m.group(0), i, i, m.start(), [])
        j = m.end()
        while j < n:
            j = _WS.match(text, j).end()
            if j >= n:
                break
            ch = text[j]
            if ch == ">":
                j += 1
                break
            if ch == "/" and j + 1 < n and text[j + 1] == ">":
                j += 2
                break
            am = _NAME.match(text, j)
            if not am:
                if ch == "<":
                    break  # malformed: a new tag starts
                j += 1
                continue
            aname, ns, ne = am.group(0), am.start(), am.end()
            j = _WS.match(text, ne).end()
            if j < n and text[j] == "=":
                j = _WS.match(text, j + 1).end()
                if j < n and text[j] in "\"'":
                    q = text[j]
                    k = find(q, j + 1)
                    if k < 0:
                        k = n
                    tag.attrs.append((aname, ns, ne, j + 1, k))
                    j = k + 1
                    continue
            tag.attrs.append((aname, ns, ne, ne, ne))
        tag.end = min(j, n)
        out.append(tag)
        i = max(tag.end, i + 1)
    return out


def _decode(raw: str, start: int) -> tuple[str, list[int] | None]:
    """Decode entity references and normalise whitespace as XML does for attribute values.

    Returns the value and, when it differs in length from the raw text, the raw offset of
    every decoded character (plus one past the end)."""
    if "&" not in raw and "\r" not in raw:
        return raw.replace("\n", " ").replace("\t", " "), None
    chars: list[str] = []
    offs: list[int] = []
    i = 0
    n = len(raw)
    while i < n:
        ch = raw[i]
        if ch == "&":
            m = _ENTITY_REF.match(raw, i)
            if m:
                ref = m.group(1)
                if ref.startswith("#x"):
                    val = chr(int(ref[2:], 16)) if int(ref[2:], 16) < 0x110000 else "?"
                elif ref.startswith("#"):
                    val = chr(int(ref[1:])) if int(ref[1:]) < 0x110000 else "?"
                else:
                    val = _PREDEF.get(ref, m.group(0))
                for v in val:
                    chars.append(v)
                    offs.append(start + i)
                i = m.end()
                continue
        if ch == "\r":
            if i + 1 < n and raw[i + 1] == "\n":
                i += 1
            ch = " "
        elif ch in "\n\t":
            ch = " "
        chars.append(ch)
        offs.append(start + i)
        i += 1
    offs.append(start + n)
    return "".join(chars), offs


# ---------------------------------------------------------------- lxml

def _parser(recover: bool) -> etree.XMLParser:
    return etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False,
                           huge_tree=False, recover=recover, remove_comments=False,
                           remove_pis=False, dtd_validation=False, attribute_defaults=False)


_ENTITY_DECL = re.compile(r"<!ENTITY", re.I)


def _lxml_pos(index: LineIndex, line: int, col: int) -> int:
    """lxml's 1-based line and (byte) column to a text offset."""
    line = max(line - 1, 0)
    lt = index.line_text(line)
    col = max(col - 1, 0)
    if not lt.isascii():
        b = lt.encode("utf-8")[:col]
        col = len(b.decode("utf-8", errors="ignore"))
    return index.offset(Pos(line, col))


def parse_xml(text: str, path: str) -> XmlDoc:
    index = LineIndex(text)
    diags: list[Diagnostic] = []
    if len(text) > MAX_TEXT:
        diags.append(Diagnostic(XML_TOO_LARGE, Severity.ERROR, path, index.span(0, 0),
                                f"the file has {len(text):,} characters; tvl-lsp analyses launch files of at most "
                                f"{MAX_TEXT:,} characters"))
        return XmlDoc(path, text, index, None, diags, refused=True)
    m = _ENTITY_DECL.search(text)
    if m:
        diags.append(Diagnostic(XML_ENTITY, Severity.ERROR, path, index.span(m.start(), m.end()),
                                "XML entity declarations are refused: tvl-lsp never expands entities "
                                "(entity bombs, external files); roslaunch files do not need them"))
        return XmlDoc(path, text, index, None, diags, refused=True)
    bad = _bad_character(text)
    if bad is not None:
        (s, e), msg = bad
        diags.append(Diagnostic(XML_SYNTAX, Severity.ERROR, path, index.span(s, e), f"Invalid roslaunch XML syntax: {msg}"))
        return XmlDoc(path, text, index, None, diags)
    data = text.encode("utf-8")
    if text.lstrip().startswith("<?xml"):
        # lxml refuses str input with an encoding declaration; bytes with a utf-8 body are fine
        data = re.sub(rb"encoding\s*=\s*[\"'][^\"']*[\"']", b'encoding="utf-8"', data, count=1)
    root_el = None
    try:
        etree.clear_error_log()
        root_el = etree.fromstring(data, _parser(False))
    except etree.XMLSyntaxError as e:
        line, col = e.position or (e.lineno or 1, 1)
        msg = (e.msg or str(e)).split(", line ")[0]
        off = _lxml_pos(index, line, col)
        diags.append(Diagnostic(XML_SYNTAX, Severity.ERROR, path, index.span(off, off + 1 if off < len(text) else off),
                                f"Invalid roslaunch XML syntax: {msg}"))
        try:
            root_el = etree.fromstring(data, _parser(True))
        except etree.XMLSyntaxError:
            root_el = None
    except ValueError as e:  # e.g. NUL bytes
        diags.append(Diagnostic(XML_SYNTAX, Severity.ERROR, path, index.span(0, 0),
                                f"Invalid roslaunch XML syntax: {e}"))
        root_el = None
    if root_el is None:
        return XmlDoc(path, text, index, None, diags)
    n_el = sum(1 for _ in root_el.iter())
    if n_el > MAX_ELEMENTS:
        diags.append(Diagnostic(XML_TOO_LARGE, Severity.ERROR, path, index.span(0, 0),
                                f"the file has {n_el:,} XML elements; tvl-lsp analyses launch files of at most "
                                f"{MAX_ELEMENTS:,} elements (real ones have hundreds)"))
        return XmlDoc(path, text, index, None, diags, refused=True)
    raw = _scan(text)
    root = _build(root_el, raw, text, index, path, diags)
    return XmlDoc(path, text, index, root, diags)


_SURROGATE = re.compile("[\ud800-\udfff]")
_CHARREF = re.compile(r"&#(x[0-9a-fA-F]+|[0-9]+);")


def _xml_char(cp: int) -> bool:
    """XML 1.0's Char production."""
    return cp in (0x9, 0xA, 0xD) or 0x20 <= cp <= 0xD7FF or 0xE000 <= cp <= 0xFFFD or 0x10000 <= cp <= 0x10FFFF


def _bad_character(text: str):
    """The first character no XML parser accepts: a lone UTF-16 surrogate in the text (an
    editor's buffer can hold one) or a character reference to a code point XML forbids
    (``&#xD800;``, ``&#0;``), as ((start, end), message); None when there is none."""
    m = _SURROGATE.search(text)
    if m is not None:
        return (m.start(), m.end()), f"an unpaired UTF-16 surrogate (U+{ord(m.group()):04X}) is not a character"
    if "&#" in text:
        for m in _CHARREF.finditer(text):
            g = m.group(1)
            cp = int(g[1:], 16) if g[0] == "x" else int(g) if len(g) < 10 else -1
            if not _xml_char(cp):
                return (m.start(), m.end()), f"reference to invalid character number ({m.group()})"
    return None


def _build(root_el, raw: list[_RawTag], text: str, index: LineIndex, path: str,
           diags: list[Diagnostic]) -> XElement | None:
    cursor = 0
    too_deep_reported = False

    def match(tag: str) -> _RawTag | None:
        nonlocal cursor
        # next raw tag with this name (skipping ones lxml dropped in recovery)
        for k in range(cursor, min(cursor + 50, len(raw))):
            if raw[k].name == tag:
                cursor = k + 1
                return raw[k]
        return None

    def make(el, depth: int) -> XElement:
        nonlocal too_deep_reported
        tag = el.tag if isinstance(el.tag, str) else str(el.tag)
        rt = match(tag)
        attrs: dict[str, XAttr] = {}
        if rt is not None:
            span = index.span(rt.start, rt.end)
            tag_span = index.span(rt.name_start, rt.name_start + len(rt.name))
            raw_attrs = {a[0]: a for a in rt.attrs}
        else:
            line = max((el.sourceline or 1) - 1, 0)
            span = Span(index.pos(index.starts[min(line, len(index.starts) - 1)]),
                        index.pos(index.line_end(min(line, len(index.starts) - 1))))
            tag_span = span
            raw_attrs = {}
        n_attrs = len(el.attrib)
        if n_attrs > MAX_ATTRIBUTES:
            diags.append(Diagnostic(XML_TOO_LARGE, Severity.ERROR, path, tag_span,
                                    f"<{tag}> has {n_attrs:,} attributes: tvl-lsp reads the first "
                                    f"{MAX_ATTRIBUTES:,} of an element (roslaunch's tags take a dozen at most)"))
            keys = [a[0] for a in rt.attrs[:MAX_ATTRIBUTES]] if rt is not None else []
            pairs = [(k, v) for k in keys if (v := el.get(k)) is not None]
        else:
            pairs = el.attrib.items()
        for k, v in pairs:
            a = raw_attrs.get(k)
            if a is not None:
                name_span = index.span(a[1], a[2])
                value_span = index.span(a[3], a[4])
                dec, offs = _decode(text[a[3]:a[4]], a[3])
                if dec != v:
                    offs = None  # could not reproduce lxml's value: spans approximate
                attrs[k] = XAttr(k, v, name_span, value_span, offs, a[3])
            else:
                attrs[k] = XAttr(k, v, span, span, None, index.offset(span.start))
        txt = el.text or ""
        x = XElement(tag, span, attrs, [], "", (el.sourceline or 1) - 1, tag_span,
                     rt.end if rt is not None and not text[max(rt.end - 2, 0):rt.end] == "/>" else -1)
        parts = [txt]
        for child in el:
            if isinstance(child.tag, str):
                if depth + 1 > MAX_DEPTH:
                    if not too_deep_reported:
                        too_deep_reported = True
                        cspan = make_span(child)
                        diags.append(Diagnostic(XML_TOO_DEEP, Severity.ERROR, path, cspan,
                                                f"elements are nested more than {MAX_DEPTH} levels deep; "
                                                "the deeper elements are not analysed"))
                else:
                    x.children.append(make(child, depth + 1))
            parts.append(child.tail or "")
        # only text directly inside (tails of children are direct text too)
        x.text = "".join(parts)
        return x

    def make_span(el) -> Span:
        line = max((el.sourceline or 1) - 1, 0)
        line = min(line, len(index.starts) - 1)
        return Span(index.pos(index.starts[line]), index.pos(index.line_end(line)))

    return make(root_el, 0)


def value_span(attr: XAttr, index: LineIndex, i: int, j: int) -> Span:
    """Span of the decoded characters ``attr.value[i:j]`` in the source."""
    if attr.value_offsets is not None:
        offs = attr.value_offsets
        i = min(max(i, 0), len(offs) - 1)
        j = min(max(j, 0), len(offs) - 1)
        return index.span(offs[i], offs[j])
    start = attr.value_start
    if index.offset(attr.value_span.end) - start != len(attr.value):
        return attr.value_span
    return index.span(start + i, start + j)


_TEXT_ENTITY = re.compile(r"&(#x[0-9A-Fa-f]+|#[0-9]+|[A-Za-z_][\w.-]*);")


def text_offsets(doc_text: str, x: XElement) -> list[int] | None:
    """Raw offset of every character of ``x.text`` (plus one past the end), for exact ranges
    inside an element's body (``<rosparam>`` YAML): CDATA sections, character and predefined
    entity references, comments, processing instructions and ``\r\n`` line ends are mapped.
    None when the body has child elements or cannot be mapped exactly."""
    i = x.content_start
    if i < 0:
        return None
    n = len(doc_text)
    chars: list[str] = []
    offs: list[int] = []
    while i < n:
        c = doc_text[i]
        if c == "<":
            if doc_text.startswith("<![CDATA[", i):
                j = doc_text.find("]]>", i + 9)
                if j < 0:
                    return None
                for k in range(i + 9, j):
                    ch = doc_text[k]
                    if ch == "\r":
                        if k + 1 < j and doc_text[k + 1] == "\n":
                            continue
                        ch = "\n"
                    chars.append(ch)
                    offs.append(k)
                i = j + 3
                continue
            if doc_text.startswith("<!--", i):
                j = doc_text.find("-->", i + 4)
                if j < 0:
                    return None
                i = j + 3
                continue
            if doc_text.startswith("<?", i):
                j = doc_text.find("?>", i + 2)
                if j < 0:
                    return None
                i = j + 2
                continue
            if doc_text.startswith("</", i):
                break
            return None  # a child element
        if c == "&":
            m = _TEXT_ENTITY.match(doc_text, i)
            if m is None:
                return None
            ref = m.group(1)
            try:
                if ref.startswith("#x"):
                    val = chr(int(ref[2:], 16))
                elif ref.startswith("#"):
                    val = chr(int(ref[1:]))
                else:
                    val = _PREDEF[ref]
            except (KeyError, ValueError, OverflowError):
                return None
            for v in val:
                chars.append(v)
                offs.append(i)
            i = m.end()
            continue
        if c == "\r":
            if i + 1 < n and doc_text[i + 1] == "\n":
                i += 1
                continue
            c = "\n"
        chars.append(c)
        offs.append(i)
        i += 1
    offs.append(i)
    if "".join(chars) != x.text:
        return None
    return offs


def strip_comments(text: str) -> str:
    """``text`` without its XML comments, in linear time (an unclosed ``<!--`` runs to the
    end, as for a parser; a regular expression would rescan the rest for every ``<!--``)."""
    if "<!--" not in text:
        return text
    out: list[str] = []
    i = 0
    while True:
        j = text.find("<!--", i)
        if j < 0:
            out.append(text[i:])
            break
        out.append(text[i:j])
        k = text.find("-->", j + 4)
        if k < 0:
            break
        i = k + 3
    return "".join(out)


def skip_prolog(text: str) -> str:
    """What follows the XML declaration, processing instructions, comments, a DOCTYPE and
    white space at the start of ``text`` (linear time)."""
    i, n = 0, len(text)
    while i < n:
        while i < n and text[i] in " \t\r\n\ufeff":
            i += 1
        for opener, closer in (("<?", "?>"), ("<!--", "-->"), ("<!DOCTYPE", ">")):
            if text.startswith(opener, i):
                k = text.find(closer, i + len(opener))
                if k < 0:
                    return ""
                i = k + len(closer)
                break
        else:
            return text[i:]
    return ""
