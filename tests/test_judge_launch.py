"""Judge's check of issues 3 and 5 on unseen pairs (tests/data/judge/ws).

Ten generic launch files with their models in a small catkin workspace (two packages), paired
by same stem, by a HAROS project file and by the marker comment: exact codes, ranges and
witnesses of ``--check``; agreement with Debian's real roslaunch over every product; the
JSON / SARIF / github / text outputs and exit codes of ``tvl-lsp --check``.
"""

from __future__ import annotations

import itertools
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.project.check import check_paths, free_top_args
from tvl_lsp.tvl import parse_model

HERE = Path(__file__).resolve().parent
WS = HERE / "data" / "judge" / "ws"
LAUNCH = WS / "src" / "jbot" / "launch"
MODELS = WS / "src" / "jbot" / "models"
SYS_PY = "/usr/bin/python3"

PAIRS = {  # launch stem -> model (same stem, HAROS project file, marker)
    "missing": LAUNCH / "missing.tvl",
    "unmatched": LAUNCH / "unmatched.tvl",
    "undef": MODELS / "undef.tvl",          # haros_judge.yaml
    "dead": MODELS / "drive.tvl",           # marker
    "dupnode": LAUNCH / "dupnode.tvl",
    "duparg": LAUNCH / "duparg.tvl",
    "evalc": LAUNCH / "evalc.tvl",
    "nested": LAUNCH / "nested.tvl",
    "good": MODELS / "good.tvl",            # marker
    "twice": LAUNCH / "twice.tvl",
    "inclarg": LAUNCH / "inclarg.tvl",
}


@pytest.fixture(scope="module")
def diags():
    return check_paths([str(WS)], jobs=1)


def _rel(p: str) -> str:
    return str(Path(p).relative_to(WS))


def _features(model_path: Path) -> list[str]:
    res = parse_model(model_path.read_text(), str(model_path))
    enc = ModelAnalysis(res.model).encoding
    return [enc.name_of(f) for f in enc.features]


def _products(model_path: Path) -> list[dict]:
    res = parse_model(model_path.read_text(), str(model_path))
    return list(ModelAnalysis(res.model).enumerate(limit=None))


def _is_product(model_path: Path, w: dict) -> bool:
    return any(p == w for p in _products(model_path))


def _key(d):
    return (_rel(d.path), d.code, d.span.start.line, d.span.start.col, d.span.end.line, d.span.end.col)


EXPECTED = {  # (file, code, start line, start col, end line, end col), 0-based
    ("src/jbot/launch/missing.launch", "missing-arg", 0, 0, 0, 8),             # <launch>
    ("src/jbot/launch/missing.launch", "constant-condition", 3, 52, 3, 63),    # $(arg Base)
    ("src/jbot/launch/unmatched.launch", "missing-arg", 0, 0, 0, 8),
    ("src/jbot/launch/unmatched.launch", "unmatched-arg", 3, 13, 3, 18),       # Camra
    ("src/jbot/launch/undef.launch", "undefined-arg", 7, 32, 7, 43),           # $(arg rate)
    ("src/jbot/launch/dead.launch", "dead-element", 9, 4, 9, 70),              # <node ... hybrid>
    ("src/jbot/launch/dead.launch", "dead-element", 11, 2, 11, 88),            # <node ... odd>
    ("src/jbot/launch/dupnode.launch", "duplicate-node", 9, 42, 9, 45),        # cam
    ("src/jbot/launch/dupnode.launch", "duplicate-node", 11, 2, 11, 84),       # <include ... Stereo>
    ("src/jbot/launch/duparg.launch", "duplicate-arg", 6, 15, 6, 19),          # port
    ("src/jbot/launch/evalc.launch", "dead-element", 7, 2, 7, 80),             # <node ... lonely>
    ("src/jbot/launch/evalc.launch", "duplicate-node", 8, 38, 8, 45),          # planner
    ("src/jbot/launch/nested.launch", "duplicate-node", 11, 40, 11, 44),       # ctrl
    # the <include> that loads driver.launch in the witness product, not the first one
    ("src/jbot/launch/twice.launch", "duplicate-node", 11, 2, 11, 71),
    # an included file's required arg that the <include> sets only under a condition
    ("src/jbot/launch/inclarg.launch", "unset-arg", 4, 2, 4, 69),
    ("src/jsens/launch/arm.launch", "unset-arg", 3, 13, 3, 24),
    ("src/jsens/launch/driver.launch", "unset-arg", 3, 42, 3, 53),
}


