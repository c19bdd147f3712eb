"""t-wise samples side by side: tvl-lsp, ddnnife and YASA (FeatJAR), each in a fresh process,
each sample verified (issue #30).

    .venv/bin/python bench/bench_sampling.py MODEL [MODEL ...] [--t 2] [--timeout 600]
        [--tools tvl-lsp,ddnnife,yasa] [--yasa-classpath CP] [--budget S] [--json OUT]

MODEL: a DIMACS CNF (every variable a feature, named by ``c <index> <name>`` lines, as the
feature-model benchmark's files are) or a TVL / UVL model (its CNF from tvl-lsp's encoding, the
features its first variables; the peers sample that CNF).  For each model and tool: the sample's
size, the wall and CPU seconds of the tool's process (``resource.getrusage`` of the children:
user + system, d4's compile included for ddnnife, the JVM for YASA), and the verdict of
``tvl_lsp.analysis.sampling.verify``: valid (every configuration a model of the CNF) and
complete (every valid interaction of ``t`` feature literals covered: exhaustively for pairs
whenever the uncovered pairs can each be asked, plus 3,000 interactions at random).  A tool
that gives no sample within ``--timeout`` seconds is killed and says so.

The peers:
- **ddnnife** (the Python package): d4 (py_d4) compiles the CNF, then
  ``Ddnnf.from_file(...).sample_t_wise(t)``; partial configurations count only the literals
  they set (the verifier checks a partial configuration extends to a product);
- **YASA** (FeatJAR's ``yasa`` command, Sat4j): needs a local build, given with
  ``--yasa-classpath`` or ``$YASA_CLASSPATH`` (docs/benchmarks/2026-11-27-sampling.md says how
  it was built here); left out when absent.  Its CSV marks a variable it leaves open with 0.

``--peer NAME MODEL T`` runs one peer alone and prints its sample as JSON (what the side-by-side
run starts in a fresh process; also the command to time a peer on its own).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
TVL = str(Path(sys.executable).with_name("tvl-lsp"))


# ------------------------------------------------------------------ the model as a CNF

def load_cnf(path: str):
    """(nvars, clauses, n features, names {var: name}, dimacs path for the peers, temp?)."""
    if path.endswith((".dimacs", ".cnf")):
        from tvl_lsp.analysis.dimacs import parse_dimacs
        nvars, clauses, names, _ = parse_dimacs(Path(path).read_text())
        return nvars, clauses, nvars, names, path, False
    from tvl_lsp.analysis.engine import ModelAnalysis
    a = ModelAnalysis.from_file(path)
    enc = a.encoding
    names = {v: a.name(f) for f, v in enc.var_of_feature.items()}
    clauses = enc.clauses()
    fd, tmp = tempfile.mkstemp(suffix=".dimacs")
    with os.fdopen(fd, "w") as fh:
        for v, nm in sorted(names.items()):
            fh.write(f"c {v} {nm}\n")
        fh.write(f"p cnf {enc.nvars} {len(clauses)}\n")
        for c in clauses:
            fh.write(" ".join(map(str, c)) + " 0\n")
    return enc.nvars, clauses, enc.n_features, names, tmp, True


# ------------------------------------------------------------------ the peers (run alone)

def peer_ddnnife(dimacs: str, t: int) -> list[list[int]]:
    import ddnnife
    from tvl_lsp.analysis.counting.d4 import compile_inprocess
    from tvl_lsp.analysis.dimacs import parse_dimacs
    nvars, clauses, _, _ = parse_dimacs(Path(dimacs).read_text())
    nnf, _count = compile_inprocess(nvars, clauses)
    with tempfile.NamedTemporaryFile("w", suffix=".nnf", delete=False) as fh:
        fh.write(nnf)
        path = fh.name
    try:
        d = ddnnife.Ddnnf.from_file(path, nvars)
        r = d.sample_t_wise(t)
    finally:
        os.unlink(path)
    if r.is_void():
        return []
    if r.is_empty():
        return [[]]
    s = r[0]
    return [list(c) for c in s.complete_configs] + [list(c) for c in s.partial_configs]


def run_yasa(classpath: str, dimacs: str, t: int, timeout: float, names_to_var: dict) -> tuple:
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "sample.csv")
        cmd = ["java", "-cp", classpath, "de.featjar.base.FeatJAR", "yasa", "--input", dimacs, "--t", str(t),
               "--output", out, "--non-parallel"]
        r = _timed(cmd, timeout)
        if r["error"] or not os.path.exists(out):
            r["error"] = r["error"] or "no output"
            return None, r
        with open(out, newline="") as fh:
            rows = list(csv.reader(fh, delimiter=";"))
        head = rows[0][1:]
        var = [names_to_var.get(h) for h in head]
        confs = []
        for row in rows[1:]:
            c = []
            for v, x in zip(var, row[1:]):
                if v is None or x == "0":
                    continue
                c.append(v if x == "+" else -v)
            confs.append(c)
        return confs, r


# ------------------------------------------------------------------ timing

def _timed(cmd: list[str], timeout: float) -> dict:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
        error = None if p.returncode in (0, 1) else f"exit {p.returncode}: {err.strip()[-300:]}"
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, 9)
        out, err = p.communicate()
        error = f"no sample in {timeout:g} s"
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall": wall, "cpu": cpu, "stdout": out, "stderr": err, "error": error, "rc": p.returncode}


def run_tool(tool: str, model: str, cnf, t: int, timeout: float, args) -> dict:
    nvars, clauses, n, names, dimacs, _ = cnf
    by_name = {nm: v for v, nm in names.items()}
    confs = None
    if tool == "tvl-lsp":
        cmd = [TVL, "sample", model, "--t", str(t), "--format", "json"]
        if args.budget:
            cmd += ["--budget", str(args.budget)]
        r = _timed(cmd, timeout)
        if not r["error"] and r["stdout"].strip():
            data = json.loads(r["stdout"])
            confs = [[by_name[k] if v else -by_name[k] for k, v in c.items() if k in by_name]
                     for c in data["configurations"]]
            if not data.get("complete", True):
                r["note"] = f"partial: coverage {data['coverage']:.4f}"
    elif tool == "ddnnife":
        r = _timed([sys.executable, __file__, "--peer", "ddnnife", dimacs, str(t)], timeout)
        if not r["error"]:
            confs = json.loads(r["stdout"])
    elif tool == "yasa":
        cp = args.yasa_classpath or os.environ.get("YASA_CLASSPATH")
        if not cp:
            return {"tool": tool, "error": "no --yasa-classpath"}
        confs, r = run_yasa(cp, dimacs, t, timeout, by_name)
    else:
        raise SystemExit(f"unknown tool {tool}")
    row = {"tool": tool, "wall": round(r["wall"], 2), "cpu": round(r["cpu"], 2), "error": r["error"],
           "note": r.get("note")}
    if confs is not None:
        from tvl_lsp.analysis.sampling.verify import verify
        v = verify(clauses, n, confs, t=t, seed=1)
        row.update(size=len(confs), valid=v.valid, complete=v.complete, exhaustive=v.exhaustive,
                   checked=v.checked, missing=len(v.missing), verify_seconds=round(v.seconds, 1),
                   partial_configurations=sum(1 for c in confs if len(c) < n))
    return row


def main(argv: list[str]) -> int:
    if argv[:1] == ["--peer"]:
        _, name, dimacs, t = argv
        if name != "ddnnife":
            raise SystemExit("only ddnnife runs as --peer")
        print(json.dumps(peer_ddnnife(dimacs, int(t))))
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("models", nargs="+")
    ap.add_argument("--t", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per tool and model (default 600)")
    ap.add_argument("--budget", type=float, default=None, help="tvl-lsp sample --budget")
    ap.add_argument("--tools", default="tvl-lsp,ddnnife,yasa")
    ap.add_argument("--yasa-classpath", default=None)
    ap.add_argument("--json", default=None, help="also write the rows to this file")
    args = ap.parse_args(argv)
    print(f"# {time.strftime('%Y-%m-%d %H:%M')}, load {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f}, "
          f"{os.cpu_count()} cores, t = {args.t}", flush=True)
    print("| model | tool | size | wall s | CPU s | valid | complete | checked | note |")
    print("|---|---|---|---|---|---|---|---|---|", flush=True)
    rows = []
    ok = True
    for model in args.models:
        cnf = load_cnf(model)
        try:
            model_rows = []
            for tool in args.tools.split(","):
                row = run_tool(tool, model, cnf, args.t, args.timeout, args)
                mp = Path(model)
                row["model"] = mp.name if mp.suffix in (".dimacs", ".cnf") else f"{mp.parent.parent.name}/{mp.name}"
                model_rows.append(row)
                size = row.get("size", "-")
                how = "exhaustive" if row.get("exhaustive") else "random sample"
                note = row.get("error") or row.get("note") or ""
                if row.get("partial_configurations"):
                    note += f" {row['partial_configurations']} partial configurations"
                print(f"| {row['model']} | {tool} | {size} | {row.get('wall', '-')} | {row.get('cpu', '-')} | "
                      f"{row.get('valid', '-')} | {row.get('complete', '-')} | "
                      f"{row.get('checked', '-')} ({how}) | {note.strip()} |", flush=True)
                if tool == "tvl-lsp" and not (row.get("valid") and row.get("complete")):
                    ok = False
            sizes = [r["size"] for r in model_rows if r["tool"] != "tvl-lsp" and r.get("size") and r.get("valid")
                     and r.get("complete")]
            mine = next((r for r in model_rows if r["tool"] == "tvl-lsp"), None)
            if mine and mine.get("size") and sizes:
                print(f"|  | tvl-lsp / smallest complete peer sample | {mine['size'] / min(sizes):.2f} |"
                      "  |  |  |  |  |  |", flush=True)
            rows += model_rows
        finally:
            if cnf[5]:
                os.unlink(cnf[4])
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
