#!/usr/bin/env bash
# Measures the figures of docs/cluster/index.md, "Scale", on this machine and projects them:
#  1. the master's throughput with tasks that take no time (farm_throughput), on 2 to 17 ranks
#     (oversubscribed), with tiny outputs and with outputs the size of a sweep task's;
#  2. a sweep task's costs on 1 rank: integration per window (tau_w) and the master's work per
#     window (classify, journal, HDF5), from sweeps/paper_ramps.toml on 4 drive radii;
#  3. parallel efficiency, 1 vs 2 workers, on the quick sweep over 8 drive radii (8 chains), both
#     under mpirun -n 2: the master alone and rank 1 (--threads 0), then rank 0 integrating too;
#  4. the projection to 64, 512 and 4096 ranks (cluster/bench/project.py), and for 10^4 chains
#     of one short task each, as a basin sweep has: sweeps/basins.toml at 4 starts per level (256
#     chains) on 1 rank and under mpirun -n 2, and the farm's message rate with their outputs.
#  With BASELINE_ASTROJAX (another build, such as main's), step 2b and the basin projection are
#  also made with it, side by side.
# Usage: cluster/bench/scaling.sh [BUILD_DIR] [BASELINE_ASTROJAX]   (MPIRUN_FLAGS=--allow-run-as-root as root)
# Some 3 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
baseline=${2:-}
mpirun=(mpirun --oversubscribe ${MPIRUN_FLAGS:-})
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "== 1. master throughput, tasks of no duration (64 chains x 300 tasks)"
for n in 2 3 5 9 17; do "${mpirun[@]}" -n $n "$build/farm_throughput" 64 300 64; done
echo "== 2. a sweep on 1 rank (sweeps/paper_ramps.toml, 4 drive radii)"
"$build/astrojax" sweep sweeps/paper_ramps.toml -o "$out/paper1.h5" -q --set "grid.drive_radius=[0.005,0.01,0.015,0.02]"
echo "== 3. 1 and 2 workers (sweeps/quick.toml, 8 drive radii)"
quick=(sweeps/quick.toml -q --set "grid.drive_radius=[0.01,0.011,0.012,0.013,0.015,0.017,0.019,0.02]")
"${mpirun[@]}" -n 2 "$build/astrojax" sweep "${quick[@]}" -o "$out/w1.h5" --threads 0
"${mpirun[@]}" -n 2 "$build/astrojax" sweep "${quick[@]}" -o "$out/w2.h5"
echo "== 2b. basin tasks (sweeps/basins.toml, 4 starts per level: 256 chains of one task) on 1 rank and on 2"
basin=(sweeps/basins.toml -q --set basin.samples=4)
"$build/astrojax" sweep "${basin[@]}" -o "$out/basin1.h5" || [ $? -eq 3 ]  # exit 3: a start that fails is a result
"${mpirun[@]}" -n 2 "$build/astrojax" sweep "${basin[@]}" -o "$out/basin2.h5" || [ $? -eq 3 ]
if [ -n "$baseline" ]; then
  echo "   the same with $baseline"
  "$baseline" sweep "${basin[@]}" -o "$out/base1.h5" || [ $? -eq 3 ]
  "${mpirun[@]}" -n 2 "$baseline" sweep "${basin[@]}" -o "$out/base2.h5" || [ $? -eq 3 ]
fi
bytes=$(/usr/bin/python3 -c "import h5py; f=h5py.File('$out/w2.h5'); p=f['provenance'].attrs; print(int(p['bytes_from_workers'] / len(f['tasks/status'])))")
echo "== 1b. master throughput with outputs of a quick-sweep task ($bytes B)"
for n in 2 3 5 9 17; do "${mpirun[@]}" -n $n "$build/farm_throughput" 64 100 "$bytes"; done | tee "$out/tput.txt"
bytes=$(/usr/bin/python3 -c "import h5py; f=h5py.File('$out/basin2.h5'); p=f['provenance'].attrs; print(int(p['bytes_from_workers'] / len(f['tasks/status'])))")
echo "== 1c. master throughput with outputs of a basin task ($bytes B)"
for n in 2 3 5 9 17; do "${mpirun[@]}" -n $n "$build/farm_throughput" 64 100 "$bytes"; done | tee "$out/tput_basin.txt"
echo "== 4. projection"
/usr/bin/python3 cluster/bench/project.py "$out/paper1.h5" "$out/w1.h5" "$out/w2.h5" "$out/tput.txt" \
  "$out/basin1.h5" "$out/basin2.h5" "$out/tput_basin.txt"
if [ -n "$baseline" ]; then
  echo "== 4b. the basin projection with $baseline"
  /usr/bin/python3 cluster/bench/project.py "$out/paper1.h5" "$out/w1.h5" "$out/w2.h5" "$out/tput.txt" \
    "$out/base1.h5" "$out/base2.h5" "$out/tput_basin.txt" | sed -n '/^basin tasks/,$p'
fi
