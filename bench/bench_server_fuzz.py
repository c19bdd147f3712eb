"""Server fuzz campaign (issue 12, the server half of its judge): random edits, requests and
malformed JSON-RPC messages through the real server, as an editor would drive it.

    .venv/bin/python bench/bench_server_fuzz.py [--seed 1] [--seeds 3] [--edits 1000] [--json OUT]

Starts ``tvl-lsp`` on stdio (the console script next to this Python, else ``python -m
tvl_lsp``) on a copy of the repository's examples (examples/ws: the turtlerand model and its
generic ROS 1 launch file; examples/ros2_ws: its ROS 2 twin), opens the four files, and runs a
seeded campaign of ``--edits`` incremental edits (``didChange`` with ranges: insertions,
deletions and replacements of random and syntax-relevant text, positions past the end of a
line / the document and inside a surrogate pair, huge inserts, deletes of everything)
interleaved with requests (hover, definition, references, completion, documentSymbol,
codeAction, semanticTokens, formatting, rename, pull diagnostics, executeCommand, ...) and
malformed messages (bad JSON, wrong types, unknown methods, wrong params, huge ids).

Recorded: every request's latency; crashes (the process exits), hangs (no answer within
``--hang`` s, 10 by default), internal errors (a -32603 response, or a traceback on stderr /
in a log message); the server's RSS (VmRSS of /proc/PID/status) and its worker processes'
(separately) after the warm-up and at the end; the server's text of each document against the
client's (a desync).  Prints a summary; ``--json`` writes it.  Exit code 1 when a judged
threshold fails: 0 crashes, 0 hangs, 0 internal errors, every request answered within 2 s,
server memory growth under 50 %.

The same runner serves ``tests/test_server_fuzz.py`` (a short campaign in the default suite,
the long one behind ``-m fuzz``).  Nothing here reads outside the repository unless given.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
FILES = {  # key -> (workspace, relative path, languageId)
    "tvl1": ("ws", "src/turtlerand/launch/generic.tvl", "tvl"),
    "launch1": ("ws", "src/turtlerand/launch/generic.launch", "xml"),
    "tvl2": ("ros2_ws", "src/turtlerand2/launch/generic.tvl", "tvl"),
    "launch2": ("ros2_ws", "src/turtlerand2/launch/generic.launch.xml", "xml"),
}
LIMIT_S = 2.0      # the judged answer time
GROWTH = 50.0      # the judged memory growth (%)

# syntax-relevant pieces of text, per kind of file
PIECES_COMMON = ["", "a", " ", "\n", "\r\n", "\r", "\t", "é", "中文", "😀", "𝔘x", "\ud800", "\udfff",
                 "\u2028", "\x00", "\ufeff", '"', "'", "=", "{", "}", "(", ")", "[", "]", ";", ",", "\\"]
PIECES = {
    "tvl": ["root ", "group ", "allOf", "oneOf", "someOf", "[1..2]", "[0..*]", "opt ", "shared ",
            "int x;", "real r in [0.0..1.0];", "bool b;", "enum e in {a, b};", "x = 3;", "ifIn: ",
            "ifOut: ", "->", "<->", "&&", "||", "!", "Teleop", "Random", "Vel", "Multiplexer",
            "Turtlesim", "Turtlerand", "parent.", "root.", "include(\"x.tvl\");", "// c", "/*", "*/",
            "Turtlesim { group allOf { opt Teleop } }", "data x = 1;", "constraint c = a -> b;",
            "sum(", "count(", "1e308", "99999999999999999999999", "selected", "excludes", "requires"],
    "xml": ["<launch>", "</launch>", "<node ", "<node pkg=\"a\" type=\"b\" name=\"n\"/>", "<arg ",
            "<arg name=\"Teleop\" default=\"true\"/>", "<group ", "</group>", "<include file=\"",
            "$(find turtlerand)/launch/generic.launch\"/>", "<param ", "<rosparam ", "<remap ",
            "<env ", "<machine ", "<let ", "<set_remap ", "<executable ", "<set_parameter ",
            "if=\"", "unless=\"", "$(arg ", "$(var ", "$(eval ", "$(find ", "$(env ", "$(optenv ",
            "$(anon ", "$(dirname)", "$(find-pkg-share ", ")", "\"", "/>", ">", "<", "<!--", "-->",
            "<![CDATA[", "]]>", "<?xml version=\"1.0\"?>", "<!DOCTYPE x [<!ENTITY a \"b\">]>", "&a;",
            "&amp;", "&#0;", "Teleop", "Random", "Multiplexer", "name=\"", "pkg=\"", "exec=\"",
            "$(eval " + "(" * 50, "$(eval 9**9**9)", "$(arg " * 30, "value=\"1\"", "textfile=\"",
            "command=\"", "ns=\"", "clear_params=\"true\"", "output=\"screen\"", "respawn=\"true\""],
}
FEATURES = ["Turtlerand", "Turtlesim", "Teleop", "Random", "Vel", "Multiplexer", "Nope", ""]
COMMANDS = ["tvl-lsp.count", "tvl-lsp.include", "tvl-lsp.exclude", "tvl-lsp.reset", "tvl-lsp.listProducts",
            "tvl-lsp.documentState", "tvl-lsp.generateConfigurations", "tvl-lsp.noSuchCommand"]
POSITIONAL = ["textDocument/hover", "textDocument/definition", "textDocument/declaration",
              "textDocument/references", "textDocument/completion", "textDocument/prepareRename",
              "textDocument/rename"]
WHOLE = ["textDocument/documentSymbol", "textDocument/foldingRange", "textDocument/semanticTokens/full",
         "textDocument/formatting", "textDocument/diagnostic", "textDocument/codeLens"]
TB = re.compile(rb"Traceback \(most recent call last\)")


# ------------------------------------------------------------------ text positions (UTF-16)

_EOL = re.compile(r"\r\n|\r|\n")


def line_starts(text: str) -> list[int]:
    return [0] + [m.end() for m in _EOL.finditer(text)]


def u16(s: str) -> int:
    return len(s.encode("utf-16-le", "surrogatepass")) // 2


def position(text: str, off: int) -> dict:
    starts = line_starts(text)
    lo = max(i for i, s in enumerate(starts) if s <= off)
    return {"line": lo, "character": u16(text[starts[lo]:off])}


def offset(text: str, pos: dict) -> int:
    """The code-point offset of a valid UTF-16 position (clamped like the server)."""
    starts = line_starts(text)
    if pos["line"] >= len(starts):
        return len(text)
    a = starts[pos["line"]]
    b = starts[pos["line"] + 1] if pos["line"] + 1 < len(starts) else len(text)
    m = _EOL.search(text, a, b)
    end = m.start() if m and m.start() < b else b
    units, i = 0, a
    while i < end and units < pos["character"]:
        units += u16(text[i])
        i += 1
    return i


_SURROGATE = re.compile("[\ud800-\udfff]")


def as_received(s: str) -> str:
    """``s`` as the server holds it once sent: JSON joins adjacent surrogate halves into one
    character, and the server replaces a lone one by U+FFFD (same length in every encoding)."""
    return _SURROGATE.sub("\ufffd", json.loads(json.dumps(s)))


def boundary(text: str, off: int) -> int:
    """``off`` moved off the middle of a CR LF pair."""
    if 0 < off < len(text) and text[off - 1] == "\r" and text[off] == "\n":
        return off - 1
    return off


# ------------------------------------------------------------------ the client

def frame(body: bytes) -> bytes:
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def server_command() -> list[str]:
    exe = Path(sys.executable).parent / "tvl-lsp"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "tvl_lsp"]


def rss_kb(pid: int) -> int | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except (OSError, ValueError):
        return None
    return None


def children(pid: int) -> list[int]:
    """Every descendant of ``pid`` (worker processes, solvers)."""
    kids: dict[int, list[int]] = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
                ppid = int(stat[stat.rindex(")") + 2:].split()[1])
            except (OSError, ValueError):
                continue
            kids.setdefault(ppid, []).append(int(d.name))
    out, todo = [], [pid]
    while todo:
        for c in kids.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def memory(pid: int) -> dict:
    kids = {c: rss_kb(c) for c in children(pid)}
    return {"server_kb": rss_kb(pid), "workers_kb": sum(v for v in kids.values() if v),
            "workers": len([v for v in kids.values() if v])}


class Client:
    """``tvl-lsp`` on pipes: framed messages out, a reader thread timestamps what comes back,
    answers the server's own requests as an editor would."""

    def __init__(self, cwd: Path, cmd: list[str] | None = None):
        env = dict(os.environ, PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""))
        self.proc = subprocess.Popen(cmd or server_command(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, env=env, cwd=str(cwd))
        self.cond = threading.Condition()
        self.responses: dict = {}        # id (json) -> (time, message)
        self.null_id: list[dict] = []    # responses with id null (parse errors, invalid requests)
        self.log_tracebacks: list[str] = []
        self.stderr = bytearray()
        self.next_id = 1
        self.wlock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()
        threading.Thread(target=self._read_err, daemon=True).start()

    def _read_err(self):
        while True:
            b = self.proc.stderr.read1(65536) if hasattr(self.proc.stderr, "read1") else self.proc.stderr.read(1)
            if not b:
                return
            self.stderr += b

    def _read(self):
        out = self.proc.stdout
        while True:
            n = None
            while True:
                line = out.readline()
                if not line:
                    with self.cond:
                        self.cond.notify_all()
                    return
                if line in (b"\r\n", b"\n"):
                    break
                k, _, v = line.decode("latin-1").partition(":")
                if k.strip().lower() == "content-length":
                    n = int(v.strip())
            body = out.read(n or 0)
            t = time.monotonic()
            try:
                msg = json.loads(body)
            except ValueError:
                continue
            self._dispatch(msg, t)

    def _dispatch(self, msg: dict, t: float):
        if "method" in msg:
            m = msg["method"]
            if m in ("window/logMessage", "window/showMessage"):
                text = str((msg.get("params") or {}).get("message", ""))
                if "Traceback" in text:
                    self.log_tracebacks.append(text[:2000])
            if "id" in msg:  # a request of the server's: answer as an editor would
                result = None
                if m == "workspace/configuration":
                    result = [None] * len((msg.get("params") or {}).get("items", []))
                elif m == "workspace/applyEdit":
                    result = {"applied": False}
                self.send_obj({"jsonrpc": "2.0", "id": msg["id"], "result": result})
            return
        with self.cond:
            if msg.get("id") is None:
                self.null_id.append(msg)
            else:
                self.responses[json.dumps(msg["id"])] = (t, msg)
            self.cond.notify_all()

    def send(self, data: bytes) -> None:
        with self.wlock:
            self.proc.stdin.write(data)
            self.proc.stdin.flush()

    def send_obj(self, obj) -> None:
        self.send(frame(json.dumps(obj).encode()))

    def request(self, method, params, msg_id=None) -> tuple[object, float]:
        if msg_id is None:
            msg_id, self.next_id = self.next_id, self.next_id + 1
        msg = {"jsonrpc": "2.0", "id": msg_id, "method": method}
        if params is not ...:
            msg["params"] = params
        t = time.monotonic()
        self.send_obj(msg)
        return msg_id, t

    def notify(self, method, params) -> None:
        self.send_obj({"jsonrpc": "2.0", "method": method, "params": params})

    def wait(self, msg_id, timeout: float):
        """(arrival time, response) or None if none came within ``timeout`` / the server died."""
        key = json.dumps(msg_id)
        end = time.monotonic() + timeout
        with self.cond:
            while True:
                if key in self.responses:
                    return self.responses.pop(key)
                left = end - time.monotonic()
                if left <= 0 or self.proc.poll() is not None:
                    return None
                self.cond.wait(min(left, 0.1))


# ------------------------------------------------------------------ the campaign

@dataclass
class Result:
    seed: int
    edits: int = 0
    malformed: int = 0
    latencies: list = field(default_factory=list)   # (method, seconds)
    slow: list = field(default_factory=list)        # (method, seconds, detail)
    hangs: list = field(default_factory=list)
    internal: list = field(default_factory=list)
    unexpected: list = field(default_factory=list)  # answers that break the protocol's promises
    desyncs: list = field(default_factory=list)
    crash: str | None = None
    exit_code: int | None = None
    mem_start: dict = field(default_factory=dict)
    mem_end: dict = field(default_factory=dict)
    mem_peak_kb: int = 0
    stderr_tracebacks: list = field(default_factory=list)
    seconds: float = 0.0
    load: tuple = ()
    stderr: bytes = b""

    def growth(self) -> float | None:
        a, b = self.mem_start.get("server_kb"), self.mem_end.get("server_kb")
        return None if not a or not b else 100.0 * (b - a) / a

    def failures(self) -> list[str]:
        out = []
        if self.crash:
            out.append(f"crash: {self.crash}")
        out += [f"hang: {h}" for h in self.hangs]
        out += [f"internal error: {e}" for e in self.internal]
        out += [f"traceback on stderr: {t[:300]}" for t in self.stderr_tracebacks]
        out += [f"over {LIMIT_S} s: {m} {s:.2f} s {d}" for m, s, d in self.slow]
        out += [f"unexpected: {u}" for u in self.unexpected]
        out += [f"desync: {d}" for d in self.desyncs]
        g = self.growth()
        if g is None or g >= GROWTH:
            out.append(f"memory growth {g if g is None else round(g, 1)} % (>= {GROWTH} %)")
        return out


class Campaign:
    def __init__(self, seed: int, edits: int, hang: float = 10.0, cmd=None, verbose=False, workdir=None):
        self.rng = random.Random(seed)
        self.res = Result(seed)
        self.n_edits = edits
        self.hang = hang
        self.verbose = verbose
        self.tmp = Path(tempfile.mkdtemp(prefix="tvl-srvfuzz-", dir=workdir))
        for ws in ("ws", "ros2_ws"):
            shutil.copytree(REPO / "examples" / ws, self.tmp / ws)
        self.docs: dict[str, list] = {}  # uri -> [text, version, kind]
        self.cmd = cmd

    # -------------------------------------------------------------- requests
    def call(self, method, params, expect=None, detail=""):
        """Send a request, wait for its answer, record latency / errors.  ``expect``: the error
        code the LSP prescribes for a malformed request (None: any answer but -32603)."""
        c = self.c
        if c.proc.poll() is not None:
            return None
        rid, t0 = c.request(method, params)
        rep = c.wait(rid, self.hang)
        if rep is None:
            if c.proc.poll() is not None:
                self.res.crash = f"exited with {c.proc.returncode} during {method} {detail}"
            else:
                self.res.hangs.append(f"{method} {detail} (no answer in {self.hang} s)")
            return None
        t1, msg = rep
        dt = t1 - t0
        self.res.latencies.append((method, dt))
        if dt > LIMIT_S:
            self.res.slow.append((method, dt, detail))
        err = msg.get("error")
        if err and err.get("code") == -32603:
            self.res.internal.append(f"{method} {detail}: {str(err.get('message'))[:500]}")
        elif expect is not None and (not err or err.get("code") not in expect):
            self.res.unexpected.append(f"{method} {detail}: wanted {expect}, got {str(msg)[:300]}")
        return msg

    def wait_answer(self, rid, t0: float, what: str) -> None:
        """The answer to a request sent by hand (no method-specific checks)."""
        c = self.c
        rep = c.wait(rid, self.hang)
        if rep is None:
            if c.proc.poll() is None:
                self.res.hangs.append(f"{what} (no answer in {self.hang} s)")
            else:
                self.res.crash = f"exited with {c.proc.returncode} on {what}"
            return
        dt = rep[0] - t0
        self.res.latencies.append((what.split(" ")[0], dt))
        if dt > LIMIT_S:
            self.res.slow.append((what, dt, ""))
        if (rep[1].get("error") or {}).get("code") == -32603:
            self.res.internal.append(f"{what}: {rep[1]['error']}")

    def random_pos(self, text: str, invalid: float = 0.1) -> dict:
        r = self.rng.random()
        starts = line_starts(text)
        if r < invalid / 3:  # past the end of the document
            return {"line": len(starts) + self.rng.randint(0, 5), "character": self.rng.randint(0, 80)}
        if r < 2 * invalid / 3:  # past the end of a line
            p = position(text, self.rng.choice(starts))
            n = p["line"]
            b = starts[n + 1] if n + 1 < len(starts) else len(text)
            return {"line": n, "character": u16(text[starts[n]:b]) + self.rng.randint(0, 40)}
        if r < invalid:  # inside a surrogate pair, or a huge character
            astral = [i for i, ch in enumerate(text) if ord(ch) > 0xFFFF]
            if astral:
                p = position(text, self.rng.choice(astral))
                return {"line": p["line"], "character": p["character"] + 1}
            return {"line": 0, "character": 2 ** 31 - 1}
        if r < invalid + 0.4:  # on a name
            names = [m.start() + self.rng.randint(0, len(m.group()))
                     for m in re.finditer(r"[A-Za-z_][A-Za-z_0-9.]*", text[:20000])]
            if names:
                return position(text, boundary(text, self.rng.choice(names)))
        return position(text, boundary(text, self.rng.randint(0, len(text))))

    def request_step(self, uri: str):
        text, _, kind = self.docs[uri]
        rng = self.rng
        r = rng.random()
        if r < 0.45:
            method = rng.choice(POSITIONAL)
            p = {"textDocument": {"uri": uri}, "position": self.random_pos(text)}
            if method == "textDocument/references":
                p["context"] = {"includeDeclaration": rng.random() < 0.5}
            elif method == "textDocument/rename":
                p["newName"] = rng.choice(["Renamed", "x", "a b", "", "é", "Teleop", "1x", "<>"])
            elif method == "textDocument/completion":
                p["context"] = {"triggerKind": rng.choice([1, 2]), "triggerCharacter": rng.choice(["$", "(", "<", " "])}
            self.call(method, p, detail=f"{uri.rsplit('/', 1)[-1]} {p['position']}")
        elif r < 0.75:
            method = rng.choice(WHOLE)
            p = {"textDocument": {"uri": uri}}
            if method == "textDocument/formatting":
                p["options"] = {"tabSize": rng.choice([2, 4, 0, 100]), "insertSpaces": rng.random() < 0.8}
            self.call(method, p, detail=uri.rsplit("/", 1)[-1])
        elif r < 0.87:
            a, b = self.random_pos(text), self.random_pos(text)
            self.call("textDocument/codeAction", {
                "textDocument": {"uri": uri}, "range": {"start": a, "end": b},
                "context": {"diagnostics": [], "only": rng.choice([None, ["quickfix"], ["refactor"]]) or []}},
                detail=f"{uri.rsplit('/', 1)[-1]} {a} {b}")
        else:
            cmd = rng.choice(COMMANDS)
            args: list = [uri]
            if cmd in ("tvl-lsp.include", "tvl-lsp.exclude"):
                args.append(rng.choice(FEATURES))
            elif cmd == "tvl-lsp.reset" and rng.random() < 0.5:
                args.append(rng.choice(FEATURES))
            elif cmd == "tvl-lsp.listProducts":
                args.append(rng.choice([1, 5, 100]))
            elif cmd == "tvl-lsp.generateConfigurations":
                args = [{"uri": uri, "mode": "one"}]
            if rng.random() < 0.1:
                args = rng.choice([[], [None], [42], [{"uri": 3}], ["file:///nowhere/x.tvl", "Teleop"]])
            msg = self.call("workspace/executeCommand", {"command": cmd, "arguments": args},
                            detail=f"{cmd} {str(args)[:120]}")
            if cmd == "tvl-lsp.documentState" and msg and isinstance(msg.get("result"), dict) and args == [uri]:
                self.check_sync(uri, msg["result"])

    def check_sync(self, uri: str, state: dict):
        text, version, _ = self.docs[uri]
        theirs = state.get("text") or ""
        if theirs != text:
            i = next((i for i, (x, y) in enumerate(zip(theirs, text)) if x != y), min(len(theirs), len(text)))
            self.res.desyncs.append(f"{uri.rsplit('/', 1)[-1]} v{version} (server v{state.get('version')}): "
                                    f"server text differs at {i} ({len(theirs)} vs {len(text)} chars): "
                                    f"server {theirs[max(0, i - 30):i + 30]!r} client {text[max(0, i - 30):i + 30]!r}")
            self.docs[uri][0] = state.get("text") or ""

    def resync(self, uri: str):
        """After an edit at an invalid position: take the server's text (the client's notion of
        where such an edit lands is not the protocol's to define)."""
        msg = self.call("workspace/executeCommand", {"command": "tvl-lsp.documentState", "arguments": [uri]},
                        detail="resync")
        if msg and isinstance(msg.get("result"), dict) and isinstance(msg["result"].get("text"), str):
            self.docs[uri][0] = msg["result"]["text"]

    # -------------------------------------------------------------- edits
    def edit_step(self, uri: str):
        rng = self.rng
        text, version, kind = self.docs[uri]
        r = rng.random()
        invalid = False
        if r < 0.02:  # delete everything
            a, b, new = 0, len(text), ""
        elif r < 0.04:  # a huge insert
            a = b = boundary(text, rng.randint(0, len(text)))
            new = rng.choice([rng.choice(PIECES[kind]) * rng.randint(2000, 20000),
                              "".join(rng.choice(PIECES[kind] + PIECES_COMMON) for _ in range(20000)),
                              "x" * 300000])
        elif r < 0.07:  # restore the original text (whole-document change)
            orig = (self.tmp / self.paths[uri]).read_text()
            version += 1
            self.c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version},
                                                     "contentChanges": [{"text": orig}]})
            self.docs[uri] = [orig, version, kind]
            return
        else:
            a = boundary(text, rng.randint(0, len(text)))
            kind_of_edit = rng.random()
            if kind_of_edit < 0.4:  # insertion
                b = a
            elif kind_of_edit < 0.7:  # deletion / replacement of a few characters
                b = boundary(text, min(len(text), a + rng.randint(1, 12)))
            else:
                b = boundary(text, min(len(text), a + rng.randint(1, 400)))
            n = rng.choice([0, 1, 1, 1, 2, 3, 6])
            new = "".join(rng.choice(PIECES[kind] if rng.random() < 0.6 else PIECES_COMMON) for _ in range(n))
        if len(text) > 60000 and b - a < 1000:  # keep documents from growing without bound
            b = boundary(text, min(len(text), a + 40000))
        start, end = position(text, a), position(text, b)
        if rng.random() < 0.06:  # an invalid position
            invalid = True
            start = rng.choice([start, {"line": start["line"], "character": start["character"] + 10 ** rng.randint(1, 6)}])
            end = rng.choice([{"line": end["line"] + rng.randint(1, 1000), "character": 0},
                              {"line": end["line"], "character": 2 ** 31 - 1},
                              {"line": 2 ** 31 - 1, "character": 2 ** 31 - 1}, end])
            if rng.random() < 0.3:
                start, end = end, start  # reversed
        version += 1
        change = {"range": {"start": start, "end": end}, "text": new}
        if rng.random() < 0.05:
            change["rangeLength"] = rng.randint(0, 100)
        self.c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version},
                                                 "contentChanges": [change]})
        self.docs[uri] = [as_received(text[:a] + new + text[b:]), version, kind]
        if invalid:
            self.resync(uri)

    # -------------------------------------------------------------- malformed messages
    def malformed_step(self, uri: str):
        rng, c = self.rng, self.c
        self.res.malformed += 1
        k = rng.randrange(16)
        pos = {"line": 0, "character": 0}
        if k == 0:  # bad JSON
            c.send(frame(rng.choice([b"{not json", b"{\"jsonrpc\": \"2.0\", \"id\": 1,", b"\xff\xfe\x00",
                                     b"[" * 5000, b"", b"null", b"\"str\"", b"{\"id\": 1e999}"])))
        elif k == 1:  # a JSON value that is not a message
            c.send(frame(json.dumps(rng.choice([[1, 2], 3, {"jsonrpc": "2.0"}, {"method": 5},
                                                {"jsonrpc": "1.0", "id": 1, "method": "x"}])).encode()))
        elif k == 2:  # unknown request: -32601
            self.call(rng.choice(["textDocument/noSuchThing", "tvl/unknown", "x" * 5000]), {"a": 1},
                      expect=[-32601], detail="unknown method")
        elif k == 3:  # unknown notifications ($/ ones are ignored too)
            c.notify(rng.choice(["$/noSuchNotification", "tvl/unknownNotification", "$/cancelRequest"]),
                     rng.choice([{}, None, {"id": "nope"}, [1]]))
        elif k == 4:  # wrong params on a known request: -32602
            bad = rng.choice([
                {"textDocument": {"uri": uri}, "position": {"line": -1, "character": 0}},
                {"textDocument": {"uri": uri}, "position": {"line": "x", "character": 0}},
                {"textDocument": {"uri": uri}, "position": {"line": 2 ** 40, "character": 0}},
                {"textDocument": {"uri": uri}},
                {"textDocument": uri, "position": pos},
                {"position": pos},
                [uri, 0, 0],
                None,
                "string",
            ])
            self.call(rng.choice(POSITIONAL[:5]), bad, expect=[-32602], detail=f"wrong params {str(bad)[:80]}")
        elif k == 5:  # huge / odd ids
            mid = rng.choice([2 ** 53, 2 ** 63 + 1, 2 ** 100, -(2 ** 70), "i" * 10000, "é😀", 0, -1])
            rid, t0 = c.request("textDocument/hover", {"textDocument": {"uri": uri}, "position": pos}, msg_id=mid)
            self.wait_answer(rid, t0, f"hover with id {str(mid)[:40]}")
        elif k == 6:  # ids of wrong types (object, array, float): no answer can carry them
            c.send_obj({"jsonrpc": "2.0", "id": rng.choice([{"a": 1}, [1], 1.5, True]),
                        "method": "textDocument/hover", "params": {"textDocument": {"uri": uri}, "position": pos}})
        elif k == 7:  # wrong params on notifications
            method = rng.choice(["textDocument/didChange", "textDocument/didOpen", "textDocument/didClose",
                                 "textDocument/didSave", "workspace/didChangeConfiguration",
                                 "workspace/didChangeWatchedFiles", "workspace/didChangeWorkspaceFolders"])
            params = rng.choice([None, [], {"textDocument": 5}, {"textDocument": {"uri": 5}},
                                 {"textDocument": {"uri": uri, "version": "x"}, "contentChanges": [{"range": 1}]},
                                 {"textDocument": {"uri": uri, "version": 10 ** 30}, "contentChanges": "x"},
                                 {"settings": [1, 2]}, {"changes": [{"uri": 5, "type": 9}]},
                                 {"event": {"added": [{"uri": "file:///", "name": 3}], "removed": 7}}])
            c.notify(method, params)
            if method == "textDocument/didClose" and isinstance(params, dict) and \
                    isinstance(params.get("textDocument"), dict) and params["textDocument"].get("uri") == uri:
                # (extra members are no error: that was a valid didClose) open it again
                text, version, kind = self.docs[uri]
                c.notify("textDocument/didOpen", {"textDocument": {
                    "uri": uri, "languageId": "tvl" if kind == "tvl" else "xml", "version": version, "text": text}})
        elif k == 8:  # a response nobody asked for, a cancel of a finished request
            c.send_obj({"jsonrpc": "2.0", "id": 999999, "result": None})
            c.notify("$/cancelRequest", {"id": max(1, c.next_id - 1)})
        elif k == 9:  # executeCommand with wrong types
            self.call("workspace/executeCommand", rng.choice([
                {"command": 5}, {"command": "tvl-lsp.count", "arguments": "x"},
                {"command": "tvl-lsp.include", "arguments": [uri, 5]},
                {"command": "tvl-lsp.listProducts", "arguments": [uri, -1]},
                {"command": "tvl-lsp.generateConfigurations", "arguments": [{"uri": uri, "mode": "bogus"}]},
                {"command": "tvl-lsp.generateConfigurations", "arguments": [{"uri": uri, "folder": "/etc"}]},
                {"arguments": []}]), detail="executeCommand wrong params")
        elif k == 10:  # a document that was never opened / a weird URI
            u = rng.choice(["file:///nowhere/x.tvl", "untitled:Untitled-1", "file:///", "http://x/y.launch",
                            "file:///%00", "not a uri", uri + "#frag", uri.replace("file://", "file://host")])
            self.call(rng.choice(POSITIONAL + WHOLE), {"textDocument": {"uri": u}, "position": pos,
                                                        "context": {"includeDeclaration": True},
                                                        "options": {"tabSize": 2, "insertSpaces": True},
                                                        "newName": "n"}, detail=f"uri {u}")
        elif k == 11:  # a batch (JSON-RPC 2.0 arrays; LSP has none)
            c.send_obj([{"jsonrpc": "2.0", "id": c.next_id + 100000, "method": "textDocument/hover",
                         "params": {"textDocument": {"uri": uri}, "position": pos}}])
        elif k == 12:  # a second initialize: -32600 (or an answer), never a crash
            self.call("initialize", {"processId": None, "capabilities": {}, "rootUri": None},
                      detail="second initialize")
        elif k == 13:  # didOpen of an already open document, then restore the mirror's text
            text, version, kind = self.docs[uri]
            c.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": kind, "version": version,
                                                               "text": text}})
        elif k == 14:  # deeply nested params (deeper than a recursive JSON parser goes)
            d = rng.choice([100, 900, 5000, 100000])
            rid = c.next_id
            c.next_id += 1
            t0 = time.monotonic()
            c.send(frame(b'{"jsonrpc": "2.0", "id": %d, "method": "textDocument/hover", "params": {"textDocument": '
                         b'{"uri": %s}, "position": {"line": 0, "character": 0}, "x": %s0%s}}'
                         % (rid, json.dumps(uri).encode(), b"[" * d, b"]" * d)))
            self.wait_answer(rid, t0, f"hover with params nested {d} deep")
        else:  # a lone surrogate as a JSON escape in the params
            rid = c.next_id
            c.next_id += 1
            t0 = time.monotonic()
            c.send(frame(b'{"jsonrpc": "2.0", "id": %d, "method": "textDocument/hover", "params": '
                         b'{"textDocument": {"uri": "%s\\ud800"}, "position": {"line": 0, "character": 0}}}'
                         % (rid, uri.encode())))
            self.wait_answer(rid, t0, "hover of a URI with a lone surrogate")

    # -------------------------------------------------------------- the run
    def run(self) -> Result:
        t_start = time.monotonic()
        roots = [self.tmp / "ws", self.tmp / "ros2_ws"]
        self.c = c = Client(self.tmp, self.cmd)
        try:
            self._run(roots)
        finally:
            self.res.seconds = time.monotonic() - t_start
            self.res.load = os.getloadavg()
            self._stop()
            shutil.rmtree(self.tmp, ignore_errors=True)
        self.res.stderr = bytes(c.stderr)
        self.res.stderr_tracebacks = [m.group(0).decode() + c.stderr[m.end():m.end() + 1500].decode("utf-8", "replace")
                                      for m in TB.finditer(bytes(c.stderr))]
        self.res.internal += [f"log message: {t[:500]}" for t in c.log_tracebacks]
        return self.res

    def _run(self, roots):
        c = self.c
        caps = {"textDocument": {"hover": {"contentFormat": ["markdown", "plaintext"]},
                                 "completion": {"completionItem": {"snippetSupport": True}},
                                 "codeAction": {"codeActionLiteralSupport": {"codeActionKind": {"valueSet": ["quickfix", "refactor", "source"]}}},
                                 "publishDiagnostics": {"relatedInformation": True},
                                 "diagnostic": {"dynamicRegistration": False},
                                 "rename": {"prepareSupport": True},
                                 "semanticTokens": {"requests": {"full": True}, "tokenTypes": [], "tokenModifiers": [],
                                                    "formats": ["relative"]},
                                 "synchronization": {"didSave": True}},
                "workspace": {"configuration": True, "workspaceFolders": True, "applyEdit": True,
                              "diagnostics": {"refreshSupport": True},
                              "codeLens": {"refreshSupport": True}, "executeCommand": {}},
                "window": {"workDoneProgress": True},
                "general": {"positionEncodings": ["utf-16"]}}
        msg = self.call("initialize", {"processId": os.getpid(), "capabilities": caps, "rootUri": roots[0].as_uri(),
                                       "workspaceFolders": [{"uri": r.as_uri(), "name": r.name} for r in roots]},
                        detail="initialize")
        if msg is None or "result" not in msg:
            self.res.crash = self.res.crash or f"initialize failed: {msg}"
            return
        c.notify("initialized", {})
        self.paths = {}
        for key, (ws, rel, lang) in FILES.items():
            p = self.tmp / ws / rel
            uri = p.as_uri()
            self.paths[uri] = p.relative_to(self.tmp)
            text = p.read_text()
            kind = "tvl" if lang == "tvl" else "xml"
            self.docs[uri] = [text, 1, kind]
            c.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": lang, "version": 1,
                                                               "text": text}})
        uris = list(self.docs)
        # warm-up: every request kind once on every document, then wait for the background checks
        for uri in uris:
            for method in WHOLE:
                p = {"textDocument": {"uri": uri}}
                if method == "textDocument/formatting":
                    p["options"] = {"tabSize": 2, "insertSpaces": True}
                self.call(method, p, detail="warm-up")
            for method in POSITIONAL:
                self.call(method, {"textDocument": {"uri": uri}, "position": {"line": 2, "character": 4},
                                   "context": {"includeDeclaration": True}, "newName": "X"}, detail="warm-up")
            self.call("workspace/executeCommand", {"command": "tvl-lsp.count", "arguments": [uri]}, detail="warm-up")
        time.sleep(2.0)
        self.res.mem_start = memory(c.proc.pid)
        done = 0
        while done < self.n_edits:
            if c.proc.poll() is not None:
                self.res.crash = self.res.crash or f"exited with {c.proc.returncode}"
                break
            if len(self.res.hangs) >= 3 or self.res.crash:
                break
            uri = self.rng.choice(uris)
            r = self.rng.random()
            if r < 0.5:
                self.edit_step(uri)
                done += 1
                self.res.edits = done
                if self.rng.random() < 0.2:  # a burst of typing
                    for _ in range(self.rng.randint(1, 8)):
                        if done < self.n_edits:
                            self.edit_step(uri)
                            done += 1
                            self.res.edits = done
            elif r < 0.9:
                self.request_step(uri)
            else:
                self.malformed_step(uri)
            if done and done % 50 == 0:
                m = memory(c.proc.pid)
                self.res.mem_peak_kb = max(self.res.mem_peak_kb, m["server_kb"] or 0)
                if self.verbose:
                    print(f"  seed {self.res.seed}: {done} edits, {len(self.res.latencies)} requests, "
                          f"rss {m['server_kb']} kB, workers {m['workers_kb']} kB", file=sys.stderr, flush=True)
        if c.proc.poll() is None and not self.res.crash:
            # final consistency check, then let the background work settle before measuring
            for uri in uris:
                msg = self.call("workspace/executeCommand", {"command": "tvl-lsp.documentState", "arguments": [uri]},
                                detail="final state")
                if msg and isinstance(msg.get("result"), dict):
                    self.check_sync(uri, msg["result"])
            time.sleep(2.0)
            self.res.mem_end = memory(c.proc.pid)

    def _stop(self):
        c = self.c
        if c.proc.poll() is None:
            try:
                rid, _ = c.request("shutdown", None)
                c.wait(rid, 10)
                c.notify("exit", None)
                self.res.exit_code = c.proc.wait(15)
            except (OSError, subprocess.TimeoutExpired):
                c.proc.kill()
                c.proc.wait()
                self.res.exit_code = -9
            if self.res.exit_code != 0:
                self.res.crash = self.res.crash or f"exit code {self.res.exit_code} after shutdown/exit"
        else:
            self.res.exit_code = c.proc.returncode
        time.sleep(0.2)


