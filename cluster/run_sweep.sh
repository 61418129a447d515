#!/usr/bin/env bash
# Runs one sweep inside a Slurm allocation, stopping cleanly on the time-limit signal and
# continuing where it stopped when the job runs again. Called by sweep.sbatch and array.sbatch;
# usable by hand inside `salloc`.
#
#   run_sweep.sh SWEEP_FILE OUTPUT.h5 [more astrojax sweep options]
#
# - The file: OUTPUT.h5 complete: nothing to do. OUTPUT.h5.part or .journal present: --resume (a requeued
#   or resubmitted job). Otherwise a fresh sweep.
# - The launcher (ASTROJAX_LAUNCHER = auto | srun | mpirun): srun --mpi=$ASTROJAX_SRUN_MPI
#   (default pmix) where Slurm has that PMI plugin, otherwise mpirun with one rank per task.
# - SIGUSR1 or SIGTERM to this script (sbatch --signal=B:USR1@GRACE, scancel --signal, a
#   preemption) is passed on as SIGUSR1: the sweep's master stops handing out tasks, writes those
#   in flight and exits with 4. The script then requeues the job (scontrol requeue) when the
#   job is requeueable, or says how to resubmit it.
# Exit codes: those of astrojax sweep (0 ok, 1 internal error, 2 bad input, 3 tasks failed,
# 4 interrupted, 5 output not writable: disk full; docs/reference/exit-codes.md). Only 4 is
# requeued: the others would fail again the same way (5 resumes with --resume once the disk has
# room). After a stop signal, a launcher's code other than 0, 2, 3 and 5 with the sweep's .part
# or journal left (mpirun's 1 when it got the SIGTERM itself) counts as 4.
set -uo pipefail

if [ $# -lt 2 ]; then sed -n '2,20p' "$0"; exit 2; fi
sweep_file=$1; output=$2; shift 2
bin=${ASTROJAX_BIN:-${ASTROJAX_DIR:-${SLURM_SUBMIT_DIR:-.}}/build/astrojax}
ntasks=${SLURM_NTASKS:-1}

log() { echo "[run_sweep $(date -u +%H:%M:%S) job ${SLURM_JOB_ID:-none}${SLURM_ARRAY_TASK_ID:+ array ${SLURM_ARRAY_TASK_ID}}] $*"; }

if [ ! -x "$bin" ]; then log "error: $bin is not an executable (set ASTROJAX_BIN or ASTROJAX_DIR)"; exit 2; fi
if [ -e "$output" ] && [ ! -e "$output.part" ] && [ ! -e "$output.journal" ]; then log "$output is complete: nothing to do"; exit 0; fi
resume=()
{ [ -e "$output.part" ] || [ -e "$output.journal" ]; } && resume=(--resume)

# srun where Slurm can start MPI ranks itself (its PMI plugin); mpirun otherwise. Under an
# allocation, Open MPI's mpirun reads the nodes and task counts from Slurm.
launcher=${ASTROJAX_LAUNCHER:-auto}
pmi=${ASTROJAX_SRUN_MPI:-pmix}
if [ "$launcher" = auto ]; then
  launcher=mpirun
  if command -v srun > /dev/null && srun --mpi=list 2>&1 | grep -qw "$pmi"; then launcher=srun; fi
fi
case "$launcher" in
  srun) cmd=(srun --mpi="$pmi" --kill-on-bad-exit=1 -n "$ntasks") ;;
  mpirun) cmd=(mpirun -n "$ntasks" ${ASTROJAX_MPIRUN_FLAGS:-}) ;;
  *) log "error: ASTROJAX_LAUNCHER must be auto, srun or mpirun, not '$launcher'"; exit 2 ;;
esac
cmd+=("$bin" sweep "$sweep_file" -o "$output" "${resume[@]}" "$@")

# The launcher runs in the background so that the signal reaches this shell at once (bash runs
# a trap only between commands; `wait` returns early for it).
stopping=0
child=
forward() {
  stopping=1
  log "stop signal: asking the sweep's master to finish the tasks in flight"
  [ -n "$child" ] && kill -USR1 "$child" 2> /dev/null
}
trap forward USR1 TERM
log "${cmd[*]}"
"${cmd[@]}" &
child=$!
while true; do
  wait "$child"; rc=$?
  # wait returns >128 when interrupted by a trapped signal while the child still runs.
  if kill -0 "$child" 2> /dev/null; then continue; fi
  break
done
trap - USR1 TERM
log "astrojax sweep exited with $rc"
# Open MPI's mpirun returns 1 for a job it was told to terminate (SIGTERM or SIGINT reaching
# mpirun itself, as scancel and Slurm's time limit deliver them to every process of the job),
# whatever its ranks return, and SIGKILLs the ranks a second later. A stop this script was
# asked for that leaves the sweep's .part or journal behind is an interruption all the same:
# the journal holds every finished task, so --resume continues it.
if [ $stopping -eq 1 ] && [ $rc -ne 0 ] && [ $rc -ne 2 ] && [ $rc -ne 3 ] && [ $rc -ne 5 ] &&
   { [ -e "$output.part" ] || [ -e "$output.journal" ]; }; then
  log "the launcher's $rc is that of a job stopped by a signal, and the sweep's .part or journal is there: interrupted (4)"
  rc=4
fi

if [ $rc -eq 4 ]; then
  if [ $stopping -eq 1 ] && [ -n "${SLURM_JOB_ID:-}" ] && [ "${ASTROJAX_REQUEUE:-1}" = 1 ]; then
    # A requeued job runs this script again from the top: the .part is there, so --resume.
    # (scontrol requeue ends this run of the script at once.)
    log "requeueing job $SLURM_JOB_ID: it continues from $output.part when it runs again"
    if scontrol requeue "$SLURM_JOB_ID"; then exit 4; fi
    log "could not requeue (was the job submitted with --requeue?)"
  fi
  log "continue with: sbatch the same script again (it resumes from $output.part)"
fi
exit $rc
