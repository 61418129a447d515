"""The energy ledger of a run file, window by window (analysis/run_ledger.py prints it):
ω_m, the balls' ω_ball, the orbit radii, the bead's s = L1 and the powers from the run's work
integrals, P_motor (the motor's, at its rod), P_drag, P_fric (friction + impacts), dE/dt and
P_clutch (what the tie clutch dissipates; 0 for a rigid tie), and what closes the ledger,
injection = dE/dt + dE_tie/dt − (P_motor − P_clutch − P_drag − P_fric), the energy the
integrator itself adds per second (E_tie = ½ I_a χ̇², the tie's kinetic energy). Files of
format 2 and 3 hold the string's side in motor_work and lack clutch_loss and tie_energy: they
read as 0. decay_rates: the e-folding rates of an orbit the motor does not feed."""
import numpy as np

from .errors import fail
from .motion import run_parameter
from .reader import read_run

LEDGER_COLUMNS = ("energy", "motor_work", "drag_loss", "friction_loss", "impact_loss", "v1", "v2")
CLUTCH_COLUMNS = ("clutch_loss", "tie_energy")  # format 4 on; a rigid tie's zeros before
COLUMNS = ("t0", "t1", "omega_m", "omega_bead", "omega_bottom", "rho1", "rho2", "L1",
           "P_motor", "P_drag", "P_fric", "dE_dt", "injection", "P_clutch")


def read_ledger(path, columns=()):
    """The run's trajectory (reader.read_run) plus its work integrals, energies and velocities
    (arrays over samples), the further /trajectory `columns`, and the masses m1, m2 and the drag
    coefficient c_D of its configuration in force."""
    run = read_run(path, LEDGER_COLUMNS + CLUTCH_COLUMNS + tuple(columns))
    for name in CLUTCH_COLUMNS:
        run.setdefault(name, np.zeros_like(run["energy"]))
    run["m1"], run["m2"] = run_parameter(path, "model.bead_mass"), run_parameter(path, "model.ball_mass")
    run["c_D"] = run_parameter(path, "model.drag")
    return run


def decay_rates(run, tail):
    """(d ln ρ2/dt, d ln K/dt) [1/s] over the final `tail` seconds: ρ2 the bottom ball's radius
    about the axis (the orbit's amplitude), K = ½ m1 |v1|² + ½ m2 |v2|²."""
    t = run["t"]
    sel = t >= t[-1] - tail
    rho2 = np.hypot(run["r2"][sel, 0], run["r2"][sel, 1])
    k = 0.5 * run["m1"] * np.sum(run["v1"][sel] ** 2, axis=1) + 0.5 * run["m2"] * np.sum(run["v2"][sel] ** 2, axis=1)
    return slope(t[sel], np.log(rho2)), slope(t[sel], np.log(k))


def decay_line(run, tail):
    """decay_rates over the final `tail` seconds next to c_D/2m and c_D/m (m the heavier ball)."""
    a, k = decay_rates(run, tail)
    m = max(run["m1"], run["m2"])
    return (f"decay over the last {tail:g} s: amplitude (ρ2) {a:+.4f} /s, kinetic energy {k:+.4f} /s; "
            f"c_D/2m = {run['c_D'] / (2 * m):.4f} /s, c_D/m = {run['c_D'] / m:.4f} /s")


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
        fail(f"the run is shorter than one window ({window} s)")
    if np.max(np.abs(run["omega_m"])) * np.median(np.diff(t)) > np.pi:
        fail("the samples are too sparse to unwrap the azimuth: lower output.sample_interval")
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
