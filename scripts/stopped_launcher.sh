#!/usr/bin/env bash
# The distributed loop while its launcher is stopped (Ctrl-Z, a debugger): runs
# `enact launch launch/bridge.yaml` for 20 s, stops the launcher (SIGSTOP) for STOP_S seconds
# (default 5) from the 7th second, continues it, and prints the FFD driver's verdict (samples
# without an answer in time, watchdog episodes: the force cuts). Runs it RUNS times (default 3).
# usage: scripts/stopped_launcher.sh [RUNS] [STOP_S]   (ENACT_BUILD_DIR: the build, default build/)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
enact="${ENACT_BUILD_DIR:-$root/build}/nodes/enact/enact"
runs="${1:-3}"
stop_s="${2:-5}"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
for ((i = 1; i <= runs; ++i)); do
  "$enact" launch "$root/launch/bridge.yaml" --duration 20 >"$log" 2>&1 &
  pid=$!
  sleep 7
  kill -STOP "$pid"
  sleep "$stop_s"
  kill -CONT "$pid"
  wait "$pid" || { cat "$log"; echo "stopped_launcher.sh: the graph failed" >&2; exit 1; }
  echo "run $i, launcher stopped ${stop_s} s: $(grep -o 'ffd: verdict: .*' "$log")"
  grep -o 'ffd: [0-9]* watchdog episode.*\|ffd: no watchdog episode' "$log" | head -1 | sed 's/^/  /'
done
grep -o 'enact launch: this machine wakes .*' "$log" | head -1
