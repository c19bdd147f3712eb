"""An adversarial campaign against every host (issue #28): special files, links, SIGTERM,
full disks, a hostile cache, hostile HTTP clients, memory limits, orphaned processes.

    .venv/bin/python bench/robustness_campaign.py [--seed N] [--rounds K] [--json OUT] [--tmpfs DIR]

Every attack is randomised by the seed (where files go, their names, when a signal comes).
Each run of a command is watched for: a hang (no exit within its timeout), a traceback, an
exit code outside 0/1/2, its peak memory (``wait4``'s ``ru_maxrss``: an unbounded read shows
there), a write outside the workspace or through a link (sentinels), a lost or truncated file
(complete texts compared), an unanswered HTTP request, and processes left behind.  The summary
counts failures per attack; 0 everywhere is the goal.  ``--tmpfs DIR``: a folder where a small
tmpfs may be mounted (root only) for the full-disk attacks; without it they use RLIMIT_FSIZE.
"""

from __future__ import annotations

import argparse
import http.client
import json
import os
import random
import resource
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections import defaultdict
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))
PY = sys.executable
MANY = REPO / "tests" / "data" / "robustness" / "many"
EXAMPLE = REPO / "examples" / "ws"
MB = 1024 * 1024

RESULTS: dict[str, dict] = defaultdict(lambda: {"runs": 0, "failures": 0, "notes": []})


def record(attack: str, ok: bool, note: str = "") -> None:
    r = RESULTS[attack]
    r["runs"] += 1
    if not ok:
        r["failures"] += 1
        if len(r["notes"]) < 5:
            r["notes"].append(note[:300])


def env(tmp: Path, **extra) -> dict:
    e = dict(os.environ, PYTHONPATH=str(REPO), TVL_LSP_CACHE_DIR=str(tmp / "cache"),
             TVL_LSP_CACHE_KEY_FILE=str(tmp / "key" / "cache.key"), ROS_PACKAGE_PATH="")
    e.update(extra)
    return e


