"""Quick fixes for model anomalies, the model side (pure): what a fix changes in a TVL or UVL text,
and which constraints to remove.

    remove_constraint(text, fmt, span) -> new text | None
        The constraint at ``span`` taken out with what keeps the text well-formed and tidy: its
        whole line(s) when it is alone there (a comment after it goes too), else the constraint
        and the blanks after it; in UVL an emptied ``constraints`` section loses its keyword line
        and a ``constraint`` / ``constraints [...]`` attribute loses its comma (and its braces
        when they are left empty).
    make_mandatory(text, fmt, parent, feature) -> (new text, phrase) | None
        An optional feature made mandatory: TVL drops its ``opt`` (in an ``allOf`` group that is
        mandatory; in the other groups the cardinality then counts it, which changes nothing for
        a feature every product with its parent has); UVL moves its subtree from the ``optional``
        group to the parent's ``mandatory`` group (made when there is none, the ``optional``
        keyword renamed when the feature was its only child), re-indented to its new place.
    correction_sets(analysis, extra, path) -> [[constraint Element, ...], ...]
        Sets of constraints whose removal makes the query ``extra`` (literals) satisfiable, each
        minimal: one set per constraint of the query's minimal unsatisfiable subset that is
        enough alone, else (every single removal leaves another reason) one minimal correction
        set per such constraint, grown from a maximal satisfiable subset without it.

:mod:`tvl_lsp.project.fixes` turns these into checked fixes: each applied to the text, the text
checked again, and offered only when it removes its finding and adds none.
"""

from __future__ import annotations

import time
from typing import Optional

from ..base.text import LineIndex, Span
from ..tvl import model as M

MAX_CORRECTION = 8   # constraints one fix may remove (a bigger set is not a quick fix)


_LAST_INDEX: list = [None, None]


def line_index(text: str) -> LineIndex:
    """The :class:`LineIndex` of ``text`` (the last one is kept: callers ask for many spans of
    one text in a row)."""
    if _LAST_INDEX[0] is not text:
        _LAST_INDEX[0], _LAST_INDEX[1] = text, LineIndex(text)
    return _LAST_INDEX[1]


def source_text(text: str, span: Span) -> str:
    """The text at ``span``, blanks collapsed (how titles and finding keys show a constraint)."""
    idx = line_index(text)
    return " ".join(text[idx.offset(span.start):idx.offset(span.end)].split())


def signature(model: M.Model, text_of) -> tuple:
    """What a model says, positions aside: its features (name, parents, groups, attributes) and
    its constraints (owner, kind, text).  Two texts with equal signatures encode the same CNF;
    ``text_of(path)`` gives the text of each file of the model."""
    feats = []
    cons = []
    names: dict[int, str] = {}

    def name(f: M.Feature) -> str:
        n = names.get(id(f))
        if n is None:
            n = names[id(f)] = f.name if f.parent is None else name(f.parent) + "." + f.name
        return n
    for f in model.features:
        groups = tuple((g.kind, g.lo, g.hi, g.keyword, tuple((name(c.feature), c.optional, c.shared)
                                                              for c in g.children)) for g in f.groups)
        attrs = tuple((a.name, a.type, source_text(text_of(a.path), a.span)) for a in f.attributes)
        feats.append((name(f), name(f.parent) if f.parent else None,
                      tuple(name(p) for p in f.shared_parents), groups, attrs,
                      bool(getattr(f, "abstract", False))))
        for c in f.constraints:
            cons.append((c.path, c.span, (name(f), c.kind, source_text(text_of(c.path), c.span))))
    return tuple(feats), cons


def _newline(text: str) -> str:
    return "\r\n" if "\r\n" in text else "\n"


def _lines(text: str) -> list[str]:
    """The lines of ``text`` with their terminators (as :class:`LineIndex` splits them)."""
    starts = LineIndex(text).starts
    out = [text[a:b] for a, b in zip(starts, starts[1:])]
    out.append(text[starts[-1]:])
    if out and out[-1] == "":
        out.pop()
    return out


