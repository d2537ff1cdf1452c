#!/usr/bin/env bash
# Configure (once) and build enact with Ninja into build/. Extra arguments are ninja targets.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ENACT_BUILD_DIR:-$root/build}"
if [[ ! -f "$build/build.ninja" ]]; then
  # ENACT_LTO=OFF in the environment: no link-time optimisation (CI's tests: an LTO link
  # generates the libraries' code again for each of some 50 executables); ENACT_UNITY=ON:
  # unity builds (a clean build in less CPU, an edit recompiles its whole batch)
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DENACT_LTO="${ENACT_LTO:-ON}" -DENACT_UNITY="${ENACT_UNITY:-OFF}" >/dev/null
fi
cmake --build "$build" --parallel "$(nproc)" ${1:+--target} "$@"