def run(args, tmp: Path, timeout: float = 90, preexec=None, **extra_env) -> dict:
    """Run ``tvl-lsp ARGS``: exit code, stderr, seconds, peak memory (MB), hung."""
    t0 = time.monotonic()
    p = subprocess.Popen([PY, "-m", "tvl_lsp", *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=env(tmp, **extra_env), preexec_fn=preexec)
    out: dict = {"hung": False}
    timer = threading.Timer(timeout, lambda: (out.__setitem__("hung", True), p.kill()))
    timer.start()
    stdout, stderr = b"", b""
    try:
        stdout, stderr = p.stdout.read(), p.stderr.read()
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
    finally:
        timer.cancel()
    out.update(rc=p.returncode, out=stdout.decode(errors="replace"), err=stderr.decode(errors="replace"),
               seconds=time.monotonic() - t0, rss_mb=ru.ru_maxrss / 1024)
    return out


def sane(r: dict, max_rss: float = 1200) -> tuple[bool, str]:
    if r["hung"]:
        return False, "hung"
    if "Traceback" in r["err"]:
        return False, "traceback: " + r["err"][-300:]
    if r["rc"] not in (0, 1, 2):
        return False, f"exit {r['rc']}: {r['err'][-200:]}"
    if r["rss_mb"] > max_rss:
        return False, f"peak memory {r['rss_mb']:.0f} MB"
    return True, ""


# ------------------------------------------------------------------ special files in a workspace

SPECIAL_NAMES = ["x.launch", "generic.launch.xml", "m.tvl", "m.uvl", "haros.yaml", "params.yaml", "model.dimacs",
                 "package.xml", "nodes.launch"]


def plant_special(ws: Path, rng: random.Random) -> list[str]:
    folders = [p for p in ws.rglob("*") if p.is_dir() and ".git" not in p.parts] + [ws]
    planted = []
    for _ in range(rng.randint(2, 5)):
        d = rng.choice(folders)
        name = f"{rng.randint(0, 999)}_{rng.choice(SPECIAL_NAMES)}"
        if rng.random() < 0.3:
            name = rng.choice(SPECIAL_NAMES)
        p = d / name
        if p.exists() or p.is_symlink():
            continue
        kind = rng.choice(["fifo", "zero", "urandom", "dir", "big", "outside-link"])
        if kind == "fifo":
            os.mkfifo(p)
        elif kind in ("zero", "urandom"):
            p.symlink_to(f"/dev/{kind}")
        elif kind == "dir":
            p.mkdir()
        elif kind == "big":
            with open(p, "wb") as fh:
                fh.truncate(40 * MB)  # sparse: bigger than the reader's cap
        else:
            p.symlink_to("/etc/hostname")
        planted.append(f"{kind}:{p.relative_to(ws)}")
    return planted


def attack_special_files(tmp: Path, rng: random.Random) -> None:
    ws = Path(tempfile.mkdtemp(prefix="ws-special-", dir=tmp)) / "ws"
    shutil.copytree(EXAMPLE, ws)
    planted = plant_special(ws, rng)
    generic = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    model = generic.with_suffix(".tvl")
    for args in (["--check", ws], ["launch", generic, "Turtlerand:=true", "Turtlesim:=true"],
                 ["graph", generic, "--format", "json"], ["generate", generic, "--dry-run"], ["count", model],
                 ["--check", ws, "-j", "2"]):
        r = run(args, tmp, timeout=120)
        ok, why = sane(r)
        record("special files (CLI)", ok, f"{args[0]} with {planted}: {why}")
    # the language server's check process
    from lsp_raw import RawServer
    srv = RawServer(cwd=str(tmp))
    try:
        srv.initialize(ws)
        srv.notify("textDocument/didOpen", {"textDocument": {"uri": generic.as_uri(), "languageId": "xml",
                                                             "version": 1, "text": generic.read_text()}})
        t0 = time.monotonic()
        got = None
        while time.monotonic() - t0 < 30:
            with srv.cond:
                got = [m for m in srv.messages if m.get("method") == "textDocument/publishDiagnostics"
                       and m["params"]["uri"] == generic.as_uri() and m["params"]["diagnostics"]]
            if got:
                break
            time.sleep(0.2)
        record("special files (server: diagnostics within 30 s)", bool(got),
               f"no diagnostics after {time.monotonic() - t0:.0f} s with {planted}")
        RESULTS["special files (server: diagnostics within 30 s)"].setdefault("seconds", []).append(
            round(time.monotonic() - t0, 2))
    finally:
        srv.close()


# ------------------------------------------------------------------ links and generate

def many_ws(tmp: Path, name: str) -> Path:
    ws = Path(tempfile.mkdtemp(prefix=name + "-", dir=tmp)) / "ws"
    shutil.copytree(MANY, ws)
    (ws / ".git").mkdir()
    (ws / ".git" / "config").write_text("[core]\n")
    return ws


def expected_files(ws: Path, tmp: Path) -> dict[str, str]:
    r = run(["generate", ws / "src/many/launch/generic.launch", "--mode", "all", "--limit", "200", "--dry-run"], tmp)
    out, cur, buf = {}, None, []
    for line in r["out"].splitlines(keepends=True):
        if line.startswith("==> "):
            if cur:
                out[cur] = "".join(buf)[:-1]
            cur, buf = Path(line[4:].strip()).name, []
        else:
            buf.append(line)
    if cur:
        out[cur] = "".join(buf)[:-1]
    return out


def attack_links(tmp: Path, rng: random.Random) -> None:
    ws = many_ws(tmp, "ws-links")
    want = expected_files(ws, tmp)
    generic = ws / "src/many/launch/generic.launch"
    configs = ws / "src/many/configs"
    outside = ws.parent / "outside"
    outside.mkdir()
    sentinel = (ws / ".git/config").read_text()
    kinds = ["file-link", "folder-link", "dotdot-link", "race"]
    rng.shuffle(kinds)
    for kind in kinds:
        if configs.is_symlink():
            configs.unlink()
        shutil.rmtree(configs, ignore_errors=True)
        if kind == "file-link":
            configs.mkdir()
            (configs / rng.choice(sorted(want))).symlink_to(Path("../../../.git/config"))
        elif kind == "folder-link":
            configs.symlink_to(outside)
        elif kind == "dotdot-link":
            configs.mkdir()
            (configs / rng.choice(sorted(want))).symlink_to(outside / "planted")
        stop = threading.Event()
        if kind == "race":
            configs.mkdir()

            def racer():
                while not stop.is_set():
                    try:
                        configs.rename(configs.with_name("real"))
                        configs.symlink_to(outside)
                        time.sleep(rng.uniform(0, 0.002))
                        configs.unlink()
                        configs.with_name("real").rename(configs)
                    except OSError:
                        pass
            t = threading.Thread(target=racer)
            t.start()
        try:
            r = run(["generate", generic, "--mode", "all", "--limit", "200"], tmp)
        finally:
            stop.set()
            if kind == "race":
                t.join()
                if configs.is_symlink():
                    configs.unlink()
                    configs.with_name("real").rename(configs)
        ok, why = sane(r)
        wrote_outside = list(outside.iterdir())
        through = (ws / ".git/config").read_text() != sentinel
        record(f"generate vs links ({kind})", ok and not wrote_outside and not through,
               f"{why} outside={wrote_outside[:2]} through_link={through} rc={r['rc']} {r['err'][-200:]}")


def attack_sigterm(tmp: Path, rng: random.Random, trials: int) -> None:
    ws = many_ws(tmp, "ws-term")
    want = expected_files(ws, tmp)
    configs = ws / "src/many/configs"
    configs.mkdir()
    for n, t in want.items():
        (configs / n).write_text(t.replace("<launch>", "<launch><!-- old -->"))
    old = {n: (configs / n).read_text() for n in want}
    for _ in range(trials):
        p = subprocess.Popen([PY, "-m", "tvl_lsp", "generate", str(ws / "src/many/launch/generic.launch"),
                              "--mode", "all", "--limit", "200"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             env=env(tmp))
        time.sleep(rng.uniform(0.2, 2.0))
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=60)
        bad = [n for n in want if (configs / n).read_text() not in (want[n], old[n])]
        extra = sorted(set(x.name for x in configs.iterdir()) - set(want))
        record("SIGTERM during generate (128 files)", not bad and not extra and b"Traceback" not in err,
               f"truncated={bad[:3]} leftovers={extra[:3]} rc={p.returncode}")


# ------------------------------------------------------------------ full disks

def attack_full_disk(tmp: Path, tmpfs: str | None) -> None:
    if tmpfs:
        d = Path(tmpfs)
        d.mkdir(parents=True, exist_ok=True)
        mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(d)],
                                 capture_output=True).returncode == 0
    else:
        mounted = False
    try:
        if mounted:
            ws = d / "ws"
            shutil.copytree(MANY, ws)
            r = run(["generate", ws / "src/many/launch/generic.launch", "--mode", "all", "--limit", "200"], tmp)
            files = list((ws / "src/many/configs").iterdir()) if (ws / "src/many/configs").exists() else []
            short = [f.name for f in files if "</launch>" not in f.read_text()]
            ok, why = sane(r)
            record("full disk: generate (64 KB tmpfs)", ok and r["rc"] == 2 and not short and
                   all(not f.name.startswith(".") for f in files) and len(r["err"].strip().splitlines()) == 1,
                   f"{why} rc={r['rc']} short={short[:3]} {r['err'][-300:]}")
            with open(d / "filler", "wb") as fh:
                try:
                    fh.write(b"\0" * MB)
                except OSError:
                    pass
            r = run(["--check", EXAMPLE, "--output", d / "report.txt"], tmp)
            ok, why = sane(r)
            record("full disk: --check --output", ok and r["rc"] == 2 and "disk is full" in r["err"]
                   and not (d / "report.txt").exists(), f"{why} rc={r['rc']} {r['err'][-300:]}")
            r = run(["count", REPO / "tests/data/counting/cards.tvl"], tmp, TVL_LSP_CACHE_DIR=str(d / "cache"))
            ok, why = sane(r)
            left = [p.name for p in (d / "cache").iterdir()] if (d / "cache").exists() else []
            record("full disk: the counting cache", ok and r["out"].strip() == "1050" and not left,
                   f"{why} out={r['out'][:40]} left={left[:3]}")
        else:
            def fsize():
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                resource.setrlimit(resource.RLIMIT_FSIZE, (200, 200))
            ws = many_ws(tmp, "ws-fsize")
            r = run(["generate", ws / "src/many/launch/generic.launch", "--mode", "all"], tmp, preexec=fsize)
            ok, why = sane(r)
            record("full disk (RLIMIT_FSIZE): generate", ok and r["rc"] == 2, f"{why} {r['err'][-200:]}")
    finally:
        if mounted:
            subprocess.run(["umount", str(d)], capture_output=True)


