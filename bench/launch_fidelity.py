"""Differential harness: tvl-lsp against the real roslaunch on a whole ROS 1 workspace.

    .venv/bin/python bench/launch_fidelity.py WORKSPACE [--json OUT] [--jobs N] [--only SUBSTR] [--stub-missing]

For every launch file of WORKSPACE (``*.launch``, ``*.launch.xml``, and ``*.test`` / ``*.xml``
files whose root element is ``<launch>``) and several argument assignments, it runs

- the real roslaunch (Debian's python3-roslaunch, ``/usr/bin/python3``, with
  ``ROS_PACKAGE_PATH=WORKSPACE``; the programs of ``<param command=...>`` are not run, only looked
  up, and the parameter compares as "set");
- ``tvl-lsp launch FILE name:=value ... --json --workspace WORKSPACE`` (in-process);

and once ``tvl-lsp --check WORKSPACE`` (check_paths, as the CLI).  It reports:

- runs where roslaunch loads the file and ``tvl-lsp launch`` reports an error (must be 0);
- runs where both load: equal nodes, equal parameters (names AND values, the whole tree;
  ``textfile`` / ``binfile`` / ``command`` parameters compare by name only, as tvl-lsp shows them by
  path / command line), and exactly equal;
- runs where roslaunch fails and tvl-lsp loads (a missed error), apart from packages that are
  not in the workspace (ResourceNotFound);
- ``--check`` errors that are false: an error with a witness where roslaunch, run with the
  witness, loads the file; an error without a witness (it holds whatever the args) where
  roslaunch loads the file under one of the assignments;
- runs where both fail: counted, and those whose two messages name nothing in common listed
  (``both_fail_other_cause``: read them, they may fail for different reasons);
- files that roslaunch rejects with their defaults (not for a package missing from the
  workspace, nor one roslaunch finds outside it, under /usr or /opt; nor a generic launch file
  paired with a feature model, whose args its configurations set) where ``--check`` says
  nothing (no error, no warning).

With ``--stub-missing``, every package roslaunch cannot find gets an empty stub package (on
``ROS_PACKAGE_PATH`` after the workspace, for both tools; ``xacro`` with a stub ``xacro``
program), so that files using third-party packages load and their parameters compare.

Assignments per file: the defaults (no args); every top-level arg without a default set to
``true`` and every boolean default flipped; every arg without a default set to ``false``; with
``--strings``, string variants (one run per value an ``$(eval)`` of the file compares a string
arg with: ``arg('robot') == 'iron'``, ``{'iron': False}.get(arg('robot'), True)``, at most four);
and each ``--check`` witness.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import re
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ORACLE = ROOT / "tests" / "data" / "launch" / "roslaunch_oracle.py"
SYS_PY = "/usr/bin/python3"
SKIP_DIRS = {".git", "build", "devel", "install", "node_modules", "__pycache__"}
ANON = re.compile(r"_anon\d+|_\d+_\d+$")


def launch_files(ws: str) -> tuple[list[str], int]:
    """Launch files under ``ws`` and the number of other XML files (not launch files)."""
    out, skipped = [], 0
    for d, dirs, files in os.walk(ws):
        dirs[:] = sorted(x for x in dirs if x not in SKIP_DIRS and not x.startswith("."))
        for f in sorted(files):
            p = os.path.join(d, f)
            if f.endswith((".launch", ".launch.xml")):
                out.append(p)
            elif f.endswith((".test", ".xml")) and f != "package.xml":
                if _launch_root(p):
                    out.append(p)
                else:
                    skipped += 1
    return out, skipped


def _launch_root(p: str) -> bool:
    try:
        with open(p, "rb") as fh:
            head = fh.read(8192).decode("utf-8", "replace")
    except OSError:
        return False
    head = re.sub(r"<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>", "", head, flags=re.S).lstrip()
    return head.startswith("<launch") and (len(head) == 7 or not head[7].isalnum())


def top_args(path: str) -> list[tuple[str, str | None, bool]]:
    """(name, default, has value) of the file's top-level <arg>s."""
    from lxml import etree
    try:
        root = etree.parse(path, etree.XMLParser(resolve_entities=False, no_network=True)).getroot()
    except Exception:
        return []
    if root is None or root.tag != "launch":
        return []
    out = []
    for x in root:
        if x.tag == "arg" and "name" in x.attrib and "$" not in x.attrib["name"]:
            out.append((x.attrib["name"], x.attrib.get("default"), "value" in x.attrib))
    return out


