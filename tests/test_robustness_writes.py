"""Safe writes (issue #28, defects 2, 3, 4 and 7): ``generate`` (CLI, configurator, the editor's
command) never writes through a symbolic link, never outside the workspace (not even when the
output folder is swapped for a link while it writes), atomically (SIGTERM or a full disk never
leaves an empty or partial file, nor a temporary file), and every failure of the operating
system is one line and a non-zero exit, never a traceback."""

from __future__ import annotations

import errno
import os
import random
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from tvl_lsp.base import safewrite
from tvl_lsp.base.safewrite import WriteError, open_folder, write_file, write_files

REPO = Path(__file__).resolve().parents[1]
MANY = REPO / "tests" / "data" / "robustness" / "many"


def run(*args, cwd=None, timeout=120, **kw) -> subprocess.CompletedProcess:
    p = subprocess.run([sys.executable, "-m", "tvl_lsp", *map(str, args)], capture_output=True, text=True,
                       timeout=timeout, cwd=cwd, **kw)
    assert "Traceback" not in p.stderr, p.stderr[-3000:]
    return p


def one_line(stderr: str) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, stderr
    return lines[0]


@pytest.fixture()
def ws(tmp_path) -> Path:
    d = tmp_path / "ws"
    shutil.copytree(MANY, d)
    (d / ".git").mkdir()
    (d / ".git" / "config").write_text("[core]\n\trepositoryformatversion = 0\n")
    return d


def generic(ws: Path) -> Path:
    return ws / "src" / "many" / "launch" / "generic.launch"


def expected(ws: Path) -> dict[str, str]:
    """name -> text of every configuration ``generate --mode all`` writes (from --dry-run)."""
    p = run("generate", generic(ws), "--mode", "all", "--limit", "200", "--dry-run")
    out, cur, buf = {}, None, []
    for line in p.stdout.splitlines(keepends=True):
        if line.startswith("==> "):
            if cur:
                out[cur] = "".join(buf)[:-1]  # (print adds a newline after the text)
            cur, buf = Path(line[4:].strip()).name, []
        else:
            buf.append(line)
    if cur:
        out[cur] = "".join(buf)[:-1]
    assert len(out) == 128
    return out


# ------------------------------------------------------------------ the safe writer itself

def test_a_link_is_never_written_through(tmp_path):
    secret = tmp_path / "secret"
    secret.write_text("keep me\n")
    d = tmp_path / "out"
    d.mkdir()
    (d / "b.launch").symlink_to(secret)
    with pytest.raises(WriteError, match="symbolic link") as e:
        write_files(str(d), {"a.launch": "A", "b.launch": "B"}, within=[str(tmp_path)])
    assert "\n" not in str(e.value)
    assert secret.read_text() == "keep me\n"
    assert not (d / "a.launch").exists()  # every target is checked before the first is written


def test_a_fifo_or_a_folder_is_not_a_target(tmp_path):
    os.mkfifo(tmp_path / "fifo.launch")
    (tmp_path / "dir.launch").mkdir()
    with pytest.raises(WriteError, match="not a regular file"):
        write_file(str(tmp_path / "fifo.launch"), "x")
    with pytest.raises(WriteError, match="folder"):
        write_file(str(tmp_path / "dir.launch"), "x")


def test_a_folder_that_is_a_link_or_outside_is_refused(tmp_path):
    ws, outside = tmp_path / "ws", tmp_path / "outside"
    ws.mkdir()
    outside.mkdir()
    (ws / "configs").symlink_to(outside)
    with pytest.raises(WriteError, match="symbolic link"):
        write_files(str(ws / "configs"), {"a.launch": "A"}, within=[str(ws)])
    with pytest.raises(WriteError, match="outside the workspace"):
        write_files(str(outside), {"a.launch": "A"}, within=[str(ws)])
    with pytest.raises(WriteError, match="outside the workspace"):
        write_files(str(ws / ".." / "outside"), {"a.launch": "A"}, within=[str(ws)])
    assert list(outside.iterdir()) == []


def test_the_folder_is_opened_once_a_swap_afterwards_changes_nothing(tmp_path):
    """The check-then-write race (defect 4): the folder is swapped for a link to outside after
    it was opened; the files still land in the folder that was opened, never outside."""
    ws, outside = tmp_path / "ws", tmp_path / "outside"
    (ws / "configs").mkdir(parents=True)
    outside.mkdir()
    with open_folder(str(ws / "configs"), within=[str(ws)]) as d:
        (ws / "configs").rename(ws / "moved")
        (ws / "configs").symlink_to(outside)
        d.write("a.launch", "A")
    assert list(outside.iterdir()) == []
    assert (ws / "moved" / "a.launch").read_text() == "A"


