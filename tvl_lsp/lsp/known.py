"""What is known about a document *now*, without waiting for a check: the latest results of its
current text (the quick pass: syntax, and for a launch file the checks that need no solver),
plus the findings of its last solver-backed check that the quick pass cannot make (anomalies,
dead elements, witnesses...), mapped through the edits made since: a finding whose range (or
a quick fix's edit) an edit touched is dropped, the others move with the text.

Diagnostics are published (and pulled) from this view, so the solver-backed findings do not
blink out at every keystroke until the next check lands, and code actions answer from it at
once (``features/code_actions.py``): the light bulb does not wait for a check.  When the
check of the current text lands, its diagnostics replace the view and are published again;
clients then ask for code actions again (VS Code on every diagnostics change, Neovim when the
user asks).

:class:`KnownDiagnostics` is a mixin of :class:`~tvl_lsp.lsp.server.TvlLanguageServer` (it
reads the scheduler's ``results`` and ``last_full``).
"""

from __future__ import annotations

import dataclasses
from typing import Optional, Sequence

from ..base.diagnostics import Diagnostic, Fix, Related, TextEdit
from ..base.text import LineIndex, Pos, Span

Edit = tuple  # (start, end, inserted length): code-point offsets before the change


def map_range(start: int, end: int, edits: Sequence[Edit]) -> Optional[tuple[int, int]]:
    """The offsets ``[start, end]`` after ``edits`` (applied in order), or None when an edit
    touched the inside of the range (an insertion at its start moves it, one at its end
    leaves it as it is)."""
    for a, b, n in edits:
        if b <= start:
            d = n - (b - a)
            start += d
            end += d
        elif a >= end:
            continue
        else:
            return None
    return start, end


class _Mapper:
    """Positions of one old text mapped onto the current text of the same file."""

    def __init__(self, path: str, old: LineIndex, new: LineIndex, edits: Sequence[Edit]):
        self.path = path
        self.old = old
        self.new = new
        self.edits = edits

    def span(self, span: Span) -> Optional[Span]:
        try:
            a, b = self.old.offset(span.start), self.old.offset(span.end)
        except Exception:  # noqa: BLE001 (a position past the old text: not mappable)
            return None
        got = map_range(a, b, self.edits)
        if got is None:
            return None
        return Span(self.new.pos(got[0]), self.new.pos(got[1]))

    def fix(self, fix: Fix, other_ok) -> Optional[Fix]:
        edits = []
        for e in fix.edits:
            if e.path == self.path:
                sp = self.span(e.span)
                if sp is None:
                    return None
                edits.append(TextEdit(e.path, sp, e.new_text) if sp != e.span else e)
            elif other_ok(e.path):
                edits.append(e)
            else:
                return None
        return Fix(fix.title, tuple(edits), fix.preferred)

    def diagnostic(self, d: Diagnostic, other_ok) -> Optional[Diagnostic]:
        sp = self.span(d.span)
        if sp is None:
            return None
        related = []
        for r in d.related:
            if r.path == self.path:
                rs = self.span(r.span)
                if rs is None:
                    continue
                related.append(Related(r.path, rs, r.message) if rs != r.span else r)
            else:
                related.append(r)
        fixes = [f2 for f2 in (self.fix(f, other_ok) for f in d.fixes) if f2 is not None]
        if sp == d.span and len(related) == len(d.related) and len(fixes) == len(d.fixes) \
                and all(a is b for a, b in zip(fixes, d.fixes)):
            return d
        return dataclasses.replace(d, span=sp, related=related, fixes=fixes)


def map_diagnostics(diags: Sequence[Diagnostic], path: str, old_text: str, new: LineIndex,
                    edits: Sequence[Edit], other_ok=lambda p: True,
                    old_index: Optional[LineIndex] = None) -> list[Diagnostic]:
    """``diags`` of the file ``path`` found on ``old_text``, moved onto the current text (whose
    index is ``new``) through ``edits``; those an edit touched are left out, and so are quick
    fixes editing a part that changed (or another file ``other_ok`` says changed)."""
    if not edits:
        return list(diags)
    m = _Mapper(path, old_index or LineIndex(old_text), new, edits)
    out = []
    for d in diags:
        got = m.diagnostic(d, other_ok) if d.path == path else None
        if got is not None:
            out.append(got)
    return out


class KnownDiagnostics:
    """The known-diagnostics view of a document (a mixin of the server)."""

    def _init_known(self) -> None:
        self._known_memo: dict[str, tuple] = {}  # uri -> (key, diagnostics)

    def known_diagnostics(self, uri: str) -> list[Diagnostic]:
        """The diagnostics of the current text of ``uri`` as far as they are known now (see the
        module docstring); at once, never waiting for a check."""
        doc = self.docs.get(uri)
        res = self.results.get(uri)
        if doc is None or res is None:
            return []
        full = self.last_full.get(uri)
        key = (doc.version, res.serial, full.serial if full is not None else None)
        memo = self._known_memo.get(uri)
        if memo is not None and memo[0] == key:
            return memo[1]
        if res.version == doc.version and res.phase == "full":
            out = list(res.diagnostics)
        else:
            out = self._mapped(doc, res, res.diagnostics)
            if full is not None and full is not res and full.solver:
                seen = {d.sort_key() for d in out}
                for d in self._mapped(doc, full, [full.diagnostics[i] for i in sorted(full.solver)
                                                  if i < len(full.diagnostics)]):
                    if d.sort_key() not in seen:
                        out.append(d)
        self._known_memo[uri] = (key, out)
        return out

    def _mapped(self, doc, res, diags) -> list[Diagnostic]:
        if res.version == doc.version:
            return list(diags)
        edits = doc.edits_since(res.version)
        if edits is None or res.text is None:
            return []

        def unchanged(p: str) -> bool:  # another file a quick fix edits: as it was checked?
            from .convert import path_to_uri
            other = self.docs.get(path_to_uri(p))
            if other is None:
                return p not in res.versions
            return res.versions.get(p, other.version) == other.version
        return map_diagnostics(diags, doc.path, res.text, doc.index, edits, unchanged, res.index)

    def forget_known(self, uri: str) -> None:
        self._known_memo.pop(uri, None)
