"""Basins of a sweep's basin groups (/basins, format 5): the orbits found at each ω_m level
grouped into attractors, matched from level to level so that one attractor keeps one label
along ω_m (as Attractors.jl's continuation matches attractors by distance), and the fraction of
starts ending on each with its 95 % Wilson interval.

Two orbits of one class are told apart by their features, each scaled to a number of order
one: ln(ω_ball / 1 rad/s), the balls' mean radii ρ1/l, ρ2/l and the bead's place s/l = L1/l.
The logarithm because ω_ball moves along ω_m in proportion for a locked orbit (ω_ball = ω_m, so
by ln(ω_k+1/ω_k) between levels: 0.23 from 4.13π to 5.2π, less above) while a lagging one keeps
it nearly constant; an undefined ω_ball (the balls near the axis, or turning backwards) counts
as 0. At
one level the samples of one class whose scaled features lie within the level's match_tolerance
of each other (single linkage) are one attractor; from one level to the next, each attractor is
given the label of the nearest attractor of the same class at the previous level within the
tolerance (centroid distance, nearest pairs first, one to one), else a new label. not-settled and
failed samples are not orbits: each keeps its class as its label. The fallen samples of a level
are one attractor: the bead on the bottom ball makes a driven spherical pendulum whose swing left
from the start decays only as exp(−c_D t/m) (10 s), so their features at the window tell their
leftover swings apart, not two orbits.
"""
import numpy as np

from .reader import BASIN_FAMILIES, BASIN_FEATURES, wilson_interval

NOT_ORBITS = ("not-settled", "failed")
UNSPLIT = NOT_ORBITS + ("fallen",)  # one attractor per level, whatever their features


def scaled_features(features, string_length):
    """(ln ω_ball, ρ1/l, ρ2/l, s/l) of samples, features as /basins/features (ω_ball [rad/s],
    radius_bead_mean, radius_bottom_mean, L1_mean [m])."""
    f = np.asarray(features, dtype=float)
    out = np.empty_like(f)
    with np.errstate(invalid="ignore", divide="ignore"):
        out[:, 0] = np.log(f[:, 0])
    out[:, 1:] = f[:, 1:] / string_length
    # An undefined feature (ω_ball of balls on the axis or turning backwards) counts as 0: the
    # orbit is told apart by the others.
    return np.nan_to_num(out, nan=0.0, neginf=0.0)


def clusters(points, tolerance):
    """Single-linkage clusters of points (n × d): a list of index arrays, largest first."""
    n = len(points)
    label = -np.ones(n, dtype=int)
    k = 0
    for i in range(n):
        if label[i] >= 0:
            continue
        label[i] = k
        stack = [i]
        while stack:
            j = stack.pop()
            near = np.flatnonzero((label < 0) & (np.linalg.norm(points - points[j], axis=1) <= tolerance))
            label[near] = k
            stack.extend(near.tolist())
        k += 1
    out = [np.flatnonzero(label == c) for c in range(k)]
    return sorted(out, key=len, reverse=True)


def match_levels(levels, tolerance):
    """Labels along ω_m. `levels`: in order of ω_m, each a list of attractors (class name,
    centroid); returns, per level, one label per attractor: (class name, k), k counting the
    attractors of that class that were not matched to one before them. The classes of UNSPLIT
    (fallen, not-settled, failed) have one label, (class name, 0), at every level."""
    labels, previous, count = [], [], {}
    for atts in levels:
        pairs = []
        for i, (cls, x) in enumerate(atts):
            for j, (pcls, px, plabel) in enumerate(previous):
                if cls == pcls and cls not in UNSPLIT:
                    d = float(np.linalg.norm(np.asarray(x) - np.asarray(px)))
                    if d <= tolerance:
                        pairs.append((d, i, j))
        mine = [None] * len(atts)
        taken = set()
        for d, i, j in sorted(pairs):
            if mine[i] is None and j not in taken:
                mine[i] = previous[j][2]
                taken.add(j)
        for i, (cls, x) in enumerate(atts):
            if mine[i] is None:
                if cls in UNSPLIT:
                    mine[i] = (cls, 0)
                else:
                    mine[i] = (cls, count.get(cls, 0))
                    count[cls] = count.get(cls, 0) + 1
        labels.append(mine)
        previous = [(cls, x, lab) for (cls, x), lab in zip(atts, mine)]
    return labels


