#!/usr/bin/env bash
# A soak of the distributed graph (docs/building.md, "Reliability"; figures: docs/performance.md): launch/bridge.yaml with a logger
# (enact record, from the first tick), two observers attaching and detaching all along
# (enact topic hz / echo), a viewer (SDL's offscreen driver), and a live parameter change
# every 10 s (enact param set). Every process's RSS is sampled every 5 s. At the end:
#   - every process is still alive;
#   - no process's RSS grew more than SOAK_MAX_GROWTH_KB (default 8192) from the end of
#     the warm-up (the first fifth of the run, at least 30 s) to the end;
#   - the recording has zero sequence gaps on every topic (enact info);
#   - enact-ffd's deadline misses (NodeStatus.overruns over its ticks) are at most
#     SOAK_MAX_MISS_PCT percent (default 1; the bench's figure between processes is 0.18 %
#     on a quiet machine), and every parameter change was applied.
# Prints a summary; exits 1 on any failure, 2 on a bad argument.
# Usage: scripts/soak.sh [MINUTES]   (default 30; fractions allowed, e.g. 0.5)
# Environment: ENACT_BUILD_DIR (default build/), SOAK_DIR (kept; default a fresh temp folder,
# removed on success), SOAK_RATE_HZ (default 5000), SOAK_MAX_GROWTH_KB, SOAK_MAX_MISS_PCT.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
minutes="${1:-30}"
if [[ "$minutes" == -h || "$minutes" == --help ]]; then sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0; fi
[[ "$minutes" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "soak.sh: MINUTES must be a number, got '$minutes'" >&2; exit 2; }
bin="${ENACT_BUILD_DIR:-$root/build}/nodes"
enact="$bin/enact/enact"
for b in "$enact" "$bin/enact-viewer/enact-viewer" "$bin/enact-sim/enact-sim"; do
  [[ -x "$b" ]] || { echo "soak.sh: $b is missing: run scripts/build.sh first" >&2; exit 1; }
done
seconds=$(awk -v m="$minutes" 'BEGIN { printf "%d", m * 60 }')
warmup=$(( seconds / 5 > 30 ? seconds / 5 : 30 ))
(( seconds > warmup )) || { echo "soak.sh: run at least 1 minute (the warm-up alone is 30 s)" >&2; exit 2; }
max_growth_kb="${SOAK_MAX_GROWTH_KB:-8192}"
max_miss_pct="${SOAK_MAX_MISS_PCT:-1}"
rate_hz="${SOAK_RATE_HZ:-5000}"
dir="${SOAK_DIR:-$(mktemp -d /tmp/enact-soak-XXXXXX)}"
mkdir -p "$dir"
pids=() loops=()
# observers' loops end with TERM, the graph's processes with INT (a clean stop)
cleanup() {
  for p in "${loops[@]}"; do pkill -TERM -P "$p" 2>/dev/null || true; kill -TERM "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done
  # whatever did not stop on SIGINT within 10 s (the viewer) is terminated
  for _ in $(seq 100); do
    alive=0
    for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    (( alive )) || break
    sleep 0.1
  done
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
echo "soak.sh: $minutes min at $rate_hz Hz, files in $dir; load: $(uptime | sed 's/.*load/load/')"

# the graph, waiting for one observer (the logger, attached as soon as the graph starts)
# before its first tick
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
attach="tcp://127.0.0.1:$port"
"$enact" launch "$root/launch/bridge.yaml" --arg observers=1 --arg rate_hz="$rate_hz" --attach "$attach" >"$dir/launch.log" 2>&1 &
launch_pid=$!
pids+=("$launch_pid")
"$enact" record -o "$dir/soak.mcap" --attach "$attach" --wait 30 >"$dir/record.log" 2>&1 &
record_pid=$!
pids+=("$record_pid")
for _ in $(seq 300); do
  grep -q "observers attach at" "$dir/launch.log" && break
  kill -0 "$launch_pid" 2>/dev/null || break
  sleep 0.1
done
grep -q "observers attach at" "$dir/launch.log" || { echo "soak.sh: the graph did not start:" >&2; cat "$dir/launch.log" >&2; exit 1; }
env -u DISPLAY SDL_VIDEODRIVER=offscreen "$bin/enact-viewer/enact-viewer" --attach "$attach" --fps 10 --size 640x400 \
  >"$dir/viewer.log" 2>&1 &
viewer_pid=$!
pids+=("$viewer_pid")

# two observers that come and go
(while true; do "$enact" topic hz ffd/state --duration 3 --attach "$attach" >/dev/null 2>&1; sleep 1; done) &
loops+=("$!")
(while true; do "$enact" topic echo sim/scene --count 120 --attach "$attach" >/dev/null 2>&1; sleep 2; done) &
loops+=("$!")

# the processes whose memory and life are checked: the launcher, its nodes, logger, viewer
sleep 3
declare -A name_of=([$launch_pid]=launch [$record_pid]=logger [$viewer_pid]=viewer)
for p in $(pgrep -P "$launch_pid"); do name_of[$p]=$(cat "/proc/$p/comm"); done
rss_kb() { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status" 2>/dev/null || echo 0; }
declare -A rss_start rss_peak rss_end
changes=0 refused=0
values=(3000 5000 4000 6000)
models=(CM1 CM2 CM0 CM3)
start=$SECONDS
while (( SECONDS - start < seconds )); do
  sleep 5
  elapsed=$(( SECONDS - start ))
  for p in "${!name_of[@]}"; do
    r=$(rss_kb "$p")
    (( elapsed <= warmup )) && rss_start[$p]=$r
    rss_end[$p]=$r
    (( r > ${rss_peak[$p]:-0} )) && rss_peak[$p]=$r
  done
  if (( elapsed % 10 < 5 )); then
    i=$(( changes % 4 ))
    if (( changes % 2 == 0 )); then set_args=(sim.stiffness_n_per_m "${values[$i]}"); else set_args=(sim.model "${models[$i]}"); fi
    "$enact" param set "${set_args[@]}" --attach "$attach" >>"$dir/param.log" 2>&1 || refused=$((refused + 1))
    changes=$((changes + 1))
  fi
done

# checks
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
echo "process        RSS after warm-up   at the end      peak   growth (kB)"
for p in "${!name_of[@]}"; do
  kill -0 "$p" 2>/dev/null || fail "${name_of[$p]} (pid $p) died"
  growth=$(( ${rss_end[$p]:-0} - ${rss_start[$p]:-0} ))
  printf "%-14s %12s kB %12s kB %9s kB %+9d\n" "${name_of[$p]}" "${rss_start[$p]:-?}" "${rss_end[$p]:-?}" "${rss_peak[$p]:-?}" "$growth"
  (( growth <= max_growth_kb )) || fail "${name_of[$p]} grew $growth kB (bound $max_growth_kb kB)"
done
for p in "${loops[@]}"; do pkill -TERM -P "$p" 2>/dev/null || true; kill -TERM "$p" 2>/dev/null || true; done
(( refused == 0 )) || fail "$refused of $changes parameter changes were not applied (see $dir/param.log)"
kill -INT "$record_pid"
wait "$record_pid" || fail "enact record exited with an error (see $dir/record.log)"
kill -INT "$launch_pid"
wait "$launch_pid" || true
"$enact" info "$dir/soak.mcap" >"$dir/info.txt" || fail "enact info cannot read the recording"
# the gaps column of each topic row (topic, publisher, type, messages, rate, gaps, note)
gaps=$(awk '/^[a-z]/ { on = /^topics:/; next } on && $6 ~ /^[0-9]+$/ { s += $6 } END { print s + 0 }' "$dir/info.txt")
(( gaps == 0 )) || fail "$gaps sequence gaps in the recording (see $dir/info.txt)"
"$enact" export "$dir/soak.mcap" --topic node/status --publisher ffd --csv "$dir/ffd_status.csv" >/dev/null
read -r overruns ticks < <(/usr/bin/python3 - "$dir/ffd_status.csv" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
last = rows[-1]
sent = next(int(last[k.replace(".topic", ".sent")]) for k in last if k.endswith(".topic") and last[k] == "ffd/state")
print(int(last["overruns"]), sent)
EOF
)
miss_pct=$(awk -v o="$overruns" -v t="$ticks" 'BEGIN { printf "%.3f", (t > 0 ? 100 * o / t : 100) }')
awk -v m="$miss_pct" -v b="$max_miss_pct" 'BEGIN { exit !(m + 0 <= b + 0) }' || fail "deadline misses $miss_pct % (bound $max_miss_pct %)"
echo "recording: $(du -h "$dir/soak.mcap" | cut -f1), sequence gaps $gaps; ffd: $ticks ticks, $overruns deadline misses ($miss_pct %);" \
  "parameter changes: $changes, $refused not applied; load at the end: $(uptime | sed 's/.*load/load/')"
if (( failures > 0 )); then
  echo "soak.sh: FAILED ($failures), files kept in $dir"
  exit 1
fi
echo "soak.sh: passed"
[[ -n "${SOAK_DIR:-}" ]] || rm -rf "$dir"
