#!/usr/bin/env bash
# Fuzzes the sweep-file parser for a bounded time: first every regression input under
# tests/fuzz/regressions (crashes found before, now fixed), then new inputs grown from the
# shipped sweep files. A crash, sanitizer report, hang (10 s) or allocation over 2 GB fails,
# leaving the input as crash-*/timeout-*/oom-* in the working directory: fix the bug, then
# keep the input under tests/fuzz/regressions.
# Usage: run_fuzz.sh FUZZER SOURCE_DIR SECONDS [CORPUS_DIR]
#   unit suite: 20 s;  a longer run: tests/fuzz/run_fuzz.sh build/fuzz/sweep_file_fuzzer . 3600 fuzz-corpus
set -euo pipefail
fuzzer=$1; src=$2; seconds=$3; corpus=${4:-fuzz-corpus}
mkdir -p "$corpus"
# The regressions one by one (a list of files: each runs once).
"$fuzzer" -rss_limit_mb=2048 -timeout=10 "$src"/tests/fuzz/regressions/* 2>&1 | tail -1
# New inputs go to $corpus (the first directory); the others are read only.
exec "$fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
  -dict="$src/tests/fuzz/sweep_file.dict" "$corpus" "$src/sweeps" "$src/tests/data" "$src/tests/fuzz/regressions"
