#!/usr/bin/env bash
# Benchmark (not a test): every shipped sweep whose header states its cost, run once with one
# process, its CPU (user + sys, /usr/bin/time) printed beside the header's "Cost:" line, so that
# a header whose figure has drifted shows. CPU time grows with contention on a shared machine:
# the load average is printed with each row.
#
#   tests/bench/sweep_costs.sh build/astrojax [SWEEP.toml ...]   (default: every sweeps/**/*.toml
#                                                                   with a measured "Cost:" line)
set -u
bin=$(realpath "$1"); shift
src=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
if [ $# -eq 0 ]; then
  mapfile -t files < <(cd "$src" && grep -l "^# Cost: [0-9.]* s of CPU" sweeps/*.toml sweeps/*/*.toml)
else
  files=("$@")
fi
printf '%-34s %10s %10s %6s  %s\n' sweep "stated [s]" "CPU [s]" load "the header says"
for f in "${files[@]}"; do
  path=$f; [ -f "$path" ] || path=$src/$f
  stated=$(grep -m1 -o "^# Cost: [0-9.]* s of CPU" "$path" | grep -o "[0-9.]*" | head -1)
  line=$(grep -m1 "^# Cost:" "$path" | cut -c9-70)
  args=(sweep "$path" -q -o "$work/out.h5" --force)
  grep -q "^\[protocol\]\|^\[hold\]\|^\[\[group\]\]\|^\[grid\]\|^\[bisect\]" "$path" || args=(run "$path" -q -o "$work/out.h5" --force)
  grep -q "^\[orbits\]" "$path" && args=(orbits "$path")
  cmd=${args[0]}
  load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f "%U %S" -o "$work/t" "$bin" "${args[@]}" > "$work/log" 2>&1 \
    || { echo "$f: astrojax $cmd failed: $(tail -1 "$work/log")"; continue; }
  cpu=$(awk '{printf "%.1f", $1 + $2}' "$work/t")
  printf '%-34s %10s %10s %6s  %s\n' "$f" "${stated:--}" "$cpu" "$load" "$line"
  rm -f "$work/out.h5"
done
