"""Hostile and broken input (issue 12): never a hang, a memory bomb, a traceback, a file read
or quoted from outside the workspace -- a clear diagnostic instead.

The fixtures in ``tests/data/hostile/ws`` are the regression files of the defects found; the
special files (a link to ``/dev/zero``, a FIFO) and the big malformed file are made by the
tests.  Each ``--check`` runs in a child process under a memory limit (1.5 GB of address space)
and a CPU limit, so a regression fails the test instead of the machine.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from tvl_lsp.base import files, yamlsafe
from tvl_lsp.launch import evalguard
from tvl_lsp.launch.ros1 import subst
from tvl_lsp.launch.ros2 import pyexpr
from tvl_lsp.project import budget
from tvl_lsp.project.check import MAX_SAME_CODE, _dedupe_sort

DATA = Path(__file__).resolve().parent / "data" / "hostile" / "ws"
MEM_LIMIT = 1536 * 1024 * 1024
CPU_LIMIT = 60


def _limits():
    resource.setrlimit(resource.RLIMIT_AS, (MEM_LIMIT, MEM_LIMIT))
    resource.setrlimit(resource.RLIMIT_CPU, (CPU_LIMIT, CPU_LIMIT))


def check(*paths, cwd=None) -> tuple[int, list[dict], str]:
    """``tvl-lsp --check --format json PATHS`` under the limits: (exit code, diagnostics, stderr)."""
    p = subprocess.run([sys.executable, "-m", "tvl_lsp", "--check", "--format", "json", *map(str, paths)],
                       capture_output=True, text=True, timeout=180, preexec_fn=_limits, cwd=cwd)
    assert p.returncode in (0, 1), f"exit {p.returncode}: {p.stderr[-2000:]}"
    assert "Traceback" not in p.stderr, p.stderr[-2000:]
    out = json.loads(p.stdout) if p.stdout.strip() else []
    diags = out if isinstance(out, list) else out.get("diagnostics", out)
    assert not [d for d in diags if d["code"] == "internal-error"], diags
    return p.returncode, diags, p.stderr


@pytest.fixture()
def ws(tmp_path) -> Path:
    dst = tmp_path / "ws"
    shutil.copytree(DATA, dst)
    return dst


def codes(diags, name=None):
    return sorted({d["code"] for d in diags if name is None or d["path"].endswith(name)})


# ---------------------------------------------------------------- special files and disclosure

def test_links_to_devices_and_fifos_are_reported_not_read(ws):
    launch = ws / "src" / "hostile" / "launch"
    os.symlink("/dev/zero", launch / "zero.launch")
    os.symlink("/dev/zero", ws / "src" / "hostile" / "models" / "zero.tvl")
    os.mkfifo(launch / "fifo.launch")
    rc, diags, _ = check(ws)   # a FIFO would block for ever, /dev/zero would exhaust memory
    by = {(Path(d["path"]).name, d["code"]) for d in diags}
    assert ("zero.launch", "file-unreadable") in by
    assert ("zero.tvl", "file-unreadable") in by
    assert ("fifo.launch", "file-unreadable") in by
    msg = next(d["message"] for d in diags if d["path"].endswith("fifo.launch"))
    assert "FIFO" in msg and "not a regular file" in msg


def test_a_special_file_named_on_the_command_line_says_why_it_is_not_checked(ws):
    link = ws / "zero.launch"
    os.symlink("/dev/zero", link)
    rc, diags, err = check(link)
    # a diagnostic of the report (file-unreadable), not silence (issue 27, class 7)
    assert rc == 1 and [d["code"] for d in diags] == ["file-unreadable"]
    assert "zero.launch is not checked: cannot be read: it is a character device" in diags[0]["message"]


def test_launch_includes_of_special_files(ws):
    rc, diags, _ = check(ws / "src" / "hostile" / "launch" / "include_special.launch")
    msgs = [d["message"] for d in diags]
    assert any("'/dev/zero' is not read: it is a character device" in m for m in msgs), msgs
    assert any("[/dev/urandom] is not read: it is a character device" in m for m in msgs), msgs


def test_model_includes_outside_the_workspace_are_not_read_nor_quoted(ws):
    rc, diags, _ = check(ws / "src" / "hostile" / "models" / "include_outside.tvl")
    assert rc == 1
    assert all(Path(d["path"]).name == "include_outside.tvl" for d in diags), diags
    inc = [d for d in diags if d["code"] == "include-missing"]
    assert len(inc) == 2 and all("outside the model's workspace" in d["message"] for d in inc)
    # nothing of /etc/passwd's content (its lines look like root:x:0:0:root:/root:/bin/bash)
    assert not any(t in d["message"] for d in diags for t in (":0:0", "nologin", "/bin/"))


def test_model_include_of_a_device(ws):
    rc, diags, _ = check(ws / "src" / "hostile" / "models" / "include_device.tvl")
    assert [d["code"] for d in diags if d["severity"] == "error"] == ["include-missing"]


# ---------------------------------------------------------------- evaluation, YAML, characters

@pytest.mark.parametrize("name", ["eval_factorial", "eval_power_tower", "eval_big_sequences", "eval_deep_not"])
def test_eval_bombs_are_not_analysable_notes(ws, name):
    rc, diags, _ = check(ws / "src" / "hostile" / "launch" / f"{name}.launch")
    assert rc == 0
    assert diags and all(d["code"] == "condition-not-analysable" and d["severity"] == "information"
                         for d in diags), diags


def test_yaml_alias_bomb_gets_a_diagnostic(ws):
    rc, diags, _ = check(ws / "src" / "hostile" / "launch" / "rosparam_alias_bomb.launch")
    assert len(diags) == 1 and "expands to more than" in diags[0]["message"]
    assert diags[0]["range"] == {"start": {"line": 2, "character": 3}, "end": {"line": 2, "character": 11}}  # <rosparam


def test_a_lone_surrogate_reference_is_an_xml_error_as_in_roslaunch(ws):
    rc, diags, _ = check(ws / "src" / "hostile" / "launch" / "surrogate_charref.launch")
    assert [d["code"] for d in diags] == ["xml-syntax"]
    assert "reference to invalid character number" in diags[0]["message"]


def test_a_megabyte_of_malformed_tags_is_checked_quickly_with_few_lines(ws):
    f = ws / "src" / "hostile" / "launch" / "malformed.launch"
    f.write_text("<launch>" + '<node pkg="a" type="b" name="x" <<' * 30_000 + "</launch>")
    assert f.stat().st_size > 1_000_000
    rc, diags, _ = check(f)
    assert rc == 1 and len(diags) <= 10
    assert "xml-syntax" in codes(diags)


def test_an_element_of_a_hundred_thousand_attributes_is_read_up_to_the_limit(ws):
    """lxml lists an element's attributes in quadratic time (300,000 took minutes); tvl-lsp
    reads the first MAX_ATTRIBUTES and says so, on the tag."""
    from tvl_lsp.launch.xml import MAX_ATTRIBUTES
    f = ws / "src" / "hostile" / "launch" / "attributes.launch"
    f.write_text('<launch>\n  <node pkg="p" type="t" name="n" '
                 + " ".join(f'a{i}="v"' for i in range(100_000)) + "/>\n</launch>\n")
    rc, diags, _ = check(f)
    big = [d for d in diags if d["code"] == "launch-file-too-large"]
    assert rc == 1 and len(big) == 1, big
    assert f"100,003 attributes" in big[0]["message"] and f"first {MAX_ATTRIBUTES:,}" in big[0]["message"]
    assert (big[0]["range"]["start"], big[0]["range"]["end"]) == ({"line": 1, "character": 3},
                                                                  {"line": 1, "character": 7})
    # the first ones are read: 997 unknown attributes (a0 ... a996) after pkg, type and name
    assert len([d for d in diags if d["code"] == "unknown-attribute"]) == MAX_ATTRIBUTES - 3


@pytest.mark.parametrize("name", ["big.launch", "big.launch.xml", "big.launch.yaml"])
def test_a_launch_file_over_two_million_characters_is_refused_at_once(ws, name):
    """Real launch files have ~20,000 characters at most; the front ends spend microseconds per
    character of a value (YAML, shlex, substitutions): 18 MB of YAML took 29 s before."""
    from tvl_lsp.launch.xml import MAX_TEXT
    f = ws / "src" / "hostile" / "launch" / name
    if name.endswith(".yaml"):
        f.write_text("launch:\n" + "".join(f"- node:\n    pkg: p\n    exec: e\n    name: n{i}\n    args: '{'y' * 2000}'\n"
                                           for i in range(1100)))
    else:
        f.write_text("<launch>\n" + "".join(f'  <node pkg="p" type="t" name="n{i}" args="{"y" * 2000}"/>\n'
                                              for i in range(1100)) + "</launch>\n")
    assert len(f.read_text()) > MAX_TEXT
    rc, diags, _ = check(f)
    assert rc == 1 and [d["code"] for d in diags] == ["launch-file-too-large"], diags
    assert f"at most {MAX_TEXT:,} characters" in diags[0]["message"]


def test_repeated_diagnostics_are_collapsed(ws):
    f = ws / "src" / "hostile" / "launch" / "dups.launch"
    f.write_text("<launch>\n" + '  <node pkg="a" type="b" name="x"/>\n' * (MAX_SAME_CODE + 300) + "</launch>\n")
    rc, diags, _ = check(f)
    dup = [d for d in diags if d["code"] == "duplicate-node"]
    assert len(dup) == MAX_SAME_CODE + 1
    assert "and 299 more [duplicate-node]" in dup[-1]["message"]


# ---------------------------------------------------------------- the pieces, in-process

def test_read_bounded_refuses_what_is_not_a_regular_file(tmp_path):
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    with pytest.raises(files.Unreadable, match="FIFO"):
        files.read_text(str(fifo))
    with pytest.raises(files.Unreadable, match="character device"):
        files.read_text("/dev/zero")
    big = tmp_path / "big"
    big.write_bytes(b"x" * 2000)
    with pytest.raises(files.Unreadable, match="larger than"):
        files.read_text(str(big), cap=1000)
    assert files.read_head(str(big), 10) == b"x" * 10
    assert files.read_text_or_none(str(tmp_path)) is None  # a folder


def test_model_workspace_and_inside(tmp_path):
    (tmp_path / "ws" / "src" / "p").mkdir(parents=True)
    m = tmp_path / "ws" / "src" / "p" / "m.tvl"
    assert files.model_workspace(str(m)) == str(tmp_path / "ws")
    assert files.inside(str(tmp_path / "ws" / "x"), [str(tmp_path / "ws")])
    assert not files.inside("/etc/passwd", [str(tmp_path / "ws")])
    os.symlink("/etc/passwd", tmp_path / "ws" / "link")
    assert not files.inside(str(tmp_path / "ws" / "link"), [str(tmp_path / "ws")])  # links resolved


@pytest.mark.parametrize("expr", ["factorial(10**7)", "((10**1000)**1000)**1000", "[0]*10**9",
                                  "'a'*10000*10000*100", "2**10**9", "'x'*99999+'y'*99999",
                                  "list(range(10**9))", "not " * 5000 + "True", "(" * 500 + "1" + ")" * 500])
def test_eval_bounds_ros1_and_ros2(expr):
    with pytest.raises((subst.NotAnalysable, subst.SubstError)):
        subst.run_eval(subst.parse_eval(expr), {}, {})
    with pytest.raises((pyexpr.NotAnalysable, pyexpr.EvalFailure)):
        pyexpr.evaluate(expr)


def test_eval_within_bounds_still_computes():
    assert subst.run_eval(subst.parse_eval("2**100"), {}, {}) == str(2 ** 100)
    assert subst.run_eval(subst.parse_eval("factorial(20)"), {}, {}) == str(2432902008176640000)
    assert pyexpr.evaluate("'ab'*3") == "ababab"
    with pytest.raises(evalguard.TooBig):
        evalguard.check_binop(__import__("operator").pow, 10, 10 ** 6)


def test_yaml_bounds():
    bomb = "a: &a [1,1,1,1,1,1,1,1,1,1]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 10)}]\n" for i in range(6))
    with pytest.raises(yamlsafe.YamlTooBig):
        yamlsafe.safe_load(bomb)
    with pytest.raises(yamlsafe.YamlTooBig):
        yamlsafe.safe_load("[" * 300 + "]" * 300)
    assert yamlsafe.safe_load("a: &x [1, 2]\nb: *x\n") == {"a": [1, 2], "b": [1, 2]}


def test_budget_stops_a_runaway_check_and_reports_it():
    def spin():
        while True:
            pass
    out = budget.limited("/ws/x.launch", spin, 0.5)
    assert [d.code for d in out] == ["analysis-budget-exceeded"]
    out = budget.limited("/ws/x.launch", lambda: (_ for _ in ()).throw(MemoryError()), 5)
    assert [d.code for d in out] == ["analysis-budget-exceeded"]


def test_collapse_keeps_the_first_and_counts_the_rest():
    from tvl_lsp.base.diagnostics import Diagnostic, Severity
    from tvl_lsp.base.text import Pos, Span
    ds = [Diagnostic("unknown-tag", Severity.WARNING, "/f.launch", Span(Pos(i, 0), Pos(i, 1)), f"m{i}")
          for i in range(MAX_SAME_CODE + 10)]
    out = _dedupe_sort(ds)
    assert len(out) == MAX_SAME_CODE + 1 and "and 10 more" in out[-1].message
    assert out[-1].span == Span(Pos(MAX_SAME_CODE, 0), Pos(MAX_SAME_CODE, 1))
