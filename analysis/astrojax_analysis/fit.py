"""The threshold fit's core (analysis/fit_thresholds.py is its command line; out_of_sample.py
uses it too): the paper's values, the parameters a fit may vary, the temporary sweeps, one
evaluation (astrojax sweep + astrojax thresholds), the residuals, the Jacobian and the
covariance. The minimiser is SciPy's Nelder–Mead (optimize.nelder_mead)."""
import concurrent.futures
import json
import math
import os
import sys
import tomllib

import numpy as np

from .errors import fail
from .optimize import nelder_mead  # noqa: F401  (the fit's minimiser, re-exported)
from .paths import SWEEPS  # noqa: F401  (the shipped sweeps, for the scripts)
from .thresholds import number, run_checked, run_sequence, run_thresholds  # noqa: F401

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
        fail(f"{option} '{spec}': expected KEY=START or KEY=START:LO:HI")
    if key not in MODEL_KEYS:
        fail(f"{option} '{spec}': unknown model key '{key}'; allowed: {', '.join(MODEL_KEYS)}")
    parts = rest.split(":")
    if len(parts) not in (1, 3):
        fail(f"{option} '{spec}': expected KEY=START or KEY=START:LO:HI")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        fail(f"{option} '{spec}': START, LO and HI must be numbers")
    if len(values) == 1:
        if key not in DEFAULT_PARAMS:
            fail(f"{option} '{spec}': give bounds for {key} as {key}=START:LO:HI")
        values += DEFAULT_PARAMS[key][1:]
    start, lo, hi = values
    low, low_open, high, unit = MODEL_KEYS[key]
    allowed = f"{'(' if low_open else '['}{low:g}, {high:g}{']' if math.isfinite(high) else ')'} {unit}".rstrip()
    if not all(math.isfinite(v) for v in values):
        fail(f"{option} '{spec}': START, LO and HI must be finite")
    if lo > hi:
        fail(f"{option} '{spec}': lo = {lo:g} > hi = {hi:g}; give lo <= hi")
    if lo == hi:
        fail(f"{option} '{spec}': lo = hi = {lo:g} leaves nothing to fit; use --fixed {key}={lo:g}")
    for name, v in (("lo", lo), ("hi", hi)):
        if v < low or (low_open and v == low) or v > high:
            fail(f"{option} '{spec}': {name} = {v:g} outside the allowed range of model.{key}: {allowed}")
    if not lo <= start <= hi:
        fail(f"{option} '{spec}': start {start:g} outside its bounds [{lo:g}, {hi:g}]")
    return Param(key, start, lo, hi)


def parse_fixed(spec):
    key, eq, rest = spec.partition("=")
    key = key.strip().removeprefix("model.")
    if not eq:
        fail(f"--fixed '{spec}': expected KEY=VALUE")
    if key not in MODEL_KEYS:
        fail(f"--fixed '{spec}': unknown model key '{key}'; allowed: {', '.join(MODEL_KEYS)}")
    try:
        v = float(rest)
    except ValueError:
        fail(f"--fixed '{spec}': VALUE must be a number")
    low, low_open, high, unit = MODEL_KEYS[key]
    if not (v > low if low_open else v >= low) or v > high:
        fail(f"--fixed '{spec}': {v:g} outside the allowed range of model.{key}: "
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
        fail(f"{option} {path}: cannot read: {e}")
    except tomllib.TOMLDecodeError as e:
        fail(f"{option} {path}: not TOML: {e}")


def segments(doc, path, option, kinds):
    segs = doc.get("protocol", {}).get("segment", [])
    got = [s.get("kind") for s in segs]
    if got[:len(kinds)] != list(kinds):
        fail(f"{option} {path}: protocol.segment kinds {got}, expected {list(kinds)} first "
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
        fail(f"--paper-sweep {paper_path}: the first segment must ramp up (to > from)")
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
        fail(f"--table1-sweep {table1_path}: expected a hold, a ramp up and a ramp down")
    if not top > up["from"]:
        fail(f"--top {top / PI:g}: must lie above the up-ramp's start, {up['from'] / PI:g}π")
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
        fail(f"--staircase-sweep {staircase_path}: expected steps up and steps down")
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
    proc = run_checked([astrojax, "sweep", scene, "-q", "-o", out, *overrides(values, tie, extra)], allowed=(0, 3))
    note = ""
    if proc.returncode == 3:
        why = " ".join((proc.stderr or proc.stdout).split())
        note = f"{os.path.splitext(os.path.basename(scene))[0]} sweep: some tasks failed ({why[:200]})"
    extra = ("--refine", str(refine)) if refine else ()
    rows, _ = run_thresholds(out, astrojax, extra)
    seq = run_sequence(out, astrojax)
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
            a, b = number(r["before_rad_s"]), number(r["after_rad_s"])
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


