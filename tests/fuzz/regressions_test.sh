#!/usr/bin/env bash
# Every input the fuzzer once crashed on is now rejected before any work: exit 2 with the file
# and the key in the message (runs without clang too).
# Usage: regressions_test.sh ASTROJAX SOURCE_DIR
set -u
bin=$1; src=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail=0
for f in "$src"/tests/fuzz/regressions/*; do
  (cd "$work" && "$bin" sweep "$f" -o "$work/out.h5" -q) > "$work/out" 2>&1
  rc=$?
  if [ $rc -ne 2 ] || ! grep -q "error: $f: key '" "$work/out"; then
    echo "FAIL: $(basename "$f"): exit $rc: $(head -c 300 "$work/out")"; fail=1
  fi
done
[ $fail -eq 0 ] && echo "fuzz regressions: all rejected with exit 2"
exit $fail
