#!/usr/bin/python3
"""Calibration of the unmeasured drive radius R and contact distance d from the thresholds.

Reads one or more sweep files over R × d × ramp_rate (sweeps/calibration.toml), takes every
chain's threshold brackets from `astrojax thresholds`, and for each (R, d):
  1. extrapolates each threshold to zero ramp rate: a weighted least-squares line
     mid = ω0 + b·rate through the chains' bracket midpoints, weights 1/(half-width)², so ω0
     is the quasi-static threshold and σ(ω0) its standard error (from the bracket widths, and
     from the scatter about the line when there are more rates than parameters); one rate
     only: ω0 = the midpoint, σ = the half-width, marked "single rate";
  2. scores it against the paper: J = Σ_k ((ω0_k − paper_k) / paper_k)² over the thresholds
     reached there.
The best (R, d) reaches the most thresholds with the smallest J. The grid points whose J lies
within 2 σ_J of the best (σ_J propagated from the σ(ω0)) span its uncertainty. The
sensitivities ∂ω0_k/∂R and ∂ω0_k/∂d are differences to the neighbouring grid values.

A threshold whose slope b moves it by more than 3 σ over the rates swept depends on the ramp:
the report says so (a transient rather than a quasi-static bifurcation; docs/guide/thresholds.md, "Bifurcation or time limit").

usage: /usr/bin/python3 analysis/calibrate.py out/calibration.h5 -o out/calibration.md [--csv out/calibration.csv]
"""
import csv
import os

import numpy as np

import astrojax_analysis as ajx

PI = np.pi
THRESHOLDS = ("omega_rise", "omega_fall", "omega_1", "omega_2")


def extrapolate(rates, mids, half_widths):
    """The zero-rate limit of one threshold from (rate, bracket midpoint, half-width) points:
    (ω0, σ(ω0), slope b, σ(b), how). Weighted least squares of mid = ω0 + b·rate, weights
    1/hw²; the covariance is scaled by the reduced χ² when there are more than two rates
    (the scatter about the line counts), never scaled below the bracket widths' own."""
    rates, mids, hw = (np.asarray(v, float) for v in (rates, mids, half_widths))
    hw = np.where(hw > 0, hw, np.finfo(float).eps * np.maximum(np.abs(mids), 1.0))
    distinct = np.unique(rates[np.isfinite(rates)])
    if len(mids) == 0:
        return np.nan, np.nan, np.nan, np.nan, "not reached"
    if len(distinct) < 2:
        w = 1.0 / hw**2
        return float(np.sum(w * mids) / np.sum(w)), float(1.0 / np.sqrt(np.sum(w))), np.nan, np.nan, "single rate"
    A = np.column_stack([np.ones_like(rates), rates]) / hw[:, None]
    y = mids / hw
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    cov = np.linalg.inv(A.T @ A)
    dof = len(mids) - 2
    if dof > 0:
        chi2 = float(np.sum((A @ coef - y) ** 2)) / dof
        cov *= max(chi2, 1.0)
    return float(coef[0]), float(np.sqrt(cov[0, 0])), float(coef[1]), float(np.sqrt(cov[1, 1])), f"{len(distinct)} rates"


def score(limits, paper):
    """J = Σ ((ω0 − paper)/paper)² over the thresholds reached, and σ_J propagated from σ(ω0)."""
    J, var = 0.0, 0.0
    for name, (w0, s0) in limits.items():
        r = (w0 - paper[name]) / paper[name]
        J += r * r
        var += (2.0 * r * s0 / paper[name]) ** 2
    return J, np.sqrt(var)


def collect(files, args):
    """{(R, d): {threshold: [(rate, mid, half-width), ...]}} and {threshold: paper value}."""
    points, paper = {}, {}
    for path in files:
        sweep = ajx.Sweep(path)
        if sweep.is_hold:
            ajx.fail(f"{path}: a hold sweep has no ramps to take thresholds from")
        rows = ajx.thresholds_for(args, path)
        for row in rows:
            c = int(row["chain"])
            paper[row["threshold"]] = ajx.number(row["paper_rad_s"])
            key = (sweep.parameter(c, "drive_radius"), sweep.parameter(c, "contact_distance"))
            entry = points.setdefault(key, {t: [] for t in THRESHOLDS})
            if not row["mid_rad_s"]:
                continue
            rate = float(sweep.grid[c][sweep.axes.index("ramp_rate")]) if "ramp_rate" in sweep.axes else np.nan
            before, after = ajx.number(row["before_rad_s"]), ajx.number(row["after_rad_s"])
            entry[row["threshold"]].append((rate, 0.5 * (before + after), 0.5 * abs(after - before)))
    return points, paper


def calibrate(points, paper):
    """Per (R, d): the zero-rate limits and the score; the best point; the consistent set."""
    table = {}
    for key, per in points.items():
        limits, notes = {}, {}
        for name in THRESHOLDS:
            pts = per.get(name, [])
            if not pts:
                continue
            rates, mids, hws = zip(*pts)
            w0, s0, b, sb, how = extrapolate(rates, mids, hws)
            limits[name] = (w0, s0)
            span = np.nanmax(rates) - np.nanmin(rates) if len(set(rates)) > 1 else 0.0
            dependent = np.isfinite(b) and abs(b) * span > 3.0 * max(s0, 1e-300)
            notes[name] = how + ("; moves with the ramp rate" if dependent else "")
        J, sJ = score(limits, paper)
        table[key] = {"limits": limits, "notes": notes, "J": J, "sigma_J": sJ, "reached": len(limits)}
    if not table:
        return table, None, []
    most = max(v["reached"] for v in table.values())
    candidates = {k: v for k, v in table.items() if v["reached"] == most}
    best = min(candidates, key=lambda k: candidates[k]["J"])
    bound = candidates[best]["J"] + 2.0 * candidates[best]["sigma_J"]
    consistent = sorted(k for k, v in candidates.items() if v["J"] <= bound)
    return table, best, consistent