def test_writes_are_atomic_and_a_full_disk_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "a.launch"
    target.write_text("old complete text\n")
    os.chmod(target, 0o640)
    real = os.write

    class FullDisk:
        def __getattr__(self, name):
            return getattr(os, name)

        @staticmethod
        def write(fd, data):
            n = real(fd, bytes(data)[:3])  # a part, then the disk is full
            if n:
                raise OSError(errno.ENOSPC, "No space left on device")
            return n
    monkeypatch.setattr(safewrite, "os", FullDisk())
    with pytest.raises(WriteError) as e:
        write_file(str(target), "new text " * 1000)
    assert str(e.value) == f"cannot write {target}: the disk is full"
    monkeypatch.undo()
    assert target.read_text() == "old complete text\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.launch"]
    write_file(str(target), "new\n")
    assert target.read_text() == "new\n" and (target.stat().st_mode & 0o777) == 0o640  # mode kept


def test_temporary_files_of_dead_writers_are_swept(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True).stdout.strip()
    stale = tmp_path / f"{safewrite.TMP_PREFIX}{dead}-abcdef.tmp"
    stale.write_text("half")
    mine = tmp_path / f"{safewrite.TMP_PREFIX}{os.getpid()}-abcdef.tmp"
    mine.write_text("in progress")
    write_files(str(tmp_path), {"x.launch": "x"})
    assert not stale.exists() and mine.exists()


# ------------------------------------------------------------------ tvl-lsp generate

def test_generate_refuses_a_committed_link_and_writes_nothing(ws):
    configs = ws / "src" / "many" / "configs"
    configs.mkdir()
    names = sorted(expected(ws))
    (configs / names[5]).symlink_to(Path("../../../.git/config"))
    before = (ws / ".git" / "config").read_text()
    p = run("generate", generic(ws), "--mode", "all", "--limit", "200")
    assert p.returncode == 2
    line = one_line(p.stderr)
    assert "symbolic link" in line and names[5] in line
    assert (ws / ".git" / "config").read_text() == before
    assert sorted(x.name for x in configs.iterdir()) == [names[5]]