def pct(xs, p):
    xs = sorted(xs)
    if not xs:
        return float("nan")
    return xs[min(len(xs) - 1, max(0, int(round(p / 100 * (len(xs) - 1)))))]


def summary(res: Result) -> dict:
    lat = [s for _, s in res.latencies]
    by_method: dict = {}
    for m, _s, _d in res.slow:
        by_method[m] = by_method.get(m, 0) + 1
    return {"seed": res.seed, "edits": res.edits, "malformed": res.malformed, "requests": len(lat),
            "p50_ms": round(pct(lat, 50) * 1000, 1), "p95_ms": round(pct(lat, 95) * 1000, 1),
            "max_ms": round(max(lat) * 1000, 1) if lat else None,
            "over_2s": len(res.slow), "over_2s_methods": by_method,
            "crash": res.crash, "hangs": len(res.hangs), "internal_errors": len(res.internal) + len(res.stderr_tracebacks),
            "unexpected": len(res.unexpected), "desyncs": len(res.desyncs),
            "rss_start_kb": res.mem_start.get("server_kb"), "rss_end_kb": res.mem_end.get("server_kb"),
            "rss_peak_kb": res.mem_peak_kb, "growth_pct": None if res.growth() is None else round(res.growth(), 1),
            "workers_start_kb": res.mem_start.get("workers_kb"), "workers_end_kb": res.mem_end.get("workers_kb"),
            "seconds": round(res.seconds, 1), "load": [round(x, 2) for x in res.load],
            "failures": res.failures()}


