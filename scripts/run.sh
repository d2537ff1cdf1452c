#!/usr/bin/env bash
# Set up, build, and run the main job: the bridge scene's stability check, an offline run
# along the built-in scripted hand path for every computer model (a table of forces, pins
# raised and falls), then the quick bridge experiment: virtual subjects on the co-located
# real-time graph (3 subjects x CM0-CM3, every trial recorded), its statistics (Friedman,
# Wilcoxon) and figure.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" enact enact-rt enact-logger >/dev/null
build="${ENACT_BUILD_DIR:-$root/build}"
enact="$build/nodes/enact/enact"
cd "$root"
echo "== enact check launch/scenes/bridge.yaml"
"$enact" check launch/scenes/bridge.yaml
echo
echo "== enact simulate launch/scenes/bridge.yaml --model all   (built-in scripted hand path, 5 kHz, offline)"
"$enact" simulate launch/scenes/bridge.yaml --model all
echo
# a fresh run each time (the runner would resume an earlier one in the same folder)
out="$build/results/bridge_quick"
rm -rf "$out"
echo "== enact experiment launch/experiments/bridge_quick.yaml --out $out   (virtual subjects, co-located graph, about a minute)"
"$enact" experiment launch/experiments/bridge_quick.yaml --out "$out"
echo
echo "== scripts/analyze.py $out/results.csv --out $out/analysis"
/usr/bin/python3 scripts/analyze.py "$out/results.csv" --out "$out/analysis"
