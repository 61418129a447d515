#!/usr/bin/env bash
# Every core computes (docs/reports/early-stop-and-every-core.md): ratios measured side by side
# in one run, never asserted.
#  1. 16 equal chains (sweeps/paper_ramps.toml's protocol at 16 drive radii 15.00-15.75 mm, each
#     chain about the same work) under `mpirun -n 2`: CPU time / wall time with rank 0
#     integrating beside the master (--threads 1, the default) and with the master alone
#     (--threads 0, the farm before this change); the same file either way (h5diff).
#  2. The same 16 chains in one process (the root path of ./setup.sh demo): --threads 2 against 1.
#  3. The demo's sweep (sweeps/paper.toml) as ./setup.sh demo runs it on this machine (as root one
#     process with a thread per core, else mpirun -n <cores>), against the same sweep as the demo
#     ran it before issue 29 (one process with one thread as root, else mpirun with the master
#     alone, --threads 0), and against BASELINE run as the demo runs it (another build, such as
#     main's): wall time ratios.
#  With BASELINE, section 1 also runs it under mpirun -n 2 (its default threads) beside this build.
# Usage: cluster/bench/every_core.sh [BUILD_DIR] [BASELINE_ASTROJAX]
#        (MPIRUN_FLAGS=--allow-run-as-root as root)   Some 3 minutes on 2 cores.
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
if [ -n "$baseline" ]; then
  read -r w u s < <(measure "${mpirun[@]}" -n 2 "$baseline" sweep "${chains[@]}" -o "$out/mb.h5")
  echo "  $baseline (its default threads): wall $w s, CPU/wall $(ratio "$w" "$u" "$s")"
  h5diff --exclude-path /provenance "$out/m1.h5" "$out/mb.h5" > /dev/null && echo "  identical to this build's file"
fi
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
paper=(sweep sweeps/paper.toml -q --force)
# As ./setup.sh demo runs EXE into FILE; OLD=1: as the demo ran before issue 29.
demo_run() {
  local exe=$1 file=$2 old=${3:-}
  if [ "$(id -u)" -eq 0 ]; then
    measure "$exe" "${paper[@]}" -o "$file" --threads "$([ -n "$old" ] && echo 1 || echo "$ranks")"
  else
    measure mpirun -n "$ranks" "$exe" "${paper[@]}" -o "$file" $([ -n "$old" ] && echo --threads 0)
  fi
}
cpu() { awk -v u="$1" -v s="$2" 'BEGIN { print u + s }'; }
read -r w2 u2 s2 < <(demo_run "$exe" "$out/demo.h5")
echo "  now ($([ "$(id -u)" -eq 0 ] && echo "one process, --threads $ranks" || echo "mpirun -n $ranks")): wall $w2 s, CPU $(cpu "$u2" "$s2") s"
read -r w1 u1 s1 < <(demo_run "$exe" "$out/before.h5" old)
echo "  as before issue 29 ($([ "$(id -u)" -eq 0 ] && echo "one process, one thread" || echo "mpirun -n $ranks, master alone")): wall $w1 s, CPU $(cpu "$u1" "$s1") s"
awk -v a="$w2" -v b="$w1" 'BEGIN { printf "  demo sweep wall ratio now / before issue 29: %.2f\n", a / b }'
h5diff --exclude-path /provenance "$out/demo.h5" "$out/before.h5" > /dev/null && echo "  the two files are identical"
if [ -n "$baseline" ]; then
  read -r w3 u3 s3 < <(demo_run "$baseline" "$out/base.h5")
  echo "  $baseline as the demo runs it: wall $w3 s, CPU $(cpu "$u3" "$s3") s"
  awk -v a="$w2" -v b="$w3" 'BEGIN { printf "  demo sweep wall ratio this build / baseline: %.2f\n", a / b }'
  h5diff --exclude-path /provenance "$out/demo.h5" "$out/base.h5" > /dev/null && echo "  identical to the baseline's file"
fi
