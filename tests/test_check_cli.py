"""``tvl-lsp --check``: formats, filters, exit codes, reproducibility; ``--explain``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest

from tvl_lsp.main import main
from tvl_lsp.base.diagnostics import Diagnostic, Related, Severity
from tvl_lsp.cli.output import format_github, gh_escape_data, gh_escape_property, to_json_objects, to_sarif
from tvl_lsp.base.text import Pos, Span

HERE = Path(__file__).resolve().parent
PAIRS = HERE / "data" / "pairs"
ROBOT = PAIRS / "robot"
SCHEMA = HERE / "data" / "sarif" / "sarif-schema-2.1.0.json"


def run(capsys, *argv):
    code = main(["--check", "-j", "1", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_text_format_and_exit_code(capsys):
    code, out, err = run(capsys, str(ROBOT))
    assert code == 1                               # undefined-arg, duplicate-node... are errors
    lines = out.splitlines()
    assert lines == sorted(lines, key=lambda l: (l.split(":")[0], int(l.split(":")[1]), int(l.split(":")[2])))
    first = lines[0]
    path, line, col, rest = first.split(":", 3)
    assert path.endswith("robot.launch") and line == "1" and col == "1"
    assert rest.startswith(" warning[missing-arg] ")
    assert any(" error[undefined-arg] " in l and ":14:" in l for l in lines)
    assert "error(s)" in err


def test_clean_tree_exits_zero_and_strict(capsys):
    assert run(capsys, str(PAIRS / "clean"))[0] == 0
    # warnings only: 0, but 1 with --strict
    assert run(capsys, str(ROBOT), "--select", "missing-arg,unmatched-arg")[0] == 0
    assert run(capsys, str(ROBOT), "--select", "missing-arg", "--select", "unmatched-arg", "--strict")[0] == 1


def test_select_and_ignore(capsys):
    _, out, _ = run(capsys, str(ROBOT), "--select", "duplicate-node")
    assert [l.split(" ")[1] for l in out.splitlines()] == ["error[duplicate-node]"]
    _, out, _ = run(capsys, str(ROBOT), "--ignore", "missing-arg,duplicate-node", "--ignore", "dead-element")
    codes = {l.split(" ")[1].split("[")[1].rstrip("]") for l in out.splitlines()}
    assert codes == {"unmatched-arg", "undefined-arg", "duplicate-arg", "constant-condition"}


def test_usage_errors_exit_2(capsys):
    code, _, err = run(capsys, "--select", "duplicate-nod", str(ROBOT))
    assert code == 2 and "unknown diagnostic code" in err and "duplicate-node" in err
    assert run(capsys, "/no/such/path")[0] == 2
    assert run(capsys, "--format", "xml", str(ROBOT))[0] == 2
    assert run(capsys, "--bogus")[0] == 2


def test_json_format_positions_are_lsp(capsys, tmp_path):
    _, out, _ = run(capsys, str(ROBOT), "--format", "json")
    data = json.loads(out)
    assert isinstance(data, list) and data
    keys = {"path", "range", "severity", "code", "message", "related", "witness"}
    assert all(set(o) == keys for o in data)
    und = next(o for o in data if o["code"] == "undefined-arg")
    line = (ROBOT / "robot.launch").read_text().splitlines()[und["range"]["start"]["line"]]
    s, e = und["range"]["start"]["character"], und["range"]["end"]["character"]
    assert line[s:e] == "$(arg arm_speed)"
    assert und["witness"] == {"Arm": True, "Base": True, "Camera": True, "Lidar": False, "Lidr": False,
                              "Robot": True, "Tracks": True, "Wheels": False}
    assert all(o["severity"] in ("error", "warning", "information", "hint") for o in data)
    miss = next(o for o in data if o["code"] == "missing-arg")
    assert miss["related"][0]["path"].endswith("robot.tvl") and miss["witness"] is None


def test_json_character_is_utf16(tmp_path, capsys):
    # a non-BMP character before the problem: 2 UTF-16 code units, 1 code point
    (tmp_path / "u.launch").write_text('<launch>\n  <node pkg="p" type="t" name="n" args="😀 $(arg nope)"/>\n</launch>\n')
    _, out, _ = run(capsys, str(tmp_path), "--format", "json")
    (o,) = [o for o in json.loads(out) if o["code"] == "undefined-arg"]
    line = (tmp_path / "u.launch").read_text().splitlines()[1]
    cp = line.index("$(arg nope)")
    assert o["range"]["start"]["character"] == cp + 1
    # text format: 1-based code points
    _, out, _ = run(capsys, str(tmp_path))
    assert f":2:{cp + 1}: warning[undefined-arg]" in out  # checked alone: the command line may give it


def test_sarif_validates_against_the_official_schema(capsys):
    _, out, _ = run(capsys, str(PAIRS), "--format", "sarif")
    log = json.loads(out)
    schema = json.loads(SCHEMA.read_text())
    jsonschema.Draft4Validator.check_schema(schema)
    jsonschema.Draft4Validator(schema).validate(log)
    run0 = log["runs"][0]
    assert log["version"] == "2.1.0"
    ids = [r["id"] for r in run0["tool"]["driver"]["rules"]]
    assert ids == sorted(set(ids))
    for res in run0["results"]:
        assert ids[res["ruleIndex"]] == res["ruleId"]
        loc = res["locations"][0]["physicalLocation"]
        assert loc["artifactLocation"]["uriBaseId"] == "%SRCROOT%"
        assert loc["region"]["startLine"] >= 1 and loc["region"]["startColumn"] >= 1
    assert any("witness" in r.get("properties", {}) for r in run0["results"])


def test_sarif_of_nothing_and_of_odd_paths_validates(tmp_path):
    schema = json.loads(SCHEMA.read_text())
    v = jsonschema.Draft4Validator(schema)
    v.validate(to_sarif([], lambda p: None, str(tmp_path)))
    d = Diagnostic("dead-element", Severity.HINT, "/elsewhere/a b%.launch", Span(Pos(0, 0), Pos(0, 0)), "m",
                   related=[Related("/x.tvl", Span(Pos(2, 1), Pos(2, 3)), "r")], witness={"A": True})
    log = to_sarif([d], lambda p: None, str(tmp_path))
    v.validate(log)
    uri = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    assert uri == "file:///elsewhere/a%20b%25.launch"


def test_github_workflow_commands_are_escaped():
    d = Diagnostic("undefined-arg", Severity.ERROR, os.path.join(os.getcwd(), "a,b:c.launch"),
                   Span(Pos(2, 4), Pos(2, 9)), "50% bad\nnext: line, here")
    out = format_github([d])
    assert out == ("::error file=a%2Cb%3Ac.launch,line=3,col=5,endLine=3,endColumn=10,title=undefined-arg"
                   "::50%25 bad%0Anext: line, here\n")
    w = Diagnostic("missing-arg", Severity.WARNING, "x.launch", Span(Pos(0, 0), Pos(0, 1)), "m")
    n = Diagnostic("constant-condition", Severity.INFORMATION, "x.launch", Span(Pos(0, 0), Pos(0, 1)), "m")
    assert format_github([w]).startswith("::warning ") and format_github([n]).startswith("::notice ")
    assert gh_escape_property("a:b,c%") == "a%3Ab%2Cc%25" and gh_escape_data("\r") == "%0D"


def test_github_format_from_cli(capsys):
    _, out, _ = run(capsys, str(ROBOT), "--format", "github")
    lines = out.splitlines()
    assert lines and all(l.startswith(("::error ", "::warning ", "::notice ")) for l in lines)
    assert any("title=duplicate-node::" in l for l in lines)


def test_output_file_and_reproducibility(tmp_path, capsys):
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    assert run(capsys, str(PAIRS), "--format", "json", "--output", str(a))[0] == 1
    assert capsys.readouterr().out == ""
    code = main(["--check", "-j", "2", str(PAIRS), "--format", "json", "--output", str(b)])
    assert code == 1
    assert a.read_text() == b.read_text()


def test_real_entry_point_runs(tmp_path):
    exe = Path(sys.executable).parent / "tvl-lsp"
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "tvl_lsp"]
    r = subprocess.run(cmd + ["--check", str(PAIRS / "clean")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    r = subprocess.run(cmd + ["--check", "--format", "text", str(ROBOT)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 1 and "error[duplicate-node]" in r.stdout


def test_default_path_is_the_current_folder(capsys, monkeypatch):
    monkeypatch.chdir(PAIRS / "clean")
    code, out, _ = run(capsys)
    assert code == 0 and out == ""
    monkeypatch.chdir(ROBOT)
    code, out, _ = run(capsys)
    assert code == 1 and out.startswith("robot.launch:1:1: warning[missing-arg]")


def test_garbage_never_crashes_the_check(tmp_path, capsys):
    import random
    rnd = random.Random(3)
    blobs = [bytes(rnd.randrange(256) for _ in range(2000)) for _ in range(4)]
    (tmp_path / "bin.launch").write_bytes(blobs[0])
    (tmp_path / "bin.tvl").write_bytes(blobs[1])
    (tmp_path / "bin.yaml").write_bytes(b"configurations:\n" + blobs[2])
    (tmp_path / "empty.launch").write_text("")
    (tmp_path / "empty.tvl").write_text("")
    (tmp_path / "bom.launch.xml").write_bytes(b"\xef\xbb\xbf<launch><node/></launch>")
    (tmp_path / "bomb.launch").write_text('<!DOCTYPE l [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;">]>'
                                          "<launch>&b;</launch>")
    (tmp_path / "deep.launch").write_text("<launch>" + "<group>" * 3000 + "</group>" * 3000 + "</launch>")
    (tmp_path / "p.yml").write_text("configurations:\n  - {lf: bin.launch, tvl: bin.tvl}\n")
    code, out, err = run(capsys, str(tmp_path), "--format", "json")
    assert code == 1, err
    data = json.loads(out)
    assert "internal-error" not in {o["code"] for o in data}
    assert {o["path"] for o in data} >= {str(tmp_path / "bin.launch"), str(tmp_path / "bomb.launch")}


def test_check_document_for_each_kind_of_file():
    from tvl_lsp.project.check import check_document, pairing_of
    ds = check_document(str(PAIRS / "badws/haros_missing.yaml"))
    assert [d.code for d in ds] == ["project-file-not-found"]
    assert check_document(str(PAIRS / "clean/clean.tvl")) == []
    ds = check_document(str(PAIRS / "robot/robot.tvl"), "root Robot { group allOf { A } A -> !A; }")
    assert "void-model" in {d.code for d in ds}
    (p,) = pairing_of(str(PAIRS / "marker/bringup.launch"))
    assert p.rule == "marker" and p.model == str(PAIRS / "clean/clean.tvl")
    assert check_document(str(PAIRS / "nothing.txt")) == []


def test_select_codes_of_every_area_in_a_fresh_process():
    # the codes of the front ends are known before any file is analysed
    r = subprocess.run([sys.executable, "-m", "tvl_lsp", "--check", str(ROBOT), "-q", "--select",
                        "duplicate-node,syntax-error,dead-feature,invalid-project"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 1, r.stderr
    assert [l.split(" ")[1] for l in r.stdout.splitlines()] == ["error[duplicate-node]"]
