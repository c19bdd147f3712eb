"""Shared pytest options.

``--corpus DIR``: the folder of the shared corpus (``corpus/`` beside the repository on our
machines).  Tests marked ``@pytest.mark.corpus`` get it from the ``corpus_dir`` fixture; without
``--corpus`` they are deselected (not skipped): the default suite never reads outside the
repository.
"""

from __future__ import annotations

from pathlib import Path

import pytest


def pytest_addoption(parser):
    parser.addoption("--corpus", action="store", default=None, metavar="DIR",
                     help="the shared corpus folder; enables the tests marked 'corpus'")


def pytest_collection_modifyitems(config, items):
    if config.getoption("--corpus"):
        return
    keep, drop = [], []
    for item in items:
        (drop if item.get_closest_marker("corpus") else keep).append(item)
    if drop:
        config.hook.pytest_deselected(items=drop)
        items[:] = keep


@pytest.fixture(scope="session")
def corpus_dir(request) -> Path:
    d = request.config.getoption("--corpus")
    if not d:
        pytest.skip("no --corpus DIR given")
    p = Path(d).resolve()
    if not p.is_dir():
        pytest.fail(f"--corpus {d}: not a folder")
    return p
