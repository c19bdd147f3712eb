"""Quick fixes for model anomalies in the editor (#30): the code actions of a TVL / UVL model's
void-model, always-false-constraint, redundant-constraint, dead-feature and false-optional
diagnostics.

The fixes are the core's (:func:`tvl_lsp.project.fixes.fixes_for`, the function ``tvl-lsp --check
--fix`` calls): each one applied to the text, checked again and offered only when it removes its
finding and adds none.  That work runs in the check process (which has this very text parsed and
analysed for its check) and is kept by content: right after a model's check for all its findings
when they are few (:func:`prefetch`, bounded: the light bulb finds them ready), else for the
findings at the requested range, bounded by the ``count.timeBudget`` setting.  A request waits
for it at most :data:`WAIT` seconds and the fixes not ready by then come with a later request
(the client asks again when the cursor or the diagnostics change); :func:`request` and
:func:`cached_actions` are the two halves for a provider that must answer at once.  Each edit names the document version it was
computed for (``documentChanges`` when the client supports them: an edited document refuses it),
and the fixes of a text are offered only while the document still has that text.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Iterable, Optional

from lsprotocol import types

from ...base.diagnostics import Diagnostic
from ...project.fixes import ANOMALY_CODES, finding_key
from ..convert import fix_to_edit, fix_to_versioned_edit, to_lsp_diagnostic
from ..documents import content_key
from ..workers import _consume

log = logging.getLogger("tvl_lsp.server")

WAIT = 2.5          # seconds a code action request waits for fixes being checked
MAX_BUDGET = 20.0   # seconds one computation may take (the setting's time budget, at most this)
KINDS = ("tvl", "uvl")
_ANOMALY = frozenset(ANOMALY_CODES)


def _jobs(ls) -> dict:
    jobs = getattr(ls, "_fix_jobs", None)
    if jobs is None:
        jobs = ls._fix_jobs = {}
    return jobs


def anomaly_findings(doc, diags: Iterable[Diagnostic]) -> list[Diagnostic]:
    """The diagnostics among ``diags`` that the anomaly quick fixes answer."""
    if doc.kind not in KINDS:
        return []
    return [d for d in diags if d.code in _ANOMALY and (not d.path or d.path == doc.path)]


def request(ls, doc, keys: list[tuple], budget: Optional[float] = None):
    """Start checking the fixes of the findings ``keys`` of the document's current text in the
    check process, unless they are known or under way; the future of that work, or None when
    every one is known.  Never waits."""
    ck = content_key(doc.path, doc.text)
    known: dict = ls.cache.get(("fixes", ck)) or {}
    missing = [k for k in keys if k not in known]
    if not missing:
        return None
    jobs = _jobs(ls)
    for (jck, jkeys), (fut, _) in jobs.items():
        if jck == ck and set(missing) <= jkeys:
            return fut  # under way
    from ..checks import fixes_worker
    for (old_ck, _), (old, old_path) in list(jobs.items()):
        if old_ck != ck and old_path == doc.path:
            old.cancel()  # a stale text's fixes: dropped while still queued
    texts = {d.path: d.text for d in ls.docs.values()}
    if budget is None:
        budget = min(float(ls.settings.time_budget), MAX_BUDGET)
    cfut = ls.check_pool.submit(fixes_worker, doc.path, doc.text, texts, [list(k) for k in missing], budget)
    fut = asyncio.wrap_future(cfut)
    jk = (ck, frozenset(missing))
    jobs[jk] = (fut, doc.path)

    def landed(f, jk=jk, ck=ck):
        jobs.pop(jk, None)
        if f.cancelled() or f.exception() is not None:
            if not f.cancelled():
                log.warning("quick fixes failed: %r", f.exception())
            return
        report = f.result()
        have = dict(ls.cache.get(("fixes", ck)) or {})
        have.update(report.fixes)
        ls.cache[("fixes", ck)] = have
        ls._remember(("fixes", ck))
        log.info("quick fixes of %d finding(s) checked: %d re-checks, %.2f s", len(report.fixes),
                 report.checks, report.seconds)
    fut.add_done_callback(landed)
    fut.add_done_callback(_consume)
    return fut


def known_fixes(ls, doc) -> dict:
    """finding key -> checked fixes known for the document's current text."""
    return ls.cache.get(("fixes", content_key(doc.path, doc.text))) or {}


