"""The editor clients agree with the server: settings, command names, file kinds, filetypes;
the pre-commit hook's file pattern; and (when editors/vscode/node_modules is installed, as
scripts/ci_editors.sh does) the TextMate grammar tests and the tokenization of the repository's
models and launch files (and, in the corpus suite, of the corpus's)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tvl_lsp.lsp.features import commands as server_commands, explain
from tvl_lsp.lsp.checks import file_kind
from tvl_lsp.lsp.settings import Settings

REPO = Path(__file__).resolve().parents[1]
EXT = REPO / "editors" / "vscode"
NVIM_DIR = REPO / "editors" / "nvim"
PACKAGE = json.loads((EXT / "package.json").read_text())
CLIENT_ONLY = ("tvl-lsp.server.", "tvl-lsp.trace.")


def _nested(dotted: str, value) -> dict:
    out: dict = {}
    cur = out
    parts = dotted.split(".")
    for p in parts[:-1]:
        cur = cur.setdefault(p, {})
    cur[parts[-1]] = value
    return out


def _non_default(prop: dict):
    t = prop.get("type")
    if t == "object":
        return {"missing-arg": "off"}
    if t == "number":
        return (prop.get("default") or 1) + 2.5
    if t == "integer":
        return (prop.get("default") or 1) + 3
    if t == "string":
        return "generated/configs"
    raise AssertionError(f"no test value for type {t}")


def test_every_vscode_setting_is_understood_by_the_server():
    props = PACKAGE["contributes"]["configuration"]["properties"]
    server_keys = [k for k in props if not k.startswith(CLIENT_ONLY)]
    assert {"tvl-lsp.diagnostics", "tvl-lsp.count.timeBudget", "tvl-lsp.generate.folder"} <= set(server_keys)
    for key in server_keys:
        s = Settings()
        before = dict(vars(s))
        s.update(_nested(key, _non_default(props[key])))
        assert vars(s) != before, f"the server ignores the VS Code setting {key}"
    # the client sends this shape (serverSettings() in src/extension.ts)
    src = (EXT / "src" / "extension.ts").read_text()
    for key in server_keys:
        leaf = key.split(".")[-1]
        assert f"'{key[len('tvl-lsp.'):]}'" in src or leaf in src, f"extension.ts never sends {key}"


def test_diagnostic_severity_values_match_the_server():
    enum = PACKAGE["contributes"]["configuration"]["properties"]["tvl-lsp.diagnostics"][
        "additionalProperties"]["enum"]
    for value in enum:
        s = Settings()
        s.update({"tvl-lsp": {"diagnostics": {"missing-arg": value}}})
        assert s.diagnostics == {"missing-arg": value}, value


def test_the_clients_call_server_commands_that_exist():
    server = {server_commands.INCLUDE, server_commands.EXCLUDE, server_commands.RESET,
              server_commands.COUNT, server_commands.LIST, server_commands.GENERATE, explain.EXPLAIN}
    src = (EXT / "src" / "extension.ts").read_text()
    called = set(re.findall(r"'(tvl-lsp\.[A-Za-z]+)'", src)) - {"tvl-lsp.running", "tvl-lsp.server"}
    assert called, "extension.ts calls no server command"
    assert called <= server, f"unknown server commands: {called - server}"
    assert server <= called, f"server commands without a client command: {server - called}"
    # the client's own palette commands are all contributed and none clashes with a server
    # command (vscode-languageclient registers those itself)
    contributed = {c["command"] for c in PACKAGE["contributes"]["commands"]}
    registered = set(re.findall(r"registerCommand\('([^']+)'", src))
    assert contributed == registered
    assert not contributed & server


def test_launch_and_model_extensions_are_files_the_server_analyses():
    exts = [e for lang in PACKAGE["contributes"]["languages"] for e in lang["extensions"]]
    assert set(exts) == {".tvl", ".launch", ".launch.xml", "_launch.xml", ".test"}
    for e in exts:
        assert file_kind(f"/ws/src/pkg/launch/generic{e}") in ("tvl", "launch"), e


def test_vscode_selects_python_launch_files():
    """ROS 2 Python launch files reach the server (a python selector: by name, or every Python
    file -- the nodes' sources are read too --; the Python extension keeps them all), are
    watched, and a workspace that has them activates the extension.  The server analyses them
    as launch files, and no other Python file as one."""
    src = (EXT / "src" / "extension.ts").read_text()
    selectors = re.findall(r"\{ scheme: 'file', language: 'python'(?:, pattern: '([^']*)')? \}", src)
    assert selectors, "no document selector for Python files"
    assert any(p == "" or {".launch.py", "_launch.py"} <= set(re.search(r"\{([^}]*)\}", p).group(1).split(","))
               for p in selectors), selectors
    call = src[src.index("createFileSystemWatcher("):]
    watched = "".join(re.findall(r"'([^']*)'", re.sub(r"//[^\n]*", "", call[: call.index(");")])))
    for suffix in (".launch.py", "_launch.py"):
        assert file_kind(f"/ws/src/pkg/launch/robot{suffix}") == "launch"
        assert f"*{suffix}" in watched or "*.py" in watched
        assert f"workspaceContains:**/*{suffix}" in PACKAGE["activationEvents"]
    for plain in ("/ws/src/pkg/pkg/util.py", "/ws/src/pkg/setup.py", "/ws/src/pkg/launch/helpers.py"):
        assert file_kind(plain) != "launch"
    assert "onLanguage:python" not in PACKAGE["activationEvents"]


def test_neovim_filetypes_reach_the_lsp_config():
    ftdetect = (NVIM_DIR / "ftdetect" / "tvl.lua").read_text()
    config = (NVIM_DIR / "lsp" / "tvl_lsp.lua").read_text()
    filetypes = set(re.findall(r"'([a-z]+)'", re.search(r"filetypes\s*=\s*\{([^}]*)\}", config).group(1)))
    detected = set(re.findall(r"=\s*'([a-z]+)'", ftdetect)) | set(re.findall(r"return '([a-z]+)'", ftdetect))
    assert detected == {"tvl", "roslaunch"}
    assert detected <= filetypes
    # every filetype has an ftplugin, tvl a syntax file
    for ft in detected:
        assert (NVIM_DIR / "ftplugin" / f"{ft}.lua").is_file()
    for ft in detected:
        assert (NVIM_DIR / "syntax" / f"{ft}.vim").is_file(), ft


def test_pre_commit_hook():
    hooks = yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text())
    hook = next(h for h in hooks if h["id"] == "tvl-lsp-check")
    assert hook["entry"] == "tvl-lsp --check"
    assert hook["language"] == "python"
    files = re.compile(hook["files"])
    for yes in ["src/lizi/launch/generic.tvl", "src/lizi/launch/generic.launch", "launch/a.launch.xml",
                "test/nav.test", "haros_lizi.yaml", "ws/haros.yml", "models/robot.uvl", "models/linux.dimacs",
                "launch/robot.launch.yaml", "launch/robot_launch.xml", "launch/robot_launch.yaml",
                "launch/robot.launch.py", "launch/robot_launch.py"]:
        assert files.search(yes), yes
    for no in ["src/lizi/package.xml", "config/params.yaml", "CMakeLists.txt", "a.tvl.bak", "my.cnf",
               "setup.py", "scripts/launch.py", "launch/robot.launch.bak", "urdf/robot.xml"]:
        assert not files.search(no), no


def test_pre_commit_hook_covers_every_suffix_the_front_ends_read():
    """Every file name the front ends and --check's folder walk take (launch/dialects.py's launch
    suffixes, the model formats, rostest files, ROS 2 Python launch files) is one the hook passes."""
    from tvl_lsp.analysis.formats import MODEL_SUFFIXES
    from tvl_lsp.launch import dialects
    from tvl_lsp.project import workspace
    hook = next(h for h in yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text())
                if h["id"] == "tvl-lsp-check")
    files = re.compile(hook["files"])
    python = [v for k, v in vars(dialects).items() if "PY" in k.upper() and "SUFFIX" in k.upper()]
    suffixes = (set(dialects.LAUNCH_SUFFIXES) | set(workspace.LAUNCH_SUFFIXES) | set(MODEL_SUFFIXES)
                | set(workspace.MODEL_SUFFIXES) | {".test", ".launch.py", "_launch.py"}
                | {s for v in python for s in (v if isinstance(v, tuple) else (v,))})
    missed = sorted(s for s in suffixes if not files.search(f"src/pkg/launch/robot{s}"))
    assert not missed, f"the pre-commit hook's files pattern misses {missed}"


NODE_MISSING = ("needs Node.js >= 20 and editors/vscode/node_modules: cd editors/vscode && npm ci "
                "(scripts/ci_editors.sh does it)")


def _node_ready() -> bool:
    return shutil.which("node") is not None and (EXT / "node_modules" / "vscode-textmate").is_dir()


@pytest.mark.skipif(not _node_ready(), reason=NODE_MISSING)
def test_textmate_grammar_tests():
    proc = subprocess.run(["npm", "run", "--silent", "test:grammar"], cwd=EXT, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.count("run successfuly") == len(list((EXT / "test" / "grammar").glob("*.*")))


@pytest.mark.slow  # end to end, several seconds: CI's slow stage (.ci/run) runs it
@pytest.mark.skipif(not _node_ready() or not (EXT / "out" / "extension.js").is_file(),
                    reason=NODE_MISSING + "; and the built extension (npm run package)")
def test_vscode_client_finds_the_server_or_says_why():
    env = dict(os.environ, TVL_TEST_PYTHON=sys.executable)
    proc = subprocess.run(["node", "--test", "test/unit/"], cwd=EXT, capture_output=True, text=True,
                          timeout=120, env=env)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert re.search(r"^# fail 0$", proc.stdout, re.M) and re.search(r"^# pass [1-9]", proc.stdout, re.M)
    assert not re.search(r"^# skipped [1-9]", proc.stdout, re.M), proc.stdout


def _tokenize_all(*folders: Path):
    proc = subprocess.run(["node", "scripts/tokenize-corpus.js", *map(str, folders)], cwd=EXT,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    m = re.search(r"tokenized (\d+) \.tvl files and (\d+) launch files", proc.stdout)
    n_tvl = sum(len(list(f.rglob("*.tvl"))) for f in folders)
    assert m and int(m.group(1)) == n_tvl and int(m.group(2)) > 0, proc.stdout


@pytest.mark.skipif(not _node_ready(), reason=NODE_MISSING)
def test_every_repository_model_and_launch_file_tokenizes():
    _tokenize_all(REPO / "examples", REPO / "tests" / "data")


@pytest.mark.corpus
@pytest.mark.skipif(not _node_ready(), reason=NODE_MISSING)
def test_every_corpus_file_tokenizes(corpus_dir):
    _tokenize_all(corpus_dir)
