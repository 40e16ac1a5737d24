#!/usr/bin/env bash
# Runs the libFuzzer targets of tests/fuzz (docs/fuzzing.md).
#   scripts/fuzz.sh [--build DIR] [--seconds N] [--seed S] [--timeout T] [TARGET[:RUNS] ...]
# DIR: a build configured with clang and -DSTATEBENCH_FUZZ=ON (scripts/sanitize.sh makes
# build-asan); default build-asan. --seconds N: N seconds per target (default 60). TARGET:RUNS
# runs that target RUNS times instead, with libFuzzer's seed S (default 1): the same executions
# on every machine, as CI wants (a time budget would fuzz further on a faster machine).
# --timeout T: an input running longer than T seconds is a finding (default 1, the limit the
# project holds itself to; on a loaded machine a scheduling stall can pass 1 s, so a longer T
# with the final report's slowest_unit_time_sec checked against 1 s is the honest alternative).
# TARGETs: default all three (fuzz_config, fuzz_log_reader, fuzz_estimators).
# Seeds come from the project's own files (tests/fuzz/make_seeds.py: the scenarios, setups,
# options and vehicles, and 0.3 s logs recorded with build/bin/statebench); each target keeps
# its working corpus in DIR/fuzz/<target>/corpus and its findings (crash-*, leak-*, timeout-*:
# an input that takes over 1 s) in DIR/fuzz/<target>/. Exit status 1 on any finding.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-asan
seconds=60
seed=""
timeout=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_config fuzz_log_reader fuzz_estimators)
export STATEBENCH_SOURCE_DIR="$PWD" SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"

seeds="$build/fuzz/seeds"
if [ ! -d "$seeds" ]; then
  statebench=build/bin/statebench
  [ -x "$statebench" ] || { echo "fuzz: $statebench is needed to record the seed log (bash scripts/setup.sh)" >&2; exit 1; }
  log=$(mktemp -d)
  trap 'rm -rf "$log"' EXIT
  # Three logs: lidar sweeps as packets files (the default), sweep files and PCDs.
  "$statebench" record scenarios/paper/setup3_shuttle.yaml --duration 0.3 --out "$log/log" >/dev/null 2>&1
  for format in sweep pcd; do
    "$statebench" record scenarios/paper/setup3_shuttle.yaml --duration 0.3 --out "$log/log_$format" \
      --lidar-format "$format" >/dev/null 2>&1
  done
  python3 tests/fuzz/make_seeds.py "$PWD" "$log/log" "$seeds" "$log/log_sweep" "$log/log_pcd"
fi

# One target per core at a time.
run_target() {
  local t="${1%%:*}" budget=(-max_total_time="$seconds")
  local bin="$build/bin/$t" work="$build/fuzz/$t" start
  if [ "$t" != "$1" ]; then
    budget=(-runs="${1#*:}" -seed="${seed:-1}")
  elif [ -n "$seed" ]; then
    budget+=(-seed="$seed")
  fi
  [ -x "$bin" ] || { echo "fuzz: no $bin (configure with -DSTATEBENCH_FUZZ=ON and clang)" >&2; return 1; }
  mkdir -p "$work/corpus" "$work/tmp"
  start=$(date +%s)
  # The targets' scratch folders go under $work/tmp (a crashing input skips their clean-up).
  if TMPDIR="$work/tmp" ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1" \
     UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
     "$bin" "${budget[@]}" -timeout="$timeout" -rss_limit_mb=4096 -max_len=65536 \
       -artifact_prefix="$work/" -print_final_stats=1 "$work/corpus" "$seeds/$t" \
       >"$work/log.txt" 2>&1; then
    local runs
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/log.txt" | grep -o '[0-9]*$' || echo "?")
    local slowest
    slowest=$(grep -o 'stat::slowest_unit_time_sec: *[0-9]*' "$work/log.txt" | grep -o '[0-9]*$' || echo "?")
    echo "fuzz: $t: $runs executions in $(( $(date +%s) - start )) s, no finding (slowest input ${slowest} s)"
  else
    echo "fuzz: $t: FINDING, see $work/log.txt and $work/" >&2
    tail -n 30 "$work/log.txt" >&2
    return 1
  fi
}

status=0
pids=()
for t in "${targets[@]}"; do
  if [ ${#pids[@]} -ge "$(nproc)" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
  run_target "$t" &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
