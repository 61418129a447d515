#!/usr/bin/python3
"""Least-squares fit of model parameters to the paper's thresholds, with the tie clutch.

Residuals r_k = (ω_k − paper_k) / paper_k for
  ω_rise = 12.63π   from rest: the first ramp of sweeps/paper_ramps.toml (up to 14π);
  ω1 = 4.80π, ω2 = 15.00π   from Table 1's orbit: sweeps/table1.toml's 60 s hold at 4π, then
                    its up-ramp, extended to --top (default 18π) so that an ω2 above 16π is
                    still measured;
  ω_fall = 3.24π    from Table 1's orbit: the same hold, then table1.toml's down-ramp started at
                    4π (run separately: an ω2 that ends in a fall would otherwise leave no
                    circular orbit for ω_fall to be measured from);
  ω_ball ≈ 4.8π     (--plateau) the mean ω_ball of the longest lagging-circular run on the
                    way up ("nearly constant", the paper); σ = --plateau-sigma.
With --protocol holds, ω1, ω2 and ω_fall come instead from one sweep held level by level,
sweeps/table1_staircase.toml (its grid dropped, one chain per evaluation, about 20 s of CPU):
the quasi-static thresholds, which ramps pass late (docs/reports/reproduction-evidence.md, "ω2 and the flower orbits").
The sweeps are temporary copies of the shipped files with segments dropped or extended
(the shipped files stay unchanged); each parameter vector is run through them with
`astrojax sweep -q --set ...`, at most --jobs (2) at a time, and read with
`astrojax thresholds --csv --sequence-csv`. ω2 (astrojax: a circular orbit giving way to a
flower) counts only where its bracket starts in a lagging-circular run of the up-ramp, the
paper's order (locked → lagging → flower).
σ_k = half the window spacing at the bracket / paper_k: the bracket's half-width divided by the
number of window steps it spans (1 + the windows inside it, not-settled ones that astrojax's
definitions let through), so a threshold smeared over unsettled windows weighs as much as a
clean one (--refine narrows brackets).
A threshold not reached adds --penalty² to χ² (a miss of --penalty σ), or, with
--missing exclude, is dropped and flagged; either way the report and the CSV name it.

Method. Each threshold is a bracket between 5–10 s windows, so ω_k(p) is piecewise constant
and a small finite-difference step sees zero or jumping derivatives. So:
  1. optional coarse scan (--scan N): N values across each parameter's bounds, one at a time
     through the start; the best point starts
  2. Nelder–Mead on χ² = Σ (r_k/σ_k)² in coordinates scaled to the bounds (derivative-free:
     plateaus and jumps do not stall it; at most --max-evals evaluations);
  3. at the optimum a central-difference Jacobian with steps of --step × |p_j| (doubled once,
     within the bounds, where no threshold moved by more than its bracket); where one of its
     points is better than the optimum, the fit moves there and takes the Jacobian again (at
     most --recentre times);
  4. covariance (JᵀWJ)⁺ with W = diag(1/σ²), in parameters scaled by |p_j|, through the SVD;
     directions whose σ exceeds 100 % of the parameters are reported as not constrained and
     left out of the pseudo-inverse; with more residuals than parameters the covariance is
     scaled by max(1, χ²/(m − n));
  5. at the optimum, the shipped paper_ramps.toml and table1.toml (with --protocol holds,
     table1_staircase.toml) with `astrojax thresholds --sequence`: is the paper's class
     sequence reproduced?

usage: /usr/bin/python3 analysis/fit_thresholds.py -o out/fit.md [--csv out/fit.csv]
       [--params drive_radius,tie_damping] [--param KEY=START[:LO:HI] ...] [--fixed KEY=VALUE ...]
       [--plateau] [--scan N] [--max-evals N] [--protocol ramps|holds]
"""
import concurrent.futures
import csv
import json
import math
import os
import sys
import tempfile
import tomllib

import numpy as np

import astrojax_analysis as ajx

HERE = os.path.dirname(os.path.abspath(__file__))
SWEEPS = os.path.join(HERE, "..", "sweeps")
PI = math.pi

# The paper's values [π rad/s]; the thresholds' names are astrojax's.
PAPER = {"omega_rise": 12.63, "omega_1": 4.80, "omega_2": 15.00, "omega_fall": 3.24, "plateau": 4.8}
SYMBOL = {"omega_rise": "ω_rise", "omega_1": "ω1", "omega_2": "ω2", "omega_fall": "ω_fall", "plateau": "ω_ball (lag)"}
THRESHOLDS = ("omega_rise", "omega_1", "omega_2", "omega_fall")

# [model] keys a fit may vary, with the range config.cpp and physics::validate allow:
# (lower bound, lower bound open?, upper bound, unit).
MODEL_KEYS = {
    "string_length": (0.0, True, 100.0, "m"), "bead_mass": (0.0, True, math.inf, "kg"),
    "ball_mass": (0.0, True, math.inf, "kg"), "drag": (0.0, False, math.inf, "kg/s"),
    "mu_static": (0.0, False, math.inf, ""), "mu_kinetic": (0.0, False, math.inf, ""),
    "gravity": (0.0, False, math.inf, "m/s²"), "drive_radius": (0.0, False, math.inf, "m"),
    "contact_distance": (0.0, True, math.inf, "m"), "top_stop": (0.0, False, math.inf, "m"),
    "tie_static_torque": (0.0, False, math.inf, "N m"), "tie_kinetic_torque": (0.0, False, math.inf, "N m"),
    "tie_inertia": (0.0, True, math.inf, "kg m²"), "tie_damping": (0.0, False, math.inf, "N m s"),
    "couple_torque": (0.0, False, math.inf, "N m"), "couple_slip_rate": (0.0, True, math.inf, "rad/s"),
}
# The set of docs/reports/reproduction-evidence.md, "One parameter set for the whole protocol";
# every evaluation sets all of these, then --fixed, then the fitted ones.
BASE = {"drive_radius": 0.015, "contact_distance": 0.035, "tie_static_torque": 1.5e-3,
        "tie_kinetic_torque": 1.35e-3, "tie_damping": 2e-6}
# Default parameter vector: start and bounds (the τ scan of docs/reports/reproduction-evidence.md; the lead's c_a runs).
DEFAULT_PARAMS = {
    "drive_radius": (0.015, 0.005, 0.02),
    "contact_distance": (0.035, 0.015, 0.05),
    "tie_static_torque": (1.5e-3, 8e-4, 2.5e-3),
    "tie_kinetic_torque": (1.35e-3, 5e-4, 2.5e-3),
    "tie_damping": (1e-5, 0.0, 3e-5),
}


# ---- parameters ------------------------------------------------------------------------

