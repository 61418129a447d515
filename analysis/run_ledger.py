#!/usr/bin/python3
"""The energy ledger of one or more `astrojax run` files, window by window.

For each window of --window seconds: the motor's ω_m and the balls' ω_ball (slope of the
unwrapped azimuth of each ball about the motor axis, in π rad/s), the orbit radii ρ1, ρ2,
the bead's s = L1, and the powers from the run's work integrals:
    P_motor (the motor's, at its rod), P_drag, P_fric (friction + impacts), dE/dt, and last
    P_clutch (what the tie clutch dissipates; 0 for a rigid tie),
and what closes the ledger,
    injection = dE/dt + dE_tie/dt − (P_motor − P_clutch − P_drag − P_fric),
the energy the integrator itself adds per second (E_tie = ½ I_a χ̇², the tie's kinetic energy).
Files of format 2 and 3 hold the string's side in motor_work and lack the clutch's columns: their
P_clutch is read as 0. An exact integration has injection ≈ 0;
an orbit the motor does not feed (P_motor ≈ 0) then decays, dE/dt ≈ −P_drag. A last line per
file gives the means over the final --tail seconds.

With --decay: the e-folding rates over the final --tail seconds of an orbit the motor does not
feed, from least-squares slopes of ln ρ2 (the bottom ball's radius about the axis: the
orbit's amplitude) and of ln K (the balls' kinetic energy), next to c_D/2m and c_D/m.

usage: /usr/bin/python3 analysis/run_ledger.py out/lag_dop853.h5 out/lag_euler.h5 [--window 10] [--decay]
"""
import h5py
import numpy as np

import astrojax_analysis as ajx

COLUMNS = ("t0", "t1", "omega_m", "omega_bead", "omega_bottom", "rho1", "rho2", "L1",
           "P_motor", "P_drag", "P_fric", "dE_dt", "injection", "P_clutch")


def read_ledger(path):
    """The run's trajectory plus its work integrals and energy (1-d arrays over samples)."""
    run = ajx.read_run(path)
    with h5py.File(path, "r") as f:
        tr = f["trajectory"]
        for name in ("energy", "motor_work", "drag_loss", "friction_loss", "impact_loss"):
            if name not in tr:
                ajx.fail(f"{path}: /trajectory/{name} missing (written by astrojax run since the energy ledger)")
            run[name] = tr[name][:]
        # Format 4: the tie clutch's terms (older files have none: a rigid tie's zeros)
        for name in ("clutch_loss", "tie_energy"):
            run[name] = tr[name][:] if name in tr else np.zeros_like(run["energy"])
        run["v1"], run["v2"] = tr["v1"][:], tr["v2"][:]
    run["m1"], run["m2"] = ajx.run_parameter(path, "model.bead_mass"), ajx.run_parameter(path, "model.ball_mass")
    run["c_D"] = ajx.run_parameter(path, "model.drag")
    return run


def decay_rates(run, tail):
    """(d ln ρ2/dt, d ln K/dt) [1/s] over the final `tail` seconds."""
    t = run["t"]
    sel = t >= t[-1] - tail
    rho2 = np.hypot(run["r2"][sel, 0], run["r2"][sel, 1])
    k = 0.5 * run["m1"] * np.sum(run["v1"][sel] ** 2, axis=1) + 0.5 * run["m2"] * np.sum(run["v2"][sel] ** 2, axis=1)
    return slope(t[sel], np.log(rho2)), slope(t[sel], np.log(k))


def slope(t, y):
    """Least-squares slope dy/dt."""
    return np.polyfit(t, y, 1)[0] if len(t) > 2 else np.nan


def window_row(run, sel):
    """One ledger row over the samples selected by the boolean mask `sel`."""
    t = run["t"][sel]
    dt = t[-1] - t[0]

    def rate(name):
        v = run[name][sel]
        return (v[-1] - v[0]) / dt

    theta = [np.unwrap(np.arctan2(run[r][:, 1], run[r][:, 0]))[sel] for r in ("r1", "r2")]
    rho = [np.hypot(run[r][sel, 0], run[r][sel, 1]).mean() for r in ("r1", "r2")]
    p_m, p_d = rate("motor_work"), rate("drag_loss")
    p_f = rate("friction_loss") + rate("impact_loss")
    de, p_c = rate("energy"), rate("clutch_loss")
    return dict(t0=t[0], t1=t[-1], omega_m=run["omega_m"][sel].mean() / np.pi,
                omega_bead=slope(t, theta[0]) / np.pi, omega_bottom=slope(t, theta[1]) / np.pi,
                rho1=rho[0], rho2=rho[1], L1=run["L1"][sel].mean(),
                P_motor=p_m, P_drag=p_d, P_fric=p_f, dE_dt=de,
                injection=de + rate("tie_energy") - (p_m - p_c - p_d - p_f), P_clutch=p_c)


def ledger(run, window, tail):
    t = run["t"]
    if len(t) < 3 or t[-1] - t[0] < window:
        ajx.fail(f"the run is shorter than one window ({window} s)")
    if np.max(np.abs(run["omega_m"])) * np.median(np.diff(t)) > np.pi:
        ajx.fail("the samples are too sparse to unwrap the azimuth: lower output.sample_interval")
    edges = np.arange(t[0], t[-1] + 1e-9, window)
    rows = [window_row(run, (t >= a) & (t <= b)) for a, b in zip(edges[:-1], edges[1:])]
    last = window_row(run, t >= t[-1] - tail)
    return rows, last


def fmt_row(r, label=None):
    head = label if label else f"{r['t0']:6.1f}-{r['t1']:6.1f}"
    return (f"{head:>13}  {r['omega_m']:6.2f}  {r['omega_bead']:6.2f} {r['omega_bottom']:6.2f}  "
            f"{r['rho1']:.3f} {r['rho2']:.3f}  {r['L1']:.3f}  {r['P_motor']:+.2e} {r['P_drag']:.2e} "
            f"{r['P_fric']:.2e} {r['dE_dt']:+.2e} {r['injection']:+.2e}  {r['P_clutch']:.2e}")


HEADER = ("     t [s]     ω_m/π  ω_bead/π ω_bot/π  ρ1 [m] ρ2 [m]  L1 [m]  P_motor   P_drag   "
          "P_fric   dE/dt     injection  P_clutch [W]")


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("inputs", nargs="+", help="HDF5 files from `astrojax run`")
    ap.add_argument("--window", type=float, default=10.0, help="window length [s] (default 10)")
    ap.add_argument("--tail", type=float, default=40.0, help="final stretch for the summary line [s] (default 40)")
    ap.add_argument("--decay", action="store_true",
                    help="also the e-folding rates of the orbit's amplitude and kinetic energy over the tail")
    args = ap.parse_args(argv)
    if not (args.window > 0 and args.tail > 0):
        ajx.fail("--window and --tail must be > 0 seconds")
    for path in args.inputs:
        run = read_ledger(path)
        rows, last = ledger(run, args.window, args.tail)
        print(f"# {path}")
        print(HEADER)
        for r in rows:
            print(fmt_row(r))
        print(fmt_row(last, f"last {args.tail:g} s"))
        if args.decay:
            a, k = decay_rates(run, args.tail)
            m = max(run["m1"], run["m2"])
            print(f"decay over the last {args.tail:g} s: amplitude (ρ2) {a:+.4f} /s, kinetic energy {k:+.4f} /s; "
                  f"c_D/2m = {run['c_D'] / (2 * m):.4f} /s, c_D/m = {run['c_D'] / m:.4f} /s")
        print()


if __name__ == "__main__":
    main()
