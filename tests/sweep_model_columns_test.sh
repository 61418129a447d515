#!/usr/bin/env bash
# /chains/model records every parameter a chain ran with, the pair couple's τ_c and Ω_ε among
# them (the last two of 16 columns), and a [grid] over couple_torque gives each chain its value:
# a tiny hold sweep (one held ω_m = 6π, the Table-1 seed, 1 s + 1 s) with the couple on, over
# τ_c = 0, 5e-4, 1e-3 N m at Ω_ε = 2 rad/s. The columns are read by name, as the analysis does.
# Usage: sweep_model_columns_test.sh ASTROJAX_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"
py=/usr/bin/python3

"$bin" sweep "$src/tests/data/tiny_hold.toml" -o "$work/couple.h5" -q \
  --set "hold.omega=[18.84955592153876]" --set 'hold.seeds=["circular_high"]' --set hold.perturbations=0 \
  --set hold.settle=1.0 --set hold.measure=1.0 \
  --set layers.pair_couple=motor_clutch --set model.couple_torque=2e-3 \
  --set "grid.couple_torque=[0.0,5e-4,1e-3]" --set "grid.couple_slip_rate=[2.0]" >"$work/couple.out" 2>&1
rc=$?
check "couple grid: exit 0 (got $rc)" "[ $rc -eq 0 ]"
PYTHONPATH="$src/analysis" "$py" - "$work/couple.h5" >"$work/columns.out" 2>&1 <<'PY'
import sys
import astrojax_analysis as ajx
import h5py
s = ajx.Sweep(sys.argv[1])
with h5py.File(sys.argv[1], "r") as f:
    print("shape", *f["chains/model"].shape)
print("last", *s.model_columns[-2:])
print("axes", *s.axes)
for c in range(s.n_chains):
    g = dict(zip(s.axes, s.grid[c]))
    print("chain", c, repr(s.parameter(c, "couple_torque")), repr(g["couple_torque"]),
          repr(s.parameter(c, "couple_slip_rate")), repr(g["couple_slip_rate"]),
          repr(s.parameter(c, "tie_damping")))
PY
check "couple grid: 16 columns, the couple's last" \
  "grep -q '^shape 3 16$' '$work/columns.out' && grep -q '^last couple_torque couple_slip_rate$' '$work/columns.out'"
check "couple grid: axes recorded" "grep -q '^axes couple_slip_rate couple_torque$' '$work/columns.out'"
check "couple grid: each chain records its grid value" \
  "grep -q '^chain 0 0.0 0.0 2.0 2.0 ' '$work/columns.out' && grep -q '^chain 1 0.0005 0.0005 2.0 2.0 ' '$work/columns.out' \
   && grep -q '^chain 2 0.001 0.001 2.0 2.0 ' '$work/columns.out'"
check "couple grid: the columns before them unchanged (c_a default 1e-7)" "grep -q '^chain 0 .* 1e-07$' '$work/columns.out'"

# A grid value out of the parameter's range is refused before any work, naming the grid point.
"$bin" sweep "$src/tests/data/tiny_hold.toml" -o "$work/bad.h5" -q --set "grid.couple_slip_rate=[1.0,0.0]" \
  >"$work/bad.out" 2>&1
rc=$?
check "bad slip rate: exit 2 (got $rc)" "[ $rc -eq 2 ]"
check "bad slip rate: names the key, the grid point and the range" \
  "grep -q 'model.couple_slip_rate' '$work/bad.out' && grep -qF 'grid.couple_slip_rate[1]' '$work/bad.out' \
   && grep -qF 'Ω_ε in (0, ∞) rad/s' '$work/bad.out'"
check "bad slip rate: no file" "[ ! -e '$work/bad.h5' ] && [ ! -e '$work/bad.h5.part' ]"

finish "sweep model columns"