def assignments(path: str, strings: bool = False) -> list[dict[str, str]]:
    args = [a for a in top_args(path) if not a[2]]
    a0: dict[str, str] = {}
    a1 = {}
    a2 = {}
    for name, default, _ in args:
        if default is None:
            a1[name] = "true"
            a2[name] = "false"
        elif default.strip().lower() in ("true", "false"):
            a1[name] = "false" if default.strip().lower() == "true" else "true"
    out = [a0]
    for a in (a1, a2):
        if a and a not in out:
            out.append(a)
    if strings:  # string variants: a value the file compares a string arg with
        defaults = {n: d for n, d, _ in args}
        for name, lit in string_variants(path, defaults)[:MAX_STRING_VARIANTS]:
            a = {name: lit}
            if a not in out:
                out.append(a)
    return out


MAX_STRING_VARIANTS = 4


def string_variants(path: str, defaults: dict) -> list[tuple[str, str]]:
    """(arg, value) pairs for the top-level args whose default is no boolean (or none): the
    string literals the file's $(eval)s compare the arg with (==, !=, in [...], a dict's keys
    in {...}.get(arg), a list's items in [...].index(arg)), other than the default, in order."""
    import ast
    try:
        text = Path(path).read_text(errors="replace")
    except OSError:
        return []
    cands = {n for n, d in defaults.items() if d is None or d.strip().lower() not in ("true", "false")}
    out: list[tuple[str, str]] = []

    def reads(n) -> str | None:
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "arg" and n.args and \
                isinstance(n.args[0], ast.Constant) and isinstance(n.args[0].value, str):
            return n.args[0].value
        if isinstance(n, ast.Name):
            return n.id
        return None

    def strs(n) -> list[str]:
        if isinstance(n, ast.Constant) and isinstance(n.value, str):
            return [n.value]
        if isinstance(n, (ast.List, ast.Tuple, ast.Set)):
            return [x.value for x in n.elts if isinstance(x, ast.Constant) and isinstance(x.value, str)]
        if isinstance(n, ast.Dict):
            return [k.value for k in n.keys if isinstance(k, ast.Constant) and isinstance(k.value, str)]
        return []

    for m in re.finditer(r"\$\(eval (.*?)\)[\"']", text):
        expr = m.group(1).replace("&quot;", '"').replace("&apos;", "'").replace("&lt;", "<").replace("&gt;", ">") \
            .replace("&amp;", "&")
        try:
            tree = ast.parse(expr.strip(), mode="eval")
        except (SyntaxError, ValueError, RecursionError, MemoryError):
            continue
        for n in ast.walk(tree):
            pairs = []
            if isinstance(n, ast.Compare):
                sides = [n.left] + list(n.comparators)
                for a in sides:
                    for b in sides:
                        if a is not b and reads(a):
                            pairs += [(reads(a), v) for v in strs(b)]
            elif isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr in ("get", "index") \
                    and n.args and reads(n.args[0]):
                pairs += [(reads(n.args[0]), v) for v in strs(n.func.value)]
            for name, v in pairs:
                if name in cands and v != (defaults.get(name) or "") and (name, v) not in out and v.strip():
                    out.append((name, v))
    return out


# ------------------------------------------------------------------ roslaunch

def make_stubs(ws: str, files: list[str], nproc: int, strings: bool = False,
               stub_files: bool = False) -> tuple[str, set[str]]:
    """Empty packages (a package.xml) for the packages roslaunch cannot find when it loads the
    files with their defaults, until no more are missing (a stub's files do not exist, so
    includes of them fail in both tools alike); ``xacro`` also gets a ``xacro`` program.  With
    ``stub_files``, the files the workspace names in them get stubs too (see ``stub_package_files``)."""
    import tempfile
    stub_dir = tempfile.mkdtemp(prefix="fidelity-stubs-")
    names: set[str] = set()
    for _ in range(4):
        jobs = [dict(file=f, args=a, package_path=ws + os.pathsep + stub_dir, commands="check")
                for f in files for a in assignments(f, strings)]
        missing = set()
        for r in oracle(jobs, nproc):
            if not r["ok"] and r["error"] == "ResourceNotFound":
                m = r["message"].split("\n")[0].strip()
                m = m.rsplit(": ", 1)[-1] if m.startswith("The following package") else m
                if re.fullmatch(r"[A-Za-z0-9_.-]+", m) and m not in names:
                    missing.add(m)
        if not missing:
            break
        for name in missing:
            d = Path(stub_dir) / name
            d.mkdir()
            (d / "package.xml").write_text(f'<package format="2"><name>{name}</name><version>0.0.0</version>'
                                           "<buildtool_depend>catkin</buildtool_depend></package>\n")
            if name == "xacro":
                (d / "xacro").write_text("#!/bin/sh\necho '<robot name=\"stub\"/>'\n")
                (d / "xacro").chmod(0o755)
        names |= missing
        if stub_files:
            stub_package_files(ws, files, stub_dir, names)
    return stub_dir, names


