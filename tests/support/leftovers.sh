#!/usr/bin/env bash
# Run by ctest after every test that starts graphs (the fixture graph_processes): fails, naming
# each one and the test that started it, when a process those tests started is still alive
# (they all carry ENACT_TEST_RUN=$1 in their environment). Waits a few seconds first: a graph
# stopping at the end of a test may take a moment. Leftovers are killed after being named.
set -uo pipefail
run_id="$1"
wait_s="${2:-15}"
marker="ENACT_TEST_RUN=$run_id"

# pids (not ours) whose environment holds the marker
leftovers() {
  local env pid
  for env in /proc/[0-9]*/environ; do
    pid="${env#/proc/}"
    pid="${pid%/environ}"
    [[ "$pid" == "$$" ]] && continue
    if { tr '\0' '\n' < "$env"; } 2>/dev/null | grep -qxF "$marker"; then echo "$pid"; fi
  done
}

for ((i = 0; i < wait_s * 10; ++i)); do
  [[ -z "$(leftovers)" ]] && { echo "leftovers.sh: no process left behind by the graph tests"; exit 0; }
  sleep 0.1
done
status=0
for pid in $(leftovers); do
  test_name="$({ tr '\0' '\n' < "/proc/$pid/environ"; } 2>/dev/null | sed -n 's/^ENACT_TEST_NAME=//p')"
  cmd="$({ tr '\0' ' ' < "/proc/$pid/cmdline"; } 2>/dev/null)"
  [[ -z "$cmd" ]] && continue  # gone meanwhile
  echo "leftovers.sh: pid $pid still runs ${wait_s} s after the graph tests ended: $cmd (started by ${test_name:-an unnamed test})"
  kill -KILL "$pid" 2>/dev/null
  status=1
done
exit "$status"