class Param:
    def __init__(self, key, start, lo, hi):
        self.key, self.start, self.lo, self.hi = key, start, lo, hi

    @property
    def unit(self):
        return MODEL_KEYS[self.key][3]


def parse_param(spec, option="--param"):
    """'key=start[:lo:hi]' -> Param; bounds default to DEFAULT_PARAMS' for its keys. Every
    error names the option and the allowed range."""
    key, eq, rest = spec.partition("=")
    key = key.strip().removeprefix("model.")
    if not eq or not rest:
        ajx.fail(f"{option} '{spec}': expected KEY=START or KEY=START:LO:HI")
    if key not in MODEL_KEYS:
        ajx.fail(f"{option} '{spec}': unknown model key '{key}'; allowed: {', '.join(MODEL_KEYS)}")
    parts = rest.split(":")
    if len(parts) not in (1, 3):
        ajx.fail(f"{option} '{spec}': expected KEY=START or KEY=START:LO:HI")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        ajx.fail(f"{option} '{spec}': START, LO and HI must be numbers")
    if len(values) == 1:
        if key not in DEFAULT_PARAMS:
            ajx.fail(f"{option} '{spec}': give bounds for {key} as {key}=START:LO:HI")
        values += DEFAULT_PARAMS[key][1:]
    start, lo, hi = values
    low, low_open, high, unit = MODEL_KEYS[key]
    allowed = f"{'(' if low_open else '['}{low:g}, {high:g}{']' if math.isfinite(high) else ')'} {unit}".rstrip()
    if not all(math.isfinite(v) for v in values):
        ajx.fail(f"{option} '{spec}': START, LO and HI must be finite")
    if lo > hi:
        ajx.fail(f"{option} '{spec}': lo = {lo:g} > hi = {hi:g}; give lo <= hi")
    if lo == hi:
        ajx.fail(f"{option} '{spec}': lo = hi = {lo:g} leaves nothing to fit; use --fixed {key}={lo:g}")
    for name, v in (("lo", lo), ("hi", hi)):
        if v < low or (low_open and v == low) or v > high:
            ajx.fail(f"{option} '{spec}': {name} = {v:g} outside the allowed range of model.{key}: {allowed}")
    if not lo <= start <= hi:
        ajx.fail(f"{option} '{spec}': start {start:g} outside its bounds [{lo:g}, {hi:g}]")
    return Param(key, start, lo, hi)


def parse_fixed(spec):
    key, eq, rest = spec.partition("=")
    key = key.strip().removeprefix("model.")
    if not eq:
        ajx.fail(f"--fixed '{spec}': expected KEY=VALUE")
    if key not in MODEL_KEYS:
        ajx.fail(f"--fixed '{spec}': unknown model key '{key}'; allowed: {', '.join(MODEL_KEYS)}")
    try:
        v = float(rest)
    except ValueError:
        ajx.fail(f"--fixed '{spec}': VALUE must be a number")
    low, low_open, high, unit = MODEL_KEYS[key]
    if not (v > low if low_open else v >= low) or v > high:
        ajx.fail(f"--fixed '{spec}': {v:g} outside the allowed range of model.{key}: "
                 f"{'(' if low_open else '['}{low:g}, {high:g}] {unit}")
    return key, v


def relation_issue(values):
    """The relations physics::validate checks between the keys a fit may move: a message, or
    None. 0 <= τ_k <= τ_s."""
    ts, tk = values.get("tie_static_torque"), values.get("tie_kinetic_torque")
    if ts is not None and tk is not None and tk > ts:
        return f"tie_kinetic_torque {tk:g} > tie_static_torque {ts:g} (allowed 0 <= τ_k <= τ_s)"
    return None


# ---- the fitting core (no astrojax) ------------------------------------------------------

def chi2_of(weighted):
    """χ² of weighted residuals r_k/σ_k (an array)."""
    return float(np.sum(np.square(weighted)))


def nelder_mead(f, x0, steps, lo, hi, max_evals, xtol=1e-3, ftol=1e-6):
    """Minimises f over the box [lo, hi] (points projected onto it), from x0 with an initial
    simplex of x0 + steps_j e_j (a step is reversed where it would leave the box). Stops after
    max_evals evaluations of f or when the simplex is smaller than xtol (in units of steps)
    and its values agree to ftol. Returns (best x, best f, number of evaluations)."""
    x0, steps, lo, hi = (np.asarray(v, float) for v in (x0, steps, lo, hi))
    n = len(x0)
    clip = lambda x: np.minimum(np.maximum(x, lo), hi)
    evals = 0

    def call(x):
        nonlocal evals
        evals += 1
        return f(x)

    simplex = [clip(x0)]
    for j in range(n):
        x = x0.copy()
        x[j] = x0[j] + steps[j] if x0[j] + steps[j] <= hi[j] else x0[j] - steps[j]
        simplex.append(clip(x))
    values = []
    for x in simplex:
        if evals >= max_evals:
            break
        values.append(call(x))
    if not values:  # max_evals = 0: no search
        return simplex[0], math.nan, 0
    if len(values) < n + 1:
        k = int(np.argmin(values))
        return simplex[k], values[k], evals
    scale = np.where(steps > 0, steps, 1.0)
    while evals < max_evals:
        order = np.argsort(values)
        simplex = [simplex[i] for i in order]
        values = [values[i] for i in order]
        size = max(np.max(np.abs((x - simplex[0]) / scale)) for x in simplex[1:])
        if size < xtol and values[-1] - values[0] <= ftol * max(1.0, abs(values[0])):
            break
        centroid = np.mean(simplex[:-1], axis=0)
        xr = clip(centroid + (centroid - simplex[-1]))
        fr = call(xr)
        if fr < values[0]:
            if evals >= max_evals:
                simplex[-1], values[-1] = xr, fr
                break
            xe = clip(centroid + 2.0 * (centroid - simplex[-1]))
            fe = call(xe)
            simplex[-1], values[-1] = (xe, fe) if fe < fr else (xr, fr)
        elif fr < values[-2]:
            simplex[-1], values[-1] = xr, fr
        else:
            if evals >= max_evals:
                break
            # contraction, outside or inside
            xc = clip(centroid + 0.5 * (xr - centroid)) if fr < values[-1] else clip(centroid + 0.5 * (simplex[-1] - centroid))
            fc = call(xc)
            if fc < min(fr, values[-1]):
                simplex[-1], values[-1] = xc, fc
            else:  # shrink towards the best point
                for i in range(1, n + 1):
                    if evals >= max_evals:
                        break
                    simplex[i] = clip(simplex[0] + 0.5 * (simplex[i] - simplex[0]))
                    values[i] = call(simplex[i])
    k = int(np.argmin(values))
    return simplex[k], values[k], evals


