"""``tvl-lsp --explain CODE``: print the documentation of a diagnostic code.

The text is the code's section of ``docs/diagnostics.md`` (``## `code` `` headings); without
the docs (an installed wheel) the registered one-line summary is printed.  ``--explain``
alone lists every code.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Optional

_PACKAGE = Path(__file__).resolve().parents[2]  # tvl_lsp/
DOC_CANDIDATES = (
    _PACKAGE.parent / "docs" / "diagnostics.md",
    _PACKAGE / "data" / "diagnostics.md",
)


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


def doc_text() -> Optional[str]:
    for p in DOC_CANDIDATES:
        if p.is_file():
            from ...base.files import read_text_or_none
            return read_text_or_none(str(p))
    return None


def sections(text: str) -> dict[str, str]:
    """code -> its section (heading included) from docs/diagnostics.md."""
    out: dict[str, str] = {}
    heads = list(re.finditer(r"(?m)^## `([a-z0-9-]+)`.*$", text))
    for i, m in enumerate(heads):
        end = heads[i + 1].start() if i + 1 < len(heads) else len(text)
        body = text[m.start():end]
        # stop at a following level-1 heading or rule
        nl = body.find("\n")
        h1 = re.search(r"(?m)^(# |---\s*$)", body[nl + 1:]) if nl >= 0 else None
        if h1:
            body = body[: nl + 1 + h1.start()]
        out[m.group(1)] = body.rstrip() + "\n"
    return out


def explain(code: str) -> Optional[str]:
    codes = load_codes()
    text = doc_text()
    if text is not None:
        sec = sections(text).get(code)
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
