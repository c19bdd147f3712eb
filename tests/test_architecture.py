"""The package's architecture (docs/architecture.md) as tests: the import-linter contracts in
pyproject.toml hold, no module imports itself back through a cycle, every top-level package
has a layer, and modules stay small enough to read."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "tvl_lsp"

MAX_LINES = 1000
MAX_SERVER_LINES = 350

import grimp  # noqa: E402  (import-linter's graph builder; both in the "test" extra)
import importlinter.cli as importlinter_cli  # noqa: E402

if sys.version_info >= (3, 11):
    import tomllib
else:  # import-linter depends on tomli there
    import tomli as tomllib


def _config() -> dict:
    with open(REPO / "pyproject.toml", "rb") as fh:
        return tomllib.load(fh)["tool"]["importlinter"]


def test_import_linter_contracts_hold(monkeypatch, capsys):
    monkeypatch.chdir(REPO)
    code = importlinter_cli.lint_imports(config_filename=str(REPO / "pyproject.toml"), no_cache=True,
                                         no_logo=True)
    out = capsys.readouterr().out
    assert code == 0, out
    assert "broken" not in out.replace("0 broken", ""), out


def _strongly_connected(graph) -> list[list[str]]:
    """Tarjan's algorithm over the module graph (iterative: no recursion limit)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
    counter = 0
    for start in sorted(graph.modules):
        if start in index:
            continue
        work = [(start, iter(sorted(graph.find_modules_directly_imported_by(start))))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph.find_modules_directly_imported_by(w)))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def test_no_import_cycles():
    """Module-level imports, imports inside functions and ``TYPE_CHECKING`` imports alike."""
    graph = grimp.build_graph("tvl_lsp", cache_dir=None)
    cycles = _strongly_connected(graph)
    details = []
    for comp in cycles:
        for a in comp:
            for b in comp:
                if a != b and graph.direct_import_exists(importer=a, imported=b):
                    details.append(f"{a} -> {b}")
    assert not cycles, "import cycles:\n" + "\n".join(details)


def test_cycle_finder_finds_a_cycle():
    class G:
        modules = {"a", "b", "c", "d"}
        edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}

        def find_modules_directly_imported_by(self, m):
            return self.edges.get(m, set())
    assert _strongly_connected(G()) == [["a", "b", "c"]]


def test_every_top_level_package_has_a_layer():
    """A new package (say ``tvl_lsp.graph``) must be placed in the layers contract, else
    nothing checks its imports."""
    layers = next(c for c in _config()["contracts"] if c["type"] == "layers")["layers"]
    named = {m.strip() for layer in layers for m in layer.replace(":", "|").split("|")}
    top = {f"tvl_lsp.{p.name}" for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}
    top |= {f"tvl_lsp.{p.stem}" for p in PACKAGE.glob("*.py") if p.stem not in ("__init__", "__main__")}
    assert top <= named, f"not in the layers contract: {sorted(top - named)}"


def test_core_packages_are_covered_by_the_core_contract():
    contracts = _config()["contracts"]
    core = set(next(c for c in contracts if c.get("id") == "core")["source_modules"])
    hosts = {"tvl_lsp.lsp", "tvl_lsp.cli", "tvl_lsp.ui", "tvl_lsp.main"}
    top = {f"tvl_lsp.{p.name}" for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}
    assert top - hosts <= core, f"core packages outside the core contract: {sorted(top - hosts - core)}"


def _lines(path: Path) -> int:
    with open(path, encoding="utf-8") as fh:
        return sum(1 for _ in fh)


def test_modules_are_small():
    big = {str(p.relative_to(REPO)): n for p in PACKAGE.rglob("*.py") if (n := _lines(p)) > MAX_LINES}
    assert not big, f"modules over {MAX_LINES} lines: {big}"


def test_server_is_thin():
    n = _lines(PACKAGE / "lsp" / "server.py")
    assert n <= MAX_SERVER_LINES, f"tvl_lsp/lsp/server.py has {n} lines (at most {MAX_SERVER_LINES})"


def test_every_sat_solver_is_interruptible():
    """pysat's solvers run in C, where the CPU budget's timer cannot stop them: every solver the
    package creates is ``analysis/sat.py``'s ``BoundedSolver`` (issue 12: a 1 KB pigeonhole
    DIMACS kept ``--check`` busy for hours)."""
    import re
    direct = re.compile(r"from pysat\.solvers import[^\n]*\bSolver\b|pysat\.solvers\.Solver\(")
    bad = [str(p.relative_to(REPO)) for p in PACKAGE.rglob("*.py")
           if p.name != "sat.py" and direct.search(p.read_text(encoding="utf-8"))]
    assert bad == []


