"""What a diagnostic code means, in the editor, from the diagnostics catalogue the package ships
(``tvl_lsp/data/diagnostics.md``, read by :mod:`tvl_lsp.base.catalogue`, as ``--explain`` reads it).

- the hover on a diagnostic: hovering inside a diagnostic's range adds its code's page (what it
  means, an example, the fix) below whatever else the hover says;
- ``tvl-lsp.explain`` [code]  -> {code, severity, summary, markdown}: a code's page (the VS Code
  extension opens it from the Problems panel and the "TVL: Explain a diagnostic code" command);
  ``tvl-lsp.explain`` []      -> {codes: [{code, severity, summary}]}: every code.
"""

from __future__ import annotations

from typing import Optional

from pygls.exceptions import JsonRpcInvalidParams

from ...base.catalogue import section
from ...base.diagnostics import CODES
from ...base.text import Pos, Span

EXPLAIN = "tvl-lsp.explain"


def page_body(code: str) -> Optional[str]:
    """The catalogue's page without its heading and severity line (the hover says both)."""
    sec = section(code)
    if sec is None:
        info = CODES.get(code)
        return info.summary if info else None
    lines = sec.splitlines()[1:]
    lines = [ln for ln in lines if not ln.startswith("**Severity:**")]
    return "\n".join(lines).strip()


def hover_notes(ls, uri: str, path: str, pos: Pos) -> tuple[str, Optional[Span]]:
    """Markdown for the diagnostics (shown ones: not turned off in the settings) whose range holds
    ``pos``, each code once, and the smallest of their ranges."""
    res = getattr(ls, "results", {}).get(uri)
    if res is None:
        return "", None
    seen: list[str] = []
    parts: list[str] = []
    span: Optional[Span] = None
    for d in res.diagnostics:
        if d.path and d.path != path or not d.span.contains(pos) or d.code in seen:
            continue
        sev = ls.settings.severity(d)
        if sev is None:
            continue
        body = page_body(d.code)
        if body is None:
            continue
        seen.append(d.code)
        parts.append(f"**`{d.code}`** ({sev.label}) · `tvl-lsp --explain {d.code}`\n\n{body}")
        if span is None or (d.span.end.line - d.span.start.line, d.span.end.col - d.span.start.col) < \
                (span.end.line - span.start.line, span.end.col - span.start.col):
            span = d.span
    return "\n\n---\n\n".join(parts), span


def register(ls) -> None:
    @ls.command(EXPLAIN)
    def explain(ls, *args):
        if not args:
            return {"codes": [{"code": c, "severity": i.severity.label, "summary": i.summary}
                              for c, i in sorted(CODES.items())]}
        code = args[0]
        if not isinstance(code, str) or code not in CODES:
            raise JsonRpcInvalidParams(f"unknown diagnostic code {code!r} (tvl-lsp.explain with no "
                                       "argument lists them)")
        info = CODES[code]
        return {"code": code, "severity": info.severity.label, "summary": info.summary,
                "markdown": section(code) or f"## `{code}`\n\n{info.summary}\n"}
