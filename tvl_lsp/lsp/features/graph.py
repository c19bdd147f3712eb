"""The computation graph in the editor (docs/graph.md): the ``tvl-lsp.graph`` command and the
topics a ``<node>`` uses, for the hover.  Thin glue: the graph is built by
:mod:`tvl_lsp.project.graph` in the configurator's worker process, over a snapshot of the open
documents.

- ``tvl-lsp.graph``  [uri, decisions?, options?] -> the graph's JSON (docs/graph.md), or
  ``{"error": message, "conflict": [features] | null}`` when the decisions name an unknown
  feature or leave no product.  ``decisions``: ``{"Feature": true|false}`` or
  ``{"include": [...], "exclude": [...]}``; omitted (or null): the configurator's current
  decisions for the launch file's model (``tvl-lsp.include`` / ``exclude``).  ``options``:
  ``{"count": true}`` adds product counts.
"""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path
from typing import Any, Optional

from pygls.exceptions import JsonRpcInvalidParams

from ..checks import SnapshotReader, file_kind
from ..convert import uri_to_path

GRAPH = "tvl-lsp.graph"
HOVER_GRAPH_WAIT = 2.0   # seconds a hover waits for the node's topics
VERBS = {"publish": "publishes", "subscribe": "subscribes to", "service": "provides", "client": "calls",
         "read": "reads", "write": "writes"}

log = logging.getLogger("tvl_lsp.server")


def _path(arg: Any) -> str:
    if isinstance(arg, dict):
        arg = arg.get("uri") or arg.get("path")
    if not isinstance(arg, str) or not arg:
        raise JsonRpcInvalidParams("the first argument must be the URI of a launch file")
    return uri_to_path(arg) if "://" in arg else str(Path(arg).absolute())


def _decisions(arg: Any) -> Optional[dict[str, bool]]:
    if arg is None:
        return None
    if not isinstance(arg, dict):
        raise JsonRpcInvalidParams("decisions: {\"Feature\": true|false} or {\"include\": [...], \"exclude\": [...]}")
    if set(arg) <= {"include", "exclude"} and all(isinstance(v, list) for v in arg.values()):
        out = {str(f): True for f in arg.get("include", [])}
        out.update({str(f): False for f in arg.get("exclude", [])})
        return out
    if not all(isinstance(v, bool) for v in arg.values()):
        raise JsonRpcInvalidParams("decisions map feature names to true (included) or false (excluded)")
    return {str(k): v for k, v in arg.items()}


def _snapshot(ls) -> SnapshotReader:
    return SnapshotReader({d.path: d.text for d in ls.docs.values()})


def register(ls) -> None:
    @ls.command(GRAPH)
    async def graph(ls, *args):
        path = _path(args[0] if args else None)
        if file_kind(path) != "launch":
            raise JsonRpcInvalidParams(f"{Path(path).name} is not a launch file")
        decisions = _decisions(args[1] if len(args) > 1 else None)
        options = args[2] if len(args) > 2 and isinstance(args[2], dict) else {}
        if decisions is None:
            models = ls.models_for_launch(path)
            decisions = dict(getattr(ls, "decisions", {}).get(models[0], {})) if models else {}
        from ...project.graph import graph_document
        fut = ls.proc_pool.submit(graph_document, path, _snapshot(ls), ls.roots_for(path), decisions,
                                  bool(options.get("count")))

        async def run():
            return await asyncio.wrap_future(fut)
        return await ls.with_progress("Building the computation graph", run())


async def node_markdown(ls, doc, el) -> list[str]:
    """Hover lines for a ``<node>``: the topics, services and parameters it uses, and when."""
    from ...project.graph import node_info
    try:
        fut = ls.proc_pool.submit(node_info, doc.path, el.span.start, _snapshot(ls), ls.roots_for(doc.path))
        infos = await asyncio.wait_for(asyncio.shield(asyncio.wrap_future(fut)), HOVER_GRAPH_WAIT)
    except asyncio.TimeoutError:
        return ["", "topics: computing… (hover again in a moment)"]
    except Exception as exc:  # a model with syntax errors, an unreadable file: say so, never fail the hover
        log.debug("graph hover failed: %r", exc)
        return ["", f"topics: not available ({exc})"]
    lines: list[str] = []
    for info in infos:
        lines.append("")
        where = f" (hints: {', '.join(info.hints)})" if info.hints else ""
        if info.extracted:
            where += " (read from its sources)"
        lines.append(f"**ROS node** `{info.name}` — `{info.package}/{info.type}`{where}")
        if not info.hinted:
            lines.append(f"- {info.note}" if info.hints_available else
                         "- topics unknown: no node hints (a HAROS project file's `nodes:`, see docs/graph.md)")
            continue
        if not info.uses:
            lines.append("- uses no topics, services or parameters (per its hints)")
        for u in info.uses:
            t = f" [`{u.type}`]" if u.type else ""
            when = f" — when `{u.condition}`" if u.condition else ""
            how = ""
            written = "`, `".join(u.written)
            src = f" at {', '.join(u.sources[:3])}" if u.sources else ""
            if u.remap:
                how = f" (`{written}`{src}, remapped by `{u.remap}`)"
            elif u.written and u.written != [u.name]:
                how = f" (`{written}`{src})"
            elif src:
                how = f" ({src.strip()})"
            lines.append(f"- {VERBS.get(u.kind, u.kind)} `{u.name}`{t}{when}{how}")
    return lines
