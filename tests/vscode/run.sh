#!/usr/bin/env bash
# The VS Code end-to-end test: a fresh profile of a real VS Code (code-server, on 127.0.0.1
# only) with the built .vsix installed, driven by Debian's Chromium through playwright-core
# (e2e.mjs), on a copy of samples/. Screenshots of every step go to $GUDSL_E2E_OUT.
#   tests/vscode/run.sh path/to/gudsl-linux-x64-*.vsix
# Needs what tests/vscode/setup.sh installs (run it first; scripts/test does).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
vsix=$(realpath "${1:?usage: run.sh path/to/gudsl.vsix}")
home=${GUDSL_E2E_HOME:-${XDG_CACHE_HOME:-$HOME/.cache}/gudsl-vscode-e2e}
. "$home/env.sh"
out=${GUDSL_E2E_OUT:-$repo/target/vscode-e2e}
port=${GUDSL_E2E_PORT:-8765}
run=$(mktemp -d "${TMPDIR:-/tmp}/gudsl-vscode-e2e.XXXXXX")
cs_pgid=
cleanup() {
    if [ -n "$cs_pgid" ]; then
        kill -TERM -- "-$cs_pgid" 2>/dev/null || true
        for _ in $(seq 50); do kill -0 -- "-$cs_pgid" 2>/dev/null || break; sleep 0.1; done
    fi
    rm -rf "$run" || true
}
trap cleanup EXIT
rm -rf "$out" && mkdir -p "$out"

# The workspace: the samples, and a pipeline long enough to cancel (400 frames).
cp -r "$repo/samples" "$run/ws"
sed -e 's/MotionCompensationPipeline/LongMotionPipeline/' -e 's/frames = 6/frames = 400/' \
    "$repo/samples/pipelines/ch4_motion_compensation.gudsl" >"$run/ws/pipelines/long_pipeline.gudsl"
grep -q 'frames = 400' "$run/ws/pipelines/long_pipeline.gudsl" ||
    { echo "run.sh: the chapter 4 sample no longer says frames = 6: fix the long pipeline's edit"; exit 1; }
mkdir -p "$run/data/User"
python3 - "$here/settings.json" "$run/data/User/settings.json" "$run/runs" <<'PY'
import json, sys
settings = json.load(open(sys.argv[1]))
settings["gudsl.run.outputFolder"] = sys.argv[3]
json.dump(settings, open(sys.argv[2], "w"), indent=2)
PY
cat >"$run/config.yaml" <<YAML
bind-addr: 127.0.0.1:$port
auth: none
cert: false
disable-telemetry: true
disable-update-check: true
disable-workspace-trust: true
YAML
export XDG_CONFIG_HOME=$run/xdg/config XDG_DATA_HOME=$run/xdg/data XDG_CACHE_HOME=$run/xdg/cache
args=(--config "$run/config.yaml" --user-data-dir "$run/data" --extensions-dir "$run/extensions")

t=$(date +%s%N)
code-server "${args[@]}" --install-extension "$vsix" >"$out/install-extension.log" 2>&1 ||
    { cat "$out/install-extension.log"; exit 1; }
echo "installed $(basename "$vsix") in $(( ($(date +%s%N) - t) / 1000000 )) ms"

# No extension gallery: the workbench and the server would ask open-vsx.org otherwise.
export EXTENSIONS_GALLERY='{}'
setsid code-server "${args[@]}" "$run/ws" >"$out/code-server.log" 2>&1 &
cs_pgid=$!
t=$(date +%s%N)
until curl -sf -o /dev/null "http://127.0.0.1:$port/healthz"; do
    sleep 0.1
    if [ $(( ($(date +%s%N) - t) / 1000000000 )) -gt 60 ]; then
        echo "code-server did not start:"; cat "$out/code-server.log"; exit 1
    fi
done

status=0
(cd "$home/driver" && DRIVER="$home/driver" CS_URL="http://127.0.0.1:$port" WS="$run/ws" RUNS="$run/runs" OUT="$out" \
    node "$here/e2e.mjs") || status=$?
# The extension's own log (activation time, server messages) beside the screenshots.
find "$run/data/logs" -name '*GU-DSL*' -exec cp {} "$out/" \; 2>/dev/null || true
echo "screenshots and logs: $out"
exit $status