def _body(line: str) -> str:
    return line.rstrip("\r\n")


def _blank_or_comment(s: str) -> bool:
    s = s.strip()
    return not s or s.startswith("//")


def _uvl_width(ws: str) -> int:
    w = 0
    for c in ws:
        w = w + 8 - (w % 8) if c == "\t" else w + 1
    return w


def _indent(line: str) -> str:
    return line[:len(line) - len(line.lstrip(" \t"))]


# ------------------------------------------------------------------ removing a constraint

def remove_constraint(text: str, fmt: str, span: Span) -> Optional[str]:
    idx = LineIndex(text)
    a, b = idx.offset(span.start), idx.offset(span.end)
    if not 0 <= a < b <= len(text):
        return None
    if fmt == "uvl":
        inline = _uvl_attribute_constraint(text, a, b)
        if inline is not None:
            return inline
    first, last = span.start.line, span.end.line
    ls = idx.starts[first]
    le = idx.line_end(last)
    nxt = idx.starts[last + 1] if last + 1 < idx.line_count else len(text)
    before, after = text[ls:a], text[b:le]
    if not before.strip() and _blank_or_comment(after):
        new = text[:ls] + text[nxt:]
        if nxt == len(text) and ls > 0 and not text.endswith(("\n", "\r")):
            # the last line had no terminator: the one before it now ends the text
            new = new.rstrip("\r\n") if new.endswith(("\n", "\r")) else new
        if fmt == "uvl":
            return _drop_empty_section(new, first, "constraints")
        return _tvl_drop_empty_body(new, ls) if fmt == "tvl" else new
    j = b
    while j < le and text[j] in " \t":
        j += 1
    if j == le:  # last on its line: take the blanks before it instead
        i = a
        while i > ls and text[i - 1] in " \t":
            i -= 1
        new, at = text[:i] + text[b:], i
    else:
        new, at = text[:a] + text[j:], a
    return _tvl_drop_empty_body(new, at) if fmt == "tvl" else new


def _tvl_braces(text: str, stop: int):
    """(offset, char) of every ``{`` and ``}`` of a TVL text before ``stop``, comments and
    strings skipped."""
    i, n = 0, min(stop, len(text))
    while i < n:
        c = text[i]
        if c == "/" and text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j + 1
            continue
        if c == "/" and text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
            continue
        if c == '"':
            j = text.find('"', i + 1)
            i = n if j < 0 else j + 1
            continue
        if c in "{}":
            yield i, c
        i += 1


def _tvl_drop_empty_body(text: str, at: int) -> str:
    """A feature body a removal left empty goes: ``opt X { }`` becomes ``opt X``, a reopened
    ``X { }`` at the top level goes with its lines (the root's braces stay)."""
    stack: list[int] = []
    for i, c in _tvl_braces(text, at):
        if c == "{":
            stack.append(i)
        elif stack:
            stack.pop()
    if not stack:
        return text
    o = stack[-1]
    close = None
    depth = 0
    for i, c in _tvl_braces(text, len(text)):
        if i < o:
            continue
        depth += 1 if c == "{" else -1
        if depth == 0:
            close = i
            break
    if close is None or text[o + 1:close].strip():
        return text
    j = _skip_ws_left(text, o)
    k = j
    while k > 0 and (text[k - 1].isalnum() or text[k - 1] in "_."):
        k -= 1
    if k == j or text[:k].rstrip().endswith("root") or text[:k].rstrip().endswith("group"):
        return text
    if len(stack) > 1:  # a child's body inside a group
        start = o
        while start > 0 and text[start - 1] in " \t":
            start -= 1
        return text[:start] + text[close + 1:]
    idx = LineIndex(text)
    p, q = idx.pos(k), idx.pos(close)
    ls = idx.starts[p.line]
    if text[ls:k].strip() or text[close + 1:idx.line_end(q.line)].strip():
        return text
    end = idx.starts[q.line + 1] if q.line + 1 < idx.line_count else len(text)
    new = text[:ls] + text[end:]
    lines = _lines(new)
    li = p.line
    if 0 < li < len(lines) and not lines[li].strip() and not lines[li - 1].strip():
        del lines[li]  # no double blank line left behind
        new = "".join(lines)
    elif li == len(lines) and lines and not lines[-1].strip():
        del lines[-1]
        new = "".join(lines)
    return new


