#!/usr/bin/env bash
# The main job: installs what is missing, builds in Release and runs the paper's suite
# (`statebench suite scenarios/paper`): every scenario of scenarios/paper/ end to end (SUMO
# traffic, exact truth, every sensor of the setup, each estimator the scenario names, scored
# against truth), two at a time, into out/paper/<scenario>/; then prints Table I of the paper side
# by side with ours and writes out/paper/table1.md, table1.json and suite.json.
# Extra arguments go to `statebench suite` (e.g. --jobs 1, --duration 60, --quiet).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
./build/bin/statebench suite scenarios/paper --out out/paper "$@"