def test_generate_refuses_an_output_folder_that_is_a_link(ws, tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    (ws / "src" / "many" / "configs").symlink_to(outside)
    p = run("generate", generic(ws), "--mode", "all")
    assert p.returncode == 2 and list(outside.iterdir()) == []
    one_line(p.stderr)


@pytest.mark.parametrize("out, says", [
    ("launch/generic.launch", "not a folder"),          # an existing file as the folder
    ("x" * 300, "too long"),                            # a 300-character folder name
    ("configs/" + "y" * 300, "too long"),
])
def test_generate_os_errors_are_one_line(ws, out, says):
    p = run("generate", generic(ws), "--out", out)
    assert p.returncode == 2
    assert says in one_line(p.stderr)


def _reads(path: Path) -> str | None:
    try:
        return path.read_text()
    except OSError:
        return None


def test_generate_interrupted_by_sigterm_leaves_complete_files_only(ws):
    """kill -TERM at random moments of ``generate --mode all`` (128 files), over an earlier
    complete generation: every file is the old or the new complete text, never empty or cut,
    and no temporary file is left."""
    want = expected(ws)
    configs = ws / "src" / "many" / "configs"
    configs.mkdir()
    for name, text in want.items():  # an earlier generation, complete, with other content
        (configs / name).write_text(text.replace("<launch>", "<launch><!-- old -->"))
    old = {n: (configs / n).read_text() for n in want}
    rng = random.Random(28)
    env = dict(os.environ, PYTHONPATH=str(REPO))
    stopped = mixed = 0
    for _ in range(12):
        proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "generate", str(generic(ws)), "--mode", "all",
                                 "--limit", "200"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
        # the moment: when the first new file is in place (polled, so the same on a fast and a slow
        # machine), then a random few milliseconds more -- the run is in the middle of its writes
        end = time.monotonic() + 60
        while proc.poll() is None and time.monotonic() < end and not any(
                _reads(configs / name) == want[name] for name in want):
            time.sleep(0.0005)
        time.sleep(rng.uniform(0, 0.02))
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
        assert b"Traceback" not in err, err.decode()[-2000:]
        stopped += proc.returncode != 0
        for name in want:
            text = (configs / name).read_text()
            assert text in (want[name], old[name]), f"{name} is neither complete text: {text!r}"
        assert sorted(p.name for p in configs.iterdir()) == sorted(want), "a temporary file was left"
        new = sum((configs / name).read_text() == want[name] for name in want)
        mixed += 0 < new < len(want)
        for name, text in old.items():  # the next run starts over an old generation again
            (configs / name).write_text(text)
    assert mixed, "no run was stopped in the middle of its writes: the test did not test anything"
    assert stopped, "no run was interrupted: the test did not test anything"


def test_check_output_on_a_full_disk_is_one_line(tmp_path, monkeypatch, capsys):
    from tvl_lsp.main import main
    out = tmp_path / "report.json"

    class FullDisk:
        def __getattr__(self, name):
            return getattr(os, name)

        @staticmethod
        def write(fd, data):
            raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(safewrite, "os", FullDisk())
    code = main(["--check", "-j", "1", str(REPO / "examples" / "ws"), "--format", "json", "--output", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert f"cannot write {out}: the disk is full" in err and "Traceback" not in err and "internal error" not in err
    assert list(tmp_path.iterdir()) == []


def test_check_output_refuses_a_link_and_writes_a_stream(tmp_path):
    victim = tmp_path / "victim"
    victim.write_text("keep\n")
    (tmp_path / "report.txt").symlink_to(victim)
    p = run("--check", REPO / "examples" / "ws", "--output", tmp_path / "report.txt")
    assert p.returncode == 2 and "symbolic link" in one_line(p.stderr) and victim.read_text() == "keep\n"
    p = run("--check", REPO / "examples" / "ws", "--output", "/dev/stdout", "-q")
    assert p.returncode in (0, 1) and "constant-condition" in p.stdout


# ------------------------------------------------------------------ the configurator's Generate

def _session(ws: Path):
    from tvl_lsp.configurator import Session
    return Session.open(str(generic(ws)), [str(ws)])


def test_configurator_write_refuses_links_and_survives_a_racing_swap(ws, tmp_path):
    """A process swaps the output folder for a link to outside, over and over, while the
    configurator writes (defect 4): nothing ever lands outside the workspace."""
    from tvl_lsp.configurator import SessionError, api
    s = _session(ws)
    out, _ = s.plan_generation({}, "all", None, 200)
    files = [{"path": f.path, "text": f.text} for f in out]
    configs = Path(files[0]["path"]).parent
    configs.mkdir(parents=True, exist_ok=True)
    outside = tmp_path / "outside"
    outside.mkdir()
    stop = threading.Event()

    def swapper():
        while not stop.is_set():
            try:
                configs.rename(configs.with_name("real"))
                configs.symlink_to(outside)
                time.sleep(0.0005)
                configs.unlink()
                configs.with_name("real").rename(configs)
            except OSError:
                pass
    t = threading.Thread(target=swapper)
    t.start()
    refused = written = 0
    try:
        for _ in range(40):
            try:
                api.write_files(s, files)
                written += 1
            except (OSError, SessionError) as e:  # (refused: the link was seen)
                assert "\n" not in str(e)
                refused += 1
    finally:
        stop.set()
        t.join()
        if configs.is_symlink():
            configs.unlink()
            configs.with_name("real").rename(configs)
    assert list(outside.iterdir()) == [], "a file was written outside the workspace"
    assert refused + written == 40


def test_configurator_generate_over_http_answers_a_json_reason(ws):
    import http.client
    import json
    from tvl_lsp.ui.server import make_server
    configs = ws / "src" / "many" / "configs"
    configs.mkdir()
    secret = ws / ".git" / "config"
    httpd, url = make_server(str(ws), 0)
    t = threading.Thread(target=httpd.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    t.start()
    try:
        port, token = httpd.server_address[1], url.split("token=", 1)[1]
        model = str(generic(ws).with_suffix(".tvl"))

        def post(body):
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
            data = json.dumps(body).encode()
            c.request("POST", "/api/generate", data, {"Host": f"127.0.0.1:{port}", "X-TVL-Token": token,
                                                      "Content-Type": "application/json"})
            r = c.getresponse()
            out = r.status, json.loads(r.read())
            c.close()
            return out
        st, body = post({"model": model, "mode": "all", "limit": 200, "write": False})
        assert st == 200
        victim = Path(body["files"][3]["path"])
        victim.symlink_to(Path("../../../.git/config"))
        before = secret.read_text()
        st, body = post({"model": model, "mode": "all", "limit": 200})
        assert st == 409 and "symbolic link" in body["error"] and secret.read_text() == before
    finally:
        httpd.shutdown()
        httpd.server_close()
