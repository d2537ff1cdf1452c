#!/usr/bin/env bash
# Set up a fresh Debian machine, build, and run the whole test suite through ctest.
# Exits non-zero on any failure.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
ctest --test-dir "${ENACT_BUILD_DIR:-$root/build}" --output-on-failure --parallel "$(nproc)"
