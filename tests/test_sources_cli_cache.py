"""``tvl-lsp extract`` (stable, sorted output; JSON fields; exit codes) and the extraction cache (by
content, in memory and on disk, checksummed; only changed files parsed again)."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

from tvl_lsp.graph.sources import cache, extract
from tvl_lsp.main import main

WS = Path(__file__).parent / "data" / "sources" / "ws"
FIELDS = {"package", "executable", "kind", "name", "type", "file", "line", "dynamic"}


def _run(argv, capsys):
    code = main(["extract", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_json_rows_sorted_and_stable(capsys):
    code, out, err = _run([str(WS), "--json", "--no-cache"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    rows = doc["endpoints"]
    assert rows and all(FIELDS <= set(r) for r in rows)
    keys = [(r["package"], r["executable"], r["file"], r["line"], r["col"], r["kind"], r["name"]) for r in rows]
    assert keys == sorted(keys)
    row = next(r for r in rows if r["executable"] == "listener" and r["name"] == "chatter")
    assert row == {**row, "kind": "subscribe", "type": "std_msgs/String", "line": 34, "dynamic": False,
                   "package": "ros1_cpp", "api": "roscpp", "ros": 1}
    assert row["file"].endswith("ros1_cpp/src/listener.cpp")
    dyn = next(r for r in rows if r["name"] == "{out}")
    assert dyn["dynamic"] is True and dyn["expression"] == "out"
    exes = {(x["package"], x["executable"]): x for x in doc["executables"]}
    assert exes[("ros2_cpp", "driver")]["aliases"] == ["ros2_cpp::Driver"]
    assert exes[("ros2_cpp", "ros2_cpp::Filter")]["kind"] == "component"
    # the same output again (from the cache this time)
    code2, out2, _ = _run([str(WS), "--json"], capsys)
    code3, out3, _ = _run([str(WS), "--json"], capsys)
    assert code2 == code3 == 0 and out2 == out3 == out


def test_text_output_and_exit_codes(capsys, tmp_path):
    code, out, _ = _run([str(WS / "src" / "ros1_cpp")], capsys)
    assert code == 0
    assert "ros1_cpp/listener  (executable, C++, 1 source(s))" in out
    assert any(line.split()[:3] == ["subscribe", "chatter", "std_msgs/String"] for line in out.splitlines())
    assert "dynamic: out" in out
    code, _, err = _run([str(tmp_path / "missing")], capsys)
    assert code == 2 and "no such file or folder" in err
    (tmp_path / "empty").mkdir()
    code, _, err = _run([str(tmp_path / "empty")], capsys)
    assert code == 2 and "no ROS package" in err
    # sources without a package.xml: one package named after the folder
    (tmp_path / "bare").mkdir()
    (tmp_path / "bare" / "node.py").write_text("import rospy\nfrom std_msgs.msg import String\n"
                                               "rospy.Publisher('out', String, queue_size=1)\n")
    code, out, _ = _run([str(tmp_path / "bare"), "--json", "--no-cache"], capsys)
    rows = json.loads(out)["endpoints"]
    assert code == 0 and [(r["package"], r["kind"], r["name"], r["type"]) for r in rows] == [
        ("bare", "publish", "out", "std_msgs/String")]


def test_only_changed_files_are_parsed_again(tmp_path, monkeypatch):
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    ws = tmp_path / "ws"
    shutil.copytree(WS, ws)
    cache.clear_memory()
    first = extract([str(ws)])
    assert 10 < first.files_parsed <= first.files_read   # (two empty __init__.py: one content, one parse)
    again = extract([str(ws)])
    assert again.files_parsed == 0 and _rows(again) == _rows(first)
    talker = ws / "src" / "ros1_cpp" / "src" / "talker.cpp"
    talker.write_text(talker.read_text().replace('"joint"', '"wrist"'))
    edited = extract([str(ws)])
    assert edited.files_parsed == 1
    assert ("talker", "publish", "arm/wrist") in _rows(edited) and ("talker", "publish", "arm/joint") not in _rows(edited)
    # a new process: everything from the disk cache
    cache.clear_memory()
    disk = extract([str(ws)])
    assert disk.files_parsed == 0 and _rows(disk) == _rows(edited)
    # unsaved text: parsed, the disk file untouched
    text = talker.read_text().replace('"wrist"', '"elbow"')
    unsaved = extract([str(ws)], texts={str(talker): text})
    assert unsaved.files_parsed == 1 and ("talker", "publish", "arm/elbow") in _rows(unsaved)
    assert '"wrist"' in talker.read_text()


def test_a_damaged_cache_entry_is_ignored_and_removed(tmp_path, monkeypatch):
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    ws = tmp_path / "ws"
    shutil.copytree(WS / "src" / "ros2_cpp", ws / "src" / "ros2_cpp")
    cache.clear_memory()
    good = extract([str(ws)])
    blobs = sorted((tmp_path / "cache").glob("src-*.json"))
    assert len(blobs) == good.files_parsed
    for i, b in enumerate(blobs):
        data = b.read_bytes()
        b.write_bytes(data[: len(data) // 2] if i % 2 else data.replace(b'"calls"', b'"callz"'))
    cache.clear_memory()
    again = extract([str(ws)])
    assert again.files_parsed == len(blobs) and _rows(again) == _rows(good)
    cache.clear_memory()
    third = extract([str(ws)])
    assert third.files_parsed == 0      # rewritten sound


def test_disk_cache_off(tmp_path, monkeypatch):
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", "")
    cache.clear_memory()
    ex = extract([str(WS / "src" / "ros2_py")])
    assert ex.files_parsed > 0 and not any(p.name.startswith("src-") for p in tmp_path.iterdir())
    assert os.environ["TVL_LSP_CACHE_DIR"] == ""


def _rows(ex):
    return {(x.name, e.kind, e.name) for x in ex.executables for e in x.endpoints}
