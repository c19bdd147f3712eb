"""Differential test against the real roslaunch (Debian's python3-roslaunch, /usr/bin/python3).

For the launch files of the test workspace (tests/testenv.py) and tests/data/launch (and, in
the corpus suite, the thesis's), and every assignment of the feature args (a fixed sample when
there are many), the nodes tvl-lsp says are loaded
(both the concrete loader and the symbolic analysis evaluated at the assignment) equal
what roslaunch loads, and where roslaunch raises a load error tvl-lsp predicts one.
"""

from __future__ import annotations

import itertools
import json
import os
import random
import re
import subprocess
from pathlib import Path

import pytest

from conftest import corpus_option
from testenv import EXAMPLE_WS, OVERLAY_WS, ROSLAUNCH_MISSING, SYS_PY, have_roslaunch, make_ws
from tvl_lsp.base.formula import evaluate
from tvl_lsp.launch import analyse_launch, find_packages, load_launch
from tvl_lsp.launch.model import json_value

HERE = Path(__file__).resolve().parent
OWN_WS = HERE / "data" / "launch" / "ws" / "src"
ORACLE = HERE / "data" / "launch" / "roslaunch_oracle.py"

pytestmark = pytest.mark.skipif(not have_roslaunch(), reason=ROSLAUNCH_MISSING)

ANON = re.compile(r"_anon\d+")


def _norm(names):
    return sorted(ANON.sub("_anon", n) for n in names)


def same_value(a, b) -> bool:
    """Strict equality of parameter values (JSON): True is not 1, 1 is not 1.0."""
    if type(a) is not type(b):
        return False
    if isinstance(a, list):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_value(a[k], b[k]) for k in a)
    return a == b


def param_diff(lr, values) -> list:
    """The parameters whose names or values differ between tvl-lsp's load and roslaunch's
    (``textfile`` / ``binfile`` / ``command`` ones: names only, tvl-lsp shows them by path)."""
    mine = {k: json_value(v) for k, v in lr.params.items()}
    out = sorted(set(mine) ^ set(values))
    for k in sorted(set(mine) & set(values)):
        if k not in lr.param_sources and not same_value(mine[k], values[k]):
            out.append((k, mine[k], values[k]))
    return out


def symbolic_load(analysis, assignment):
    """The parameter tree of the symbolic analysis at one assignment of its free args (the last
    fact that holds wins, as in roslaunch), shaped like a LoadResult for :func:`param_diff`."""
    from types import SimpleNamespace
    params, sources = {}, {}
    for p in analysis.params:
        if evaluate(p.condition, assignment):
            params[p.name] = p.data
            if p.source in ("textfile", "binfile", "command"):
                sources[p.name] = p.source
            else:
                sources.pop(p.name, None)
    return SimpleNamespace(params=params, param_sources=sources)


def _fails(fact) -> bool:
    """A fact saying roslaunch fails: an error, an unset arg (a warning where the command
    line could give it, but this run does not; likewise an undeclared arg), or a program missing
    from a package's sources (a warning: a build may provide it)."""
    return fact.severity == 1 or fact.code in ("unset-arg", "command-not-found", "undefined-arg")


