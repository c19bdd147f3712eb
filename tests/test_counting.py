"""The counting service (issue #15): d4's d-DNNF behind every count, pyganak as the fallback.

Oracles: enumeration of the products with a SAT solver (small models), pyganak's projected
counts, ddnnife's counts on the same d-DNNF, and the SAT-based core / dead analysis.
"""

import itertools
import json
import os
import random
import shutil
import threading
import time
from pathlib import Path

import pytest

from tvl_lsp.base import formula as fm
from tvl_lsp.analysis.counting import service as S
from tvl_lsp.analysis.counting.cache import DiskCache
from tvl_lsp.analysis.counting.circuit import Circuit
from tvl_lsp.analysis.counting.d4 import compile_cnf, compile_inprocess
from tvl_lsp.analysis.counting.errors import CountCancelled, CountTimeout, EngineFailed
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.cli.commands import count as count_cmd
from tvl_lsp.cli.commands import sample as sample_cmd
from tvl_lsp.tvl import parse_model

REPO = Path(__file__).resolve().parents[1]
DATA = REPO / "tests" / "data" / "counting"
MODELS = ["cards.tvl", "attrs_determined.tvl", "attrs_free.tvl", "void.tvl"]
EXAMPLE = REPO / "examples" / "ws" / "src" / "turtlerand" / "launch" / "generic.tvl"


@pytest.fixture(autouse=True)
def fresh_cache(tmp_path, monkeypatch):
    """Every test compiles into its own disk cache, with an empty memory cache."""
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    S.MEMORY.clear()
    S.forget_failures()
    yield tmp_path / "cache"
    S.MEMORY.clear()
    S.forget_failures()


def load(name) -> ModelAnalysis:
    p = DATA / name if not isinstance(name, Path) else name
    if str(p).endswith(".dimacs"):
        return ModelAnalysis.from_dimacs(p.read_text(), str(p))
    res = parse_model(p.read_text(), str(p))
    assert not res.errors, res.errors
    return ModelAnalysis(res.model)


def products(a: ModelAnalysis) -> list[dict]:
    return list(a.enumerate(limit=None))


def hard_cnf(n=200, seed=7):
    """A random 3-CNF d4 needs far more than 20 s for (measured)."""
    rng = random.Random(seed)
    return n, [[rng.choice([-1, 1]) * v for v in rng.sample(range(1, n + 1), 3)] for _ in range(int(n * 2.5))]


# ------------------------------------------------------------------ counts

@pytest.mark.parametrize("name", MODELS + ["tiny.dimacs"])
def test_counts_equal_enumeration_and_pyganak(name):
    a = load(name)
    prods = products(a)
    c = a.count_result()
    assert c.value == len(prods)
    assert c.value == a.counter._pyganak([], None, None)
    expected = {"attrs_free.tvl": "pyganak"}.get(name, "d4")
    assert c.engine == expected


def test_attribute_determinism_is_detected():
    assert load("attrs_determined.tvl").encoding.aux_determined()
    assert load("cards.tvl").encoding.aux_determined()
    free = load("attrs_free.tvl").encoding
    assert free.attribute_vars() and not free.aux_determined()
    # the d-DNNF of such a CNF counts attribute values too: more than the products
    a = load("attrs_free.tvl")
    enc = a.encoding
    raw = S.CNFCounter(enc.nvars, enc.clauses(), enc.n_features, determined=True).count()
    assert raw.engine == "d4" and raw.value > a.count()


def test_cardinality_counters_are_functions_of_the_features():
    """Every model of the CNF is fixed by its features: d4's count over all variables equals
    the number of products."""
    a = load("cards.tvl")
    enc = a.encoding
    assert enc.nvars > enc.n_features  # the groups did introduce counter variables
    from tvl_lsp.analysis.counting.d4 import compile_inprocess
    _, n_all = compile_inprocess(enc.nvars, enc.clauses())
    used = {abs(x) for c in enc.clauses() for x in c} | set(range(1, enc.n_features + 1))
    assert n_all >> (enc.nvars - len(used)) == len(products(a))


