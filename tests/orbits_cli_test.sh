#!/usr/bin/env bash
# astrojax orbits end to end: bad input exits 2 naming the file or option, the key and the
# allowed range, before any work; a good call prints the orbits and writes CSV and HDF5.
# Usage: orbits_cli_test.sh ASTROJAX_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"
cfg="$src/sweeps/orbits.toml"

bad() {  # name, expected text 1, expected text 2, then arguments
  local name=$1 t1=$2 t2=$3; shift 3
  "$bin" orbits "$cfg" --csv "$work/$name.csv" "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  check "$name: exit code 2 (got $rc)" "[ $rc -eq 2 ]"
  check "$name: message has '$t1'" "grep -qF -- '$t1' '$work/$name.err'"
  check "$name: message has '$t2'" "grep -qF -- '$t2' '$work/$name.err'"
  check "$name: no CSV written" "[ ! -e '$work/$name.csv' ]"
}
bad negative_omega "orbits.omega[0]" "(0, 2000]" --set orbits.omega=-1.0
bad omega_word "--omega" "4.7pi" --omega fast
bad unknown_parameter "colour" "drive_radius" --continue colour
bad unknown_key "orbits.colour" "unknown key" --set orbits.colour=1
bad s_off_string "orbits.s[0]" "the stops" --set orbits.s=0.9
bad bad_range "orbits.range" "lo < hi" --set "orbits.range=[2.0,1.0]"
bad lag_rigid_tie "layers.tie" "clutch" --lag --s 0.4589
bad lag_without_s "--lag" "--s" --lag --set layers.tie=clutch --set model.tie_static_torque=1e-3 \
  --set model.tie_kinetic_torque=9e-4
# --map: the second parameter is a continuation parameter (the list named), not ω; --s given;
# the curves known, hopf only with the clutch; the range contains the model's value.
bad map_not_continuation "top_stop" "not a continuation parameter; allowed: s, string_length" --map top_stop --s 0.4589
bad map_omega "omega" "not a continuation parameter; allowed: s, string_length" --map omega --s 0.4589
bad map_without_s "--map" "--s" --map drive_radius
bad map_hopf_rigid "layers.tie" "clutch" --map drive_radius --s 0.4589 --curves hopf
bad map_unknown_curve "--curves" "cone_down" --map drive_radius --s 0.4589 --curves wobble
bad map_range "--range 0.02 0.03" "drive_radius = 0.01" --map drive_radius --s 0.4589 --range 0.02 0.03
bad map_with_continue "--map cannot be combined" "--continue" --map drive_radius --s 0.4589 --continue omega

# --map: the fold and cone_up curves over R at the documented set; the point where they meet is
# found from both curves at the same place.
"$bin" orbits "$src/sweeps/orbits_map.toml" --map drive_radius --range 0.005 0.03 --curves cone_up,fold \
  --curves-csv "$work/map.csv" -o "$work/map.h5" >"$work/map.out" 2>&1
rc=$?
check "map: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "map: fold meets cone_up, from the fold curve" "grep -q 'codim-2: fold+cone_up  *at drive_radius = 0.00930[0-9]*, omega_m = 4.626[0-9]*π' '$work/map.out'"
check "map: and from the cone_up curve" "grep -q 'codim-2: cone_up+fold  *at drive_radius = 0.00930[0-9]*, omega_m = 4.626[0-9]*π' '$work/map.out'"
check "map: CSV with header, curve rows and codim-2 rows" "head -1 '$work/map.csv' | grep -q '^row,parameter,curve_id,kind,s,p,omega_m' && grep -q '^curve,drive_radius,' '$work/map.csv' && grep -q '^fold+cone_up,' '$work/map.csv'"
check "map: HDF5 written" "[ -s '$work/map.h5' ] && [ ! -e '$work/map.h5.part' ]"
if command -v h5dump >/dev/null; then
  check "map: the parameter's unit" "h5dump -a /curves/parameter_unit '$work/map.h5' | grep -q '\"m\"'"
fi

# --lag: the one set's lagging orbit at s = 0.4589 m, its Hopf point and the CSV.
"$bin" orbits "$cfg" --lag --s 0.4589 --omega 10pi --set layers.tie=clutch --set model.drive_radius=0.015 \
  --set model.contact_distance=0.035 --set model.tie_kinetic_torque=1.35e-3 --set model.tie_static_torque=1.5e-3 \
  --set model.tie_damping=2e-6 --csv "$work/lag.csv" >"$work/lag.out" 2>&1
rc=$?
check "lag: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "lag: the held, stable lag at 4.243π" "grep -q '^  +/-  *4.243[0-9]*π.*held stable' '$work/lag.out'"
check "lag: its Hopf point" "grep -q 'loss (hopf) +/-  *4.308[0-9]*π' '$work/lag.out'"
check "lag: CSV with header and the Hopf row" "head -1 '$work/lag.csv' | grep -q '^s,kind,side,omega_ball,torque' && grep -q ',loss (hopf),' '$work/lag.csv'"

