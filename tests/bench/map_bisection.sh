#!/usr/bin/env bash
# Benchmark (not a test): a map of ω_fall and ω1 over (R, d) by bisection to 0.05π against the
# fixed 0.1π ladder of held levels for the same grid, run side by side, and the bisection map's
# wall time on 2, 4 and 8 ranks with the master's share of the CPU. Prints ratios.
#
#   tests/bench/map_bisection.sh build/astrojax [N] [RANKS...]
#
# N × N grid points (default 4: a subgrid; the 16 × 16 map's CPU is extrapolated as 256/N² times
# the subgrid's, which holds as long as every point costs about the same). Three runs in one
# process each: the bisection with its probes stopped once their class is decided
# (sweep/probe_verdict.hpp), the same bisection with every probe held through its window
# (decide_early = false), and the ladder; each row gives its CPU and its integration steps
# (/tasks/steps summed). The locked-orbit seed is solved once per process and grid point
# (orbits/orbit_seed.hpp, shared by a point's two chains), the same for the three: two more runs,
# a 0.1 s hold at 4π from that seed and from circular_high (no solve) at every point, measure it
# as their difference, and the ratio is printed again with it taken out of both sides. Then
# the bisection map runs under mpirun -n RANKS (default 2 4 8, oversubscribed), timing rank 0
# (the master) on its own. Both maps start on the locked orbit at 4π (seed locked_orbit), hold
# each level 100 s + 20 s (the staircases of sweeps/paper.toml) and reach it at 0.1 rad/s².
# Where the bisection's steps go, probe by probe (ramp, bead stuck, sliding, on the ball):
# build/tests/bench/probe_anatomy N [-v].
set -u
bin=$(realpath "$1"); n=${2:-4}; shift; [ $# -gt 0 ] && shift; ranks=${*:-2 4 8}
# MAP_BENCH_KEEP=dir keeps the sweep files and their outputs there (to profile one of them).
if [ -n "${MAP_BENCH_KEEP:-}" ]; then work=$MAP_BENCH_KEEP; mkdir -p "$work"; rm -f "$work"/*.h5; else work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; fi
pi=3.141592653589793
grid=$(python3 -c "
n=$n
R=[0.005+0.025*i/(n-1) for i in range(n)]; d=[0.02+0.03*i/(n-1) for i in range(n)]
print('[grid]\ndrive_radius = %s\ncontact_distance = %s' % (R, d))")
common="[model]
drive_radius = 0.015
contact_distance = 0.035
[layers]
friction = \"stick_slip\"
[integrator]
method = \"dop853\"
rtol = 1e-9
atol = 1e-11
$grid
[output]
path = \"$work/x.h5\""
w() { python3 -c "print($1*$pi)"; }
cat > "$work/bisect.toml" <<TOML
$common
[bisect]
start_seed = "locked_orbit"
start_omega = $(w 4)
from = $(w 4)
width = $(w 0.05)
settle = 100.0
measure = 20.0
step_rate = 0.1
sample_rate = 50.0
[[group]]
name = "fall"
purpose = "omega_fall by bisection"
bisect = { threshold = "omega_fall", to = $(w 2.5) }
[[group]]
name = "omega1"
purpose = "omega_1 by bisection"
bisect = { threshold = "omega_1", to = $(w 6.5) }
TOML
cat > "$work/ladder.toml" <<TOML
$common
[protocol]
start_seed = "locked_orbit"
start_omega = $(w 4)
windows_per_task = 4
sample_rate = 50.0
[[group]]
name = "fall"
purpose = "omega_fall on the 0.1 pi ladder: 4 pi down to 2.5 pi"
[[group.protocol.segment]]
kind = "steps"
from = $(w 4)
to = $(w 2.5)
num = 16
settle = 100.0
measure = 20.0
step_rate = 0.1
[[group]]
name = "omega1"
purpose = "omega_1 on the 0.1 pi ladder: 4 pi up to 6.5 pi"
[[group.protocol.segment]]
kind = "steps"
from = $(w 4)
to = $(w 6.5)
num = 26
settle = 100.0
measure = 20.0
step_rate = 0.1
TOML
cpu() {  # user + sys seconds of a command, from /usr/bin/time
  /usr/bin/time -f "%U %S %e" -o "$work/t" "$@" > "$work/out" 2>&1 || { cat "$work/out"; exit 1; }
  awk '{ printf "%.2f %.2f", $1 + $2, $3 }' "$work/t"
}
sed 's/^step_rate = 0.1$/step_rate = 0.1\ndecide_early = false/' "$work/bisect.toml" > "$work/full.toml"
# Probes next to the threshold the start level's locked orbit predicts (bisect.guide).
sed 's/^step_rate = 0.1$/step_rate = 0.1\nguide = "held_orbit"/' "$work/bisect.toml" > "$work/guided.toml"
# The ladder as the map issue found it: every level held through its window (protocol.early_stop,
# on by default since, stops a level once its orbit has settled).
sed 's/^windows_per_task = 4$/windows_per_task = 4\nearly_stop = false/' "$work/ladder.toml" > "$work/ladder_full.toml"
hold() { printf '%s\n[hold]\nomega = [%s]\nsettle = 0.0\nmeasure = 0.1\nseeds = ["%s"]\nperturbations = 0\nsample_rate = 50.0\n' "$common" "$(w 4)" "$1"; }
hold locked_orbit > "$work/seeded.toml"
hold circular_high > "$work/unseeded.toml"
read cb wb < <(cpu "$bin" sweep "$work/bisect.toml" -o "$work/bisect.h5" -q)
read cf wf < <(cpu "$bin" sweep "$work/full.toml" -o "$work/full.h5" -q)
read cg wg < <(cpu "$bin" sweep "$work/guided.toml" -o "$work/guided.h5" -q)
read cl wl < <(cpu "$bin" sweep "$work/ladder.toml" -o "$work/ladder.h5" -q)
read clf wlf < <(cpu "$bin" sweep "$work/ladder_full.toml" -o "$work/ladder_full.h5" -q)
read cs ws < <(cpu "$bin" sweep "$work/seeded.toml" -o "$work/seeded.h5" -q)
read cu wu < <(cpu "$bin" sweep "$work/unseeded.toml" -o "$work/unseeded.h5" -q)
steps() { /usr/bin/python3 -c "import h5py, sys; print(int(h5py.File(sys.argv[1])['tasks/steps'][:].sum()))" "$1"; }
sb=$(steps "$work/bisect.h5"); sf=$(steps "$work/full.h5"); sg=$(steps "$work/guided.h5"); sl=$(steps "$work/ladder.h5"); slf=$(steps "$work/ladder_full.h5")
"$bin" thresholds "$work/bisect.h5" --csv "$work/b.csv" > /dev/null
"$bin" thresholds "$work/ladder.h5" --no-hold --csv "$work/l.csv" > /dev/null
ran() { /usr/bin/python3 -c "import h5py, sys; print(int((h5py.File(sys.argv[1])['brackets/probes/ran'][:] == 1).sum()))" "$1"; }
probes=$(ran "$work/bisect.h5")
pts=$((n * n))
echo "map of ω_fall and ω1 over (R, d), $n × $n points, one process ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
fprobes=$(ran "$work/full.h5")
gprobes=$(ran "$work/guided.h5")
printf "  %-44s %9s %9s %10s %12s %12s\n" "" "CPU [s]" "wall [s]" "steps" "CPU a point" "16×16 (×$((256 / pts)))"
row() { printf "  %-44s %9.2f %9.2f %10d %12.3f %12.1f\n" "$1" "$2" "$3" "$4" "$(python3 -c "print($2/$pts)")" "$(python3 -c "print($2*256/$pts)")"; }
row "bisection to 0.05π, decided early ($probes probes)" "$cb" "$wb" "$sb"
row "bisection, probes held through ($fprobes probes)" "$cf" "$wf" "$sf"
row "bisection guided by the held orbit ($gprobes probes)" "$cg" "$wg" "$sg"
row "ladder of 0.1π (42 levels a point)" "$cl" "$wl" "$sl"
row "ladder, every level held through" "$clf" "$wlf" "$slf"
echo "  CPU ratio bisection/ladder: $(python3 -c "print(f'{$cb/$cl:.3f}')") (target ≤ 0.2); held through: $(python3 -c "print(f'{$cf/$cl:.3f}')")"
echo "  CPU ratio guided bisection/ladder: $(python3 -c "print(f'{$cg/$cl:.3f}')") (target ≤ 0.2); integration steps: $(python3 -c "print(f'{$sg/$sl:.3f}')")"
echo "  CPU ratio bisection/ladder held through (the ladder before the early stop): $(python3 -c "print(f'{$cb/$clf:.3f}')"); both held through: $(python3 -c "print(f'{$cf/$clf:.3f}')")"
seed=$(python3 -c "print(max($cs - $cu, 0.0))")
echo "  the seeds alone ($pts solves, a 0.1 s hold from locked_orbit less one from circular_high): $(python3 -c "print(f'{$seed:.2f}')") s;" \
  "CPU ratio without them: $(python3 -c "print(f'{($cb - $seed)/($cl - $seed):.3f}')"), guided: $(python3 -c "print(f'{($cg - $seed)/($cl - $seed):.3f}')")"
echo "  integration steps bisection/ladder: $(python3 -c "print(f'{$sb/$sl:.3f}')"); held through: $(python3 -c "print(f'{$sf/$sl:.3f}')"); against the ladder held through: $(python3 -c "print(f'{$sb/$slf:.3f}')")"
h5diff -q "$work/ladder.h5" "$work/ladder_full.h5" /windows/class > /dev/null &&
  echo "  the ladder's classes with and without the early stop: identical" || echo "  the ladder's classes with and without the early stop: DIFFER"
h5diff -q "$work/bisect.h5" "$work/full.h5" /brackets/known_omega > /dev/null && h5diff -q "$work/bisect.h5" "$work/full.h5" /brackets/other_omega > /dev/null &&
  h5diff -q "$work/bisect.h5" "$work/full.h5" /brackets/status > /dev/null &&
  echo "  brackets decided early identical to those of probes held through: yes" || {
  echo "  brackets decided early identical to those of probes held through: NO"
  # A chain's later probes start where its last lock was decided, not at that window's end: a
  # probe near the threshold may then go the other way (build/tests/bench/probe_anatomy N checks
  # each verdict against the same probe held through from the same start).
  /usr/bin/python3 - "$work/bisect.h5" "$work/full.h5" <<'PY'
import h5py, sys, numpy as np
a, b = (h5py.File(p)["brackets"] for p in sys.argv[1:3])
same = np.ones(a["status"].shape, bool)
for k in ("known_omega", "other_omega"):
    x, y = a[k][:], b[k][:]
    same &= (x == y) | (np.isnan(x) & np.isnan(y))
same &= (a["status"][:] == b["status"][:])
pi = lambda f, k, i: f"{f[k][i] / np.pi:.4f}π"
for i in np.flatnonzero(~same):
    print(f"    chain {i}: {pi(a, 'known_omega', i)} → {pi(a, 'other_omega', i)} decided early, "
          f"{pi(b, 'known_omega', i)} → {pi(b, 'other_omega', i)} held through")
print(f"    {int(same.sum())} of {same.size} chains identical")
PY
}
python3 - "$work/b.csv" "$work/l.csv" <<'PY'
import csv, sys, math
# A ladder's threshold is the pair of neighbouring levels where the class changes; the bisection's
# bracket holds it when the two intervals overlap (both are the held orbit's, from the same start).
def rows(p):
    return [r for r in csv.DictReader(open(p)) if r["threshold"] in ("omega_fall", "omega_1")]
b = {(r["parameters"], r["threshold"]): r for r in rows(sys.argv[1])}
agree = n = 0
for r in rows(sys.argv[2]):
    k = (r["parameters"], r["threshold"])
    if k not in b or not r["before_rad_s"] or not b[k]["after_rad_s"] or not b[k]["before_rad_s"]:
        continue
    lo_l, hi_l = sorted(float(r[c]) for c in ("before_rad_s", "after_rad_s"))
    lo_b, hi_b = sorted(float(b[k][c]) for c in ("before_rad_s", "after_rad_s"))
    n += 1
    agree += lo_b <= hi_l + 1e-9 and lo_l <= hi_b + 1e-9
print(f"  brackets that overlap the ladder's: {agree} of {n} points with both (history differs: the ladder "
      f"visits every level, a probe jumps from the known side)")
PY
# The guided brackets against the middles', per threshold (both from the same start, by other
# histories), and the first guided chains more than a width away, with the levels they probed.
/usr/bin/python3 - "$work/bisect.h5" "$work/guided.h5" <<'PY'
import h5py, sys, numpy as np
a, b = (h5py.File(p)["brackets"] for p in sys.argv[1:3])
th = a["threshold"][:]
ka, oa, kb, ob = a["known_omega"][:], a["other_omega"][:], b["known_omega"][:], b["other_omega"][:]
both = (a["status"][:] == 1) & (b["status"][:] == 1)
w = a["width"][:]
same = both & np.isclose(ka, kb, rtol=0, atol=1e-9) & np.isclose(oa, ob, rtol=0, atol=1e-9)
lo_a, hi_a, lo_b, hi_b = np.minimum(ka, oa), np.maximum(ka, oa), np.minimum(kb, ob), np.maximum(kb, ob)
overlap = both & (np.maximum(lo_a, lo_b) <= np.minimum(hi_a, hi_b) + 1e-9)
apart = np.abs(0.5 * (ka + oa) - 0.5 * (kb + ob))
g = b["guide"][:]
inside = both & np.isfinite(g) & (g >= lo_b - (hi_b - lo_b)) & (g <= hi_b + (hi_b - lo_b))
def probes(f):  # probes run, per bracket row
    p = f["probes"]
    ran = np.bincount(p["chain"][:], weights=(p["ran"][:] == 1), minlength=int(f["chain"][:].max()) + 1)
    return ran[f["chain"][:]]
pa, pb = probes(a), probes(b)
print("  guided brackets against the middles' (chains converged both ways):")
for t, name in ((1, "ω_fall"), (2, "ω1")):
    m = th == t
    if not m.any():
        continue
    far = both & m & (apart > w)
    print(f"    {name}: {int((both & m).sum())} chains; the same bracket {int(same[m].sum())}, overlapping or touching "
          f"{int(overlap[m].sum())}, middles more than a width apart {int(far.sum())}"
          + (f" (at most {apart[far].max() / np.pi:.3f}π)" if far.any() else "")
          + f"; the prediction within its bracket ± a width {int(inside[m].sum())}; probes a chain {pb[m].mean():.2f}"
          f" (middles {pa[m].mean():.2f}), closed in three {int((pb[m] == 3).sum())}")
p = b["probes"]
pc, po, pr = p["chain"][:], p["omega_m"][:], p["ran"][:]
for i in np.flatnonzero(both & (apart > w))[:4]:
    c = b["chain"][i]
    levels = ", ".join(f"{x / np.pi:.3f}" for x, r in zip(po[pc == c], pr[pc == c]) if r == 1)
    print(f"    chain {c}: guided {kb[i] / np.pi:.3f}π → {ob[i] / np.pi:.3f}π (predicted {g[i] / np.pi:.3f}π; probed "
          f"{levels}π), middles {ka[i] / np.pi:.3f}π → {oa[i] / np.pi:.3f}π")
PY
echo "bisection map on the farm (mpirun --oversubscribe, --threads 0: rank 0 the master alone, timed on its own)"
printf "  %6s %10s %14s %18s\n" "ranks" "wall [s]" "master CPU [s]" "master CPU / wall"
for r in $ranks; do
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -n "$r" sh -c \
    "if [ \"\$OMPI_COMM_WORLD_RANK\" = 0 ]; then exec /usr/bin/time -f '%U %S %e' -o '$work/m' '$bin' sweep '$work/bisect.toml' -o '$work/r$r.h5' -q --threads 0; else exec '$bin' sweep '$work/bisect.toml' -o '$work/r$r.h5' -q --threads 0; fi" \
    > "$work/mpi.out" 2>&1 || { cat "$work/mpi.out"; exit 1; }
  awk -v r="$r" '{ printf "  %6d %10.2f %14.2f %18.3f\n", r, $3, $1 + $2, ($1 + $2) / $3 }' "$work/m"
  h5diff -q "$work/bisect.h5" "$work/r$r.h5" /brackets || echo "  /brackets differs on $r ranks"
done
