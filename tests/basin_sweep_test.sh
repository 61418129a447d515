#!/usr/bin/env bash
# A basin sweep (tests/data/tiny_basin.toml: 2 levels × 6 hanging starts) gives the same file on
# 1 and 3 ranks, /basins included; stopped part-way and resumed, or with a worker killed and
# resumed, it gives the same file as one run straight through; `astrojax classify` rewrites
# /basins with /windows; both readers accept the file, and at 2π rad/s, far below the paper's
# ω_fall = 3.24π, every start ends fallen (the known answer).
# Usage: basin_sweep_test.sh ASTROJAX MPIEXEC SOURCE_DIR PYTHON
set -u
bin=$1; mpiexec=$2; src=$3; py=$4
source "$(dirname "$0")/check.sh"
toml=$src/tests/data/tiny_basin.toml
same() { for g in /config /chains /windows /samples /tasks /basins; do h5diff "$1" "$2" $g > "$work/diff" 2>&1 || return 1; done; }

"$mpiexec" --oversubscribe -n 1 "$bin" sweep "$toml" -o "$work/one.h5" -q > "$work/one.out" 2>&1
rc1=$?
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$toml" -o "$work/three.h5" -q > "$work/three.out" 2>&1
rc3=$?
cat "$work/one.out" "$work/three.out"
check "1 rank: exit 0 (got $rc1)" "[ $rc1 -eq 0 ]"
check "3 ranks: exit 0 (got $rc3)" "[ $rc3 -eq 0 ]"
check "1 and 3 ranks: the same file but /provenance, /basins included" "same '$work/one.h5' '$work/three.h5'"

"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$toml" -o "$work/resumed.h5" -q --max-tasks 5 > "$work/part.out" 2>&1
rcp=$?
check "stopped part-way: exit 4 (got $rcp)" "[ $rcp -eq 4 ] && [ -s '$work/resumed.h5.part' ]"
check "stopped part-way: the .part's /basins counts the samples done, and only them" \
  "'$py' -c 'import h5py,sys; f=h5py.File(sys.argv[1]); n=(f[\"basins/class\"][:]>=0).sum(); sys.exit(0 if 5<=n<12 and f[\"basins/levels/done\"][:].sum()==n else 1)' '$work/resumed.h5.part'"
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$toml" -o "$work/resumed.h5" -q --resume > "$work/resume.out" 2>&1
check "resumed: exit 0 and the same file as the straight run" "[ $? -eq 0 ] && same '$work/one.h5' '$work/resumed.h5'"

# kill -9 of a worker mid-sweep (as tests/sweep_fault_test.sh), then --resume.
"$mpiexec" --oversubscribe -n 3 "$bin" sweep "$toml" -o "$work/killed.h5" -q > "$work/killed.out" 2>&1 &
mp=$!
victim=""
for _ in $(seq 200); do
  victim=$(pgrep -P "$mp" -f "astrojax sweep" | sort -n | tail -1)
  [ -n "$victim" ] && [ -s "$work/killed.h5.journal" ] && break
  sleep 0.05
done
[ -n "$victim" ] && kill -9 "$victim" 2> /dev/null
wait "$mp" 2> /dev/null
if [ -e "$work/killed.h5.part" ]; then
  "$bin" sweep "$toml" -o "$work/killed.h5" -q --resume > "$work/killed.resume" 2>&1
  check "kill -9 of a worker: --resume exit 0 and the same file" "[ $? -eq 0 ] && same '$work/one.h5' '$work/killed.h5'"
else  # the sweep finished before the kill landed: still the same file
  check "kill -9 of a worker: (finished first) the same file" "same '$work/one.h5' '$work/killed.h5'"
fi

"$bin" verify "$work/one.h5" > "$work/verify.out" 2>&1
check "verify: exit 0 ($(tail -1 "$work/verify.out"))" "[ $? -eq 0 ]"
cp "$work/one.h5" "$work/re.h5"
"$bin" classify "$work/re.h5" -o "$work/re2.h5" --set classifier.fallen_fraction=7 > "$work/re2.out" 2>&1
check "classify with settings that change classes: /basins follows (the C++ reader accepts it)" \
  "[ $? -eq 0 ] && ! h5diff '$work/one.h5' '$work/re2.h5' /basins/class > /dev/null 2>&1 && '$bin' verify '$work/re2.h5' > /dev/null 2>&1; [ \$? -ne 2 ]"
