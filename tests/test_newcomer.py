"""A new user's first steps: the documented commands can be run as written, the package installs
(non-editable too) with its grammar, and its extras can be installed."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    tomllib = None

REPO = Path(__file__).resolve().parent.parent
DOCS = [REPO / "README.md", REPO / "bench" / "README.md", REPO / "CONTRIBUTING.md", REPO / "docs" / "testing.md"]


def _commands(path: Path) -> list[str]:
    """Shell commands of a Markdown file: lines of ```sh / ```console blocks, indented code lines
    and inline `code` spans."""
    text = path.read_text(encoding="utf-8")
    out: list[str] = []
    for block in re.findall(r"```(?:sh|console|bash)\n(.*?)```", text, re.S):
        out += [ln.removeprefix("$ ").strip() for ln in block.splitlines() if ln.strip()]
    out += [ln.strip() for ln in text.splitlines() if ln.startswith("    ") and not ln.startswith("     ")]
    out += re.findall(r"`([^`\n]+)`", text)
    return out


def _project_table() -> dict:
    text = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    if tomllib is not None:
        return tomllib.loads(text)["project"]
    # Python 3.10 has no tomllib: the two tables this test reads, by hand
    deps = re.search(r"^dependencies = \[(.*?)^\]", text, re.S | re.M).group(1)
    extras = re.search(r"^\[project\.optional-dependencies\]\n(.*?)(?=^\[)", text, re.S | re.M).group(1)
    return {"dependencies": re.findall(r'"([^"]+)"', deps),
            "optional-dependencies": {m.group(1): re.findall(r'"([^"]+)"', m.group(2))
                                      for m in re.finditer(r"^([\w-]+) = \[(.*?)\]", extras, re.S | re.M)}}


def test_no_extra_requires_flamapy():
    """flamapy 2.6 pins python-sat 0.1.x and the project needs python-sat>=1.8, so an extra with
    flamapy (it was `bench`) makes `pip install -e '.[bench]'` fail with ResolutionImpossible;
    bench/README.md installs flamapy into its own venv instead."""
    project = _project_table()
    assert any(d.startswith("python-sat") for d in project["dependencies"])
    for extra, reqs in project.get("optional-dependencies", {}).items():
        assert not [r for r in reqs if r.lower().startswith("flamapy")], extra


def test_documented_venvs_use_python3():
    """A fresh Debian has `python3` but no `python`: the documented commands make venvs with it
    (the flamapy venv of bench/README.md said `python -m venv`)."""
    bad = [(p.name, c) for p in DOCS for c in _commands(p) if re.search(r"(^|&&\s*)python -m venv", c)]
    assert not bad, bad
    flamapy = [c for c in _commands(REPO / "bench" / "README.md") if "flamapy-venv/bin/pip install flamapy" in c]
    assert flamapy and all(c.startswith("python3 -m venv /tmp/flamapy-venv") for c in flamapy), flamapy


def test_documented_pytest_runs_from_the_venv():
    """The README installs pytest only into .venv: a bare `pytest ...` is not on a new user's PATH."""
    bad = [(p.name, c) for p in DOCS for c in _commands(p)
           if re.match(r"pytest\b", c) or re.search(r"&&\s*pytest\b", c)]
    assert not bad, bad


def test_bench_readme_scripts_exist():
    """Every `.venv/bin/python bench/X.py` in bench/README.md names a script of the repository."""
    scripts = {m for c in _commands(REPO / "bench" / "README.md") for m in re.findall(r"bench/[\w.]+\.py", c)}
    assert scripts
    assert all((REPO / s).is_file() for s in scripts), scripts


def test_non_editable_wheel_has_the_grammar_and_checks(tmp_path):
    """`pip install .` (not -e) builds a wheel: tvl_lsp/grammars is a symlink to ../grammars, and
    the grammar must be in the wheel for `tvl-lsp --check` to work from it."""
    # built with the venv's own setuptools (the test extra brings setuptools>=77): no package index
    try:
        from importlib.metadata import version
        if int(version("setuptools").split(".")[0]) < 77:
            pytest.skip("setuptools < 77 in this venv: .venv/bin/pip install -e '.[test]' brings a newer one")
    except Exception:
        pytest.skip("no setuptools in this venv: .venv/bin/pip install -e '.[test]' brings it")
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index",
                        "--disable-pip-version-check", "-q", "-w", str(tmp_path / "dist"), str(REPO)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    (wheel,) = (tmp_path / "dist").glob("tvl_lsp-*.whl")
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        assert "tvl_lsp/grammars/tvl.lark" in names, [n for n in names if "grammar" in n]
        assert "tvl_lsp/data/diagnostics.md" in names, "the diagnostics catalogue (--explain, hovers)"
        assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names), "the licence file"
        metadata = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
        assert "License-Expression: MIT" in metadata
        z.extractall(tmp_path / "site")
    env = dict(os.environ, PYTHONPATH=str(tmp_path / "site"))
    probe = ("import sys, tvl_lsp, tvl_lsp.main as c; assert tvl_lsp.__file__.startswith(sys.argv[1]), tvl_lsp.__file__;"
             " sys.argv = ['tvl-lsp', '--check', '-q', sys.argv[2]]; sys.exit(c.main())")
    r = subprocess.run([sys.executable, "-c", probe, str(tmp_path / "site"), str(REPO / "examples")],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "constant-condition" in r.stdout
    # --explain prints a code's whole page from the wheel's own catalogue (not the repository's)
    probe = ("import sys, tvl_lsp, tvl_lsp.main as c; assert tvl_lsp.__file__.startswith(sys.argv[1]), tvl_lsp.__file__;"
             " sys.exit(c.main(['--explain', 'missing-arg']))")
    r = subprocess.run([sys.executable, "-c", probe, str(tmp_path / "site")],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("## `missing-arg`") and "**Fix:**" in r.stdout and "```" in r.stdout, r.stdout
