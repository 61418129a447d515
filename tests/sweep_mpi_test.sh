#!/usr/bin/env bash
# The sweep's result depends on its tasks alone: the file from 1 rank (the master computes)
# and from 3 ranks (a master and 2 workers) are identical in everything but /provenance; and a
# sweep stopped part-way (--max-tasks, as an interruption) and resumed (--resume) gives the
# same file as one run straight through.
# Usage: sweep_mpi_test.sh ASTROJAX MPIEXEC SOURCE_DIR
set -u
bin=$1; mpiexec=$2; src=$3
source "$(dirname "$0")/check.sh"

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
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$src/tests/data/tiny_sweep.toml" -o "$work/resumed.h5" -q --max-tasks 3 \
  > "$work/part.out" 2>&1
rcp=$?
check "stopped part-way: exit 4 (got $rcp)" "[ $rcp -eq 4 ]"
check "stopped part-way: the .part file holds the finished tasks" "[ -s '$work/resumed.h5.part' ] && [ ! -e '$work/resumed.h5' ]"
check "stopped part-way: says how to resume" "grep -q -- '--resume' '$work/part.out'"
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$src/tests/data/tiny_sweep.toml" -o "$work/resumed.h5" -q --resume \
  > "$work/resume.out" 2>&1
rcr=$?
check "resumed: exit 0 (got $rcr)" "[ $rcr -eq 0 ] && [ -s '$work/resumed.h5' ] && [ ! -e '$work/resumed.h5.part' ]"
for g in /config /chains /windows /samples /tasks; do
  check "$g of the resumed sweep identical to the straight run" "h5diff '$work/one.h5' '$work/resumed.h5' $g > '$work/diff' 2>&1"
done
"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$src/tests/data/tiny_sweep.toml" -o "$work/resumed.h5" -q --resume \
  > "$work/again.out" 2>&1
rca=$?
check "nothing left to resume: exit 2 with the reason (got $rca)" "[ $rca -eq 2 ] && grep -q 'nothing to resume' '$work/again.out'"
"$bin" thresholds "$work/one.h5" --no-hold --csv "$work/th.csv" > "$work/th.out" 2>&1
rct=$?
check "thresholds: exit 0 (got $rct)" "[ $rct -eq 0 ]"
check "thresholds: the four printed with the paper's values" \
  "for s in ω_rise ω_fall ω1 ω2; do grep -q \"^  \$s \" '$work/th.out' || exit 1; done; grep -q '12.63' '$work/th.out'"
check "thresholds: CSV with a header and 8 rows" "[ \$(wc -l < '$work/th.csv') -eq 9 ]"
"$bin" thresholds "$work/missing.h5" > /dev/null 2>&1
check "thresholds of a missing file: exit 2" "[ $? -eq 2 ]"
cp "$work/one.h5" "$work/re.h5"
"$bin" classify "$work/re.h5" > "$work/re0.out" 2>&1
check "classify without -o or --force: exit 2, nothing rewritten" "[ $? -eq 2 ] && grep -q 'give -o COPY' '$work/re0.out'"
"$bin" classify "$work/re.h5" --force > "$work/re.out" 2>&1
check "classify with the defaults: 0 changed" "grep -q ' 0 changed class' '$work/re.out'"
for d in class confidence omega_ball rotation_number L1_mean mode_fraction; do
  check "classify reproduces /windows/$d from the stored samples" "h5diff '$work/one.h5' '$work/re.h5' /windows/$d > /dev/null 2>&1"
done
"$bin" classify "$work/re.h5" -o "$work/re2.h5" --set classifier.fallen_fraction=7 --set classifier.on_ball_tol=1e-9 > "$work/re2.out" 2>&1
check "classify -o with other settings changes classes in the copy only" \
  "! grep -q ' 0 changed class' '$work/re2.out' && h5diff '$work/one.h5' '$work/re.h5' /windows/class > /dev/null 2>&1"
