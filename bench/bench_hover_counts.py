"""Hover counts on an industrial model in the language server (issue #15).

    .venv/bin/python bench/bench_hover_counts.py [--models DIR] [--model automotive01] [--uvl]
                                                 [--clicks N] [--reopen N]

Opens ``uvl/<model>.uvl`` (``--uvl``) or ``dimacs/<model>.dimacs`` converted to a flat TVL model
(the root with every variable as an optional child, every clause a constraint: the same
products) in ``tvl-lsp`` on stdio with an empty counting cache, and hovers a feature every
0.25 s until the hover shows "in N of M products".  Reports:

- **cold**: the time from opening to the first counted hover (parse, checks, d4 compilation and
  the one-pass counts, in the worker process); then the latency of hovers on other features;
- **clicks**: ``--clicks`` configurator decisions through the server (``workspace/executeCommand
  tvl-lsp.configurator [uri, "decide", {feature, value}]``, then ``[uri, "counts"]``: the
  remaining count and every feature's count under all decisions so far), each timed from the
  decide request to the counts answer;
- **reopen**: ``--reopen`` times, a fresh server on the same counting cache (the model compiled
  before) opens the model: the time from opening to the first counted hover;
- as a baseline in the same run, d4 alone compiling the same CNF (niced like the server's
  workers).

``--models`` default: ``/work/shared/models`` (``$TVL_LSP_MODELS`` overrides).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional

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


def uvl_features(text: str) -> list[str]:
    """The feature names of a UVL model, in file order (the lines of its ``features`` block that
    are not group keywords)."""
    feats = []
    inside = False
    for ln in text.splitlines():
        word = ln.strip().split(" ", 1)[0] if ln.strip() else ""
        if ln.startswith("features"):
            inside = True
            continue
        if ln and not ln[0].isspace():
            inside = False
        if inside and word and word not in ("mandatory", "optional", "alternative", "or") \
                and not word.startswith("[") and not word.startswith("//"):
            feats.append(word.strip('"'))
    return feats


async def first_counted_hover(b: Bench, uri: str, pos, feature: str, timeout: float) -> Optional[float]:
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < timeout:
        dt, md = await b.hover(uri, pos(feature))
        if "products**" in md:
            return time.perf_counter() - t0
        await asyncio.sleep(0.25)
    return None


def open_doc(b: Bench, path: Path, text: str) -> str:
    uri = path.as_uri()
    b.client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id=path.suffix.lstrip("."), version=1, text=text)))
    return uri


async def stop(b: Bench) -> None:
    await b.client.shutdown_async(None)
    b.client.exit(None)
    await b.client.stop()


async def configurator(b: Bench, uri: str, op: str, params: Optional[dict] = None):
    return await b.client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="tvl-lsp.configurator", arguments=[uri, op] + ([params] if params is not None else [])))


async def clicks(b: Bench, uri: str, feats: list[str], n: int, seed: int = 1) -> list[float]:
    """``n`` configurator decisions (random open features, included or excluded; a refused one
    is not kept), each timed from the decide request to the answer of the counts request that
    follows it (the remaining count and every feature's count under all decisions)."""
    rng = random.Random(seed)
    c = await configurator(b, uri, "counts", {"wait": 10, "timeout": 60})
    assert not c.get("pending"), c
    times = []
    for _ in range(n):
        open_ = [f for f, v in c["features"].items() if v not in ("0", c["remaining"])]
        if not open_:
            break
        f = rng.choice(sorted(open_))
        t = time.perf_counter()
        r = await configurator(b, uri, "decide", {"feature": f, "value": rng.random() < 0.5})
        c = await configurator(b, uri, "counts", {"wait": 10, "timeout": 60})
        times.append(time.perf_counter() - t)
        assert not c.get("pending") and c.get("complete", True), c
        assert len(c["features"]) >= len(feats) - 1, len(c["features"])
        if not r.get("ok"):
            print(f"  decision on {f} refused")
    return times


async def run(args) -> int:
    src = Path(args.models) / ("uvl" if args.uvl else "dimacs") / f"{args.model}.{'uvl' if args.uvl else 'dimacs'}"
    if not src.exists():
        print(f"bench_hover_counts: no {src} (pass --models DIR); nothing measured")
        return 0
    tmp = Path(tempfile.mkdtemp(prefix="hover-"))
    os.environ["TVL_LSP_CACHE_DIR"] = str(tmp / "cache")
    ws = tmp / "ws"
    ws.mkdir()
    if args.uvl:
        text = src.read_text()
        feats = uvl_features(text)
        model = ws / src.name
    else:
        text, feats = dimacs_to_tvl(src.read_text(), "Model")
        model = ws / f"{args.model}.tvl"
    model.write_text(text)
    lines = text.splitlines()

    def pos(name):
        for i, ln in enumerate(lines):
            words = ln.strip().rstrip(",").split(" ")
            if (args.uvl and words[0] == name) or (not args.uvl and words[:2] == ["opt", name]):
                return types.Position(line=i, character=ln.index(name) + 1)
        raise KeyError(name)

    print(f"{model.name}: {len(feats)} features")
    b = Bench()
    await start(b, ws, args.budget)
    try:
        uri = open_doc(b, model, text)
        first = await first_counted_hover(b, uri, pos, feats[len(feats) // 2], args.timeout)
        if first is None:
            print(f"no counted hover within {args.timeout:g} s")
            return 1
        print(f"cold: first counted hover {first:.2f} s after opening (empty cache)")
        times = []
        for name in feats[1:: max(1, len(feats) // 40)][:40]:
            dt, md = await b.hover(uri, pos(name))
            assert "products**" in md, md
            times.append(dt)
        print(f"hover with counts: median {statistics.median(times) * 1000:.0f} ms, "
              f"max {max(times) * 1000:.0f} ms over {len(times)} features")
        if args.clicks:
            ct = await clicks(b, uri, feats, args.clicks)
            print(f"configurator click (decide -> every count): median {statistics.median(ct) * 1000:.0f} ms, "
                  f"max {max(ct) * 1000:.0f} ms over {len(ct)} decisions")
    finally:
        await stop(b)
    for i in range(args.reopen):
        b = Bench()
        await start(b, ws, args.budget)
        try:
            uri = open_doc(b, model, text)
            again = await first_counted_hover(b, uri, pos, feats[(i + 1) * len(feats) // (args.reopen + 2)],
                                              args.timeout)
            print(f"reopen {i + 1} (compiled before): first counted hover "
                  + (f"{again:.2f} s after opening" if again is not None else f"none within {args.timeout:g} s"))
        finally:
            await stop(b)
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
            "from tvl_lsp.analysis.formats import parse_any_model\n"
            "from tvl_lsp.analysis.engine import ModelAnalysis\n"
            "a = ModelAnalysis(parse_any_model(open(sys.argv[1]).read(), sys.argv[1]).model); c = a.counter\n"
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
    ap.add_argument("--uvl", action="store_true", help="open uvl/<model>.uvl instead of the DIMACS twin as TVL")
    ap.add_argument("--clicks", type=int, default=10, help="configurator decisions to time")
    ap.add_argument("--reopen", type=int, default=2, help="fresh servers opening the compiled model")
    return asyncio.run(run(ap.parse_args()))


if __name__ == "__main__":
    sys.exit(main())
