"""The energy ledger of a run file, window by window (analysis/run_ledger.py prints it):
ω_m, the balls' ω_ball, the orbit radii, the bead's s = L1 and the powers from the run's work
integrals, P_motor, P_drag, P_fric (friction + impacts), dE/dt, and what closes the ledger,
injection = dE/dt − (P_motor − P_drag − P_fric), the energy the integrator itself adds per second."""
import numpy as np

from .errors import fail
from .reader import read_run

LEDGER_COLUMNS = ("energy", "motor_work", "drag_loss", "friction_loss", "impact_loss")
COLUMNS = ("t0", "t1", "omega_m", "omega_bead", "omega_bottom", "rho1", "rho2", "L1",
           "P_motor", "P_drag", "P_fric", "dE_dt", "injection")


def read_ledger(path, columns=()):
    """The run's trajectory (reader.read_run) plus its work integrals and energy (1-d arrays
    over samples) and the further /trajectory `columns`."""
    return read_run(path, LEDGER_COLUMNS + tuple(columns))


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
    de = rate("energy")
    return dict(t0=t[0], t1=t[-1], omega_m=run["omega_m"][sel].mean() / np.pi,
                omega_bead=slope(t, theta[0]) / np.pi, omega_bottom=slope(t, theta[1]) / np.pi,
                rho1=rho[0], rho2=rho[1], L1=run["L1"][sel].mean(),
                P_motor=p_m, P_drag=p_d, P_fric=p_f, dE_dt=de, injection=de - (p_m - p_d - p_f))


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
            f"{r['P_fric']:.2e} {r['dE_dt']:+.2e} {r['injection']:+.2e}")


HEADER = ("     t [s]     ω_m/π  ω_bead/π ω_bot/π  ρ1 [m] ρ2 [m]  L1 [m]  P_motor   P_drag   "
          "P_fric   dE/dt     injection [W]")
