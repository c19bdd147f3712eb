"""roslaunch's own test files and real robots' launch files vs what Debian's roslaunch 1.15 did
(``ROSLAUNCH_RESULTS.json``): files it loads get no error; files it rejects for a reason inside
the file get at least one.  Corpus suite (``--corpus DIR``): the files are third-party."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tvl_lsp.launch import analyse_launch, check_launch, find_packages

pytestmark = pytest.mark.corpus

# rejected by roslaunch for reasons outside the file: packages/files that are not in the corpus
# (ResourceNotFound, files under /usr/share), or a command run relative to roslaunch's cwd.
OUTSIDE = {
    "roslaunch/resources/example-params.launch",       # $(find rosparam): /usr/share
    "roslaunch/test/xml/test-rosparam-invalid-3.xml",  # $(find rosparam): /usr/share
    "gazebo_ros_pkgs/gazebo_plugins/test2/spawn_model/spawn_box_param.launch",  # `cat relative/path` fails
}


def _results(base: Path):
    p = base / "ROSLAUNCH_RESULTS.json"
    if not p.exists():
        pytest.fail(f"{p} not found: the folder given with --corpus has no recorded roslaunch results there")
    return json.loads(p.read_text())


def _check(base: Path):
    res = _results(base)
    pk = find_packages(str(base))
    false_errors, missed = [], []
    for rel, r in sorted(res.items()):
        path = base / rel
        if not path.exists():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        diags = check_launch(analyse_launch(text, str(path), packages=pk))
        errors = [d for d in diags if d.severity == 1]
        # an arg the command line must give is a warning (unset-arg), and so is an undeclared
        # $(arg) in a file checked alone (undefined-arg: roslaunch takes it from name:=value):
        # roslaunch run without it fails, tvl-lsp says why
        found = errors + [d for d in diags if d.code in ("unset-arg", "undefined-arg")]
        if r["ok"]:
            if errors:
                false_errors.append((rel, [(d.code, d.message[:120]) for d in errors[:3]]))
        elif r["error"] not in ("ResourceNotFound", "FileNotFoundError") and rel not in OUTSIDE:
            if not found:
                missed.append((rel, r["message"][:160]))
    return res, false_errors, missed


def test_roslaunch_own_tests(corpus_dir):
    res, false_errors, missed = _check(corpus_dir / "launch" / "roslaunch-tests")
    assert len(res) > 100
    assert false_errors == []
    assert missed == []


def test_real_robots(corpus_dir):
    res, false_errors, missed = _check(corpus_dir / "launch")
    assert len(res) > 200
    assert false_errors == []
    assert missed == []


def _norm(names):
    import re
    return sorted(re.sub(r"_(anon\d+|vm_\d+_\d+)$", "_ANON", n) for n in names)


@pytest.mark.parametrize("sub", ["roslaunch-tests", "."])
def test_concrete_loader_matches_recorded_roslaunch_runs(sub, corpus_dir):
    """``load_launch`` with no args: the same nodes as roslaunch for every file it loaded, and
    a load error for every file it rejected (here ResourceNotFound counts: the concrete loader
    mirrors roslaunch, packages outside the corpus included)."""
    from tvl_lsp.launch import load_launch
    base = corpus_dir / "launch" / sub
    res = _results(base)
    pk = find_packages(str(base))
    wrong = []
    for rel, r in sorted(res.items()):
        if rel in OUTSIDE and not r["ok"] and "cat" in r["message"]:
            continue  # the command's relative path depends on roslaunch's working directory
        lr = load_launch(str(base / rel), {}, packages=pk)
        if r["ok"]:
            if lr.error or _norm(n["name"] for n in lr.nodes) != _norm(r["nodes"]):
                wrong.append((rel, lr.error, [n["name"] for n in lr.nodes], r["nodes"]))
        elif lr.error is None:
            wrong.append((rel, r["error"], r["message"][:100]))
    assert wrong == []
