"""The counting cache does not trust its folder (issue #28, defects 5, 6, 7 and 8):
``TVL_LSP_CACHE_DIR`` may be a shared folder, a copied one, one another user writes to.

- a forged ``.count``, an entry copied from another key, a facts file forged with a recomputed
  checksum: ignored (the seal is an HMAC under a secret outside the folder), the count computed
  again and right;
- a FIFO, a link to ``/dev/zero`` or to a file outside in place of an entry: never a hang,
  never an unbounded read;
- eviction deletes only the files the cache names and recognises;
- a full cache disk: the count is still answered, no traceback, no temporary file left;
- ``TVL_LSP_CACHE_MAX_MB=inf`` / ``1e400`` / words: explained in one line, the default used.
"""

from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tvl_lsp.analysis.counting import cache as C
from tvl_lsp.analysis.counting import service as S
from tvl_lsp.base import safewrite

REPO = Path(__file__).resolve().parents[1]
CARDS = REPO / "tests" / "data" / "counting" / "cards.tvl"
TWO = "p cnf 2 1\n1 2 0\n"


def count_cli(path, env, *extra, timeout=60) -> subprocess.CompletedProcess:
    p = subprocess.run([sys.executable, "-m", "tvl_lsp", "count", str(path), *extra], capture_output=True,
                       text=True, timeout=timeout, env=env)
    assert "Traceback" not in p.stderr, p.stderr[-3000:]
    return p


@pytest.fixture()
def env(tmp_path):
    e = dict(os.environ, PYTHONPATH=str(REPO), TVL_LSP_CACHE_DIR=str(tmp_path / "cache"),
             TVL_LSP_CACHE_KEY_FILE=str(tmp_path / "key" / "cache.key"))
    e.pop("TVL_LSP_CACHE_MAX_MB", None)
    return e


def entries(folder: Path, suffix: str) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.name.endswith(suffix))


def test_a_forged_count_is_not_printed(tmp_path, env):
    m = tmp_path / "two.dimacs"
    m.write_text(TWO)
    assert count_cli(m, env).stdout.strip() == "3"
    cache = Path(env["TVL_LSP_CACHE_DIR"])
    (count,) = entries(cache, ".count")
    count.write_text("999\n")                       # the previous format, forged
    assert count_cli(m, env).stdout.strip() == "3"
    (count,) = entries(cache, ".count")
    payload = json.dumps({"key": count.name[:-6], "count": format(999, "x"), "nnf": None}).encode()
    head = json.dumps({"tvl-lsp": C.ENTRY, "size": len(payload), "mac": "0" * 64}).encode()
    count.write_bytes(head + b"\n" + payload)      # the format, with a made-up seal
    assert count_cli(m, env).stdout.strip() == "3"


def test_an_entry_copied_from_another_key_is_ignored(tmp_path, env):
    a, b = tmp_path / "a.dimacs", tmp_path / "b.dimacs"
    a.write_text(TWO)
    b.write_text("p cnf 3 1\n1 2 3 0\n")
    assert count_cli(a, env).stdout.strip() == "3"
    cache = Path(env["TVL_LSP_CACHE_DIR"])
    (ka,) = entries(cache, ".count")
    assert count_cli(b, env).stdout.strip() == "7"
    (kb,) = set(entries(cache, ".count")) - {ka}
    kb.write_bytes(ka.read_bytes())                  # a's sound entry under b's name
    assert count_cli(b, env).stdout.strip() == "7"


@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "outside", "folder"])
@pytest.mark.parametrize("suffix", [".count", ".nnf"])
def test_special_files_in_the_cache_are_a_miss(tmp_path, env, kind, suffix):
    m = tmp_path / "two.dimacs"
    m.write_text(TWO)
    assert count_cli(m, env).stdout.strip() == "3"
    cache = Path(env["TVL_LSP_CACHE_DIR"])
    for p in entries(cache, suffix):
        p.unlink()
        if kind == "fifo":
            os.mkfifo(p)
        elif kind == "dev-zero":
            p.symlink_to("/dev/zero")
        elif kind == "outside":
            secret = tmp_path / "secret.txt"
            secret.write_text("o 1 0\n")
            p.symlink_to(secret)
        else:
            p.mkdir()
    t = time.monotonic()
    assert count_cli(m, env, timeout=30).stdout.strip() == "3"
    assert time.monotonic() - t < 20


def test_service_reads_never_block_on_a_fifo_or_dev_zero(fresh_cache):
    svc = S.CNFCounter(2, [[1, 2]], 2)
    assert svc.count().value == 3
    key = svc.key
    for name in (f"{key}.count", f"{key}.nnf"):
        (fresh_cache / name).unlink()
    os.mkfifo(fresh_cache / f"{key}.count")
    (fresh_cache / f"{key}.nnf").symlink_to("/dev/zero")
    S.MEMORY.clear()
    d = C.DiskCache()
    assert d.get_count(key) is None and d.get(key) is None and not d.has(key)
    svc = S.CNFCounter(2, [[1, 2]], 2)
    assert svc.circuit().circuit.count([]) == 3   # compiled again, and stored again
    assert d.get_count(key) == 3 and d.get(key) is not None