def test_codes_and_exact_ranges(diags):
    assert {_key(d) for d in diags} == EXPECTED


def test_correct_generic_launch_file_is_clean(diags):
    assert [d for d in diags if d.path.endswith("good.launch")] == []


def test_pairing_rules(diags):
    from tvl_lsp.project.workspace import load_workspace
    ws = load_workspace([str(WS)])
    rules = {}
    for stem, model in PAIRS.items():
        ps, problems = ws.pair(str(LAUNCH / f"{stem}.launch"))
        assert not problems and len(ps) == 1 and ps[0].model == str(model), stem
        rules[stem] = ps[0].rule
    assert rules.pop("undef") == "haros-project"
    assert rules.pop("dead") == rules.pop("good") == "marker"
    assert set(rules.values()) == {"same-stem"}
    # every model feature has an arg in the paired files: no missing-arg besides the two planted
    assert sorted(_rel(d.path) for d in diags if d.code == "missing-arg") == [
        "src/jbot/launch/missing.launch", "src/jbot/launch/unmatched.launch"]
    msgs = {_rel(d.path): d.message for d in diags if d.code in ("dead-element", "undefined-arg")}
    assert "drive.tvl" in msgs["src/jbot/launch/dead.launch"]     # marker
    assert "Lidar && !Fast" in msgs["src/jbot/launch/undef.launch"]  # HAROS project file


def test_messages_and_suggestions(diags):
    um = [d for d in diags if d.code == "unmatched-arg"][0]
    assert "`Camra`" in um.message and "did you mean `Camera`" in um.message
    mi = {_rel(d.path): d.message for d in diags if d.code == "missing-arg"}
    assert "`Camera`" in mi["src/jbot/launch/missing.launch"]


def test_unset_arg_is_a_warning_only_where_the_command_line_can_set_it(diags):
    """issue 5 / docs: unset-arg is a warning in --check (the command line may set the arg);
    an arg of an included file is not set by the command line: roslaunch fails, an error."""
    us = {_rel(d.path): d for d in diags if d.code == "unset-arg"}
    assert us["src/jsens/launch/arm.launch"].severity == 2
    assert us["src/jsens/launch/driver.launch"].severity == 2
    d = us["src/jbot/launch/inclarg.launch"]
    assert d.severity == 1 and d.witness == {"Bot": True, "Cam": True, "Named": False}


def test_witnesses_are_full_products(diags):
    stem_of = {str(LAUNCH / f"{s}.launch"): m for s, m in PAIRS.items()}
    ws = [d for d in diags if d.code in ("duplicate-node", "undefined-arg", "duplicate-arg")
          or (d.code == "unset-arg" and d.witness)]
    assert len(ws) == 8
    for d in ws:
        model = stem_of[d.path]
        assert d.witness is not None and set(d.witness) == set(_features(model)), d.message
        assert all(isinstance(v, bool) for v in d.witness.values())
        assert _is_product(model, d.witness), (d.message, d.witness)
    by = {(_rel(d.path), d.span.start.line): {k for k, v in d.witness.items() if v} for d in ws}
    assert by[("src/jbot/launch/undef.launch", 7)] == {"Bot", "Lidar"}
    assert by[("src/jbot/launch/duparg.launch", 6)] == {"Bot", "Sim", "Real"}
    assert by[("src/jbot/launch/dupnode.launch", 9)] == {"Bot", "Front", "Rear"}
    assert by[("src/jbot/launch/dupnode.launch", 11)] == {"Bot", "Front", "Stereo"}
    assert by[("src/jbot/launch/evalc.launch", 8)] == {"Bot", "Nav", "Map"}
    assert by[("src/jbot/launch/nested.launch", 11)] == {"Bot", "Left"}
    assert by[("src/jbot/launch/twice.launch", 11)] == {"Bot"}
    assert by[("src/jbot/launch/inclarg.launch", 4)] == {"Bot", "Cam"}


# ------------------------------------------------------------------ roslaunch differential

