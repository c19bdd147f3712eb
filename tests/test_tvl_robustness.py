"""Bad input never crashes or hangs: each case gets a diagnostic within seconds."""

import random
import time

from tvl_lsp.tvl import MAX_FILE_SIZE, parse_model


def run(text, files=None, limit=10.0):
    files = files or {}
    t0 = time.perf_counter()
    res = parse_model(text, "/r/a.tvl", read_file=lambda p: files.get(p))
    assert time.perf_counter() - t0 < limit
    return res


def test_10000_deep_parentheses():
    n = 10_000
    res = run("root A { " + "(" * n + "A" + ")" * n + "; }")
    assert "nesting-too-deep" in {d.code for d in res.diagnostics}
    assert res.model.root.name == "A"


def test_10000_deep_unary_and_binary_chains():
    res = run("root A { " + "!" * 10_000 + "A; }")
    assert "nesting-too-deep" in {d.code for d in res.diagnostics}
    res = run("root A { A" + " && A" * 10_000 + "; }")  # left-nested, 10,000 deep
    assert "nesting-too-deep" in {d.code for d in res.diagnostics}


def test_10000_deep_nested_features():
    n = 10_000
    text = "root A { group allOf { " + "".join(f"F{i} {{ group allOf {{ " for i in range(n)) + "Leaf" + " } }" * n + " } }"
    res = run(text)
    assert "nesting-too-deep" in {d.code for d in res.diagnostics}
    assert res.model.feature("F0") is not None


def test_20_mb_file():
    text = "root A { group allOf { B } }\n" + "// padding\n" * (20 * 1024 * 1024 // 11)
    assert len(text) > MAX_FILE_SIZE
    res = run(text)
    assert [d.code for d in res.diagnostics] == ["file-too-large"]


def test_binary_junk():
    rnd = random.Random(7)
    junk = bytes(rnd.randrange(256) for _ in range(200_000)).decode("latin-1")
    res = run(junk)
    assert res.diagnostics and all(d.severity == 1 for d in res.diagnostics[:1])
    res = run("\x00\x01\x02 root A { }")
    assert "illegal-character" in {d.code for d in res.diagnostics}


def test_unterminated_comment():
    res = run("root A { group allOf { B } }\n/* never closed\nB { }\n")
    d = [x for x in res.diagnostics if x.code == "unterminated-comment"]
    assert len(d) == 1 and d[0].span.start.line == 1
    assert res.model.feature("B") is not None


def test_unterminated_comment_inside_a_block():
    res = run("root A { group allOf { B } /* oops\n")
    assert {"unterminated-comment", "syntax-error"} <= {d.code for d in res.diagnostics}


def test_include_cycle_and_self_include():
    res = run("root A { }\ninclude(a.tvl);\n")
    assert [d.code for d in res.diagnostics] == ["include-cycle"]
    files = {"/r/b.tvl": "include(a.tvl);\n"}
    res = run("root A { }\ninclude(b.tvl);\n", files=files)
    assert [d.code for d in res.diagnostics] == ["include-cycle"]


def test_read_file_that_raises_is_a_missing_include():
    def boom(path):
        raise PermissionError(path)
    res = parse_model("root A { }\ninclude(x.tvl);\n", "/r/a.tvl", read_file=boom)
    assert [d.code for d in res.diagnostics] == ["include-missing"]


def test_empty_and_whitespace_files():
    for text in ("", "   \n\n", "// only a comment\n"):
        res = run(text)
        assert res.model.root is None


def test_many_errors_are_bounded():
    res = run("root A { " + "= " * 5000 + "}")
    assert 0 < len(res.diagnostics) < 100


def test_hundreds_of_errors_stay_bounded_and_keep_the_model():
    text = "root A { group allOf { B } }\n" + "".join(f"B {{ x{i} == ; }}\n" for i in range(300))
    res = run(text)
    msgs = [d.message for d in res.diagnostics if d.code == "syntax-error"]
    assert any("too many syntax errors" in m for m in msgs)
    assert res.model.root.name == "A" and res.model.feature("B") is not None


def test_token_limit(monkeypatch):
    import tvl_lsp.tvl as tvl
    monkeypatch.setattr(tvl, "MAX_TOKENS", 50)
    res = run("root A { " + "B; " * 100 + "}")
    assert [d.code for d in res.diagnostics] == ["file-too-large"]
    files = {"/r/b.tvl": "B { " + "B; " * 100 + "}"}
    res = run("root A { group allOf { B } }\ninclude(b.tvl);\n", files=files)
    assert [(d.code, d.path) for d in res.diagnostics] == [("file-too-large", "/r/b.tvl")]