def _oracle(jobs):
    r = subprocess.run([SYS_PY, str(ORACLE)], input=json.dumps(jobs), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def _assignments(free, limit=24, seed=7):
    if len(free) <= 5:
        return [dict(zip(free, bits)) for bits in itertools.product([False, True], repeat=len(free))]
    rnd = random.Random(seed)
    out = [dict.fromkeys(free, True), dict.fromkeys(free, False)]
    out += [{f: rnd.random() < 0.5 for f in free} for _ in range(limit - 2)]
    return out


def _files(*src: Path) -> list[str]:
    """The launch files under these ``src`` folders, relative to them."""
    return sorted({str(p.relative_to(s)) for s in src
                   for p in list(s.glob("*/launch/*.launch")) + list(s.glob("*/test/*.test"))})


def pytest_generate_tests(metafunc):
    """(workspace, launch file relative to its src folder, extra environment) cases: the test
    workspace, tests/data/launch/ws and, with --corpus, the thesis's workspace."""
    if "case" not in metafunc.fixturenames:
        return
    crawler_env = (("CRAWLER_SIMULATION", "false"), ("CRAWLER_SERIAL_PORT", "/dev/ttyUSB0"))
    cases = [("repo", f, ()) for f in _files(EXAMPLE_WS / "src", OVERLAY_WS / "src")]
    # the crawler's file reads two environment variables; also run it with them set
    cases += [("repo", "crawler_bringup/launch/generic.launch", crawler_env)]
    cases += [("own", f, ()) for f in _files(OWN_WS)]
    corpus = corpus_option(metafunc.config)
    if corpus is not None:
        thesis = corpus / "thesis" / "ws" / "src"
        cases += [("thesis", f, ()) for f in _files(thesis)]
        cases += [("thesis", "turtlebot_bringup/launch/generic.launch",
                   (("TURTLEBOT_SIMULATION", "false"), ("TURTLEBOT_SERIAL_PORT", "/dev/ttyUSB0")))]
    metafunc.parametrize("case", [pytest.param(c, id=f"{c[0]}:{c[1]}{'+env' if c[2] else ''}",
                                               marks=[pytest.mark.corpus] if c[0] == "thesis" else [])
                                  for c in cases])


@pytest.fixture(scope="module")
def workspaces(tmp_path_factory, request):
    """name -> src folder, made on first use."""
    made: dict[str, Path] = {}

    def get(name: str) -> Path:
        if name not in made:
            if name == "repo":
                made[name] = make_ws(tmp_path_factory.mktemp("repo") / "ws") / "src"
            elif name == "own":
                made[name] = OWN_WS
            else:
                made[name] = request.getfixturevalue("corpus_dir") / "thesis" / "ws" / "src"
        return made[name]
    return get


def _prepare(path, ws, extra_env):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("TURTLEBOT_", "CRAWLER_"))}
    env.update(dict(extra_env))
    pk = find_packages(str(ws))
    analysis = analyse_launch(Path(path).read_text(), path, packages=pk, env=env)
    assigns = _assignments(analysis.free_args)
    jobs = [dict(file=path, args={k: str(v).lower() for k, v in a.items()}, package_path=str(ws),
                 env=dict(extra_env)) for a in assigns]
    # args that are not free booleans and have no default: roslaunch needs them; one more run
    # gives each a string value (the free ones false)
    required = [d.name for d in analysis.feature_args
                if d.default is None and d.value is None and d.name not in analysis.free_args]
    if required:
        a = dict.fromkeys(analysis.free_args, False)
        assigns.append(a)
        jobs.append(dict(file=path, args={**{k: "false" for k in a}, **{r: f"v_{r}" for r in required}},
                         package_path=str(ws), env=dict(extra_env)))
    return env, pk, analysis, assigns, jobs


@pytest.fixture(scope="module")
def oracle_results(request, workspaces):
    """One roslaunch process for all files of the session's cases (its start-up dominates)."""
    cases = sorted({item.callspec.params["case"] for item in request.session.items
                    if item.module is request.module and hasattr(item, "callspec") and "case" in item.callspec.params})
    all_jobs = []
    for name, rel, extra_env in cases:
        ws = workspaces(name)
        all_jobs.extend(_prepare(str(ws / rel), ws, extra_env)[4])
    results = iter(_oracle(all_jobs))
    out = {}
    for name, rel, extra_env in cases:
        ws = workspaces(name)
        out[(name, rel, extra_env)] = [next(results) for _ in _prepare(str(ws / rel), ws, extra_env)[4]]
    return out


