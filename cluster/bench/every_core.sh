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
#     alone, --threads 0; every settle at full length, --set protocol.early_stop=false), and
#     against BASELINE run as the demo runs it (another build, such as main's): wall time ratios.
#  With BASELINE, section 1 also runs it under mpirun -n 2 (its default threads) beside this build.
#  With BASELINE_PAPER too (the baseline's own sweeps/paper.toml, e.g. `git show
#  7f5a349:sweeps/paper.toml > /tmp/paper_ref.toml` for the build from before issue 29, which
#  refuses today's keys), section 3 runs the baseline on that file as the demo ran before issue 29
#  (as root one process, else mpirun -n <cores>; no --threads, which that build does not know).
# Usage: cluster/bench/every_core.sh [BUILD_DIR] [BASELINE_ASTROJAX] [BASELINE_PAPER]
#        (MPIRUN_FLAGS=--allow-run-as-root as root; SECTIONS="3" for the demo's sweep alone)
#        Some 3 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
baseline=${2:-}
baseline_paper=${3:-}
sections=${SECTIONS:-1 2 3}
section() { [[ " $sections " == *" $1 "* ]]; }
exe="$build/astrojax"
mpirun=(mpirun --oversubscribe ${MPIRUN_FLAGS:-})
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cores=$(nproc)

# Runs a command; its wall, user and sys seconds (children included: mpirun's ranks) go to
# $out/time. A failure prints the command's output to stderr and returns 1.
measure() {
  /usr/bin/time -f "%e %U %S" -o "$out/time" "$@" > "$out/log" 2>&1 || { echo "failed: $*" >&2; cat "$out/log" >&2; return 1; }
}
ratio() { awk -v w="$1" -v u="$2" -v s="$3" 'BEGIN { printf "%.2f", (u + s) / w }'; }

radii="[0.01500,0.01505,0.01510,0.01515,0.01520,0.01525,0.01530,0.01535,0.01540,0.01545,0.01550,0.01555,0.01560,0.01565,0.01570,0.01575]"
chains=(sweeps/paper_ramps.toml -q --force --set "grid.drive_radius=$radii")
if section 1; then
  echo "== 1. 16 equal chains under mpirun -n 2 on $cores cores: CPU / wall"
  for t in 1 0; do
    measure "${mpirun[@]}" -n 2 "$exe" sweep "${chains[@]}" -o "$out/m$t.h5" --threads $t
    read -r w u s < "$out/time"
    echo "  --threads $t: wall $w s, user $u s, sys $s s: CPU/wall $(ratio "$w" "$u" "$s")"
  done
  h5diff --exclude-path /provenance "$out/m1.h5" "$out/m0.h5" > /dev/null && echo "  the two files are identical (h5diff, /provenance aside)"
  if [ -n "$baseline" ]; then
    if measure "${mpirun[@]}" -n 2 "$baseline" sweep "${chains[@]}" -o "$out/mb.h5"; then
      read -r w u s < "$out/time"
      echo "  $baseline (its default threads): wall $w s, CPU/wall $(ratio "$w" "$u" "$s")"
      h5diff --exclude-path /provenance "$out/m1.h5" "$out/mb.h5" > /dev/null && echo "  identical to this build's file"
    else
      echo "  $baseline: could not run sweeps/paper_ramps.toml (above), left out"
    fi
  fi
fi

if section 2; then
  echo "== 2. the same 16 chains in one process: --threads 2 against 1"
  for t in 2 1; do
    measure "$exe" sweep "${chains[@]}" -o "$out/p$t.h5" --threads $t
    read -r w u s < "$out/time"
    eval "wall_p$t=$w"
    echo "  --threads $t: wall $w s, CPU/wall $(ratio "$w" "$u" "$s")"
  done
  [ -f "$out/m1.h5" ] && h5diff --exclude-path /provenance "$out/p2.h5" "$out/m1.h5" > /dev/null && echo "  identical to the mpirun file"
  awk -v a="$wall_p2" -v b="$wall_p1" 'BEGIN { printf "  wall ratio 2 threads / 1 thread: %.2f\n", a / b }'
fi

section 3 || exit 0
echo "== 3. the demo's sweep, sweeps/paper.toml, as ./setup.sh demo runs it (load: $(cut -d' ' -f1-3 /proc/loadavg))"
ranks=$(( cores < 2 ? 2 : cores ))
root=$([ "$(id -u)" -eq 0 ] && echo 1 || echo "")
# As ./setup.sh demo runs EXE on TOML into FILE, with EXTRA arguments; OLD=1: as the demo ran
# before issue 29 (as root one process with one thread, else mpirun with the master alone).
demo_run() {
  local exe=$1 toml=$2 file=$3 old=$4
  shift 4
  if [ -n "$root" ]; then
    measure "$exe" sweep "$toml" -q --force -o "$file" "$@" $([ -z "$old" ] && echo --threads "$ranks")
  else
    measure "${mpirun[@]}" -n "$ranks" "$exe" sweep "$toml" -q --force -o "$file" "$@"
  fi
  read -r w u s < "$out/time"
  cpu=$(awk -v u="$u" -v s="$s" 'BEGIN { print u + s }')
}
demo_run "$exe" sweeps/paper.toml "$out/demo.h5" ""
w2=$w
echo "  now ($([ -n "$root" ] && echo "one process, --threads $ranks" || echo "mpirun -n $ranks"), the early stop on): wall $w s, CPU $cpu s"
if [ -n "$root" ]; then old_args=(--threads 1); else old_args=(--threads 0); fi
demo_run "$exe" sweeps/paper.toml "$out/before.h5" old "${old_args[@]}" --set protocol.early_stop=false
w1=$w
echo "  this build as the demo ran before issue 29 ($([ -n "$root" ] && echo "one process, one thread" || echo "mpirun -n $ranks, master alone"), every settle at full length): wall $w s, CPU $cpu s"
awk -v a="$w2" -v b="$w1" 'BEGIN { printf "  demo sweep wall ratio now / as before issue 29: %.2f\n", a / b }'
if [ -n "$baseline" ]; then
  if [ -n "$baseline_paper" ]; then
    # The baseline build on its own paper.toml, as the demo ran it then.
    demo_run "$baseline" "$baseline_paper" "$out/base.h5" old
    how="on $baseline_paper as the demo ran it before issue 29"
  else
    demo_run "$baseline" sweeps/paper.toml "$out/base.h5" ""
    how="as the demo runs it"
  fi
  echo "  $baseline $how: wall $w s, CPU $cpu s"
  awk -v a="$w2" -v b="$w" 'BEGIN { printf "  demo sweep wall ratio this build / baseline: %.2f\n", a / b }'
  h5diff --exclude-path /provenance "$out/demo.h5" "$out/base.h5" > /dev/null && echo "  identical to the baseline's file"
fi
