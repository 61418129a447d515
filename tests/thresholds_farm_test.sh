#!/usr/bin/env bash
# astrojax thresholds with its holds and refinements as farm tasks: the same report in one
# process (-j 1, -j 2) as under mpirun on 2 and on 3 ranks, byte for byte (table, --csv,
# --markdown), and with --no-hold rank 0 alone reports; a hold and a refinement that fail on
# a worker are reported as failed with their reason, with no hang; bad input under mpirun is refused by rank 0 alone; a stop request
# (Ctrl-C in one process, SIGUSR1 through mpirun) ends it with exit 4 and no report.
# On the README's "your own sweep" (quick.toml at R = 5, 10, 20 mm: two ω_rise brackets, four
# holds and two refinements) and on tests/data/tiny_rise.toml with an event bound of 10 per
# run, which the sweep's 3-window tasks stay under and 52 s holds and a 6x slower ramp exceed.
# Usage: thresholds_farm_test.sh ASTROJAX MPIEXEC SOURCE_DIR
set -u
bin=$1; mpiexec=$2; src=$3
source "$(dirname "$0")/check.sh"
source "$(dirname "$0")/sweep_faults.sh"  # wait_mpi, wait_for: no wait on mpirun can hang
cd "$work"
# astrojax on $1 ranks in the background; mp is mpirun's pid.
mpi() { local n=$1; shift; "$mpiexec" --oversubscribe -n "$n" "$bin" "$@" & mp=$!; }
# Waits for that mpirun (at most $1 s) with rank 0's stderr in $2 and sets rc. Open MPI 4's
# mpirun now and then stays waiting after every rank has exited (sweep_faults.sh, wait_mpi):
# it is then killed and rank 0's code read from what it printed last (interrupted 4, an error
# 2, else 0).
wait_job() {
  wait_mpi "$mp" "$1" /dev/null
  if [ "$mpirun_hung" = 1 ]; then
    if grep -q '^interrupted' "$2"; then rc=4; elif grep -q '^error:' "$2"; then rc=2; else rc=0; fi
  fi
}

"$bin" sweep "$src/sweeps/quick.toml" -o own.h5 -q --set "grid.drive_radius=[0.005,0.01,0.02]" > sweep.out 2>&1
check "sweep: exit 0" "[ $? -eq 0 ]"
args=(own.h5 --refine 2)
"$bin" thresholds "${args[@]}" -j 1 --csv j1.csv --markdown j1.md > j1.out 2>&1
check "1 process, -j 1: exit 0" "[ $? -eq 0 ]"
check "two ω_rise brackets, each held on both sides and refined" \
  "[ \$(grep -c ',omega_rise,.*,\\(excursion\\|bifurcation\\|time-limited transient\\|undecided\\),' j1.csv) -eq 2 ] \
   && [ \$(grep -c '2× slower' j1.out) -eq 2 ]"
"$bin" thresholds "${args[@]}" -j 2 --csv j2.csv --markdown j2.md > j2.out 2>&1
check "1 process, -j 2: exit 0" "[ $? -eq 0 ]"
for n in 2 3; do
  mpi $n thresholds "${args[@]}" --csv n$n.csv --markdown n$n.md > n$n.out 2> n$n.err
  wait_job 120 n$n.err
  check "mpirun -n $n: exit 0 (got $rc)" "[ $rc -eq 0 ]"
done
for run in j2 n2 n3; do
  check "$run: the table, the CSV and the Markdown byte-identical to one process's" \
    "cmp -s j1.out $run.out && cmp -s j1.csv $run.csv && cmp -s j1.md $run.md"
done

# Without holds or refinements there is nothing to farm out: under mpirun rank 0 alone reports.
"$bin" thresholds own.h5 --no-hold --csv nh1.csv > nh1.out 2>&1
mpi 3 thresholds own.h5 --no-hold --csv nh3.csv > nh3.out 2> nh3.err
wait_job 60 nh3.err
check "--no-hold under mpirun: exit 0, the report once, as one process's (got $rc)" \
  "[ $rc -eq 0 ] && cmp -s nh1.out nh3.out && cmp -s nh1.csv nh3.csv"

# Failures on the workers: both holds hit the event bound, and so does the refinement 6x slower.
"$bin" sweep "$src/tests/data/tiny_rise.toml" -o bound.h5 -q --set integrator.max_events=10 > bound.out 2>&1
check "sweep under an event bound of 10: exit 0" "[ $? -eq 0 ]"
"$bin" thresholds bound.h5 --refine 6 -j 1 --csv f1.csv > f1.out 2>&1
check "failing checks, 1 process: exit 0" "[ $? -eq 0 ]"
mpi 3 thresholds bound.h5 --refine 6 --csv f3.csv > f3.out 2> f3.err
wait_job 60 f3.err
check "failing checks, mpirun -n 3: exit 0, no hang (got $rc)" "[ $rc -eq 0 ]"
check "the failed hold is undecided, with the reason" \
  "grep -q 'undecided: the hold at 12.333pi failed: event bound 10 hit at t = ' f3.out"
check "the failed refinement says failed: why" "grep -Eq '6× slower +failed: event bound 10 hit at t = ' f3.out"
check "failures: the same report and CSV as one process's" "cmp -s f1.out f3.out && cmp -s f1.csv f3.csv"

# Bad input under mpirun: refused before any work, said once (by rank 0), every rank ends.
mpi 3 thresholds missing.h5 > bad.out 2> bad.err
wait_job 60 bad.err
check "a missing file under mpirun: exit 2, said once (got $rc)" \
  "[ $rc -eq 2 ] && [ \$(grep -c 'missing.h5: no such file' bad.err) -eq 1 ]"
mpi 2 thresholds own.h5 --hold 1e9 > bad2.out 2> bad2.err
wait_job 60 bad2.err
check "a bad --hold under mpirun: exit 2, said once (got $rc)" \
  "[ $rc -eq 2 ] && [ \$(grep -c -- '--hold 1e9' bad2.err) -eq 1 ]"

# A stop request once the holds run (rank 0 has used 0.3 s of CPU: reading the file takes a
# few ms), with holds of 5000 s (about 1.5 s of CPU each) so that some are still unstarted.
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat" 2> /dev/null || echo 0; }
await_cpu() {
  [ -n "$1" ] || return
  for _ in $(seq 300); do running "$1" && [ "$(cpu_ticks "$1")" -lt 30 ] || return; sleep 0.05; done
}
"$bin" thresholds own.h5 --hold 5000 -j 1 --csv int1.csv > int1.out 2> int1.err &
p=$!
await_cpu $p
kill -INT $p
wait_for $p 60
check "Ctrl-C: exit 4, says so, no CSV (got $rc)" \
  "[ $rc -eq 4 ] && grep -q '^interrupted' int1.err && [ ! -e int1.csv ] && [ ! -s int1.out ]"
mpi 3 thresholds own.h5 --hold 5000 --csv int3.csv > int3.out 2> int3.err
master=
for _ in $(seq 200); do
  for k in $(pgrep -P $mp); do [ "$(rank_of $k)" = 0 ] && master=$k; done
  [ -n "$master" ] && break; sleep 0.05
done
await_cpu "$master"
kill -USR1 $mp
wait_job 60 int3.err
check "SIGUSR1 to mpirun: exit 4, says so, no CSV (got $rc)" \
  "[ $rc -eq 4 ] && grep -q '^interrupted' int3.err && [ ! -e int3.csv ]"

finish "thresholds_farm"
