#!/usr/bin/env bash
# Set up, build, and run the main job: the bridge scene's stability check, then an offline
# run along the built-in scripted hand path for every computer model (a table of forces,
# pins raised and falls).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" enact >/dev/null
enact="${ENACT_BUILD_DIR:-$root/build}/nodes/enact/enact"
cd "$root"
echo "== enact check launch/scenes/bridge.yaml"
"$enact" check launch/scenes/bridge.yaml
echo
echo "== enact simulate launch/scenes/bridge.yaml --model all   (built-in scripted hand path, 5 kHz, offline)"
"$enact" simulate launch/scenes/bridge.yaml --model all