def test_same_nodes_and_errors_as_roslaunch(case, workspaces, oracle_results):
    name, rel, extra_env = case
    ws = workspaces(name)
    path = str(ws / rel)
    env, pk, analysis, assigns, jobs = _prepare(path, ws, extra_env)
    results = oracle_results[case]
    checked_ok = checked_err = 0
    for a, job, o in zip(assigns, jobs, results):
        lr = load_launch(path, job["args"], packages=pk, env=env)
        # the symbolic analysis knows the free args only (a run giving other args: concrete only)
        symbolic = set(job["args"]) <= set(analysis.free_args)
        sym_nodes = _norm(n.name for n in analysis.nodes if not n.is_test and evaluate(n.condition, a))
        sym_errs = [f for f in analysis.facts if _fails(f) and evaluate(f.condition, a)]
        where = f"{path} {job['args']}"
        if o["ok"]:
            checked_ok += 1
            assert lr.error is None, (where, lr.error)
            assert _norm(n["name"] for n in lr.nodes) == _norm(o["nodes"]), where
            assert param_diff(lr, o["values"]) == [], where
            if symbolic:
                assert sym_nodes == _norm(o["nodes"]), where
                assert param_diff(symbolic_load(analysis, a), o["values"]) == [], where
                assert not sym_errs, (where, [(f.code, f.message) for f in sym_errs])
        else:
            checked_err += 1
            assert lr.error is not None, (where, o)
            if o["error"] != "ResourceNotFound" and symbolic:
                # a reason inside the workspace: the symbolic analysis predicts it too
                assert sym_errs, (where, o)
    assert checked_ok + checked_err == len(assigns)


# ---------------------------------------------------------------- launch files nobody has seen

FEATS = ["A", "B", "C"]

def _cond(r):
    k = r.random()
    f = r.choice(FEATS)
    if k < 0.35: return f' if="$(arg {f})"'
    if k < 0.55: return f' unless="$(arg {f})"'
    if k < 0.62: g = r.choice(FEATS); return f' if="$(eval arg(\'{f}\') and not {g})"'
    if k < 0.66: return f' if="$(eval {f} or {r.choice(FEATS)})"'
    if k < 0.68: return ' if="$(arg mode)"'
    return ""

def _gen(r, depth=0, names=None, inc_ok=True):
    out = []
    for _ in range(r.randint(1, 4)):
        k = r.random()
        if k < 0.35:
            nm = r.choice(["a", "b", "c", "d", "$(arg side)", "x_$(arg side)", "$(anon q)"])
            ns = r.choice(["", "", ' ns="n1"', ' ns="/abs"', ' ns="$(arg side)"', ' ns=""'])
            extra = r.choice(["", "", ' respawn="true"', ' required="$(arg A)"', ' respawn="$(arg B)"'])
            out.append(f'<node pkg="alpha_pkg" type="t" name="{nm}"{ns}{extra}{_cond(r)}/>')
        elif k < 0.55 and depth < 3:
            ns = r.choice(["", "", ' ns="g1"', ' ns="$(arg side)"'])
            out.append(f'<group{ns}{_cond(r)}>' + "".join(_gen(r, depth + 1, names, inc_ok)) + '</group>')
        elif k < 0.68:
            nm = r.choice(["side", "mode", "extra", "v"])
            kind = r.choice(["value", "default", "value"])
            val = r.choice(["left", "right", "true", "false", "maybe", "$(arg A)", "$(arg extra)"])
            out.append(f'<arg name="{nm}" {kind}="{val}"{_cond(r)}/>')
        elif k < 0.78 and inc_ok:
            args = ""
            for a in r.sample(["robot", "rate", "fast", "bogus"], r.randint(0, 3)):
                v = r.choice(["r1", "$(arg side)", "true", "$(arg C)", "2"])
                args += f'<arg name="{a}" value="{v}"{_cond(r) if r.random() < .3 else ""}/>'
            pa = ' pass_all_args="true"' if r.random() < 0.15 else ""
            target = r.choice(["part.launch", "part.launch", "all_args.launch"])
            out.append(f'<include file="$(find beta)/launch/{target}"{pa}{r.choice(["", _cond(r)])}>{args}</include>')
        elif k < 0.81:
            out.append(r.choice([
                f'<rosparam{_cond(r)}>{{k: 1, m: {{n: 2}}}}</rosparam>',
                f'<rosparam param="lst"{_cond(r)}>[1, 2]</rosparam>',
                f'<rosparam{_cond(r)}>3</rosparam>',
                f'<env name="E" value="$(optenv HOME x)"{_cond(r)}/>',
                f'<test test-name="t{r.randint(0, 3)}" pkg="alpha_pkg" type="t"{_cond(r)}/>',
                f'<node pkg="alpha_pkg" type="t" name="$(eval \'e\' + str(arg(\'A\')))"{_cond(r)}/>',
                f'<group ns="cp" clear_params="true"{_cond(r)}><node pkg="alpha_pkg" type="t" name="cp"/></group>',
                f'<node pkg="alpha_pkg" type="t" name="w" clear_params="true"{_cond(r)}><param name="z" value="1"/></node>',
                f'<machine name="m1" address="localhost"{_cond(r)}/>',
                f'<arg name="dflt" default="$(arg nope)"{_cond(r)}/>',
                f'<node pkg="alpha_pkg" type="t" name="o" output="$(arg side)"{_cond(r)}/>',
            ]))
        elif k < 0.88:
            out.append(f'<param name="{r.choice(["p", "~q", "/r"])}" value="{r.choice(["1", "$(arg side)", "x"])}"{_cond(r)}/>')
        else:
            out.append(f'<remap from="a" to="{r.choice(["b", "$(arg side)"])}"{_cond(r)}/>')
    return out