def derivative(w_plus, w_minus, w0, x_plus, x_minus, x0, resolution=np.nan):
    """A finite difference of one threshold: (slope, how).

    Central where both sides are reached, unless the two one-sided differences disagree by
    more than twice the resolution (a bracket width): the threshold jumps on one side, and
    the one-sided slope of smaller magnitude (the side without the jump) is taken. One side
    against the centre where only one side is reached; NaN where fewer than two points are."""
    if np.isfinite(w_plus) and np.isfinite(w_minus) and x_plus != x_minus:
        if np.isfinite(w0) and np.isfinite(resolution) and x_plus != x0 and x_minus != x0 \
                and abs((w_plus - w0) - (w0 - w_minus)) > 2.0 * resolution:
            fwd, bwd = (w_plus - w0) / (x_plus - x0), (w0 - w_minus) / (x0 - x_minus)
            return (fwd, "jump below: forward") if abs(fwd) <= abs(bwd) else (bwd, "jump above: backward")
        return (w_plus - w_minus) / (x_plus - x_minus), "central"
    if np.isfinite(w_plus) and np.isfinite(w0) and x_plus != x0:
        return (w_plus - w0) / (x_plus - x0), "forward"
    if np.isfinite(w_minus) and np.isfinite(w0) and x_minus != x0:
        return (w0 - w_minus) / (x0 - x_minus), "backward"
    return np.nan, "not reached"


def covariance(J, sigma, scale, chi2=None, max_rel_sigma=1.0):
    """Covariance of the parameters from the Jacobian of the relative residuals.

    J (m × n): ∂r_k/∂p_j; sigma (m): σ_k of r_k; scale (n): the parameters' scales s_j (|p_j|).
    In scaled parameters q_j = p_j/s_j, A = W^½ J S has SVD U Σ Vᵀ and (AᵀA)⁻¹ = V Σ⁻² Vᵀ.
    A direction v_i with 1/Σ_i > max_rel_sigma (a change of the parameters by more than
    max_rel_sigma of their own size moves χ² by less than 1) is not constrained: it is left
    out of the pseudo-inverse and returned. With chi2 and m > n the covariance is scaled by
    max(1, χ²/(m − n)). Returns (C in parameter units (n × n), [(1/Σ_i, v_i) unconstrained],
    singular values, the factor applied)."""
    J, sigma, scale = (np.asarray(v, float) for v in (J, sigma, scale))
    m, n = J.shape
    A = (J / sigma[:, None]) * scale[None, :]
    U, s, Vt = np.linalg.svd(A, full_matrices=True)
    s_all = np.zeros(n)
    s_all[:len(s)] = s
    s_all[s_all <= 1e-12 * max(s_all.max(), np.finfo(float).tiny)] = 0.0  # zero to rounding
    inv = np.zeros(n)
    loose = []
    for i in range(n):
        if s_all[i] > 0 and 1.0 / s_all[i] <= max_rel_sigma:
            inv[i] = 1.0 / s_all[i] ** 2
        else:
            loose.append((math.inf if s_all[i] == 0 else 1.0 / s_all[i], Vt[i]))
    Cq = (Vt.T * inv) @ Vt
    factor = 1.0
    if chi2 is not None and m > n:
        factor = max(1.0, chi2 / (m - n))
    C = factor * Cq * np.outer(scale, scale)
    return C, loose, s_all, factor


def direction_text(v, keys, tol=0.2):
    """'+0.71 τ_s −0.70 τ_k': a direction's components above tol (in scaled parameters)."""
    first = next((c for c in v if abs(c) >= tol), 1.0)
    v = v if first > 0 else -v  # the sign of a direction is arbitrary: its first term positive
    return " ".join(f"{c:+.2f} {k}" for c, k in zip(v, keys) if abs(c) >= tol)


# ---- sweep files: temporary copies of the shipped protocols ---------------------------

def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} as TOML")


def toml_dump(table, prefix=""):
    """A TOML text of nested dicts of scalars, arrays of scalars and arrays of tables (what
    the sweep files use)."""
    lines, subs = [], []
    for k, v in table.items():
        if isinstance(v, dict):
            subs.append((k, v, False))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            subs.append((k, v, True))
        else:
            lines.append(f"{k} = {toml_value(v)}")
    for k, v, is_array in subs:
        name = f"{prefix}.{k}" if prefix else k
        for t in (v if is_array else [v]):
            lines.append(f"\n[[{name}]]" if is_array else f"\n[{name}]")
            lines.append(toml_dump(t, name))
    return "\n".join(line for line in lines if line != "")


def load_toml(path, option):
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except OSError as e:
        ajx.fail(f"{option} {path}: cannot read: {e}")
    except tomllib.TOMLDecodeError as e:
        ajx.fail(f"{option} {path}: not TOML: {e}")


def segments(doc, path, option, kinds):
    segs = doc.get("protocol", {}).get("segment", [])
    got = [s.get("kind") for s in segs]
    if got[:len(kinds)] != list(kinds):
        ajx.fail(f"{option} {path}: protocol.segment kinds {got}, expected {list(kinds)} first "
                 f"(the shipped file's protocol)")
    return segs


def write_sweep(doc, name, work):
    """Writes the sweep document `doc` as work/name.toml; returns its path."""
    path = os.path.join(work, f"{name}.toml")
    with open(path, "w") as f:
        f.write(toml_dump(doc) + "\n")
    return path


def rise_file(paper_path, work):
    """'rise': paper_ramps.toml's first ramp, up from rest. Returns ({name: path}, {name: description})."""
    paper = load_toml(paper_path, "--paper-sweep")
    seg = segments(paper, paper_path, "--paper-sweep", ["ramp"])[0]
    if not seg["to"] > seg["from"]:
        ajx.fail(f"--paper-sweep {paper_path}: the first segment must ramp up (to > from)")
    paper["protocol"]["segment"] = [seg]
    return ({"rise": write_sweep(paper, "rise", work)},
            {"rise": f"{os.path.relpath(paper_path)}, its first ramp only: {seg['from'] / PI:g}π → {seg['to'] / PI:g}π "
                     f"at {seg['rate']} rad/s², {seg['window']} s windows"})


