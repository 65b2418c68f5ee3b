#!/usr/bin/env bash
# Builds the platform-specific .vsix: the extension (type-checked, bundled by esbuild) and the
# `gudsl` server for this machine's platform (linux-x64 on x86_64), stripped.
#   npm ci && npm run package            -> gudsl-<platform>-<version>.vsix
# GUDSL_SERVER_BINARY names the binary to ship (default: the repository's release build, built
# when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(cd .. && pwd)
binary=${GUDSL_SERVER_BINARY:-$repo/target/release/gudsl}
if [ ! -x "$binary" ]; then
    echo "== building the server: cargo build --release -p gudsl-server" >&2
    (cd "$repo" && cargo build --release -p gudsl-server)
fi
case "$(uname -s)-$(uname -m)" in
    Linux-x86_64) target=linux-x64 ;;
    Linux-aarch64) target=linux-arm64 ;;
    Darwin-arm64) target=darwin-arm64 ;;
    Darwin-x86_64) target=darwin-x64 ;;
    *) echo "package.sh: no VS Code target for $(uname -s)-$(uname -m)" >&2; exit 1 ;;
esac
rm -rf server && mkdir -p server
cp "$binary" server/gudsl
# Debug info is most of the binary (28 MB stripped against 168 MB).
strip server/gudsl 2>/dev/null || echo "package.sh: strip not found; shipping the binary unstripped" >&2
version=$(node -p "require('./package.json').version")
out=gudsl-$target-$version.vsix
npx vsce package --target "$target" --allow-missing-repository -o "$out"
ls -l "$out"
