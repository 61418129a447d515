#!/usr/bin/env bash
# A map by bisection ([bisect], sweep/bisection.hpp) on the farm: the file from 1 rank and from
# 3 ranks is the same, a sweep stopped part-way and resumed gives the same file as one run
# straight through, thresholds --csv prints one row per grid point, and bad input is refused
# naming the file and the key before any work, leaving nothing behind.
# Usage: bisect_sweep_test.sh ASTROJAX MPIEXEC SOURCE_DIR
set -u
bin=$1; mpiexec=$2; src=$3
source "$(dirname "$0")/check.sh"
map="$src/tests/data/bisect_map.toml"

# same NAME A B: /chains, /brackets and /tasks of files A and B identical.
same() {
  for g in /chains /brackets /tasks; do
    check "$1: $g identical" "h5diff '$2' '$3' $g > '$work/diff' 2>&1"
  done
}

"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$map" -o "$work/one.h5" -q > "$work/one.out" 2>&1
check "1 rank: exit 0" "[ $? -eq 0 ]"
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$map" -o "$work/three.h5" -q > "$work/three.out" 2>&1
check "3 ranks: exit 0" "[ $? -eq 0 ]"
same "1 and 3 ranks" "$work/one.h5" "$work/three.h5"
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$map" -o "$work/resumed.h5" -q --max-tasks 9 > "$work/part.out" 2>&1
check "stopped after 9 probes: exit 4, a .part left" "[ $? -eq 4 ] && [ -s '$work/resumed.h5.part' ]"
"$mpiexec" --oversubscribe -n 2 "$bin" sweep "$map" -o "$work/resumed.h5" -q --resume > "$work/resume.out" 2>&1
check "resumed on 2 ranks: exit 0" "[ $? -eq 0 ] && [ -s '$work/resumed.h5' ]"
same "the resumed map and the straight run" "$work/one.h5" "$work/resumed.h5"
"$bin" verify "$work/one.h5" > "$work/verify.out" 2>&1
check "verify: ok" "[ $? -eq 0 ]"
"$bin" thresholds "$work/one.h5" --csv "$work/th.csv" > "$work/th.out" 2>&1
check "thresholds: exit 0" "[ $? -eq 0 ]"
check "thresholds --csv: a header and one row per grid point (4)" "[ \$(wc -l < '$work/th.csv') -eq 5 ]"
check "thresholds --csv: columns for both axes, rows by bisection, converged within 0.1π" \
  "head -1 '$work/th.csv' | grep -q 'contact_distance,drive_radius,method,width_rad_s' &&
   [ \$(grep -c ',bisection,' '$work/th.csv') -eq 4 ] && [ \$(grep -c '\"converged\"' '$work/th.csv') -eq 4 ] &&
   awk -F, 'NR > 1 { w = \$4 - \$5; if (w < 0) w = -w; if (w > 0.3141592654) exit 1 }' '$work/th.csv'"
check "thresholds --csv: the last column is each row's start seed (the file's circular_high)" \
  "head -1 '$work/th.csv' | grep -q ',probes_run,start_seed\$' && [ \$(grep -c ',circular_high\$' '$work/th.csv') -eq 4 ]"
check "thresholds: the table of bisections" "grep -q 'omega_fall' '$work/th.out' && grep -q 'converged' '$work/th.out'"

# Guided by the start level's locked orbit (bisect.guide): the prediction is computed on whichever
# rank runs probe 0, a pure function of its state, so 1 and 3 ranks give the same file again;
# every converged chain has a finite prediction and a bracket one lattice cell (≤ 0.1π) wide.
"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$map" -o "$work/g1.h5" -q --set bisect.guide=held_orbit > "$work/g1.out" 2>&1
check "guided, 1 rank: exit 0" "[ $? -eq 0 ]"
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$map" -o "$work/g3.h5" -q --set bisect.guide=held_orbit > "$work/g3.out" 2>&1
check "guided, 3 ranks: exit 0" "[ $? -eq 0 ]"
same "guided, 1 and 3 ranks" "$work/g1.h5" "$work/g3.h5"
check "guided: /brackets/guide finite and every bracket converged within 0.1π" "/usr/bin/python3 - '$work/g1.h5' <<'PY'
import sys, h5py, numpy as np
b = h5py.File(sys.argv[1])['brackets']
ok = (b['status'][:] == 1).all() and np.isfinite(b['guide'][:]).all()
ok = ok and (np.abs(b['known_omega'][:] - b['other_omega'][:]) <= 0.1 * np.pi + 1e-12).all()
sys.exit(0 if ok else 1)
PY"
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$map" -o "$work/gr.h5" -q --set bisect.guide=held_orbit --max-tasks 7 > "$work/gpart.out" 2>&1
check "guided, stopped after 7 probes: exit 4" "[ $? -eq 4 ] && [ -s '$work/gr.h5.part' ]"
"$mpiexec" --oversubscribe -n 2 "$bin" sweep "$map" -o "$work/gr.h5" -q --set bisect.guide=held_orbit --resume > "$work/gres.out" 2>&1
check "guided, resumed on 2 ranks: exit 0" "[ $? -eq 0 ]"
same "guided, the resumed map and the straight run" "$work/g1.h5" "$work/gr.h5"
check "unguided files have no /brackets/guide" "! h5ls '$work/one.h5/brackets/guide' > /dev/null 2>&1"
"$bin" thresholds "$work/g1.h5" > "$work/gth.out" 2>&1
check "thresholds of a guided map: a guide column, each row's prediction in π rad/s" \
  "grep -q 'probes  guide \[π\]' '$work/gth.out' && [ \$(grep -cE 'converged +[0-9]+/10  3\.[0-9]{3}\$' '$work/gth.out') -eq 4 ]"
check "thresholds of an unguided map: no guide column" "! grep -q 'guide' '$work/th.out'"

# Bad input: exit 2, the file and the key named, nothing written.
bad() {  # NAME EXPECTED-KEY OVERRIDE...
  local name=$1 key=$2; shift 2
  "$bin" sweep "$map" -o "$work/bad.h5" "$@" > "$work/bad.out" 2>&1
  local rc=$?
  check "$name: exit 2 naming bisect_map.toml and '$key' (got $rc: $(head -c 300 "$work/bad.out"))" \
    "[ $rc -eq 2 ] && grep -q 'bisect_map.toml' '$work/bad.out' && grep -q \"key '$key'\" '$work/bad.out' && [ ! -e '$work/bad.h5' ] && [ ! -e '$work/bad.h5.part' ]"
}
bad "a width below what a 20 s window resolves" "bisect.width" --set bisect.width=0.01
bad "a width as wide as the range" "bisect.width" --set bisect.width=5
bad "a grid with one point on an axis" "grid.contact_distance" --set "grid.contact_distance=[0.03]"
bad "a ramp_rate axis" "grid.ramp_rate" --set "grid.ramp_rate=[0.1,0.2]"
bad "ω_fall with to above from" "bisect.to" --set bisect.to=15.0
bad "an unknown threshold" "bisect.threshold" --set bisect.threshold=omega_3
bad "an unknown key" "bisect.widht" --set bisect.widht=0.3
bad "[bisect] beside [protocol]" "bisect" --set protocol.start_omega=1.0
bad "a guide for a threshold that is not a locked orbit's end" "bisect.guide" --set bisect.threshold=omega_2 --set bisect.to=20.0 --set bisect.guide=held_orbit
bad "an unknown guide" "bisect.guide" --set bisect.guide=secant
finish bisect_sweep_test
