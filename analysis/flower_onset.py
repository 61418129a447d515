#!/usr/bin/python3
"""Where the lagging circular orbit turns into a flower: the Hopf point ω_H from a staircase.

Reads a sweep of `steps` segments up and back down in ω_m (sweeps/table1_staircase.toml), and for
each chain and each level the relative radius oscillation of the bottom ball over the measured
window, a = std(ρ2)/mean(ρ2): about 1e-8 on a circular orbit, several per cent on a flower.

Near a supercritical Hopf bifurcation the limit cycle's amplitude obeys a² = k (ω_m − ω_H)
(the normal form's r² = μ/ℓ), so ω_H is where the line through a² meets zero. The fit:
  - each level's a² is the midpoint of the up and down legs' values, and its σ their half
    difference: the up leg comes to the limit cycle from the smaller circle and the down leg
    from the larger one, so together they bracket it (a level not yet settled gets a wide σ,
    a settled one a narrow σ); combined with the window's own sampling error, half the
    difference of a² over the window's two halves;
  - the model a² = μ (k + q μ), μ = max(ω_m − ω_H, 0) (the normal form to the next order: far
    above onset the line bends), weighted least squares over the levels up to --span π rad/s
    above the first level of the flower that lasts to the top of the up leg (by the
    classifier); k and q are
    linear and solved for every trial ω_H, ω_H by a scan and golden section;
  - σ(ω_H) where χ² has risen by one (scaled by the reduced χ² when it exceeds one);
  - the torque the tie passes there, τ_H = τ_k + c_a (ω_H − ω_ball), with ω_ball the lagging
    orbit's at the last circular level (the tie clutch of docs/physics/model.md: τ_k + c_a (ω_m − χ̇) while slipping).
Also: the classifier's own bracket (the last lagging level to the first flower level on the way
up), whether the way down returns to a circle at the same level (no hysteresis: a soft, i.e.
supercritical, onset), and the largest |dE/dt| / P_drag over the flower windows (≈ 0: the motor
sustains the flower, it is not a transient).

usage: /usr/bin/python3 analysis/flower_onset.py out/table1_staircase.h5 -o out/flower_onset.md [--span 3]
"""
import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
PAPER_OMEGA_2 = 15.00  # [π rad/s]
SPAN = 3.0  # default --span: the levels fitted reach this far above the first flower [π rad/s]


def amplitude(sweep, c, w):
    """a = std(ρ2)/mean(ρ2) of window w of chain c (the bottom ball)."""
    return float(sweep.stats["radius_bottom_std"][c, w] / sweep.stats["radius_bottom_mean"][c, w])


def sampling_sigma(sweep, c, w):
    """The error of a² from the window's finite length: half the difference of a² over the
    window's first and second halves, from the stored samples (ρ2 = |(x2, y2)|, the radius about
    the motor axis). A limit cycle that the window covers evenly gives the same a² in both."""
    r2 = sweep.samples(c, w)["r2"]
    rho = np.hypot(r2[:, 0], r2[:, 1])
    h = len(rho) // 2
    if h < 2:
        return np.nan
    a2 = [(np.std(part) / np.mean(part)) ** 2 for part in (rho[:h], rho[h:])]
    return 0.5 * abs(a2[0] - a2[1])


def levels(sweep, c):
    """{level ω_m [rad/s]: {"up": window, "down": window}} over the chain's steps legs
    (direction ±1; the held seed leg is left out)."""
    out = {}
    for w in range(sweep.n_windows):
        d = int(sweep.direction[c, w])
        if not sweep.valid[c, w] or d == 0:
            continue
        key = round(float(sweep.omega_mean[c, w]) / PI, 6)  # a level is one ω_m, up or down
        out.setdefault(key, {})["up" if d > 0 else "down"] = w
    return dict(sorted(out.items()))


