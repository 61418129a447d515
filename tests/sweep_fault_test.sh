#!/usr/bin/env bash
# Faults a sweep survives, nothing lost: after kill -9 of the master, of a worker (mpirun: 137)
# or of mpirun mid-sweep, after a .part cut short (as a write killed half-way leaves it), after a journal
# record cut short, and after the disk filling up (a file-size limit), the same command with
# --resume completes with a file equal to an uninterrupted run's (h5diff, all but
# /provenance). A worker that hangs (SIGSTOP) past --task-timeout is given up and its task run
# by another rank. An output that cannot be written, or that cannot fit, is refused before work.
# Usage: sweep_fault_test.sh ASTROJAX MPIEXEC SOURCE_DIR
set -u
bin=$1; mpiexec=$2; src=$3
source "$(dirname "$0")/check.sh"
source "$(dirname "$0")/sweep_faults.sh"
cd "$work"
"$bin" sweep "${sweep[@]}" -o straight.h5 > straight.out 2>&1
check "uninterrupted run: exit 0" "[ $? -eq 0 ]"

for who in master worker; do
  start_mpi "$who.h5" 400000
  case $who in master) victim=$rank0 ;; worker) victim=$rank1 ;; esac
  kill -9 "$victim"
  wait_mpi "$mp" 60 "$out"
  gone $rank0 $rank1 $rank2
  check "kill -9 $who: killed mid-sweep (pid '$victim', a .part and no file)" \
    "[ -n '$victim' ] && [ -e '$who.h5.part' ] && [ ! -e '$who.h5' ]"
  # mpirun ends the job and returns 128 + the signal of the rank killed (when it does not hang).
  check "kill -9 $who: mpirun exit 137 (got $rc$([ $mpirun_hung = 1 ] && echo ', mpirun hung: its code unknown'))" \
    "[ $rc -eq 137 ] || [ $mpirun_hung -eq 1 ]"
  resume "$who.h5"
  check "kill -9 $who: --resume exit 0 ($(tail -1 "$who.h5.resume"))" "[ $? -eq 0 ] && [ ! -e '$who.h5.journal' ]"
  check "kill -9 $who: resumed file equals the uninterrupted one" "same '$who.h5' straight.h5"
done
# kill -9 of mpirun: ranks it started on this node may live on (Open MPI 4 on one node does not
# kill them) and finish the sweep. A resume started meanwhile is refused (the journal is
# locked by the running master); once they are gone the file is complete or resumable.
start_mpi mpirun.h5 100000  # early: the ranks that outlive mpirun are still writing when the resume starts
kill -9 "$mp"
wait "$mp" 2> /dev/null  # mpirun itself, killed: ends at once
resume mpirun.h5
rc=$?
alive=0; running "$rank0" && alive=1
check "kill -9 mpirun: a resume while the old master runs is refused (exit $rc, master alive $alive)" \
  "[ $rc -eq 2 ] && grep -q 'in use by another running sweep\|mpirun.h5 is complete' mpirun.h5.resume || [ $alive -eq 0 ]"
gone $rank0 $rank1 $rank2
if [ -e mpirun.h5.part ]; then resume mpirun.h5; fi
check "kill -9 mpirun: the file completes and equals the uninterrupted one" "same mpirun.h5 straight.h5"

# A .part cut short, as a master killed in the middle of an HDF5 write can leave it: unreadable,
# rebuilt from the journal.
"$bin" sweep "${sweep[@]}" -o torn.h5 --max-tasks 20 > /dev/null 2>&1
truncate -s $(($(size torn.h5.part) / 2)) torn.h5.part
"$bin" sweep "${sweep[@]}" -o torn.h5 --resume > torn.out 2>&1
check "torn .part: resume exit 0, rebuilt from the journal" "[ $? -eq 0 ] && grep -q 'rebuilt from' torn.out"
check "torn .part: resumed file equals the uninterrupted one" "same torn.h5 straight.h5"
# The last journal record cut short (killed in the middle of an append): that task runs again.
"$bin" sweep "${sweep[@]}" -o tail.h5 --max-tasks 20 > /dev/null 2>&1
truncate -s $(($(size tail.h5.journal) - 1000)) tail.h5.journal
"$bin" sweep "${sweep[@]}" -o tail.h5 --resume > tail.out 2>&1
check "torn journal: resume exit 0 and says so" "[ $? -eq 0 ] && grep -q 'cut short' tail.out"
check "torn journal: resumed file equals the uninterrupted one" "same tail.h5 straight.h5"

# The disk filling up mid-sweep (a file-size limit of half the finished file, set once the sweep
# runs, SIGXFSZ ignored so writes fail with EFBIG as with ENOSPC): a clear error that says how to
# resume; then resumed without the limit.
(trap '' XFSZ; exec "$bin" sweep "${sweep[@]}" -o full.h5 > full.out 2>&1) &
p=$!
for _ in $(seq 1000); do [ -e full.h5.journal ] && break; sleep 0.01; done
limit=$(($(size straight.h5) / 2))
prlimit --pid $p --fsize=$limit:$limit
wait_for $p 120
check "disk full: exit 5 with the reason and how to resume (got $rc)" \
  "[ $rc -eq 5 ] && grep -q 'too large\|No space' full.out && grep -q -- '--resume' full.out"
"$bin" sweep "${sweep[@]}" -o full.h5 --resume > full.resume 2>&1
check "disk full: resumed file equals the uninterrupted one" "[ $? -eq 0 ] && same full.h5 straight.h5"

# A worker that hangs past --task-timeout: given up, its task handed to another rank; the job
# ends instead of waiting, with the file complete and equal to the uninterrupted one.
start_mpi hang.h5 100000 --task-timeout 2
stop_rank2 30
check "hung worker: the master ends the sweep within 30 s ($waited s)" "[ $master_ended -eq 1 ]"
check "hung worker: the job's exit code is the master's, 0: every task done (got $rc)" "[ $rc -eq 0 ]"
check "hung worker: the master names the rank given up" "grep -q 'rank 2: no result after .* given up, its task handed to another' hang.h5.out"
check "hung worker: the file equals the uninterrupted one" "same hang.h5 straight.h5"

# Outputs that cannot be written, and a sweep that cannot fit: refused before any work.
touch afile
"$bin" sweep "${sweep[@]}" -o afile/out.h5 > bad.out 2>&1
check "output under a regular file: exit 2 naming output.path" "[ $? -eq 2 ] && grep -q \"key 'output.path'\" bad.out"
"$bin" sweep "${sweep[@]}" -o big.h5 --set protocol.sample_rate=1e5 \
  --set "grid.drive_radius={start=0.005,stop=0.02,num=1000}" > big.out 2>&1
check "a sweep larger than the free space: exit 2 before work" \
  "[ $? -eq 2 ] && grep -q 'may write up to' big.out && [ ! -e big.h5.part ]"

finish "sweep_fault"
