"""``tvl-lsp --explain CODE``: print the documentation of a diagnostic code.

The text is the code's page in the diagnostics catalogue, ``tvl_lsp/data/diagnostics.md``
(package data: an installed wheel has it; ``tvl_lsp.base.catalogue`` reads it).  Should the
catalogue be missing (a broken install) the registered one-line summary is printed.
``--explain`` alone lists every code.
"""

from __future__ import annotations

import sys
from typing import Optional

from ...base.catalogue import all_sections, catalogue_text as doc_text, sections  # noqa: F401 (re-exported)


def load_codes() -> dict:
    """Import every module that may register codes, then return the catalogue."""
    import importlib
    import pkgutil

    import tvl_lsp
    for m in pkgutil.walk_packages(tvl_lsp.__path__, "tvl_lsp."):
        if m.name in ("tvl_lsp.__main__", "tvl_lsp.main") or m.name.startswith(("tvl_lsp.lsp", "tvl_lsp.cli")):
            continue
        try:
            importlib.import_module(m.name)
        except Exception:  # a module that cannot load here registers nothing we could check
            pass
    from ...base.diagnostics import CODES
    return CODES


def explain(code: str) -> Optional[str]:
    codes = load_codes()
    sec = all_sections().get(code)
    if sec is not None:
        return sec
    info = codes.get(code)
    if info is None:
        return None
    return f"## `{code}` ({info.severity.label}, {info.area})\n\n{info.summary}\n"


def listing(codes: dict, width: Optional[int] = None) -> str:
    """Every code in an aligned table (code, default severity, summary), grouped by nothing but
    the alphabet.  On a terminal the summaries wrap under their column; piped, one line a code."""
    import shutil
    import textwrap
    if width is None and sys.stdout.isatty():
        width = shutil.get_terminal_size((100, 24)).columns
    cw = max(len("CODE"), *(len(c) for c in codes))
    sw = max(len("SEVERITY"), *(len(i.severity.label) for i in codes.values()))
    indent = cw + sw + 4
    lines = [f"{'CODE':<{cw}}  {'SEVERITY':<{sw}}  SUMMARY"]
    for c in sorted(codes):
        i = codes[c]
        head = f"{c:<{cw}}  {i.severity.label:<{sw}}  "
        if width and width - indent >= 30:
            body = textwrap.wrap(i.summary, width - indent) or [""]
            lines.append(head + body[0])
            lines += [" " * indent + b for b in body[1:]]
        else:
            lines.append(head + i.summary)
    lines.append("")
    lines.append(f"{len(codes)} codes.  tvl-lsp --explain CODE prints a code's page: what it means, an "
                 "example, the fix.")
    return "\n".join(lines) + "\n"


def main(argv: Optional[list[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("--list", "-l"):
        sys.stdout.write(listing(load_codes()))
        return 0
    if argv[0] in ("-h", "--help"):
        print("usage: tvl-lsp --explain CODE   (no CODE: list every code)")
        return 0
    code = argv[0].strip()
    text = explain(code)
    if text is None:
        import difflib
        m = difflib.get_close_matches(code, sorted(load_codes()), n=3)
        hint = f" Did you mean: {', '.join(m)}?" if m else ""
        print(f"tvl-lsp --explain: unknown code `{code}`.{hint}", file=sys.stderr)
        return 2
    sys.stdout.write(text)
    return 0