def ramp_files(table1_path, top, work):
    """--protocol ramps: 'up' (table1.toml's hold at 4π and its up-ramp, to `top` rad/s) and
    'down' (the same hold, then table1.toml's down-ramp from the hold's ω_m)."""
    t1 = load_toml(table1_path, "--table1-sweep")
    hold, up, down = segments(t1, table1_path, "--table1-sweep", ["steps", "ramp", "ramp"])[:3]
    if not (up["to"] > up["from"] and down["to"] < down["from"]):
        ajx.fail(f"--table1-sweep {table1_path}: expected a hold, a ramp up and a ramp down")
    if not top > up["from"]:
        ajx.fail(f"--top {top / PI:g}: must lie above the up-ramp's start, {up['from'] / PI:g}π")
    up_doc = json.loads(json.dumps(t1))
    up_doc["protocol"]["segment"] = [hold, dict(up, to=top)]
    down_doc = json.loads(json.dumps(t1))
    down_doc["protocol"]["segment"] = [hold, dict(down, **{"from": hold["to"]})]
    files = {"up": write_sweep(up_doc, "up", work), "down": write_sweep(down_doc, "down", work)}
    how = {
        "up": f"{os.path.relpath(table1_path)}, hold at {hold['from'] / PI:g}π ({hold['settle']} s), up to "
              f"{top / PI:g}π at {up['rate']} rad/s², {up['window']} s windows",
        "down": f"{os.path.relpath(table1_path)}, the same hold, then down {hold['to'] / PI:g}π → {down['to'] / PI:g}π "
                f"at {down['rate']} rad/s², {down['window']} s windows",
    }
    return files, how


def staircase_file(staircase_path, work):
    """--protocol holds: 'held', a copy of the staircase without its grid (the fitted values set
    each evaluation's one chain)."""
    doc = load_toml(staircase_path, "--staircase-sweep")
    n = len(doc.get("protocol", {}).get("segment", []))
    segs = segments(doc, staircase_path, "--staircase-sweep", ["steps"] * max(n, 2))
    if not any(s["to"] > s["from"] for s in segs) or not any(s["to"] < s["from"] for s in segs):
        ajx.fail(f"--staircase-sweep {staircase_path}: expected steps up and steps down")
    doc.pop("grid", None)
    levels = sum(int(s["num"]) for s in segs[1:])
    return ({"held": write_sweep(doc, "held", work)},
            {"held": f"{os.path.relpath(staircase_path)}: from Table 1's orbit at {segs[0]['from'] / PI:g}π, "
                     f"{levels} levels up and down, each held {segs[1]['settle']} s and measured {segs[1]['measure']} s"})


# ---- one evaluation: three sweeps, their thresholds ----------------------------------

def overrides(values, tie, extra=()):
    """--set arguments: the drive radius as the one grid value (the shipped files have a grid
    over R), every other key as model.KEY; `extra` are further KEY=VALUE settings (--set)."""
    out = ["--set", f"layers.tie={tie}"]
    for e in extra:
        out += ["--set", e]
    for k, v in values.items():
        out += ["--set", f"grid.drive_radius=[{v!r}]"] if k == "drive_radius" else ["--set", f"model.{k}={v!r}"]
    return out


def run_sweep(astrojax, scene, out, values, tie, refine, extra=()):
    """One sweep and its thresholds: (threshold rows, sequence rows, note). Exit code 3 (some
    tasks failed, the file written with their windows classed "failed", which astrojax
    thresholds skips) is kept, with astrojax's reason in the note; any other error stops."""
    proc = ajx.run_checked([astrojax, "sweep", scene, "-q", "-o", out, *overrides(values, tie, extra)], allowed=(0, 3))
    note = ""
    if proc.returncode == 3:
        why = " ".join((proc.stderr or proc.stdout).split())
        note = f"{os.path.splitext(os.path.basename(scene))[0]} sweep: some tasks failed ({why[:200]})"
    extra = ("--refine", str(refine)) if refine else ()
    rows, _ = ajx.run_thresholds(out, astrojax, extra)
    seq = ajx.run_sequence(out, astrojax)
    return rows, seq, note


def bracket(rows, name, seq=(), direction=1):
    """(mid, σ, lower window, half-width) [rad/s] of threshold `name` from astrojax's rows
    (chain 0), NaN if not reached. σ is the half-width divided by the number of window steps the
    bracket spans: 1 plus the windows of `seq`'s runs (leg `direction`) that lie inside it, which
    astrojax's definitions let through (not-settled windows before ω_fall, for example). So σ is
    half the window spacing whether or not the change of class was clean: a bracket widened by
    unsettled windows says the model's transition is not sharp, not that the value is unknown,
    and must not buy a small weight."""
    for r in rows:
        if r["threshold"] == name and int(r["chain"]) == 0:
            a, b = ajx.number(r["before_rad_s"]), ajx.number(r["after_rad_s"])
            return 0.5 * (a + b), 0.5 * abs(b - a) / (1 + windows_inside(seq, a, b, direction)), a, 0.5 * abs(b - a)
    return np.nan, np.nan, np.nan, np.nan


def windows_inside(seq, a, b, direction):
    """The windows of the runs of leg `direction` (chain 0) that lie strictly between ω_m = a and
    b, with a tolerance of 1e-9 rad/s: the windows a bracket [a, b] steps over."""
    lo, hi = min(a, b) + 1e-9, max(a, b) - 1e-9
    n = 0
    for r in seq:
        if r["kind"] != "run" or int(r.get("chain", 0) or 0) != 0 or int(r["direction"]) != direction:
            continue
        f, t = float(r["omega_from_rad_s"]), float(r["omega_to_rad_s"])
        if lo <= min(f, t) and max(f, t) <= hi:
            n += int(r["windows"])
    return n


def up_runs(seq, cls):
    return [r for r in seq if r["kind"] == "run" and r["direction"] == "1" and r["class"] == cls]


def measure(results, plateau_sigma):
    """{name: (value [rad/s], σ [rad/s], note, bracket half-width [rad/s])} from the three
    sweeps' rows (σ: see bracket); value NaN where not reached, with the reason in the note."""
    out = {}
    rise_rows, rise_seq = results["rise"][:2]
    up_rows, up_seq = results["up" if "up" in results else "held"][:2]
    down_rows, down_seq = results["down" if "down" in results else "held"][:2]
    for name, rows, seq, leg in (("omega_rise", rise_rows, rise_seq, 1), ("omega_1", up_rows, up_seq, 1),
                                 ("omega_fall", down_rows, down_seq, -1)):
        mid, sigma, _, hw = bracket(rows, name, seq, leg)
        out[name] = (mid, sigma, "" if np.isfinite(mid) else "not reached", hw)
    mid, sigma, before, hw = bracket(up_rows, "omega_2", up_seq, 1)
    lag = up_runs(up_seq, "lagging-circular")
    in_lag = [r for r in lag if float(r["omega_from_rad_s"]) - 1e-9 <= before <= float(r["omega_to_rad_s"]) + 1e-9]
    if np.isfinite(mid) and in_lag:
        out["omega_2"] = (mid, sigma, "", hw)
    elif not lag:
        out["omega_2"] = (np.nan, np.nan, "not reached: no lagging orbit on the way up", np.nan)
    else:
        top = max(float(r["omega_to_rad_s"]) for r in up_seq if r["kind"] == "run" and r["direction"] == "1")
        end = max(float(r["omega_to_rad_s"]) for r in lag)
        after = [r["class"] for r in up_seq if r["kind"] == "run" and r["direction"] == "1"
                 and float(r["omega_from_rad_s"]) >= end - 1e-9]
        out["omega_2"] = (np.nan, np.nan, f"not reached: the lag survives to the ramp's top, {top / PI:.2f}π"
                          if end >= top - 1e-9 else
                          f"not reached: the lag ends at {end / PI:.2f}π in {after[0] if after else '?'}, "
                          f"not in a flower", np.nan)
    if lag:
        longest = max(lag, key=lambda r: int(r["windows"]))
        out["plateau"] = (float(longest["omega_ball_mean_rad_s"]), plateau_sigma * PAPER["plateau"] * PI, "", np.nan)
    else:
        out["plateau"] = (np.nan, np.nan, "not reached: no lagging orbit on the way up", np.nan)
    return out


