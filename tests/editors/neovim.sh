#!/usr/bin/env bash
# Headless Neovim with the shipped configuration (editors/neovim/gudsl.lua) against the gudsl
# binary: tests/editors/neovim_test.lua drives it on a copy of a sample.
#   tests/editors/neovim.sh [path/to/gudsl]        (default: target/debug/gudsl)
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
gudsl=$(realpath "${1:-$repo/target/debug/gudsl}")
if ! command -v nvim >/dev/null; then
    echo "== installing neovim (Debian)" >&2
    "$repo/scripts/apt-install" neovim
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/gudsl-nvim.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/project/.git"
cp "$repo/samples/seed/listing07_action_transitions.gudsl" "$work/project/"
cat >"$work/init.lua" <<LUA
dofile('$repo/editors/neovim/gudsl.lua').setup({ cmd = { '$gudsl', 'lsp' } })
LUA
cd "$work/project"
HOME=$work XDG_CONFIG_HOME=$work/config XDG_STATE_HOME=$work/state XDG_DATA_HOME=$work/data \
    timeout 120 nvim --headless -u "$work/init.lua" -i NONE listing07_action_transitions.gudsl \
    -c "luafile $repo/tests/editors/neovim_test.lua" 2>&1 | tr -d '\r'
exit "${PIPESTATUS[0]}"