# ------------------------------------------------------------------ the cache

def attack_cache(tmp: Path, rng: random.Random) -> None:
    cache = tmp / "cache-attack"
    m = tmp / "m.dimacs"
    m.write_text("p cnf 5 3\n1 2 0\n-3 4 0\n5 -1 0\n")
    truth = "12"
    shared_files = {}
    cache.mkdir()
    for i in range(5):  # a shared folder: somebody else's files
        name = rng.choice(["notes.txt", "a.nnf", "b.count", "c.facts", f"{'ab' * 32}.nnf", "photo.jpg"]) + str(i)
        (cache / name).write_text("theirs " * rng.randint(10, 5000))
        shared_files[name] = (cache / name).read_text()
    for kind in ["forge-count", "fifo-count", "zero-nnf", "foreign", "outside-link", "fifo-facts"]:
        r = run(["count", m], tmp, TVL_LSP_CACHE_DIR=str(cache), TVL_LSP_CACHE_MAX_MB="0.001")
        for p in cache.iterdir():
            if p.name.endswith(".count") and kind == "forge-count":
                p.write_text("999\n")
            elif p.name.endswith(".count") and kind == "fifo-count":
                p.unlink()
                os.mkfifo(p)
            elif p.name.endswith(".nnf") and kind == "zero-nnf" and p.name not in shared_files:
                p.unlink()
                p.symlink_to("/dev/zero")
            elif p.name.endswith(".count") and kind == "outside-link":
                p.unlink()
                p.symlink_to("/etc/hostname")
        r = run(["count", m], tmp, timeout=60, TVL_LSP_CACHE_DIR=str(cache), TVL_LSP_CACHE_MAX_MB="0.001")
        ok, why = sane(r, 600)
        record("hostile cache entries", ok and r["out"].strip() == truth, f"{kind}: {why} out={r['out'][:40]}")
    gone = [n for n, t in shared_files.items() if not (cache / n).exists() or (cache / n).read_text() != t]
    record("eviction in a shared folder (other files untouched)", not gone, f"deleted or changed: {gone}")
    for value in ("inf", "1e400", "-1", "nan", "lots"):
        r = run(["count", m], tmp, TVL_LSP_CACHE_MAX_MB=value)
        ok, why = sane(r)
        record("TVL_LSP_CACHE_MAX_MB values", ok and r["out"].strip() == truth, f"{value}: {why}")
    r = run(["--check", EXAMPLE, "-q"], tmp, TVL_LSP_LOG="debug")
    record("TVL_LSP_LOG=debug", sane(r)[0], r["err"][-200:])


