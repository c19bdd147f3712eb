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


def main(argv: Optional[list[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("--list", "-l"):
        codes = load_codes()
        for c in sorted(codes):
            i = codes[c]
            print(f"{c:28} {i.severity.label:11} {i.summary}")
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
