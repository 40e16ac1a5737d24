#!/usr/bin/env bash
# The main job: installs what is missing, builds in Release and runs the paper's scenarios
# (scenarios/paper/*.yaml) end to end: SUMO traffic, exact truth, every sensor of the setup, and
# the factor graph and the EKF baseline scored against truth, into out/<scenario>/.
# Extra arguments are passed to every `statebench run` call (e.g. --quiet, --duration 60).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
for scenario in scenarios/paper/*.yaml; do
  name=$(basename "$scenario" .yaml)
  ./build/bin/statebench run "$scenario" --out "out/$name" "$@"
done
