"""Mutational fuzzing of the check pipeline (issue 12): TVL, UVL, launch XML (ROS 1 and 2) and
rosparam YAML texts, mutated grammar-aware (tokens of the language spliced in, pieces deleted
or repeated, hostile characters inserted), through the same function ``--check`` and the
editor use (``check_document``).

Every run must end without an exception, without an ``internal-error``, and with every
diagnostic's range inside the text.  The default run is derandomized (a fixed seed, a few
hundred cases in all); ``-m fuzz`` runs the long campaign (``TVL_LSP_FUZZ_EXAMPLES``, default
2,000 per format, a random seed).  A defect found becomes a regression file in
``tests/data/hostile``.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from tvl_lsp.base.text import LineIndex
from tvl_lsp.project.check import check_document

HERE = Path(__file__).resolve().parent
SEEDS = {
    "tvl": [HERE / "data" / "ws" / "src" / "scout" / "launch" / "generic.tvl",
            HERE / "data" / "hostile" / "ws" / "src" / "hostile" / "models" / "include_device.tvl"],
    "launch": [HERE / "data" / "ws" / "src" / "scout" / "launch" / "generic.launch",
               HERE / "data" / "hostile" / "ws" / "src" / "hostile" / "launch" / "include_special.launch"],
    "yaml": [],
}
TOKENS = {
    "tvl": ["root", "group", "allOf", "oneOf", "someOf", "opt", "shared", "include(", "int", "real", "bool", "enum",
            "in", "[", "]", "{", "}", "(", ")", ";", ",", "&&", "||", "!", "->", "<->", "==", "is", "ifIn:",
            "ifOut:", "sum(", "parent.", "this.", "..", "*", "/*", "\"", "[1..*]", "0", "99999999999999999999"],
    "launch": ["<launch>", "</launch>", "<node ", "<group ", "<include ", "<arg ", "<param ", "<rosparam>",
               "</rosparam>", "<remap ", "/>", ">", "<", "if=\"", "unless=\"", "name=\"", "ns=\"", "file=\"",
               "$(arg ", "$(eval ", "$(find ", "$(var ", ")", "\"", "&amp;", "&#xD800;", "&#0;", "<!--",
               "-->", "<!DOCTYPE x [<!ENTITY a \"b\">]>", "pass_all_args=\"true\"", "subst_value=\"true\"",
               "textfile=\"/dev/zero\"", "**", "*10**9"],
    "yaml": ["&a", "*a", "[", "]", "{", "}", ":", "- ", "!degrees ", "!radians ", "deg(", "rad(", "\n  ",
             "'", "\"", "$(arg x)", "!!binary", "? ", "|", ">"],
}
HOSTILE_CHARS = ["\ud800", "\udfff", "\x00", "\ufeff", "\u202e", "\r", "\t", "\U0001F916", "\\"]
EXAMPLES = int(os.environ.get("TVL_LSP_FUZZ_EXAMPLES", "2000"))

ROSPARAM = """<launch>
  <arg name="x" default="1.0"/>
  <rosparam subst_value="true">
limits: {min: !degrees -90, max: rad(pi/2), gain: $(arg x)}
list: &a [1, 2, 3]
again: *a
  </rosparam>
</launch>
"""


@st.composite
def mutated(draw, kind: str) -> str:
    seeds = [p.read_text(encoding="utf-8") for p in SEEDS[kind]] + ([ROSPARAM] if kind in ("launch", "yaml") else [])
    text = draw(st.sampled_from(seeds))
    for _ in range(draw(st.integers(1, 6))):
        n = len(text)
        i = draw(st.integers(0, n))
        op = draw(st.sampled_from(["token", "delete", "repeat", "char", "swap"]))
        if op == "token":
            text = text[:i] + draw(st.sampled_from(TOKENS[kind])) + text[i:]
        elif op == "delete" and n:
            j = draw(st.integers(i, min(n, i + 40)))
            text = text[:i] + text[j:]
        elif op == "repeat" and n:
            j = draw(st.integers(i, min(n, i + 60)))
            text = text[:i] + text[i:j] * draw(st.integers(2, 50)) + text[j:]
        elif op == "char":
            text = text[:i] + draw(st.sampled_from(HOSTILE_CHARS)) + text[i:]
        elif op == "swap" and n > 2:
            j = draw(st.integers(0, n - 1))
            a, b = sorted((i % n, j))
            text = text[:a] + text[b:b + 10] + text[a + 10:b] + text[a:a + 10] + text[b + 10:]
    return text


@pytest.fixture(scope="module")
def ws(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("fuzz") / "ws"
    shutil.copytree(HERE / "data" / "ws", root)
    return root


def _check(ws: Path, rel: str, text: str) -> None:
    path = str(ws / rel)
    diags = check_document(path, text, roots=[str(ws)], timeout=2.0, cpu_budget=20.0)
    idx = LineIndex(text)
    nlines = len(idx.starts)
    for d in diags:
        assert d.code != "internal-error", (d.message, text[:2000])
        if d.path == path:
            s, e = d.span.start, d.span.end
            assert 0 <= s.line < nlines and 0 <= e.line < nlines and (s.line, s.col) <= (e.line, e.col), \
                (d.code, d.span, text[:500])
            assert s.col <= len(idx.line_text(s.line)) + 1 and e.col <= len(idx.line_text(e.line)) + 1, \
                (d.code, d.span)


def _campaign(long: bool):
    return settings(max_examples=EXAMPLES if long else 70, derandomize=not long, deadline=None,
                    suppress_health_check=list(HealthCheck), database=None)


CASES = [("tvl", "src/scout/launch/generic.tvl"),
         ("launch", "src/scout/launch/generic.launch"),
         ("launch", "src/scout/launch/fuzz2.launch.xml"),
         ("yaml", "src/scout/launch/rosparam.launch")]


def _fuzz(ws: Path, kind: str, rel: str, long: bool) -> None:
    @_campaign(long)
    @given(mutated(kind))
    def run(text):
        _check(ws, rel, text)
    run()


@pytest.mark.parametrize("kind,rel", CASES)
def test_fuzz_check_pipeline(ws, kind, rel):
    _fuzz(ws, kind, rel, long=False)


@pytest.mark.fuzz
@pytest.mark.parametrize("kind,rel", CASES)
def test_fuzz_check_pipeline_long(ws, kind, rel):
    _fuzz(ws, kind, rel, long=True)
