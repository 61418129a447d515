#!/usr/bin/env bash
# The holds and refinements of `astrojax thresholds` on the farm, side by side
# (docs/reports/threshold-maps.md): one sweep's thresholds with the default holds and
# --refine F, in one process on one thread (-j 1) and under `mpirun -n 2` (rank 0's master
# with one thread beside it, and one worker rank), alternately REPEAT times; the brackets alone
# (--no-hold, no integration) are timed too, so the holds' and refinements' share is the
# difference. Prints each run's wall and CPU (user + sys, mpirun's ranks included), the
# medians and their ratio, the load average before each run, and checks that every report and
# CSV is the same bytes.
# Usage: tests/bench/thresholds_farm.sh [BUILD_DIR] [SWEEP.toml] [REFINE] [REPEAT]
#        (default: build sweeps/paper.toml 2 3; as root, export OMPI_ALLOW_RUN_AS_ROOT=1
#        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 first)
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=$(realpath "${1:-build}")/astrojax
sweep=${2:-sweeps/paper.toml}
refine=${3:-2}
repeat=${4:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

"$bin" sweep "$sweep" -o "$out/sweep.h5" -q > /dev/null
file="$out/sweep.h5"
# run NAME COMMAND...: appends "wall cpu" to $out/NAME.times; the report to $out/NAME.out/.csv.
run() {
  local name=$1; shift
  local load; load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f "%e %U %S" -o "$out/t" "$@" --csv "$out/$name.csv" > "$out/$name.out" 2> "$out/$name.err"
  read -r wall user sys < "$out/t"
  local cpu; cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')
  echo "$wall $cpu" >> "$out/$name.times"
  printf "  %-22s wall %6.2f s  cpu %6.2f s  (load %s)\n" "$name" "$wall" "$cpu" "$load"
}
echo "thresholds of $sweep with holds and --refine $refine ($(nproc) cores):"
for k in $(seq "$repeat"); do
  run brackets_only "$bin" thresholds "$file" --no-hold
  run one_process_j1 "$bin" thresholds "$file" --refine "$refine" -j 1
  run mpirun_n2 mpirun -n 2 "$bin" thresholds "$file" --refine "$refine"
done
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
for name in brackets_only one_process_j1 mpirun_n2; do
  w=$(cut -d' ' -f1 "$out/$name.times" | median); c=$(cut -d' ' -f2 "$out/$name.times" | median)
  eval "wall_$name=$w; cpu_$name=$c"
  printf "median %-22s wall %6.2f s  cpu %6.2f s\n" "$name" "$w" "$c"
done
awk -v a="$wall_mpirun_n2" -v b="$wall_one_process_j1" -v r="$wall_brackets_only" 'BEGIN {
  printf "wall, mpirun -n 2 / one process: %.2f; the holds and refinements alone (less --no-hold): %.2f\n",
         a / b, (a - r) / (b - r) }'
cmp -s "$out/one_process_j1.out" "$out/mpirun_n2.out" && cmp -s "$out/one_process_j1.csv" "$out/mpirun_n2.csv" \
  && echo "the reports and CSVs are the same bytes" || { echo "the reports differ"; exit 1; }
