#!/usr/bin/env bash
# Build the fuzz targets of tests/fuzz with clang, libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer (folder build-fuzz) and run each for SECONDS (default 60),
# starting from its corpus tests/fuzz/corpus/NAME (README, "Reliability").
#   - new inputs go to build-fuzz/corpus/NAME; with --merge, those that reach new code are
#     added to tests/fuzz/corpus/NAME (commit them: they are replayed by ctest);
#   - a crash is written into tests/fuzz/corpus/NAME (crash-..., leak-..., timeout-...), so
#     it fails its replay test (ctest -L fuzz_replay) until fixed, and stays there after;
#     the script then exits 1.
# Usage: scripts/fuzz.sh [SECONDS] [--merge] [TARGET...]   (targets: every one by default)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ENACT_FUZZ_DIR:-$root/build-fuzz}"
seconds=60 merge=0 targets=()
for a in "$@"; do
  case "$a" in
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --merge) merge=1 ;;
    [0-9]*) seconds="$a" ;;
    -*) echo "fuzz.sh: unknown option '$a' (see --help)" >&2; exit 2 ;;
    *) targets+=("$a") ;;
  esac
done
all=(mcap scene model launch path bus param_set falcon metec inverse3)
(( ${#targets[@]} )) || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz.sh: no target '$t' (targets: ${all[*]})" >&2; exit 2; }
done
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ is missing: run scripts/setup.sh" >&2; exit 1; }
if [[ ! -f "$build/build.ninja" ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="-O1 -g" \
    -DENACT_FUZZ=ON -DENACT_SANITIZE=address,undefined -DENACT_VIEWER=OFF >/dev/null
fi
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
failed=()
for t in "${targets[@]}"; do
  corpus="$root/tests/fuzz/corpus/$t"
  fresh="$build/corpus/$t"
  mkdir -p "$fresh"
  echo "fuzz.sh: $t for $seconds s"
  if ! "$build/tests/fuzz/fuzz_$t" "$fresh" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=8192 -artifact_prefix="$corpus/" -print_final_stats=1 >"$build/fuzz_$t.log" 2>&1; then
    failed+=("$t")
    grep -m 3 -E "ERROR|SUMMARY|Test unit written" "$build/fuzz_$t.log" || tail -5 "$build/fuzz_$t.log"
  fi
  grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$build/fuzz_$t.log" | tail -1 || true
  if (( merge )); then
    "$build/tests/fuzz/fuzz_$t" -merge=1 -artifact_prefix="$build/" "$corpus" "$fresh" >>"$build/fuzz_$t.log" 2>&1 || true
  fi
done
if (( ${#failed[@]} )); then
  echo "fuzz.sh: findings in: ${failed[*]} (inputs in tests/fuzz/corpus/NAME; logs in $build/fuzz_NAME.log)"
  exit 1
fi
echo "fuzz.sh: no findings"