DRIVER = r'''
import io, json, os, sys
jobs = json.load(sys.stdin)
os.environ["ROS_PACKAGE_PATH"] = jobs["package_path"]
import rospkg
import roslaunch.substitution_args as sa
from roslaunch.config import ROSLaunchConfig
from roslaunch.xmlloader import XmlLoader
out = []
for job in jobs["runs"]:
    sa._rospack = rospkg.RosPack()
    argv = ["roslaunch", job["file"]] + ["%s:=%s" % kv for kv in sorted(job["args"].items())]
    cfg = ROSLaunchConfig()
    so, se = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = io.StringIO(), io.StringIO()
    try:
        loader = XmlLoader()
        loader.ignore_unset_args = False
        loader.load(job["file"], cfg, argv=argv, verbose=False)
        res = {"ok": True, "nodes": sorted(n.namespace + n.name for n in cfg.nodes)}
    except BaseException as e:
        res = {"ok": False, "error": type(e).__name__, "message": str(e)[:400]}
    finally:
        sys.stdout, sys.stderr = so, se
    out.append(res)
print(json.dumps(out))
'''


def _have_roslaunch() -> bool:
    if not os.path.exists(SYS_PY):
        return False
    return subprocess.run([SYS_PY, "-c", "import roslaunch.xmlloader, rospkg"], capture_output=True).returncode == 0


needs_roslaunch = pytest.mark.skipif(not _have_roslaunch(), reason="no roslaunch (apt-get install python3-roslaunch)")


def _roslaunch(runs):
    payload = {"package_path": str(WS / "src"), "runs": runs}
    r = subprocess.run([SYS_PY, "-c", DRIVER], input=json.dumps(payload), capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout)


def _classify(message: str):
    m = re.search(r"multiple nodes named \[([^\]]+)\]", message)
    if m:
        return "duplicate-node", m.group(1)
    m = re.search(r"arg '([^']+)' has already been declared", message)
    if m:
        return "duplicate-arg", m.group(1)
    m = re.search(r"requires the '([^']+)' arg to be set|arg '([^']+)' is not defined", message)
    if m:
        return "undefined-arg", m.group(1) or m.group(2)
    return None, None


def _name_of(d) -> str:
    if d.code == "duplicate-node":
        return re.search(r"named \[([^\]]+)\]", d.message).group(1)
    return re.search(r"'([^']+)'", d.message.split("]", 1)[-1] if d.message.startswith("[") else d.message).group(1)


def _s(v: bool) -> str:
    return "true" if v else "false"


@needs_roslaunch
def test_every_witness_makes_roslaunch_raise_that_error(diags):
    ws = [d for d in diags if d.code in ("duplicate-node", "undefined-arg", "duplicate-arg")
          or (d.code == "unset-arg" and d.witness)]
    runs = []
    for d in ws:
        args = {k: _s(v) for k, v in d.witness.items()}
        for n in free_top_args(Path(d.path).read_text(), d.path):
            args.setdefault(n, "false")
        runs.append({"file": d.path, "args": args})
    for d, res in zip(ws, _roslaunch(runs)):
        assert not res["ok"], (d.message, d.witness)
        code = "undefined-arg" if d.code == "unset-arg" else d.code
        assert _classify(res["message"]) == (code, _name_of(d)), (d.message, res["message"])


def _cases():
    for stem, model in PAIRS.items():
        lf = LAUNCH / f"{stem}.launch"
        feats = set(_features(model))
        free = [n for n in free_top_args(lf.read_text(), str(lf)) if n not in feats]
        for p in _products(model):
            for vals in itertools.product([False, True], repeat=len(free)):
                yield stem, lf, {**{k: _s(v) for k, v in p.items()}, **{n: _s(v) for n, v in zip(free, vals)}}


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
@needs_roslaunch
def test_all_products_agree_with_roslaunch(diags):
    cases = list(_cases())
    assert len(cases) > 40
    results = _roslaunch([{"file": str(lf), "args": a} for _, lf, a in cases])
    raised = 0
    for (stem, lf, args), res in zip(cases, results):
        # tvl-lsp launch FILE a:=b ... --json
        r = subprocess.run([sys.executable, "-m", "tvl_lsp", "launch", str(lf), *[f"{k}:={v}" for k, v in
                            sorted(args.items())], "--json", "--workspace", str(WS)],
                           capture_output=True, text=True, timeout=60)
        ours = json.loads(r.stdout)
        if res["ok"]:
            assert not ours.get("error"), (stem, args, ours.get("error"))
            assert sorted(n["name"] for n in ours["nodes"]) == res["nodes"], (stem, args)
            continue
        kind, name = _classify(res["message"])
        assert ours.get("error"), (stem, args, res["message"])
        if kind is None:
            continue
        raised += 1
        # roslaunch's error under a product is reported by --check on this file
        here = [d for d in diags if d.path == str(lf)
                and (d.code == kind or (kind == "undefined-arg" and d.code == "unset-arg"))]
        if kind == "undefined-arg" and not here:
            here = [d for d in diags if d.path == str(lf) and d.code == "unmatched-arg"]
            assert any(f"`{name}`" in d.message for d in here), (stem, args, res["message"])
            continue
        assert any(_name_of(d) == name for d in here), (stem, args, res["message"])
    assert raised >= 8


