"""Formatting of TVL (``tvl_lsp.tvl.format.format_tvl``: idempotent, meaning preserved)."""

from __future__ import annotations

from lsprotocol import types

from ..convert import to_lsp_position
from ...base.text import Pos


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_FORMATTING)
    async def formatting(ls, params: types.DocumentFormattingParams):
        doc = ls.docs.get(params.text_document.uri)
        if doc is None or doc.kind != "tvl":
            return None
        try:
            from ...tvl.format import format_tvl
        except ImportError:
            return None
        text, version = doc.text, doc.version
        new = await ls.run_in_thread(format_tvl, text)
        if new is None or new == text or doc.version != version:
            return []
        index = doc.index
        last = index.line_count - 1
        end = to_lsp_position(index, Pos(last, len(index.line_text(last))), ls.encoding)
        return [types.TextEdit(range=types.Range(start=types.Position(line=0, character=0), end=end), new_text=new)]
