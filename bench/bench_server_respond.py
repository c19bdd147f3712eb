"""How soon the language server answers, on an idle and on a busy machine (issue #28: 14, 15, 12).

    .venv/bin/python bench/bench_server_respond.py first   [--busy N] [--repeat 5]
    .venv/bin/python bench/bench_server_respond.py actions [--busy N] [--editors 4] [--keys 60]
    .venv/bin/python bench/bench_server_respond.py hover   [--busy N] [--model PATH.uvl] [--repeat 2]
    .venv/bin/python bench/bench_server_respond.py memory  [--model PATH] [--cycles 12]
    .venv/bin/python bench/bench_server_respond.py soak    [--model PATH] [--minutes 10]

``--busy N`` starts N processes that only burn CPU (``python -c 'while 1: pass'``, at normal
priority: a background build) before the servers and stops them at the end; ``--busy 2x``
means two per core.  Every server is a fresh ``tvl-lsp`` on stdio with an empty counting cache
(``TVL_LSP_CACHE_DIR`` in a scratch folder), a push-diagnostics client (Neovim's way: no pull).

- ``first``: a generated two-node launch file paired with a three-feature model (a ROS package
  in a scratch workspace), opened right after ``initialized``.  Times from ``didOpen`` to the
  first ``publishDiagnostics`` of the file, to the first one holding the solver-free finding
  (``unmatched-arg``: an arg naming no feature, a typo of one) and to the first holding the solver-backed one
  (``dead-element``: a node no product loads).
- ``actions``: ``--editors`` editors (each its own server, as four editor windows are) type
  into their launch file at once (one key every ``--interval`` s, inside a comment) and, after
  every key, ask for the code actions at an ``unmatched-arg`` (as VS Code does on every cursor
  move and diagnostics change): the latency of every ``codeAction`` (p50 / p95 / max) and how
  many answers held a quick fix (the light bulb).  ``--ws DIR --launch REL --at TEXT``: type
  into another launch file (e.g. the thesis's lizi) and ask at TEXT.
- ``hover``: opens ``--model`` (default: automotive01.uvl of the shared models) and hovers a
  feature every 0.25 s until the hover shows its count: the time from opening to the first
  counted hover.
- ``memory``: opens ``--model`` (default: automotive01.uvl), then ``--cycles`` times replaces its
  text by an edited one (a feature renamed everywhere: a new model to check and count) and
  restores it, waiting for each text's check; prints the RSS of the server and of its worker
  processes (with their d4 children) after the first check, after each cycle, and idle at the
  end.
- ``soak``: an hour of editing, compressed: ``--minutes`` of edits (bursts of keys, a feature
  renamed, lines deleted, undos) to the big model and the robot's launch file, a key every
  ``--interval`` s on average, with hovers, code actions and code lenses; the tree's RSS every
  ``--sample`` s, then idle.

Prints one line per measure with the machine's load (``os.getloadavg``).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional

from lsprotocol import types
from pygls.lsp.client import LanguageClient

REPO = Path(__file__).resolve().parents[1]
SHARED_MODELS = REPO.parent / "shared" / "models"
KEEP = False  # --keep: leave the scratch folders (server logs) in place

MODEL = """\
// a three-feature robot
root Robot {
  group allOf {
    opt Lidar,
    opt Nav,
    opt Camera
  }
  Nav -> Lidar;
}
"""

LAUNCH = """\
<launch>
  <!-- the generic launch file of robot.tvl -->
  <arg name="Robot"/>
  <arg name="Lidar"/>
  <arg name="Nav"/>
  <arg name="Camra"/>

  <node pkg="lidar_driver" type="lidar_node" name="lidar" if="$(arg Lidar)"/>
  <group if="$(arg Nav)">
    <node pkg="move_base" type="move_base" name="planner" unless="$(arg Lidar)"/>
  </group>
