"""The diagnostics catalogue: one page per diagnostic code, shipped inside the package.

``tvl_lsp/data/diagnostics.md`` is the one source of truth (a ``## `code` `` heading per code:
what it means, a minimal example, the fix).  It is package data, so an installed wheel, and the
server inside the VS Code extension, have it too: ``tvl-lsp --explain CODE`` prints a section,
the server's hover on a diagnostic shows it, SARIF output carries it as the rule's help.
"""

from __future__ import annotations

import re
from functools import lru_cache
from typing import Optional

RESOURCE = ("data", "diagnostics.md")  # inside the tvl_lsp package
REPO_PATH = "tvl_lsp/data/diagnostics.md"  # where the file lives in the repository


def catalogue_text() -> Optional[str]:
    """The whole catalogue, or None when the package data is missing (a broken install)."""
    from .files import package_text  # (through the bounded reader)
    try:
        return package_text(*RESOURCE)
    except (OSError, ModuleNotFoundError):
        return None


def sections(text: str) -> dict[str, str]:
    """code -> its section (heading included, up to the next code, level-1 heading or rule)."""
    out: dict[str, str] = {}
    heads = list(re.finditer(r"(?m)^## `([a-z0-9-]+)`.*$", text))
    for i, m in enumerate(heads):
        end = heads[i + 1].start() if i + 1 < len(heads) else len(text)
        body = text[m.start():end]
        nl = body.find("\n")
        h1 = re.search(r"(?m)^(# |---\s*$)", body[nl + 1:]) if nl >= 0 else None
        if h1:
            body = body[: nl + 1 + h1.start()]
        out[m.group(1)] = body.rstrip() + "\n"
    return out


@lru_cache(maxsize=1)
def all_sections() -> dict[str, str]:
    text = catalogue_text()
    return sections(text) if text else {}


def section(code: str) -> Optional[str]:
    """The catalogue's page for ``code`` (Markdown), or None."""
    return all_sections().get(code)
