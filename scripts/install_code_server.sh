#!/usr/bin/env bash
# Install code-server (VS Code in the browser) from npm for the VS Code end-to-end test
# (tests/test_editors_vscode.py), without any download outside the npm registry and Debian:
# code-server's postinstall and @vscode/ripgrep's fetch binaries from GitHub, so scripts are
# skipped and the steps they do are done here, with Debian's ripgrep in place of the download.
#
# The result is cached, keyed by the code-server version and the Node.js major version:
#   ${TVL_CI_CACHE:-~/.cache/tvl-lsp-ci}/code-server-<version>-node<major>/
# A second run finds it and only checks that it starts. Prints the code-server executable's
# path as its last line. Needs Node.js 20 (code-server 4.100.x refuses others), npm, a C++
# toolchain, and Debian's ripgrep libkrb5-dev libsecret-1-dev libxkbfile-dev libx11-dev
# pkg-config (installed with apt-get when missing and running as root or with sudo).
#
#   scripts/install_code_server.sh                 # install or reuse the cached copy
#   CODE_SERVER_VERSION=4.100.3 scripts/install_code_server.sh
set -euo pipefail

VERSION="${CODE_SERVER_VERSION:-4.100.3}"
CACHE="${TVL_CI_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/tvl-lsp-ci}"
START=$(date +%s)

step() { printf '== install_code_server: %s\n' "$*" >&2; }
die() { printf 'install_code_server: FAILED: %s\n' "$*" >&2; exit 1; }

command -v node >/dev/null || die "node is not installed (code-server $VERSION needs Node.js 20)"
command -v npm >/dev/null || die "npm is not installed"
NODE_MAJOR=$(node -p 'process.versions.node.split(".")[0]')
[[ "$NODE_MAJOR" == 20 ]] || die "code-server $VERSION needs Node.js 20, found $(node --version)"

DEST="$CACHE/code-server-$VERSION-node$NODE_MAJOR"
LAUNCHER="$DEST/code-server"

works() {
  [[ -f "$DEST/.complete" && -x "$LAUNCHER" ]] && "$LAUNCHER" --version 2>/dev/null | head -1 | grep -q "^$VERSION "
}

if works; then
  step "cached: $DEST ($("$LAUNCHER" --version 2>/dev/null | head -1))"
  echo "$LAUNCHER"
  exit 0
fi

step "system packages (ripgrep and the headers of the native modules)"
DEBS=(ripgrep libkrb5-dev libsecret-1-dev libxkbfile-dev libx11-dev pkg-config g++ make python3)
missing=()
for d in "${DEBS[@]}"; do
  dpkg-query -W -f='${Status}' "$d" 2>/dev/null | grep -q 'install ok installed' || missing+=("$d")
done
if ((${#missing[@]})); then
  command -v apt-get >/dev/null || die "missing Debian packages: ${missing[*]}"
  SUDO=""; [[ $(id -u) -eq 0 ]] || SUDO="sudo"
  $SUDO apt-get update -qq || die "apt-get update failed"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null \
    || die "apt-get could not install ${missing[*]}"
fi
RG="$(command -v rg)" || die "ripgrep (rg) is not installed"

# node-gyp would download Node's headers from nodejs.org: use the ones Debian's nodejs installs
if [[ -z "${npm_config_nodedir:-}" && -z "$(npm config get nodedir 2>/dev/null | grep -v '^undefined$')" \
      && -f /usr/include/node/common.gypi ]]; then
  export npm_config_nodedir=/usr
fi

mkdir -p "$CACHE"
BUILD="$(mktemp -d "$CACHE/.build-code-server-XXXXXX")"
trap 'rm -rf "$BUILD"' EXIT
NPM=(npm --no-audit --no-fund --loglevel=error --no-update-notifier)
export npm_config_yes=true

step "npm install code-server@$VERSION (scripts off) into $BUILD"
(cd "$BUILD" && echo '{"private":true}' >package.json && "${NPM[@]}" install --ignore-scripts "code-server@$VERSION") \
  || die "npm install code-server@$VERSION failed"
CS="$BUILD/node_modules/code-server"
VS="$CS/lib/vscode"
[[ -d "$VS" ]] || die "no lib/vscode in the code-server package"

step "VS Code's dependencies (lib/vscode, scripts off)"
(cd "$VS" && "${NPM[@]}" install --omit=dev --ignore-scripts) || die "npm install in lib/vscode failed"

step "ripgrep: Debian's $RG in place of @vscode/ripgrep's download"
mkdir -p "$VS/node_modules/@vscode/ripgrep/bin"
ln -sfn "$RG" "$VS/node_modules/@vscode/ripgrep/bin/rg"

step "native modules of lib/vscode (npm rebuild)"
(cd "$VS" && "${NPM[@]}" rebuild) || die "npm rebuild in lib/vscode failed (are the -dev packages installed?)"
# the rebuild runs @vscode/ripgrep's postinstall again: put the link back if it was replaced
ln -sfn "$RG" "$VS/node_modules/@vscode/ripgrep/bin/rg"

step "what code-server's postinstall.sh does: node_modules.asar and the bin scripts"
(cd "$VS" && ln -sfn node_modules node_modules.asar)
(cd "$VS/bin/remote-cli" && rm -rf code-server && ln -s code-linux.sh code-server)
(cd "$VS/bin/helpers" && rm -rf browser.sh && ln -s browser-linux.sh browser.sh)

step "the built-in extensions' dependencies (lib/vscode/extensions)"
(cd "$VS/extensions" && "${NPM[@]}" install --omit=dev) || die "npm install in lib/vscode/extensions failed"

step "code-server's own native modules (argon2, built from source: its prebuilt download is off limits)"
# by name: a plain `npm rebuild` here would run code-server's postinstall.sh again
native=()
for gyp in "$BUILD"/node_modules/*/binding.gyp "$BUILD"/node_modules/@*/*/binding.gyp; do
  [[ -f "$gyp" ]] || continue
  pkg="${gyp#"$BUILD/node_modules/"}"; pkg="${pkg%/binding.gyp}"
  [[ "$pkg" == code-server ]] || native+=("$pkg")
done
((${#native[@]})) || die "no native module found beside code-server (expected argon2)"
echo "rebuilding ${native[*]}" >&2
(cd "$BUILD" && npm_config_build_from_source=true "${NPM[@]}" rebuild "${native[@]}") || die "npm rebuild ${native[*]} failed"

cat >"$BUILD/code-server" <<EOF
#!/bin/sh
# code-server $VERSION, installed by tvl-lsp's scripts/install_code_server.sh
exec node "\$(dirname "\$0")/node_modules/code-server/out/node/entry.js" "\$@"
EOF
chmod +x "$BUILD/code-server"
"$BUILD/code-server" --version >/dev/null 2>&1 || die "the installed code-server does not start"

touch "$BUILD/.complete"
rm -rf "$DEST"
mv "$BUILD" "$DEST"
trap - EXIT
works || die "code-server at $DEST does not report version $VERSION"
step "installed $("$LAUNCHER" --version | head -1) at $DEST in $(( $(date +%s) - START )) s"
echo "$LAUNCHER"