def hopf_fit(omega, a2, sigma):
    """Weighted fit of a² = μ (k + q μ), μ = max(ω − ω_H, 0): (ω_H, σ(ω_H), k, q, reduced χ²).
    The normal form to the next order (q: the curvature a window far above onset shows). ω in
    any unit; σ > 0. Needs at least three points above ω_H."""
    omega, a2, sigma = (np.asarray(v, float) for v in (omega, a2, sigma))
    wt = 1.0 / sigma**2

    def coefficients(wh):
        mu = np.maximum(omega - wh, 0.0)
        A = np.column_stack([mu, mu * mu]) * np.sqrt(wt)[:, None]
        coef, *_ = np.linalg.lstsq(A, a2 * np.sqrt(wt), rcond=None)
        return coef, mu

    def chi2(wh):
        (k, q), mu = coefficients(wh)
        return float(np.sum(wt * (a2 - mu * (k + q * mu)) ** 2))

    # ω_H lies below the third-highest level (three points above it fix the parabola).
    lo, hi = float(omega.min()) - (omega.max() - omega.min()), float(np.sort(omega)[-3])
    wh = ajx.scan_and_refine(chi2, lo, hi, 400)
    c0 = chi2(wh)
    dof = len(omega) - 3
    red = c0 / dof if dof > 0 else np.nan
    target = c0 + max(red if np.isfinite(red) else 1.0, 1.0)  # Δχ² = 1, scaled by χ²/dof ≥ 1

    def crossing(direction):
        step = 1e-4 * max(abs(wh), 1.0)
        x = wh
        while chi2(x + direction * step) < target and abs(x - wh) < 10 * (hi - lo):
            x += direction * step
            step *= 1.5
        a, b = sorted((x, x + direction * step))
        for _ in range(60):  # bisection on χ²(ω) = target
            m = 0.5 * (a + b)
            if (chi2(m) < target) == (direction > 0):
                a = m
            else:
                b = m
        return 0.5 * (a + b)

    sigma_wh = 0.5 * (crossing(+1) - crossing(-1))
    (k, q), _ = coefficients(wh)
    return wh, sigma_wh, float(k), float(q), red


def analyse(sweep, c, span):
    lev = levels(sweep, c)
    flower = [k for k, v in sweep.class_names.items() if v == "flower"]
    lagging = [k for k, v in sweep.class_names.items() if v == "lagging-circular"]
    row = {"chain": c, "label": sweep.grid_label(c) or f"chain {c}"}
    ups = [(om, v["up"]) for om, v in lev.items() if "up" in v]
    # The flower that lasts to the top of the staircase: a flower window that gives way to a
    # circle again further up (a transient at the lock's loss) is not the onset.
    first_flower = None
    for om, w in reversed(ups):
        if sweep.cls[c, w] not in flower:
            break
        first_flower = om
    last_lag = None
    for om, w in ups:
        if first_flower is not None and om >= first_flower:
            break
        if sweep.cls[c, w] in lagging:
            last_lag = (om, w)
    row["bracket"] = (last_lag[0] if last_lag else np.nan, first_flower if first_flower is not None else np.nan)
    downs = [(om, v["down"]) for om, v in lev.items() if "down" in v]
    back = [om for om, w in downs if sweep.cls[c, w] in flower]
    row["down_lowest_flower"] = min(back) if back else np.nan
    fl_windows = [w for _, w in ups + downs if sweep.cls[c, w] in flower]
    row["sustain"] = max((abs(sweep.stats["energy_rate"][c, w]) / sweep.stats["drag_power"][c, w]
                          for w in fl_windows), default=np.nan)
    row["omega_ball"] = float(sweep.stats["omega_ball"][c, last_lag[1]]) if last_lag else np.nan
    row["L1"] = float(sweep.stats["L1_mean"][c, last_lag[1]]) if last_lag else np.nan
    row["tau_k"] = sweep.parameter(c, "tie_kinetic_torque") if "tie_kinetic_torque" in sweep.model_columns else np.nan
    row["c_a"] = sweep.parameter(c, "tie_damping") if "tie_damping" in sweep.model_columns else np.nan
    row.update(omega_H=np.nan, sigma_H=np.nan, k=np.nan, q=np.nan, red=np.nan, tau_H=np.nan, n=0)
    if first_flower is None:
        return row
    om, a2, sg = [], [], []
    for o, v in lev.items():
        if o > first_flower + span or not ("up" in v and "down" in v):
            continue
        up, dn = amplitude(sweep, c, v["up"]) ** 2, amplitude(sweep, c, v["down"]) ** 2
        om.append(o)
        a2.append(0.5 * (up + dn))
        # Half the legs' difference, combined with each window's own sampling error; never
        # below the rounding of a² itself.
        s_legs = 0.5 * abs(up - dn)
        s_win = max(sampling_sigma(sweep, c, v["up"]), sampling_sigma(sweep, c, v["down"]))
        sg.append(max(np.hypot(s_legs, s_win), 4 * np.finfo(float).eps * max(up, dn), 1e-300))
    if sum(o >= first_flower for o in om) < 3:
        return row
    wh, swh, k, q, red = hopf_fit(om, a2, sg)
    row.update(omega_H=wh, sigma_H=swh, k=k, q=q, red=red, n=len(om))
    if np.isfinite(row["omega_ball"]) and np.isfinite(row["c_a"]):
        row["tau_H"] = row["tau_k"] + row["c_a"] * (wh * PI - row["omega_ball"])
    return row


