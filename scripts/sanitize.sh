#!/usr/bin/env bash
# Build the unit tests and the fuzz corpora's replays under AddressSanitizer +
# UndefinedBehaviorSanitizer (folder build-asan: clang, -O0, line tables only, no LTO: the
# quickest build; the instrumentation is the same, and a second compiler reads the code: clang
# took 30-60 % less CPU than gcc for the same files, and the normal build is gcc's) and run
# them: every suite but
# those of whole graphs of processes, the viewer and the experiments (they run in the normal
# build; docs/building.md, "Reliability"). Exits non-zero on any failure or sanitizer report.
# Usage: scripts/sanitize.sh [ctest label regex]   (default: every suite below)
#        scripts/sanitize.sh --build-only          (build, run nothing: .ci/run builds it
#                                                   while the normal suite runs)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ENACT_ASAN_DIR:-$root/build-asan}"
suites=(test_config_yaml test_msgs test_physics test_haptics test_task test_rt test_bus test_record
        test_devices test_falcon test_metec test_usb test_vendor test_inverse3 test_sim test_launch test_graph)
fuzz=(mcap scene model launch path bus param_set falcon metec inverse3)
# enact itself: the launch and device suites run the command line
targets=(enact "${suites[@]}" "${fuzz[@]/#/replay_}")
if [[ ! -f "$build/build.ninja" ]]; then
  # clang from scripts/setup.sh (the fuzz targets' compiler too); gcc where it is missing
  compiler=$(command -v clang++ || command -v g++)
  debug_info=-gline-tables-only
  [[ "$compiler" == *clang* ]] || debug_info=-g1
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER="$compiler" \
    -DCMAKE_CXX_FLAGS_DEBUG="-O0 $debug_info" -DENACT_SANITIZE=address,undefined -DENACT_VIEWER=OFF -DENACT_UNITY="${ENACT_UNITY:-ON}" >/dev/null
fi
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]}"
[[ "${1:-}" == --build-only ]] && exit 0
labels="${1:-^($(IFS='|'; echo "${suites[*]}")|fuzz_replay)\$}"
# handle_segv=0: the drivers' own fatal-signal handlers (zero force, then die of the signal)
# are under test; memory errors are still caught by the instrumentation
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:handle_segv=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# the longest pure-computation checks (minutes under the instrumentation at -O0, the same code
# as the suites' shorter cases, which run here) run in the normal build only: CI stays within
# its time. Under the sanitizers on a 2-vCPU VM (normal build in brackets where measured): the
# mesh search of every pair 167 s (4.3 s); the 44 kHz twins of the 5 kHz bridge and
# deformable-walk cases 11-19 s (1-3.6 s at 5 kHz here); a million-value histogram 17 s (the
# 100,000-value one stays); the no-jolt sweeps over each kind of change, and over every model
# and threshold, 11-21 s (a restore in one tick, a hostile burst and a change beside a hand
# that left stay); the stability runs of 200,000 to a million steps of a few masses, 8-12 s
# each (their shorter siblings, the same integrators and guard, stay: CI22-CI25, 2026-12-02,
# 2-vCPU AMD EPYC VM): a mass ratio of a million, the stiff chains near their bound, the
# exact bound of a mass on its proxy link, implicit Euler at a hundred times the explicit
# bound, the 12-triangle box against the box over 300,000 steps
slow='^(HeldFace\.|Mesh\.TheHeldTriangleAndCullingMatchTheFullSearchOfEveryPairEveryStep$|ColocatedNoJolt\.(EachKindOfChangeAloneNeverMakesTheHandFeelMore|AHostileBurstEndingInARestoreNeverMakesTheHandFeelMore|NoShippedModelOrThresholdMakesTheHandFeelMoreThanTheSceneAsLoaded)$|Bridge/(Identical|DeformableWalk)\..*/.*44000.*|LatencyHistogram\.UniformOneToAMillion$|HardCases\.MassRatioOfAMillion$|Explicit/StiffChain\.NearItsBoundKeepsItsEnergy/.*|Bound\.ExactForAMassOnItsProxyLink$|ImplicitEuler\.HundredTimesTheExplicitBoundStaysBounded$|Mesh\.ABoxAsTwelveTrianglesGivesTheBoxObjectsForces$)'
ctest --test-dir "$build" -L "$labels" -E "$slow" --output-on-failure --parallel "$(nproc)"
