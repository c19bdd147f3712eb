"""Pull diagnostics (``textDocument/diagnostic``) for clients that advertise them; the
push side is the server's scheduler (``TvlLanguageServer.schedule``)."""

from __future__ import annotations

from lsprotocol import types


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_DIAGNOSTIC,
                types.DiagnosticOptions(identifier="tvl-lsp", inter_file_dependencies=True,
                                        workspace_diagnostics=False))
    async def pull(ls, params: types.DocumentDiagnosticParams):
        uri = params.text_document.uri
        doc = ls.docs.get(uri)
        if doc is None or doc.kind is None:
            return types.RelatedFullDocumentDiagnosticReport(items=[])
        res = await ls.wait_full(uri, ls.settings.time_budget + 1)
        doc = ls.docs.get(uri)
        if doc is None:
            return types.RelatedFullDocumentDiagnosticReport(items=[])
        rid = f"{doc.version}:{res.phase if res else 'none'}:{res.version if res else ''}"
        return types.RelatedFullDocumentDiagnosticReport(items=ls.lsp_diagnostics(uri), result_id=rid)
