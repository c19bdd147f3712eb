"""Language server latency on ROS 2 Python launch files: a keystroke (didChange) -> the
diagnostics of that version (publishDiagnostics), as bench_latency.py measures it for models and
XML launch files.

    .venv/bin/python bench/bench_latency_ros2py.py [--edits 200] [--interval 0.05] [--py DIR ...] [--files N]

Starts ``tvl-lsp`` on stdio (a push-diagnostics client) on a copy of tests/data/ros2py_editor/ws
(the rover: ``rover.launch.py`` paired with ``rover.tvl``, its clean twin, an ``ld.add_action``
file) and, with ``--py``, of folders of real ROS 2 repositories (fetched, never committed), of
whose ``.launch.py`` / ``*_launch.py`` files ``--files`` are typed into (evenly spread over the
sorted list).  Into each file: a comment opened at the end of its first line, words typed into
it one character every ``--interval`` seconds, then erased, so the file stays what it is; for
every version, the time from sending ``didChange`` to the first ``publishDiagnostics`` of that
version or a later one (the quick pass: the file's own analysis).  Then, per file, the time from
the last keystroke to the diagnostics of the solver-backed check of the final text (``settle``:
debounce + check).  Prints p50 / p95 / max in milliseconds; the goal (issue #25) is p50 <= 50 ms
for a keystroke.
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_latency import Bench, fmt  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
FIXTURE = REPO / "tests" / "data" / "ros2py_editor" / "ws"
OWN = ["src/rover/launch/rover.launch.py", "src/rover/launch/clean.launch.py", "src/rover/launch/teleop_launch.py"]


class PyBench(Bench):
    def open(self, path: Path, text: str) -> str:
        uri = path.as_uri()
        self.client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
            uri=uri, language_id="python", version=1, text=text)))
        return uri

    async def typing_py(self, uri: str, text: str, edits: int, interval: float) -> tuple[list[float], float]:
        """(keystroke latencies, seconds from the last keystroke to the full check's diagnostics)."""
        first = text.split("\n", 1)[0]
        col = len(first) + 3
        version = 1
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version + 1),
            content_changes=[types.TextDocumentContentChangePartial(
                range=types.Range(start=types.Position(line=0, character=len(first)),
                                  end=types.Position(line=0, character=len(first))), text="  #")]))
        version += 1
        await asyncio.sleep(0.3)
        typed = ""
        keys = list(" typing in the editor") * (edits // 20 + 1)
        last = 0.0
        for i in range(edits):
            version += 1
            if i < edits // 2:
                ch = keys[i]
                rng = types.Range(start=types.Position(line=0, character=col + len(typed)),
                                  end=types.Position(line=0, character=col + len(typed)))
                typed += ch
                new = ch
            else:
                rng = types.Range(start=types.Position(line=0, character=col + len(typed) - 1),
                                  end=types.Position(line=0, character=col + len(typed)))
                typed = typed[:-1]
                new = ""
            last = self.sent[(uri, version)] = time.perf_counter()
            self.client.text_document_did_change(types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[types.TextDocumentContentChangePartial(range=rng, text=new)]))
            await asyncio.sleep(interval)
        settle = float("nan")
        while time.perf_counter() - last < 60:
            st = await self.client.workspace_execute_command_async(types.ExecuteCommandParams(
                command="tvl-lsp.documentState", arguments=[uri]))
            if st and st.get("phase") == "full" and st.get("resultVersion") == version:
                settle = time.perf_counter() - last
                break
            await asyncio.sleep(0.01)
        await asyncio.sleep(0.5)
        out = []
        got = sorted((v, t) for (u, v), t in self.got.items() if u == uri)
        for (u, v), t in self.sent.items():
            if u != uri:
                continue
            later = [tg for vg, tg in got if vg >= v and tg >= t]
            if later:
                out.append(min(later) - t)
        return out, settle


def spread(files: list[Path], n: int) -> list[Path]:
    if len(files) <= n:
        return files
    step = len(files) / n
    return [files[int(i * step)] for i in range(n)]


async def main_async(args) -> int:
    tmp = Path(tempfile.mkdtemp(prefix="tvl-bench-py-"))
    ws = tmp / "ws"
    shutil.copytree(FIXTURE, ws)
    targets = [(Path(rel).name, ws / rel) for rel in OWN]
    for i, d in enumerate(args.py or []):
        dst = tmp / f"real{i}"
        shutil.copytree(d, dst, symlinks=True, ignore=shutil.ignore_patterns(".git"))
        found = sorted(p for p in dst.rglob("*.py") if p.name.endswith((".launch.py", "_launch.py")))
        targets += [(str(p.relative_to(dst)), p) for p in spread(found, args.files)]
    b = PyBench()
    await b.start(tmp)
    print(f"# tvl-lsp latency on Python launch files, {args.edits} edits per file, one every "
          f"{args.interval * 1000:.0f} ms")
    every, settles = [], []
    for label, p in targets:
        text = p.read_text(encoding="utf-8", errors="replace")
        uri = b.open(p, text)
        await asyncio.sleep(1.5)  # first analysis, model counts
        lat, settle = await b.typing_py(uri, text, args.edits, args.interval)
        every += lat
        settles.append(settle)
        b.client.text_document_did_close(types.DidCloseTextDocumentParams(
            text_document=types.TextDocumentIdentifier(uri=uri)))
        print(f"didChange -> diagnostics  {label[-60:]:60s} {fmt(lat)}  settle {settle * 1000:7.1f} ms")
    print(f"didChange -> diagnostics  {'all files':60s} {fmt(every)}")
    print(f"last keystroke -> full check's diagnostics (settle), all files: {fmt([s for s in settles if s == s])}")
    await b.client.shutdown_async(None)
    b.client.exit(None)
    await asyncio.sleep(0.2)
    shutil.rmtree(tmp, ignore_errors=True)
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--edits", type=int, default=200)
    ap.add_argument("--interval", type=float, default=0.05)
    ap.add_argument("--py", nargs="*", help="folders of real ROS 2 repositories (their Python launch files)")
    ap.add_argument("--files", type=int, default=10, help="Python launch files typed into per --py folder")
    return asyncio.run(main_async(ap.parse_args()))


if __name__ == "__main__":
    sys.exit(main())
