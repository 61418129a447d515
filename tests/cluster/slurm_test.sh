#!/usr/bin/env bash
# The cluster scripts against a real Slurm on this machine: installs Debian's slurm-wlm and
# munge when missing (needs root), starts munged, slurmctld and slurmd with a minimal
# configuration in a temporary directory (nothing under /etc is changed), and then
#  1. submits cluster/sweep.sbatch on the quick sweep and checks the job's file;
#  2. submits a longer sweep, signals it mid-way as the time limit would
#     (scancel --batch --signal=USR1), lets run_sweep.sh requeue it, and checks that the
#     requeued job resumed and that its file equals an uninterrupted run's (h5diff, all but
#     /provenance);
#  3. runs cluster/array.sbatch over a list of two sweep files.
# Usage: slurm_test.sh ASTROJAX SOURCE_DIR     (ctest -L cluster; ./setup.sh test-cluster)
# Exit 77 (skipped) when not root: the daemons and apt need it.
set -u
bin=$1; src=$2
if [ "$(id -u)" -ne 0 ]; then echo "slurm_test: needs root (apt, munged, slurmd); skipped"; exit 77; fi
missing=()
for p in slurm-wlm munge; do
  dpkg-query -W -f='${Status}' "$p" 2> /dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing ${missing[*]}"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq -o DPkg::Lock::Timeout=600 \
    --no-install-recommends "${missing[@]}" > /dev/null || { echo "FAIL: apt-get install ${missing[*]}"; exit 1; }
fi