def report(path, rows, span):
    f = lambda v, d=3: f"{v:.{d}f}" if np.isfinite(v) else "—"
    lines = ["# Onset of the flower orbit (Hopf point of the lagging orbit)", "", f"- sweep: `{path}`",
             f"- fit: a² = μ (k + q μ), μ = max(ω_m − ω_H, 0), over the levels up to {span:g}π above the first flower window; "
             "a = std/mean of the bottom ball's radius; σ of a level = half the difference of its up and down legs; "
             "σ(ω_H) where χ² has risen by max(1, χ²/dof), i.e. scaled by √(χ²/dof) when that exceeds 1; it leaves out "
             "the spread over histories (where the bead sticks, analysis/sensitivity.py --histories)",
             f"- paper: ω2 = {PAPER_OMEGA_2:.2f}π rad/s", "",
             "| chain | c_a [N m s] | L1 [m] | ω_ball [π] | classifier: last lagging → first flower [π] "
             "| ω_H ± σ [π] | vs ω2 | χ²/dof | τ_H [N m] | flower on the way down to [π] | max \\|dE/dt\\|/P_drag (flowers) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lo, hi = r["bracket"]
        rel = f"{(r['omega_H'] - PAPER_OMEGA_2) / PAPER_OMEGA_2 * 100:+.1f} %" if np.isfinite(r["omega_H"]) else "—"
        lines.append(
            f"| {r['label']} | {r['c_a']:.3g} | {f(r['L1'], 4)} | {f(r['omega_ball'] / PI)} | {f(lo, 2)} → {f(hi, 2)} "
            f"| {f(r['omega_H'], 2)} ± {f(r['sigma_H'], 2)} | {rel} | {f(r['red'], 2)} | "
            f"{r['tau_H']:.4g} | {f(r['down_lowest_flower'], 2)} | {r['sustain']:.1e} |".replace("nan", "—"))
    lines += ["", "A chain without a flower window on the way up has no fit (—). ω_H lies below the classifier's "
              "bracket: the classifier names a flower only once the radius oscillation is large enough to see.", ""]
    return "\n".join(lines)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="sweep file with steps up and down (sweeps/table1_staircase.toml)")
    ap.add_argument("-o", "--output", required=True, help="markdown report to write")
    ap.add_argument("--span", type=float, default=SPAN,
                    help=f"fit the levels up to this many π rad/s above the first flower window (default {SPAN:g})")
    args = ap.parse_args(argv)
    if not (args.span > 0):
        ajx.fail(f"--span {args.span}: allowed > 0 (π rad/s)")
    sweep = ajx.Sweep(args.input)
    if sweep.is_hold:
        ajx.fail(f"{args.input}: a hold sweep has no staircase; run sweeps/table1_staircase.toml")
    rows = [analyse(sweep, c, args.span) for c in range(sweep.n_chains)]
    ajx.write_report(args.output, report(args.input, rows, args.span))


if __name__ == "__main__":
    ajx.run(main)
