"""astrojax_analysis.basins on a synthetic file whose answer is known: the attractors are the
file's own (/basins/attractors, matched by the program), ordered by their first level along ω_m
within a part, with their counts and Wilson intervals; a file without stored attractors is refused
naming /basins/attractors; the Wilson interval against published values.
Usage: analysis_basins_test.py SOURCE_DIR"""
import sys
import types

import numpy as np

sys.path.insert(0, sys.argv[1] + "/analysis")
from astrojax_analysis import basins as bs  # noqa: E402
from astrojax_analysis.reader import SweepFileError, wilson_interval  # noqa: E402

failures = []


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


CLASSES = ["fallen", "locked-circular", "lagging-circular", "flower", "not-settled", "failed"]
# Two parts; part 0 has levels stored out of ω_m order (rows 1, 0), part 1 one level (row 2).
# Attractors: 0 "locked-circular B" (part 0, appears only at the higher level), 1 "fallen"
# (part 0), 2 "locked-circular A" (part 0, from the lower level), 3 "fallen" (part 1).
level = np.array([0, 0, 0, 1, 1, 1, 2])
cls = np.array([1, 1, 0, 0, 1, -1, 0])
attractor = np.array([0, 0, 1, 1, 2, -1, 3])
L, A = 3, 4
count = np.zeros((L, A), int)
for lev, a in zip(level, attractor):
    if a >= 0:
        count[lev, a] += 1
done = np.array([3, 2, 1])
lo, hi = wilson_interval(count, done[:, None])
att = {"name": ["locked-circular B", "fallen", "locked-circular A", "fallen"], "class": np.array([1, 0, 1, 0]),
       "part": np.array([0, 0, 0, 1]), "count": count, "fraction": count / done[:, None], "lower": lo, "upper": hi}
levels = {"part": np.array([0, 0, 1]), "omega_m": np.array([5.2, 4.13, 4.13]) * np.pi, "done": done,
          "samples": np.array([3, 3, 1]), "family": np.array([2, 2, 2]), "first": np.array([0, 3, 6])}
sweep = types.SimpleNamespace(path="synthetic.h5", classes=[types.SimpleNamespace(name=n) for n in CLASSES],
                              basins={"level": level, "class": cls, "attractor": attractor, "attractors": att,
                                      "levels": levels})

t = bs.basin_table(sweep, 0)
check("levels in rising ω_m", np.allclose(t["omega_m"] / np.pi, [4.13, 5.2]))
check("labels in order of first appearance along ω_m", t["labels"] == ["fallen", "locked-circular A", "locked-circular B"])
check("classes follow the labels", t["classes"] == ["fallen", "locked-circular", "locked-circular"])
check("counts per level and label", t["count"].tolist() == [[1, 1, 0], [1, 0, 2]])
check("fractions are the file's", np.allclose(t["fraction"], [[0.5, 0.5, 0], [1 / 3, 0, 2 / 3]]))
check("each sample's label index", t["sample_label"].tolist() == [2, 2, 0, 0, 1, -1, -1])
t1 = bs.basin_table(sweep, 1)
check("another part has its own attractors", t1["labels"] == ["fallen"] and t1["count"].tolist() == [[1]])

old = types.SimpleNamespace(path="old.h5", classes=sweep.classes, basins=dict(sweep.basins, attractors=None))
try:
    bs.basin_table(old, 0)
    check("a file without stored attractors is refused", False)
except SweepFileError as e:
    check("a file without stored attractors is refused naming /basins/attractors and the way out",
          "/basins/attractors" in str(e) and "astrojax classify" in str(e))

# Wilson: 5 of 10 is [0.2366, 0.7634], 0 of 10 is [0, 0.2775] (Newcombe 1998, method 3).
lo, hi = wilson_interval(np.array([5, 0]), np.array([10, 10]))
check("wilson: published values", np.allclose(lo, [0.2366, 0.0], atol=5e-5) and np.allclose(hi, [0.7634, 0.2775], atol=5e-5))
check("wilson: NaN of no trial", np.isnan(wilson_interval(0, 0)[0]))

print(f"analysis_basins: {len(failures)} failed")
sys.exit(1 if failures else 0)
