"""Document symbols (the feature tree; the launch structure), folding ranges and semantic
tokens for TVL."""

from __future__ import annotations

import bisect
import re

from lsprotocol import types

from ..convert import to_lsp_range
from ...base.text import LineIndex, Span, to_encoding
from ...tvl import model as M
from ...project import facts as F
from ...project.facts import MODEL_KINDS

TOKEN_TYPES = ["keyword", "class", "property", "variable", "number", "string", "comment",
               "operator", "enumMember", "type"]
TOKEN_MODIFIERS = ["declaration", "readonly"]
LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=TOKEN_MODIFIERS)


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    async def document_symbol(ls, params: types.DocumentSymbolParams):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind is None:
            return None
        parsed = await ls.parsed(doc.path)
        if doc.kind in MODEL_KINDS:
            model = getattr(parsed, "model", None)
            return tvl_symbols(model, doc.path, doc.index, ls.encoding) if model else []
        return launch_symbols(parsed, doc.path, doc.index, ls.encoding) if parsed is not None else []

    @ls.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
    async def folding_range(ls, params: types.FoldingRangeParams):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind is None:
            return None
        if doc.kind in MODEL_KINDS:
            parsed = await ls.parsed(doc.path)
            return tvl_folding(getattr(parsed, "model", None), doc.path, doc.text)
        return launch_folding(doc.text)

    @ls.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, LEGEND)
    async def semantic_tokens(ls, params: types.SemanticTokensParams):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind != "tvl":
            return types.SemanticTokens(data=[])
        parsed = await ls.parsed(doc.path)
        return types.SemanticTokens(data=tvl_semantic_tokens(doc.text, getattr(parsed, "model", None),
                                                             doc.path, ls.encoding))


# ------------------------------------------------------------------ symbols

def _sym(name, detail, kind, rng, sel, children=None):
    return types.DocumentSymbol(name=name or "?", detail=detail, kind=kind, range=rng,
                                selection_range=sel, children=children or None)


def _range(index, span, enc, sel=None):
    rng = to_lsp_range(index, span, enc)
    s = to_lsp_range(index, sel, enc) if sel is not None else rng
    # the selection range must be inside the range
    if (s.start.line, s.start.character) < (rng.start.line, rng.start.character) or \
            (s.end.line, s.end.character) > (rng.end.line, rng.end.character):
        s = rng
    return rng, s


def tvl_symbols(model: M.Model, path: str, index: LineIndex, enc: str):
    def feat(f: M.Feature, depth=0):
        kids = []
        for a in f.attributes:
            if a.path == path:
                rng, sel = _range(index, a.span, enc, a.name_span)
                kids.append(_sym(a.name, a.type, types.SymbolKind.Field, rng, sel))
        if depth < 200:
            for g in f.groups:
                for c in g.children:
                    if c.feature.parent is f and c.feature.path == path:
                        kids.append(feat(c.feature, depth + 1))
        rng, sel = _range(index, f.span, enc, f.name_span)
        detail = ("opt" if f.optional else "") + "".join(f" group {F.group_text(g)}" for g in f.groups)
        return _sym(f.name, detail.strip() or None, types.SymbolKind.Class, rng, sel, kids)

    out = []
    for t in model.types:
        if t.path == path:
            rng, sel = _range(index, t.span, enc, t.name_span)
            out.append(_sym(t.name, t.base, types.SymbolKind.TypeParameter, rng, sel))
    for c in model.constants:
        if c.path == path:
            rng, sel = _range(index, c.span, enc, c.name_span)
            out.append(_sym(c.name, c.type, types.SymbolKind.Constant, rng, sel))
    if model.root is not None and model.root.path == path:
        out.append(feat(model.root))
    return out


