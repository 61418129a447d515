#!/usr/bin/env bash
# The bad-input corpus (tests/bad_input/cases.txt): every malformed file, override, output path
# and option is refused with exit 2, a message with the file or option and the key or problem,
# and nothing left behind (the case's working directory stays empty, the fixtures unchanged).
# Cases run four at a time: most of a sweep's refusal is MPI start-up, waiting, not computing.
# Usage: bad_input_test.sh ASTROJAX SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"
B=$src/tests/bad_input/files
RUN=$src/sweeps/spin_up.toml
SWEEP=$src/tests/data/tiny_sweep.toml
HOLD=$src/tests/data/tiny_hold.toml
QUICK=$src/sweeps/quick.toml
PAPER=$src/sweeps/paper.toml
NL=$'\n'
FX=$work/fixtures
mkdir -p "$FX/adir" "$FX/partdir/out.h5.part"
cp "$RUN" "$FX/run.toml"; cp "$SWEEP" "$FX/sweep.toml"; touch "$FX/afile"
state() { find "$FX" "$src/tests/bad_input" "$src/sweeps" "$src/tests/data" -printf '%p %s %T@\n' | sort; }
before=$(state)

# One case: its failures, one line each, into $work/case$n.fail (empty when it passes).
run_case() {
  local n=$1 line=$2 W=$work/case$1
  local out=$W.out fails=$W.fail
  mkdir "$W"
  local expected=${line%% | *}
  eval "args=(${line#* | })"
  (cd "$W" && "$bin" "${args[@]}") > "$out" 2>&1
  local rc=$? where="case $n (${line#* | })" msg
  msg=$(head -c 300 "$out")
  : > "$fails"
  [ $rc -eq 2 ] || echo "$where: exit $rc, not 2: $msg" >> "$fails"
  IFS=';' read -ra parts <<< "$expected"
  [ ${#parts[@]} -ge 2 ] || echo "$where: expects fewer than the file or option and the key or problem" >> "$fails"
  for p in "${parts[@]}"; do
    p=${p# }; p=${p% }
    eval "p=\"$p\""
    grep -qF -- "$p" "$out" || echo "$where: message lacks '$p': $msg" >> "$fails"
  done
  [ -z "$(find "$W" -mindepth 1)" ] || echo "$where: left behind: $(cd "$W" && find . -mindepth 1 | head -3)" >> "$fails"
  rm -rf "$W"
}

n=0
while IFS= read -r line; do
  case $line in ''|'#'*) continue ;; esac
  n=$((n + 1))
  while [ "$(jobs -rp | wc -l)" -ge 4 ]; do wait -n; done
  run_case $n "$line" &
done < "$src/tests/bad_input/cases.txt"
wait
for k in $(seq $n); do
  check "$(cat "$work/case$k.fail" 2>/dev/null || echo "case $k: no result")" "[ -e '$work/case$k.fail' ] && [ ! -s '$work/case$k.fail' ]"
done
check "fixtures and sources unchanged" "[ \"\$(state)\" = \"\$before\" ]"
check "at least 100 cases (got $n)" "[ $n -ge 100 ]"
finish "bad_input ($n cases)"
