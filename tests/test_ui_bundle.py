"""The configurator's web UI is built from editors/configurator into tvl_lsp/ui/static and
committed (pip install alone then serves it).  This test fails when the committed bundle is
older than its sources: BUILD-INFO.json holds the hash of every input (computed as
editors/configurator/build.mjs computes it) and of every output.  CI also rebuilds it with
Node and compares byte for byte (``npm run check`` in scripts/ci_ui.sh)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SRC = REPO / "editors" / "configurator"
STATIC = REPO / "tvl_lsp" / "ui" / "static"


def _inputs() -> list[str]:
    files = [p.relative_to(SRC).as_posix() for p in (SRC / "src").rglob("*") if p.is_file()]
    files += ["build.mjs", "package.json", "package-lock.json"]
    return sorted(files)


def test_bundle_matches_its_sources():
    info = json.loads((STATIC / "BUILD-INFO.json").read_text())
    assert info["inputs"] == _inputs(), "sources added or removed: run `npm run build` in editors/configurator"
    h = hashlib.sha256()
    for rel in _inputs():
        h.update((rel + "\0").encode())
        h.update((SRC / rel).read_bytes().decode("utf-8").replace("\r\n", "\n").encode())
        h.update(b"\0")
    assert info["sources"] == h.hexdigest(), "tvl_lsp/ui/static is stale: run `npm run build` in editors/configurator"
    for name, digest in info["files"].items():
        assert hashlib.sha256((STATIC / name).read_bytes()).hexdigest() == digest, f"{name} edited by hand?"


def test_the_package_ships_the_bundle():
    assert '"ui/static/*"' in (REPO / "pyproject.toml").read_text()
    for name in ("index.html", "app.js", "app.css", "elk-worker.js", "THIRD-PARTY-NOTICES.txt"):
        assert (STATIC / name).is_file()
    assert "__TVL_TOKEN__" in (STATIC / "index.html").read_text()
