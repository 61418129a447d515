#!/usr/bin/env bash
# The early stop's benchmark (docs/reports/early-stop-and-every-core.md): every shipped sweep
# with settling run with and without it, side by side in one run, one process each; prints the
# CPU ratio (user + sys) and checks that every window's class and every threshold is the same
# (tests/early_stop_test.py). With BASELINE, the runs without it use that build (e.g. main's,
# which has no early stop) instead of --set protocol.early_stop=false.
# Usage: tests/bench/early_stop.sh [BUILD_DIR] [BASELINE_ASTROJAX] [SWEEP.toml ...]
#        (default: the main job alone; ALL=1 for every shipped sweep with settling, ~10 CPU-minutes)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
baseline=${2:-}
shift $(( $# < 2 ? $# : 2 ))
sweeps=("$@")
if [ ${#sweeps[@]} -eq 0 ]; then
  if [ "${ALL:-0}" = 1 ]; then
    sweeps=(sweeps/paper.toml sweeps/table1.toml sweeps/hold.toml sweeps/parameter_study.toml sweeps/rise.toml
            sweeps/rise_kicks.toml sweeps/table1_staircase.toml sweeps/adequacy/hold.toml)
  else
    sweeps=(sweeps/paper.toml)
  fi
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
/usr/bin/python3 tests/early_stop_test.py "$build/astrojax" . "$out" "${sweeps[@]}" ${baseline:+--baseline "$baseline"}
