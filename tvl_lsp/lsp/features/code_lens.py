"""A code lens on the model's root with its product count."""

from __future__ import annotations

import asyncio

from lsprotocol import types

from ..convert import to_lsp_range
from ...project.facts import MODEL_KINDS
from .commands import COUNT

LENS_WAIT = 0.3


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_CODE_LENS)
    async def code_lens(ls, params: types.CodeLensParams):
        uri = params.text_document.uri
        doc = ls.docs.get(uri)
        if doc is None or doc.kind not in MODEL_KINDS:
            return None
        res = await ls.parsed(doc.path)
        model = getattr(res, "model", None)
        if model is None or model.root is None or model.root.path != doc.path:
            return []
        facts = await ls.model_facts(doc.path, wait=LENS_WAIT)
        if facts is None:
            title = "counting products…"
            asyncio.ensure_future(_refresh_when_ready(ls, doc.path))
        elif facts.total is None and facts.retry:
            title = "products: counting again in the background…"  # (refreshed when it answers)
        elif facts.total is None:
            title = f"products: not counted ({facts.error})"
        else:
            title = f"{facts.total} products"
            decisions = getattr(ls, "decisions", {}).get(doc.path)
            if decisions:
                title += f" · {len(decisions)} decision(s) in the configurator"
        rng = to_lsp_range(doc.index, model.root.name_span, ls.encoding)
        return [types.CodeLens(range=rng, command=types.Command(title=title, command=COUNT, arguments=[uri]))]


async def _refresh_when_ready(ls, path: str) -> None:
    await ls.model_facts(path)
    if ls.cap("workspace.code_lens.refresh_support", False):
        try:
            ls.workspace_code_lens_refresh(None)
        except Exception:
            pass
