#!/usr/bin/env bash
# Verified resumes, exit codes that mean one thing, liveness, finished work never discarded:
# - a byte flipped in a finished file (/chains, /windows, /tasks, a sample chunk): verify names it;
# - a .part damaged in /chains, in a carried state or in a sample chunk, and a journal with a
#   flipped byte, resume into the uninterrupted file; a .part without its journal is refused;
#   astrojax verify names the damage and passes the resumed file;
# - a rerun without --resume over an interrupted sweep is refused (exit 2), its files untouched;
#   --force starts afresh;
# - a sweep whose tasks all failed prints a summary starting with FAILED and exits 3;
# - under mpirun the job's code is the master's: SIGUSR1 gives 4, a full disk 5 (workers used to
#   return 4 first), SIGTERM to cluster/run_sweep.sh gives 4 and no requeue outside Slurm;
#   every interrupted file resumes into one equal to the uninterrupted run's;
# - a stopped worker without --task-timeout is noticed by the automatic bound, its task runs on
#   another rank and the file is complete; a worker waiting for work does not spin.
# Usage: reliability_fault_test.sh ASTROJAX MPIEXEC SOURCE_DIR
set -u
bin=$1; mpiexec=$2; src=$3
source "$(dirname "$0")/check.sh"
source "$(dirname "$0")/sweep_faults.sh"
cd "$work"
ticks() { awk '{print $14 + $15}' "/proc/$1/stat" 2> /dev/null || echo 0; }  # user + system CPU [1/100 s]

"$bin" sweep "${sweep[@]}" -o straight.h5 > straight.out 2>&1
check "uninterrupted run: exit 0" "[ $? -eq 0 ]"

# A finished file's records carry checksums (Fletcher32 on every uncompressed chunk and whole
# array, the zlib Adler-32 of each deflated sample chunk): one byte flipped on disk in a chunk
# of a dataset, and astrojax verify exits 2 naming that dataset; the file as written passes.
flip() {  # flip FILE DATASET CHUNK: one byte in the middle of that chunk as stored
  /usr/bin/python3 - "$@" <<'PY'
import sys, h5py
path, name, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
with h5py.File(path, "r") as f:
    info = f[name].id.get_chunk_info(k)
at = info.byte_offset + info.size // 2
with open(path, "r+b") as fh:
    fh.seek(at); b = fh.read(1); fh.seek(at); fh.write(bytes([b[0] ^ 0x10]))
PY
}
"$bin" verify straight.h5 > verify.out 2>&1
check "astrojax verify of a finished file: exit 0, no dataset without a checksum" "[ $? -eq 0 ] && ! grep -q 'no checksum' verify.out"
for dk in chains/model:0 chains/grid_values:0 windows/omega_ball:0 windows/class:0 tasks/final_state:0 samples/count:0 \
          samples/t:4 samples/r2:7; do
  d=${dk%:*}
  cp straight.h5 flipped.h5
  flip flipped.h5 "$d" "${dk#*:}"
  "$bin" verify flipped.h5 > verify.out 2>&1
  rc=$?
  check "a byte flipped in a chunk of /$d of a finished file: verify exit 2 (got $rc) naming it" \
    "[ $rc -eq 2 ] && grep -q 'DAMAGED: /$d: cannot be read' verify.out"
done

# Finished work is never discarded silently.
"$bin" sweep "${sweep[@]}" -o rerun.h5 --max-tasks 10 > /dev/null 2>&1
check "interrupted by --max-tasks: exit 4" "[ $? -eq 4 ]"
sums=$(md5sum rerun.h5.part rerun.h5.journal)
"$bin" sweep "${sweep[@]}" -o rerun.h5 > rerun.out 2>&1
rc=$?
check "rerun without --resume: exit 2 (got $rc)" "[ $rc -eq 2 ]"
check "rerun without --resume: says what is there and both ways on" \
  "grep -q 'rerun.h5.journal (10 finished task results)' rerun.out && grep -q -- '--resume' rerun.out && grep -q -- '--force' rerun.out"
check "rerun without --resume: the .part and the journal untouched" "[ \"\$(md5sum rerun.h5.part rerun.h5.journal)\" = \"\$sums\" ]"
"$bin" sweep "${sweep[@]}" -o rerun.h5 --force > /dev/null 2>&1
check "rerun with --force: exit 0, a complete file" "[ $? -eq 0 ] && [ ! -e rerun.h5.part ] && same rerun.h5 straight.h5"

# A damaged .part resumes into the uninterrupted file: a resume trusts only the sweep file and
# the journal's checksummed records, and makes every dataset again (/chains, the carried states
# and the sample chunks damaged here with h5py, as a flipped byte would).
"$bin" sweep "${sweep[@]}" -o damaged.h5 --max-tasks 20 > /dev/null 2>&1
/usr/bin/python3 - damaged.h5.part <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r+") as f:
    f["chains/grid_values"][1, 0] = 0.0154883
    m = f["chains/model"][...]; m[0, 0] += 1e-3; f["chains/model"][...] = m
    s = f["tasks/final_state"][...]; s[np.isfinite(s[:, 0]), 8] += 1.4; f["tasks/final_state"][...] = s
    f["samples/t"].id.write_direct_chunk((0, 0, 0), b"\x00" * 64, 1)  # a chunk deflate cannot read
