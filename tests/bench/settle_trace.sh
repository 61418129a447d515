#!/usr/bin/env bash
# Where the early stop's settles end (docs/reports/early-stop-and-every-core.md, 2026-11-28
# session 4). Builds a copy of the committed tree (git archive HEAD) with
# tests/bench/settle_trace.patch, a print to stderr at the end of every settle span (ω_m, the
# seconds of it integrated, how it ended: full, fixed, land, periodic; the last fixed-point test's
# verdict and contractions Λ; the recurrence's n s/(ε l) at 30 s; its steps, the bead's mode
# switches and the tie's switches), runs SWEEP with it on one process and prints, per chain, the
# runs of levels that ended alike. A diagnostic, not a test: the patch is kept out of the
# program, and this script fails loudly where it no longer applies.
# Usage: tests/bench/settle_trace.sh [BUILD_DIR] [SWEEP.toml]   (default build, sweeps/paper.toml;
#        the copy is built in BUILD_DIR/settle_trace: a few minutes, ccache helps)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
sweep=${2:-sweeps/paper.toml}
work="$build/settle_trace"
rm -rf "$work/src"
mkdir -p "$work/src"
git archive HEAD | tar -x -C "$work/src"
patch -s -d "$work/src" -p1 < tests/bench/settle_trace.patch
cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DASTROJAX_PEERS=OFF -DASTROJAX_FUZZ=OFF > "$work/cmake.log" 2>&1 ||
  { tail -20 "$work/cmake.log"; exit 1; }
cmake --build "$work/build" -j"$(nproc)" --target astrojax >> "$work/cmake.log" 2>&1 ||
  { tail -20 "$work/cmake.log"; exit 1; }
AJX_SETTLE_TRACE=1 "$work/build/astrojax" sweep "$sweep" -q --force -o "$work/out.h5" 2> "$work/trace.txt"
/usr/bin/python3 tests/bench/settle_trace.py "$work/trace.txt" "$work/out.h5"