_FIND_FILE = re.compile(r"\$\(find ([A-Za-z0-9_.-]+)\)/([^\s\"'<>$]+)")


def stub_package_files(ws: str, files: list[str], stub_dir: str, names: set[str]) -> None:
    """In the stub packages, the files the workspace's launch files name there (``$(find pkg)/rel``
    without further substitutions): a launch file declaring, with an empty default, every arg
    an ``<include>`` of the workspace passes to it; a YAML file holding ``{}``; any other file
    empty.  Both tools then load what the workspace does with them (not what the real package
    would do: its nodes and parameters are not there, alike for both)."""
    from lxml import etree
    wanted: dict[Path, set[str]] = {}
    for f in files:
        try:
            text = Path(f).read_text(errors="replace")
        except OSError:
            continue
        for m in _FIND_FILE.finditer(text):
            pkg, rel = m.group(1), m.group(2)
            # (a name completed by a substitution, $(find p)/launch/$(arg x).launch, is not known)
            if pkg in names and ".." not in rel and "." in rel.rsplit("/", 1)[-1] and \
                    not text.startswith("$", m.end()):
                wanted.setdefault(Path(stub_dir) / pkg / rel, set())
        try:
            root = etree.fromstring(text.encode(), etree.XMLParser(resolve_entities=False, no_network=True,
                                                                 recover=True))
        except Exception:
            continue
        if root is None:
            continue
        for inc in root.iter("include"):
            m = _FIND_FILE.fullmatch(inc.get("file", "").strip())
            if m and m.group(1) in names and "." in m.group(2).rsplit("/", 1)[-1]:
                target = wanted.setdefault(Path(stub_dir) / m.group(1) / m.group(2), set())
                target.update(a.get("name") for a in inc if a.tag == "arg" and a.get("name")
                              and "$" not in a.get("name"))
    for path, args in sorted(wanted.items()):
        if path.exists() or not path.resolve().is_relative_to(Path(stub_dir).resolve()):
            continue
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if path.suffix in (".launch", ".xml", ".test"):
            path.write_text("<launch>\n" + "".join(f'  <arg name="{a}" default=""/>\n' for a in sorted(args))
                            + "</launch>\n")
        elif path.suffix in (".yaml", ".yml"):
            path.write_text("{}\n")
        else:
            path.write_text("")