def launch_symbols(analysis, path: str, index: LineIndex, enc: str):
    els = F.own_elements(analysis, path) if hasattr(analysis, "elements") else []
    own = set(map(id, els))
    kinds = {"node": types.SymbolKind.Object, "include": types.SymbolKind.Module,
             "arg": types.SymbolKind.Variable, "param": types.SymbolKind.Property,
             "rosparam": types.SymbolKind.Property, "group": types.SymbolKind.Namespace,
             "remap": types.SymbolKind.Key, "env": types.SymbolKind.Variable,
             "launch": types.SymbolKind.File, "test": types.SymbolKind.Event,
             "machine": types.SymbolKind.Struct}

    def make(e, depth=0):
        a = e.attrs
        label = a["name"].value if "name" in a else a["file"].value if "file" in a else \
            a["ns"].value if "ns" in a else a["from"].value if "from" in a else ""
        name = f"<{e.tag}> {label}".strip()
        cond = str(e.condition)
        detail = None if cond == "true" else f"if {cond}"
        kids = [make(c, depth + 1) for c in e.children if id(c) in own and depth < 100]
        rng, sel = _range(index, e.span, enc, e.tag_span)
        return _sym(name, detail, kinds.get(e.tag, types.SymbolKind.Object), rng, sel, kids)

    tops = [e for e in els if e.parent is None or id(e.parent) not in own]
    return [make(e) for e in tops]


# ------------------------------------------------------------------ folding

def tvl_folding(model, path: str, text: str):
    out = []
    seen = set()

    def add(span: Span, kind=None):
        if span.end.line > span.start.line and (span.start.line, span.end.line) not in seen:
            seen.add((span.start.line, span.end.line))
            out.append(types.FoldingRange(start_line=span.start.line, end_line=span.end.line, kind=kind))
    if model is not None:
        for f in model.features:
            if f.path == path:
                add(f.span)
            for g in f.groups:
                if g.path == path:
                    add(g.span)
        for t in model.types:
            if t.path == path:
                add(t.span)
    index = LineIndex(text)
    for m in re.finditer(r"/\*.*?\*/", text, re.S):
        add(index.span(m.start(), m.end()), types.FoldingRangeKind.Comment)
    return sorted(out, key=lambda r: (r.start_line, r.end_line))


_TAG = re.compile(r"<!--.*?-->|<(/?)([\w\-]+)(?:[^<>\"']|\"[^\"]*\"|'[^']*')*?(/?)>", re.S)


_NAME = re.compile(r"[\w\-]+")
_SPECIAL = re.compile(r"[<>\"']")


def xml_tags(text: str):
    """``(start, end, close, tag, selfclose)`` of each comment (tag None) and tag of ``text``,
    as :data:`_TAG`'s ``finditer`` finds them, in linear time: the regex rescans a quoted
    value or an unclosed comment from every ``<`` before it (a 50,000-character line of
    broken tags: 7 s of folding on the event loop, found by bench/bench_server_fuzz.py)."""
    specials = [m.start() for m in _SPECIAL.finditer(text)]
    quotes = {q: [i for i in specials if text[i] == q] for q in "\"'"}
    comment_ends = True  # False once a "<!--" has no "-->" after it: no later one has
    i, n = text.find("<"), len(text)
    while 0 <= i < n:
        if text.startswith("<!--", i):
            e = text.find("-->", i + 4) if comment_ends else -1
            if e >= 0:
                yield i, e + 3, "", None, ""
                i = text.find("<", e + 3)
                continue
            comment_ends = False
        close = "/" if text.startswith("/", i + 1) else ""
        m = _NAME.match(text, i + 1 + len(close))
        end = None
        if m:
            k = bisect.bisect_left(specials, m.end())
            while k < len(specials):
                j = specials[k]
                c = text[j]
                if c == "<":
                    break
                if c == ">":
                    end = j + 1
                    break
                qs = quotes[c]
                q = bisect.bisect_right(qs, j)
                if q >= len(qs):
                    break
                k = bisect.bisect_right(specials, qs[q])
        if end is not None:
            selfclose = "/" if end - 2 >= m.end() and text[end - 2] == "/" else ""
            yield i, end, close, m.group(0), selfclose
            i = text.find("<", end)
        else:
            i = text.find("<", i + 1)