"$bin" orbits "$cfg" --omega 4.7pi --s-points 21 --continue omega --s 0.5443 --range 14 16 \
  --csv "$work/o.csv" --branches-csv "$work/b.csv" --events-csv "$work/e.csv" -o "$work/o.h5" >"$work/good.out" 2>&1
rc=$?
check "good: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "good: the ω line" "grep -q 'omega_m = 14.765485 rad/s (4.70000π)' '$work/good.out'"
check "good: a cone edge and a frictionless orbit" "grep -q '^  cone_up' '$work/good.out' && grep -q '^  frictionless' '$work/good.out'"
check "good: the fold of the Table-1 branch" "grep -q 'fold  *15.6692' '$work/good.out'"
check "good: CSV with header and rows" "head -1 '$work/o.csv' | grep -q '^branch_id,lambda,omega_m,case' && [ \$(wc -l < '$work/o.csv') -gt 20 ]"
check "good: events CSV" "grep -q ',fold,' '$work/e.csv'"
check "good: HDF5 written" "[ -s '$work/o.h5' ] && [ ! -e '$work/o.h5.part' ]"
if command -v h5dump >/dev/null; then
  check "good: units on /orbits/T1" "h5dump -a /orbits/T1/units '$work/o.h5' | grep -q '\"N\"'"
fi

# --compare: the chains of a sweep with the same model, read by column name; files from before
# the tie clutch's columns (10 of /chains/model's 16) and before the pair couple's (14) are
# matched on what they record; a file whose column names and columns disagree is bad input.
# The sweep crosses ω_rise at orbits.toml's model (R = 1 cm, d = 3 cm).
"$bin" sweep "$src/tests/data/tiny_rise.toml" -o "$work/rise.h5" -q --set model.drive_radius=0.01 >/dev/null 2>&1
cmp_run() {  # name, file
  "$bin" orbits "$cfg" --omega 4.7pi --s-points 11 --threshold-s-points 11 --compare "$2" >"$work/$1.out" 2>&1
}
cmp_run compare "$work/rise.h5"; rc=$?
check "compare: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "compare: its one chain, a rise bracket" \
  "grep -q '(1 chains with this model)' '$work/compare.out' && grep -q 'omega_rise .*chain 0 bracket 1[0-9.]*π' '$work/compare.out'"
check "compare: no note on columns" "! grep -q 'model parameters, not' '$work/compare.out'"
# $3 columns kept, $4 of their names.
for nm in "10 10" "14 14" "12 16"; do
  set -- $nm
  /usr/bin/python3 -c "
import h5py, shutil, sys
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], 'r+') as f:
    names = f['chains/model'].attrs['columns']  # a string array from format 3 on, joined by commas before
    joined = isinstance(names, (bytes, str))
    names = (names.decode() if isinstance(names, bytes) else names).split(',') if joined else [str(n) for n in names]
    m = f['chains/model'][:, :int(sys.argv[3])]
    del f['chains/model']
    d = f.create_dataset('chains/model', data=m)
    if joined:
        d.attrs['columns'] = ','.join(names[:int(sys.argv[4])])
    else:
        d.attrs.create('columns', names[:int(sys.argv[4])], dtype=h5py.string_dtype())" \
    "$work/rise.h5" "$work/rise_$1.h5" $1 $2
done
cmp_run compare_10 "$work/rise_10.h5"; rc=$?
check "compare, 10 columns: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "compare, 10 columns: the chain, matched on those, the missing named" \
  "grep -q '(1 chains with this model)' '$work/compare_10.out' && grep -q 'records 10 of the 16 model parameters, not tie_static_torque, tie_kinetic_torque, tie_inertia, tie_damping, couple_torque, couple_slip_rate' '$work/compare_10.out'"
cmp_run compare_14 "$work/rise_14.h5"; rc=$?
check "compare, 14 columns: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "compare, 14 columns: the chain, matched on those" \
  "grep -q '(1 chains with this model)' '$work/compare_14.out' && grep -q 'records 14 of the 16 model parameters, not couple_torque, couple_slip_rate;' '$work/compare_14.out'"
cmp_run compare_12 "$work/rise_12.h5"; rc=$?
check "compare, 12 columns under 16 names: exit 2 (got $rc)" "[ $rc -eq 2 ]"
check "compare, 12 columns under 16 names: names the file and the counts" \
  "grep -q 'rise_12.h5' '$work/compare_12.out' && grep -q 'chains/model: 12 columns but 16 column names' '$work/compare_12.out'"

finish "orbits cli"