# ------------------------------------------------------------------ --check outputs

def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "tvl_lsp", "--check", *args], capture_output=True, text=True,
                          timeout=120, cwd=cwd)


def test_json_positions_are_lsp_0_based_and_text_1_based():
    j = _cli(str(WS), "--format", "json")
    assert j.returncode == 1
    items = json.loads(j.stdout)
    t = _cli(str(WS), "--format", "text")
    lines = [ln for ln in t.stdout.splitlines() if re.match(r".+:\d+:\d+: \w+\[", ln)]
    assert len(items) == len(lines) == len(EXPECTED)
    for it, ln in zip(items, lines):
        assert set(it) >= {"path", "range", "severity", "code", "message", "related", "witness"}
        p, line, col = re.match(r"(.+?):(\d+):(\d+):", ln).groups()
        assert (int(line), int(col)) == (it["range"]["start"]["line"] + 1, it["range"]["start"]["character"] + 1)
        assert f"{it['severity']}[{it['code']}]" in ln
        if it["code"] in ("duplicate-node", "undefined-arg", "duplicate-arg"):
            assert it["witness"] and all(isinstance(v, bool) for v in it["witness"].values())
    assert items == sorted(items, key=lambda i: (i["path"], i["range"]["start"]["line"],
                                                 i["range"]["start"]["character"]))


def test_sarif_is_valid_and_github_annotations(tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    out = tmp_path / "r.sarif"
    s = _cli(str(WS), "--format", "sarif", "--output", str(out))
    assert s.returncode == 1
    doc = json.loads(out.read_text())
    schema = json.loads((HERE / "data" / "sarif" / "sarif-schema-2.1.0.json").read_text())
    jsonschema.validate(doc, schema)
    results = doc["runs"][0]["results"]
    assert len(results) == len(EXPECTED)
    for r in results:
        reg = r["locations"][0]["physicalLocation"]["region"]
        assert reg["startLine"] >= 1 and reg["startColumn"] >= 1
    g = _cli(str(WS), "--format", "github")
    anns = [ln for ln in g.stdout.splitlines() if ln.startswith("::")]
    assert len(anns) == len(EXPECTED)
    assert all(re.match(r"::(error|warning|notice) file=[^,]+,line=\d+,col=\d+,endLine=\d+,endColumn=\d+,"
                        r"title=[^:]+::", a) for a in anns), anns[:3]


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
def test_exit_codes_select_ignore_strict():
    good = str(LAUNCH / "good.launch")
    assert _cli(good).returncode == 0
    assert _cli(good, "--strict").returncode == 0
    warn_only = str(LAUNCH / "unmatched.launch")
    assert _cli(warn_only).returncode == 0
    assert _cli(warn_only, "--strict").returncode == 1
    assert _cli(str(WS)).returncode == 1
    assert _cli(str(WS), "--ignore", "duplicate-node,undefined-arg,duplicate-arg").returncode == 1
    assert _cli(str(WS), "--ignore", "duplicate-node,undefined-arg,duplicate-arg,unset-arg").returncode == 0
    sel = _cli(str(WS), "--select", "duplicate-arg", "--format", "json")
    assert sel.returncode == 1 and {i["code"] for i in json.loads(sel.stdout)} == {"duplicate-arg"}
    assert _cli(str(WS), "--format", "nope").returncode == 2


def test_if_and_unless_element_is_not_also_reported_dead(tmp_path):
    """``if="1" unless="$(arg A)"``: roslaunch fails on the tag (if-and-unless); the element is
    not 'never loaded because if="1" is false' as well."""
    lf = tmp_path / "both.launch"
    lf.write_text('<launch>\n  <arg name="A"/>\n'
                  '  <node pkg="x" type="y" name="z" if="1" unless="$(arg A)"/>\n</launch>\n')
    ds = check_paths([str(lf)], jobs=1)
    assert [d.code for d in ds] == ["if-and-unless"]
    assert (ds[0].span.start.line, ds[0].span.start.col) == (2, 3)