def launch_folding(text: str):
    index = LineIndex(text)
    out = []
    stack = []
    for start, end, close, tag, selfclose in xml_tags(text):
        if tag is None:
            s = index.span(start, end)
            if s.end.line > s.start.line:
                out.append(types.FoldingRange(start_line=s.start.line, end_line=s.end.line,
                                              kind=types.FoldingRangeKind.Comment))
            continue
        if close:
            while stack:
                t, opened = stack.pop()
                if t == tag:
                    a, b = index.pos(opened).line, index.pos(start).line
                    if b > a:
                        out.append(types.FoldingRange(start_line=a, end_line=b))
                    break
        elif not selfclose:
            stack.append((tag, start))
        else:
            s = index.span(start, end)
            if s.end.line > s.start.line:
                out.append(types.FoldingRange(start_line=s.start.line, end_line=s.end.line))
    return sorted(out, key=lambda r: (r.start_line, r.end_line))


# ------------------------------------------------------------------ semantic tokens

_KW_TYPES = {"BOOL", "INTK", "REALK", "ENUM", "STRUCT"}
_OPS = set("&|-<>!=+*/?:")


def tvl_semantic_tokens(text: str, model, path: str, enc: str) -> list[int]:
    from ...tvl.lexer import KEYWORDS, tokenize
    toks, _ = tokenize(text)
    index = LineIndex(text)
    features, attrs, consts, typenames, enums = set(), set(), set(), set(), set()
    decl_offsets = set()
    if model is not None:
        for f in model.features:
            features.add(f.name)
            for p, s in f.decl_spans or [(f.path, f.name_span)]:
                if p == path:
                    decl_offsets.add(index.offset(s.start))
            for a in f.attributes:
                attrs.add(a.name)
                if a.path == path:
                    decl_offsets.add(index.offset(a.name_span.start))
                for ev in a.enum_values:
                    enums.add(ev.name)
        consts = {c.name for c in model.constants}
        typenames = {t.name for t in model.types}
        for t in model.types:
            for ev in t.enum_values:
                enums.add(ev.name)
    spans: list[tuple[int, int, int, int]] = []  # start, end, type, modifiers

    kw = set(KEYWORDS)
    prev_end = 0

    def comments(a: int, b: int):
        gap = text[a:b]
        for m in re.finditer(r"//[^\r\n]*|/\*.*?(?:\*/|$)", gap, re.S):
            spans.append((a + m.start(), a + m.end(), 6, 0))

    for t in toks:
        if t.start > prev_end:
            comments(prev_end, t.start)
        prev_end = max(prev_end, t.end)
        v = t.value
        if re.fullmatch(r"-?[0-9]+(\.[0-9]+)?", v):
            spans.append((t.start, t.end, 4, 0))
        elif v.startswith('"'):
            spans.append((t.start, t.end, 5, 0))
        elif v in kw:
            spans.append((t.start, t.end, 9 if KEYWORDS[v] in _KW_TYPES else 0, 0))
        elif re.fullmatch(r"[^\W\d][\w$]*", v):
            mod = 1 if t.start in decl_offsets else 0
            if v in features:
                spans.append((t.start, t.end, 1, mod))
            elif v in attrs:
                spans.append((t.start, t.end, 2, mod))
            elif v in consts:
                spans.append((t.start, t.end, 3, 2))
            elif v in typenames:
                spans.append((t.start, t.end, 9, 0))
            elif v in enums:
                spans.append((t.start, t.end, 8, 0))
        elif v and all(ch in _OPS for ch in v):
            spans.append((t.start, t.end, 7, 0))
    if prev_end < len(text):
        comments(prev_end, len(text))
    spans.sort()
    data: list[int] = []
    last_line = last_col = 0
    for a, b, ty, mod in spans:
        # split multi-line tokens (block comments) per line
        pa, pb = index.pos(a), index.pos(b)
        for line in range(pa.line, pb.line + 1):
            lt = index.line_text(line)
            c0 = pa.col if line == pa.line else 0
            c1 = pb.col if line == pb.line else len(lt)
            if c1 <= c0:
                continue
            s = to_encoding(lt, c0, enc)
            e = to_encoding(lt, c1, enc)
            dl = line - last_line
            dc = s - last_col if dl == 0 else s
            data.extend([dl, dc, e - s, ty, mod])
            last_line, last_col = line, s
    return data