def _drop_empty_section(text: str, near: int, keyword: str) -> str:
    """Remove the ``keyword`` line of the UVL section above line ``near`` when nothing but
    blanks and comments is left below it."""
    lines = _lines(text)
    k = min(near, len(lines)) - 1
    while k >= 0 and _body(lines[k]).strip() != keyword:
        if not _blank_or_comment(lines[k]) and _uvl_width(_indent(lines[k])) == 0:
            return text  # another section started: not inside one
        k -= 1
    if k < 0:
        return text
    width = _uvl_width(_indent(lines[k]))
    for ln in lines[k + 1:]:
        if _blank_or_comment(ln):
            continue
        if _uvl_width(_indent(ln)) > width:
            return text  # a constraint is left
        break
    del lines[k]
    out = "".join(lines)
    if k == len(lines):  # it was the last section: no blank lines left hanging at the end
        out = out.rstrip(" \t\r\n") + _newline(text) if out.strip() else out
    return out


def _skip_ws_left(text: str, i: int) -> int:
    while i > 0 and text[i - 1] in " \t\r\n":
        i -= 1
    return i


def _skip_ws_right(text: str, i: int) -> int:
    while i < len(text) and text[i] in " \t\r\n":
        i += 1
    return i


def _uvl_attribute_constraint(text: str, a: int, b: int) -> Optional[str]:
    """A constraint written as a UVL attribute (``{constraint X}``, ``{constraints [X, Y]}``)
    taken out with its separator; None when the constraint is not one."""
    i = _skip_ws_left(text, a)
    word = "constraint"
    if text[:i].endswith(word) and (i == len(word) or not (text[i - len(word) - 1].isalnum()
                                                          or text[i - len(word) - 1] == "_")):
        return _remove_item(text, i - len(word), b, "{", "}")
    if i > 0 and text[i - 1] in "[,":
        # an item of ``constraints [ ... ]``: find the list's brackets
        depth = 0
        k = i - 1
        while k >= 0:
            c = text[k]
            if c in ")]}":
                depth += 1
            elif c in "([{":
                if depth == 0:
                    break
                depth -= 1
            k -= 1
        if k < 0 or text[k] != "[":
            return None
        kw = _skip_ws_left(text, k)
        if not text[:kw].endswith("constraints"):
            return None
        close = _matching(text, k, "[", "]")
        if close is None:
            return None
        if not text[k + 1:a].strip(" \t\r\n,") and not text[b:close].strip(" \t\r\n,"):
            # its only item: the whole attribute goes
            return _remove_item(text, kw - len("constraints"), close + 1, "{", "}")
        return _remove_item(text, a, b, "[", "]")
    return None


def _matching(text: str, k: int, op: str, cl: str) -> Optional[int]:
    depth = 0
    for j in range(k, len(text)):
        if text[j] == op:
            depth += 1
        elif text[j] == cl:
            depth -= 1
            if depth == 0:
                return j
    return None


def _remove_item(text: str, s: int, e: int, op: str, cl: str) -> Optional[str]:
    """Remove the list item ``text[s:e]`` with one comma next to it; a list left empty loses its
    brackets (``op`` ... ``cl``) and the blanks before them."""
    left = _skip_ws_left(text, s)
    right = _skip_ws_right(text, e)
    if left > 0 and text[left - 1] == ",":
        return text[:left - 1] + text[e:]
    if right < len(text) and text[right] == ",":
        return text[:s] + text[_skip_ws_right(text, right + 1):]
    if left > 0 and text[left - 1] == op and right < len(text) and text[right] == cl:
        start = left - 1
        while start > 0 and text[start - 1] in " \t":
            start -= 1
        return text[:start] + text[right + 1:]
    return None


