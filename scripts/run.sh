#!/usr/bin/env bash
# The main job: installs what is missing, builds in Release and runs the default scenarios into
# out/. Extra arguments are passed to every `statebench simulate` call (e.g. --quiet).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
for scenario in scenarios/paper/*.yaml; do
  name=$(basename "$scenario" .yaml)
  ./build/bin/statebench simulate "$scenario" --out "out/$name" "$@"
done
