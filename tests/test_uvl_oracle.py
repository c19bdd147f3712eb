"""Differential tests against uvlparser 2.5.0, the UVL community's parser.

uvlparser is no dependency of tvl-lsp nor of the ``test`` extra (it installs top-level ``main.py``
and ``uvl/`` into site-packages): it is the ``uvl-oracle`` extra.  Its verdicts on our fixtures
are recorded in tests/data/uvl/uvlparser_verdicts.json and checked here every time; when it is
installed (``pip install -e '.[uvl-oracle]'``, as ``.ci/run`` does, or a folder with its
``main.py`` given as ``UVLPARSER_TARGET``) it is also run live, in a subprocess, on the fixtures
and on the UVL that ``tvl-lsp convert`` writes for our TVL fixtures (which it must accept).
"""

from __future__ import annotations

import json
import os
from importlib import metadata
import subprocess
import sys
from pathlib import Path

import pytest

from tvl_lsp.analysis.convert import convert_model
from tvl_lsp.analysis.formats import parse_any_model
from tvl_lsp.uvl import parse_uvl

ROOT = Path(__file__).resolve().parents[1]
UVL = Path(__file__).parent / "data" / "uvl"
TABLE = json.loads((UVL / "uvlparser_verdicts.json").read_text())["files"]
SYNTAX = {"syntax-error", "illegal-character", "unterminated-comment", "unterminated-string", "multiple-roots"}


def our_verdict(path: Path) -> str:
    res = parse_uvl(path.read_text(), str(path))
    return "reject" if any(d.code in SYNTAX for d in res.errors) else "accept"


def test_every_fixture_has_a_recorded_verdict():
    on_disk = {str(p.relative_to(UVL)) for p in UVL.rglob("*.uvl")}
    assert on_disk == set(TABLE)


@pytest.mark.parametrize("name", sorted(TABLE))
def test_accept_reject_like_uvlparser(name):
    row = TABLE[name]
    want = "accept" if row.get("departure") else row["uvlparser"]
    assert our_verdict(UVL / name) == want


# ------------------------------------------------------------------ the live oracle

ORACLE = r"""
import sys
sys.path.insert(0, sys.argv[1])
from main import get_tree
for p in sys.argv[2:]:
    try:
        get_tree(p)
        print("VERDICT accept")
    except Exception as e:
        print("VERDICT reject")
"""


@pytest.fixture(scope="session")
def uvlparser():
    """The folder that holds uvlparser's top-level ``main.py``: ``UVLPARSER_TARGET``, else the
    installed ``uvl-oracle`` extra.  Nothing is installed during the run."""
    target = os.environ.get("UVLPARSER_TARGET")
    if target and (Path(target) / "main.py").is_file():
        return target
    try:
        main = Path(str(metadata.distribution("uvlparser").locate_file("main.py")))
    except metadata.PackageNotFoundError:
        main = None
    if main is None or not main.is_file():
        pytest.skip("uvlparser 2.5.0 is not installed: .venv/bin/pip install -e '.[uvl-oracle]' (the UVL community's parser)")
    return str(main.parent)


def run_oracle(target: str, paths: list[Path]) -> list[str]:
    p = subprocess.run([sys.executable, "-c", ORACLE, target] + [str(x) for x in paths],
                       capture_output=True, text=True, timeout=600)
    return [ln.split()[1] for ln in p.stdout.splitlines() if ln.startswith("VERDICT ")]


def test_live_uvlparser_agrees_with_the_recorded_verdicts(uvlparser):
    names = sorted(TABLE)
    got = run_oracle(uvlparser, [UVL / n for n in names])
    assert dict(zip(names, got)) == {n: TABLE[n]["uvlparser"] for n in names}


def test_uvlparser_accepts_the_uvl_we_write(uvlparser, tmp_path):
    data = Path(__file__).parent / "data"
    sources = ([ROOT / "examples/ws/src/turtlerand/launch/generic.tvl"] + sorted((data / "pairs").rglob("*.tvl"))
               + sorted((data / "convert").glob("*.tvl")))
    written = []
    for src in sources:
        res = parse_any_model(src.read_text(), str(src))
        out = tmp_path / (src.stem + f"_{len(written)}.uvl")
        out.write_text(convert_model(res.model, "uvl").text)
        written.append(out)
    assert run_oracle(uvlparser, written) == ["accept"] * len(written)