def residuals(meas, names, missing, penalty):
    """(weighted residuals r_k/σ_k, relative r_k, σ_k, flags) over `names`; a threshold not
    reached gives `penalty` (missing='penalty') or is dropped (missing='exclude')."""
    w, rel, sig, flags = [], [], [], []
    for k in names:
        value, sigma, note = meas[k][:3]
        paper = PAPER[k] * PI
        if np.isfinite(value):
            s = max(sigma, 1e-6 * paper) / paper
            rel.append((value - paper) / paper)
            sig.append(s)
            w.append(rel[-1] / s)
            flags.append("")
        elif missing == "penalty":
            rel.append(np.nan)
            sig.append(np.nan)
            w.append(penalty)
            flags.append(f"{note}: penalty {penalty:g} σ")
        else:
            flags.append(f"{note}: excluded")
    return np.array(w), np.array(rel), np.array(sig), flags


class Evaluator:
    """Runs parameter vectors through the three sweeps (cached; --jobs sweeps at a time) and
    records every evaluation for the CSV."""

    def __init__(self, args, params, fixed, files, work):
        self.args, self.params, self.fixed, self.files, self.work = args, params, fixed, files, work
        self.names = list(THRESHOLDS) + (["plateau"] if args.plateau else [])
        self.cache, self.log, self.count = {}, [], 0

    def values(self, x):
        v = dict(BASE)
        v.update(self.fixed)
        v.update({p.key: float(xi) for p, xi in zip(self.params, x)})
        return v

    def many(self, xs, phase):
        """Evaluates the points xs (sweeps of all of them in one pool); returns their records."""
        keys = [tuple(float(v) for v in x) for x in xs]
        todo = []
        for key in keys:
            if key not in self.cache and key not in todo:
                todo.append(key)
        jobs = []
        for key in todo:
            values = self.values(key)
            issue = relation_issue(values)
            if issue:
                self.cache[key] = self.record(key, values, None, phase, issue)
                continue
            self.count += 1
            for name in self.files:
                jobs.append((key, values, name, os.path.join(self.work, f"e{self.count}_{name}.h5")))
        results = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=self.args.jobs) as pool:
            futures = {pool.submit(run_sweep, self.args.astrojax_exe, self.files[name], out, values, self.args.tie,
                                   self.args.refine, self.args.set): (key, name, out) for key, values, name, out in jobs}
            for fut in futures:
                key, name, out = futures[fut]
                results.setdefault(key, {})[name] = fut.result()
                os.remove(out)
        for key in todo:
            if key in results:
                self.cache[key] = self.record(key, self.values(key), results[key], phase, None)
        return [self.cache[k] for k in keys]

    def record(self, key, values, results, phase, issue):
        if results is None:
            meas = {k: (np.nan, np.nan, f"infeasible: {issue}", np.nan) for k in self.names}
        else:
            meas = measure(results, self.args.plateau_sigma)
        w, rel, sig, flags = residuals(meas, self.names, self.args.missing, self.args.penalty)
        chi2 = chi2_of(w) if results is not None else self.args.penalty ** 2 * len(self.names)
        rec = dict(index=len(self.log), phase=phase, x=np.array(key), values=values, meas=meas, chi2=chi2,
                   flags=[f for f in flags if f] + [r[2] for r in (results or {}).values() if r[2]], issue=issue)
        self.log.append(rec)
        line = " ".join(f"{p.key}={xi:.4g}" for p, xi in zip(self.params, key))
        got = " ".join(f"{SYMBOL[k]}={meas[k][0] / PI:.2f}π" if np.isfinite(meas[k][0]) else f"{SYMBOL[k]}=—"
                       for k in self.names)
        print(f"[{rec['index']:3d} {phase}] {line}: {got}  χ²={chi2:.4g}", file=sys.stderr, flush=True)
        return rec

    def chi2(self, x):
        return self.many([x], "simplex")[0]["chi2"]


# ---- the fit --------------------------------------------------------------------------

def coarse_scan(ev, params, x0, n):
    """N values across each parameter's bounds, one parameter at a time through x0."""
    pts = []
    for j, p in enumerate(params):
        for v in np.linspace(p.lo, p.hi, n):
            x = np.array(x0, float)
            x[j] = v
            pts.append(x)
    recs = ev.many(pts, "scan")
    return min(recs + ev.many([x0], "start"), key=lambda r: r["chi2"])["x"]


def jacobian(ev, params, x, step):
    """∂ω_k/∂p_j [rad/s per unit] by finite differences at x (see derivative()), steps
    step·|p_j| (step·range at p_j = 0) within the bounds. Where no threshold moved by more than
    its bracket width, the step is doubled once; an entry of the doubled step replaces the
    first only where the first was at the resolution or not reached. Returns (D (m × n),
    how (m × n), steps used (n), centre record)."""
    centre = ev.many([x], "optimum")[0]
    names = ev.names
    h0 = np.array([step * (abs(xi) if xi != 0 else p.hi - p.lo) for xi, p in zip(x, params)])
    h = h0.copy()
    D = np.full((len(names), len(params)), np.nan)
    how = [["" for _ in params] for _ in names]
    redo = [True] * len(params)
    for attempt in range(2):
        pts = []
        for j, p in enumerate(params):
            if redo[j]:
                xp, xm = np.array(x, float), np.array(x, float)
                xp[j], xm[j] = min(x[j] + h[j], p.hi), max(x[j] - h[j], p.lo)
                pts.append((j, xp, xm))
        recs = ev.many([q for _, a, b in pts for q in (a, b)], "jacobian")
        for i, (j, xp, xm) in enumerate(pts):
            rp, rm = recs[2 * i], recs[2 * i + 1]
            moved = False
            for k, name in enumerate(names):
                wp, wm, w0 = rp["meas"][name][0], rm["meas"][name][0], centre["meas"][name][0]
                widths = [rp["meas"][name][1], rm["meas"][name][1], centre["meas"][name][1]]
                res = 2.0 * np.nanmax(widths) if np.any(np.isfinite(widths)) else np.nan
                d, hw = derivative(wp, wm, w0, xp[j], xm[j], x[j], res)
                span = abs(d * (xp[j] - xm[j])) if hw == "central" else abs(d * h[j])
                if np.isfinite(d) and np.isfinite(res) and span <= res:
                    hw += ", within a bracket"
                elif np.isfinite(d):
                    moved = True
                if attempt == 0 or not np.isfinite(D[k, j]) or ("within a bracket" in how[k][j] and np.isfinite(d)):
                    D[k, j], how[k][j] = d, hw + (" (h doubled)" if attempt == 1 else "")
            redo[j] = not moved
        if attempt == 1 or not any(redo):
            break
        h = np.where(redo, 2 * h0, h0)
    return D, how, h, centre


