"""Basins of a sweep's basin groups (/basins, format 5): the fraction of starts ending on each
attractor at each ω_m level with its 95 % Wilson interval.

The attractors are matched across ω_m once, by the program, when the sweep finishes (and again
by `astrojax classify`), and stored in the file: /basins/attractor gives each sample's attractor,
/basins/attractors each attractor's name, class and part and its counts per level
(src/sweep/basin_match.hpp says how two orbits of one class are told apart: their features'
bands, each the feature's measured swing over the window plus the classifier's drift tolerance,
do not overlap). This module reads them; it does not match again.
"""
import numpy as np

from .reader import BASIN_FAMILIES, BASIN_FEATURES, SweepFileError, wilson_interval

NOT_ORBITS = ("not-settled", "failed")


def _levels(sweep, part):
    lv = sweep.basins["levels"]
    rows = np.flatnonzero(lv["part"] == part)
    return rows[np.argsort(lv["omega_m"][rows], kind="stable")]


def basin_table(sweep, part):
    """The matched basins of one part (a (group, variant) of the file): a dict with the levels'
    ω_m [rad/s] in rising order, N done per level, the attractors' labels (in order of first
    appearance along ω_m) and classes, counts (levels × labels), fractions with their Wilson
    intervals, and each sample's label index (-1: not classified, or of another part)."""
    b = sweep.basins
    at = b.get("attractors")
    if at is None:
        raise SweepFileError(sweep.path, "/basins/attractors", "missing: the file was made before the attractors were "
                             "stored; `astrojax classify FILE -o FILE2` adds them")
    lv = b["levels"]
    rows = _levels(sweep, part)
    mine = np.flatnonzero(at["part"] == part)
    first = [int(np.flatnonzero(at["count"][rows, a] > 0)[0]) if at["count"][rows, a].any() else len(rows) for a in mine]
    order = [int(a) for _, a in sorted(zip(first, mine), key=lambda x: (x[0], x[1]))]
    names = [c.name for c in sweep.classes]
    sample_label = -np.ones(len(b["class"]), dtype=int)
    for j, a in enumerate(order):
        sample_label[b["attractor"] == a] = j
    return {"omega_m": lv["omega_m"][rows], "done": lv["done"][rows], "samples": lv["samples"][rows],
            "labels": [at["name"][a] for a in order], "classes": [names[at["class"][a]] for a in order],
            "count": at["count"][np.ix_(rows, order)], "fraction": at["fraction"][np.ix_(rows, order)],
            "lower": at["lower"][np.ix_(rows, order)], "upper": at["upper"][np.ix_(rows, order)],
            "sample_label": sample_label, "family": BASIN_FAMILIES[int(lv["family"][rows[0]])]}


def up_probability(sweep, part):
    """P(the bead is up) at each level of a part: the fraction of classified samples whose
    class is an orbit other than fallen (not-settled and failed samples count as not up, so
    the probability is a lower bound where they occur), with its Wilson interval."""
    lv = sweep.basins["levels"]
    rows = _levels(sweep, part)
    names = [c.name for c in sweep.classes]
    up = [i for i, n in enumerate(names) if n not in ("fallen",) + NOT_ORBITS]
    k = lv["count"][rows][:, up].sum(axis=1)
    n = lv["done"][rows]
    lo, hi = wilson_interval(k, n)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(n > 0, k / np.maximum(n, 1), np.nan)
    return lv["omega_m"][rows], p, lo, hi


def basin_parts(sweep):
    """The parts of the file with basin levels, in file order."""
    if sweep.basins is None:
        return []
    return sorted(set(int(p) for p in sweep.basins["levels"]["part"]))


__all__ = ["BASIN_FEATURES", "basin_parts", "basin_table", "up_probability"]
