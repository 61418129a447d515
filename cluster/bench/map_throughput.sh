#!/usr/bin/env bash
# How many ranks a map by bisection keeps busy: the master's cost per result against a probe's.
#
#   cluster/bench/map_throughput.sh [BUILD_DIR] [RANKS...]     (MPIRUN_FLAGS=--allow-run-as-root as root)
#
# Runs sweeps/maps/example.toml on a 6 × 4 grid of (R, d) (48 chains: ω_fall and ω1 at 24 points)
# under mpirun -n N --threads 0 for N in RANKS (default 2 4 8, oversubscribed where the machine
# has fewer cores): rank 0 is then the master alone (it hands out probes, journals and commits
# their results to the HDF5 file) and is timed on its own, N − 1 ranks integrate. From the run
# on 2 ranks and the one on the most ranks:
#   tau = the worker's CPU / probes run (2 ranks)  [s]  one probe's integration (and its seed)
#   c   = the master's CPU / results (most ranks)  [s]  what one result costs rank 0, an upper
#         bound: it includes the master's start (plan, file) and, with fewer workers, its waiting
#         in MPI for their results (on 2 ranks it is the largest)
# A master serves at most tau/c workers before it becomes the bottleneck; a map keeps at most
# its chains busy (grid points × thresholds: a chain's probes run in order). A map of 10^4
# grid points with two thresholds has 2·10^4 chains, so it keeps min(tau/c, 2·10^4) ranks busy.
# Prints, per N: wall time, the master's CPU and its share of the CPU of all ranks; then c, tau
# and the projection. About two minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=$(realpath "${1:-build}")
shift || true
ranks=${*:-2 4 8}
mpirun=(mpirun --oversubscribe ${MPIRUN_FLAGS:-})
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
grid=(--set "grid.drive_radius=[0.005,0.01,0.015,0.02,0.025,0.03]" --set "grid.contact_distance=[0.02,0.03,0.04,0.05]")

echo "map: sweeps/maps/example.toml on 6 × 4 (R, d), ω_fall and ω1 to 0.1π ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
printf "  %6s %10s %16s %18s %14s\n" "ranks" "wall [s]" "master CPU [s]" "all ranks CPU [s]" "master share"
for n in $ranks; do
  # Every rank writes its own user + sys seconds; rank 0 is the master alone (--threads 0).
  "${mpirun[@]}" -n "$n" sh -c "exec /usr/bin/time -f '%U %S' -o '$work/cpu.$n.'\$OMPI_COMM_WORLD_RANK \
    '$build/astrojax' sweep sweeps/maps/example.toml ${grid[*]@Q} -o '$work/map$n.h5' -q --threads 0" \
    > "$work/out.$n" 2>&1 || { cat "$work/out.$n"; exit 1; }
  wall=$(grep -o 'in [0-9.]* s wall' "$work/out.$n" | grep -o '[0-9.]*')
  master=$(awk '{ print $1 + $2 }' "$work/cpu.$n.0")
  all=$(cat "$work/cpu.$n".* | awk '{ s += $1 + $2 } END { print s }')
  printf "  %6d %10.2f %16.2f %18.2f %13.1f%%\n" "$n" "$wall" "$master" "$all" "$(python3 -c "print(100*$master/$all)")"
done
first=$(echo $ranks | cut -d' ' -f1); last=$(echo $ranks | awk '{ print $NF }')
[ "$first" = 2 ] || { echo "(the projection needs a run on 2 ranks)"; exit 0; }
/usr/bin/python3 - "$work/map2.h5" "$work/cpu.$last.0" "$work/cpu.2.1" <<'PY'
import sys
import h5py
f = h5py.File(sys.argv[1])
results = len(f["tasks/status"])            # every probe of every chain reports, run or not
probes = int(f["brackets/probes/ran"][:].sum())
cpu = lambda p: sum(float(x) for x in open(p).read().split()[:2])
c, tau = cpu(sys.argv[2]) / results, cpu(sys.argv[3]) / max(probes, 1)
busy = tau / c
chains = 2 * 10**4
print(f"master: at most {c * 1e3:.2f} ms of CPU per result ({results} results); worker: {tau * 1e3:.1f} ms per probe "
      f"({probes} probes run)")
print(f"one master serves at least tau/c = {busy:.0f} workers; a map of 10^4 grid points (2·10^4 chains of ω_fall and ω1) "
      f"keeps min({busy:.0f}, {chains}) = {min(busy, chains):.0f} ranks busy")
PY