def report(args, params, ev, best, D, how, h, cov, loose, tight, factor, sv, finals, describe, elapsed):
    names = ev.names
    keys = [p.key for p in params]
    meas = best["meas"]
    w, rel, sig, flags = residuals(meas, names, args.missing, args.penalty)
    L = ["# Threshold fit with the tie clutch", ""]
    L.append(f"Command: `{' '.join(['/usr/bin/python3', 'analysis/fit_thresholds.py'] + args.argv)}`  ")
    L.append(f"{len(ev.log)} evaluations ({ev.count} ran: 3 sweeps each, {args.jobs} at a time), "
             f"{elapsed:.0f} s wall; Nelder–Mead stopped after {args.nm_evals} of --max-evals {args.max_evals}; "
             f"moved {args.recentred} time(s) to a better Jacobian point (--recentre {args.recentre}).")
    L += ["", "Sweeps of each evaluation (temporary copies; the shipped files are unchanged):", ""]
    L += [f"- {k}: {v}" for k, v in describe.items()]
    fixed = {k: v for k, v in best["values"].items() if k not in keys}
    L += ["", f"Held fixed: layers.tie = {args.tie}" + "".join(f", {k} = {v:g}" for k, v in fixed.items()) + ".", ""]
    L += ["## Best parameters", "",
          "| parameter | start | bounds | best | σ | σ / best | constrained |", "|---|---|---|---|---|---|---|"]
    for j, p in enumerate(params):
        s = math.sqrt(cov[j, j]) if cov is not None and cov[j, j] > 0 else math.nan
        weight = max((abs(v[j]) for _, v in loose), default=0.0)
        constrained = "no (in an unconstrained direction)" if weight >= 0.3 else "yes"
        xj = best["x"][j]
        if weight >= 0.3:
            s = math.nan  # the pseudo-inverse's σ of a parameter in a free direction means nothing
        s_text = "—" if not np.isfinite(s) else f"{s:.2g}"
        r_text = "—" if not (np.isfinite(s) and xj) else f"{100 * s / abs(xj):.1f} %"
        L.append(f"| {p.key} [{p.unit}] | {p.start:.4g} | {p.lo:.4g}–{p.hi:.4g} | {xj:.4g} | {s_text} | {r_text} "
                 f"| {constrained} |")
    m_used = int(np.sum([not f for f in flags]))
    L += ["", f"χ² = {best['chi2']:.4g} over {len(names)} residuals ({m_used} reached), {len(params)} parameters; "
          + (f"covariance scaled by {factor:.3g} = max(1, χ²/(m − n))." if factor != 1.0 or m_used > len(params)
             else "no more residuals than parameters: the covariance is not scaled by χ²."),
          "σ: (JᵀWJ)⁺ over the constrained directions, W = diag(1/σ_k²) with σ_k half the window spacing at each bracket.", ""]
    failed = [r for r in ev.log if any("some tasks failed" in f for f in r["flags"])]
    L += [f"Evaluations with failed tasks (astrojax sweep exit code 3; their windows are skipped by "
          f"`astrojax thresholds`): {len(failed)} of {len(ev.log)}"
          + (f", indices {', '.join(str(r['index']) for r in failed)} (reasons in the CSV's flags)" if failed else "")
          + ("; the best point is one of them." if best in failed else "."), ""]
    L += ["## Thresholds at the best parameters", "",
          "| threshold | this model [π rad/s] | bracket half-width [π] | paper [π] | relative error | σ_k | note |",
          "|---|---|---|---|---|---|---|"]
    i_used = 0
    for k, name in enumerate(names):
        value, _, note, hw = meas[name]
        if np.isfinite(value):
            hw_text = f"{hw / PI:.3f}" if np.isfinite(hw) else "—"  # the plateau is no bracket
            L.append(f"| {SYMBOL[name]} | {value / PI:.3f} | {hw_text} | {PAPER[name]:.2f} | "
                     f"{100 * rel[i_used]:+.1f} % | {100 * sig[i_used]:.1f} % | |")
            i_used += 1
        else:
            i_used += 1 if args.missing == "penalty" else 0
            L.append(f"| {SYMBOL[name]} | — | — | {PAPER[name]:.2f} | — | — | {note} |")
    L += ["", "## Sensitivities at the best parameters", "",
          "∂ω_k/∂p_j in π rad/s per unit of p_j, from ±h_j (central differences; one-sided where a side is "
          "not reached); in brackets the change of ω_k in % for a 10 % change of p_j. \"within a bracket\": "
          "the threshold moved by no more than one window step (2 σ_k) over the step, so the slope is at the "
          "resolution (it may be 0 or one bracket's jump).", ""]
    L.append("| threshold | " + " | ".join(f"{k} (h = {hj:.3g} {p.unit})" for k, hj, p in zip(keys, h, params)) + " |")
    L.append("|---|" + "---|" * len(keys))
    for k, name in enumerate(names):
        cells = []
        value = meas[name][0]
        for j in range(len(keys)):
            d = D[k, j]
            if not np.isfinite(d):
                cells.append(f"— ({how[k][j]})")
                continue
            pct = 100 * d * 0.1 * best["x"][j] / value if np.isfinite(value) and value else math.nan
            note = (" ⁽ʳ⁾" if "within a bracket" in how[k][j] else "") + (" ⁽ʲ⁾" if "jump" in how[k][j] else "") \
                + (" ⁽ᶠ⁾" if how[k][j].startswith(("forward", "backward")) else "")
            cells.append(f"{d / PI:.4g} ({pct:+.2f} %){note}")
        L.append(f"| {SYMBOL[name]} | " + " | ".join(cells) + " |")
    L += ["", "⁽ʳ⁾ within a bracket (at the resolution). ⁽ʲ⁾ the threshold jumps on one side (the one-sided "
          "differences disagree by more than two bracket widths): the slope of the other side. ⁽ᶠ⁾ one side not "
          "reached (or not allowed): one-sided. The covariance uses these slopes.", "",
          "## What the thresholds do not constrain", ""]
    L.append("Singular values of W^½ J S (parameters scaled by |p_j|): "
             + ", ".join(f"{s:.3g}" for s in sv) + ". A direction with 1/s > 1 (a change of the parameters by "
             "their own size moves χ² by less than 1) is not constrained:")
    L.append("")
    if loose:
        for inv_s, v in loose:
            L.append(f"- {direction_text(v, keys)} (σ along it: "
                     f"{'∞' if not math.isfinite(inv_s) else f'{100 * inv_s:.0f} %'} of the parameters)")
    else:
        L.append("- none: every direction is constrained to better than 100 %.")
    L += ["", "Constrained combinations (σ along each, as a fraction of the parameters):", ""]
    L += [f"- {direction_text(v, keys)}: {100 * inv_s:.2g} %" for inv_s, v in tight] or ["- none"]
    L += ["", "## Class sequence at the best parameters (the shipped files, unchanged protocols)", ""]
    for label, (cmd, text, steps) in finals.items():
        L += [f"`{cmd}`", "", "| step | status | at ω_m [π rad/s] | what |", "|---|---|---|---|"]
        for r in steps:
            at = ajx.number(r["omega_from_rad_s"])
            L.append(f"| {r['step']} | {r['status']} | {'' if not np.isfinite(at) else f'{at / PI:.3f}'} | "
                     f"{r['step_description']} |")
        L += ["", "```", text.rstrip(), "```", ""]
    return "\n".join(L) + "\n"


