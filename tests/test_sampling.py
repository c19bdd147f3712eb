"""t-wise sampling (tvl_lsp.analysis.sampling, issue #30): every sample is checked against the
products enumerated by brute force (valid: each configuration is a product; complete: every
interaction some product has is in some configuration), on our own models and generated ones;
determinism per seed and across jobs; the budget's partial result; the verifier (it must catch a
bad sample); the output formats and ``generate --mode sample``."""

from __future__ import annotations

import ast
import itertools
import json
import random
import shutil
from pathlib import Path

import pytest

from model_gen import generated_model
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.sampling import sample
from tvl_lsp.analysis.sampling.verify import verify
from tvl_lsp.cli.commands import generate as generate_cmd
from tvl_lsp.cli.commands import sample as sample_cmd

DATA = Path(__file__).parent / "data" / "sampling"
REPO = Path(__file__).parent.parent


def load(path) -> ModelAnalysis:
    text = Path(path).read_text()
    if str(path).endswith(".dimacs"):
        return ModelAnalysis.from_dimacs(text, str(path))
    return ModelAnalysis.from_file(str(path), text)


def gen(tmp_path, n, seed=3) -> ModelAnalysis:
    p = tmp_path / f"gen{n}_{seed}.tvl"
    p.write_text(generated_model(n, seed))
    return load(p)


def interactions(confs, names, t):
    out = set()
    for c in confs:
        out |= set(itertools.combinations([(n, c[n]) for n in names], t))
    return out


def check_against_products(a: ModelAnalysis, confs, t, include=(), exclude=()):
    names = [a.name(f) for f in a.encoding.features]
    prods = [p for p in a.enumerate(limit=None)
             if all(p[i] for i in include) and not any(p[x] for x in exclude)]
    keys = {tuple(p[n] for n in names) for p in prods}
    assert all(tuple(c[n] for n in names) in keys for c in confs), "a configuration is not a product"
    missing = interactions(prods, names, t) - interactions(confs, names, t)
    assert not missing, f"{len(missing)} valid interactions not covered, e.g. {sorted(missing)[:3]}"
    return prods


# ------------------------------------------------------------------ validity and completeness

@pytest.mark.parametrize("t", [1, 2, 3])
@pytest.mark.parametrize("model", ["robot.tvl", "three.dimacs"])
def test_sample_is_valid_and_complete(model, t):
    a = load(DATA / model)
    confs, r = a.twise_sample(t, seed=5)
    assert r.complete and r.left == 0 and r.coverage == 1.0
    prods = check_against_products(a, confs, t)
    assert len(confs) <= len(prods)


@pytest.mark.parametrize("t", [1, 2, 3])
def test_generated_models(tmp_path, t):
    """A small generated model against its products; a bigger one against the verifier (every
    pair asked; every triple on models this small)."""
    a = gen(tmp_path, 22, seed=3)
    confs, r = a.twise_sample(t, seed=2)
    assert r.complete
    check_against_products(a, confs, t)
    a = gen(tmp_path, 70 if t < 3 else 36, seed=11)
    enc = a.encoding
    r = sample(enc.clauses(), enc.n_features, t=t, seed=2)
    assert r.complete and r.products
    v = verify(enc.clauses(), enc.n_features, r.products, t=t)
    assert v.ok and v.exhaustive, v.summary()


def test_random_cnfs_with_invalid_pairs_and_triples_propagation_cannot_see():
    """Random 3-CNFs: most invalid interactions are proven by SAT calls, learnt once."""
    rng = random.Random(4)
    for k in range(6):
        n = 12
        cls = [[v * rng.choice([1, -1]) for v in rng.sample(range(1, n + 1), 3)] for _ in range(32)]
        text = "".join(f"c {v} v{v}\n" for v in range(1, n + 1)) + f"p cnf {n} {len(cls)}\n" + \
            "".join(" ".join(map(str, c)) + " 0\n" for c in cls)
        a = ModelAnalysis.from_dimacs(text, f"r{k}.dimacs")
        for t in (2, 3):
            confs, r = a.twise_sample(t, seed=k)
            assert r.complete
            if not confs:
                assert a.is_void()
                continue
            check_against_products(a, confs, t)


def test_within_decisions():
    a = load(DATA / "robot.tvl")
    confs, r = a.twise_sample(2, include=["Arm"], exclude=["Lidar"], seed=1)
    assert r.complete and confs and all(c["Arm"] and not c["Lidar"] for c in confs)
    check_against_products(a, confs, 2, include=["Arm"], exclude=["Lidar"])