def sensitivities(table, best):
    """∂ω0/∂R and ∂ω0/∂d [rad/s per m] at the best point, by differences to its grid neighbours
    (central where both exist)."""
    Rs = sorted({k[0] for k in table})
    ds = sorted({k[1] for k in table})
    out = {}
    for axis, values in ((0, Rs), (1, ds)):
        i = values.index(best[axis])
        lo, hi = values[max(i - 1, 0)], values[min(i + 1, len(values) - 1)]
        for name in THRESHOLDS:
            def at(v):
                key = (v, best[1]) if axis == 0 else (best[0], v)
                return table.get(key, {}).get("limits", {}).get(name, (np.nan, np.nan))[0]
            out[(name, axis)] = (at(hi) - at(lo)) / (hi - lo) if hi != lo else np.nan
    return out


def fmt_pi(v, digits=3):
    return f"{v / PI:.{digits}f}" if np.isfinite(v) else ""


def report(files, table, best, consistent, paper, sens):
    lines = ["# Calibration of R and d from the thresholds", "",
             f"- sweeps: {', '.join(f'`{p}`' for p in files)}",
             "- each threshold extrapolated to zero ramp rate (weighted least squares over the chains' "
             "brackets); J = Σ ((ω0 − paper)/paper)² over the thresholds reached", ""]
    if best is None:
        return "\n".join(lines + ["No chain reached any threshold: nothing to calibrate.", ""])
    b = table[best]
    lines += ["## Best fit", "",
              f"R = {1e3 * best[0]:g} mm, d = {1e2 * best[1]:g} cm: {b['reached']} of 4 thresholds reached, "
              f"J = {b['J']:.3g} ± {b['sigma_J']:.2g}.",
              f"Consistent within 2 σ_J: R in [{1e3 * min(k[0] for k in consistent):g}, "
              f"{1e3 * max(k[0] for k in consistent):g}] mm, d in [{1e2 * min(k[1] for k in consistent):g}, "
              f"{1e2 * max(k[1] for k in consistent):g}] cm ({len(consistent)} grid points).", "",
              "| threshold | ω0 [π rad/s] | σ [π rad/s] | paper [π rad/s] | relative difference | within 5 % | "
              "∂ω0/∂R [π rad/s per mm] | ∂ω0/∂d [π rad/s per cm] | how |",
              "|---|---:|---:|---:|---:|---|---:|---:|---|"]
    for name in THRESHOLDS:
        p = paper.get(name, np.nan)
        if name in b["limits"]:
            w0, s0 = b["limits"][name]
            rel = (w0 - p) / p
            lines.append(f"| {name} | {fmt_pi(w0)} | {fmt_pi(s0)} | {fmt_pi(p, 2)} | {100 * rel:+.1f} % | "
                         f"{'yes' if abs(rel) <= 0.05 else 'no'} | {fmt_pi(sens[(name, 0)] * 1e-3)} | "
                         f"{fmt_pi(sens[(name, 1)] * 1e-2)} | {b['notes'][name]} |")
        else:
            lines.append(f"| {name} | not reached | | {fmt_pi(p, 2)} | | no | | | |")
    lines += ["", "## Every grid point", "",
              "| R [mm] | d [cm] | reached | J | " + " | ".join(f"{t} ω0 [π]" for t in THRESHOLDS) + " |",
              "|---:|---:|---:|---:|" + "---:|" * len(THRESHOLDS)]
    for key in sorted(table):
        v = table[key]
        cells = [fmt_pi(v["limits"][t][0]) if t in v["limits"] else "" for t in THRESHOLDS]
        lines.append(f"| {1e3 * key[0]:g} | {1e2 * key[1]:g} | {v['reached']} | {v['J']:.3g} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def write_csv(path, table):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["drive_radius_m", "contact_distance_m", "threshold", "omega0_rad_s", "sigma_rad_s", "J", "how"])
        for key in sorted(table):
            v = table[key]
            for name in THRESHOLDS:
                if name in v["limits"]:
                    w0, s0 = v["limits"][name]
                    w.writerow([f"{key[0]:.9g}", f"{key[1]:.9g}", name, f"{w0:.9g}", f"{s0:.6g}", f"{v['J']:.6g}",
                                v["notes"][name]])


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("inputs", nargs="+", help="HDF5 files from `astrojax sweep` over drive_radius, contact_distance "
                                              "and ramp_rate")
    ap.add_argument("-o", "--output", required=True, help="the Markdown report (.md)")
    ap.add_argument("--csv", help="the per-point table as CSV (default: the report's path with .csv)")
    ap.add_argument("--astrojax", metavar="PATH",
                    help="the astrojax executable (default: $ASTROJAX, build/astrojax, or astrojax on PATH)")
    args = ap.parse_args(argv)
    args.thresholds, args.refine = None, None
    if not args.output.endswith(".md"):
        ajx.fail(f"-o {args.output}: the report is Markdown, give a path ending in .md")
    for p in args.inputs:
        if not os.path.isfile(p):
            ajx.fail(f"{p}: no such file")
    points, paper = collect(args.inputs, args)
    table, best, consistent = calibrate(points, paper)
    sens = sensitivities(table, best) if best is not None else {}
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    with open(args.output, "w") as f:
        f.write(report(args.inputs, table, best, consistent, paper, sens))
    write_csv(args.csv or os.path.splitext(args.output)[0] + ".csv", table)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    ajx.run(main)