def final_check(args, values, work):
    """The shipped paper_ramps.toml and table1.toml at `values`: {label: (command, astrojax
    thresholds --sequence output, step rows)}."""
    out = {}
    second = ("table1_staircase", args.staircase_sweep) if args.protocol == "holds" else ("table1", args.table1_sweep)
    for label, path in (("paper", args.paper_sweep), second):
        h5 = os.path.join(work, f"final_{label}.h5")
        sets = overrides(values, args.tie, args.set)
        if label == "table1_staircase":  # its grid runs c_a: one chain at the fitted value
            sets += ["--set", f"grid.tie_damping=[{values['tie_damping']!r}]"]
        ajx.run_checked([args.astrojax_exe, "sweep", path, "-q", "-o", h5, *sets])
        text = ajx.run_checked([args.astrojax_exe, "thresholds", h5, "--no-hold", "--sequence"]).stdout
        steps = [r for r in ajx.run_sequence(h5, args.astrojax_exe) if r["kind"] == "step"]
        cmd = "build/astrojax sweep " + os.path.relpath(path) + " -o OUT " + " ".join(
            f'"{s}"' if i % 2 else s for i, s in enumerate(sets)) + "; build/astrojax thresholds OUT --sequence"
        out[label] = (cmd, text, steps)
    return out


def write_csv(path, ev):
    names = ev.names
    keys = [p.key for p in ev.params]
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["index", "phase", *keys, *(f"{n}_rad_s" for n in names), *(f"{n}_half_width_rad_s" for n in names),
                    *(f"{n}_sigma_rad_s" for n in names), "chi2", "flags"])
        for r in ev.log:
            w.writerow([r["index"], r["phase"], *(f"{v:.9g}" for v in r["x"]),
                        *("" if not np.isfinite(r["meas"][n][0]) else f"{r['meas'][n][0]:.9g}" for n in names),
                        *("" if not np.isfinite(r["meas"][n][3]) else f"{r['meas'][n][3]:.9g}" for n in names),
                        *("" if not np.isfinite(r["meas"][n][1]) else f"{r['meas'][n][1]:.9g}" for n in names),
                        f"{r['chi2']:.9g}", "; ".join(r["flags"] + ([r["issue"]] if r["issue"] else []))])
    print(f"wrote {path}")


