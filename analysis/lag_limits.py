#!/usr/bin/python3
"""Where the bead sits decides both ω_fall and the lag's ω_ball: the limits of the lagging
orbit of the slipping tie along the string, from `astrojax orbits --lag` (no simulation).

For each drive radius R, contact distance d and bead position s (the bead stuck at L1 = s), the
stuck family at s, continued in ω as the lag of the slipping tie (orbits/lagging_orbit.hpp), gives
  ω_fall(s)   where the circle enters the static cone as ω grows: below it the stuck bead slides
              down. It is the locked orbit's fall at that s (and the lag's lower end);
  ceiling(s)  the highest ω_ball of a lag that is held by friction and stable: its Hopf point
              (a flower beyond), or the cone's exit if that comes first (the bead slides up).
The paper: ω_fall = 3.24π, and between ω1 and ω2 the balls lag at ω_ball ≈ 4.8π up to ω2,
where the lag ends in a flower: on this model's lag that is the Hopf point, so ω_ball at ω2 is
the ceiling. Neither number depends on τ_k (it only picks where on the branch the lag sits at a
given ω_m) and the Hopf point barely on c_a (docs/reports/reproduction-evidence.md, "The lag's ceiling").

usage: /usr/bin/python3 analysis/lag_limits.py -o out/lag_limits.md [--radii 0.015] [--distances 0.035]
                                               [--s 0.40:0.62:0.02]
"""
import os
import tempfile

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis import tie

HERE = os.path.dirname(os.path.abspath(__file__))
PAPER_FALL, PAPER_LAG = 3.24, 4.80  # [π rad/s]
TOLERANCE = 0.05  # the target: within 5 %


def numbers(text, option, lo, hi):
    """tie.numbers' list of numbers, each also within [lo, hi]."""
    values = tie.numbers(text, option)
    if any(not (lo <= v <= hi) for v in values):
        ajx.fail(f"{option}: '{text}': each value must lie in [{lo}, {hi}]")
    return values


def s_grid(text):
    try:
        lo, hi, step = (float(v) for v in text.split(":"))
    except ValueError:
        ajx.fail(f"--s: '{text}' is not LO:HI:STEP")
    if not (0.05 < lo < hi <= 0.8 and 0 < step <= hi - lo):
        ajx.fail(f"--s: '{text}': need 0.05 < LO < HI <= 0.8 m and 0 < STEP <= HI - LO")
    return list(np.arange(lo, hi + 0.5 * step, step))


def limits(astrojax, R, d, grid, overrides):
    """Per s: (ω_fall, ceiling, what ends it, τ there), in π rad/s and N m; NaN where the
    stable side (bead on the tie's side, ball opposite: '+/-', Table 1's) has no held lag."""
    with tempfile.TemporaryDirectory() as tmp:
        csv_path = os.path.join(tmp, "lag.csv")
        cmd = [astrojax, "orbits", os.path.join(HERE, "..", "sweeps", "orbits.toml"), "--lag", "--omega", "10pi",
               "--csv", csv_path, "--set", "layers.tie=clutch", "--set", f"model.drive_radius={R!r}",
               "--set", f"model.contact_distance={d!r}"]
        for o in overrides:
            cmd += ["--set", o]
        for s in grid:
            cmd += ["--s", f"{s:.6f}"]
        ajx.run_checked(cmd)
        rows = ajx.read_astrojax_csv(csv_path, {"s", "kind", "side", "omega_ball", "torque"}, "astrojax orbits --lag")
    out = {}
    for s in grid:
        ev = [r for r in rows if abs(float(r["s"]) - s) < 1e-6 and r["side"] == "+/-" and r["kind"] != "lag"]
        entries = [float(r["omega_ball"]) for r in ev if r["kind"] == "cone_entry"]
        if not entries:
            out[s] = (np.nan, np.nan, "no held lag", np.nan)
            continue
        fall = min(entries)
        ends = [(float(r["omega_ball"]), "Hopf" if r["kind"] == "loss (hopf)" else r["kind"], float(r["torque"]))
                for r in ev if r["kind"] in ("loss (hopf)", "loss", "cone_exit") and float(r["omega_ball"]) > fall]
        top = min(ends) if ends else (np.nan, "none in range", np.nan)
        out[s] = (fall / np.pi, top[0] / np.pi, top[1], top[2])
    return out