@pytest.mark.parametrize("name", MODELS + ["tiny.dimacs"])
def test_per_feature_counts_equal_include_counts(name):
    a = load(name)
    prods = products(a)
    per = a.feature_counts()
    for f in a.encoding.features:
        n = a.name(f)
        assert per[n] == sum(1 for p in prods if p[n])
        if name != "attrs_free.tvl":  # (pyganak: one count per feature, slow enough)
            assert per[n] == a.count(include=[n])


@pytest.mark.parametrize("name", ["cards.tvl", "attrs_free.tvl", "tiny.dimacs"])
def test_per_feature_counts_under_decisions(name):
    a = load(name)
    prods = products(a)
    names = [a.name(f) for f in a.encoding.features]
    rng = random.Random(3)
    for _ in range(6):
        inc = rng.sample(names, 1)
        exc = [x for x in rng.sample(names, 2) if x not in inc][:1]
        sel = [p for p in prods if all(p[x] for x in inc) and not any(p[x] for x in exc)]
        r = a.feature_counts_result(include=inc, exclude=exc)
        assert r.total == len(sel) == a.count(include=inc, exclude=exc)
        for f, v in a.encoding.var_of_feature.items():
            assert r.counts[v] == sum(1 for p in sel if p[a.name(f)])


@pytest.mark.parametrize("name", ["cards.tvl", "attrs_determined.tvl", "tiny.dimacs"])
def test_core_and_dead_from_counts_match_the_sat_analysis(name):
    a = load(name)
    r = a.feature_counts_result()
    enc = a.encoding
    core = {a.name(f) for f, v in enc.var_of_feature.items() if r.counts[v] == r.total}
    dead = {a.name(f) for f, v in enc.var_of_feature.items() if r.counts[v] == 0}
    assert core == set(a.core_features())
    assert dead == set(a.dead_features())
    assert core and (dead or name != "cards.tvl")


def test_per_feature_counts_agree_with_ddnnife():
    a = load("cards.tvl")
    enc = a.encoding
    # ddnnife reads the d-DNNF of the CNF itself; the counts compared are the service's (of the
    # reduced CNF, lifted back)
    raw = S.CNFCounter(enc.nvars, enc.clauses(), enc.n_features, reduce=False)
    comp = raw.circuit()
    import ddnnife
    m = ddnnife.Ddnnf.from_file(comp.path, a.encoding.nvars).as_mut()
    n = a.encoding.n_features
    for lits in ([], [3], [3, -5], [-2]):
        r = a.counter.feature_counts(lits)
        assert r.total == m.count(lits)
        assert r.counts[1:] == m.count_multiple(lits, list(range(1, n + 1)))


@pytest.mark.parametrize("name", ["cards.tvl", "attrs_free.tvl"])
def test_count_under_a_formula(name):
    a = load(name)
    prods = products(a)
    names = [a.name(f) for f in a.encoding.features]
    rng = random.Random(11)
    for _ in range(8):
        x, y, z = rng.sample(names, 3)
        f = fm.disj([fm.conj([fm.var(x), fm.neg(fm.var(y))]), fm.var(z)])
        want = sum(1 for p in prods if fm.evaluate(f, p))
        assert a.count(formula=f) == want
        # the other route: the formula's clauses compiled with the model
        cubes = a._cubes
        a._cubes = lambda g, limit=0: None
        try:
            assert a.count(formula=f) == want
        finally:
            a._cubes = cubes


@pytest.mark.parametrize("seed", range(40))
def test_circuit_passes_equal_brute_force(seed):
    rng = random.Random(seed)
    n = rng.randint(1, 9)
    cls = [[rng.choice([1, -1]) * rng.randint(1, n) for _ in range(rng.randint(1, 3))]
           for _ in range(rng.randint(0, 2 * n))]
    text, n_d4 = compile_inprocess(n, cls)
    c = Circuit(text, n)
    models = [m for m in itertools.product([False, True], repeat=n)
              if all(any((x > 0) == m[abs(x) - 1] for x in cl) for cl in cls)]
    assert n_d4 == len(models) == c.count()
    for _ in range(3):
        lits = [rng.choice([1, -1]) * rng.randint(1, n) for _ in range(rng.randint(0, 2))]
        sel = [m for m in models if all((x > 0) == m[abs(x) - 1] for x in lits)]
        r = c.counts(lits)
        assert r.total == len(sel) == c.count(lits)
        assert r.positive[1:] == [sum(1 for m in sel if m[v]) for v in range(n)]
        if sel:
            s = c.sample(rng, lits)
            assert tuple(x > 0 for x in s) in sel


