"""Analysis engine vs flamapy 2.6, side by side in one run (issue 4).

    .venv/bin/python bench/bench_analysis.py [--models-dir DIR] [--flamapy-python PY] [--timeout 120] [--models a,b]

The models: ``DIR/dimacs/NAME.dimacs`` and ``DIR/uvl/NAME.uvl`` for each NAME of ``--models``;
``--models-dir`` defaults to ../shared/models (the team's shared folder of large models; the
DIMACS and UVL twins of the published benchmark models).  Our side runs on the DIMACS twins (imported as flat TVL models:
count, dead, core, all anomalies with explanations) and on the UVL twins (imported here into a
TVL model with their hierarchy, for false-optional features, which only mean something with a
hierarchy).  pyganak alone on the raw CNF gives the reference count and time.  flamapy runs each
operation on the UVL twin in a fresh child process (its default backends: BDD for the count,
SAT for the others) under a per-operation timeout.

flamapy 2.6 pins python-sat 0.1.x, which conflicts with the project's python-sat 1.x, so it
lives in its own virtualenv (``python -m venv /tmp/flamapy-venv && /tmp/flamapy-venv/bin/pip
install flamapy==2.6.0``); pass its interpreter with ``--flamapy-python``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
DEFAULT_MODELS_DIR = ROOT.parent / "shared" / "models"
SHARED = DEFAULT_MODELS_DIR  # set from --models-dir in main()

from tvl_lsp.analysis.counting.projected import CACHE, count_cnf  # noqa: E402
from tvl_lsp.analysis.dimacs import dimacs_to_model, parse_dimacs  # noqa: E402
from tvl_lsp.analysis.engine import ModelAnalysis  # noqa: E402
from tvl_lsp.base.text import ZERO_SPAN  # noqa: E402
from tvl_lsp.tvl import model as M  # noqa: E402

MODELS = ["busybox-1.18.0", "ecos-i386pc", "embtoolkit", "uclinux-distribution", "freebsd-8.0.0", "automotive01"]

# ----------------------------------------------------------------------------- UVL twin

_GROUP = re.compile(r"^(optional|mandatory|alternative|or|\[(\d+)\s*\.\.\s*(\d+|\*)\]|\[(\d+)\])$")
_TOKEN = re.compile(r'\s*("(?:[^"\\]|\\.)*"|<=>|=>|[!&|()]|[^\s!&|()"]+)')


def _name(tok: str) -> str:
    return tok[1:-1] if tok.startswith('"') else tok


def uvl_to_model(text: str, path: str) -> tuple[M.Model, set, set]:
    """The UVL feature tree and constraints as a TVL model.  A feature with several group
    blocks keeps its mandatory/optional children and gets a synthetic mandatory child per
    alternative / or / [n..m] block (returned in the second item, to leave out of results)."""
    lines = text.splitlines()
    feats: list[M.Feature] = []
    by_name: dict[str, M.Feature] = {}
    blocks: dict[M.Feature, list] = {}
    stack: list[tuple[int, str, object]] = []  # (depth, "f"/"g", feature or block)
    i = 0
    while i < len(lines) and lines[i].strip() != "features":
        i += 1
    i += 1
    while i < len(lines):
        raw = lines[i]
        i += 1
        s = raw.strip()
        if not s:
            continue
        if not raw[0].isspace():
            if s == "constraints":
                break
            continue
        depth = len(raw) - len(raw.lstrip("\t "))
        while stack and stack[-1][0] >= depth:
            stack.pop()
        m = _GROUP.match(s)
        if m:
            owner = stack[-1][2]
            kw = m.group(1)
            if kw == "optional" or kw == "mandatory":
                blk = ["plain", 0, None, []]
            elif kw == "alternative":
                blk = ["alt", 1, 1, []]
            elif kw == "or":
                blk = ["or", 1, None, []]
            elif m.group(4):
                blk = ["card", int(m.group(4)), int(m.group(4)), []]
            else:
                blk = ["card", int(m.group(2)), None if m.group(3) == "*" else int(m.group(3)), []]
            blk.append(kw == "optional")
            blocks.setdefault(owner, []).append(blk)
            stack.append((depth, "g", blk))
            continue
        tok = _TOKEN.match(s).group(1)
        name = _name(tok)
        parent = None
        if stack and stack[-1][1] == "g":
            blk = stack[-1][2]
            parent = stack[-2][2]
        f = M.Feature(name, ZERO_SPAN, ZERO_SPAN, path, parent=parent, is_root=parent is None)
        feats.append(f)
        by_name[name] = f
        if parent is not None:
            blk[3].append(f)
        stack.append((depth, "f", f))
    synthetic = set()
    mandatory = {c for bl in blocks.values() for b in bl if b[0] == "plain" and not b[4] for c in b[3]}
    extra: list[M.Feature] = []
    for f, bl in blocks.items():
        plain = [b for b in bl if b[0] == "plain"]
        others = [b for b in bl if b[0] != "plain"]
        kids: list[M.GroupChild] = []
        for b in plain:
            kids += [M.GroupChild(c, b[4], False, ZERO_SPAN, path) for c in b[3]]
        if not plain and len(others) == 1:
            b = others[0]
            g = M.Group("card", f, ZERO_SPAN, ZERO_SPAN, path, lo=b[1], hi=b[2])
            g.children = [M.GroupChild(c, False, False, ZERO_SPAN, path) for c in b[3]]
            f.group = g
            continue
        for k, b in enumerate(others):
            s_ = M.Feature(f"__{f.name}_g{k}", ZERO_SPAN, ZERO_SPAN, path, parent=f)
            synthetic.add(s_)
            extra.append(s_)
            g = M.Group("card", s_, ZERO_SPAN, ZERO_SPAN, path, lo=b[1], hi=b[2])
            g.children = [M.GroupChild(c, False, False, ZERO_SPAN, path) for c in b[3]]
            for c in b[3]:
                c.parent = s_
            s_.group = g
            kids.append(M.GroupChild(s_, False, False, ZERO_SPAN, path))
        n = len(kids)
        f.group = M.Group("allOf", f, ZERO_SPAN, ZERO_SPAN, path, children=kids, lo=n, hi=n)
    root = feats[0]
    model = M.Model(path, root=root, features=feats + extra)
    # constraints
    for raw in lines[i:]:
        s = raw.strip()
        if not s or not raw[0].isspace():
            continue
        toks = [t for t in _TOKEN.findall(s)]
        e = _Parser(toks, by_name).parse()
        root.constraints.append(M.Constraint(e, "plain", root, ZERO_SPAN, path))
    return model, synthetic, mandatory


class _Parser:
    """UVL boolean constraints: ! > & > | > => > <=>."""

    def __init__(self, toks, names):
        self.t = toks
        self.i = 0
        self.names = names

    def peek(self):
        return self.t[self.i] if self.i < len(self.t) else None

    def parse(self):
        return self.bi(0)

    LEVELS = [("<=>", "<->"), ("=>", "->"), ("|", "||"), ("&", "&&")]

    def bi(self, level):
        if level == len(self.LEVELS):
            return self.un()
        tok, op = self.LEVELS[level]
        left = self.bi(level + 1)
        while self.peek() == tok:
            self.i += 1
            right = self.bi(level + 1)
            left = M.Binary(op, left, right)
        return left

    def un(self):
        t = self.peek()
        self.i += 1
        if t == "!":
            return M.Unary("!", self.un())
        if t == "(":
            e = self.bi(0)
            self.i += 1  # )
            return e
        f = self.names.get(_name(t))
        if f is None:
            raise ValueError(f"unknown feature {t}")
        return M.Name([f.name], target=f)


# ----------------------------------------------------------------------------- runs

FLAMA_WORKER = r"""
import sys, time, json, logging
logging.disable(logging.CRITICAL)
t = time.time()
from flamapy.interfaces.python.flamapy_feature_model import FLAMAFeatureModel
m = FLAMAFeatureModel(sys.argv[1]); t1 = time.time()
r = getattr(m, sys.argv[2])(); t2 = time.time()
print(json.dumps({"load": t1 - t, "op": t2 - t1,
                  "result": r if isinstance(r, int) else (len(r) if r is not None else None)}))
