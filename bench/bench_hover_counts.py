"""Hover counts on an industrial model in the language server (issue #15).

    .venv/bin/python bench/bench_hover_counts.py [--models DIR] [--model automotive01]

Converts ``dimacs/<model>.dimacs`` to a flat TVL model (the root with every variable as an
optional child, every clause a constraint: the same products), starts ``tvl-lsp`` on stdio with
an empty counting cache, opens the model and hovers a feature every 0.25 s until the hover shows
"in N of M products".  Reports the time from opening to the first counted hover (parse, checks,
d4 compilation and the one-pass counts, in the worker process), then the latency of hovers on
other features once the counts are there, and then, as a baseline in the same run, d4 alone
compiling the same CNF (niced like the server's workers).  ``--models`` default: ``/work/shared/models``
(``$TVL_LSP_MODELS`` overrides).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_latency import Bench  # noqa: E402
from lsprotocol import types  # noqa: E402

DEFAULT_MODELS = os.environ.get("TVL_LSP_MODELS", "/work/shared/models")


def dimacs_to_tvl(text: str, root: str) -> tuple[str, list[str]]:
    names: dict[int, str] = {}
    clauses: list[list[int]] = []
    cur: list[int] = []
    nv = 0
    for line in text.splitlines():
        if line.startswith("c "):
            parts = line.split()
            if len(parts) >= 3 and parts[1].isdigit():
                names[int(parts[1])] = re.sub(r"\W", "_", parts[2])
            continue
        if line.startswith("p "):
            nv = int(line.split()[2])
            continue
        for tok in line.split():
            x = int(tok)
            if x:
                cur.append(x)
            else:
                clauses.append(cur)
                cur = []
    feats = [names.get(i, f"v{i}") for i in range(1, nv + 1)]
    out = [f"root {root} {{", "  group [0..*] {"]
    out.append(",\n".join(f"    opt {f}" for f in feats))
    out.append("  }")
    for c in clauses:
        out.append("  " + " || ".join(("!" if x < 0 else "") + feats[abs(x) - 1] for x in c) + ";")
    out.append("}")
    return "\n".join(out) + "\n", feats


async def start(b: Bench, root: Path, budget: float) -> None:
    os.environ["TVL_LSP_LOGFILE"] = str(root.parent / "server.log")
    os.environ.setdefault("TVL_LSP_LOG", "INFO")
    await b.client.start_io(sys.executable, "-m", "tvl_lsp")
    caps = types.ClientCapabilities(
        window=types.WindowClientCapabilities(work_done_progress=True),
        workspace=types.WorkspaceClientCapabilities(configuration=True),
        text_document=types.TextDocumentClientCapabilities(
            hover=types.HoverClientCapabilities(content_format=[types.MarkupKind.Markdown])))
    await b.client.initialize_async(types.InitializeParams(
        capabilities=caps, root_uri=root.as_uri(), initialization_options={"count": {"timeBudget": budget}},
        workspace_folders=[types.WorkspaceFolder(uri=root.as_uri(), name="ws")]))
    b.client.initialized(types.InitializedParams())


async def run(args) -> int:
    path = Path(args.models) / "dimacs" / f"{args.model}.dimacs"
    if not path.exists():
        print(f"bench_hover_counts: no {path} (pass --models DIR); nothing measured")
        return 0
    tmp = Path(tempfile.mkdtemp(prefix="hover-"))
    os.environ["TVL_LSP_CACHE_DIR"] = str(tmp / "cache")
    ws = tmp / "ws"
    ws.mkdir()
    text, feats = dimacs_to_tvl(path.read_text(), "Model")
    model = ws / f"{args.model}.tvl"
    model.write_text(text)
    lines = text.splitlines()

    def pos(name):
        for i, ln in enumerate(lines):
            if ln.strip() == f"opt {name}," or ln.strip() == f"opt {name}":
                return types.Position(line=i, character=ln.index(name) + 1)
        raise KeyError(name)

    b = Bench()
    await start(b, ws, args.budget)
    try:
        t0 = time.perf_counter()
        uri = b.open(model, text)
        first = None
        while time.perf_counter() - t0 < args.timeout:
            dt, md = await b.hover(uri, pos(feats[len(feats) // 2]))
            if "products**" in md:
                first = time.perf_counter() - t0
                print(f"first counted hover: {first:.2f} s after opening ({md.splitlines()[-1]})")
                break
            await asyncio.sleep(0.25)
        if first is None:
            print(f"no counted hover within {args.timeout:g} s")
            return 1
        times = []
        for name in feats[1:: max(1, len(feats) // 40)][:40]:
            dt, md = await b.hover(uri, pos(name))
            assert "products**" in md, md
            times.append(dt)
        print(f"hover with counts: median {statistics.median(times) * 1000:.0f} ms, "
              f"max {max(times) * 1000:.0f} ms over {len(times)} features")
    finally:
        await b.client.shutdown_async(None)
        b.client.exit(None)
        await b.client.stop()
    # the same run's baseline: d4 alone compiling the model's CNF (its child process, niced as
    # the server's workers are), with an empty cache; the difference is what the server adds
    # (parse, encoding, check, the one-pass counts, the hover)
    base = compile_alone(model, text, tmp / "cache-baseline")
    print(f"baseline, d4 compiling the same CNF alone: {base:.2f} s; the server's first counted hover "
          f"came {first - base:.2f} s after it would have finished")
    return 0


def compile_alone(model: Path, text: str, cache: Path) -> float:
    import subprocess
    code = ("import os, sys, time; os.nice(10)\n"
            "from tvl_lsp.tvl import parse_model\n"
            "from tvl_lsp.analysis.engine import ModelAnalysis\n"
            "a = ModelAnalysis(parse_model(open(sys.argv[1]).read(), sys.argv[1]).model); c = a.counter\n"
            "t = time.perf_counter(); c.circuit(600); print(time.perf_counter() - t)\n")
    out = subprocess.run([sys.executable, "-c", code, str(model)], capture_output=True, text=True,
                         env=dict(os.environ, TVL_LSP_CACHE_DIR=str(cache)), check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default=DEFAULT_MODELS)
    ap.add_argument("--model", default="automotive01")
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--budget", type=float, default=60, help="the server's count.timeBudget (s)")
    return asyncio.run(run(ap.parse_args()))


if __name__ == "__main__":
    sys.exit(main())
