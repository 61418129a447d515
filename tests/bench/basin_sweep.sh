#!/usr/bin/env bash
# The basin sweep's CPU time against issue 29's target: sweeps/basins.toml's 16 levels × 200
# samples × 2 variants (6400 chains a group) in at most 10 CPU-minutes. Runs each group of the
# file alone with N samples per level (default 20, a tenth), in one process, and prints its CPU
# time (user + sys), the simulated seconds, and the extrapolation to N = 200 (the cost is linear
# in N: every sample is its own chain of the same length), with the ratio to the target.
# Figures printed, never asserted; on a shared machine user time grows with contention.
# Usage: tests/bench/basin_sweep.sh ASTROJAX [N]   (from the repository's root)
set -u
bin=${1:-build/astrojax}; n=${2:-20}
toml=sweeps/basins.toml
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
groups=$(sed -n 's/^name = "\(.*\)"/\1/p' "$toml")
printf "basin sweep %s with N = %s per level (target: N = 200, 6400 chains a group, 600 CPU s)\n" "$toml" "$n"
for g in $groups; do
  # The file with this group's [[group]] block only.
  awk -v g="$g" '/^\[\[group\]\]/ || /^\[output\]/ { if (buf != "" && keep) printf "%s", buf; buf = ""; keep = 0; grp = /group/ }
                 grp { buf = buf $0 "\n"; if ($0 == "name = \"" g "\"") keep = 1; next } { print }' "$toml" > "$work/$g.toml"
  TIMEFORMAT="%U %S"
  { time "$bin" sweep "$work/$g.toml" -o "$work/$g.h5" -q --force --set "basin.samples=$n" > "$work/$g.out" 2>&1; } 2> "$work/$g.time"
  read -r user sys < "$work/$g.time"
  cpu=$(echo "$user + $sys" | bc -l)
  sim=$(sed -n 's/.* \([0-9]*\) of \([0-9]*\) simulated s.*/\2/p' "$work/$g.out")
  full=$(echo "$cpu * 200 / $n" | bc -l)
  printf "  group %-8s CPU %7.1f s for %s simulated s (%.0f simulated s per CPU s); at N = 200: %6.0f CPU s, ratio to 600 s: %.2f\n" \
    "$g" "$cpu" "$sim" "$(echo "$sim / $cpu" | bc -l)" "$full" "$(echo "$full / 600" | bc -l)"
done