PY
"$bin" verify damaged.h5.part > verify.out 2>&1
check "astrojax verify of the damaged .part: exit 2, names /chains/grid_values and /samples/t" \
  "[ $? -eq 2 ] && grep -q 'DAMAGED: /chains/grid_values at ' verify.out && grep -q 'DAMAGED: /samples/t: cannot be read' verify.out"
"$bin" sweep "${sweep[@]}" -o damaged.h5 --resume > damaged.out 2>&1
check "damaged .part: resume exit 0, rebuilt from the journal" "[ $? -eq 0 ] && grep -q 'rebuilt from' damaged.out"
check "damaged .part: the resumed file equals the uninterrupted one" "same damaged.h5 straight.h5"
"$bin" verify damaged.h5 > verify.out 2>&1
check "astrojax verify of the resumed file: exit 0, ok" "[ $? -eq 0 ] && tail -1 verify.out | grep -q '^ok '"
# A byte flipped inside the journal: its CRC marks that record damaged; the intact records after
# it are kept, the resume says how many results it kept and discarded, and those tasks run again.
"$bin" sweep "${sweep[@]}" -o flip.h5 --max-tasks 20 > /dev/null 2>&1
at=$(($(size flip.h5.journal) / 2))
printf '\xff' | dd of=flip.h5.journal bs=1 seek=$at conv=notrunc status=none
"$bin" sweep "${sweep[@]}" -o flip.h5 --resume > flip.out 2>&1
check "flipped journal byte: resume exit 0 and says what it kept and discarded" \
  "[ $? -eq 0 ] && grep -Eq 'results kept, [1-9][0-9]* discarded' flip.out"
check "flipped journal byte: the resumed file equals the uninterrupted one" "same flip.h5 straight.h5"
# A .part without its journal cannot be checked: refused.
"$bin" sweep "${sweep[@]}" -o nojournal.h5 --max-tasks 5 > /dev/null 2>&1
rm nojournal.h5.journal
"$bin" sweep "${sweep[@]}" -o nojournal.h5 --resume > nojournal.out 2>&1
check "a .part without a journal: resume refused with exit 2" "[ $? -eq 2 ] && grep -q 'has no journal' nojournal.out"

# Every task failed: not "ok". (Euler at 90 ms blows up: "non-finite state".)
"$bin" sweep "${sweep[@]}" -o failed.h5 --set integrator.method=euler --set integrator.step=0.09 > failed.out 2>&1
rc=$?
check "all tasks failed: exit 3 (got $rc)" "[ $rc -eq 3 ]"
check "all tasks failed: the summary starts with FAILED ($(head -1 failed.out))" "head -1 failed.out | grep -q '^FAILED '"

# SIGUSR1 to mpirun (forwarded to the ranks): interrupted, 4, resumable.
start_mpi usr1.h5 300000
kill -USR1 "$mp"
wait_mpi "$mp" 60 "$out"
check "SIGUSR1 to mpirun: exit 4 (got $rc)" "[ $rc -eq 4 ] && [ -e usr1.h5.part ]"
resume usr1.h5
check "SIGUSR1 to mpirun: the resume completes and equals the uninterrupted run" "[ $? -eq 0 ] && same usr1.h5 straight.h5"

# SIGTERM to a bare mpirun (Ctrl-C, scancel and Slurm's time limit reach mpirun itself): Open
# MPI's mpirun returns 1 for a job it was told to terminate, whatever the ranks return, and
# SIGKILLs them a second after its SIGTERM. The documented outcome: exit 1, the .part and the
# journal left, and the resume equal to the uninterrupted run. (A master whose tasks in flight
# end within that second also prints INTERRUPTED; not asserted, a loaded machine can miss it.)
start_mpi term.h5 300000
kill -TERM "$mp"
wait_mpi "$mp" 60 "$out"
gone $rank0 $rank1 $rank2
echo "SIGTERM to mpirun: mpirun exit $rc, master's summary: $(grep -oE '^(ok|FAILED|INTERRUPTED)' term.h5.out || echo 'none, killed')"
check "SIGTERM to mpirun: exit 1, Open MPI's own (got $rc$([ $mpirun_hung = 1 ] && echo ', mpirun hung: its code unknown'))" \
  "[ $rc -eq 1 ] || [ $mpirun_hung -eq 1 ]"
check "SIGTERM to mpirun: the .part and the journal are left" "[ -e term.h5.part ] && [ -e term.h5.journal ] && [ ! -e term.h5 ]"
resume term.h5
check "SIGTERM to mpirun: the resume completes and equals the uninterrupted run" "[ $? -eq 0 ] && same term.h5 straight.h5"

