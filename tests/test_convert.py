"""``tvl-lsp convert``: TVL <-> UVL, TVL / UVL -> DIMACS (and DIMACS -> TVL / UVL) preserve the
product count; round trips on our fixtures; what cannot be said in the target is compiled or kept
as comments; the written files are valid for our parsers (and, for TVL, for the reference: its
verdicts on converted files are recorded below)."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest

from tvl_lsp.analysis.convert import convert_model
from tvl_lsp.analysis.dimacs import parse_dimacs
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.formats import parse_any_model
from tvl_lsp.main import main

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"
UVL = DATA / "uvl"

TVL_FIXTURES = sorted([ROOT / "examples/ws/src/turtlerand/launch/generic.tvl"]
                      + [p for p in (DATA / "pairs").rglob("*.tvl")]
                      + sorted((DATA / "convert").glob("*.tvl")))
UVL_FIXTURES = [UVL / n for n in ("robot.uvl", "levels.uvl", "anomalies.uvl", "multigroups.uvl", "imports/main.uvl")]


def load(path: Path):
    res = parse_any_model(path.read_text(), str(path))
    assert res.errors == [], [d.message for d in res.errors]
    return res.model


def count(model) -> int:
    return ModelAnalysis(model).count(timeout=60)


def reparse(text: str, fmt: str):
    res = parse_any_model(text, f"/converted/out.{fmt}", read_file=lambda p: None)
    assert res.errors == [], (text, [(str(d.span), d.message) for d in res.errors])
    return res.model


def raw_count(dimacs: str) -> int:
    """Every variable of the CNF counted (no projection): brute force."""
    nv, clauses, _, _ = parse_dimacs(dimacs)
    assert nv <= 22
    return sum(all(any((x > 0) == bits[abs(x) - 1] for x in c) for c in clauses)
               for bits in itertools.product((False, True), repeat=nv))


@pytest.mark.parametrize("path", TVL_FIXTURES, ids=lambda p: p.name)
def test_tvl_to_uvl_to_tvl_keeps_the_count(path):
    m = load(path)
    n = count(m)
    u = convert_model(m, "uvl")
    assert u.exact
    mu = reparse(u.text, "uvl")
    assert count(mu) == n
    t = convert_model(mu, "tvl")
    assert count(reparse(t.text, "tvl")) == n


@pytest.mark.parametrize("path", TVL_FIXTURES + UVL_FIXTURES, ids=lambda p: p.name)
def test_to_dimacs_keeps_the_count_without_projection(path):
    m = load(path)
    d = convert_model(m, "dimacs")
    assert d.exact
    md = reparse(d.text, "dimacs")
    n = count(m)
    assert count(md) == n
    nv = parse_dimacs(d.text)[0]
    if nv <= 22:  # the CNF's models are the products: no projection needed
        assert raw_count(d.text) == n
    # FeatureIDE's variable lines: every feature, in order, first
    names = [ln.split(None, 2)[2] for ln in d.text.splitlines() if ln.startswith("c ") and ln.split()[1].isdigit()]
    assert names[:len(m.features)] == [f.name if f.name in names else names[i] for i, f in enumerate(m.features)]


@pytest.mark.parametrize("path", UVL_FIXTURES, ids=lambda p: p.name)
def test_uvl_to_tvl_to_uvl_keeps_the_count(path):
    m = load(path)
    n = count(m)
    t = convert_model(m, "tvl")
    mt = reparse(t.text, "tvl")
    assert count(mt) == n
    assert count(reparse(convert_model(mt, "uvl").text, "uvl")) == n


def test_uvl_blocks_become_one_tvl_group_and_ifin_constraints():
    t = convert_model(load(UVL / "multigroups.uvl"), "tvl")
    text = t.text
    assert "root Drone {\n  group allOf {\n    Frame,\n    opt Camera,\n    opt Quad," in text
    assert "// the 'alternative' group of Drone (TVL has one group per feature):" in text
    assert "  ifIn: Quad || Hexa;\n  ifIn: !(Quad && Hexa);" in text
    assert "  ifIn: Wifi || Radio;" in text
    assert count(reparse(text, "tvl")) == 90


def test_tvl_specials_are_compiled_into_uvl_constraints():
    """Shared features, a group whose optional children weaken its bounds, attributes that
    restrict features, ifIn / ifOut constraints."""
    m = load(DATA / "convert" / "specials.tvl")
    conv = convert_model(m, "uvl")
    assert conv.exact
    text = conv.text
    assert any("shared feature" in n for n in conv.notes)
    assert "constraints" in text and "=>" in text
    mu = reparse(text, "uvl")
    assert count(mu) == count(m)
    # the products themselves agree, not just their number
    a, b = ModelAnalysis(m), ModelAnalysis(mu)
    assert sorted(map(_key, a.enumerate(limit=None))) == sorted(map(_key, b.enumerate(limit=None)))


def _key(product: dict) -> tuple:
    return tuple(sorted(k for k, v in product.items() if v))


def test_names_are_adapted_and_listed():
    m = load(UVL / "robot.uvl")
    t = convert_model(m, "tvl")
    assert "Sensor_3D" in t.text and any("Sensor 3D -> Sensor_3D" in n for n in t.notes)
    u = convert_model(reparse(t.text, "tvl"), "uvl")
    assert "\t\t\tSensor_3D\n" in u.text


def test_uvl_attributes_in_tvl():
    t = convert_model(load(UVL / "robot.uvl"), "tvl").text
    assert "  int weight is 3;" in t
    # no TVL type for strings: a data entry (the reference's syntax: no ';' after the last one)
    assert '  data {\n    "vendor" "\'ACME\'"\n  }' in t
    assert '"description" "\\"an iRobot Create. Discontinued.\\""' not in t


def test_unanalysed_uvl_constraints_are_kept_as_comments():
    conv = convert_model(load(UVL / "levels.uvl"), "tvl")
    assert "// UVL constraint not converted (it compares values (UVL's arithmetic / type level)): " \
           "Topping.price + Sauce.price < 3" in conv.text
    assert any("kept as comments" in n for n in conv.notes)


# ------------------------------------------------------------------ the command

def test_cli_convert_verify(tmp_path, capsys):
    out = tmp_path / "robot.tvl"
    assert main(["convert", str(UVL / "robot.uvl"), str(out), "--verify"]) == 0
    err = capsys.readouterr().err
    assert "products: 20 (uvl), 20 (tvl): same" in err
    assert out.read_text().startswith("// converted by tvl-lsp from robot.uvl\nroot Robot {")
    d = tmp_path / "robot.dimacs"
    assert main(["convert", str(out), str(d)]) == 0
    assert main(["count", str(d)]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1] == "20"


def test_cli_convert_refuses(tmp_path, capsys):
    bad = tmp_path / "bad.uvl"
    bad.write_text("features\n\tA\n\t\toptional\n\t\t\tB\nconstraints\n\tC\n")
    assert main(["convert", str(bad), str(tmp_path / "x.tvl")]) == 1
    assert "has errors: not converted" in capsys.readouterr().err
    assert not (tmp_path / "x.tvl").exists()
    assert main(["convert", str(bad), str(tmp_path / "x.tvl"), "--force"]) == 0
    assert main(["convert", str(UVL / "robot.uvl"), str(tmp_path / "x.txt")]) == 2
    assert main(["convert", str(UVL / "robot.uvl"), str(tmp_path / "y.uvl")]) == 2
    assert main(["convert", str(tmp_path / "missing.tvl"), str(tmp_path / "y.uvl")]) == 2
    capsys.readouterr()
    assert main(["convert", str(UVL / "anomalies.uvl"), "-", "--to", "dimacs"]) == 0
    assert capsys.readouterr().out.startswith("c 1 Car\nc 2 Engine\n")


# The TVL written for the UVL fixtures is pinned in tests/data/convert/golden/, and the reference
# parser's verdict on each golden file is recorded in reference_verdicts.json (TVLParser v20100804
# via ../shared/reference/tvl-reference, on a machine that has it; CI has no copy).  After a change
# to the writer, regenerate both with TVL_REFERENCE_DIR set:  .venv/bin/python tests/test_convert.py
GOLDEN = DATA / "convert" / "golden"
VERDICTS = json.loads((DATA / "convert" / "reference_verdicts.json").read_text())


@pytest.mark.parametrize("path", UVL_FIXTURES, ids=lambda p: p.name)
def test_converted_tvl_is_the_text_the_reference_accepted(path):
    text = convert_model(load(path), "tvl").text
    golden = GOLDEN / (path.stem + ".tvl")
    assert text == golden.read_text(), f"the TVL written for {path.name} changed: regenerate (see above)"
    assert VERDICTS[golden.name].startswith("Feature model valid")
    assert count(reparse(text, "tvl")) == count(load(path))


if __name__ == "__main__":  # pragma: no cover - regenerates the golden files and the verdicts
    import os
    import subprocess
    ref = ROOT.parent / "shared" / "reference" / "tvl-reference"
    GOLDEN.mkdir(parents=True, exist_ok=True)
    verdicts = {}
    for p in UVL_FIXTURES:
        g = GOLDEN / (p.stem + ".tvl")
        g.write_text(convert_model(load(p), "tvl").text)
        out = subprocess.run([str(ref), str(g)], capture_output=True, text=True, env=os.environ)
        verdicts[g.name] = (out.stdout or out.stderr).splitlines()[0]
        print(g.name, verdicts[g.name])
    (DATA / "convert" / "reference_verdicts.json").write_text(json.dumps(verdicts, indent=1, sort_keys=True) + "\n")