def _make(seed):
    r = random.Random(seed)
    head = "".join(f'<arg name="{f}"/>' for f in FEATS)
    pre = '<arg name="side" value="left" if="$(arg A)"/><arg name="side" value="right" unless="$(arg A)"/>' if r.random() < 0.7 else ""
    return f"<launch>{head}{pre}" + "".join(_gen(r)) + "</launch>\n"



def test_random_generic_launch_files_against_roslaunch(tmp_path):
    """Random generic launch files (groups, namespaces, conditional and paired args, includes
    with args and pass_all_args, evals, anon names, params, rosparam, tests, ...) under all 8
    assignments of their three features: same nodes and params as roslaunch, and a predicted
    error wherever roslaunch fails."""
    pk = find_packages(str(OWN_WS))
    jobs, meta = [], []
    for seed in range(40):
        p = str(tmp_path / f"g{seed}.launch")
        Path(p).write_text(_make(seed))
        for bits in itertools.product([False, True], repeat=3):
            a = dict(zip(FEATS, bits))
            jobs.append(dict(file=p, args={k: str(v).lower() for k, v in a.items()}, package_path=str(OWN_WS)))
            meta.append((p, a))
    results = _oracle(jobs)
    analyses = {}
    n_ok = 0
    for (p, a), job, o in zip(meta, jobs, results):
        if p not in analyses:
            analyses[p] = analyse_launch(Path(p).read_text(), p, packages=pk, features=FEATS)
        an = analyses[p]
        lr = load_launch(p, job["args"], packages=pk)
        sym_nodes = _norm(x.name for x in an.nodes if evaluate(x.condition, a) and not x.is_test)
        sym_errs = [x for x in an.facts if _fails(x) and evaluate(x.condition, a)]
        where = (Path(p).read_text(), a, o)
        if o["ok"]:
            n_ok += 1
            assert lr.error is None and not sym_errs, (where, lr.error, [x.message for x in sym_errs])
            assert _norm(x["name"] for x in lr.nodes) == _norm(o["nodes"]) == sym_nodes, where
            assert param_diff(lr, o["values"]) == [], where
            assert param_diff(symbolic_load(an, a), o["values"]) == [], where
        else:
            assert lr.error is not None and sym_errs, where
    assert 0 < n_ok < len(jobs)  # both outcomes are exercised


# ---------------------------------------------------------------- the command line as roslaunch reads it

