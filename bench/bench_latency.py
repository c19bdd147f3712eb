"""Language server latency: didChange -> publishDiagnostics and hover response times.

    .venv/bin/python bench/bench_latency.py [--edits 200] [--interval 0.05] [--workspace thesis|repo|DIR]

Starts ``tvl-lsp`` on stdio on a copy of a workspace (plus a generated 2,000-feature model),
with a push-diagnostics client, and:

1. types into each file (one incremental insertion every ``--interval`` seconds, as a fast
   typist) and measures, for every version, the time from sending ``didChange`` to receiving
   the first ``publishDiagnostics`` for that version;
2. hovers features while idle;
3. hovers a feature while the server counts the 2,000-feature model's products per feature
   (a long count in the worker process).

The workspace: ``thesis`` (default: the HAROS-TVL thesis's workspace, lizi, turtlebot and
turtlerand, at ../shared/corpus/thesis/ws on the team's machines; the published figures), a
folder holding a copy of it, or ``repo`` (the repository's own test workspace, examples/ws +
tests/data/ws: scout, crawler and turtlerand; always there).

Prints p50 / p95 / max in milliseconds.  Goals: typing in the thesis files p50 <= 30 ms,
p95 <= 100 ms; hover <= 50 ms while a count runs.
"""

from __future__ import annotations

import argparse
import asyncio
import shutil
import sys
import tempfile
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

REPO = Path(__file__).resolve().parents[1]
THESIS_WS = REPO.parent / "shared" / "corpus" / "thesis" / "ws"
sys.path.insert(0, str(Path(__file__).resolve().parent))
from gen_model import generate_model  # noqa: E402

# per workspace: the files typed into, then the model / launch file hovered, the feature and
# the arg hovered there, and the model's product count (seen in a counted hover)
PROFILES = {
    "thesis": dict(files=[
        ("lizi model", "src/lizi/launch/generic.tvl"),
        ("lizi launch", "src/lizi/launch/generic.launch"),
        ("turtlebot model", "src/turtlebot/launch/turtlebot.tvl"),
        ("turtlebot launch", "src/turtlebot_bringup/launch/generic.launch"),
        ("turtlerand launch", "src/turtlerand/launch/generic.launch"),
    ], model="src/lizi/launch/generic.tvl", launch="src/lizi/launch/generic.launch", robot="lizi",
        feature="Gmapping", arg='"Gazebo', total="2304"),
    "repo": dict(files=[
        ("scout model", "src/scout/launch/generic.tvl"),
        ("scout launch", "src/scout/launch/generic.launch"),
        ("crawler model", "src/crawler/models/crawler.tvl"),
        ("crawler launch", "src/crawler_bringup/launch/generic.launch"),
        ("turtlerand launch", "src/turtlerand/launch/generic.launch"),
    ], model="src/scout/launch/generic.tvl", launch="src/scout/launch/generic.launch", robot="scout",
        feature="Slam ->", arg='"Simulation', total="1152"),
}


def pct(xs, p):
    xs = sorted(xs)
    if not xs:
        return float("nan")
    k = min(len(xs) - 1, max(0, int(round(p / 100 * (len(xs) - 1)))))
    return xs[k]


def fmt(xs):
    return (f"n={len(xs):4d}  p50={pct(xs, 50) * 1000:7.1f} ms  p95={pct(xs, 95) * 1000:7.1f} ms  "
            f"max={max(xs) * 1000:7.1f} ms" if xs else "no samples")