# cluster/run_sweep.sh turns a SIGTERM to itself into SIGUSR1 to mpirun (forwarded without
# terminating the job): 4. When mpirun gets the SIGTERM too (scancel and the time limit signal
# every process of the job), mpirun's 1 with the journal left also counts as 4. No requeue
# outside Slurm.
for who in script both; do
  rm -f script.h5*
  SLURM_NTASKS=3 ASTROJAX_BIN="$bin" ASTROJAX_LAUNCHER=mpirun ASTROJAX_MPIRUN_FLAGS=--oversubscribe \
    "$src/cluster/run_sweep.sh" "${sweep[0]}" script.h5 "${sweep[@]:1}" > script.out 2>&1 &
  sp=$!
  for _ in $(seq 1500); do [ "$(size script.h5.journal)" -gt 300000 ] && break; sleep 0.01; done
  launcher=$(pgrep -P "$sp" -x mpirun)
  kill -TERM "$sp"
  [ $who = both ] && kill -TERM $launcher
  # The script waits for mpirun, which may stay waiting after its ranks exited: bounded.
  idle=0
  for _ in $(seq 600); do
    kill -0 "$sp" 2> /dev/null || break
    if [ -z "$(live_children "${launcher:-0}")" ]; then idle=$((idle + 1)); else idle=0; fi
    [ $idle -eq 100 ] && { echo "mpirun still waiting 10 s after its ranks exited: killed"; kill -KILL $launcher; }
    sleep 0.1
  done
  kill -0 "$sp" 2> /dev/null && { echo "run_sweep.sh still running after 60 s: killed"; kill -KILL "$sp" $launcher; }
  wait "$sp"
  rc=$?
  check "SIGTERM to run_sweep.sh ($who): exit 4 (got $rc), no requeue outside Slurm" \
    "[ $rc -eq 4 ] && grep -q 'continue with' script.out && ! grep -q requeueing script.out && [ -e script.h5.journal ]"
done

# A full disk under mpirun (a file-size limit of half the finished file on the master, SIGXFSZ ignored by a shell that
# then becomes the rank: mpirun resets the signals of what it starts): the job's code is the
# master's 5, which run_sweep.sh does not requeue; the workers' stop no longer decides it.
rm -f full.h5*
"$mpiexec" --oversubscribe -n 3 bash -c 'trap "" XFSZ; exec "$0" "$@"' "$bin" sweep "${sweep[@]}" -o full.h5 > full.out 2>&1 &
mp=$!
for _ in $(seq 1500); do [ -e full.h5.journal ] && break; sleep 0.01; done
for k in $(pgrep -P $mp); do
  [ "$(rank_of $k)" = 0 ] && prlimit --pid $k --fsize=$(($(size straight.h5) / 2)):$(($(size straight.h5) / 2))
done
wait_mpi $mp 60 full.out
check "disk full under mpirun: exit 5, the master's (got $rc), the reason and how to resume" \
  "[ $rc -eq 5 ] && grep -q 'too large\|No space' full.out && grep -q -- '--resume' full.out"
resume full.h5
check "disk full under mpirun: the resume completes and equals the uninterrupted run" "[ $? -eq 0 ] && same full.h5 straight.h5"

# A stopped worker without --task-timeout: the automatic bound (20 times the slowest task, here
# at least 2 s) gives it up and hands its task to the other worker.
start_mpi stop.h5 100000 --min-task-timeout 2
stop_rank2 60
check "stopped worker: the master ends the sweep within 60 s ($waited s)" "[ $master_ended -eq 1 ]"
check "stopped worker: exit 0 (got $rc), the rank named" "[ $rc -eq 0 ] && grep -q 'rank 2: no result after' stop.h5.out"
check "stopped worker: the file is complete and equals the uninterrupted one" "[ ! -e stop.h5.part ] && same stop.h5 straight.h5"

# A worker waiting for work does not spin: one chain in one long task (RK4 at 5 µs: about 15 s
# of CPU, interrupted after 4), so one worker works and the other waits; their CPU over 3 s,
# both ranks still running at its end.
# --threads 0: the one task goes to a worker rank, not to rank 0's own thread.
start_mpi idle.h5 0 --set "grid.drive_radius=[0.01]" --set protocol.windows_per_task=1000 --set integrator.step=5e-6 --threads 0
sleep 1
a1=$(ticks "$rank1"); a2=$(ticks "$rank2")
sleep 3
b1=$(ticks "$rank1"); b2=$(ticks "$rank2")
both_running=0; running "$rank1" && running "$rank2" && both_running=1
kill -USR1 "$mp"; wait_mpi "$mp" 60 "$out"
check "the idle test's one task outlasts its measurement (both workers still running after 4 s)" "[ $both_running -eq 1 ]"
busy=$(( b1 - a1 > b2 - a2 ? b1 - a1 : b2 - a2 )); idle=$(( b1 - a1 > b2 - a2 ? b2 - a2 : b1 - a1 ))
echo "CPU over 3 s [1/100 s]: working worker $busy, waiting worker $idle"
check "a waiting worker uses less than a tenth of the working one's CPU ($idle vs $busy)" "[ $busy -gt 0 ] && [ $((10 * idle)) -lt $busy ]"

finish "reliability_fault"