"""


OURS_WORKER = r"""
import sys, time, json
sys.path.insert(0, sys.argv[1])
from bench_analysis import uvl_to_model
from tvl_lsp.analysis.engine import ModelAnalysis
path, op = sys.argv[2], sys.argv[3]
text = open(path).read()
if op == "fo":
    m, syn, _ = uvl_to_model(text, path)
    r = len([f for f, p in ModelAnalysis(m).analyzer.false_optional() if f not in syn])
else:
    a = ModelAnalysis.from_dimacs(text, path)
    r = len(a.dead_features() if op == "dead" else [f for f in a.analyzer.core() if f is not a.model.root])
print(json.dumps({"result": r}))
"""


def ours_fresh(path: Path, op: str) -> dict:
    """One operation end to end in a fresh process, like flamapy's runs: start, import, read
    and encode the model, answer."""
    t = time.time()
    p = subprocess.run([sys.executable, "-c", OURS_WORKER, str(Path(__file__).resolve().parent), str(path), op],
                       capture_output=True, text=True, timeout=600)
    d = json.loads(p.stdout.strip().splitlines()[-1])
    d["wall"] = time.time() - t
    return d


def flamapy(py: str, uvl: Path, op: str, timeout: float) -> dict:
    t = time.time()
    try:
        p = subprocess.run([py, "-c", FLAMA_WORKER, str(uvl), op], capture_output=True, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"timeout": True, "wall": time.time() - t}
    try:
        d = json.loads(p.stdout.strip().splitlines()[-1])
    except Exception:
        return {"error": (p.stderr or p.stdout).strip()[-200:], "wall": time.time() - t}
    d["wall"] = time.time() - t
    return d


def timed(fn):
    t = time.perf_counter()
    r = fn()
    return r, time.perf_counter() - t


def ours(name: str, count_timeout: float) -> dict:
    out: dict = {}
    dpath = SHARED / "dimacs" / f"{name}.dimacs"
    text = dpath.read_text()
    # raw CNF, pyganak alone (in a child process like our big-model path, for a fair ratio)
    nv, clauses, names, _ = parse_dimacs(text)
    (a, _), out["t_load"] = timed(lambda: (lambda an: (an, an.encoding))(ModelAnalysis(dimacs_to_model(text, str(dpath)))))
    # best of two, interleaved, with the count cache emptied: the machine is shared
    raw_t, our_t = [], []
    for _ in range(2):
        CACHE.data.clear()
        out["raw_count"], t = timed(lambda: count_cnf(nv, clauses, None, inprocess=False))
        raw_t.append(t)
        CACHE.data.clear()
        out["count"], t = timed(lambda: a.count(timeout=count_timeout))
        our_t.append(t)
    out["t_raw"], out["t_count"] = min(raw_t), min(our_t)
    root = a.model.root
    (core, dead), out["t_core_dead"] = timed(lambda: (a.analyzer.core(), a.analyzer.dead()))
    out["core"] = len([f for f in core if f is not root])
    out["dead"] = len(dead)
    b = ModelAnalysis(a.model)
    diags, out["t_anomalies"] = timed(lambda: b.anomalies(time_budget=None))
    out["n_anomalies"] = len(diags)
    out["all_explained"] = all(d.related for d in diags if d.code in ("dead-feature", "false-optional"))
    # UVL twin with its hierarchy: false-optional features
    upath = SHARED / "uvl" / f"{name}.uvl"
    (um, syn, mand), out["t_uvl_load"] = timed(lambda: uvl_to_model(upath.read_text(), str(upath)))
    u = ModelAnalysis(um)
    u.encoding
    fo, out["t_fo"] = timed(lambda: u.analyzer.false_optional())
    out["fo"] = len({f for f, p in fo if f not in syn})
    # flamapy's definition: every non-mandatory, non-root feature f with parent p such that
    # p && !f is unsatisfiable (alternative / or members included, dead parents not excluded)
    def flama_def():
        s, v = u.analyzer.plain, u.encoding.var_of_feature
        n = 0
        for f in um.features:
            if f in syn or f.parent is None or f in mand:
                continue
            p = f.parent.parent if f.parent in syn else f.parent
            n += not s.solve(assumptions=[v[p], -v[f]])
        return n
    out["fo_fdef"], out["t_fo_fdef"] = timed(flama_def)
    out["uvl_dead"] = len([f for f in u.analyzer.dead() if f not in syn])
    out["uvl_core"] = len([f for f in u.analyzer.core() if f not in syn])
    ud, out["t_uvl_anomalies"] = timed(lambda: ModelAnalysis(um).anomalies(time_budget=None))
    out["uvl_features"] = len([f for f in um.features if f not in syn])
    out["fresh_dead"] = ours_fresh(dpath, "dead")
    out["fresh_core"] = ours_fresh(dpath, "core")
    out["fresh_fo"] = ours_fresh(upath, "fo")
    return out


def fmt_t(x):
    if x is None:
        return "—"
    return f"{x:.3f}" if x < 0.1 else (f"{x:.2f}" if x < 10 else f"{x:.1f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--models-dir", default=str(DEFAULT_MODELS_DIR), metavar="DIR",
                    help="folder with dimacs/NAME.dimacs and uvl/NAME.uvl (default: %(default)s)")
    ap.add_argument("--flamapy-python", default=os.environ.get("FLAMAPY_PYTHON", "/tmp/flamapy-venv/bin/python"))
    ap.add_argument("--timeout", type=float, default=60.0, help="per flamapy operation (s)")
    ap.add_argument("--count-timeout", type=float, default=300.0)
    ap.add_argument("--models", default=",".join(MODELS))
    ap.add_argument("--json", default=None, help="also write the raw results here")
    ap.add_argument("--from-json", default=None, help="only print the table of an earlier run")
    args = ap.parse_args(argv)
    global SHARED
    SHARED = Path(args.models_dir)
    if not args.from_json:
        missing = [str(SHARED / sub / f"{n}.{sub}") for n in args.models.split(",") for sub in ("dimacs", "uvl")
                   if not (SHARED / sub / f"{n}.{sub}").is_file()]
        if missing:
            print(f"bench_analysis.py: {len(missing)} model file(s) missing, e.g. {missing[0]}: the models are in the "
                  f"team's shared folder (../shared/models); pass --models-dir DIR with dimacs/ and uvl/ twins, "
                  f"or --models NAME,... for those you have", file=sys.stderr)
            return 2
    have_flamapy = Path(args.flamapy_python).exists()
    results = {}
    start = time.time()
    if args.from_json:
        results = json.loads(Path(args.from_json).read_text())
    for name in ([] if args.from_json else args.models.split(",")):
        r = ours(name, args.count_timeout)
        if have_flamapy:
            upath = SHARED / "uvl" / f"{name}.uvl"
            for op in ("dead_features", "core_features", "false_optional_features", "configurations_number"):
                prev = [v for k, v in r.items() if k.startswith("fl_") and "Parsing failed" in v.get("error", "")]
                # flamapy cannot read the file: every operation would fail the same way
                r["fl_" + op] = dict(prev[0]) if prev else flamapy(args.flamapy_python, upath, op, args.timeout)
        results[name] = r
        print(name, json.dumps(r, default=str), file=sys.stderr, flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(results, default=str, indent=1))

    def fl(r, op, what="op"):
        d = r.get("fl_" + op)
        if d is None:
            return "n/a", None
        if d.get("timeout"):
            return f"timeout ({args.timeout:g} s)", None
        if "error" in d:
            return ("parse error" if "Parsing failed" in d["error"] else "error"), None
        return d["result"], d[what]

    T = args.timeout
    print("Counts (ours: the DIMACS twin through tvl-lsp; pyganak alone: the raw CNF; both in a child "
          "process, best of two; flamapy: the UVL twin, default BDD backend)\n")
    print("| model | features | digits | ours = pyganak alone | ours s | pyganak alone s | ratio | flamapy |")
    print("|---|---|---|---|---|---|---|---|")
    for name, r in results.items():
        r["count"], r["raw_count"] = int(r["count"]), int(r["raw_count"])
        fc, fct = fl(r, "configurations_number")
        fcs = fc if fct is None else (f"{'same count' if fc == r['count'] else 'count ' + str(fc)} in {fmt_t(fct)} s")
        print(f"| {name} | {r['uvl_features']} | {len(str(r['count']))} | "
              f"{'yes' if r['count'] == r['raw_count'] else 'NO'} | {fmt_t(r['t_count'])} | {fmt_t(r['t_raw'])} "
              f"| {r['t_count'] / r['t_raw']:.2f} | {fcs} |")
    print("\nAnomalies: numbers found (ours / flamapy) and times.  End to end = a fresh process that "
          "imports, reads the model, and answers one operation (flamapy: load + operation); "
          "operation only = after loading (ours: backbone for dead + core together, false-optional "
          "includes the backbone).\n")
    print("| model | dead | core | false-optional: ours / ours with flamapy's definition / flamapy "
          "| end to end s, ours: dead / core / FO | end to end s, flamapy: dead / core / FO | speed-up end to end "
          "| operation s, ours: dead+core / FO | operation s, flamapy: dead / core / FO "
          "| ours: all anomalies with explanations s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, r in results.items():
        fd, fdt = fl(r, "dead_features")
        fcore, fcoret = fl(r, "core_features")
        ffo, ffot = fl(r, "false_optional_features")
        walls = []
        sp = []
        for op, ours_k in (("dead_features", "fresh_dead"), ("core_features", "fresh_core"),
                           ("false_optional_features", "fresh_fo")):
            d = r.get("fl_" + op) or {}
            if "load" in d:
                walls.append(fmt_t(d["wall"]))
                sp.append(f"{d['wall'] / r[ours_k]['wall']:.0f}x")
            else:
                walls.append(str(fl(r, op)[0]).replace(f"({T:g} s)", ""))
                sp.append("—")
        expl = (f"{fmt_t(r['t_anomalies'])} ({r['n_anomalies']} diagnostics"
                f"{', each explained' if r['all_explained'] else ''})")
        print(f"| {name} | {r['dead']} / {fd} | {r['core']} / {fcore} | {r['fo']} / {r['fo_fdef']} / {ffo} "
              f"| {fmt_t(r['fresh_dead']['wall'])} / {fmt_t(r['fresh_core']['wall'])} / {fmt_t(r['fresh_fo']['wall'])} "
              f"| {' / '.join(walls)} | {' / '.join(sp)} "
              f"| {fmt_t(r['t_core_dead'])} / {fmt_t(r['t_fo'])} | {fmt_t(fdt)} / {fmt_t(fcoret)} / {fmt_t(ffot)} "
              f"| {expl} |")
    print(f"\nwhole run: {time.time() - start:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