# ------------------------------------------------------------------ sampling

def _pairs(p: dict, names) -> set:
    lits = [(n, p[n]) for n in names]
    return set(itertools.combinations(lits, 2))


@pytest.mark.parametrize("name", MODELS + ["tiny.dimacs", EXAMPLE])
def test_pairwise_sample_is_valid_and_covers_every_valid_pair(name):
    a = load(name)
    prods = products(a)
    names = [a.name(f) for f in a.encoding.features]
    keys = {tuple(p[n] for n in names) for p in prods}
    sample, engine = a.sample(t=2, seed=1)
    assert engine == "sat"  # t-wise samples need no compilation (tvl_lsp.analysis.sampling)
    assert all(tuple(s[n] for n in names) in keys for s in sample)
    valid = set().union(*[_pairs(p, names) for p in prods]) if prods else set()
    covered = set().union(*[_pairs(s, names) for s in sample]) if sample else set()
    assert valid <= covered
    if len(prods) > 20:
        assert len(sample) < len(prods)
    # the same seed, the same sample
    assert a.sample(t=2, seed=1)[0] == sample


def test_pairwise_sample_within_decisions_and_t1():
    a = load("cards.tvl")
    names = [a.name(f) for f in a.encoding.features]
    prods = [p for p in products(a) if p["Arm"] and not p["Lidar"]]
    sample, _ = a.sample(t=2, include=["Arm"], exclude=["Lidar"], seed=4)
    keys = {tuple(p[n] for n in names) for p in prods}
    assert all(tuple(s[n] for n in names) in keys for s in sample)
    assert set().union(*[_pairs(p, names) for p in prods]) <= set().union(*[_pairs(s, names) for s in sample])
    one, _ = a.sample(t=1, seed=4)
    lits = {(n, p[n]) for p in products(a) for n in names}
    assert lits <= {(n, s[n]) for s in one for n in names}
    assert len(one) < len(sample) + 1


@pytest.mark.parametrize("name", ["tiny.dimacs", "attrs_free.tvl"])
def test_uniform_sample_is_valid_seeded_and_uniform(name):
    a = load(name)
    names = [a.name(f) for f in a.encoding.features]
    prods = products(a)
    keys = [tuple(p[n] for n in names) for p in prods]
    k = 3000 if name == "tiny.dimacs" else 600
    sample, engine = a.sample(uniform=k, seed=9)
    assert engine == ("d4" if name == "tiny.dimacs" else "pyganak")
    got = [tuple(s[n] for n in names) for s in sample]
    assert set(got) <= set(keys)
    assert a.sample(uniform=20, seed=9)[0] == sample[:20]
    # every product drawn about k / |products| times (a fixed seed: no flakiness)
    expect = k / len(keys)
    for key in keys:
        assert 0.6 * expect < got.count(key) < 1.4 * expect


# ------------------------------------------------------------------ service: cache, fallback, cancel

def test_disk_cache_hit_and_memory_hit(fresh_cache):
    a = load("cards.tvl")
    comp = a.counter.circuit()
    assert comp.source == "d4"
    files = sorted(p.suffix for p in fresh_cache.iterdir())
    assert files == [".count", ".nnf"]
    assert ModelAnalysis(a.model).counter.circuit().source == "memory"
    S.MEMORY.clear()
    b = load("cards.tvl")
    c2 = b.counter.circuit()
    assert c2.source == "disk" and b.count() == a.count()
    # the same CNF from a differently laid out text shares the entry
    S.MEMORY.clear()
    text = (DATA / "cards.tvl").read_text().replace("\n  ", "\n      ")
    c = ModelAnalysis(parse_model(text, "other.tvl").model).counter
    assert c.circuit().source == "disk"


