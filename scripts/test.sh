#!/usr/bin/env bash
# Builds everything (installing packages first when needed) and runs the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
ctest --test-dir build --output-on-failure -j"$(nproc)"
