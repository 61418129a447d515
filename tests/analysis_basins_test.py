"""astrojax_analysis.basins on synthetic cases whose answer is known: single-linkage clusters,
attractors matched across levels (same class, nearest within the tolerance, one to one), and
the Wilson interval against published values.
Usage: analysis_basins_test.py SOURCE_DIR"""
import sys

import numpy as np

sys.path.insert(0, sys.argv[1] + "/analysis")
from astrojax_analysis import basins as bs  # noqa: E402
from astrojax_analysis.reader import wilson_interval  # noqa: E402

failures = []


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


# Two tight groups 1.0 apart, and a chain of points 0.05 apart that single linkage joins.
pts = np.array([[0, 0], [0.02, 0], [1, 0], [1.03, 0], [2, 0], [2.05, 0], [2.1, 0], [2.15, 0]], dtype=float)
cl = bs.clusters(pts, 0.06)
check("clusters: three, the chain of 4 first", [sorted(c.tolist()) for c in cl] == [[4, 5, 6, 7], [0, 1], [2, 3]])
check("clusters: a tolerance below every gap leaves singletons", len(bs.clusters(pts, 0.01)) == len(pts))

# Level by level: a locked orbit drifting slowly (one label throughout); two lagging orbits at
# level 1 (one near the level-0 lagging orbit, one far: a new label), of which the far one
# survives to level 2 alone; the fallen pendulum, which keeps its one label however far its
# features move (its leftover swing, not another orbit).
L = [
    [("locked-circular", [1.0, 0.2]), ("lagging-circular", [0.5, 0.3]), ("fallen", [0.0, 0.1])],
    [("locked-circular", [1.0, 0.21]), ("lagging-circular", [0.46, 0.3]), ("lagging-circular", [0.2, 0.6])],
    [("locked-circular", [1.0, 0.22]), ("lagging-circular", [0.18, 0.6]), ("fallen", [0.0, 0.5]),
     ("not-settled", [0.3, 0.3])],
]
lab = bs.match_levels(L, 0.1)
check("match: the locked orbit keeps one label", lab[0][0] == lab[1][0] == lab[2][0] == ("locked-circular", 0))
check("match: the near lagging orbit keeps its label", lab[1][1] == lab[0][1] == ("lagging-circular", 0))
check("match: the far lagging orbit is a new attractor", lab[1][2] == ("lagging-circular", 1))
check("match: which it stays at the next level", lab[2][1] == ("lagging-circular", 1))
check("match: the fallen pendulum is one attractor along ω_m, wherever its features",
      lab[0][2] == ("fallen", 0) and lab[2][2] == ("fallen", 0))
check("match: not-settled keeps its class as its label", lab[2][3] == ("not-settled", 0))
# One to one: two attractors near one previous one; the nearer takes its label.
lab = bs.match_levels([[("flower", [0.5])], [("flower", [0.58]), ("flower", [0.53])]], 0.1)
check("match: one to one, the nearer first", lab[1][1] == ("flower", 0) and lab[1][0] == ("flower", 1))
check("label text: a class with two attractors gets letters",
      bs.label_text(("flower", 1), {"flower": 2}) == "flower B" and bs.label_text(("fallen", 0), {"fallen": 1}) == "fallen")

# Wilson: 5 of 10 is [0.2366, 0.7634], 0 of 10 is [0, 0.2775] (Newcombe 1998, method 3).
lo, hi = wilson_interval(np.array([5, 0]), np.array([10, 10]))
check("wilson: published values", np.allclose(lo, [0.2366, 0.0], atol=5e-5) and np.allclose(hi, [0.7634, 0.2775], atol=5e-5))
check("wilson: NaN of no trial", np.isnan(wilson_interval(0, 0)[0]))

print(f"analysis_basins: {len(failures)} failed")
sys.exit(1 if failures else 0)
