#!/usr/bin/env bash
# The sweep's result depends on its tasks alone: the file from 1 rank (the master computes)
# and from 3 ranks (a master and 2 workers) are identical in everything but /provenance.
# Usage: sweep_mpi_test.sh ASTROJAX MPIEXEC SOURCE_DIR
set -u
bin=$1; mpiexec=$2; src=$3
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail=0; pass=0
check() { if eval "$2"; then pass=$((pass+1)); else echo "FAIL: $1"; fail=$((fail+1)); fi; }

"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$src/tests/data/tiny_sweep.toml" -o "$work/one.h5" -q > "$work/one.out" 2>&1
rc1=$?
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$src/tests/data/tiny_sweep.toml" -o "$work/three.h5" -q > "$work/three.out" 2>&1
rc3=$?
cat "$work/one.out" "$work/three.out"
check "1 rank: exit 0 (got $rc1)" "[ $rc1 -eq 0 ]"
check "3 ranks: exit 0 (got $rc3)" "[ $rc3 -eq 0 ]"
for g in /config /chains /windows /samples /tasks; do
  check "$g identical for 1 and 3 ranks" "h5diff '$work/one.h5' '$work/three.h5' $g > '$work/diff' 2>&1"
done
check "every window classified" "! h5dump -A 0 -d /windows/class '$work/three.h5' | grep -q -- '-1'"
check "ranks recorded" "h5dump -a /provenance/ranks '$work/three.h5' | grep -q '(0): 3'"
echo "sweep_mpi: $pass passed, $fail failed"
[ $fail -eq 0 ]