@pytest.mark.parametrize("args", [
    {"3d_sensor": "asus", "_rate": "5", "frame": " odom "},   # not a ROS name; a private param; stripped
    {"frame": ""},                                           # an empty value sets nothing
    {"frame": "a:=b", "__ns_like": "1"},                     # ':=' twice: ignored; an undeclared arg
])
def test_the_command_line_is_read_as_roslaunch_reads_it(args):
    """roslaunch takes name:=value as a ROS remapping (rosgraph.names.load_mappings): it ignores
    some of them; tvl-lsp launch loads the same parameters and says which it ignored."""
    path = str(OWN_WS / "delta" / "launch" / "cmdline_names.launch")
    (o,) = _oracle([dict(file=path, args=args, package_path=str(OWN_WS))])
    assert o["ok"]
    lr = load_launch(path, args, packages=find_packages(str(OWN_WS)))
    assert lr.error is None and param_diff(lr, o["values"]) == []
    ignored = [k for k in args if k in ("3d_sensor", "_rate") or args[k] in ("", "a:=b")]
    assert len([w for w in lr.warnings if "roslaunch ignores" in w]) == len(ignored)


# ---------------------------------------------------------------- $(find) as rospkg crawls

def test_find_crawls_the_workspace_as_rospkg_does(tmp_path):
    """Metapackages are not found, rosbuild manifest.xml packages are, CATKIN_IGNORE ends a
    branch (COLCON_IGNORE does not), symbolic links are followed."""
    src = tmp_path / "ws" / "src"
    xml = '<package format="2"><name>{}</name><version>0.0.0</version>{}</package>'
    for rel, name, extra in [("meta", "meta", "<export><metapackage/></export>"), ("plain", "plain", ""),
                             ("skipped/inner", "inner", ""), ("colcon_only", "colcon_only", ""),
                             ("../elsewhere/linked_pkg", "linked", "")]:
        (src / rel).mkdir(parents=True)
        (src / rel / "package.xml").write_text(xml.format(name, extra))
    (src / "skipped" / "CATKIN_IGNORE").write_text("")
    (src / "colcon_only" / "COLCON_IGNORE").write_text("")
    (src / "legacy").mkdir()
    (src / "legacy" / "manifest.xml").write_text("<package/>")
    (src / "link").symlink_to(tmp_path / "ws" / "elsewhere")
    jobs = []
    for name in ("meta", "plain", "inner", "colcon_only", "legacy", "linked"):
        f = src / "plain" / f"find_{name}.launch"
        f.write_text(f'<launch><param name="where" value="$(find {name})"/></launch>')
        jobs.append(dict(file=str(f), args={}, package_path=str(src)))
    pk = find_packages(str(src))
    for job, o in zip(jobs, _oracle(jobs)):
        lr = load_launch(job["file"], {}, packages=pk)
        assert (lr.error is None) == o["ok"], (job["file"], o, lr.error)
        if o["ok"]:
            assert param_diff(lr, o["values"]) == [], job["file"]
    assert set(pk) == {"plain", "colcon_only", "legacy", "linked"}


def test_an_undeclared_arg_given_on_the_command_line_loads():
    path = str(OWN_WS / "delta" / "launch" / "undeclared_cmdline.launch")
    args = {"bag_filename": "/data/run.bag"}
    (o,) = _oracle([dict(file=path, args=args, package_path=str(OWN_WS))])
    assert o["ok"]
    lr = load_launch(path, args, packages=find_packages(str(OWN_WS)))
    assert lr.error is None and param_diff(lr, o["values"]) == []


@pytest.mark.parametrize("args", [{}, {"serial": "false"}])
def test_an_unused_include_arg_error_names_them_all(args):
    path = str(OWN_WS / "delta" / "launch" / "unused_include_args.launch")
    (o,) = _oracle([dict(file=path, args=args, package_path=str(OWN_WS))])
    assert not o["ok"]
    lr = load_launch(path, args, packages=find_packages(str(OWN_WS)))
    assert lr.error == o["message"]