# ------------------------------------------------------------------ making a feature mandatory

def make_mandatory(text: str, fmt: str, parent: M.Feature, feature: M.Feature) -> Optional[tuple[str, str]]:
    """(new text, what it does) or None when the model is not written in a way this handles."""
    if fmt == "tvl":
        return _tvl_mandatory(text, parent, feature)
    if fmt == "uvl":
        return _uvl_mandatory(text, parent, feature)
    return None


def _tvl_mandatory(text: str, parent: M.Feature, feature: M.Feature) -> Optional[tuple[str, str]]:
    gc = parent.child_entry(feature)
    g = parent.group_of(feature)
    if gc is None or g is None or not gc.optional:
        return None
    idx = LineIndex(text)
    a = idx.offset(gc.span.start)
    if not text.startswith("opt", a) or a + 3 >= len(text) or text[a + 3] not in " \t\r\n":
        return None
    j = _skip_ws_right(text, a + 3)
    new = text[:a] + text[j:]
    if g.kind == "allOf":
        return new, f"make {feature.name} mandatory (drop `opt`)"
    return new, f"make {feature.name} a plain member of its {g.text} group (drop `opt`)"


def _group_keyword_line(g: M.Group) -> int:
    return g.keyword_span.start.line


def _uvl_mandatory(text: str, parent: M.Feature, feature: M.Feature) -> Optional[tuple[str, str]]:
    g = next((x for x in parent.groups if any(c.feature is feature and c.optional for c in x.children)), None)
    if g is None or g.keyword != "optional":
        return None
    lines = _lines(text)
    nl = _newline(text)
    kw = _group_keyword_line(g)
    s = feature.name_span.start.line
    e = max(s, feature.span.end.line)
    if not (0 <= kw < s <= e < len(lines)) or _body(lines[kw]).split("//")[0].strip() != "optional":
        return None
    sub = list(lines[s:e + 1])
    if not sub[-1].endswith(("\n", "\r")):
        sub[-1] += nl
    others = [c for c in g.children if c.feature is not feature]
    mand = next((x for x in parent.groups if x.keyword == "mandatory" and x.children), None)
    what = f"make {feature.name} mandatory (move it under `mandatory`)"
    if mand is None and not others:
        # its only child: the group becomes mandatory
        line = lines[kw]
        i = line.index("optional")
        lines[kw] = line[:i] + "mandatory" + line[i + len("optional"):]
        return "".join(lines), what
    if mand is None:
        block = [_indent(lines[kw]) + "mandatory" + nl] + sub
        at, drop = kw, set(range(s, e + 1))
    else:
        mkw = _group_keyword_line(mand)
        first = mand.children[0].feature.name_span.start.line
        mend = mand.span.end.line
        if not (0 <= mkw < first <= mend < len(lines)):
            return None
        w_from, w_to = _indent(lines[s]), _indent(lines[first])
        block = []
        for ln in sub:
            if _blank_or_comment(ln) and not ln.strip():
                block.append(ln)
            elif ln.startswith(w_from):
                block.append(w_to + ln[len(w_from):])
            else:
                return None  # mixed tabs and spaces: leave it to the user
        at = mend + 1
        drop = set(range(s, e + 1)) | ({kw} if not others else set())
        if at >= len(lines) and not lines[-1].endswith(("\n", "\r")):
            lines[-1] += nl
    out: list[str] = []
    for i, ln in enumerate(lines):
        if i == at:
            out.extend(block)
        if i not in drop:
            out.append(ln)
    if at >= len(lines):
        out.extend(block)
    new = "".join(out)
    if not text.endswith(("\n", "\r")) and new.endswith(nl):
        new = new[:-len(nl)]
    return new, what