def test_void_and_single_product():
    a = ModelAnalysis.from_dimacs("p cnf 2 2\n1 0\n-1 0\n", "void.dimacs")
    confs, r = a.twise_sample(2)
    assert confs == [] and r.void and r.complete
    a = ModelAnalysis.from_dimacs("c 1 a\nc 2 b\np cnf 2 2\n1 0\n-2 0\n", "one.dimacs")
    confs, r = a.twise_sample(3)
    assert r.complete and len(confs) == 1 and confs[0]["a"] and not confs[0]["b"]


def test_core_dead_and_equivalent_features_leave_the_interactions():
    a = load(DATA / "robot.tvl")
    _, r = a.twise_sample(2)
    # Robot, Base, Wheels, Motors, Drive (core) and Ghost (dead) are fixed; Nav == Map count once
    assert r.features == 18 and r.open_features == 12 and r.representatives == 11


# ------------------------------------------------------------------ determinism, jobs, budget

def test_same_seed_same_sample_and_jobs_do_not_change_it(tmp_path):
    a = gen(tmp_path, 60, seed=5)
    one, r1 = a.twise_sample(2, seed=9, iterations=3)
    again, _ = a.twise_sample(2, seed=9, iterations=3)
    par, r2 = a.twise_sample(2, seed=9, iterations=3, jobs=2)
    assert one == again == par and r1.sizes == r2.sizes and len(r1.sizes) == 3
    other, r3 = a.twise_sample(2, seed=10, iterations=3)
    assert r3.complete and verify(a.encoding.clauses(), a.encoding.n_features,
                                  [[a.encoding.var(n) if v else -a.encoding.var(n) for n, v in c.items()]
                                   for c in other], t=2).ok


def test_budget_and_cancel_give_an_honest_partial_result(tmp_path):
    a = gen(tmp_path, 120, seed=7)
    enc = a.encoding
    calls = [0]

    def cancel():  # stops the run after a few configurations
        calls[0] += 1
        return calls[0] > 4
    r = sample(enc.clauses(), enc.n_features, t=2, cancel=cancel, iterations=1)
    assert not r.complete and r.stopped == "cancelled" and r.products
    assert r.left > 0 and 0 < r.coverage < 1 and r.covered + r.left + r.invalid == r.considered
    v = verify(enc.clauses(), enc.n_features, r.products, t=2)
    assert v.valid and not v.complete  # each configuration is a product; pairs are missing
    full = sample(enc.clauses(), enc.n_features, t=2, iterations=1)
    assert full.complete and full.left == 0
    assert verify(enc.clauses(), enc.n_features, full.products, t=2).ok
    r = sample(enc.clauses(), enc.n_features, t=2, budget=1e-9)
    assert not r.complete and r.stopped == "budget"
    from tvl_lsp.analysis.counting import CountTimeout
    with pytest.raises(CountTimeout):
        a.sample(t=2, timeout=1e-9)


# ------------------------------------------------------------------ the verifier

