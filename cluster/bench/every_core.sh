#!/usr/bin/env bash
# Every core computes (docs/reports/early-stop-and-every-core.md): ratios measured side by side
# in one run, never asserted.
#  1. 16 equal chains (sweeps/paper_ramps.toml's protocol at 16 drive radii 15.00-15.75 mm, each
#     chain about the same work) under `mpirun -n 2`: CPU time / wall time with rank 0
#     integrating beside the master (--threads 1, the default) and with the master alone
#     (--threads 0, the farm before this change); the same file either way (h5diff).
#  2. The same 16 chains in one process (the root path of ./setup.sh demo): --threads 2 against 1.
#  3. The demo's sweep (sweeps/paper.toml -> out/paper.h5) as ./setup.sh demo runs it on this
#     machine, against the same sweep as it ran before (one process, every settle at full
#     length; or BASELINE, another build such as main's): wall time ratio.
# Usage: cluster/bench/every_core.sh [BUILD_DIR] [BASELINE_ASTROJAX]
#        (MPIRUN_FLAGS=--allow-run-as-root as root)   Some 2 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
baseline=${2:-}
exe="$build/astrojax"
mpirun=(mpirun --oversubscribe ${MPIRUN_FLAGS:-})
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cores=$(nproc)

# wall user sys of a command, from /usr/bin/time (children included: mpirun's ranks)
measure() { /usr/bin/time -f "%e %U %S" -o "$out/time" "$@" > "$out/log" 2>&1 || { cat "$out/log"; exit 1; }; cat "$out/time"; }
ratio() { awk -v w="$1" -v u="$2" -v s="$3" 'BEGIN { printf "%.2f", (u + s) / w }'; }

radii="[0.01500,0.01505,0.01510,0.01515,0.01520,0.01525,0.01530,0.01535,0.01540,0.01545,0.01550,0.01555,0.01560,0.01565,0.01570,0.01575]"
chains=(sweeps/paper_ramps.toml -q --force --set "grid.drive_radius=$radii")
echo "== 1. 16 equal chains under mpirun -n 2 on $cores cores: CPU / wall"
for t in 1 0; do
  read -r w u s < <(measure "${mpirun[@]}" -n 2 "$exe" sweep "${chains[@]}" -o "$out/m$t.h5" --threads $t)
  echo "  --threads $t: wall $w s, user $u s, sys $s s: CPU/wall $(ratio "$w" "$u" "$s")"
done
h5diff --exclude-path /provenance "$out/m1.h5" "$out/m0.h5" > /dev/null && echo "  the two files are identical (h5diff, /provenance aside)"
echo "== 2. the same 16 chains in one process: --threads 2 against 1"
for t in 2 1; do
  read -r w u s < <(measure "$exe" sweep "${chains[@]}" -o "$out/p$t.h5" --threads $t)
  eval "wall_p$t=$w"
  echo "  --threads $t: wall $w s, CPU/wall $(ratio "$w" "$u" "$s")"
done
h5diff --exclude-path /provenance "$out/p2.h5" "$out/m1.h5" > /dev/null && echo "  identical to the mpirun file"
awk -v a="$wall_p2" -v b="$wall_p1" 'BEGIN { printf "  wall ratio 2 threads / 1 thread: %.2f\n", a / b }'

echo "== 3. the demo's sweep, sweeps/paper.toml, as ./setup.sh demo runs it"
ranks=$(( cores < 2 ? 2 : cores ))
if [ "$(id -u)" -eq 0 ]; then
  demo=("$exe" sweep sweeps/paper.toml -q --force -o "$out/demo.h5" --threads "$ranks" --set protocol.early_stop=true)
else
  demo=(mpirun -n "$ranks" "$exe" sweep sweeps/paper.toml -q --force -o "$out/demo.h5" --set protocol.early_stop=true)
fi
if [ -n "$baseline" ]; then
  before=("$baseline" sweep sweeps/paper.toml -q --force -o "$out/before.h5")
  label="$baseline, one process"
else
  before=("$exe" sweep sweeps/paper.toml -q --force -o "$out/before.h5" --threads 1 --set protocol.early_stop=false)
  label="one process, early stop off"
fi
if [ "$(id -u)" -ne 0 ] && [ -z "$baseline" ]; then
  before=(mpirun -n "$ranks" "$exe" sweep sweeps/paper.toml -q --force -o "$out/before.h5" --threads 0 --set protocol.early_stop=false)
  label="mpirun -n $ranks, master alone, early stop off"
fi
read -r w1 u1 s1 < <(measure "${before[@]}")
echo "  before ($label): wall $w1 s, CPU $(awk -v u="$u1" -v s="$s1" 'BEGIN{print u+s}') s"
read -r w2 u2 s2 < <(measure "${demo[@]}")
echo "  now (${demo[*]:0:3} ...): wall $w2 s, CPU $(awk -v u="$u2" -v s="$s2" 'BEGIN{print u+s}') s"
awk -v a="$w2" -v b="$w1" 'BEGIN { printf "  demo sweep wall ratio now / before: %.2f\n", a / b }'
