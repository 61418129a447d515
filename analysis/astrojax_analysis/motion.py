"""The motor's frame: the phase φ inside a sweep window and positions in the frame turning
with the motor."""
import numpy as np

from .reader import open_h5, resolved
from .sweep import require_phase


def window_phase(sweep, c, k, s):
    """The motor phase φ at the samples s of window k of chain c: the file's phase at the
    window start plus ∫ω_m dt (trapezoid; exact on a linear ramp, as ω_m is)."""
    require_phase(sweep)
    t, omega_m = s["t"], s["omega_m"]
    t0 = float(sweep.t_begin[c, k])
    # From the window start to each sample: the first sample is at or just after t0.
    rel = np.concatenate([[0.0], np.cumsum(0.5 * (omega_m[1:] + omega_m[:-1]) * np.diff(t))])
    w0 = float(sweep.omega_begin[c, k])
    lead = 0.5 * (w0 + omega_m[0]) * (t[0] - t0)
    return float(sweep.phi_begin[c, k]) + lead + rel


def run_parameter(path, key):
    """A setting of a run file's configuration in force, e.g. 'model.drive_radius'."""
    from .reader import SweepFileError
    with open_h5(path) as f:
        g = f.get("resolved")
        if g is None:
            raise SweepFileError(path, "/resolved", "missing: the configuration in force (format 2 on); "
                                 "rerun it with this version of astrojax")
        values = resolved(g)
    if key not in values:
        raise SweepFileError(path, "/resolved", f"no setting {key}")
    return values[key]


def corotating(r, phi):
    """Positions in the frame turning with the motor: x' along the motor's rod, z unchanged."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * r[:, 0] + s * r[:, 1], -s * r[:, 0] + c * r[:, 1], r[:, 2]], axis=1)
