#!/usr/bin/env bash
# cluster/run_sweep.sh's exit codes and requeue decision, under a real mpirun with a stand-in for
# astrojax (a script that waits for SIGUSR1 and then exits with the code it is given, leaving a
# journal or not) and a stand-in for Slurm's scontrol that records what it is asked:
# - a stop signal to the script (SIGTERM), the sweep exiting 4: requeued inside Slurm, exit 4;
#   outside Slurm (no SLURM_JOB_ID): not requeued, exit 4;
# - the sweep exiting 5 (disk full), 3 or 2 after a stop: exit the same, never requeued;
# - SIGTERM to the script and to mpirun at once (as scancel and the time limit deliver it):
#   mpirun's own 1 with the sweep's journal left is an interruption: 4, requeued; without a
#   journal it stays 1 and is not requeued.
# Usage: run_sweep_codes_test.sh SOURCE_DIR
set -u
src=$1
source "$(dirname "$0")/check.sh"
cd "$work"
mkdir bin
# The stand-in for astrojax: "sweep FILE -o OUT ...". STUB_JOURNAL=1 leaves OUT.journal, as an
# interrupted sweep does; on SIGUSR1 or SIGTERM it exits STUB_CODE.
cat > bin/astrojax <<'SH'
#!/usr/bin/env bash
out=$4
[ "${STUB_JOURNAL:-0}" = 1 ] && touch "$out.journal"
trap 'exit $STUB_CODE' USR1 TERM
touch "$out.started"
while true; do sleep 0.05; done
SH
cat > bin/scontrol <<'SH'
#!/usr/bin/env bash
echo "$*" >> "$(dirname "$0")/../scontrol.log"
SH
chmod +x bin/astrojax bin/scontrol
touch sweep.toml

# case NAME CODE JOURNAL SLURM SIGNAL_MPIRUN: runs run_sweep.sh, stops it with SIGTERM (and
# mpirun too when SIGNAL_MPIRUN=1); sets rc and requeued (1 when scontrol was asked to requeue).
run_case() {
  local name=$1 code=$2 journal=$3 slurm=$4 both=$5
  rm -f out.h5* scontrol.log
  env PATH="$work/bin:$PATH" ASTROJAX_BIN="$work/bin/astrojax" ASTROJAX_LAUNCHER=mpirun STUB_CODE=$code \
    STUB_JOURNAL=$journal ${slurm:+SLURM_JOB_ID=4242} SLURM_NTASKS=1 "$src/cluster/run_sweep.sh" sweep.toml out.h5 \
    > "$name.out" 2>&1 &
  local sp=$! launcher=
  for _ in $(seq 300); do [ -e out.h5.started ] && break; sleep 0.05; done
  launcher=$(pgrep -P $sp -x mpirun)
  kill -TERM $sp
  [ "$both" = 1 ] && [ -n "$launcher" ] && kill -TERM $launcher
  for _ in $(seq 300); do kill -0 $sp 2> /dev/null || break; sleep 0.1; done
  if kill -0 $sp 2> /dev/null; then echo "$name: run_sweep.sh still running after 30 s: killed"; kill -KILL $sp $launcher; fi
  wait $sp; rc=$?
  requeued=0; grep -q "requeue 4242" scontrol.log 2> /dev/null && requeued=1
}

run_case stop4_slurm 4 1 1 0
check "SIGTERM, the sweep interrupted (4), in Slurm: exit 4 (got $rc) and requeued ($requeued)" "[ $rc -eq 4 ] && [ $requeued -eq 1 ]"
run_case stop4 4 1 "" 0
check "SIGTERM, the sweep interrupted (4), outside Slurm: exit 4 (got $rc), not requeued" \
  "[ $rc -eq 4 ] && [ $requeued -eq 0 ] && grep -q 'continue with' stop4.out"
for code in 5 3 2; do
  run_case "stop$code" $code 1 1 0
  check "SIGTERM, the sweep exiting $code: exit $code (got $rc), not requeued ($requeued)" "[ $rc -eq $code ] && [ $requeued -eq 0 ]"
done
run_case both_journal 4 1 1 1
check "SIGTERM to the script and to mpirun, the journal left: exit 4 (got $rc), requeued ($requeued)" \
  "[ $rc -eq 4 ] && [ $requeued -eq 1 ] && grep -q 'interrupted (4)' both_journal.out"
run_case both_nojournal 4 0 1 1
check "SIGTERM to the script and to mpirun, no journal: mpirun's 1 (got $rc), not requeued ($requeued)" \
  "[ $rc -eq 1 ] && [ $requeued -eq 0 ]"

finish "run_sweep_codes"