def test_verifier_catches_missing_interactions_and_invalid_configurations():
    a = load(DATA / "robot.tvl")
    enc = a.encoding
    r = sample(enc.clauses(), enc.n_features, t=2, seed=3)
    assert verify(enc.clauses(), enc.n_features, r.products, t=2).ok
    cut = r.products[: len(r.products) // 2]
    v = verify(enc.clauses(), enc.n_features, cut, t=2)
    assert v.valid and not v.complete and v.exhaustive and v.missing
    # each pair reported missing is in some product
    prods = [[enc.var(n) if val else -enc.var(n) for n, val in p.items()] for p in a.enumerate(limit=None)]
    for x, y in v.missing:
        assert any(x in p and y in p for p in prods)
    bad = [list(r.products[0])]
    ghost = enc.var("Ghost")
    bad[0] = [ghost if abs(x) == ghost else x for x in bad[0]]
    v = verify(enc.clauses(), enc.n_features, bad + r.products, t=2)
    assert not v.valid and v.invalid_configurations == [0]
    v3 = verify(enc.clauses(), enc.n_features, r.products, t=3)
    assert v3.exhaustive and not v3.complete  # a pairwise sample misses triples here


# ------------------------------------------------------------------ the command and its formats

def test_sample_command_json_and_text(capsys):
    m = str(DATA / "robot.tvl")
    assert sample_cmd.main([m, "--t", "3", "--seed", "2", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["complete"] and data["coverage"] == 1.0 and data["t"] == 3 and data["interactions"]["left"] == 0
    check_against_products(load(m), data["configurations"], 3)
    assert sample_cmd.main([m, "--t", "2"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines and all("Robot" in ln.split() and "Ghost" not in ln.split() for ln in lines)
    assert sample_cmd.main([m, "--t", "4"]) == 2


def test_sample_command_github_matrix(capsys):
    m = str(DATA / "robot.tvl")
    assert sample_cmd.main([m, "--t", "2", "--format", "github-matrix"]) == 0
    out = capsys.readouterr().out
    assert out.count("\n") == 1  # one line: for $GITHUB_OUTPUT
    matrix = json.loads(out)
    entries = matrix["include"]
    a = load(m)
    names = [a.name(f) for f in a.encoding.features]
    confs = [{n: e[n] for n in names} for e in entries]
    check_against_products(a, confs, 2)
    for k, e in enumerate(entries, 1):
        assert e["config"] == f"c{k:0{len(str(len(entries)))}d}"
        assert e["args"].split() == [f"{n}:={'true' if e[n] else 'false'}" for n in names]


def test_sample_command_budget_exits_1_with_a_partial_sample(tmp_path, capsys):
    p = tmp_path / "big.tvl"
    p.write_text(generated_model(200, 5))
    assert sample_cmd.main([str(p), "--t", "2", "--budget", "1e-9", "--format", "json"]) == 1
    cap = capsys.readouterr()
    data = json.loads(cap.out)
    assert data["complete"] is False and data["stopped"] == "budget"
    assert "budget" in cap.err


# ------------------------------------------------------------------ generate --mode sample

def _ws(tmp_path, which="ws"):
    ws = tmp_path / which
    shutil.copytree(REPO / "examples" / which, ws)
    return ws


def test_generate_sample_writes_one_file_per_product_ros1(tmp_path, capsys):
    ws = _ws(tmp_path)
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    assert generate_cmd.main([str(launch), "--mode", "sample", "--t", "3", "--out", "cfg",
                              "--workspace", str(ws)]) == 0
    files = sorted((ws / "src" / "turtlerand" / "cfg").glob("*.launch"))
    a = load(ws / "src" / "turtlerand" / "launch" / "generic.tvl")
    confs, _ = a.twise_sample(3)
    assert len(files) == len(confs)
    assert all("<include file=\"$(find turtlerand)/launch/generic.launch\">" in f.read_text() for f in files)


def test_generate_sample_python_configurations(tmp_path):
    ws = _ws(tmp_path, "ros2_ws")
    launch = ws / "src" / "turtlerand2" / "launch" / "generic.launch.xml"
    assert generate_cmd.main([str(launch), "--mode", "sample", "--t", "2", "--format", "python", "--out", "cfg",
                              "--workspace", str(ws)]) == 0
    files = sorted((ws / "src" / "turtlerand2" / "cfg").glob("*.launch.py"))
    a = load(ws / "src" / "turtlerand2" / "launch" / "generic.tvl")
    names = [a.name(f) for f in a.encoding.features if f is not a.model.root]
    confs = []
    for f in files:
        tree = ast.parse(f.read_text())
        fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef))
        assert fn.name == "generate_launch_description"
        args = next(n for n in ast.walk(fn) if isinstance(n, ast.keyword) and n.arg == "launch_arguments")
        pairs = dict(ast.literal_eval(args.value))
        assert "FindPackageShare('turtlerand2')" in f.read_text() and "'launch/generic.launch.xml'" in f.read_text()
        confs.append({n: pairs[n] == "true" for n in names})
    assert files
    check_against_products(a, [dict(c, **{a.model.root.name: True}) for c in confs], 2)


def test_generate_python_format_needs_ros2(tmp_path, capsys):
    ws = _ws(tmp_path)
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    assert generate_cmd.main([str(launch), "--mode", "sample", "--format", "python", "--workspace", str(ws),
                              "--dry-run"]) == 2
    assert "ROS 2" in capsys.readouterr().err


@pytest.mark.parametrize("t", [1, 2, 3])
def test_features_in_no_clause_and_units(t):
    """Features the clauses never mention are free; a unit clause fixes one."""
    for clauses, n in (([], 3), ([[1, 2]], 4), ([[2]], 3)):
        r = sample(clauses, n, t=t)
        assert r.complete and all(len(p) == n for p in r.products)
        v = verify(clauses, n, r.products, t=t)
        assert v.ok and v.exhaustive, v.summary()
        got = {tuple(sorted(c)) for p in r.products for c in itertools.combinations(p, t)}
        every = {tuple(sorted(c)) for vs in itertools.combinations(range(1, n + 1), t)
                 for c in itertools.product(*[(x, -x) for x in vs])
                 if all(any(lit in c for lit in cl) or any(abs(lit) not in vs for lit in cl) for cl in clauses)
                 and not (clauses == [[2]] and -2 in c)}
        assert every <= got