def run_campaign(seed: int, edits: int, **kw) -> Result:
    return Campaign(seed, edits, **kw).run()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1, help="first seed")
    ap.add_argument("--seeds", type=int, default=3, help="number of campaigns (seeds seed, seed+1, ...)")
    ap.add_argument("--edits", type=int, default=1000, help="edits per campaign")
    ap.add_argument("--hang", type=float, default=10.0, help="seconds without an answer that count as a hang")
    ap.add_argument("--json", help="write the summaries here")
    ap.add_argument("--stderr", help="write each campaign's server stderr to STDERR.SEED")
    ap.add_argument("-v", "--verbose", action="store_true")
    a = ap.parse_args(argv)
    out, ok = [], True
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}, {os.cpu_count()} CPUs")
    for seed in range(a.seed, a.seed + a.seeds):
        res = run_campaign(seed, a.edits, hang=a.hang, verbose=a.verbose)
        s = summary(res)
        out.append(s)
        if a.stderr:
            Path(f"{a.stderr}.{seed}").write_bytes(res.stderr)
        ok &= not s["failures"]
        print(f"seed {seed}: {s['edits']} edits, {s['malformed']} malformed, {s['requests']} requests in "
              f"{s['seconds']} s; latency p50 {s['p50_ms']} ms, p95 {s['p95_ms']} ms, max {s['max_ms']} ms; "
              f"over 2 s: {s['over_2s']} {s['over_2s_methods'] or ''}")
        print(f"  crash: {s['crash']}, hangs: {s['hangs']}, internal errors: {s['internal_errors']}, "
              f"unexpected answers: {s['unexpected']}, desyncs: {s['desyncs']}")
        print(f"  server RSS {s['rss_start_kb']} -> {s['rss_end_kb']} kB ({s['growth_pct']} %), peak "
              f"{s['rss_peak_kb']} kB; workers {s['workers_start_kb']} -> {s['workers_end_kb']} kB; "
              f"load average {s['load']}")
        for f in s["failures"][:30]:
            print("   ", f)
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1))
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
