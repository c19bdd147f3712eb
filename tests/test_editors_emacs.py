"""Second real-editor client: Emacs (batch) with eglot and editors/emacs/tvl-lsp.el against
tvl-lsp on a scratch copy of the test workspace (tests/testenv.py): diagnostics, a hover with the product
count, and the add-missing-arg quick fix (steps and expectations in tests/editors/emacs_e2e.el).
Debian: apt-get install emacs-nox elpa-eglot (scripts/ci_editors.sh does). Skipped without them."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import pytest

from testenv import REPO, make_ws

HARNESS = REPO / "tests" / "editors" / "emacs_e2e.el"


def _emacs_with_eglot() -> str | None:
    emacs = shutil.which("emacs")
    if not emacs:
        return None
    try:
        proc = subprocess.run([emacs, "--batch", "--eval", "(require 'eglot)"], capture_output=True,
                              timeout=60, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.SubprocessError):
        return None
    return emacs if proc.returncode == 0 else None


EMACS = _emacs_with_eglot()


@pytest.mark.skipif(EMACS is None, reason="no Emacs with eglot (apt-get install emacs-nox elpa-eglot)")
def test_emacs_eglot_diagnostics_hover_and_quick_fix(tmp_path):
    ws = make_ws(tmp_path / "ws")
    out = tmp_path / "result.json"
    env = dict(os.environ)
    env.update({"HOME": str(tmp_path / "home"), "TVL_LSP_REPO": str(REPO),
                "TVL_LSP_CMD": json.dumps([sys.executable, "-m", "tvl_lsp"]), "TVL_E2E_WS": str(ws),
                "TVL_E2E_OUT": str(out)})
    proc = subprocess.run([EMACS, "--batch", "-l", str(HARNESS)], cwd=ws, env=env, capture_output=True,
                          text=True, timeout=300, stdin=subprocess.DEVNULL)
    assert out.is_file(), f"the harness wrote no result (exit {proc.returncode}):\n{proc.stderr[-4000:]}"
    result = json.loads(out.read_text())
    report = "\n".join(f"{'PASS' if c['ok'] is True else 'FAIL'} {c['name']}: {c['detail'][:600]}"
                       for c in result["checks"])
    assert result["ok"] is True and proc.returncode == 0, report
    assert {c["name"] for c in result["checks"]} >= {"eglot connected", "expected diagnostics (flymake)",
                                                      "hover shows the product count",
                                                      "missing-arg gone after the fix"}, report


@pytest.mark.skipif(EMACS is None, reason="no Emacs with eglot (apt-get install emacs-nox elpa-eglot)")
def test_emacs_eglot_on_a_python_launch_file(tmp_path):
    """*.launch.py opens in ros2-launch-python-mode (a python-mode) served by tvl-lsp; ordinary
    Python stays in python-mode."""
    import shutil
    ws = tmp_path / "ws"
    shutil.copytree(REPO / "tests" / "data" / "ros2py_editor" / "ws", ws)
    out = tmp_path / "result.json"
    env = dict(os.environ)
    env.update({"HOME": str(tmp_path / "home"), "TVL_LSP_REPO": str(REPO),
                "TVL_LSP_CMD": json.dumps([sys.executable, "-m", "tvl_lsp"]), "TVL_E2E_WS": str(ws),
                "TVL_E2E_OUT": str(out)})
    proc = subprocess.run([EMACS, "--batch", "-l", str(REPO / "tests" / "editors" / "emacs_python_e2e.el")], cwd=ws,
                          env=env, capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    assert out.is_file(), f"the harness wrote no result (exit {proc.returncode}):\n{proc.stderr[-4000:]}"
    result = json.loads(out.read_text())
    report = "\n".join(f"{'PASS' if c['ok'] is True else 'FAIL'} {c['name']}: {c['detail'][:600]}"
                       for c in result["checks"])
    assert result["ok"] is True and proc.returncode == 0, report