def label_text(label, counts):
    """'locked-circular', or 'locked-circular B' when its class has more than one attractor."""
    cls, k = label
    return cls if counts.get(cls, 1) <= 1 else f"{cls} {chr(ord('A') + k) if k < 26 else k}"


def basin_table(sweep, part):
    """The matched basins of one part (a (group, variant) of the file): a dict with the levels'
    ω_m [rad/s] in rising order, N done per level, the attractor labels (texts, in order of
    first appearance), counts (levels × labels), fractions with their Wilson intervals, and
    each sample's label index."""
    b = sweep.basins
    lv = b["levels"]
    rows = np.flatnonzero(lv["part"] == part)
    rows = rows[np.argsort(lv["omega_m"][rows], kind="stable")]
    names = [c.name for c in sweep.classes]
    length = sweep.parameter(int(b["chain"][lv["first"][rows[0]]]), "string_length")
    sample_label = -np.ones(len(b["class"]), dtype=int)
    per_level, members = [], []
    for r in rows:
        idx = np.flatnonzero((b["level"] == r) & (b["class"] >= 0))
        x = scaled_features(b["features"][idx], length)
        atts, mem = [], []
        for code in np.unique(b["class"][idx]):
            of = np.flatnonzero(b["class"][idx] == code)
            groups = [of] if names[code] in UNSPLIT else [of[g] for g in clusters(x[of], lv["match_tolerance"][r])]
            for g in groups:
                atts.append((names[code], x[g].mean(axis=0)))
                mem.append(idx[g])
        per_level.append(atts)
        members.append(mem)
    tolerance = float(np.min(lv["match_tolerance"][rows]))
    labels = match_levels(per_level, tolerance)
    order = []
    for lab in labels:
        for x in lab:
            if x not in order:
                order.append(x)
    counts_per_class = {}
    for cls, k in order:
        counts_per_class[cls] = counts_per_class.get(cls, 0) + 1
    count = np.zeros((len(rows), len(order)), dtype=int)
    for li, (lab, mem) in enumerate(zip(labels, members)):
        for x, m in zip(lab, mem):
            count[li, order.index(x)] += len(m)
            sample_label[m] = order.index(x)
    done = lv["done"][rows]
    with np.errstate(invalid="ignore", divide="ignore"):
        fraction = np.where(done[:, None] > 0, count / np.maximum(done[:, None], 1), np.nan)
    lo, hi = wilson_interval(count, done[:, None])
    return {"omega_m": lv["omega_m"][rows], "done": done, "samples": lv["samples"][rows],
            "labels": [label_text(x, counts_per_class) for x in order], "classes": [x[0] for x in order],
            "count": count, "fraction": fraction, "lower": lo, "upper": hi, "sample_label": sample_label,
            "family": BASIN_FAMILIES[int(lv["family"][rows[0]])], "tolerance": tolerance}


def up_probability(sweep, part):
    """P(the bead is up) at each level of a part: the fraction of classified samples whose
    class is an orbit other than fallen (not-settled and failed samples count as not up, so
    the probability is a lower bound where they occur), with its Wilson interval."""
    b = sweep.basins
    lv = b["levels"]
    rows = np.flatnonzero(lv["part"] == part)
    rows = rows[np.argsort(lv["omega_m"][rows], kind="stable")]
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


__all__ = ["BASIN_FEATURES", "basin_parts", "basin_table", "clusters", "label_text", "match_levels",
           "scaled_features", "up_probability"]