# A cloud around a stored state (basin.state): the end of window 0 of chain 7 of one.h5 (the bead
# fallen at 3π); refused before any work, naming the key, for a chain the file does not have.
stored() {
  sed -e 's/^family = "hanging"/family = "cloud"\nepsilon = 0.005\nstate = {file = "'"${work//\//\\/}"'\/one.h5", chain = '"$1"', window = 0}/' \
      -e '/^s = /d' -e '/^swing = /d' -e 's/^samples = .*/samples = 2/' "$toml" > "$work/stored.toml"
}
stored 7
"$bin" sweep "$work/stored.toml" -o "$work/stored.h5" -q > "$work/stored.out" 2>&1
check "a cloud around a stored state runs (exit $?)" "[ -s '$work/stored.h5' ]"
check "its starts lie within 2ε of the stored state (the bead moved by up to ε, the bottom ball by up to 2ε), and differ" "'$py' -c '
import h5py, numpy as np, sys
a = h5py.File(sys.argv[1]); b = h5py.File(sys.argv[2])
c = list(a[\"basins/start\"].attrs[\"columns\"]); i = [c.index(n) for n in (\"r1_z [m]\", \"r2_z [m]\")]
s = b[\"basins/start\"][:][:, i]; e = a[\"tasks/final_state\"][7][[list(a[\"tasks/final_state\"].attrs[\"columns\"]).index(n) for n in (\"r1_z [m]\", \"r2_z [m]\")]]
sys.exit(0 if np.all(np.abs(s - e) <= 2 * 0.005 + 1e-9) and not np.array_equal(s[0], s[1]) else 1)' '$work/one.h5' '$work/stored.h5'"
stored 99
"$bin" sweep "$work/stored.toml" -o "$work/stored99.h5" -q > "$work/stored99.out" 2>&1
rc=$?
check "a stored state of a chain the file lacks: exit 2, naming basin.state and the chain ($(head -c 200 "$work/stored99.out"))" \
  "[ $rc -eq 2 ] && grep -q \"key 'basin.state'\" '$work/stored99.out' && grep -q 'chain 99' '$work/stored99.out' && [ ! -e '$work/stored99.h5' ]"
PYTHONPATH=$src/analysis "$py" - "$work/one.h5" "$work/re2.h5" > "$work/py.out" 2>&1 <<'PY'
import sys
import numpy as np
import astrojax_analysis as ajx
from astrojax_analysis import basins as bs
s = ajx.Sweep(sys.argv[1])
lv = s.basins["levels"]
names = [c.name for c in s.classes]
low = int(np.argmin(lv["omega_m"]))
assert abs(lv["omega_m"][low] - 2 * np.pi) < 1e-12
assert lv["done"][low] == 6, lv["done"]
assert lv["count"][low, names.index("fallen")] == 6, lv["count"][low]
t = bs.basin_table(s, 0)
assert t["labels"][0] == "fallen" and t["fraction"][0, 0] == 1.0, t
# Wilson's interval of 6 of 6: [n/(n + z²), 1].
assert abs(t["lower"][0, 0] - 6 / (6 + 1.959963984540054 ** 2)) < 1e-12
ajx.Sweep(sys.argv[2])  # the reclassified copy reads: its /basins agrees with its /windows
print("ok")
PY
check "Python reader: every start at 2π fallen, 6 of 6 with Wilson's interval ($(tail -1 "$work/py.out"))" \
  "[ \"\$(tail -1 '$work/py.out')\" = ok ]"
PYTHONPATH=$src/analysis "$py" "$src/analysis/plot_basins.py" "$work/one.h5" -o "$work/basins.png" > "$work/plot.out" 2>&1
check "plot_basins.py draws the figure" "[ -s '$work/basins.png' ]"
PYTHONPATH=$src/analysis "$py" "$src/analysis/plot_basins.py" "$src/tests/data/tiny_sweep.toml" -o "$work/x.png" > "$work/bad.out" 2>&1
check "plot_basins.py on a file that is not a sweep: exit 2, one line" "[ $? -eq 2 ] && [ \$(wc -l < '$work/bad.out') -eq 1 ]"
finish basin_sweep
