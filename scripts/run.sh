#!/usr/bin/env bash
# Set up, build, and run the main job: the bridge scene's stability check, an offline run
# along the built-in scripted hand path for every computer model (a table of forces, pins
# raised and falls), then the co-located real-time loop for a few seconds (loop statistics
# and what the hand felt).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" enact enact-rt >/dev/null
enact="${ENACT_BUILD_DIR:-$root/build}/nodes/enact/enact"
cd "$root"
echo "== enact check launch/scenes/bridge.yaml"
"$enact" check launch/scenes/bridge.yaml
echo
echo "== enact simulate launch/scenes/bridge.yaml --model all   (built-in scripted hand path, 5 kHz, offline)"
"$enact" simulate launch/scenes/bridge.yaml --model all
echo
echo "== enact launch launch/bridge_rt.yaml --duration 5   (co-located real-time loop, simulated ERGOS and cells)"
"$enact" launch launch/bridge_rt.yaml --duration 5