def oracle(jobs: list[dict], nproc: int) -> list[dict]:
    if not jobs:
        return []
    chunks = [jobs[i::nproc] for i in range(nproc)]
    procs = []
    for ch in chunks:
        p = subprocess.Popen([SYS_PY, str(ORACLE)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, cwd="/tmp")
        procs.append(p)
    outs = []
    for p, ch in zip(procs, chunks):
        o, e = p.communicate(json.dumps(ch))
        if p.returncode != 0:
            raise SystemExit(f"oracle failed: {e[-2000:]}")
        outs.append(json.loads(o))
    res = [None] * len(jobs)
    for k, out in enumerate(outs):
        for i, r in enumerate(out):
            res[k + i * nproc] = r
    return res


# ------------------------------------------------------------------ tvl-lsp

def _tvl_launch(job: dict) -> dict:
    from tvl_lsp.cli.commands.launch import main as launch_main
    argv = [job["file"]] + [f"{k}:={v}" for k, v in sorted(job["args"].items())] + [
        "--json", "--workspace", job["ws"]]
    buf = io.StringIO()
    try:
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
            code = launch_main(argv)
        out = json.loads(buf.getvalue())
    except Exception as exc:  # a crash is an error
        return {"error": f"crash: {exc!r}", "error_code": "crash", "nodes": [], "params": {}}
    out["exit"] = code
    return out


def tvl_runs(jobs: list[dict], nproc: int) -> list[dict]:
    if nproc <= 1:
        return [_tvl_launch(j) for j in jobs]
    with ProcessPoolExecutor(nproc) as ex:
        return list(ex.map(_tvl_launch, jobs, chunksize=8))


def tvl_check(ws: str, nproc: int) -> list:
    from tvl_lsp.project.check import check_paths
    return check_paths([ws], jobs=nproc)


# ------------------------------------------------------------------ comparison

def _norm_nodes(names) -> list[str]:
    return sorted(ANON.sub("_ANON", n) for n in names)


def _eq(rl, tv) -> bool:
    if isinstance(rl, bool) or isinstance(tv, bool):
        return type(rl) is type(tv) and rl == tv
    if isinstance(rl, float) and isinstance(tv, (int, float)) and not isinstance(tv, bool):
        return rl == tv and isinstance(tv, float)
    if isinstance(rl, list) and isinstance(tv, list):
        return len(rl) == len(tv) and all(_eq(a, b) for a, b in zip(rl, tv))
    if isinstance(rl, dict) and isinstance(tv, dict):
        return rl.keys() == tv.keys() and all(_eq(rl[k], tv[k]) for k in rl)
    return type(rl) is type(tv) and rl == tv


_NAMES = re.compile(r"'([^']{2,})'|\[([^\]]{2,})\]|\"([^\"]{2,})\"")


_TVL_PREFIX = re.compile(r"^(\$\(eval\) failed: \w+: |ResourceNotFound: |in the included file [^:]*: )")


def same_cause(rl_message: str, tvl_message: str) -> bool:
    """Whether two error messages name something in common (an arg, a file, a value in quotes or
    brackets) -- a crude test that both tools fail for the same reason; the rest is read by hand."""
    def names(m: str) -> set[str]:
        out = set()
        for g in _NAMES.findall(m):
            for x in g:
                if x:
                    out.add(x.strip())
                    out.add(os.path.basename(x.strip()))
        return out - {"", "bool"}
    a, b = names(rl_message), names(tvl_message)
    flat = " ".join(rl_message.split())
    core = " ".join(_TVL_PREFIX.sub("", tvl_message.strip()).split())[:60]
    return bool(a & b) or " ".join(tvl_message.split()) in flat or (len(core) > 3 and core in flat)


def _legacy_eq(rl, s) -> bool:
    """tvl-lsp before typed values printed every value as a string."""
    import yaml
    if isinstance(rl, str):
        return rl == s
    try:
        return _eq(rl, yaml.safe_load(s))
    except Exception:
        return str(rl) == s


def compare_params(rl: dict, tv: dict, sources: dict | None) -> tuple[bool, bool, list]:
    """(equal modulo textfile/command, exactly equal, differences)."""
    diffs = []
    if set(rl) != set(tv):
        for k in sorted(set(rl) ^ set(tv)):
            diffs.append((k, rl.get(k, "<absent>"), tv.get(k, "<absent>")))
        return False, False, diffs[:6]
    exact = True
    for k in sorted(rl):
        a, b = rl[k], tv[k]
        src = (sources or {}).get(k)
        if src in ("textfile", "binfile", "command") or (
                sources is None and isinstance(a, (str, dict)) and isinstance(b, str)
                and (b.startswith("$(command") or os.path.isabs(b))):
            if not _eq(a, b):
                exact = False
            continue
        if isinstance(a, dict) and "__binary__" in a:
            continue
        ok = _eq(a, b) if sources is not None else _legacy_eq(a, b)
        if not ok:
            diffs.append((k, a, b))
    return not diffs, exact and not diffs, diffs[:6]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("workspace")
    ap.add_argument("--json", help="write every finding to this file")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", help="only files whose path contains this")
    ap.add_argument("--no-check", action="store_true", help="skip tvl-lsp --check")
    ap.add_argument("--fake-commands", default="", metavar="PROG,...",
                    help="programs to treat as installed (stub executables put first on PATH for both "
                         "roslaunch and tvl-lsp), e.g. xacro: more files load, more parameters compare")
    ap.add_argument("--stub-missing", action="store_true",
                    help="give every package that roslaunch cannot find an empty stub package (outside the "
                         "workspace, on ROS_PACKAGE_PATH for both tools; xacro with a stub 'xacro' program): "
                         "files that include or $(find) third-party packages then load, and their parameters "
                         "compare")
    ap.add_argument("--stub-files", action="store_true",
                    help="with --stub-missing: also stub the files the workspace names in stub packages (launch "
                         "files declaring the args passed to them, empty YAML), so that more runs load in both")
    ap.add_argument("--strings", action="store_true",
                    help="also run string variants: each string arg set to a value the file compares it with")
    ap.add_argument("-v", "--verbose", action="store_true")
    ns = ap.parse_args()
    if ns.fake_commands:
        import tempfile
        stub_dir = tempfile.mkdtemp(prefix="fidelity-bin-")
        for prog in ns.fake_commands.split(","):
            p = Path(stub_dir) / prog.strip()
            p.write_text("#!/bin/sh\necho '<robot name=\"stub\"/>'\n")
            p.chmod(0o755)
        os.environ["PATH"] = stub_dir + os.pathsep + os.environ.get("PATH", "")
    if not os.path.exists(SYS_PY) or subprocess.run([SYS_PY, "-c", "import roslaunch"],
                                                     capture_output=True).returncode:
        print("the real roslaunch is needed: apt-get install python3-roslaunch", file=sys.stderr)
        return 2
    sys.path.insert(0, str(ROOT))
    ws = os.path.abspath(ns.workspace)
    t0 = time.time()
    files, skipped_xml = launch_files(ws)
    if ns.only:
        files = [f for f in files if ns.only in f]
    print(f"workspace {ws}: {len(files)} launch files ({sum(f.endswith(('.test', '.xml')) for f in files)} "
          f".test/.xml), {skipped_xml} other XML files")

    pkg_path = ws
    stub_dir = None
    if ns.stub_missing:
        stub_dir, names = make_stubs(ws, files, ns.jobs, ns.strings, ns.stub_files)
        pkg_path = ws + os.pathsep + stub_dir
        os.environ["ROS_PACKAGE_PATH"] = stub_dir  # tvl-lsp launch: after the workspace, as rospack
        print(f"stub packages for {len(names)} packages missing from the workspace: {' '.join(sorted(names)[:30])}"
              f"{' ...' if len(names) > 30 else ''}")

    # --check first: its witnesses become assignments too
    check_errors: dict[str, list] = {}
    check_warn_files: set[str] = set()
    check_files = None
    if not ns.no_check:
        diags = tvl_check(ws, ns.jobs)
        for d in diags:
            if d.severity == 1:
                check_errors.setdefault(d.path, []).append(d)
            if d.severity in (1, 2):
                check_warn_files.add(d.path)
        from tvl_lsp.project.workspace import discover_files
        check_files = set(discover_files([ws]).launches)
        print(f"--check: {len(diags)} diagnostics, {sum(map(len, check_errors.values()))} errors "
              f"({time.time() - t0:.0f}s)")

    jobs, meta = [], []
    for f in files:
        for i, a in enumerate(assignments(f, ns.strings)):
            jobs.append(dict(file=f, args=a, package_path=pkg_path, commands="check", ws=ws))
            meta.append((f, "assign", i))
        for k, d in enumerate(check_errors.get(f, [])):
            if d.witness:
                a = {x: ("true" if v else "false") if isinstance(v, bool) else str(v) for x, v in d.witness.items()}
                jobs.append(dict(file=f, args=a, package_path=pkg_path, commands="check", ws=ws))
                meta.append((f, "witness", k))
    rl = oracle([{k: v for k, v in j.items() if k != "ws"} for j in jobs], ns.jobs)
    print(f"roslaunch: {len(jobs)} runs ({time.time() - t0:.0f}s)")
    tv = tvl_runs(jobs, ns.jobs)
    print(f"tvl-lsp launch: {len(jobs)} runs ({time.time() - t0:.0f}s)")

    stats = dict(runs=0, both_ok=0, rl_ok_tvl_error=0, rl_fail_tvl_ok=0, rl_fail_tvl_ok_pkg=0,
                 nodes_equal=0, params_equal=0, params_exact=0, paired_default_fail=0, both_fail=0)
    findings = {"false_error_runs": [], "missed_runs": [], "node_diffs": [], "param_diffs": [],
                "both_fail_other_cause": [],
                "check_false_errors": [], "check_silent": [], "check_unverified": []}
    ok_by_file: dict[str, list] = {}
    default_result: dict[str, dict] = {}
    for (f, kind, i), job, r, t in zip(meta, jobs, rl, tv):
        rel = os.path.relpath(f, ws)
        if kind == "witness":
            d = check_errors[f][i]
            if r["ok"]:
                findings["check_false_errors"].append(dict(file=rel, line=d.span.start.line + 1, code=d.code,
                                                           message=d.message[:300], witness=job["args"]))
            continue
        stats["runs"] += 1
        if i == 0:
            default_result[f] = r
        if r["ok"]:
            ok_by_file.setdefault(f, []).append(job["args"])
        terr = t.get("error")
        if r["ok"] and terr:
            stats["rl_ok_tvl_error"] += 1
            findings["false_error_runs"].append(dict(file=rel, args=job["args"], tvl=terr[:300],
                                                     code=t.get("error_code")))
        elif not r["ok"] and terr:
            stats["both_fail"] += 1
            if not same_cause(r["message"], terr):
                findings["both_fail_other_cause"].append(dict(file=rel, args=job["args"], roslaunch=r["message"][:300],
                                                              tvl=terr[:300], code=t.get("error_code")))
        elif not r["ok"] and not terr:
            if r["error"] == "ResourceNotFound":
                stats["rl_fail_tvl_ok_pkg"] += 1
            else:
                stats["rl_fail_tvl_ok"] += 1
                findings["missed_runs"].append(dict(file=rel, args=job["args"], roslaunch=r["message"][:300]))
        elif r["ok"] and not terr:
            stats["both_ok"] += 1
            tn = _norm_nodes(n["name"] for n in t["nodes"])
            if tn == _norm_nodes(r["nodes"]):
                stats["nodes_equal"] += 1
            else:
                findings["node_diffs"].append(dict(file=rel, args=job["args"], roslaunch=_norm_nodes(r["nodes"]),
                                                   tvl=tn))
            eq, exact, diffs = compare_params(r["values"], t.get("params", {}), t.get("param_sources"))
            stats["params_equal"] += eq
            stats["params_exact"] += exact
            if not eq:
                findings["param_diffs"].append(dict(file=rel, args=job["args"], diffs=[list(map(str, d))[:3]
                                                                                         for d in diffs]))
    if not ns.no_check:
        for f, errs in check_errors.items():
            for d in errs:
                if d.witness:
                    continue
                rel = os.path.relpath(f, ws)
                if ok_by_file.get(f):
                    findings["check_false_errors"].append(dict(file=rel, line=d.span.start.line + 1, code=d.code,
                                                               message=d.message[:300], witness=None,
                                                               loads_with=ok_by_file[f][0]))
        from tvl_lsp.project.workspace import load_workspace
        wsp = load_workspace([ws])
        for f, r in default_result.items():
            if r["ok"] or r["error"] == "ResourceNotFound":
                continue
            if re.search(r"(?<![\w/])/(usr|opt)/", r["message"]) or (stub_dir and stub_dir in r["message"]):
                continue  # a package outside the workspace found by roslaunch on this machine (or a stub)
            if any(p.model for p in wsp.pair(f)[0]):
                # a generic launch file paired with a feature model: its args are the model's
                # features, which its configurations set (the file is not run with its defaults)
                stats["paired_default_fail"] += 1
                continue
            if f not in check_warn_files:
                findings["check_silent"].append(dict(file=os.path.relpath(f, ws), roslaunch=r["message"][:300],
                                                     checked=f in check_files))
    print()
    print(f"runs (file x assignment): {stats['runs']}")
    print(f"  roslaunch loads, tvl-lsp errors:     {stats['rl_ok_tvl_error']}")
    print(f"  roslaunch fails, tvl-lsp loads:      {stats['rl_fail_tvl_ok']} "
          f"(+{stats['rl_fail_tvl_ok_pkg']} packages outside the workspace)")
    print(f"  both fail:                           {stats['both_fail']} "
          f"({len(findings['both_fail_other_cause'])} naming nothing in common: read them)")
    print(f"  both load:                           {stats['both_ok']}")
    print(f"    same nodes:                        {stats['nodes_equal']}")
    print(f"    same params (textfile/command by name): {stats['params_equal']}")
    print(f"    same params exactly:               {stats['params_exact']}")
    print(f"--check false errors:                  {len(findings['check_false_errors'])} "
          f"({len({(x['file'], x['code'], x['line']) for x in findings['check_false_errors']})} distinct)")
    print(f"--check silent on a file roslaunch rejects with its defaults: {len(findings['check_silent'])} "
          f"(+{stats['paired_default_fail']} generic launch files paired with a model, not counted)")
    if check_files is not None:
        print(f"--check launch files found: {len(check_files)} of {len(files)}")
    print(f"({time.time() - t0:.0f}s)")
    if ns.verbose:
        for k, v in findings.items():
            if v:
                print(f"\n== {k} ({len(v)})")
                for x in v[:40]:
                    print("  ", json.dumps(x)[:600])
    if ns.json:
        Path(ns.json).write_text(json.dumps(dict(workspace=ws, stats=stats, findings=findings), indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
