# Shared by the shell tests (source it): a scratch directory $work removed on exit;
# check NAME CONDITION evaluates CONDITION and counts a pass or a failure (printing NAME);
# finish NAME prints the tally and returns non-zero if any check failed.
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail=0; pass=0
check() { if eval "$2"; then pass=$((pass+1)); else echo "FAIL: $1"; fail=$((fail+1)); fi; }
finish() { echo "$1: $pass passed, $fail failed"; [ $fail -eq 0 ]; }
