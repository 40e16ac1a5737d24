#!/usr/bin/env bash
# The unit tests under AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer, and
# the fuzz targets, in their own build folder (docs/fuzzing.md). .ci/run runs it after the tests.
#   scripts/sanitize.sh [--all] [--full-ubsan] [--fuzz-seconds N] [--build DIR]
# Default (CI): clang -O1, the folders core, estimator and sensors with their tests,
# UBSan without its pointer checks (alignment, null, object-size, pointer-overflow, vptr: they
# double the compile time of this Eigen-heavy code; ASan still catches a null or wild pointer
# when it is used), each fuzz target a fixed number of executions with a fixed seed (about 10 s
# each on CI's machine; the same inputs on every machine). --fuzz-seconds N: N seconds each
# instead. --all: every folder and its tests (about three times
# the build); --full-ubsan: every UBSan check.
set -euo pipefail
cd "$(dirname "$0")/.."
folders="core;estimator;sensors"
exclude="alignment,null,object-size,pointer-overflow,vptr"
fuzz_seconds=""
build=build-asan
while [ $# -gt 0 ]; do
  case "$1" in
    --all) folders="core;estimator;sensors;simulator;reports;apps"; shift ;;
    --full-ubsan) exclude=""; shift ;;
    --fuzz-seconds) fuzz_seconds="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    *) echo "sanitize: unknown argument $1" >&2; exit 2 ;;
  esac
done
command -v clang++ >/dev/null || { echo "sanitize: clang++ is needed (bash scripts/setup.sh)" >&2; exit 1; }
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
generator=()
if command -v ninja >/dev/null && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DSTATEBENCH_SANITIZE=address,undefined \
  -DSTATEBENCH_SANITIZE_EXCLUDE="$exclude" -DSTATEBENCH_FUZZ=ON \
  -DSTATEBENCH_BUILD_BENCHMARKS=OFF -DSTATEBENCH_FOLDERS="$folders" >"$build.configure.log" 2>&1 ||
  { tail -n 20 "$build.configure.log" >&2; exit 1; }
cmake --build "$build" -j"$(nproc)"
ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
  ctest --test-dir "$build" --output-on-failure -j"$(nproc)"
if [ -n "$fuzz_seconds" ]; then
  bash scripts/fuzz.sh --build "$build" --seconds "$fuzz_seconds"
else
  bash scripts/fuzz.sh --build "$build" --seed 1 fuzz_config:20000 fuzz_log_reader:8000 \
    fuzz_estimators:1500
fi