# ------------------------------------------------------------------ HTTP

def attack_http(tmp: Path, rng: random.Random) -> None:
    ws = tmp / "ws-http"
    shutil.copytree(EXAMPLE, ws)
    ui = subprocess.Popen([PY, "-m", "tvl_lsp", "ui", str(ws), "--no-browser"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, env=env(tmp))
    try:
        url = ui.stdout.readline().decode().strip()
        port = int(url.split(":")[2].split("/")[0])
        token = url.split("token=")[1]

        def req(body: bytes, headers=(), op="targets", timeout=60):
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
            c.putrequest("POST", f"/api/{op}", skip_host=True, skip_accept_encoding=True)
            hs = [("Host", f"127.0.0.1:{port}"), ("X-TVL-Token", token), ("Content-Type", "application/json"),
                  ("Content-Length", str(len(body)))] + list(headers)
            for k, v in hs:
                c.putheader(k, v)
            c.endheaders(body)
            r = c.getresponse()
            out = r.status, r.read()
            c.close()
            return out
        n = rng.randint(50_000, 200_000)
        for name, body, hs, want in [
            ("nested arrays", b"[" * n + b"]" * n, (), {400}),
            ("nested objects", b'{"a":' * (n // 4) + b"1" + b"}" * (n // 4), (), {400}),
            ("unclosed nesting", b"[" * n, (), {400}),
            ("duplicate Host", b"{}", [("Host", "evil:1")], {400}),
            ("duplicate Content-Length", b"{}", [("Content-Length", "2")], {400}),
            ("chunked", b"{}", [("Transfer-Encoding", "chunked")], {501, 400}),
            ("not JSON", bytes(rng.randrange(256) for _ in range(1000)), (), {400}),
            ("a generate that may not write", json.dumps({"mode": "all", "folder": "/etc"}).encode(), (), {409, 422}),
        ]:
            try:
                st, _ = req(body, hs, "generate" if "generate" in name else "targets")
                record(f"HTTP: {name}", st in want, f"status {st}")
            except OSError as e:
                record(f"HTTP: {name}", False, f"no answer: {e!r}")

        def one(_):
            try:
                return req(b"{}")[0]
            except OSError as e:
                return repr(e)
        with ThreadPoolExecutor(200) as ex:
            got = list(ex.map(one, range(200)))
        bad = [g for g in got if g not in (200, 503)]
        record("HTTP: 200 simultaneous requests answered", not bad, f"{len(bad)} unanswered: {bad[:2]}")
        slow = []
        for _ in range(300):
            try:
                s = socket.create_connection(("127.0.0.1", port), timeout=5)
                s.send(b"POST /api/targets HTTP/1.1\r\nHo")
                slow.append(s)
            except OSError:
                break
        time.sleep(1)
        try:
            t0 = time.monotonic()
            st, _ = req(b"{}", timeout=60)
            record("HTTP: a request during 300 slowloris connections is answered", st in (200, 503),
                   f"status {st} after {time.monotonic() - t0:.1f} s")
        except OSError as e:
            record("HTTP: a request during 300 slowloris connections is answered", False, repr(e))
        threads = len(os.listdir(f"/proc/{ui.pid}/task"))
        record("HTTP: threads of the server during slowloris <= 100", threads <= 100, f"{threads} threads")
        for s in slow:
            s.close()
        time.sleep(12)
        st, _ = req(b"{}")
        record("HTTP: served again after the attack", st == 200, f"status {st}")
    finally:
        ui.send_signal(signal.SIGTERM)
        try:
            _, err = ui.communicate(timeout=30)
            record("HTTP: stops cleanly on SIGTERM", b"Traceback" not in err, err.decode()[-300:])
        except subprocess.TimeoutExpired:
            ui.kill()
            record("HTTP: stops cleanly on SIGTERM", False, "did not stop")


# ------------------------------------------------------------------ memory limits and children

def attack_memory(tmp: Path) -> None:
    models = [REPO / "tests/data/counting/cards.tvl", EXAMPLE / "src/turtlerand/launch/generic.tvl"]
    two = tmp / "two.dimacs"
    two.write_text("p cnf 2 1\n1 2 0\n")
    for gb in (1, 2, 4, 6):
        for m in models + [two]:
            def lim(gb=gb):
                resource.setrlimit(resource.RLIMIT_AS, (gb << 30, gb << 30))
            r = run(["count", m], tmp, preexec=lim)
            ok, why = sane(r, 10_000)
            record(f"count under ulimit -v {gb} GB", ok and r["rc"] == 0 and "bad_alloc" not in r["err"],
                   f"{m.name}: {why} rc={r['rc']} {r['err'][-200:]}")


def descendants(pid: int) -> set[int]:
    from test_robustness_processes import descendants as d
    return d(pid)


def attack_orphans(tmp: Path) -> None:
    from test_robustness_processes import alive, counting_children, hard_tvl, wait_for
    ws = tmp / "ws-hard"
    model = hard_tvl(ws / "src" / "hard" / "hard.tvl")
    (ws / ".catkin_workspace").touch()
    for host in ("ui", "count", "server"):
        if host == "server":
            from lsp_raw import RawServer
            srv = RawServer(cwd=str(tmp))
            srv.initialize(ws)
            srv.notify("textDocument/didOpen", {"textDocument": {"uri": model.as_uri(), "languageId": "tvl",
                                                                 "version": 1, "text": model.read_text()}})
            proc = srv.proc
        else:
            args = ["ui", model, "--no-browser"] if host == "ui" else ["count", model]
            proc = subprocess.Popen([PY, "-m", "tvl_lsp", *map(str, args)], stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, env=env(tmp))
        if host != "count":
            wait_for(lambda: counting_children(proc.pid), 60)
        else:
            time.sleep(3)
        everything = descendants(proc.pid)
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(30)
        except subprocess.TimeoutExpired:
            proc.kill()
        wait_for(lambda: not alive(everything), 10)
        left = alive(everything)
        record("no process left after SIGTERM (ui, count, server during a compilation)", not left,
               f"{host}: {len(left)} left")
        for p in left:
            try:
                os.kill(p, signal.SIGKILL)
            except OSError:
                pass


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=2, help="rounds of the randomised attacks")
    ap.add_argument("--sigterm", type=int, default=30, help="SIGTERM trials")
    ap.add_argument("--tmpfs", help="a folder to mount a 64 KB tmpfs on (root only)")
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--only", help="comma-separated attack groups")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    groups = {"special": lambda t: [attack_special_files(t, rng) for _ in range(args.rounds)],
              "links": lambda t: [attack_links(t, rng) for _ in range(args.rounds)],
              "sigterm": lambda t: attack_sigterm(t, rng, args.sigterm),
              "disk": lambda t: attack_full_disk(t, args.tmpfs),
              "cache": lambda t: [attack_cache(t / f"r{i}", rng) for i in range(args.rounds)
                                  if (t / f"r{i}").mkdir() is None],
              "http": lambda t: attack_http(t, rng),
              "memory": attack_memory,
              "orphans": attack_orphans}
    chosen = args.only.split(",") if args.only else list(groups)
    t0 = time.monotonic()
    for g in chosen:
        with tempfile.TemporaryDirectory(prefix=f"tvl-campaign-{g}-") as d:
            g0 = time.monotonic()
            try:
                groups[g](Path(d))
            except Exception as e:  # a crash of the campaign itself is a finding too
                record(f"{g}: campaign error", False, f"{type(e).__name__}: {e}")
            print(f"[{g}] {time.monotonic() - g0:.0f} s", file=sys.stderr)
    total = sum(r["runs"] for r in RESULTS.values())
    failed = sum(r["failures"] for r in RESULTS.values())
    width = max(len(k) for k in RESULTS) if RESULTS else 10
    for k, r in RESULTS.items():
        print(f"{k:<{width}}  {r['runs']:>4} runs  {r['failures']:>3} failures" +
              (f"   {r['notes'][0]}" if r["notes"] else ""))
    print(f"seed {args.seed}: {total} runs, {failed} failures, {time.monotonic() - t0:.0f} s")
    if args.json:
        Path(args.json).write_text(json.dumps({"seed": args.seed, "results": RESULTS}, indent=2))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
