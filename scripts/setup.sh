#!/usr/bin/env bash
# Install every system dependency of enact from Debian packages, when missing.
# Idempotent: prints nothing and touches nothing when all are present;
# runs `apt-get update` once first when something must be installed.
# Installs Node.js and npm (when the commands are absent) and the npm packages of the interop
# tests (tests/interop/package.json: the MCAP reader, Foxglove's WebSocket client) into
# .deps/npm (the build ignores that folder), so they run on every fresh machine, CI included.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

# the independent MCAP reader of the interop test, from the npm registry
npm_deps() {
  command -v npm >/dev/null || return 0
  local dir="$root/.deps/npm"
  if [[ -d "$dir/node_modules/@mcap/core" && -d "$dir/node_modules/@foxglove/ws-protocol" ]] && cmp -s "$root/tests/interop/package.json" "$dir/package.json"; then return 0; fi
  echo "setup.sh: installing the MCAP interop test's npm packages into .deps/npm"
  mkdir -p "$dir"
  cp "$root/tests/interop/package.json" "$dir/package.json"
  npm install --prefix "$dir" --no-audit --no-fund --loglevel=error >/dev/null || echo "setup.sh: npm install failed: the MCAP interop test will say so" >&2
}

packages=(
  # build
  cmake ninja-build g++ pkg-config
  # bus: ZeroMQ + cppzmq, Protobuf + protoc
  libzmq3-dev cppzmq-dev libprotobuf-dev protobuf-compiler
  # devices, config; height maps from 16-bit PNG
  libusb-1.0-0-dev libyaml-cpp-dev libpng-dev
  # the Foxglove bridge: WebSocket server over standalone asio, JSON
  libwebsocketpp-dev libasio-dev nlohmann-json3-dev
  # recordings: MCAP chunk compression and CRC-32 (ISA-L's, zlib's to combine them)
  libzstd-dev liblz4-dev zlib1g-dev libisal-dev
  # the live viewer: Dear ImGui (with its SDL2 and OpenGL 3 backends) and stb, SDL2, OpenGL
  # headers; Mesa's software OpenGL and Xvfb for snapshots and its tests without a screen
  libimgui-dev libstb-dev libsdl2-dev libgl-dev libgl1-mesa-dri libegl-mesa0 xvfb
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # enact bench loop's peer arm: Cyclone DDS's ddsperf ping/pong beside our round trip
  cyclonedds-tools
  # enact bench physics's peer arm: the Open Dynamics Engine stepping the same bridge
  libode-dev
  # analysis and plotting scripts (run under /usr/bin/python3)
  python3 python3-scipy python3-matplotlib python3-zmq python3-protobuf python3-yaml
  # sweeps beyond one machine (enact sweep): a single-node Slurm for scripts/slurm_local.sh and
  # the tests, and Dask distributed (scripts/dask_sweep.py)
  slurm-wlm munge python3-distributed
  # fuzz targets (scripts/fuzz.sh): clang with libFuzzer and the sanitizer runtimes
  clang libclang-rt-14-dev
)

# the independent MCAP reader's runtime, checked by command: a machine may have Node.js from
# elsewhere (any version >= 18 reads our files), in which case nothing is installed
declare -A by_command=([node]=nodejs [npm]=npm)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
for c in "${!by_command[@]}"; do
  command -v "$c" >/dev/null || missing+=("${by_command[$c]}")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  npm_deps
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup.sh: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "setup.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup.sh: done"
npm_deps