class Bench:
    def __init__(self):
        self.client = LanguageClient("bench", "1")
        self.sent: dict[tuple[str, int], float] = {}
        self.got: dict[tuple[str, int], float] = {}

        @self.client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def on_diags(params: types.PublishDiagnosticsParams):
            key = (params.uri, params.version)
            if key in self.sent and key not in self.got:
                self.got[key] = time.perf_counter()

        @self.client.feature(types.WORKSPACE_CONFIGURATION)
        def on_config(params):
            return [{} for _ in params.items]

        @self.client.feature(types.WINDOW_WORK_DONE_PROGRESS_CREATE)
        def on_progress_create(params):
            return None

        @self.client.feature(types.PROGRESS)
        def on_progress(params):
            return None

    async def start(self, root: Path):
        # the server's log goes to a file: nobody reads this client's stderr pipe
        import os
        self.logfile = str(root.parent / "server.log")
        os.environ["TVL_LSP_LOGFILE"] = self.logfile
        await self.client.start_io(sys.executable, "-m", "tvl_lsp")
        caps = types.ClientCapabilities(
            window=types.WindowClientCapabilities(work_done_progress=True),
            workspace=types.WorkspaceClientCapabilities(configuration=True),
            text_document=types.TextDocumentClientCapabilities(
                hover=types.HoverClientCapabilities(content_format=[types.MarkupKind.Markdown]),
                publish_diagnostics=types.PublishDiagnosticsClientCapabilities(version_support=True)))
        await self.client.initialize_async(types.InitializeParams(
            capabilities=caps, root_uri=root.as_uri(),
            workspace_folders=[types.WorkspaceFolder(uri=root.as_uri(), name="ws")]))
        self.client.initialized(types.InitializedParams())

    def open(self, path: Path, text: str) -> str:
        uri = path.as_uri()
        self.client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
            uri=uri, language_id="tvl" if path.suffix == ".tvl" else "xml", version=1, text=text)))
        return uri

    async def typing(self, uri: str, text: str, edits: int, interval: float) -> list[float]:
        """Open a closed comment at the end of the first line, type words into it character by
        character, then erase them (the rest of the file stays analysed as it is)."""
        first = text.split("\n", 1)[0]
        line = 0
        opener, closer = ("<!-- ", " -->") if uri.endswith(".launch") else ("/* ", " */")
        col = len(first) + len(opener)
        version = 1
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version + 1),
            content_changes=[types.TextDocumentContentChangePartial(
                range=types.Range(start=types.Position(line=0, character=len(first)),
                                  end=types.Position(line=0, character=len(first))),
                text=opener + closer)]))
        version += 1
        await asyncio.sleep(0.3)
        typed = ""
        keys = list("typing in the editor ") * (edits // 20 + 1)
        for i in range(edits):
            version += 1
            if i < edits // 2:
                ch = keys[i]
                rng = types.Range(start=types.Position(line=line, character=col + len(typed)),
                                  end=types.Position(line=line, character=col + len(typed)))
                typed += ch
                new = ch
            else:
                rng = types.Range(start=types.Position(line=line, character=col + len(typed) - 1),
                                  end=types.Position(line=line, character=col + len(typed)))
                typed = typed[:-1]
                new = ""
            self.sent[(uri, version)] = time.perf_counter()
            self.client.text_document_did_change(types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[types.TextDocumentContentChangePartial(range=rng, text=new)]))
            await asyncio.sleep(interval)
        await asyncio.sleep(1.0)
        # a keystroke is shown once diagnostics for its version or a later one arrive
        out = []
        got = sorted((v, t) for (u, v), t in self.got.items() if u == uri)
        for (u, v), t in self.sent.items():
            if u != uri:
                continue
            later = [tg for vg, tg in got if vg >= v and tg >= t]
            if later:
                out.append(min(later) - t)
        return out

    async def code_lens(self, uri: str):
        """What an editor asks when it shows a model (starts the counts)."""
        return await self.client.text_document_code_lens_async(types.CodeLensParams(
            text_document=types.TextDocumentIdentifier(uri=uri)))

    async def hover(self, uri: str, pos: types.Position) -> tuple[float, str]:
        t0 = time.perf_counter()
        h = await self.client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri), position=pos))
        return time.perf_counter() - t0, (h.contents.value if h else "")


def pos_of(text: str, needle: str, offset: int = 1) -> types.Position:
    i = text.index(needle) + offset
    return types.Position(line=text.count("\n", 0, i), character=i - (text.rfind("\n", 0, i) + 1))


