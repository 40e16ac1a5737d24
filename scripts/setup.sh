#!/usr/bin/env bash
# Installs every Debian package StateBench needs (idempotent; sudo when not root) and builds the
# project in Release into build/. Usage: bash scripts/setup.sh [--no-build | --no-bench]
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libyaml-cpp-dev libceres-dev libgeographiclib-dev libtbb-dev
  libbullet-dev libpcl-dev libsqlite3-dev nlohmann-json3-dev
  libzstd-dev  # the compressed lidar sweep files of recorded logs
  # statebench import/export rosbag: ROS1 bag I/O and the message headers it converts
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libtf2-msgs-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev  # bench only: lidar_raycast_bench's Embree comparison
  clang libclang-rt-14-dev  # the compiler; the sanitizer runtimes and libFuzzer (sanitize.sh)
  sumo sumo-tools
  python3 python3-plotly  # the HTML reports (reports/python, docs/reports.md)
  chromium chromium-driver python3-selenium  # the reports' tests in a headless browser
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

# plotly.js for the HTML reports, from npm: the minified "basic" bundle (scatter, bar; about
# 1 MB, where Debian's python3-plotly ships the full bundle unminified, 8.6 MB), at the version
# Debian's python3-plotly 5.4 is built for. Into third_party/npm (not committed); npm's output
# goes to a log file.
PLOTLY_JS_VERSION=2.6.3
PLOTLY_JS="plotly.js-basic-dist-min@$PLOTLY_JS_VERSION"
plotly_dir="third_party/npm/node_modules/plotly.js-basic-dist-min"
plotly_file="$plotly_dir/plotly-basic.min.js"
if [ ! -f "$plotly_file" ] ||
   ! grep -q "\"version\": \"$PLOTLY_JS_VERSION\"" "$plotly_dir/package.json"; then
  if ! command -v npm >/dev/null; then
    mkdir -p build
    echo "setup: installing npm; apt output in build/apt-install.log"
    if ! { $SUDO apt-get update -qq &&
           DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends npm
         } >>build/apt-install.log 2>&1; then
      tail -n 20 build/apt-install.log >&2
      echo "setup: apt-get failed, see build/apt-install.log" >&2
      exit 1
    fi
  fi
  mkdir -p build third_party/npm
  echo "setup: installing $PLOTLY_JS with npm; output in build/npm-install.log"
  if ! npm install --prefix third_party/npm --no-save --no-audit --no-fund "$PLOTLY_JS" \
       >build/npm-install.log 2>&1 || [ ! -f "$plotly_file" ]; then
    tail -n 20 build/npm-install.log >&2
    echo "setup: npm install failed, see build/npm-install.log" >&2
    exit 1
  fi
fi

# SUMO's tools and data live under SUMO_HOME (Debian: /usr/share/sumo).
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"

if [ "${1:-}" != "--no-build" ]; then
  # --no-bench (the test command): the Google Benchmark programs are left out of this build.
  bench=ON
  if [ "${1:-}" = "--no-bench" ]; then bench=OFF; fi
  # clang (also the sanitizer build's compiler): about a quarter less compile time than g++ on
  # this Eigen- and Ceres-heavy code (620 vs 833 CPU seconds for the whole Release build).
  # Ninja when installed (it keeps both cores busy to the end of the build).
  generator=()
  if command -v ninja >/dev/null && [ ! -f build/Makefile ]; then generator=(-G Ninja); fi
  cmake -S . -B build "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Release \
    -DSTATEBENCH_BUILD_BENCHMARKS=$bench
  cmake --build build -j"$(nproc)"
fi
