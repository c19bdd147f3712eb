"""The nodes' C++ and Python sources in the editor (issue #26): a hover on the name a call asks for
(``nh.advertise<T>("chatter", 1)``, ``self.create_subscription(String, 'scan', ...)``) says what
the call is, in which products of the workspace's launch files its program runs, and who is on
the other end of the name there.  Thin glue: :func:`tvl_lsp.project.graph.source_info` does the
work in the worker process, over a snapshot of the open documents (unsaved text included).

Editing a source re-checks the open launch files of its workspace (``checks.depends_on``), whose
graph checks read the sources again (only the changed files are parsed again).
"""

from __future__ import annotations

import asyncio
import logging
from typing import Optional

from ...base.text import Pos, Span

SOURCE_HOVER_WAIT = 2.0   # seconds a hover waits for the answer
VERBS = {"publish": "publishes", "subscribe": "subscribes to", "service": "provides", "client": "calls",
         "action_server": "serves the action", "action_client": "calls the action",
         "param_declare": "declares the parameter", "param_read": "reads the parameter",
         "param_write": "writes the parameter", "param_delete": "deletes the parameter",
         "param_search": "searches for the parameter"}
OTHER = {"publish": "published by", "subscribe": "subscribed to by", "service": "provided by", "client": "called by",
         "action_server": "served by", "action_client": "called by", "read": "read by", "write": "written by"}

log = logging.getLogger("tvl_lsp.server")


def markdown(use) -> str:
    t = f" [`{use.type}`]" if use.type else ""
    who = ", ".join(f"`{use.package}/{x}`" for x in use.executables[:4]) or f"`{use.package}`"
    lines = [f"**{VERBS.get(use.kind, use.kind)}** `{use.name}`{t} — {who}"]
    if use.dynamic:
        lines.append("")
        lines.append("The name is computed at run time: `{…}` stands for what is not known before "
                     "(a project file's `values:` hint can give it).")
    if not use.running:
        lines.append("")
        lines.append("No launch file of the workspace (paired with a model, or named by a HAROS project file) "
                     "starts this program.")
    for r in use.running:
        lines.append("")
        where = r.launch.rsplit("/", 1)[-1]
        if r.condition is None:
            when = "in every product" + (f" ({r.total})" if r.total is not None else "")
        else:
            share = f" ({r.products} of {r.total} products)" if r.products is not None and r.total else ""
            when = f"when `{r.condition}`{share}"
        lines.append(f"`{where}`: runs as `{r.node}` {when}")
        if r.resource is not None:
            if r.others:
                parts = []
                for o in r.others[:8]:
                    parts.append(f"`{o.node}`" + (f" (when `{o.condition}`)" if o.condition else ""))
                verb = OTHER.get(r.others[0].kind, r.others[0].kind)
                lines.append(f"- `{r.resource}`: {verb} " + ", ".join(parts))
            else:
                lines.append(f"- `{r.resource}`: no other node uses it in these products")
    if use.note:
        lines.append("")
        lines.append(use.note)
    return "\n".join(lines)


async def source_hover(ls, doc, pos) -> tuple[Optional[str], Optional[Span]]:
    """(markdown, span) for a hover in a node's source, or (None, None)."""
    from ...project.graph import source_info
    from .graph import _snapshot
    try:
        fut = ls.proc_pool.submit(source_info, doc.path, pos.line, pos.col, _snapshot(ls), ls.roots_for(doc.path))
        use = await asyncio.wait_for(asyncio.shield(asyncio.wrap_future(fut)), SOURCE_HOVER_WAIT)
    except asyncio.TimeoutError:
        return "reading the sources… (hover again in a moment)", None
    except Exception as exc:  # an unreadable file, a model with errors: never fail the hover
        log.debug("source hover failed: %r", exc)
        return None, None
    if use is None:
        return None, None
    a, b, c, d = use.span
    return markdown(use), Span(Pos(a, b), Pos(c, d))
