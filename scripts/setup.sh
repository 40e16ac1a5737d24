#!/usr/bin/env bash
# Installs every Debian package StateBench needs (idempotent; sudo when not root) and builds the
# project in Release into build/. Usage: bash scripts/setup.sh [--no-build | --no-bench]
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake pkg-config git
  libeigen3-dev libyaml-cpp-dev libceres-dev libgeographiclib-dev libtbb-dev
  libbullet-dev libpcl-dev libsqlite3-dev nlohmann-json3-dev
  # statebench import/export rosbag: ROS1 bag I/O and the message headers it converts
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libtf2-msgs-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev  # bench only: lidar_raycast_bench's Embree comparison
  clang libclang-rt-14-dev  # scripts/sanitize.sh: sanitizer build and libFuzzer targets
  sumo sumo-tools
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  # apt's output goes to a log file; the user sees one line (and the log's tail on failure).
  mkdir -p build
  log="build/apt-install.log"
  echo "setup: installing ${#missing[@]} packages (${missing[*]}); apt output in $log"
  if ! { $SUDO apt-get update -qq &&
         DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
           "${missing[@]}"; } >"$log" 2>&1; then
    tail -n 20 "$log" >&2
    echo "setup: apt-get failed, see $log" >&2
    exit 1
  fi
  echo "setup: installed ${#missing[@]} packages"
else
  echo "setup: all ${#PACKAGES[@]} packages present"
fi

# SUMO's tools and data live under SUMO_HOME (Debian: /usr/share/sumo).
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"

if [ "${1:-}" != "--no-build" ]; then
  # --no-bench (the test command): the Google Benchmark programs are left out of this build.
  bench=ON
  if [ "${1:-}" = "--no-bench" ]; then bench=OFF; fi
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSTATEBENCH_BUILD_BENCHMARKS=$bench
  cmake --build build -j"$(nproc)"
fi