"$bin" classify "$work/re.h5" -o "$work/re2.h5" > "$work/re3.out" 2>&1
check "classify -o onto an existing file: exit 2 without --force" "[ $? -eq 2 ] && grep -q 'exists; give --force' '$work/re3.out'"
"$bin" classify "$work/re.h5" --force --set nonsense=1 > /dev/null 2>&1
check "classify with an unknown setting: exit 2" "[ $? -eq 2 ]"
"$bin" classify "$work/re.h5" --force --set fallen_fraction=7 > "$work/re4.out" 2>&1
check "classify with a key lacking its section: exit 2, the full key suggested" \
  "[ $? -eq 2 ] && grep -q 'did you mean classifier.fallen_fraction' '$work/re4.out'"
# thresholds --set classifies in memory: the same table and class sequence as thresholds of the
# copy classify wrote with those settings, and a sequence unlike the defaults' (else the
# comparison would prove nothing).
"$bin" thresholds "$work/one.h5" --no-hold --sequence-csv "$work/seq.csv" > /dev/null 2>&1
"$bin" thresholds "$work/re2.h5" --no-hold --csv "$work/th_copy.csv" --sequence-csv "$work/seq_copy.csv" > /dev/null 2>&1
"$bin" thresholds "$work/one.h5" --no-hold --csv "$work/th_set.csv" --sequence-csv "$work/seq_set.csv" \
  --set classifier.fallen_fraction=7 --set classifier.on_ball_tol=1e-9 > "$work/th_set.out" 2>&1
check "thresholds --set: exit 0, the table and sequence of classify's copy, a sequence unlike the defaults'" \
  "[ $? -eq 0 ] && cmp -s '$work/th_copy.csv' '$work/th_set.csv' && cmp -s '$work/seq_copy.csv' '$work/seq_set.csv' && ! cmp -s '$work/seq.csv' '$work/seq_set.csv'"
"$bin" thresholds "$work/one.h5" --no-hold --set model.drag=1 > "$work/th_bad.out" 2>&1
check "thresholds --set on a model key: exit 2, says only the classifier's settings can change" \
  "[ $? -eq 2 ] && grep -q 'only the classifier' '$work/th_bad.out'"
# The hold mode: the same on 1 and 3 ranks (the seeds' random kicks included).
"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$src/tests/data/tiny_hold.toml" -o "$work/hold1.h5" -q > /dev/null 2>&1
rh1=$?
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$src/tests/data/tiny_hold.toml" -o "$work/hold3.h5" -q > /dev/null 2>&1
rh3=$?
check "hold: exit 0 on 1 and 3 ranks ($rh1, $rh3)" "[ $rh1 -eq 0 ] && [ $rh3 -eq 0 ]"
for g in /chains /windows /samples /tasks; do
  check "hold: $g identical for 1 and 3 ranks" "h5diff '$work/hold1.h5' '$work/hold3.h5' $g > /dev/null 2>&1"
done
check "hold: 8 chains with their ω_m and seeds" "h5dump -A 0 -d /chains/seed '$work/hold1.h5' | grep -q '0, 0, 1, 1, 0, 0, 1, 1'"
# The classifier on simulated orbits: at 6π (R = 1 cm, d = 3 cm) the hanging seed stays
# fallen, and the Table 1 seed settles on a locked circular orbit with the bead high.
"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$src/tests/data/tiny_hold.toml" -o "$work/six.h5" -q \
  --set "hold.omega=[18.84955592153876]" --set hold.settle=60.0 --set hold.measure=10.0 > /dev/null 2>&1
check "simulated at 6π: fallen from hanging, locked-circular from the bead high" \
  "h5dump -y -w 0 -A 0 -d /windows/class '$work/six.h5' | sed -n '/DATA {/,/}/p' | tr -d ' \\n' | grep -q 'DATA{0,0,1,1}'"
check "every window classified" "! h5dump -A 0 -d /windows/class '$work/three.h5' | grep -q -- '-1'"
check "ranks recorded" "h5dump -a /provenance/ranks '$work/three.h5' | grep -q '(0): 3'"
finish "sweep_mpi"
