"""Pull diagnostics (``textDocument/diagnostic``) for clients that pull them and accept
``workspace/diagnostic/refresh`` (the others get them pushed: see
``TvlProtocol.lsp_initialize``); the push side is the server's scheduler
(``TvlLanguageServer.schedule``).  Answered within :data:`PULL_WAIT`; the server asks the
client to pull again once a pending check is done."""

from __future__ import annotations

from lsprotocol import types

PULL_WAIT = 0.5  # seconds a pull waits for a pending check when the client accepts refreshes


def register(ls) -> None:
    @ls.feature(types.TEXT_DOCUMENT_DIAGNOSTIC,
                types.DiagnosticOptions(identifier="tvl-lsp", inter_file_dependencies=True,
                                        workspace_diagnostics=False))
    async def pull(ls, params: types.DocumentDiagnosticParams):
        uri = params.text_document.uri
        doc = ls.docs.get(uri)
        if doc is None or doc.kind is None:
            return types.RelatedFullDocumentDiagnosticReport(items=[])
        # a client that can be told to pull again gets an answer at once (the latest results:
        # the syntax pass, or the last full check) and a refresh when the full check lands
        # (publish); one that cannot waits for the solver-backed check, within its budget
        # (pull diagnostics are offered only to clients that accept refreshes; one that pulls
        # all the same is answered with the latest results at once)
        refresh = ls.cap("workspace.diagnostics.refresh_support", False)
        res = await ls.wait_full(uri, PULL_WAIT if refresh else 0.0)
        doc = ls.docs.get(uri)
        if doc is None:
            return types.RelatedFullDocumentDiagnosticReport(items=[])
        rid = f"{doc.version}:{res.phase if res else 'none'}:{res.version if res else ''}"
        return types.RelatedFullDocumentDiagnosticReport(items=ls.lsp_diagnostics(uri), result_id=rid)
