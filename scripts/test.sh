#!/usr/bin/env bash
# Builds everything (installing packages first when needed) and runs the whole test suite, then
# the sanitizer build's tests and a short fuzz run (scripts/sanitize.sh; --no-sanitize skips it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --no-bench  # the benchmarks are built by the main command (scripts/run.sh)
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
ctest --test-dir build --output-on-failure -j"$(nproc)"
if [ "${1:-}" != "--no-sanitize" ]; then
  bash scripts/sanitize.sh
fi
