#!/usr/bin/env bash
# astrojax thresholds --refine: re-running a bracket from the file's stored state at the same
# rate (factor 1) gives back the sweep's own bracket exactly; 3× slower gives a bracket inside
# the two old windows and narrower than the old one. Bad factors exit 2.
# Usage: thresholds_refine_test.sh ASTROJAX_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"

"$bin" sweep "$src/tests/data/tiny_rise.toml" -o "$work/rise.h5" -q > "$work/sweep.out" 2>&1
check "sweep: exit 0" "[ $? -eq 0 ]"
"$bin" thresholds "$work/rise.h5" --refine 1 --csv "$work/r1.csv" > "$work/r1.out" 2>&1
check "refine 1: exit 0" "[ $? -eq 0 ]"
# Columns: 4 before, 5 after (the sweep's), 10 refined_before, 11 refined_after.
rise1=$(grep ',omega_rise,' "$work/r1.csv")
check "the sweep crosses ω_rise" "[ -n \"\$(echo '$rise1' | cut -d, -f4)\" ]"
check "refine 1 reproduces the sweep's ω_rise bracket exactly" \
  "echo '$rise1' | awk -F, '{exit !(\$4 == \$10 && \$5 == \$11)}'"
"$bin" thresholds "$work/rise.h5" --refine 3 -j 2 --csv "$work/r3.csv" > "$work/r3.out" 2>&1
check "refine 3: exit 0" "[ $? -eq 0 ]"
rise3=$(grep ',omega_rise,' "$work/r3.csv")
# The old windows' outer edges: each window spans rate · window = 0.5 · 4 ... rad/s around its
# mean; the refined bracket must lie within [before − half a window, after + half a window].
check "refine 3: a bracket inside the old windows and narrower than the old bracket" \
  "echo '$rise3' | awk -F, '{h = (\$5 - \$4) / 2; exit !(\$10 != \"\" && \$10 >= \$4 - h && \$11 <= \$5 + h && (\$11 - \$10) < (\$5 - \$4))}'"
check "refine 3: printed with its factor" "grep -q '3× slower' '$work/r3.out'"
"$bin" thresholds "$work/rise.h5" --refine 0 > /dev/null 2>&1
check "refine 0: exit 2" "[ $? -eq 2 ]"

finish "thresholds_refine"