def test_total_count_from_disk_needs_no_parse(fresh_cache):
    n, cls = 30, [[1, 2], [-3, 4], [5, -6, 7]]
    svc = S.CNFCounter(n, cls, n)
    total = svc.count().value
    S.MEMORY.clear()
    svc2 = S.CNFCounter(n, cls, n)
    c = svc2.count()
    assert c.value == total and c.cached and S.MEMORY.get(svc2.key) is None


def test_damaged_cache_file_is_recompiled(fresh_cache):
    a = load("cards.tvl")
    want = a.count(include=["Arm"])
    key = a.counter.key
    S.MEMORY.clear()
    (fresh_cache / f"{key}.nnf").write_text("o 1 0\n1 99 0\n")
    b = load("cards.tvl")
    assert b.count(include=["Arm"]) == want
    assert b.counter.circuit().source in ("d4", "memory")


def test_disk_cache_is_bounded(tmp_path):
    dc = DiskCache(tmp_path / "c", limit=3000)
    for i in range(6):
        dc.put(f"k{i}", "o 1 0\n" + "x" * 994, 1)  # (d4's format: eviction recognises it)
        os.utime(tmp_path / "c" / f"k{i}.nnf", (1000 + i, 1000 + i))
        os.utime(tmp_path / "c" / f"k{i}.count", (1000 + i, 1000 + i))
    total = sum(p.stat().st_size for p in (tmp_path / "c").iterdir())
    assert total <= 3000
    assert dc.get("k5") is not None and dc.get("k0") is None


