"""Test-suite wide options and fixtures.

The default suite needs nothing outside the repository: its fixtures live in ``tests/data``
(and ``examples/``).  Tests that run over third-party material that cannot live in the
repository (the thesis's workspace, real robots' launch files, roslaunch's and the TVL
reference's own test files: ``shared/corpus`` on our machines) form the opt-in *corpus suite*:

* mark them ``@pytest.mark.corpus`` (a whole module: ``pytestmark = pytest.mark.corpus``);
* take the folder from the ``corpus_dir`` fixture (a :class:`pathlib.Path`), never from a path
  of their own;
* run them with ``--corpus=DIR``; without it they are *deselected*, not skipped, so that a
  fresh clone reports no skips for material it cannot have::

      .venv/bin/pytest --corpus=../shared/corpus              # the default suite + the corpus suite
      .venv/bin/pytest -m corpus --corpus=../shared/corpus    # the corpus suite alone

  Write ``--corpus=DIR`` with ``=``: pytest finds its configuration (pyproject.toml) from the
  paths on its command line before it reads this file's options, so in ``--corpus DIR`` it takes
  DIR for a test path, and from a folder outside the repository it finds no configuration and no
  ``--corpus`` option (pytest_configure below says so when it can).

A test parametrized over the corpus's files at collection time reads the folder with
:func:`corpus_option` (``None`` without ``--corpus``) in ``pytest_generate_tests``.  Corpus tests
on the large DIMACS/UVL models take that folder from the ``models_dir`` fixture (``--models=DIR``,
default: ``models`` beside the corpus folder, as in ``shared/``).

To keep it so, a test that is not marked ``corpus`` and opens or lists anything under
``../shared`` (the folder beside the repository on our machines) fails at once with
:class:`SharedFolderRead` (an audit hook; it sees this process only, not the programs a test
runs: CI's fresh-clone run covers those).

A test may skip only when an optional external program is absent (roslaunch, Neovim, Emacs,
Node.js); its reason says how to install it (``tests/testenv.py`` has the probes and reasons).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

# the counting service keeps compiled models on disk: the suite and the servers it starts use a
# folder of their own, not the user's cache (a test that needs an empty one sets its own)
if "TVL_LSP_CACHE_DIR" not in os.environ:
    import atexit
    import shutil
    import tempfile
    _CACHE = tempfile.mkdtemp(prefix="tvl-lsp-test-cache-")
    os.environ["TVL_LSP_CACHE_DIR"] = _CACHE
    atexit.register(shutil.rmtree, _CACHE, True)
# ... and the secret that seals its entries (not the user's ~/.config/tvl-lsp/cache.key)
if "TVL_LSP_CACHE_KEY_FILE" not in os.environ:
    import atexit
    import shutil
    import tempfile
    _KEYDIR = tempfile.mkdtemp(prefix="tvl-lsp-test-key-")
    os.environ["TVL_LSP_CACHE_KEY_FILE"] = os.path.join(_KEYDIR, "cache.key")
    atexit.register(shutil.rmtree, _KEYDIR, True)
_SHARED_PREFIXES = tuple(sorted({os.path.join(str(p), "") for p in
                                 (REPO.parent / "shared", (REPO.parent / "shared").resolve())}))
_guard_item: "pytest.Item | None" = None


class SharedFolderRead(RuntimeError):
    """A test outside the corpus suite read ../shared, which a fresh clone does not have."""


def _audit(event: str, args: tuple) -> None:
    if _guard_item is None or event not in ("open", "os.listdir", "os.scandir"):
        return
    path = args[0] if args else None
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if not isinstance(path, str):
        return
    full = os.path.join(os.path.abspath(path), "")
    if full.startswith(_SHARED_PREFIXES):
        item = _guard_item
        raise SharedFolderRead(f"{item.nodeid} reads {path}: ../shared is not there in a fresh clone; "
                               "write a fixture in tests/data, or mark the test @pytest.mark.corpus "
                               "and take the folder from the corpus_dir fixture")


sys.addaudithook(_audit)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem):
    global _guard_item
    _guard_item = None if item.get_closest_marker("corpus") else item
    try:
        return (yield)
    finally:
        _guard_item = None


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("tvl-lsp")
    group.addoption("--corpus", metavar="DIR", default=None,
                    help="also run the tests marked `corpus` over this folder (on our machines: "
                         "../shared/corpus); without it they are deselected")
    group.addoption("--models", metavar="DIR", default=None,
                    help="the large models some corpus tests use (default: `models` beside the "
                         "--corpus folder; on our machines ../shared/models)")


def pytest_configure(config: pytest.Config) -> None:
    # the `corpus` marker is declared in pyproject.toml
    value = config.getoption("corpus")
    if value is not None and config.rootpath != REPO:
        raise pytest.UsageError(f"pytest took its configuration from {config.rootpath}, not {REPO}: write "
                                f"--corpus={value} (with '='), else pytest takes the folder for a test path")
    if value is not None:
        path = Path(value).expanduser()
        if not path.is_dir():
            raise pytest.UsageError(f"--corpus {value}: no such folder")
        config.option.corpus = str(path.resolve())


def corpus_option(config: pytest.Config) -> Path | None:
    """The folder given with ``--corpus`` (absolute), or None."""
    value = config.getoption("corpus")
    return Path(value) if value else None


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    # a test that reads the corpus without the marker would fail on a fresh clone: refuse it
    unmarked = [item.nodeid for item in items if "corpus_dir" in getattr(item, "fixturenames", ())
                and item.get_closest_marker("corpus") is None]
    if unmarked:
        raise pytest.UsageError("these tests use corpus_dir without @pytest.mark.corpus: " + ", ".join(unmarked))
    if corpus_option(config) is not None:
        return
    kept, deselected = [], []
    for item in items:
        (deselected if item.get_closest_marker("corpus") else kept).append(item)
    if deselected:
        config.hook.pytest_deselected(items=deselected)
        items[:] = kept


def pytest_report_header(config: pytest.Config) -> str:
    corpus = corpus_option(config)
    return f"corpus: {corpus}" if corpus else "corpus: none (tests marked `corpus` deselected; --corpus=DIR runs them)"


@pytest.fixture(scope="session")
def corpus_dir(request: pytest.FixtureRequest) -> Path:
    """The corpus folder given with ``--corpus`` (absolute).  Only tests marked ``corpus`` may
    use it: they are the only ones that run with the folder there."""
    corpus = corpus_option(request.config)
    if corpus is None:  # unreachable: unmarked users are refused at collection, marked ones deselected
        pytest.fail("corpus_dir needs --corpus DIR")
    return corpus


@pytest.fixture(scope="session")
def models_dir(request: pytest.FixtureRequest, corpus_dir: Path) -> Path:
    """The folder of large models (``--models DIR``, default ``models`` beside the corpus)."""
    given = request.config.getoption("models")
    path = Path(given).expanduser().resolve() if given else corpus_dir.parent / "models"
    if not path.is_dir():
        pytest.skip(f"no models folder at {path}: give --models=DIR (on our machines ../shared/models)")
    return path


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty counting cache folder for the test, and no count in memory or on record."""
    from tvl_lsp.analysis.counting import service as S
    from tvl_lsp.project import models
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(tmp_path / "cache"))
    S.MEMORY.clear()
    S.forget_failures()
    models.clear()
    yield tmp_path / "cache"
    S.MEMORY.clear()
    S.forget_failures()
    models.clear()
