#!/usr/bin/env bash
# The configurator's web UI in CI: Debian's Chromium for the Playwright tests
# (tests/test_ui_browser.py; Playwright's own browser download is never used), and a rebuild of
# the committed bundle (tvl_lsp/ui/static) from editors/configurator, which must match it byte
# for byte. Needs Node.js >= 20 with npm, apt-get as root (or sudo). Idempotent; fails loudly.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
die() { printf 'ci_ui: FAILED: %s\n' "$*" >&2; exit 1; }

printf '\n== ci_ui: Chromium (Debian) for the browser tests\n'
if [[ -x /usr/bin/chromium ]]; then
  /usr/bin/chromium --version 2>/dev/null || true
else
  command -v apt-get >/dev/null || die "apt-get is needed to install chromium"
  SUDO=""; [[ $(id -u) -eq 0 ]] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get install -y -qq chromium >/dev/null || { $SUDO apt-get update -qq && $SUDO apt-get install -y -qq chromium >/dev/null; } \
    || die "apt-get could not install chromium"
fi

printf '\n== ci_ui: the committed bundle is up to date with editors/configurator\n'
cd "$REPO/editors/configurator"
npm ci --no-audit --no-fund --loglevel=error || die "npm ci failed in editors/configurator"
npm run --silent typecheck || die "the configurator's TypeScript does not type-check"
npm run --silent check || die "tvl_lsp/ui/static is stale: run 'npm run build' in editors/configurator and commit it"