async def fixes_of(ls, doc, keys: list[tuple], wait: float) -> dict:
    """finding key -> checked fixes, for the keys whose fixes are known for the document's text
    within ``wait`` seconds (a computation started here goes on and lands in the cache)."""
    fut = request(ls, doc, keys)
    if fut is not None:
        try:
            await asyncio.wait_for(asyncio.shield(fut), wait)
        except asyncio.TimeoutError:
            pass
        except asyncio.CancelledError:
            raise
        except Exception:  # noqa: BLE001 (logged by the callback; the other actions are still answered)
            pass
        await asyncio.sleep(0)  # (the callback that fills the cache runs first)
    return known_fixes(ls, doc)


PREFETCH_FINDINGS = 40   # a checked model with at most this many findings gets its fixes at once
PREFETCH_BUDGET = 2.0    # seconds


def prefetch(ls, uri: str) -> None:
    """After a model's check: check the fixes of its findings now (bounded), so the light bulb
    finds them ready.  Models with many findings get theirs on demand (the cursor's)."""
    try:
        doc = ls.docs.get(uri)
        res = ls.results.get(uri)
        if doc is None or res is None or res.version != doc.version or doc.kind not in KINDS:
            return
        findings = anomaly_findings(doc, res.diagnostics)
        if not findings or len(findings) > PREFETCH_FINDINGS:
            return
        budget = min(PREFETCH_BUDGET, float(ls.settings.time_budget))
        request(ls, doc, [finding_key(d, doc.text) for d in findings], budget)
    except Exception:  # noqa: BLE001 (a prefetch never breaks the check that triggered it)
        log.exception("prefetching quick fixes failed")


def _edit(ls, fix, uri: str, version: Optional[int], index) -> types.WorkspaceEdit:
    if ls.cap("workspace.workspace_edit.document_changes", False):
        return fix_to_versioned_edit(fix, uri, version, index, ls.encoding)
    return fix_to_edit(fix, ls.index_of, ls.encoding)


async def actions(ls, uri: str, doc, diags: list[Diagnostic], wait: float = WAIT) -> list[types.CodeAction]:
    """The quick fixes of the anomaly diagnostics ``diags`` of the document ``doc``, waiting at
    most ``wait`` seconds for those being checked."""
    findings = anomaly_findings(doc, diags)
    if not findings:
        return []
    text = doc.text
    await fixes_of(ls, doc, [finding_key(d, text) for d in findings], wait)
    now = ls.docs.get(uri)
    if now is None or now.text != text:
        return []  # edited meanwhile: these fixes are for a text that is gone
    return cached_actions(ls, uri, now, findings)


def cached_actions(ls, uri: str, doc, diags: list[Diagnostic]) -> list[types.CodeAction]:
    """The quick fixes known now for the anomaly diagnostics ``diags`` of the document's current
    text (no waiting: what a code action provider that answers at once returns)."""
    findings = anomaly_findings(doc, diags)
    if not findings:
        return []
    known = known_fixes(ls, doc)
    keys = [finding_key(d, doc.text) for d in findings]
    version = doc.version
    now = doc
    out = []
    for d, k in zip(findings, keys):
        fixes = known.get(k) or []
        if not fixes:
            continue
        sev = ls.settings.severity(d)
        if sev is None:
            continue
        ld = to_lsp_diagnostic(d, now.index, ls.encoding, ls.index_of, sev)
        for fx in fixes:
            out.append(types.CodeAction(title=fx.title, kind=types.CodeActionKind.QuickFix, diagnostics=[ld],
                                        is_preferred=fx.preferred or None,
                                        edit=_edit(ls, fx, uri, version, now.index)))
    return out
