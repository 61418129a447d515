#!/usr/bin/env bash
# The astrojax executable end to end: bad input exits 2 with the file, key and range on
# stderr and writes no output file; a good run exits 0 and writes a readable HDF5 file.
# Usage: cli_test.sh ASTROJAX_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"

bad() {  # name, key expected in the message, range text, then --set overrides
  local name=$1 key=$2 range=$3; shift 3
  local out="$work/$name.h5"
  "$bin" run "$src/sweeps/spin_up.toml" -o "$out" "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  check "$name: exit code 2 (got $rc)" "[ $rc -eq 2 ]"
  check "$name: message names the file" "grep -q 'sweeps/spin_up.toml' '$work/$name.err'"
  check "$name: message names the key $key" "grep -qF '$key' '$work/$name.err'"
  check "$name: message gives the range $range" "grep -qF '$range' '$work/$name.err'"
  check "$name: no output file" "[ ! -e '$out' ] && [ ! -e '$out.part' ]"
}
bad unknown_key model.colour "unknown key" --set model.colour=1
bad negative_length model.string_length "(0, 100]" --set model.string_length=-1
bad negative_mass model.ball_mass "(0, inf)" --set model.ball_mass=-0.01
bad R_ge_l model.drive_radius "0 <= R < l" --set model.drive_radius=1.0
bad negative_mu model.mu_static "[0, inf)" --set model.mu_static=-0.2
bad d_ge_l model.contact_distance "0 < d < l" --set model.contact_distance=0.9
bad reversed_schedule "schedule[1].rate" "(0, 10000]" --set "schedule=[{kind=\"hold\",omega=1.0,duration=1.0},{kind=\"ramp\",from=1.0,to=5.0,rate=-1.0}]"
bad empty_schedule schedule "at least one" --set "schedule=[]"

# A mistyped key, command or option names the nearest right one; --version names the commit.
bad typo_key "model.drive_radus" "allowed: ball_mass," --set model.drive_radus=0.01
check "typo_key: the nearest key suggested" "grep -q \"did you mean 'drive_radius'\" '$work/typo_key.err'"
"$bin" swep x >/dev/null 2>"$work/typo_cmd.err"
check "mistyped command: exit 2 and the nearest command" "[ $? -eq 2 ] && grep -q \"did you mean 'sweep'\" '$work/typo_cmd.err'"
"$bin" thresholds x.h5 --hodl >/dev/null 2>"$work/typo_opt.err"
check "mistyped option: exit 2 and the nearest option" "[ $? -eq 2 ] && grep -q \"did you mean '--hold'\" '$work/typo_opt.err'"
"$bin" --version >"$work/version.out" 2>&1
check "--version: exit 0, the version and the git commit" "[ $? -eq 0 ] && grep -Eq '^astrojax [0-9]+\.[0-9]+\.[0-9]+ \(git commit ([0-9a-f]{12}|unknown); ' '$work/version.out'"

# sweep --dry-run: the plan per group and variant, nothing run or written; bad input still 2.
"$bin" sweep "$src/sweeps/paper.toml" --dry-run -o "$work/dry.h5" >"$work/dry.out" 2>&1
check "--dry-run: exit 0, nothing written" "[ $? -eq 0 ] && [ ! -e '$work/dry.h5' ] && [ ! -e '$work/dry.h5.part' ] && [ ! -e '$work/dry.h5.journal' ]"
check "--dry-run: one row per group and variant, and the totals" \
  "[ \$(grep -Ec '^  (rise|up|fall) +(paper|clutch) ' '$work/dry.out') -eq 6 ] && grep -q 'in all: 6 chains, 82 tasks' '$work/dry.out'"
"$bin" sweep "$src/sweeps/quick.toml" --dry-run --set model.drive_radius=-1 >/dev/null 2>"$work/dry_bad.err"
check "--dry-run of a bad file: exit 2 naming the key" "[ $? -eq 2 ] && grep -q 'model.drive_radius' '$work/dry_bad.err'"

# An unwritable output path is bad input too, found before any work.
"$bin" run "$src/sweeps/spin_up.toml" -o /proc/no/such/dir/x.h5 >/dev/null 2>"$work/unwritable.err"
rc=$?
check "unwritable output: exit 2 (got $rc)" "[ $rc -eq 2 ]"
check "unwritable output: names output.path" "grep -q 'output.path' '$work/unwritable.err'"

# A good, short run.
"$bin" run "$src/sweeps/spin_up.toml" -o "$work/good.h5" --set "schedule=[{kind=\"hold\",omega=6.0,duration=2.0}]" >"$work/good.out" 2>&1
rc=$?
check "good run: exit 0 (got $rc)" "[ $rc -eq 0 ]"
check "good run: summary line" "grep -q '^ok ' '$work/good.out'"
check "good run: file written" "[ -s '$work/good.h5' ] && [ ! -e '$work/good.h5.part' ]"
if command -v h5dump >/dev/null; then
  check "good run: 201 samples of r1" "h5dump -H -d /trajectory/r1 '$work/good.h5' | grep -q '( 201, 3 )'"
  check "good run: units attribute" "h5dump -a /trajectory/r1/units '$work/good.h5' | grep -q '\"m\"'"
  check "good run: configuration stored verbatim" "h5dump -d /config '$work/good.h5' | grep -q 'Spin-up from rest'"
fi
# An explicit start from the paper's Table 1 orbit (0.3 mm off the string length: projected).
explicit=(--set initial.preset=explicit --set "initial.r1=[-0.14427,0.0,-0.52483]"
          --set "initial.r2=[0.11924,0.0,-0.62353]" --set "initial.v1=[0.0,-2.13,0.0]"
          --set "initial.v2=[0.0,1.761,0.0]" --set model.drive_radius=0.0
          --set "schedule=[{kind=\"hold\",omega=14.77,duration=1.0}]")
"$bin" run "$src/sweeps/spin_up.toml" -o "$work/explicit.h5" "${explicit[@]}" --set initial.length_tolerance=1e-3 >/dev/null 2>&1
rc=$?
check "explicit start within tolerance: exit 0 (got $rc)" "[ $rc -eq 0 ] && [ -s '$work/explicit.h5' ]"
"$bin" run "$src/sweeps/spin_up.toml" -o "$work/explicit_bad.h5" "${explicit[@]}" >/dev/null 2>"$work/explicit_bad.err"
rc=$?
check "explicit start off the string: exit 2 (got $rc)" "[ $rc -eq 2 ] && [ ! -e '$work/explicit_bad.h5' ]"
check "explicit start off the string: names initial.r1 and the tolerance" \
  "grep -q \"initial.r1\" '$work/explicit_bad.err' && grep -q 'length_tolerance' '$work/explicit_bad.err'"

finish "cli"