def err(value, paper):
    return (value - paper) / paper


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("-o", "--output", required=True, help="Markdown report to write")
    ap.add_argument("--radii", default="0.015", help="R values [m] (default 0.015, the one set's)")
    ap.add_argument("--distances", default="0.035", help="d values [m] (default 0.035)")
    ap.add_argument("--s", default="0.40:0.62:0.02", help="bead positions LO:HI:STEP [m] (default 0.40:0.62:0.02)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="more model keys for astrojax (default: the one set's τ_s 1.5e-3, τ_k 1.35e-3, c_a 2e-6)")
    ap.add_argument("--astrojax", default=None, help="the astrojax binary (default: build/astrojax)")
    args = ap.parse_args(argv)
    radii = numbers(args.radii, "--radii", 1e-3, 0.05)
    distances = numbers(args.distances, "--distances", 0.01, 0.1)
    grid = s_grid(args.s)
    astrojax = ajx.require_astrojax(args.astrojax)
    overrides = ["model.tie_static_torque=1.5e-3", "model.tie_kinetic_torque=1.35e-3", "model.tie_damping=2e-6"]
    overrides += args.set

    text = [f"# The lag's limits along the string (`analysis/lag_limits.py`)\n",
            f"Paper: ω_fall = {PAPER_FALL}π, the lag's ω_ball ≈ {PAPER_LAG}π up to ω2. Model keys: "
            f"{', '.join(overrides)}.\n"]
    summary = ["| R [mm] | d [cm] | best s [m] | ω_fall(s) | ceiling(s) | larger error | s with ω_fall within 5 % "
               "| s with the ceiling within 5 % |", "|---|---|---|---|---|---|---|---|"]
    for R in radii:
        for d in distances:
            lim = limits(astrojax, R, d, grid, overrides)
            text.append(f"\n## R = {R * 1e3:g} mm, d = {d * 1e2:g} cm\n")
            text.append("| s [m] | ω_fall(s) [π] | error | ceiling of the lag [π] | error | ended by | τ there [N m] |")
            text.append("|---|---|---|---|---|---|---|")
            best = None
            fall_ok, lag_ok = [], []
            for s in grid:
                fall, top, by, tau = lim[s]
                ef, el = err(fall, PAPER_FALL), err(top, PAPER_LAG)
                text.append(f"| {s:.3f} | {fall:.3f} | {ef:+.1%} | {top:.3f} | {el:+.1%} | {by} | {tau:.3e} |")
                if np.isfinite(ef) and abs(ef) <= TOLERANCE:
                    fall_ok.append(s)
                if np.isfinite(el) and abs(el) <= TOLERANCE:
                    lag_ok.append(s)
                worst = max(abs(ef), abs(el))
                if np.isfinite(worst) and (best is None or worst < best[0]):
                    best = (worst, s, fall, top)
            span = lambda v: f"{min(v):.2f}–{max(v):.2f}" if v else "none"
            if best:
                summary.append(f"| {R * 1e3:g} | {d * 1e2:g} | {best[1]:.3f} | {best[2]:.3f}π | {best[3]:.3f}π "
                               f"| {best[0]:.1%} | {span(fall_ok)} | {span(lag_ok)} |")
            else:
                summary.append(f"| {R * 1e3:g} | {d * 1e2:g} | — | — | — | — | none | none |")
            print(summary[-1], flush=True)
    text.append("\n## Summary: the s that minimises the larger of the two errors\n")
    text += summary
    ajx.write_report(args.output, "\n".join(text) + "\n")


if __name__ == "__main__":
    ajx.run(main)
