"""Opt-in corpus suite (``--corpus=../shared/corpus``): conversions keep the product count on every
countable corpus model, and the UVL twins of the large DIMACS models count like them.

    .venv/bin/pytest -m corpus --corpus=../shared/corpus -k convert
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_lsp.analysis.convert import convert_model
from tvl_lsp.analysis.counting import CountTimeout
from tvl_lsp.analysis.dimacs import parse_dimacs
from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.analysis.formats import parse_any_model

pytestmark = pytest.mark.corpus

COUNT_BUDGET = 60.0


def _count(model, budget=COUNT_BUDGET):
    return ModelAnalysis(model).count(timeout=budget)


def _reparse(text: str, fmt: str):
    res = parse_any_model(text, f"/converted/out.{fmt}", read_file=lambda p: None)
    assert res.errors == [], [(str(d.span), d.message) for d in res.errors[:3]]
    return res.model


def test_every_countable_corpus_model_converts_with_its_count(corpus_dir: Path):
    checked, failures = [], []
    for path in sorted(corpus_dir.rglob("*.tvl")):
        res = parse_any_model(path.read_text(encoding="utf-8", errors="replace"), str(path))
        if res.errors or res.model.root is None:
            continue  # rejected models are not converted
        try:
            n = _count(res.model)
        except CountTimeout:
            continue  # not countable here within the budget
        rel = str(path.relative_to(corpus_dir))
        try:
            for fmt in ("uvl", "dimacs"):
                conv = convert_model(res.model, fmt)
                assert conv.exact, conv.notes
                m2 = _reparse(conv.text, fmt)
                assert _count(m2, 300) == n, f"{fmt}"
                if fmt == "uvl":  # and back
                    assert _count(_reparse(convert_model(m2, "tvl").text, "tvl"), 300) == n, "uvl->tvl"
        except AssertionError as ex:
            failures.append(f"{rel}: {ex}")
        checked.append(rel)
    assert failures == []
    assert len(checked) >= 40  # the thesis's, haros-tvl's and the reference's own models


SMALL_TWINS = ["busybox-1.18.0", "uclinux-distribution", "fiasco-2020"]


@pytest.mark.parametrize("name", SMALL_TWINS)
def test_uvl_twin_counts_like_its_dimacs_twin(models_dir: Path, name: str):
    upath, dpath = models_dir / "uvl" / f"{name}.uvl", models_dir / "dimacs" / f"{name}.dimacs"
    u = parse_any_model(upath.read_text(), str(upath))
    d = parse_any_model(dpath.read_text(), str(dpath))
    assert u.errors == [] and d.errors == []
    # the same variables (in another order)
    names = [f.name for f in u.model.features]
    assert len(set(names)) == len(names) and set(names) == {f.name for f in d.model.features[1:]}
    nu, nd = _count(u.model, 600), _count(d.model, 600)
    if name == "fiasco-2020":
        # the DIMACS export leaves the root variable out of every clause (it is neither forced
        # nor linked to its children): every product is counted twice, with and without it
        _, clauses, names, _ = parse_dimacs(dpath.read_text())
        assert names[1] == "__Root__" and not any(abs(x) == 1 for c in clauses for x in c)
        assert nd == 2 * nu
    else:
        assert nu == nd


def test_check_reports_the_dead_features_of_a_uvl_twin(models_dir: Path):
    from tvl_lsp.project.check import check_document
    path = models_dir / "uvl" / "busybox-1.18.0.uvl"
    out = check_document(str(path), timeout=120)
    dead = [d for d in out if d.code == "dead-feature"]
    assert len(dead) == 18 and all("Because:" in d.message for d in dead)
    # the same features as in the DIMACS twin
    dd = check_document(str(models_dir / "dimacs" / "busybox-1.18.0.dimacs"), timeout=120)
    assert sorted(d.data["feature"] for d in dead) == sorted(d.data["feature"] for d in dd if d.code == "dead-feature")
