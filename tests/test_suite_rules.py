"""The rules of the test suite itself (tests/conftest.py): corpus tests are opt-in and
deselected (not skipped) without ``--corpus``; a test outside the corpus suite cannot read
``../shared``; the default suite's skips are only for absent optional programs."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO, SharedFolderRead

CONFTEST = (REPO / "tests" / "conftest.py").read_text()

SAMPLE = '''
import pytest

def test_plain():
    pass

@pytest.mark.corpus
def test_on_the_corpus(corpus_dir):
    assert (corpus_dir / "a.tvl").is_file()

@pytest.mark.parametrize("x", [1, pytest.param(2, marks=pytest.mark.corpus)])
def test_param(x):
    pass
'''


def _run(folder: Path, *args: str) -> subprocess.CompletedProcess:
    # no third-party plugins: the sample needs none, and they are most of pytest's start-up time
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", "-rs", *args],
                          cwd=folder, capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, PYTEST_DISABLE_PLUGIN_AUTOLOAD="1"))


@pytest.fixture
def suite(tmp_path: Path) -> Path:
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "conftest.py").write_text(CONFTEST)
    (tmp_path / "tests" / "test_sample.py").write_text(SAMPLE)
    (tmp_path / "corpus").mkdir()
    (tmp_path / "corpus" / "a.tvl").write_text("root R { }\n")
    return tmp_path


def test_corpus_tests_are_deselected_without_the_option(suite):
    r = _run(suite, "tests")
    assert r.returncode == 0, r.stdout + r.stderr
    assert re.search(r"\b2 passed, 2 deselected\b", r.stdout), r.stdout
    assert "skipped" not in r.stdout


def test_corpus_option_runs_them(suite):
    r = _run(suite, "tests", "--corpus", "corpus")
    assert r.returncode == 0, r.stdout + r.stderr
    assert re.search(r"\b4 passed\b", r.stdout) and "deselected" not in r.stdout, r.stdout
    r = _run(suite, "tests", "-m", "corpus", "--corpus", "corpus")
    assert re.search(r"\b2 passed, 2 deselected\b", r.stdout), r.stdout


def test_a_missing_corpus_folder_is_a_usage_error(suite):
    r = _run(suite, "tests", "--corpus", "nowhere")
    assert r.returncode == 4 and "--corpus nowhere: no such folder" in r.stderr, r.stdout + r.stderr


def test_corpus_dir_without_the_marker_is_refused(suite):
    (suite / "tests" / "test_sample.py").write_text("def test_sneaky(corpus_dir):\n    pass\n")
    r = _run(suite, "tests")
    assert r.returncode == 4 and "without @pytest.mark.corpus" in r.stderr, r.stdout + r.stderr


def test_reading_the_shared_folder_fails_the_test():
    with pytest.raises(SharedFolderRead, match="write a fixture in tests/data"):
        open(REPO.parent / "shared" / "corpus" / "README.md")
    with pytest.raises(SharedFolderRead):   # before the folder is even looked for
        os.listdir(REPO.parent / "shared")


def test_skip_reasons_say_how_to_install_the_program():
    """Every skip in the default suite names an optional program and how to get it (the corpus
    suite's modules may skip on what the corpus lacks)."""
    reasons = []
    for p in sorted((REPO / "tests").glob("test_*.py")):
        text = p.read_text()
        if re.search(r"^pytestmark = pytest\.mark\.corpus$", text, re.M):
            continue
        reasons += [(p.name, m) for m in re.findall(r"""\breason=([^\n]+)""", text)]
        reasons += [(p.name, m) for m in re.findall(r"""pytest\.skip\(([^\n]+)""", text)]
    assert reasons
    how = re.compile(r"apt-get install|pip install|npm ci|ci_editors\.sh|MISSING|--models")
    bad = [(f, r) for f, r in reasons if not how.search(r)]
    assert not bad, bad


def test_testing_doc_tells_the_size_of_the_default_suite_and_its_markers(request):
    """docs/testing.md says "about N tests" of the default suite and how to run each marker of
    pyproject.toml.  The size is compared (within 15 %) when this run collected the whole default
    suite; a run of a few files collects fewer and leaves it to the full run."""
    doc = (REPO / "docs" / "testing.md").read_text(encoding="utf-8")
    markers = re.findall(r'^\s*"(\w+):', (REPO / "pyproject.toml").read_text(encoding="utf-8"), re.M)
    assert {"slow", "fuzz", "vscode", "corpus"} <= set(markers), markers
    for name in markers:
        assert f"-m {name}" in doc, f"docs/testing.md does not say how to run the {name} tests"
    m = re.search(r"about ([\d,]+) tests", doc)
    assert m, "docs/testing.md does not say how many tests the default suite has"
    said = int(m.group(1).replace(",", ""))
    files = {Path(str(item.path)).name for item in request.session.items}
    every = {p.name for p in (REPO / "tests").glob("test_*.py")}
    if len(files) < 0.9 * len(every) or request.config.getoption("markexpr") != "not slow and not vscode and not fuzz":
        return  # not the whole default suite
    ran = len(request.session.items)
    assert abs(ran - said) <= 0.15 * ran, f"docs/testing.md says about {said} tests; the default suite has {ran}"