T=$(mktemp -d /tmp/ajx_slurm.XXXXXX)
chmod 755 "$T"
pids=()
cleanup() {
  # Only what this test started, by pid: jobs first, then the daemons.
  [ -f "$T/slurm.conf" ] && SLURM_CONF="$T/slurm.conf" scancel --quiet --user=root 2> /dev/null
  sleep 1
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2> /dev/null || break; sleep 0.1; done
    kill -9 "$p" 2> /dev/null
  done
  if [ "${KEEP:-0}" = 1 ]; then echo "kept $T"; else rm -rf "$T"; fi
}
trap cleanup EXIT
fail=0; pass=0
check() { if eval "$2"; then pass=$((pass+1)); echo "ok: $1"; else echo "FAIL: $1"; fail=$((fail+1)); fi; }
die() { echo "FAIL: $*"; for f in "$T"/*.log; do echo "--- $f"; tail -20 "$f"; done; exit 1; }

# munge: its own key, socket and logs in $T.
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 status=none
chmod 600 "$T/munge.key"
mkdir -m 755 "$T/munge"
munged --foreground --force --key-file="$T/munge.key" --socket="$T/munge/munge.sock" \
  --pid-file="$T/munge/munged.pid" --log-file="$T/munged.log" --seed-file="$T/munge/seed" > "$T/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$T/munge/munge.sock" ] && break; sleep 0.1; done
[ -S "$T/munge/munge.sock" ] || die "munged did not start"

host=$(hostname -s)
port=$((20000 + $$ % 20000))
mkdir -p "$T/state" "$T/spool"
# A node with more CPUs than cores (config_overrides): a master and 2 workers on 2 cores.
cat > "$T/slurm.conf" <<CONF
ClusterName=ajxtest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$T/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
MpiDefault=none
JobRequeue=1
ReturnToService=2
SchedulerType=sched/builtin
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=4 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$T/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" > "$T/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" > "$T/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do sinfo -h -o %T 2> /dev/null | grep -qx idle && break; sleep 0.3; done
sinfo -h -o %T 2> /dev/null | grep -qx idle || die "the node did not become idle: $(sinfo 2>&1)"
echo "slurm up: $(sinfo -h -o '%P %D %T %c')"

# The job's environment: this build; root may run mpirun in this test only.
export ASTROJAX_DIR=$src ASTROJAX_BIN=$bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
job_state() { scontrol show job "$1" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p'; }
wait_done() {  # job id, seconds
  for _ in $(seq $(($2 * 5))); do
    case "$(job_state "$1")" in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | "") return 0 ;; esac
    sleep 0.2
  done
  return 1
}
exit_code() { scontrol show job "$1" | sed -n 's/.* ExitCode=\([0-9]*\):.*/\1/p'; }
same_file() {  # two sweep files equal in everything but /provenance
  for g in /config /chains /windows /samples /tasks; do h5diff "$1" "$2" "$g" > /dev/null 2>&1 || return 1; done
}

cd "$T"
# 1. The quick sweep as a batch job on 3 ranks, started by mpirun.
j1=$(ASTROJAX_LAUNCHER=mpirun sbatch --parsable --ntasks=3 --time=10 --output="$T/quick-%j.log" "$src/cluster/sweep.sbatch" \
  "$src/sweeps/quick.toml" "$T/quick.h5" -q)
check "sbatch sweep.sbatch accepted (job '$j1')" "[ -n '$j1' ]"
wait_done "$j1" 300 || echo "job $j1 still $(job_state "$j1") after 300 s"
cat "$T"/quick-*.log
check "quick sweep job COMPLETED with exit 0 ($(job_state "$j1"), $(exit_code "$j1"))" \
  "[ '$(job_state "$j1")' = COMPLETED ] && [ '$(exit_code "$j1")' = 0 ]"
check "quick sweep: the file is complete, on 3 ranks" \
  "[ -s '$T/quick.h5' ] && [ ! -e '$T/quick.h5.part' ] && h5dump -a /provenance/ranks '$T/quick.h5' | grep -q '(0): 3'"
check "quick sweep: started by mpirun" "grep -q '\] mpirun -n 3' '$T'/quick-*.log"
check "quick sweep: every window classified" "! h5dump -A 0 -d /windows/class '$T/quick.h5' | grep -q -- '-1'"

# 2. Signalled mid-way, requeued, resumed. The sweep: the quick one with 1 window per task over
# 8 drive radii (264 tasks, a few seconds on 2 cores); the signal comes once its journal holds
# a few tasks, as the time limit would (scancel --batch --signal=USR1 = what --signal=B:USR1 sends).
long=(--set protocol.windows_per_task=1 --set "grid.drive_radius=[0.01,0.011,0.012,0.013,0.015,0.017,0.019,0.02]")
# The launcher: srun --mpi=pmix where Slurm has it (Debian's does), which forwards the signal.
j2=$(sbatch --parsable --ntasks=3 --time=10 --output="$T/long-%j.log" \
  "$src/cluster/sweep.sbatch" "$src/sweeps/quick.toml" "$T/long.h5" "${long[@]}")
for _ in $(seq 3000); do [ "$(stat -c %s "$T/long.h5.journal" 2> /dev/null || echo 0)" -gt 300000 ] && break; sleep 0.01; done
check "the long job was still running when signalled" "[ '$(job_state "$j2")' = RUNNING ] && [ -e '$T/long.h5.part' ]"
scancel --batch --signal=USR1 "$j2"
# The job requeues itself and runs again; wait for the second run to finish. Slurm holds a
# requeued batch job until a begin time some minutes on: release it now to save the wait.
for _ in $(seq 600); do [ "$(job_state "$j2")" = PENDING ] && break; sleep 0.2; done
scontrol update JobId="$j2" StartTime=now
for _ in $(seq 1500); do grep -q "resuming" "$T/long-$j2.log" 2> /dev/null && break; sleep 0.2; done
sleep 1
wait_done "$j2" 300 || echo "job $j2 still $(job_state "$j2") after 300 s"
cat "$T/long-$j2.log"
check "signalled job: master stopped with exit 4 and the job requeued itself" \
  "grep -q 'exited with 4' '$T/long-$j2.log' && grep -q 'requeueing job' '$T/long-$j2.log'"
check "requeued job resumed from the .part and completed ($(job_state "$j2"), $(exit_code "$j2"))" \
  "grep -q 'resuming' '$T/long-$j2.log' && [ '$(job_state "$j2")' = COMPLETED ] && [ '$(exit_code "$j2")' = 0 ]"
check "long sweep: started by srun --mpi=pmix" "grep -q '\] srun --mpi=pmix' '$T/long-$j2.log'"
check "restart count 1" "scontrol show job '$j2' | grep -q 'Restarts=1'"
"$bin" sweep "$src/sweeps/quick.toml" -o "$T/straight.h5" -q "${long[@]}" > "$T/straight.out" 2>&1
check "uninterrupted run of the same sweep: exit 0" "[ $? -eq 0 ]"
check "resumed file equals the uninterrupted one (h5diff but /provenance)" "same_file '$T/long.h5' '$T/straight.h5'"

# 3. A job array over a list of two sweep files.
printf '# two sweeps\n%s\n\n%s --set grid.drive_radius=[0.015]\n' "$src/tests/data/tiny_sweep.toml" \
  "$src/tests/data/tiny_hold.toml" > "$T/list.txt"
j3=$(sbatch --parsable --array=1-2 --ntasks=2 --time=10 --output="$T/array-%A_%a.log" \
  "$src/cluster/array.sbatch" "$T/list.txt" "$T/arr")
for k in 1 2; do wait_done "${j3}_$k" 300 || echo "array element $k still running"; done
cat "$T"/array-*.log
check "array element 1 wrote arr/tiny_sweep.h5" "[ -s '$T/arr/tiny_sweep.h5' ]"
check "array element 2 wrote arr/tiny_hold.h5 with its option (R = 1.5 cm)" \
  "h5dump -d /chains/grid_values '$T/arr/tiny_hold.h5' | grep -q '0.015'"

echo "slurm_test: $pass passed, $fail failed"
[ $fail -eq 0 ]