def test_concurrent_writers_leave_a_valid_cache(fresh_cache):
    n, cls = 200, [[i, i + 1] for i in range(1, 199)] + [[-i, -(i + 2)] for i in range(1, 198, 3)]
    results = []

    def work():
        svc = S.CNFCounter(n, cls, n)
        results.append(svc.count().value)
    # separate processes would race on the same file: threads with separate counters race
    # on the compile lock and the disk cache's atomic rename
    ts = [threading.Thread(target=work) for _ in range(3)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert len(set(results)) == 1
    S.MEMORY.clear()
    svc = S.CNFCounter(n, cls, n)
    assert svc.circuit().source == "disk" and svc.count([5]).value <= results[0]
    assert not [p for p in fresh_cache.iterdir() if p.name.startswith(".")]


def test_fallback_to_pyganak_when_d4_fails(monkeypatch):
    a = load("cards.tvl")
    want = len(products(a))

    def broken(*args, **kwargs):
        raise EngineFailed("d4 failed (simulated)")
    monkeypatch.setattr("tvl_lsp.analysis.counting.d4.compile_inprocess", broken)
    c = a.count_result()
    assert (c.value, c.engine) == (want, "pyganak") and "simulated" in c.note
    r = a.feature_counts_result()
    assert r.engine == "pyganak" and r.total == want
    assert r.counts[a.encoding.var("Arm")] == sum(1 for p in products(a) if p["Arm"])


def test_d4_timeout_falls_back_and_is_remembered():
    n, cls = hard_cnf()
    svc = S.CNFCounter(n, cls, n)
    t = time.monotonic()
    with pytest.raises(CountTimeout):
        svc.count(timeout=0.6)  # d4 gets 0.45 s, pyganak the rest: neither is enough
    assert time.monotonic() - t < 5
    # a second query with no more budget does not try d4 again
    t = time.monotonic()
    with pytest.raises((CountTimeout, EngineFailed)):
        svc.circuit(timeout=0.4)
    assert time.monotonic() - t < 0.3


def test_compile_is_cancellable_and_reports_progress(tmp_path):
    n, cls = hard_cnf()
    ev = threading.Event()
    threading.Timer(1.3, ev.set).start()
    seen = []
    t = time.monotonic()
    with pytest.raises(CountCancelled):
        compile_cnf(n, cls, str(tmp_path / "x.nnf"), cancel=ev, progress=seen.append)
    assert time.monotonic() - t < 3
    assert seen and "d4" in seen[0]
    assert not (tmp_path / "x.nnf").exists()


def test_compiling_writes_nothing_on_stdout(capfd):
    a = load("cards.tvl")
    a.count()
    compile_inprocess(3, [[1, 2]])
    out, _ = capfd.readouterr()
    assert out == ""


# ------------------------------------------------------------------ CLI

def test_count_per_feature_json(capsys):
    p = DATA / "tiny.dimacs"
    assert count_cmd.main([str(p), "--per-feature", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["count"] == 12 and data["engine"] == "d4" and data["complete"]
    # the flat-model import gives the same answers, the root included
    a = load("tiny.dimacs")
    assert data["features"] == a.feature_counts()
    assert count_cmd.main([str(p), "--per-feature", "--include", "Lidar"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[-1] == str(a.count(include=["Lidar"]))
    assert "Fusion\t2" in lines
    m = DATA / "cards.tvl"
    assert count_cmd.main([str(m), "--per-feature", "--json", "--exclude", "Arm"]) == 0
    data = json.loads(capsys.readouterr().out)
    b = load("cards.tvl")
    assert data["features"] == b.feature_counts(exclude=["Arm"])
    assert data["count"] == b.count(exclude=["Arm"]) and data["features"]["Gripper"] == 0


def test_count_json_keeps_huge_counts_exact(capsys, tmp_path):
    d = tmp_path / "wide.dimacs"
    d.write_text("p cnf 300 1\n1 2 0\n")
    assert count_cmd.main([str(d), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["count"] == 3 * 2 ** 298 and data["count_text"] == str(3 * 2 ** 298)


def test_sample_command(capsys):
    m = DATA / "cards.tvl"
    assert sample_cmd.main([str(m), "--t", "2", "--seed", "3", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    a = load("cards.tvl")
    names = [a.name(f) for f in a.encoding.features]
    prods = products(a)
    keys = {tuple(p[n] for n in names) for p in prods}
    confs = data["configurations"]
    assert all(tuple(c[n] for n in names) in keys for c in confs)
    assert set().union(*[_pairs(p, names) for p in prods]) <= set().union(*[_pairs(c, names) for c in confs])
    assert len(confs) < len(prods)
    assert sample_cmd.main([str(m), "--uniform", "5", "--include", "Legs", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert len(data["configurations"]) == 5 and all(c["Legs"] and c["Arm"] for c in data["configurations"])
    assert sample_cmd.main([str(m), "--t", "2", "--include", "Nope"]) == 2
    assert sample_cmd.main([str(DATA / "void.tvl"), "--t", "2"]) == 1


def test_generate_sample_writes_a_pairwise_cover(tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(REPO / "examples" / "ws", ws)
    launch = ws / "src" / "turtlerand" / "launch" / "generic.launch"
    from tvl_lsp.cli.commands import generate
    assert generate.main([str(launch), "--mode", "sample", "--t", "2", "--out", "cfg", "--workspace", str(ws)]) == 0
    files = sorted((ws / "src" / "turtlerand" / "cfg").glob("*.launch"))
    a = load(ws / "src" / "turtlerand" / "launch" / "generic.tvl")
    names = [a.name(f) for f in a.encoding.features]
    prods = products(a)
    assert 0 < len(files) <= len(prods)
    import re
    confs = []
    for f in files:
        vals = dict(re.findall(r'<arg name="(\w+)" value="(true|false)"/>', f.read_text()))
        conf = {n: vals.get(n, "true") == "true" for n in names}
        confs.append(conf)
    keys = {tuple(p[n] for n in names) for p in prods}
    assert all(tuple(c[n] for n in names) in keys for c in confs)
    assert set().union(*[_pairs(p, names) for p in prods]) <= set().union(*[_pairs(c, names) for c in confs])


def test_cnf_without_variables(tmp_path):
    """d4 dies of a floating point exception on it: the service never hands it one."""
    assert compile_inprocess(0, []) == ("t 1 0\n", 1)
    assert compile_inprocess(0, [[]])[1] == 0
    assert compile_cnf(0, [], str(tmp_path / "x.nnf"))["count"] == 1
    assert S.CNFCounter(0, [], 0).count().value == 1
    assert S.CNFCounter(0, [], 0).feature_counts().total == 1
    res = parse_model("root R { }\n", "r.tvl")
    if res.model is not None and res.model.root is not None:
        assert ModelAnalysis(res.model).count() == 1
