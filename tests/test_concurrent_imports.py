"""Hosts with threads import the whole core on their main thread first (the CI failure of
2026-11-27: a check thread and a pairing thread importing ``tvl_lsp.launch`` at the same moment;
one saw a partially initialised module, so a launch file was 'not paired with a model')."""

import subprocess
import sys
import textwrap

import pytest

from tvl_lsp.configurator.preload import CORE_PACKAGES, import_core


def _run(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


def test_import_core_imports_every_core_module_without_failures():
    assert import_core() == []
    import pkgutil, importlib
    for sub in CORE_PACKAGES:
        pkg = importlib.import_module(f"tvl_lsp.{sub}")
        for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
            assert info.name in sys.modules, info.name


@pytest.mark.parametrize("host", ["lsp", "ui"])
def test_hosts_import_the_core_before_starting_threads(host, tmp_path):
    """A fresh interpreter: creating the host leaves no lazily imported core module for a
    thread to import later (the lazy imports in lsp/checks.py, lsp/documents.py,
    configurator/session.py and ui/server.py's warm-up thread)."""
    lazy = ["tvl_lsp.launch.dialects", "tvl_lsp.project.workspace", "tvl_lsp.project.check",
            "tvl_lsp.analysis.formats", "tvl_lsp.project.generate", "tvl_lsp.project.graph",
            "tvl_lsp.configurator.pool", "tvl_lsp.tvl.format", "tvl_lsp.launch.ros2.schema"]
    if host == "lsp":
        make = "from tvl_lsp.server import create_server; create_server()"
    else:
        (tmp_path / "m.tvl").write_text("root M { opt A; }\n")
        make = ("import threading; threading.Thread.start = lambda self: None; "
                "from tvl_lsp.ui.server import make_server; "
                f"httpd, url = make_server({str(tmp_path / 'm.tvl')!r}); httpd.server_close()")
    missing = _run(f"""
        import sys
        {make}
        print([m for m in {lazy!r} if m not in sys.modules])
    """)
    assert missing == "[]"


def test_concurrent_lazy_imports_after_preload_never_fail():
    """Eight rounds of four threads importing the lazily used entry points at the same moment,
    each round in a fresh interpreter after the preload: no error in any thread."""
    code = """
        import importlib, threading
        from tvl_lsp.configurator.preload import import_core
        import_core()
        mods = ["tvl_lsp.launch", "tvl_lsp.project.workspace", "tvl_lsp.project.check", "tvl_lsp.analysis.formats"]
        barrier = threading.Barrier(len(mods)); errors = []
        def go(m):
            barrier.wait()
            try:
                importlib.import_module(m)
            except BaseException as exc:
                errors.append(f"{m}: {exc!r}")
        ts = [threading.Thread(target=go, args=(m,)) for m in mods]
        [t.start() for t in ts]; [t.join() for t in ts]
        print(errors)
    """
    for _ in range(8):
        assert _run(code) == "[]"
