#!/usr/bin/env bash
# astrojax thresholds --hold and --sequence, end to end on the tiny sweep across ω_rise
# (R = 2 cm). Checks:
#  - each side is held at the bracket's own ω_m (the middle of its window), for the default
#    5 drag times (5 · 0.018/1.7245e-3 = 52.2 s) rounded up to whole windows;
#  - the energy account of each side closes: P_motor = P_drag + P_friction+impacts + dE/dt to
#    1e-6 of P_motor (the balance closes to 1e-7 per window; the CSV keeps 9 digits);
#  - the fallen pendulum below ω_rise is an orbit the motor sustains: it stays fallen and its
#    |dE/dt| / P_drag is below the derived tolerance m/(2 c_D T) (0.096 for T = 54.5 s);
#  - the verdict follows the rule of sweep/hold_verdict.hpp, re-derived here from the columns;
#  - with --refine, the rate_dependent column; --sequence finds the paper's "rise" step at the
#    bracket; bad --hold values exit 2 before any work;
#  - every chain is listed: on the README's "your own sweep" (quick.toml at R = 5, 10, 20 mm) the
#    5 mm chain, which reaches no threshold, says "nothing reached"; a missing file is one line.
# Usage: thresholds_hold_test.sh ASTROJAX_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"

"$bin" sweep "$src/tests/data/tiny_rise.toml" -o "$work/rise.h5" -q > "$work/sweep.out" 2>&1
check "sweep: exit 0" "[ $? -eq 0 ]"
"$bin" thresholds "$work/rise.h5" --hold -j 2 --csv "$work/hold.csv" > "$work/hold.out" 2>&1
check "--hold: exit 0" "[ $? -eq 0 ]"
# Columns by name, from the header.
col() { awk -F, -v name="$1" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) print i }' "$work/hold.csv"; }
row=$(grep ',omega_rise,' "$work/hold.csv")
get() { echo "$row" | awk -F, -v i="$(col "$1")" '{ print $i }'; }
check "the sweep crosses ω_rise" "[ -n \"$(get mid_rad_s)\" ]"
check "held at the bracket's ω_m" \
  "awk -v a=$(get pre_omega_rad_s) -v b=$(get before_rad_s) -v c=$(get post_omega_rad_s) -v d=$(get after_rad_s) \
     'BEGIN { exit !(a - b < 1e-9 * b && b - a < 1e-9 * b && c - d < 1e-9 * d && d - c < 1e-9 * d) }'"
# The windows: the ramp's 2π rad/s at 0.5 rad/s² in 3 windows of 4.19 s, one bracket apart.
for side in pre post; do
  check "$side: hold of 5 drag times rounded up to whole windows" \
    "awk -v h=$(get ${side}_hold_s) -v b=$(get before_rad_s) -v a=$(get after_rad_s) 'BEGIN { w = (a - b) / 0.5;
       t = 5 * 0.018 / 1.7245e-3; n = h / w; exit !(h >= t && h < t + w && n - int(n + 0.5) < 1e-6 && int(n + 0.5) - n < 1e-6) }'"
done
for side in pre post; do
  check "$side: P_motor = P_drag + P_other + dE/dt" \
    "awk -v m=$(get ${side}_motor_power_W) -v d=$(get ${side}_drag_power_W) -v o=$(get ${side}_friction_impact_power_W) \
         -v e=$(get ${side}_energy_rate_W) 'BEGIN { r = m - d - o - e; if (r < 0) r = -r; exit !(m > 0 && r <= 1e-6 * m) }'"
done
check "pre: the sweep saw fallen, and held it stays fallen" \
  "[ \"$(get pre_class)\" = fallen ] && [ \"$(get pre_final_class)\" = fallen ]"
check "pre: sustained, |r| below m/(2 c_D T)" \
  "awk -v r=$(get pre_ratio) -v s=$(get pre_sustained) -v dt=$(get pre_determined) \
     -v h=$(get pre_hold_s) 'BEGIN { t = 0.018 / (2 * 1.7245e-3 * h); if (r < 0) r = -r; exit !(s == 1 && dt == 1 && r <= t) }'"