def parse_args(argv):
    ap = ajx.parser(__doc__)
    ap.add_argument("-o", "--output", required=True, help="the Markdown report (.md)")
    ap.add_argument("--csv", help="every evaluation as CSV")
    ap.add_argument("--params", default=",".join(DEFAULT_PARAMS),
                    help=f"which of the default parameters to fit, comma-separated (default: all: "
                         f"{', '.join(f'{k}={s:g}:{lo:g}:{hi:g}' for k, (s, lo, hi) in DEFAULT_PARAMS.items())})")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=START[:LO:HI]",
                    help="a parameter to fit (a [model] key), in place of its --params default; repeatable")
    ap.add_argument("--fixed", action="append", default=[], metavar="KEY=VALUE",
                    help="a [model] key held at VALUE (default: " + ", ".join(f"{k}={v:g}" for k, v in BASE.items())
                         + " for the keys not fitted)")
    ap.add_argument("--tie", default="clutch", choices=("clutch", "rigid"), help="layers.tie (default clutch)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a further setting passed to every sweep as astrojax --set, e.g. "
                         "layers.pair_couple=motor_clutch; repeatable")
    ap.add_argument("--plateau", action="store_true", help="also fit the lag's mean ω_ball to the paper's ≈ 4.8π")
    ap.add_argument("--plateau-sigma", type=float, default=0.02,
                    help="relative σ of the paper's ω_ball ≈ 4.8π (default 0.02: ±0.1π)")
    ap.add_argument("--missing", choices=("penalty", "exclude"), default="penalty",
                    help="a threshold not reached: a residual of --penalty σ (default), or excluded and flagged")
    ap.add_argument("--penalty", type=float, default=100.0, help="residual of a threshold not reached, in σ (default 100)")
    ap.add_argument("--scan", type=int, default=0, metavar="N",
                    help="coarse scan first: N values across each parameter's bounds (default 0: none)")
    ap.add_argument("--max-evals", type=int, default=40, help="Nelder–Mead's evaluations at most (default 40)")
    ap.add_argument("--simplex", type=float, default=0.15,
                    help="initial simplex step as a fraction of each parameter's bounds (default 0.15)")
    ap.add_argument("--recentre", type=int, default=3, metavar="N",
                    help="at most N times, move to a Jacobian point better than the optimum and take the "
                         "Jacobian again (default 3)")
    ap.add_argument("--step", type=float, default=0.1,
                    help="Jacobian step as a fraction of |p_j| (default 0.1; doubled once where nothing moves)")
    ap.add_argument("--top", type=float, default=18.0, help="top of the up-ramp from Table 1's orbit [π rad/s] (default 18)")
    ap.add_argument("--jobs", type=int, default=2, help="sweeps run at a time (default 2)")
    ap.add_argument("--refine", type=int, default=0, metavar="F",
                    help="refine every bracket F times slower (`astrojax thresholds --refine F`; default off)")
    ap.add_argument("--paper-sweep", default=os.path.join(SWEEPS, "paper_ramps.toml"), help="default sweeps/paper_ramps.toml")
    ap.add_argument("--table1-sweep", default=os.path.join(SWEEPS, "table1.toml"), help="default sweeps/table1.toml")
    ap.add_argument("--protocol", choices=("ramps", "holds"), default="ramps",
                    help="ω1, ω2, ω_fall from the ramps of table1.toml (default) or from the levels held in "
                         "--staircase-sweep")
    ap.add_argument("--staircase-sweep", default=os.path.join(SWEEPS, "table1_staircase.toml"),
                    help="default sweeps/table1_staircase.toml")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable (default: build/astrojax)")
    args = ap.parse_args(argv)
    args.argv = list(argv if argv is not None else sys.argv[1:])
    checks = [("--max-evals", args.max_evals, 0, 10000), ("--jobs", args.jobs, 1, 64), ("--scan", args.scan, 0, 50),
              ("--recentre", args.recentre, 0, 20),
              ("--refine", args.refine, 0, 1000)]
    for name, v, lo, hi in checks:
        if not lo <= v <= hi:
            ajx.fail(f"{name} {v}: allowed {lo}..{hi}")
    if args.scan == 1:
        ajx.fail("--scan 1: a scan needs N >= 2 values (or 0: no scan)")
    for name, v, lo, hi in (("--plateau-sigma", args.plateau_sigma, 0, 1), ("--step", args.step, 0, 1),
                            ("--simplex", args.simplex, 0, 1), ("--penalty", args.penalty, 0, 1e6)):
        if not (lo < v <= hi):
            ajx.fail(f"{name} {v:g}: allowed ({lo:g}, {hi:g}]")
    if not 4.0 < args.top <= 40.0:
        ajx.fail(f"--top {args.top:g}: allowed (4, 40] π rad/s")
    chosen = [k.strip() for k in args.params.split(",") if k.strip()] if args.params else []
    for k in chosen:
        if k not in DEFAULT_PARAMS:
            ajx.fail(f"--params: unknown '{k}'; allowed: {', '.join(DEFAULT_PARAMS)} (others with --param KEY=START:LO:HI)")
    given = [parse_param(s) for s in args.param]
    by_key = {p.key: p for p in given}
    params = [by_key.pop(k) if k in by_key else Param(k, *DEFAULT_PARAMS[k]) for k in chosen] + list(by_key.values())
    if len({p.key for p in params}) != len(params):
        ajx.fail("--param: a key is given twice")
    if not params:
        ajx.fail("--params: nothing to fit")
    fixed = dict(parse_fixed(s) for s in args.fixed)
    both = sorted(set(fixed) & {p.key for p in params})
    if both:
        ajx.fail(f"--fixed {', '.join(both)}: also fitted (--params/--param); give each key one role")
    start = dict(BASE, **fixed, **{p.key: p.start for p in params})
    issue = relation_issue(start)
    if issue:
        ajx.fail(f"--param/--fixed: the start point is not allowed: {issue}")
    for name in ("paper_sweep", "table1_sweep", "staircase_sweep"):
        if not os.path.isfile(getattr(args, name)):
            ajx.fail(f"--{name.replace('_', '-')} {getattr(args, name)}: no such file")
    return args, params, fixed


def main(argv=None):
    import time
    args, params, fixed = parse_args(argv)
    args.astrojax_exe = ajx.require_astrojax(args.astrojax)
    t0 = time.time()
    with tempfile.TemporaryDirectory() as work:
        files, describe = rise_file(args.paper_sweep, work)
        second = (staircase_file(args.staircase_sweep, work) if args.protocol == "holds"
                  else ramp_files(args.table1_sweep, args.top * PI, work))
        files.update(second[0])
        describe.update(second[1])
        ev = Evaluator(args, params, fixed, files, work)
        x0 = np.array([p.start for p in params])
        first = ev.many([x0], "start")[0]
        if first["issue"]:
            ajx.fail(f"the start point: {first['issue']}")
        if args.scan:
            x0 = coarse_scan(ev, params, x0, args.scan)
        lo, hi = np.array([p.lo for p in params]), np.array([p.hi for p in params])
        x_best, _, args.nm_evals = nelder_mead(ev.chi2, x0, args.simplex * (hi - lo), lo, hi, args.max_evals)
        best = min(ev.log, key=lambda r: r["chi2"])  # the best point evaluated at all (scan included)
        D, how, h, centre = jacobian(ev, params, best["x"], args.step)
        args.recentred = 0
        for _ in range(args.recentre):  # a Jacobian point better than the optimum becomes the optimum
            better = min(ev.log, key=lambda r: r["chi2"])
            if better["chi2"] >= best["chi2"]:
                break
            best, args.recentred = better, args.recentred + 1
            D, how, h, centre = jacobian(ev, params, best["x"], args.step)
        w, rel, sig, flags = residuals(centre["meas"], ev.names, args.missing, args.penalty)
        reached = [k for k, n in enumerate(ev.names) if np.isfinite(centre["meas"][n][0])
                   and np.all(np.isfinite(D[k]))]
        scale = np.array([abs(v) if v else (p.hi - p.lo) for v, p in zip(best["x"], params)])
        if reached:
            Jrel = np.array([D[k] / (PAPER[ev.names[k]] * PI) for k in reached])
            srel = np.array([max(centre["meas"][ev.names[k]][1], 1e-6) / (PAPER[ev.names[k]] * PI) for k in reached])
            chi2 = float(np.sum(((np.array([centre["meas"][ev.names[k]][0] for k in reached]) /
                                  (np.array([PAPER[ev.names[k]] for k in reached]) * PI) - 1) / srel) ** 2))
            cov, loose, sv, factor = covariance(Jrel, srel, scale, chi2)
            _, _, Vt = np.linalg.svd((Jrel / srel[:, None]) * scale[None, :], full_matrices=True)
            tight = [(1.0 / sv[i], Vt[i]) for i in range(len(params)) if sv[i] > 0 and 1.0 / sv[i] <= 1.0]
        else:
            cov, loose, sv, factor = None, [(math.inf, row) for row in np.eye(len(params))], np.zeros(len(params)), 1.0
            tight = []
        finals = final_check(args, best["values"], work)
    text = report(args, params, ev, best, D, how, h, cov, loose, tight, factor, sv, finals, describe, time.time() - t0)
    ajx.write_report(args.output, text)
    if args.csv:
        write_csv(args.csv, ev)


if __name__ == "__main__":
    main()