async def main_async(args) -> int:
    tmp = Path(tempfile.mkdtemp(prefix="tvl-bench-"))
    ws = tmp / "ws"
    prof = PROFILES["repo" if args.workspace == "repo" else "thesis"]
    if args.workspace == "repo":
        shutil.copytree(REPO / "examples" / "ws", ws)
        shutil.copytree(REPO / "tests" / "data" / "ws", ws, dirs_exist_ok=True)
    else:
        shutil.copytree(args.workspace, ws)
    big_dir = ws / "src" / "big"
    big_dir.mkdir(parents=True)
    (big_dir / "package.xml").write_text("<package><name>big</name></package>\n")
    big = big_dir / "big.tvl"
    big.write_text(generate_model(2000, seed=1))
    b = Bench()
    await b.start(ws)
    print(f"# tvl-lsp latency, {args.edits} edits per file, one every {args.interval * 1000:.0f} ms")
    all_thesis = []
    for label, rel in prof["files"]:
        p = ws / rel
        text = p.read_text()
        uri = b.open(p, text)
        if p.suffix == ".tvl":
            await b.code_lens(uri)
        await asyncio.sleep(1.5)  # first analysis, counts
        lat = await b.typing(uri, text, args.edits, args.interval)
        all_thesis += lat
        print(f"didChange -> diagnostics  {label:18s} {fmt(lat)}")
    print(f"didChange -> diagnostics  {'all ' + prof['robot'] + ' files':18s} {fmt(all_thesis)}")
    text = big.read_text()
    uri_big = b.open(big, text)
    await asyncio.sleep(3)
    lat = await b.typing(uri_big, text, max(20, args.edits // 4), max(args.interval, 0.2))
    print(f"didChange -> diagnostics  {'2,000-feature model':18s} {fmt(lat)}")

    lizi = ws / prof["model"]
    ltext = lizi.read_text()
    uri_lizi = lizi.as_uri()
    pos = pos_of(ltext, prof["feature"])
    robot = prof["robot"]
    idle = []
    for _ in range(args.hovers):
        t, v = await b.hover(uri_lizi, pos)
        idle.append(t)
    print(f"hover (idle)              {robot + ' feature':18s} {fmt(idle)}   "
          f"[{prof['total'] in v and 'counted' or 'no count'}]")
    lpath = ws / prof["launch"]
    ltxt = lpath.read_text()
    idle = []
    for _ in range(args.hovers):
        t, v = await b.hover(lpath.as_uri(), pos_of(ltxt, prof["arg"], 2))
        idle.append(t)
    print(f"hover (idle)              {robot + ' <arg>':18s} {fmt(idle)}")

    # a long count: per-feature counts of the 2,000-feature model, started by a hover on it
    big2 = big_dir / "big2.tvl"
    big2_text = generate_model(2000, seed=2)
    big2.write_text(big2_text)
    uri_big2 = b.open(big2, big2_text)
    await b.code_lens(uri_lizi)
    await asyncio.sleep(1.0)
    t0 = time.perf_counter()
    asyncio.ensure_future(b.hover(uri_big2, pos_of(big2_text, "F10 ", 1)))
    await asyncio.sleep(0.2)
    during = []
    while time.perf_counter() - t0 < args.count_window:
        t, v = await b.hover(uri_lizi, pos)
        during.append(t)
        await asyncio.sleep(0.02)
    t, v = await b.hover(uri_big2, pos_of(big2_text, "F10 ", 1))
    counted = "of " in v
    print(f"hover during a count      {robot + ' feature':18s} {fmt(during)}   "
          f"[the 2,000-feature count {'finished' if counted else 'was still running'} after "
          f"{time.perf_counter() - t0:.1f} s]")
    log = Path(b.logfile).read_text() if Path(b.logfile).exists() else ""
    if log.strip():
        print("# server log:\n" + log[-3000:])
    await b.client.shutdown_async(None)
    b.client.exit(None)
    await asyncio.sleep(0.2)
    shutil.rmtree(tmp, ignore_errors=True)
    return 0


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--edits", type=int, default=200)
    ap.add_argument("--interval", type=float, default=0.05)
    ap.add_argument("--hovers", type=int, default=50)
    ap.add_argument("--count-window", type=float, default=5.0, help="seconds of hovering during the count")
    ap.add_argument("--workspace", default="thesis", metavar="thesis|repo|DIR",
                    help=f"thesis: {THESIS_WS} (default); repo: the repository's test workspace; "
                         "DIR: a copy of the thesis's workspace")
    args = ap.parse_args()
    if args.workspace not in ("thesis", "repo"):
        args.workspace = str(Path(args.workspace).resolve())
    elif args.workspace == "thesis":
        args.workspace = str(THESIS_WS)
    if args.workspace != "repo" and not (Path(args.workspace) / "src" / "lizi").is_dir():
        print(f"bench_latency.py: no thesis workspace (src/lizi, src/turtlebot...) at {args.workspace}: it is in "
              "the team's shared corpus (../shared/corpus/thesis/ws); pass --workspace DIR with a copy of it, "
              "or --workspace repo for the repository's own workspace", file=sys.stderr)
        return 2
    return asyncio.run(main_async(args))


if __name__ == "__main__":
    sys.exit(main())
