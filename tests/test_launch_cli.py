"""``tvl-lsp launch FILE [name:=value ...] [--json]``."""

from __future__ import annotations

import json
from pathlib import Path

from tvl_lsp.main import main

WS = Path(__file__).resolve().parent / "data" / "launch" / "ws"


def test_cli_json_nodes_and_exit_codes(capsys):
    f = str(WS / "src" / "alpha" / "launch" / "conflicts.launch")
    assert main(["launch", f, "A:=true", "B:=false", "--json", "--workspace", str(WS)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [n["name"] for n in out["nodes"]] == ["/worker"] and "error" not in out
    assert main(["launch", f, "A:=true", "B:=true", "--json", "--workspace", str(WS)]) == 1
    out = json.loads(capsys.readouterr().out)
    assert "multiple nodes named [/worker]" in out["error"]


def test_cli_text_view_shows_namespaces_remaps_and_include_tree(capsys):
    f = str(WS / "src" / "alpha" / "launch" / "generic_ns.launch")
    assert main(["launch", f, "A:=false", "B:=true", "C:=false", "--workspace", str(WS)]) == 0
    out = capsys.readouterr().out
    assert "/left/r1/driver  (beta/driver, ns /left/r1/) args='--rate 5'" in out
    assert "part.launch [ns /left/]" in out
    assert "/passed_b" in out and "/arm/ctrl" in out


def test_cli_usage_errors(capsys):
    assert main(["launch"]) == 2
    assert main(["launch", "/nonexistent/x.launch", "--json"]) == 1
    assert "error" in json.loads(capsys.readouterr().out)