</launch>
"""


def pct(xs, p):
    xs = sorted(xs)
    if not xs:
        return float("nan")
    return xs[min(len(xs) - 1, max(0, int(round(p / 100 * (len(xs) - 1)))))]


def fmt(xs) -> str:
    if not xs:
        return "no samples"
    return (f"n={len(xs)} p50={pct(xs, 50) * 1000:.0f} ms p95={pct(xs, 95) * 1000:.0f} ms "
            f"max={max(xs) * 1000:.0f} ms")


def load() -> str:
    a, b, c = os.getloadavg()
    return f"load {a:.1f} {b:.1f} {c:.1f} on {os.cpu_count()} cores"


# ------------------------------------------------------------------ the machine's other work

class Busy:
    """``n`` processes that burn CPU at normal priority until stopped."""

    def __init__(self, n: int):
        self.procs = [subprocess.Popen([sys.executable, "-c", "while 1: pass"]) for _ in range(n)]

    def stop(self) -> None:
        for p in self.procs:
            p.kill()
        for p in self.procs:
            p.wait()


def busy_count(spec: str) -> int:
    if spec.endswith("x"):
        return int(spec[:-1] or 1) * (os.cpu_count() or 1)
    return int(spec)


# ------------------------------------------------------------------ a client

class Editor:
    """One editor: a fresh server on stdio and a push-diagnostics client."""

    def __init__(self, scratch: Path, name: str = "bench"):
        self.client = LanguageClient(name, "1")
        self.scratch = scratch
        self.published: list[tuple[float, str, Optional[int], list]] = []  # (time, uri, version, diags)
        self.event = asyncio.Event()

        @self.client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def on_diags(params: types.PublishDiagnosticsParams):
            self.published.append((time.perf_counter(), params.uri, params.version, list(params.diagnostics)))
            self.event.set()

        @self.client.feature(types.WORKSPACE_CONFIGURATION)
        def on_config(params):
            return [{} for _ in params.items]

        @self.client.feature(types.WINDOW_WORK_DONE_PROGRESS_CREATE)
        def on_progress_create(params):
            return None

        @self.client.feature(types.PROGRESS)
        def on_progress(params):
            return None

        @self.client.feature(types.WORKSPACE_CODE_LENS_REFRESH)
        def on_lens_refresh(params):
            return None

    async def start(self, root: Path, options: Optional[dict] = None) -> None:
        env = dict(os.environ, TVL_LSP_CACHE_DIR=str(self.scratch / "cache"),
                   TVL_LSP_LOGFILE=str(self.scratch / "server.log"),
                   TVL_LSP_LOG=os.environ.get("TVL_LSP_LOG", "INFO"))
        self.client_env = env
        await self.client.start_io(sys.executable, "-m", "tvl_lsp", env=env)
        caps = types.ClientCapabilities(
            window=types.WindowClientCapabilities(work_done_progress=True),
            workspace=types.WorkspaceClientCapabilities(configuration=True),
            text_document=types.TextDocumentClientCapabilities(
                hover=types.HoverClientCapabilities(content_format=[types.MarkupKind.Markdown]),
                code_action=types.CodeActionClientCapabilities(
                    code_action_literal_support=types.ClientCodeActionLiteralOptions(
                        code_action_kind=types.ClientCodeActionKindOptions(value_set=["quickfix", "source"]))),
                publish_diagnostics=types.PublishDiagnosticsClientCapabilities(version_support=True)))
        await self.client.initialize_async(types.InitializeParams(
            capabilities=caps, root_uri=root.as_uri(), initialization_options=options or {},
            workspace_folders=[types.WorkspaceFolder(uri=root.as_uri(), name="ws")]))
        self.client.initialized(types.InitializedParams())

    @property
    def pid(self) -> Optional[int]:
        proc = getattr(self.client, "_server", None)
        return getattr(proc, "pid", None)

    def open(self, path: Path, text: str, lang: str = "xml") -> str:
        uri = path.as_uri()
        self.client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
            uri=uri, language_id=lang, version=1, text=text)))
        return uri

    def change(self, uri: str, version: int, rng: Optional[types.Range], text: str) -> None:
        change = (types.TextDocumentContentChangePartial(range=rng, text=text) if rng is not None
                  else types.TextDocumentContentChangeWholeDocument(text=text))
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[change]))

    async def wait_for(self, pred, timeout: float) -> Optional[float]:
        """The time of the first publication satisfying ``pred(uri, version, diags)``."""
        end = time.perf_counter() + timeout
        seen = 0
        while True:
            for t, uri, version, diags in self.published[seen:]:
                if pred(uri, version, diags):
                    return t
            seen = len(self.published)
            left = end - time.perf_counter()
            if left <= 0:
                return None
            self.event.clear()
            try:
                await asyncio.wait_for(self.event.wait(), left)
            except asyncio.TimeoutError:
                return None

    async def stop(self) -> None:
        try:
            await asyncio.wait_for(self.client.shutdown_async(None), 10)
            self.client.exit(None)
        except Exception:
            pass
        try:
            await asyncio.wait_for(self.client.stop(), 10)
        except Exception:
            pass


def robot_ws(root: Path) -> tuple[Path, Path]:
    pkg = root / "src" / "robot"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package format=\"2\"><name>robot</name></package>\n")
    (pkg / "launch" / "robot.tvl").write_text(MODEL)
    (pkg / "launch" / "robot.launch").write_text(LAUNCH)
    return pkg / "launch" / "robot.launch", pkg / "launch" / "robot.tvl"


def has(code: str):
    return lambda diags: any(str(d.code) == code for d in diags)


# ------------------------------------------------------------------ first diagnostics

async def first_once(i: int) -> dict:
    scratch = Path(tempfile.mkdtemp(prefix="tvl-first-"))
    launch, _ = robot_ws(scratch / "ws")
    ed = Editor(scratch)
    try:
        await ed.start(scratch / "ws")
        t0 = time.perf_counter()
        uri = ed.open(launch, launch.read_text())
        res = {}
        for label, pred in (("any", lambda d: True), ("unmatched-arg", has("unmatched-arg")),
                            ("dead-element", has("dead-element"))):
            t = await ed.wait_for(lambda u, v, d: u == uri and pred(d), 120)
            res[label] = None if t is None else t - t0
        return res
    finally:
        await ed.stop()
        shutil.rmtree(scratch, ignore_errors=True)


async def first(args) -> None:
    runs = []
    for i in range(args.repeat):
        runs.append(await first_once(i))
        await asyncio.sleep(0.5)
    print(f"# first diagnostics of a two-node launch file in a fresh server, {args.repeat} runs, "
          f"{args.busy_n} busy processes, {load()}")
    for label in ("any", "unmatched-arg", "dead-element"):
        xs = [r[label] for r in runs if r[label] is not None]
        print(f"didOpen -> first {label:14s} {fmt(xs)}  (missing: {args.repeat - len(xs)}) "
              f"runs: {' '.join(f'{x:.2f}' for x in xs)}")


# ------------------------------------------------------------------ code actions while typing

async def actions(args) -> None:
    eds = []
    scratch = Path(tempfile.mkdtemp(prefix="tvl-actions-"))
    try:
        for i in range(args.editors):
            d = scratch / f"e{i}"
            if args.ws:
                shutil.copytree(args.ws, d / "ws", symlinks=True)
                launch = d / "ws" / args.launch
            else:
                launch, _ = robot_ws(d / "ws")
            ed = Editor(d, f"editor{i}")
            await ed.start(d / "ws")
            eds.append((ed, launch))
        t_open = time.perf_counter()
        results = await asyncio.gather(*(type_and_ask(ed, launch, args) for ed, launch in eds))
        lat = [x for r in results for x in r["lat"]]
        bulbs = sum(r["bulbs"] for r in results)
        asked = sum(len(r["lat"]) for r in results)
        name = args.launch or "robot.launch"
        print(f"# codeAction while {args.editors} editors type in {Path(name).name} (a key every "
              f"{args.interval * 1000:.0f} ms, {args.keys} keys each), {args.busy_n} busy processes, {load()}")
        print(f"codeAction at `{args.at}`   {fmt(lat)}  quick fix offered in {bulbs} of {asked} answers")
        print(f"  (typing took {time.perf_counter() - t_open:.1f} s)")
    finally:
        for ed, _ in eds:
            await ed.stop()
        shutil.rmtree(scratch, ignore_errors=True)


async def full_check_of(ed: Editor, uri: str, version: int, timeout: float = 300) -> None:
    """Until the results of ``version`` come from its full check (documentState)."""
    end = time.perf_counter() + timeout
    while time.perf_counter() < end:
        st = await ed.client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="tvl-lsp.documentState", arguments=[uri]))
        if "phase" not in st:  # (a server before #28: its first publication, then 3 s)
            await ed.wait_for(lambda u, v, d: u == uri and v == version, timeout)
            await asyncio.sleep(3)
            return
        if st["phase"] == "full" and st["resultVersion"] == version:
            return
        await asyncio.sleep(0.2)


async def type_and_ask(ed: Editor, launch: Path, args) -> dict:
    """Open the launch file, wait for its first full check, then type into a comment of a
    line of its own below ``<launch>`` (so that the file stays valid), and ask for the code
    actions at ``args.at`` after every key."""
    text = launch.read_text()
    uri = ed.open(launch, text)
    await full_check_of(ed, uri, 1)
    lines = text.split("\n")
    cline = next(i for i, ln in enumerate(lines) if "<launch" in ln) + 1
    opener = "  <!-- "
    ed.change(uri, 2, types.Range(start=types.Position(line=cline, character=0),
                                  end=types.Position(line=cline, character=0)), opener + " -->\n")
    text = "\n".join(lines[:cline] + [opener + " -->"] + lines[cline:])
    lines = text.split("\n")
    col = len(opener)
    i = text.index(args.at)
    aline = text.count("\n", 0, i)
    acol = i - (text.rfind("\n", 0, i) + 1) + 1
    at = types.Range(start=types.Position(line=aline, character=acol), end=types.Position(line=aline, character=acol))
    lat, bulbs = [], 0
    version = 2
    typed = 0
    for k in range(args.keys):
        version += 1
        if k % 10 < 7:  # type, then erase some (the file stays valid)
            pos = types.Position(line=cline, character=col + typed)
            ed.change(uri, version, types.Range(start=pos, end=pos), "x")
            typed += 1
        else:
            a = types.Position(line=cline, character=col + typed - 1)
            b = types.Position(line=cline, character=col + typed)
            ed.change(uri, version, types.Range(start=a, end=b), "")
            typed -= 1
        await asyncio.sleep(args.ask_after)  # (VS Code asks as soon as the cursor moves)
        t = time.perf_counter()
        got = await ed.client.text_document_code_action_async(types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(uri=uri), range=at,
            context=types.CodeActionContext(diagnostics=[], trigger_kind=types.CodeActionTriggerKind.Automatic)))
        lat.append(time.perf_counter() - t)
        if any(getattr(a, "kind", None) == types.CodeActionKind.QuickFix for a in got or []):
            bulbs += 1
        await asyncio.sleep(max(0.0, args.interval - (time.perf_counter() - t)))
    return {"lat": lat, "bulbs": bulbs}


# ------------------------------------------------------------------ first counted hover

def uvl_feature_line(text: str) -> tuple[int, int, str]:
    """(line, column, name) of a feature declared about the middle of a UVL model."""
    lines = text.split("\n")
    cands = []
    inside = False
    for i, ln in enumerate(lines):
        if ln.startswith("features"):
            inside = True
            continue
        if ln and not ln[0].isspace():
            inside = False
        w = ln.strip().split(" ", 1)[0] if ln.strip() else ""
        if inside and w and w not in ("mandatory", "optional", "alternative", "or") and not w.startswith(("[", "//")):
            cands.append((i, ln.index(w) + 1, w.strip('"')))
    return cands[len(cands) // 2]


async def hover_once(model: Path, timeout: float) -> dict:
    scratch = Path(tempfile.mkdtemp(prefix="tvl-hover-"))
    ws = scratch / "ws"
    ws.mkdir()
    dst = ws / model.name
    text = model.read_text()
    dst.write_text(text)
    line, col, name = uvl_feature_line(text)
    ed = Editor(scratch)
    out: dict = {"first": None, "says": []}
    try:
        await ed.start(ws)
        t0 = time.perf_counter()
        uri = ed.open(dst, text, dst.suffix.lstrip("."))
        while time.perf_counter() - t0 < timeout:
            h = await ed.client.text_document_hover_async(types.HoverParams(
                text_document=types.TextDocumentIdentifier(uri=uri),
                position=types.Position(line=line, character=col)))
            md = h.contents.value if h else ""
            last = md.strip().splitlines()[-1] if md.strip() else "(no hover)"
            if not out["says"] or out["says"][-1][1] != last:
                out["says"].append((time.perf_counter() - t0, last))
            if "products**" in md:
                out["first"] = time.perf_counter() - t0
                break
            await asyncio.sleep(0.25)
        return out
    finally:
        await ed.stop()
        if KEEP:
            print(f"  (server log: {scratch / 'server.log'})")
        else:
            shutil.rmtree(scratch, ignore_errors=True)


async def hover(args) -> None:
    model = Path(args.model or SHARED_MODELS / "uvl" / "automotive01.uvl")
    if not model.exists():
        print(f"bench_server_respond: no {model} (pass --model PATH); nothing measured")
        return
    runs = []
    for _ in range(args.repeat):
        runs.append(await hover_once(model, args.timeout))
    print(f"# first counted hover on {model.name}, fresh server, empty cache, {args.busy_n} busy processes, {load()}")
    xs = [r["first"] for r in runs if r["first"] is not None]
    print(f"didOpen -> first counted hover  {fmt(xs)}  (none within {args.timeout:g} s: {args.repeat - len(xs)}) "
          f"runs: {' '.join(f'{x:.2f}' for x in xs)}")
    for r in runs:
        print("  the hover said: " + "; ".join(f"{t:.1f} s: {s[:70]}" for t, s in r["says"]))


# ------------------------------------------------------------------ memory over edit cycles

def rss_kb(pid: int) -> int:
    try:
        with open(f"/proc/{pid}/status") as fh:
            for ln in fh:
                if ln.startswith("VmRSS:"):
                    return int(ln.split()[1])
    except OSError:
        pass
    return 0


def descendants(pid: int) -> list[int]:
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        try:
            with open(f"/proc/{p}/task/{p}/children") as fh:
                kids = [int(x) for x in fh.read().split()]
        except OSError:
            kids = []
        out += kids
        todo += kids
    return out


def tree_mb(pid: int) -> tuple[float, float]:
    """(server MB, worker processes MB)."""
    return rss_kb(pid) / 1024, sum(rss_kb(c) for c in descendants(pid)) / 1024


async def memory(args) -> None:
    model = Path(args.model or SHARED_MODELS / "uvl" / "automotive01.uvl")
    if not model.exists():
        print(f"bench_server_respond: no {model} (pass --model PATH); nothing measured")
        return
    scratch = Path(tempfile.mkdtemp(prefix="tvl-mem-"))
    ws = scratch / "ws"
    ws.mkdir()
    dst = ws / model.name
    text = model.read_text()
    dst.write_text(text)
    ed = Editor(scratch)
    try:
        await ed.start(ws, {"count": {"timeBudget": 30}})
        pid = ed.pid
        uri = ed.open(dst, text, dst.suffix.lstrip("."))
        version = 1

        async def settle(v):
            # this text's full check (documentState says which check the results come from)
            end = time.perf_counter() + 600
            while time.perf_counter() < end:
                st = await ed.client.workspace_execute_command_async(types.ExecuteCommandParams(
                    command="tvl-lsp.documentState", arguments=[uri]))
                if "phase" not in st:  # (a server before #28: the first publication, then 3 s)
                    await ed.wait_for(lambda u, vv, d: u == uri and vv == v, 300)
                    await asyncio.sleep(3)
                    break
                if st["phase"] == "full" and st["resultVersion"] == v:
                    break
                await asyncio.sleep(0.25)
            # and its counts (the code lens says "counting products…" until they are there)
            while time.perf_counter() < end:
                lens = await ed.client.text_document_code_lens_async(types.CodeLensParams(
                    text_document=types.TextDocumentIdentifier(uri=uri)))
                title = lens[0].command.title if lens and lens[0].command else ""
                if "counting" not in title:
                    break
                await asyncio.sleep(0.5)
            await asyncio.sleep(args.settle)
        await settle(version)
        s0, w0 = tree_mb(pid)
        print(f"# memory over edit/restore cycles of {model.name}, {load()}")
        print(f"after the first check      server {s0:7.0f} MB  workers {w0:7.0f} MB  total {s0 + w0:7.0f} MB")
        t_start = time.perf_counter()
        for c in range(args.cycles):
            if dst.suffix == ".uvl":
                line, col, name = uvl_feature_line(text)
                edited = text.replace(name, f"{name}_{c}")
            else:  # a comment: a new text (parse, encoding, check) of the same formula
                edited = text.replace("\n", f"\nc edit {c}\n", 1)
            version += 1
            ed.change(uri, version, None, edited)
            await settle(version)
            version += 1
            ed.change(uri, version, None, text)
            await settle(version)
            s, w = tree_mb(pid)
            print(f"after cycle {c + 1:3d}            server {s:7.0f} MB  workers {w:7.0f} MB  total {s + w:7.0f} MB"
                  f"  ({(s + w) / (s0 + w0):.2f}x, {time.perf_counter() - t_start:.0f} s)")
        await asyncio.sleep(args.idle)
        s, w = tree_mb(pid)
        print(f"idle {args.idle:g} s after           server {s:7.0f} MB  workers {w:7.0f} MB  total {s + w:7.0f} MB"
              f"  ({(s + w) / (s0 + w0):.2f}x)")
    finally:
        await ed.stop()
        shutil.rmtree(scratch, ignore_errors=True)


async def soak(args) -> None:
    """An hour of editing, compressed: the big model and the robot's launch file edited
    for ``--minutes`` (bursts of keys in comments, a feature renamed and renamed back, lines
    deleted and typed again), with hovers, code actions and code lenses meanwhile; the process
    tree's RSS every ``--sample`` seconds, and idle at the end."""
    import random
    model = Path(args.model or SHARED_MODELS / "uvl" / "automotive01.uvl")
    if not model.exists():
        print(f"bench_server_respond: no {model} (pass --model PATH); nothing measured")
        return
    rng = random.Random(args.seed)
    scratch = Path(tempfile.mkdtemp(prefix="tvl-soak-"))
    launch, _ = robot_ws(scratch / "ws")
    big = scratch / "ws" / model.name
    shutil.copy(model, big)
    ed = Editor(scratch)
    try:
        await ed.start(scratch / "ws", {"count": {"timeBudget": 30}})
        pid = ed.pid
        docs = {}
        for p in (big, launch):
            text = p.read_text()
            docs[ed.open(p, text, p.suffix.lstrip("."))] = [text, 1, text]
        for uri in docs:
            await full_check_of(ed, uri, 1, 600)
        await asyncio.sleep(args.settle)
        s0, w0 = tree_mb(pid)
        print(f"# soak: {args.minutes:g} min of edits to {model.name} and robot.launch, {load()}")
        print(f"after the first checks   server {s0:7.0f} MB  workers {w0:7.0f} MB  total {s0 + w0:7.0f} MB")
        peak = s0 + w0
        t0 = time.perf_counter()
        next_sample = t0 + args.sample
        edits = 0
        while time.perf_counter() - t0 < args.minutes * 60:
            uri = rng.choice(list(docs))
            text, version, original = docs[uri]
            r = rng.random()
            if r < 0.05:
                new = original  # undo everything
            elif r < 0.15 and uri.endswith(".uvl"):
                line, col, name = uvl_feature_line(original)
                new = text.replace(name, name + "x") if name in text else original
            elif r < 0.25:
                lines = text.split("\n")
                i = rng.randrange(len(lines))
                new = "\n".join(lines[:i] + lines[i + 1:])  # a line deleted
            else:
                # a few keys in a comment at a random line
                lines = text.split("\n")
                i = rng.randrange(1, len(lines))
                c = "//" if uri.endswith(".uvl") else "<!--"
                end = "" if uri.endswith(".uvl") else " -->"
                word = "".join(rng.choice("abcdefgh ") for _ in range(rng.randint(1, 8)))
                lines.insert(i, f"{c} {word}{end}" if not uri.endswith(".uvl") else f"\t{c} {word}")
                new = "\n".join(lines)
            version += 1
            ed.change(uri, version, None, new)
            docs[uri] = [new, version, original]
            edits += 1
            if edits % 10 == 0:
                lines = new.split("\n")
                pos = types.Position(line=rng.randrange(len(lines)), character=2)
                tdi = types.TextDocumentIdentifier(uri=uri)
                await ed.client.text_document_hover_async(types.HoverParams(text_document=tdi, position=pos))
                await ed.client.text_document_code_action_async(types.CodeActionParams(
                    text_document=tdi, range=types.Range(start=pos, end=pos),
                    context=types.CodeActionContext(diagnostics=[])))
                if uri.endswith(".uvl"):
                    await ed.client.text_document_code_lens_async(types.CodeLensParams(text_document=tdi))
            await asyncio.sleep(rng.expovariate(1.0 / args.interval))
            if time.perf_counter() >= next_sample:
                next_sample += args.sample
                s, w = tree_mb(pid)
                peak = max(peak, s + w)
                print(f"{time.perf_counter() - t0:6.0f} s {edits:6d} edits  server {s:7.0f} MB  workers {w:7.0f} MB"
                      f"  total {s + w:7.0f} MB  ({(s + w) / (s0 + w0):.2f}x)")
        for uri in docs:
            await full_check_of(ed, uri, docs[uri][1], 600)
        await asyncio.sleep(args.idle)
        s, w = tree_mb(pid)
        print(f"idle {args.idle:g} s after {edits} edits: server {s:7.0f} MB  workers {w:7.0f} MB  total {s + w:7.0f} MB"
              f"  ({(s + w) / (s0 + w0):.2f}x; peak {peak / (s0 + w0):.2f}x)")
    finally:
        await ed.stop()
        shutil.rmtree(scratch, ignore_errors=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["first", "actions", "hover", "memory", "soak"])
    ap.add_argument("--busy", default="0", help="CPU-burning processes meanwhile: N, or Nx (N per core)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--editors", type=int, default=4)
    ap.add_argument("--keys", type=int, default=60)
    ap.add_argument("--interval", type=float, default=0.15, help="seconds between keys")
    ap.add_argument("--ask-after", type=float, default=0.0, help="actions: seconds from a key to the request")
    ap.add_argument("--ws", help="actions: a workspace to copy (default: a generated robot package)")
    ap.add_argument("--launch", help="actions: the launch file typed into, relative to --ws")
    ap.add_argument("--at", default="Camra", help="actions: the text whose code actions are asked for")
    ap.add_argument("--keep", action="store_true", help="keep the scratch folders (server logs)")
    ap.add_argument("--model", help="the model of 'hover' and 'memory' (default: automotive01.uvl)")
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--cycles", type=int, default=12)
    ap.add_argument("--settle", type=float, default=1.0, help="memory: seconds after each text's counts")
    ap.add_argument("--idle", type=float, default=10.0, help="memory, soak: seconds idle at the end")
    ap.add_argument("--minutes", type=float, default=10.0, help="soak: minutes of editing")
    ap.add_argument("--sample", type=float, default=30.0, help="soak: seconds between RSS samples")
    ap.add_argument("--seed", type=int, default=1, help="soak: the edits' random seed")
    args = ap.parse_args()
    args.busy_n = busy_count(args.busy)
    global KEEP
    KEEP = args.keep
    if args.what == "hover" and "--repeat" not in sys.argv:
        args.repeat = 2
    busy = Busy(args.busy_n)
    try:
        if args.busy_n:
            time.sleep(2.0)  # the load is there before the servers start
        asyncio.run({"first": first, "actions": actions, "hover": hover, "memory": memory,
                     "soak": soak}[args.what](args))
    finally:
        busy.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