def test_server_module_is_the_public_entry_point():
    """tvl_lsp.server is the server's public entry (create_server, serve), the object the lsp
    package builds, with every feature registered; the console command starts it."""
    import inspect

    import tvl_lsp.main
    import tvl_lsp.server as public
    from tvl_lsp.lsp import server as impl
    assert public.create_server is impl.create_server and public.TvlLanguageServer is impl.TvlLanguageServer
    assert list(inspect.signature(public.serve).parameters) == ["tcp"]
    server = public.create_server()
    commands = set(server.protocol.fm.commands)
    assert {"tvl-lsp.explain", "tvl-lsp.count", "tvl-lsp.configurator"} <= commands
    assert '"tvl_lsp.server"' in inspect.getsource(tvl_lsp.main._main)


def _layer_names(layer: str) -> list[str]:
    return [m.strip().removeprefix("tvl_lsp.") for m in layer.split("|")]


def test_the_layer_pictures_match_the_contract():
    """docs/architecture.md draws the layers contract of pyproject.toml line by line, in order,
    and the README's "How it is built" names every layer."""
    layers = next(c for c in _config()["contracts"] if c["type"] == "layers")["layers"]
    want = [" | ".join(_layer_names(layer)) for layer in layers]
    doc = (REPO / "docs" / "architecture.md").read_text(encoding="utf-8")
    intro = doc.index("a layer imports only from the layers below it")
    block = doc[doc.index("```\n", intro) + 4: doc.index("\n```", doc.index("```\n", intro) + 4)]
    drawn = [re.split(r"\s{2,}", line.strip())[0] for line in block.splitlines() if line.strip()]
    assert drawn == want, f"docs/architecture.md's layer picture: {drawn}, the contract: {want}"
    names = {n for layer in layers for n in _layer_names(layer)}
    for name in names:
        assert f"`{name}`" in doc or f"{name}/" in doc or f"{name}.py" in doc, name
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    built = readme[readme.index("## How it is built"):]
    missing = sorted(n for n in names if not re.search(rf"`(tvl_lsp/)?{n}(/|\.py)?`", built))
    assert not missing, f"README's How it is built leaves out {missing}"


# ------------------------------------------------------------------ file I/O goes through two modules

# where a raw open() / os.open() / os.fdopen() is allowed, and why (issue #28: the server's check
# process read the workspace's launch files with a plain open(): a FIFO blocked every check, a
# link to /dev/zero was read without bound)
RAW_IO_ALLOWED = {
    "tvl_lsp/base/files.py": {"os.open"},                      # the bounded reader itself
    "tvl_lsp/base/safewrite.py": {"os.open", "open", "os.fdopen"},  # the safe writer (and named streams)
    "tvl_lsp/analysis/counting/d4.py": {"os.open", "os.fdopen"},    # fd 1 -> os.devnull around d4
}
# Path methods that read or write a file without the bounds
RAW_METHODS = {"read_text", "read_bytes", "write_text", "write_bytes"}
# `.open(...)` on these names is not file I/O
OPEN_RECEIVERS = {"Session", "webbrowser", "cls"}


def raw_io_calls(source: str) -> list[tuple[int, str]]:
    """(line, call) of every raw file operation in ``source``."""
    import ast
    out = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        if isinstance(f, ast.Name) and f.id == "open":
            out.append((node.lineno, "open"))
        elif isinstance(f, ast.Attribute):
            recv = f.value.id if isinstance(f.value, ast.Name) else None
            if f.attr in RAW_METHODS and recv != "files":  # (files: tvl_lsp.base.files, the bounded reader)
                out.append((node.lineno, f".{f.attr}"))
            elif f.attr in ("open", "fdopen") and recv in ("os", "io", "codecs"):
                out.append((node.lineno, f"{recv}.{f.attr}"))
            elif f.attr == "open" and recv not in OPEN_RECEIVERS:
                out.append((node.lineno, f"{recv or '?'}.open"))
    return sorted(out)


def test_every_file_read_and_write_goes_through_the_bounded_reader_or_the_safe_writer():
    """Reads go through ``base/files.py`` (regular files only, a size cap, never blocking);
    writes through ``base/safewrite.py`` (atomic, never through a link)."""
    bad = []
    for p in sorted(PACKAGE.rglob("*.py")):
        rel = str(p.relative_to(REPO))
        allowed = RAW_IO_ALLOWED.get(rel, set())
        for line, call in raw_io_calls(p.read_text(encoding="utf-8")):
            if call not in allowed:
                bad.append(f"{rel}:{line}: {call}(...)")
    assert bad == [], ("raw file I/O; read with tvl_lsp.base.files (read_text, read_bytes, read_head), "
                       "write with tvl_lsp.base.safewrite:\n" + "\n".join(bad))


def test_the_raw_io_finder_finds_raw_io():
    src = ("open('x').read()\nPath('x').read_text()\nos.open('x', 0)\np.write_bytes(b'')\n"
           "Session.open('m')\nwebbrowser.open('u')\nf.open()\nio.open('x')\n")
    assert [c for _, c in raw_io_calls(src)] == ["open", ".read_text", "os.open", ".write_bytes", "f.open", "io.open"]