# ------------------------------------------------------------------ a group that cannot be satisfied

def relax_group(text: str, group: M.Group) -> Optional[tuple[str, str]]:
    """A ``[n..m]`` group asking for more children than it has, bounded by what it has (``[3..4]``
    of two children becomes ``[2..2]``): (new text, what it does), or None."""
    if group.kind != "card":
        return None
    n = len({id(c.feature) for c in group.children})
    if group.lo <= n or n == 0:
        return None
    lo = n
    hi = None if group.hi is None else max(lo, min(group.hi, n))
    idx = LineIndex(text)
    a, b = idx.offset(group.keyword_span.start), idx.offset(group.keyword_span.end)
    old = text[a:b]
    if not (old.startswith("[") and old.endswith("]")):
        return None
    new = f"[{lo}..{'*' if hi is None else hi}]"
    owner = group.owner.name if group.owner is not None else "its feature"
    return text[:a] + new + text[b:], f"change the group `{old}` of {owner}, which has {n} children, to `{new}`"


# ------------------------------------------------------------------ which constraints to remove

def _satisfies(model: list[int], clauses: list[list[int]]) -> bool:
    n = len(model)
    for c in clauses:
        for x in c:
            v = abs(x)
            if v <= n and (model[v - 1] > 0) == (x > 0):
                break
        else:
            return False
    return True


def removable(e, path: str) -> bool:
    """A constraint of the file at ``path`` a fix may remove (not one the front end has reported
    as an error: that one gets its own fix)."""
    return (e.kind == "constraint" and e.path == path and isinstance(e.obj, M.Constraint)
            and not getattr(e.obj, "reported_error", False))


def correction_sets(analysis, extra: list[int], path: str, limit: int = 4,
                    deadline: Optional[float] = None) -> list[list]:
    """Minimal sets of removable constraints (elements) whose removal makes ``extra``
    satisfiable with the rest of the model (see the module docstring); [] when none exists or
    the query is satisfiable already."""
    with analysis._lock:
        enc = analysis.encoding
        an = analysis.analyzer
        s = an.selector_solver  # (numbers the selectors)
        cons = [e for e in enc.elements if e.kind == "constraint"]
        fixed = [e.selector for e in enc.elements if e.kind != "constraint"]
        fixed += [e.selector for e in cons if not removable(e, path)]
        if not s.solve(assumptions=fixed + extra):
            return []  # the feature tree (or what may not be removed) alone forbids it
        ex = an.explain(extra, deadline=deadline)
        if ex is None:
            return []
        mus = [e for e in ex.elements if removable(e, path)]
        free = [e for e in cons if removable(e, path)]
        out: list[list] = []
        for c in mus:
            if deadline is not None and time.monotonic() > deadline:
                return out
            if s.solve(assumptions=fixed + extra + [x.selector for x in free if x is not c]):
                out.append([c])
        if out:
            return out
        # every single removal leaves another reason: a minimal correction set per MUS member
        for c in mus[:limit]:
            if not s.solve(assumptions=fixed + extra):
                break
            m = s.get_model()
            kept: list[int] = []
            for d in free:
                if d is c:
                    continue
                if deadline is not None and time.monotonic() > deadline:
                    return out
                if _satisfies(m, d.clauses):
                    kept.append(d.selector)
                elif s.solve(assumptions=fixed + extra + kept + [d.selector]):
                    kept.append(d.selector)
                    m = s.get_model()
            if s.solve(assumptions=fixed + extra + kept + [c.selector]):
                kept.append(c.selector)  # c is not needed: the others make the correction
            keep = set(kept)
            rest = [d for d in free if d.selector not in keep]
            if rest and len(rest) <= MAX_CORRECTION and not any(set(map(id, rest)) == set(map(id, r)) for r in out):
                out.append(rest)
        return out
