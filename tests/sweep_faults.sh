# Shared by the sweep fault tests (source it after check.sh, with bin, mpiexec and src set): the
# sweep they interrupt, file comparison, and starting, watching and resuming it on 3 ranks.
# Fixed-step RK4 at 0.1 ms makes each sweep about 3 s of CPU, so that every fault lands mid-sweep:
# with its own dop853 the quick sweep ends in 0.3 s, and a kill the scheduler delays could come
# after the end.
sweep=("$src/sweeps/quick.toml" -q --set protocol.windows_per_task=1 --set "grid.drive_radius=[0.01,0.015,0.02]"
       --set integrator.method=rk4 --set integrator.step=1e-4)
same() { for g in /config /chains /windows /samples /tasks; do h5diff "$1" "$2" "$g" > /dev/null 2>&1 || return 1; done; }
size() { stat -c %s "$1" 2> /dev/null || echo 0; }
# Whether process $1 runs: exists and is not a zombie (a rank whose mpirun died is reparented,
# and its new parent may not reap it at once; kill -0 answers for a zombie too).
running() { local st; st=$(awk '{print $3}' "/proc/$1/stat" 2> /dev/null); [ -n "$st" ] && [ "$st" != Z ]; }
# The MPI rank of process $1.
rank_of() { tr '\0' '\n' < "/proc/$1/environ" 2> /dev/null | sed -n 's/^OMPI_COMM_WORLD_RANK=//p'; }
# Starts the sweep on 3 ranks into $1 and waits until its journal holds more than $2 bytes
# (some tasks done, most not); sets mp (mpirun's pid) and rank0..rank2 (the ranks' pids).
start_mpi() {
  rm -f "$1"*
  "$mpiexec" --oversubscribe -n 3 "$bin" sweep "${sweep[@]}" -o "$1" "${@:3}" > "$1.out" 2>&1 &
  mp=$!; out="$1.out"
  for _ in $(seq 1500); do [ "$(size "$1.journal")" -gt "$2" ] && break; sleep 0.01; done
  rank0=; rank1=; rank2=
  for k in $(pgrep -P $mp); do
    r=$(rank_of $k)
    [ -n "$r" ] && eval "rank$r=$k"
  done
}
# Waits until the given pids are gone (the ranks of a killed job).
gone() { for p in "$@"; do for _ in $(seq 100); do kill -0 "$p" 2> /dev/null || break; sleep 0.1; done; done; }
# The children of $1 that have not exited (a rank that exited and is not reaped yet is a zombie).
live_children() { for c in $(pgrep -P "$1"); do [ "$(awk '{print $3}' "/proc/$c/stat" 2> /dev/null)" = Z ] || echo "$c"; done; }

# Waits for a launcher started in the background ($1: its pid) for at most $2 s, with the
# master's output in $3, and sets rc. Every wait on an mpirun goes through here, so that no
# test can hang:
# - it ends: rc is its exit code;
# - it stays waiting 10 s after every rank it started has exited (Open MPI's mpirun here does,
#   about 1 run in 6): killed, and rc read from the master's summary line, which the master
#   printed before it exited (ok 0, FAILED 3, INTERRUPTED 4, none 99); mpirun_hung=1;
# - it still runs after $2 s: killed with its ranks; rc 124.
wait_mpi() {
  local pid=$1 limit=$2 out=$3 idle=0 n
  mpirun_hung=0
  for n in $(seq $((limit * 10))); do
    kill -0 "$pid" 2> /dev/null || break
    if [ -z "$(live_children "$pid")" ]; then idle=$((idle + 1)); else idle=0; fi
    [ $idle -ge 100 ] && break
    sleep 0.1
  done
  if ! kill -0 "$pid" 2> /dev/null; then
    wait "$pid"; rc=$?
  elif [ $idle -ge 100 ]; then
    echo "mpirun still waiting 10 s after its ranks exited: killed, the code read from the summary"
    kill -KILL "$pid" 2> /dev/null; wait "$pid" 2> /dev/null
    mpirun_hung=1
    rc=$(code_from_summary "$out")
  else
    echo "still running after $limit s: killed"
    local kids; kids=$(pgrep -P "$pid")
    kill -KILL $kids "$pid" 2> /dev/null; wait "$pid" 2> /dev/null
    rc=124
  fi
}
# The master's summary line: its first word, then two spaces.
summary_re='^(ok|FAILED|INTERRUPTED)  '
# The exit code the master's summary line in $1 stands for (ok 0, FAILED 3, INTERRUPTED 4, none 99).
code_from_summary() {
  case "$(grep -oE "$summary_re" "$1" | tail -1)" in
    "ok  ") echo 0 ;; "FAILED  ") echo 3 ;; "INTERRUPTED  ") echo 4 ;; *) echo 99 ;;
  esac
}
# Waits for a background process that is not a launcher ($1) for at most $2 s and sets rc (124
# and killed if it still runs).
wait_for() {
  for _ in $(seq $(($2 * 10))); do kill -0 "$1" 2> /dev/null || break; sleep 0.1; done
  if kill -0 "$1" 2> /dev/null; then echo "still running after $2 s: killed"; kill -KILL "$1"; wait "$1" 2> /dev/null; rc=124
  else wait "$1"; rc=$?; fi
}
# Resumes the sweep of start_mpi into $1 on 3 ranks (at most 120 s); its exit code is the
# function's and rc's.
resume() {
  "$mpiexec" --oversubscribe -n 3 "$bin" sweep "${sweep[@]}" -o "$1" --resume > "$1.resume" 2>&1 &
  wait_mpi $! 120 "$1.resume"
  return $rc
}

# SIGSTOPs rank 2 of the job start_mpi started and waits up to $1 s for the master to end the
# sweep: its summary line printed (and the file written), or the master gone (sets master_ended
# 0/1 and waited [s]). The summary, not the process's exit, is what the master controls: its
# MPI_Abort then leaves the ending to Open MPI, whose mpirun now and then takes ~30 s to kill
# it (seen about 1 run in 10 here, with "ORTE_ERROR_LOG: Data unpack would read past end of
# buffer" from show_help.c). Then lets mpirun end and rank 2 go on, so that nothing is left
# behind; sets rc to mpirun's exit code (wait_mpi).
summary_printed() { grep -qE "$summary_re" "$1" 2> /dev/null; }
stop_rank2() {
  kill -STOP "$rank2"
  local t0=$(date +%s)
  for _ in $(seq $(($1 * 10))); do running "$rank0" && ! summary_printed "$out" || break; sleep 0.1; done
  waited=$(($(date +%s) - t0)); master_ended=0
  { ! running "$rank0" || summary_printed "$out"; } && master_ended=1
  for _ in $(seq 100); do kill -0 "$mp" 2> /dev/null || break; sleep 0.1; done
  kill -CONT "$rank2" 2> /dev/null
  wait_mpi "$mp" 60 "$out"
  # Open MPI 4's mpirun now and then dies by a signal (SIGSEGV seen) while it carries out the
  # master's MPI_Abort; the master had printed its summary and closed the file by then, so its
  # code is read from the summary.
  if [ $rc -ge 128 ] && [ $rc -ne 137 ] && grep -q "ending the job" "$out"; then
    echo "mpirun died by signal $((rc - 128)) while ending the job: the code read from the master's summary"
    rc=$(code_from_summary "$out")
  fi
  gone $rank2
}
