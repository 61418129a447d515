#!/usr/bin/env bash
# astrojax bench end to end: bad input exits 2 naming the option or the file and key, and
# writes nothing; a small good run writes a CSV with the header's columns on every row.
# Usage: bench_cli_test.sh ASTROJAX_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"
scene="$src/sweeps/scenes/locked_circular.toml"

"$bin" bench work-precision "$scene" -o "$work/a.csv" --methods rk5 >/dev/null 2>"$work/a.err"
rc=$?
check "unknown method: exit 2 (got $rc)" "[ $rc -eq 2 ] && grep -q 'rk5' '$work/a.err' && grep -q 'dop853' '$work/a.err'"
check "unknown method: no file" "[ ! -e '$work/a.csv' ] && [ ! -e '$work/a.csv.part' ]"
"$bin" bench work-precision "$scene" -o "$work/b.csv" --rtols 2 >/dev/null 2>"$work/b.err"
rc=$?
check "rtol out of range: exit 2 (got $rc)" "[ $rc -eq 2 ] && grep -qF '[1e-15, 1)' '$work/b.err'"
"$bin" bench work-precision "$scene" -o "$work/c.csv" --set model.drive_radius=2 >/dev/null 2>"$work/c.err"
rc=$?
check "bad scene key: exit 2 naming file and key (got $rc)" \
  "[ $rc -eq 2 ] && grep -q 'locked_circular.toml' '$work/c.err' && grep -q 'model.drive_radius' '$work/c.err'"

"$bin" bench work-precision "$scene" -o "$work/good.csv" --horizon 0.5 --methods rk4,dop853 \
  --rtols 1e-6,1e-8 --steps 2e-3 --repeats 1 >"$work/good.out" 2>&1
rc=$?
check "good run: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "good run: 3 rows" "[ \$(grep -c '^locked_circular,' '$work/good.csv') -eq 3 ]"
check "good run: every row has the header's columns" \
  "[ \$(grep -v '^#' '$work/good.csv' | awk -F, '{print NF}' | sort -u | wc -l) -eq 1 ]"
# The other bench commands refuse what they cannot measure, before any work.
"$bin" bench stability "$src/sweeps/spin_up.toml" -o "$work/s.csv" --methods dopri5 >/dev/null 2>"$work/s.err"
rc=$?
check "stability with an adaptive method: exit 2 (got $rc)" "[ $rc -eq 2 ] && grep -q 'fixed-step' '$work/s.err' && [ ! -e '$work/s.csv' ]"
"$bin" bench friction "$scene" -o "$work/f.csv" --set layers.friction=kinetic >/dev/null 2>"$work/f.err"
rc=$?
check "friction without stick-slip: exit 2 naming layers.friction (got $rc)" \
  "[ $rc -eq 2 ] && grep -q 'layers.friction' '$work/f.err' && [ ! -e '$work/f.csv' ]"
"$bin" bench constraints "$src/sweeps/scenes/stick_slip_passage.toml" -o "$work/k.csv" --horizon 5 >/dev/null 2>"$work/k.err"
rc=$?
check "constraints on a switching scene: exit 2 (got $rc)" "[ $rc -eq 2 ] && grep -q 'one contact mode' '$work/k.err' && [ ! -e '$work/k.csv' ]"
"$bin" bench threshold "$scene" -o "$work/t.csv" --horizon 2 >/dev/null 2>"$work/t.err"
rc=$?
check "threshold where the bead never falls: exit 2 (got $rc)" \
  "[ $rc -eq 2 ] && grep -q 'never lands' '$work/t.err' && [ ! -e '$work/t.csv' ] && [ ! -e '$work/t.csv.part' ]"
# A scene that ramps up measures ω1; scenes ramping both ways cannot share one table.
up="$src/sweeps/scenes/lock_loss_ramp.toml"
"$bin" bench threshold "$up" "$src/sweeps/scenes/fall_ramp.toml" -o "$work/m.csv" >/dev/null 2>"$work/m.err"
rc=$?
check "threshold over scenes ramping both ways: exit 2 (got $rc)" \
  "[ $rc -eq 2 ] && grep -q 'fall_ramp' '$work/m.err' && grep -q 'the same way' '$work/m.err' && [ ! -e '$work/m.csv' ]"
"$bin" bench threshold "$up" -o "$work/u.csv" --horizon 4 >/dev/null 2>"$work/u.err"
rc=$?
check "ω1 before the lock is lost: exit 2 (got $rc)" \
  "[ $rc -eq 2 ] && grep -q 'half a turn behind' '$work/u.err' && [ ! -e '$work/u.csv' ]"
"$bin" bench threshold "$up" -o "$work/w.csv" --horizon 8 --methods dop853 --rtols 1e-6 --repeats 1 >/dev/null 2>&1
rc=$?
check "ω1 run: exit 0 and the omega_1 columns (got $rc)" \
  "[ $rc -eq 0 ] && grep -q '^scene,.*,omega_1,omega_1_error,' '$work/w.csv' && [ \$(grep -c '^lock_loss_ramp,dop853,' '$work/w.csv') -eq 1 ]"
finish "bench_cli_test"