# The rule: pre kept its class and is sustained; post ends in another class -> bifurcation, in
# the old class -> excursion; pre changed class or is not sustained -> time-limited.
verdict=$(get verdict)
expected=$(awk -v pc=$(get pre_class) -v pf=$(get pre_final_class) -v ps=$(get pre_sustained) \
               -v pd=$(get pre_determined) -v qf=$(get post_final_class) 'BEGIN {
  if (pd != 1 && pc == pf) print "undecided";
  else if (pf != pc || ps != 1) print "time-limited transient";
  else if (qf != pc) print "bifurcation";
  else print "excursion" }')
check "verdict '$verdict' follows the rule ('$expected')" "[ \"$expected\" = \"$verdict\" ]"
check "printed: the verdict in the table and its reason with both sides" \
  "grep -E '^  ω_rise .* $verdict \\[1\\]' '$work/hold.out' && grep -q \"\\[1\\] ω_rise of chain 0[^:]*: $verdict: held at\" '$work/hold.out'"
# The holds are the default; --no-hold gives the brackets alone.
"$bin" thresholds "$work/rise.h5" --csv "$work/default.csv" > "$work/default.out" 2>&1
check "holds by default: the CSV has the verdict" "head -1 '$work/default.csv' | grep -q ',verdict,' && grep -q ',omega_rise,.*,$verdict,' '$work/default.csv'"
"$bin" thresholds "$work/rise.h5" --no-hold --csv "$work/nohold.csv" > "$work/nohold.out" 2>&1
check "--no-hold: no verdict column, 'not judged' printed" "! head -1 '$work/nohold.csv' | grep -q verdict && grep -q 'not judged' '$work/nohold.out'"

"$bin" thresholds "$work/rise.h5" --refine 2 --hold 30 -j 2 --csv "$work/both.csv" > /dev/null 2>&1
check "--refine with --hold: exit 0" "[ $? -eq 0 ]"
check "--refine with --hold: rate_dependent yes or no on the ω_rise row" \
  "head -1 '$work/both.csv' | grep -q ',rate_dependent$' && grep ',omega_rise,' '$work/both.csv' | grep -Eq ',(yes|no)$'"

"$bin" thresholds "$work/rise.h5" --sequence --sequence-csv "$work/seq.csv" > "$work/seq.out" 2>&1
check "--sequence: exit 0" "[ $? -eq 0 ]"
check "--sequence: the rise step present at the bracket's midpoint" \
  "grep ',step,' '$work/seq.csv' | grep ',rise,present,' | awk -F, -v m=$(get mid_rad_s) \
     '{ d = \$7 - m; if (d < 0) d = -d; exit !(d < 1e-6 * m) }'"
check "--sequence: printed against the paper" "grep -q 'rise *present' '$work/seq.out'"

for bad in -3 abc 0tau 1e9; do
  "$bin" thresholds "$work/rise.h5" --hold "$bad" > "$work/bad.out" 2>&1
  check "--hold $bad: exit 2 naming --hold" "[ $? -eq 2 ] && grep -q -- '--hold' '$work/bad.out'"
done

"$bin" sweep "$src/sweeps/quick.toml" -o "$work/own.h5" -q --set "grid.drive_radius=[0.005,0.01,0.02]" > /dev/null 2>&1
"$bin" thresholds "$work/own.h5" --no-hold > "$work/own.out" 2>&1
check "every chain listed: exit 0" "[ $? -eq 0 ]"
check "every chain listed: the 5 mm chain says nothing reached" \
  "grep -E '^ *\(none\) +0 drive_radius=0.005 +nothing reached' '$work/own.out'"
check "every chain listed: the others have their ω_rise" \
  "grep -cE '^ *ω_rise +[12] drive_radius' '$work/own.out' | grep -qx 2"
"$bin" thresholds "$work/none.h5" > "$work/none.out" 2>&1
check "a missing file: exit 2, one line naming it" \
  "[ $? -eq 2 ] && [ \$(wc -l < '$work/none.out') -eq 1 ] && grep -q 'none.h5: no such file' '$work/none.out'"

finish "thresholds_hold"
