"""The tie clutch's scans (analysis/tie_scan.py, table1_scan.py, lag_limits.py): where a run
loses the lock, where the tie first slips, the lagging plateau of ω_ball, and the run's end."""
import numpy as np

from .config import model_values
from .errors import fail
from .ledger import ledger, read_ledger
from .thresholds import run_checked

PAPER_OMEGA_1 = 4.80  # [π rad/s]


def numbers(text, name):
    """A comma-separated list of numbers >= 0 of option `name`."""
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        fail(f"{name}: '{text}' is not a comma-separated list of numbers")
    if not values or any(not (v >= 0) or not np.isfinite(v) for v in values):
        fail(f"{name}: '{text}': give one or more finite numbers >= 0")
    return values


def run(astrojax, scene, out, overrides):
    run_checked([astrojax, "run", scene, "-o", out, "-q", *(a for o in overrides for a in ("--set", o))])


def string_params(path, run):
    """l and d of the run: its stored configuration, then its --set overrides."""
    v = model_values(path, run, {"string_length": 0.826, "contact_distance": 0.03})
    return v["string_length"], v["contact_distance"]


def summarise(path, window, tail):
    run = read_ledger(path)
    first_slip = float(run["summary"].get("first_tie_slip", -1.0))
    l, d = string_params(path, run)
    rows, last = ledger(run, window, tail)
    up = l - d - 0.01  # the bead counts as up above the bottom stop by 1 cm [m]
    # The lock is lost when the balls have fallen half a turn behind the motor: a locked orbit
    # keeps a bounded phase lag, a lagging one accumulates it at ω_m − ω_ball.
    t, wm = run["t"], run["omega_m"]
    motor = np.concatenate(([0.0], np.cumsum(0.5 * (wm[1:] + wm[:-1]) * np.diff(t))))
    ball = np.unwrap(np.arctan2(run["r2"][:, 1], run["r2"][:, 0]))
    behind = (motor - ball) - (motor[0] - ball[0])
    k = np.argmax(behind > np.pi) if np.any(behind > np.pi) else None
    t_lost = t[k] if k is not None else None
    after = [r for r in rows if t_lost is not None and r["t0"] >= t_lost and r["L1"] < up]
    slip_omega = (np.interp(first_slip, t, wm) / np.pi) if first_slip >= 0 else None
    return dict(lost=wm[k] / np.pi if k is not None else None, slip=slip_omega,
                plateau=(min(r["omega_bottom"] for r in after), max(r["omega_bottom"] for r in after),
                         after[0]["omega_m"], after[-1]["omega_m"]) if after else None,
                last=last, fallen=last["L1"] >= up)


def cell(v, fmt="{:.2f}π"):
    return "—" if v is None else fmt.format(v)
