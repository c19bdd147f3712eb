"""Model facts kept on disk by content (tvl_lsp.project.factstore, issue #15): read back exactly,
keyed by every text the parse read (an edit is never answered with the old counts), and a
damaged, foreign or inconsistent file is ignored and removed -- never a crash, never a wrong
count."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tvl_lsp.analysis.counting import cache as C
from tvl_lsp.analysis.counting import service as S
from tvl_lsp.project import facts as F
from tvl_lsp.project import factstore, models

REPO = Path(__file__).resolve().parents[1]
ROBOT = REPO / "tests" / "data" / "uvl" / "robot.uvl"
CARDS = REPO / "tests" / "data" / "counting" / "cards.tvl"


@pytest.fixture
def cache(fresh_cache):
    return fresh_cache


def _src(path: Path, text: str | None = None) -> dict[str, str]:
    return {str(path): path.read_text() if text is None else text}


def _same(a: F.ModelFacts, b: F.ModelFacts) -> bool:
    return (a.total, a.per_feature, a.core, a.dead, a.false_optional) == \
        (b.total, b.per_feature, b.core, b.dead, b.false_optional)


@pytest.mark.parametrize("path", [ROBOT, CARDS])
def test_computed_facts_are_stored_and_read_back_exactly(cache, path):
    src = _src(path)
    assert F.stored_model_facts(str(path), src) is None
    computed = F.compute_model_facts(str(path), src, 30.0)
    assert computed.error is None and computed.total
    stored = F.stored_model_facts(str(path), src)
    assert stored is not None and _same(stored, computed)
    assert list(stored.per_feature) == list(computed.per_feature)  # the same order too
    files = sorted(p.name for p in cache.iterdir())
    assert any(n.endswith(".facts") for n in files)
    assert not any(n.endswith((".tmp", ".part", ".ctmp")) or n.startswith(".") for n in files)


def test_an_edit_or_an_include_edit_is_a_new_content(cache, tmp_path):
    src = _src(ROBOT)
    F.compute_model_facts(str(ROBOT), src, 30.0)
    text = src[str(ROBOT)]
    assert F.stored_model_facts(str(ROBOT), {str(ROBOT): text + "\n"}) is None  # layout only: a miss
    assert F.stored_model_facts(str(ROBOT), {str(ROBOT): text.replace("Arm", "Arms")}) is None
    assert F.stored_model_facts(str(tmp_path / "robot.uvl"), src | {str(tmp_path / "robot.uvl"): text}) is None
    inc = {str(ROBOT): text, "/w/inc.uvl": "a"}
    assert factstore.key(str(ROBOT), inc) != factstore.key(str(ROBOT), inc | {"/w/inc.uvl": "b"})
    assert factstore.key(str(ROBOT), inc) != factstore.key(str(ROBOT), src)
    assert factstore.key(str(ROBOT), inc) == factstore.key(str(ROBOT), dict(reversed(list(inc.items()))))


def test_incomplete_facts_are_not_stored(cache, monkeypatch):
    real = S.CNFCounter.feature_counts

    def partial(self, *a, **k):
        r = real(self, *a, **k)
        r.complete = False
        return r
    monkeypatch.setattr(S.CNFCounter, "feature_counts", partial)
    F.compute_model_facts(str(ROBOT), _src(ROBOT), 30.0)
    assert not list(cache.glob("*.facts"))


def _stored_file(cache: Path) -> Path:
    (f,) = cache.glob("*.facts")
    return f


def _rewrite(f: Path, change, reseal: bool = True) -> None:
    """Change the payload and recompute a matching checksum; ``reseal``: and the cache's seal
    (which needs the secret: a file that is sound as a file, yet says something impossible),
    else the seal is left as it was (a forger without the secret)."""
    seal, inner = f.read_bytes().split(b"\n", 1)
    head, payload = inner.split(b"\n", 1)
    plain = json.loads(payload)
    change(plain)
    payload = json.dumps(plain).encode()
    h = json.loads(head)
    import hashlib
    h["size"], h["sha256"] = len(payload), hashlib.sha256(payload).hexdigest()
    inner = json.dumps(h).encode() + b"\n" + payload
    f.write_bytes(C.seal(f.name, inner) if reseal else seal + b"\n" + inner)


DAMAGES = {
    "empty": lambda f: f.write_bytes(b""),
    "garbage": lambda f: f.write_bytes(os.urandom(3000)),
    "truncated": lambda f: f.write_bytes(f.read_bytes()[:-7]),
    "a count changed, checksum stale": lambda f: f.write_bytes(f.read_bytes().replace(b'"total":"', b'"total":"1', 1)),
    "count above the total": lambda f: _rewrite(f, lambda p: p["per_feature"][0].__setitem__(1, "ffffffff")),
    "negative count": lambda f: _rewrite(f, lambda p: p["per_feature"][0].__setitem__(1, "-1")),
    "not hexadecimal": lambda f: _rewrite(f, lambda p: p.__setitem__("total", "12 ")),
    "wrong types": lambda f: _rewrite(f, lambda p: p.__setitem__("core", {"a": 1})),
    "forged, checksum recomputed, not sealed": lambda f: _rewrite(
        f, lambda p: p.__setitem__("total", format(int(p["total"], 16) + 1, "x")), reseal=False),
    "unsealed, as the previous version wrote it": lambda f: f.write_bytes(f.read_bytes().split(b"\n", 1)[1]),
    "other format": lambda f: f.write_bytes(f.read_bytes().replace(factstore.FORMAT.encode(), b"tvl-lsp-facts-0")),
    "json list": lambda f: f.write_bytes(b"[1, 2, 3]\n[]"),
}


@pytest.mark.parametrize("damage", sorted(DAMAGES))
def test_a_damaged_file_is_ignored_removed_and_counted_again(cache, damage):
    src = _src(ROBOT)
    computed = F.compute_model_facts(str(ROBOT), src, 30.0)
    f = _stored_file(cache)
    DAMAGES[damage](f)
    assert F.stored_model_facts(str(ROBOT), src) is None
    assert not f.exists()  # removed: the next count stores a sound one
    models.clear()
    again = F.compute_model_facts(str(ROBOT), src, 30.0)
    assert _same(again, computed)
    assert _same(F.stored_model_facts(str(ROBOT), src), computed)


def test_a_foreign_file_under_this_name_is_ignored(cache):
    """Another model's sound file copied under this model's name (its key says otherwise)."""
    rsrc, csrc = _src(ROBOT), _src(CARDS)
    F.compute_model_facts(str(ROBOT), rsrc, 30.0)
    mine = _stored_file(cache)
    F.compute_model_facts(str(CARDS), csrc, 30.0)
    (theirs,) = set(cache.glob("*.facts")) - {mine}
    mine.write_bytes(theirs.read_bytes())
    assert F.stored_model_facts(str(ROBOT), rsrc) is None
    assert F.stored_model_facts(str(CARDS), csrc) is not None


def test_unreadable_cache_folder_is_a_miss(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", str(blocker / "cache"))
    models.clear()
    f = F.compute_model_facts(str(ROBOT), _src(ROBOT), 30.0)  # storing fails quietly
    assert f.error is None and f.total
    assert F.stored_model_facts(str(ROBOT), _src(ROBOT)) is None
    monkeypatch.setenv("TVL_LSP_CACHE_DIR", "")  # the disk cache disabled
    assert F.stored_model_facts(str(ROBOT), _src(ROBOT)) is None
    models.clear()


def test_counts_beyond_the_int_string_limit_round_trip():
    big = 3 ** 20000  # 9,543 decimal digits: json's int conversion refuses more than 4,300
    fields = {"total": big, "per_feature": {"A": big, "B": big // 3, "C": 0}, "core": {"A"}, "dead": {"C"},
              "false_optional": set(), "hover": None}
    data = factstore.encode("k", fields)
    assert factstore.decode("k", data) == fields
    assert factstore.decode("other", data) is None


def test_blobs_are_bounded_with_the_rest_of_the_cache(tmp_path):
    d = C.DiskCache(tmp_path, limit=10_000)
    for i in range(5):
        assert d.put_blob(f"b{i}.facts", bytes(4000)) is not None
    assert sum(p.stat().st_size for p in tmp_path.iterdir()) <= 10_000
    assert d.get_blob("b4.facts") == bytes(4000)
    assert d.put_blob("../escape", b"x") is None and d.get_blob("../escape") is None
    assert d.put_blob(".hidden", b"x") is None


def test_the_worker_initializer_imports_nothing_heavy():
    """A worker process imports its initializer's module at the server's priority, before
    the initializer renices it: that module must not pull lsprotocol / pygls in."""
    code = ("import sys; import tvl_lsp.lsp.procinit as p; "
            "print(sorted(m for m in ('lsprotocol', 'pygls', 'tvl_lsp.analysis') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=dict(os.environ, PYTHONPATH=str(REPO)))
    assert out.stdout.strip() == "[]", out.stdout
    from tvl_lsp.lsp import procinit, workers
    assert workers._worker_init is procinit._worker_init


# ------------------------------------------------------------------ the hover before the parse

EXAMPLE = REPO / "examples" / "ws" / "src" / "turtlerand" / "launch" / "generic.tvl"
IMPORTS = REPO / "tests" / "data" / "uvl" / "imports" / "main.uvl"


@pytest.mark.parametrize("path", [ROBOT, CARDS, EXAMPLE])
def test_stored_hover_rows_say_what_the_parsed_hover_says(cache, path):
    """Every feature declaration of a self-contained model: the stored hover (answered before
    the server parses) is the hover the parse gives, at every position of the name."""
    from tvl_lsp.base.text import Pos
    src = _src(path)
    computed = F.compute_model_facts(str(path), src, 30.0)
    stored = F.stored_model_facts(str(path), src)
    assert stored.hover, "no hover rows stored"
    model = models.load(str(path), src[str(path)], src.get)[0].model
    declared = {(f, s) for f in model.features for p, s in f.decl_spans if p == str(path)}
    assert len(stored.hover) == len(declared)
    for r in stored.hover:
        for line, col in ((r[0], r[1]), (r[2], r[3]), (r[0], (r[1] + r[3]) // 2)):
            target, span = F.name_at(model, str(path), Pos(line, col))
            assert F.hover_at(stored.hover, Pos(line, col)) == (F.feature_markdown(target, computed), span)
    assert F.hover_at(stored.hover, Pos(10_000, 0)) is None


def test_no_hover_rows_for_a_model_that_reads_other_files_or_has_errors(cache):
    src = {str(IMPORTS): IMPORTS.read_text()}
    for p in sorted((IMPORTS.parent).rglob("*.uvl")):
        src[str(p)] = p.read_text()
    f = F.compute_model_facts(str(IMPORTS), src, 30.0)
    assert f.error is None and f.total
    stored = F.stored_model_facts(str(IMPORTS), src)
    assert stored is not None and stored.hover is None
    # its text alone is not the model: nothing stored under the text alone
    assert F.stored_model_facts(str(IMPORTS), {str(IMPORTS): src[str(IMPORTS)]}) is None
    broken = ROBOT.read_text() + "\n\tArm =>\n"
    models.clear()
    f = F.compute_model_facts(str(ROBOT), {str(ROBOT): broken}, 30.0)
    stored = F.stored_model_facts(str(ROBOT), {str(ROBOT): broken})
    assert stored is None or stored.hover is None