def test_a_tampered_nnf_is_compiled_again(fresh_cache):
    svc = S.CNFCounter(3, [[1, 2], [-1, 3]], 3)
    want = svc.count([1]).value
    nnf = fresh_cache / f"{svc.key}.nnf"
    nnf.write_text("o 1 0\nt 2 0\n1 2 0\n")        # a valid d-DNNF of another formula
    S.MEMORY.clear()
    assert S.CNFCounter(3, [[1, 2], [-1, 3]], 3).count([1]).value == want


def test_eviction_deletes_only_what_the_cache_wrote(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    user = {"notes.txt": "x" * 5000, "photo.jpg": "y" * 5000, "e" * 64 + ".nnf": "my own file" * 500,
            "report.count": "42\n", "data.facts": "{}" * 2000}
    for name, text in user.items():
        (shared / name).write_text(text)
    (shared / "sub").mkdir()
    (shared / "link.nnf").symlink_to(shared / "notes.txt")
    d = C.DiskCache(shared, limit=3000)
    for i in range(6):
        d.put(f"{i:064x}", "o 1 0\n" + "x" * 994, 1)
        d.put_blob(f"{i:064x}.facts", b"z" * 500)
    for name, text in user.items():
        assert (shared / name).read_text() == text, f"{name} was touched"
    assert (shared / "sub").is_dir() and (shared / "link.nnf").is_symlink()
    ours = [p for p in shared.iterdir() if p.name[:64] in {f"{i:064x}" for i in range(6)}]
    assert sum(p.stat().st_size for p in ours) <= 3000 and ours


def test_a_full_cache_disk_answers_and_leaves_no_temporary(fresh_cache, monkeypatch):
    fresh_cache.mkdir(parents=True, exist_ok=True)
    real = os.write

    class FullDisk:
        def __getattr__(self, name):
            return getattr(os, name)

        @staticmethod
        def write(fd, data):
            real(fd, bytes(data)[:1])
            raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(safewrite, "os", FullDisk())
    assert S.CNFCounter(3, [[1, 2], [-1, 3]], 3).count().value == 4
    n, cls = 60, [[i, i + 1] for i in range(1, 60)]
    assert S.CNFCounter(n, cls, n).count(timeout=30).value > 0  # (d4 in a child: its files fail too)
    monkeypatch.undo()
    assert [p.name for p in fresh_cache.iterdir()] == []


def test_a_full_cache_disk_from_the_command_line(tmp_path, env):
    """RLIMIT_FSIZE stands for a disk that fills up: every write past 64 bytes fails (EFBIG)."""
    import resource
    m = tmp_path / "m.dimacs"
    m.write_text("p cnf 40 3\n1 2 0\n3 -4 0\n5 6 7 0\n")

    def small_files():
        import signal
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (64, 64))
    p = subprocess.run([sys.executable, "-m", "tvl_lsp", "count", str(m)], capture_output=True, text=True,
                       timeout=60, env=env, preexec_fn=small_files)
    assert "Traceback" not in p.stderr and p.returncode == 0, p.stderr
    assert p.stdout.strip() == str(3 * 3 * 7 * 2 ** 33)
    cache = Path(env["TVL_LSP_CACHE_DIR"])
    assert not [q for q in cache.iterdir() if q.name.startswith(".")] if cache.exists() else True


@pytest.mark.parametrize("value", ["inf", "1e400", "nan", "-5", "lots"])
def test_a_bad_cache_size_is_explained_not_fatal(tmp_path, env, value):
    m = tmp_path / "two.dimacs"
    m.write_text(TWO)
    env["TVL_LSP_CACHE_MAX_MB"] = value
    p = count_cli(m, env)
    assert p.returncode == 0 and p.stdout.strip() == "3"
    assert f"TVL_LSP_CACHE_MAX_MB={value!r} is not valid" in p.stderr and "using 512 MB" in p.stderr


def test_the_secret_is_refused_when_others_can_read_it(tmp_path, monkeypatch):
    key = tmp_path / "k" / "cache.key"
    monkeypatch.setenv("TVL_LSP_CACHE_KEY_FILE", str(key))
    monkeypatch.setattr(C, "_SECRET", [])
    s1 = C.secret()
    assert key.stat().st_mode & 0o777 == 0o600 and bytes.fromhex(key.read_text().strip()) == s1
    monkeypatch.setattr(C, "_SECRET", [])
    assert C.secret() == s1                          # read back
    key.chmod(0o644)
    monkeypatch.setattr(C, "_SECRET", [])
    assert C.secret() != s1                          # readable by others: not used
    monkeypatch.setattr(C, "_SECRET", [])
    key.unlink()
    key.symlink_to(tmp_path / "planted")
    (tmp_path / "planted").write_text("ab" * 32 + "\n")
    (tmp_path / "planted").chmod(0o600)
    assert C.secret() != bytes.fromhex("ab" * 32)  # a link is not our file
    monkeypatch.setattr(C, "_SECRET", [])


def test_sealed_entries_round_trip_and_reject_tampering():
    data = C.seal("k.facts", b"payload")
    assert C.unseal("k.facts", data) == b"payload"
    assert C.unseal("other.facts", data) is None
    assert C.unseal("k.facts", data.replace(b"payload", b"paylaod")) is None
    assert C.unseal("k.facts", data[:-1]) is None
    assert C.unseal("k.facts", b"[" * 100000) is None
