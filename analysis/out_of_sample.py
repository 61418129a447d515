#!/usr/bin/python3
"""Out-of-sample test of the model variants: fitted on the four thresholds only, then asked
for the paper's other observations without refitting.

Variants (each a row of the reproduction report's hypothesis table):
  rigid   the paper's physics, rigid tie: fits R, d;
  clutch  the tie clutch: fits R, d, τ_s, τ_k, c_a;
  couple  the rigid tie with the pair couple (layers.pair_couple = "motor_clutch"): fits R, d, τ_c,
          with Ω_ε held at 1 rad/s (the slip on the lag, ≈ 8π rad/s, saturates its tanh).
Fit. analysis/fit_thresholds.py's evaluation and Nelder–Mead, --protocol holds: ω_rise from the
first ramp of sweeps/paper_ramps.toml, ω1, ω2, ω_fall from sweeps/table1_staircase.toml held
level by level (one chain), ω_fall from Table 1's orbit held straight down (paper.toml's fall
group) where the staircase's down leg has no circular orbit left to fall from; J = Σ ((ω_k −
paper_k)/paper_k)² over the four thresholds only (analysis/calibrate.py's score), a threshold not
reached counted as a relative miss of --penalty. Cost bounded: start at the
documented set (sweeps/paper.toml), then at most --max-evals evaluations (about 30 s each for
the clutch, less for the rigid tie on 1 core), no Jacobian; the report says how many ran.
Predictions at the best point, nothing refitted, each from the staircase held at that point:
  lag      the mean ω_ball of the longest lagging run on the way up (paper ≈ 4.8π) and the drop
           at ω1: ω_ball of the first lagging level minus that of the last locked level (paper 0);
  orbits   the bead's and the ball's radius at 4.8π and 15π (paper: the same orbit at both, Table
           1's circular orbit: bead 14.4 cm, ball 11.9 cm from the axis);
  flower   the bead's and the ball's mean radius over the flower levels (Table 1's flower
           starts: bead ≈ 4 cm, ball ≈ 24 cm);
  mass     m1 = m2 = 0.1 kg: the class and ω_ball at 4.8π and 15π (paper: unchanged orbits,
           locked at 4.8π, lagging at ω_ball = 4.8π at 15π);
  length   l = 0.662 m, started on the locked orbit of the shorter string (start_seed =
           "locked_orbit" at 4π; Table 1's start scaled by l/0.826 does not lock): the same.

usage: /usr/bin/python3 analysis/out_of_sample.py -o out/out_of_sample.md [--variants rigid,clutch,couple]
       [--max-evals N] [--penalty P] [--keep DIR]
"""
import argparse
import math
import os
import sys
import tempfile
import time

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis import fit as ft

PI = math.pi
DOCUMENTED = dict(ft.BASE)  # sweeps/paper.toml's clutch: R 15 mm, d 3.5 cm, τ_s, τ_k, c_a
VARIANTS = {
    "rigid": dict(label="paper's physics, rigid tie", tie="rigid", set=[],
                  params=["drive_radius", "contact_distance"]),
    "clutch": dict(label="tie clutch", tie="clutch", set=[],
                   params=["drive_radius", "contact_distance", "tie_static_torque", "tie_kinetic_torque",
                           "tie_damping"]),
    "couple": dict(label="pair couple (rigid tie)", tie="rigid",
                   set=["layers.pair_couple=motor_clutch", "model.couple_slip_rate=1.0"],
                   params=["drive_radius", "contact_distance", "couple_torque"]),
}
BOUNDS = dict(ft.DEFAULT_PARAMS, tie_damping=(2e-6, 0.0, 3e-5), couple_torque=(1e-3, 1e-4, 3e-3))
TABLE1 = {"bead": 0.144, "ball": 0.119}  # Table 1's circular orbit, radius from the axis [m]
FLOWER = {"bead": 0.04, "ball": 0.24}    # Table 1's flower starts, radius from the axis [m]
CHANGES = {"mass": ["model.bead_mass=0.1", "model.ball_mass=0.1"],
           "length": ["model.string_length=0.662", "protocol.start_seed=locked_orbit"]}


def score(meas, penalty):
    """J = Σ ((ω_k − paper_k)/paper_k)² over the four thresholds of `meas` ({name: (value
    [rad/s], …)}); a threshold not reached adds penalty²."""
    rel = [meas[k][0] / (ft.PAPER[k] * PI) - 1 for k in ft.THRESHOLDS]
    return float(sum(r * r if np.isfinite(r) else penalty ** 2 for r in rel))


class Evaluator(ft.Evaluator):
    """fit_thresholds' evaluation, with ω_fall from the fresh orbit ('fall') where the staircase's
    down leg has no circular orbit to fall from (the rigid tie falls at ω1 on the way up), and
    scored by J = Σ ((ω_k − paper_k)/paper_k)², a threshold not reached counting as a miss of
    --penalty (relative): unweighted, so that variants with different window spacings are
    scored alike."""

    def record(self, key, values, results, phase, issue):
        if results is not None and not np.isfinite(ft.bracket(results["held"][0], "omega_fall")[0]):
            results = dict(results, down=results["fall"])
        rec = super().record(key, values, results, phase, issue)
        rec["J"] = score(rec["meas"], self.args.penalty)
        print(f"      J = {rec['J']:.4g}", file=sys.stderr, flush=True)
        return rec

    def chi2(self, x):
        return self.many([x], "simplex")[0]["J"]


def fall_file(work):
    """'fall': table1_staircase.toml's hold at 4π, then paper.toml's fall group: 3.9π … 2.5π."""
    doc = ft.load_toml(os.path.join(ft.SWEEPS, "table1_staircase.toml"), "table1_staircase.toml")
    doc.pop("grid", None)
    hold, first = doc["protocol"]["segment"][:2]
    doc["protocol"]["segment"] = [hold, dict(first, **{"from": 3.9 * PI, "to": 2.5 * PI, "num": 15})]
    return ft.write_sweep(doc, "fall", work)


def fit(variant, args, files, work):
    """Nelder–Mead on the four thresholds from the documented set: (best record, evaluations)."""
    spec = VARIANTS[variant]
    params = [ft.Param(k, *BOUNDS[k]) for k in spec["params"]]
    ns = argparse.Namespace(jobs=1, astrojax_exe=args.astrojax_exe, tie=spec["tie"], refine=0, set=spec["set"],
                            plateau=False, plateau_sigma=0.02, missing="penalty", penalty=args.penalty)
    ev = Evaluator(ns, params, {}, files, work)
    x0 = np.array([p.start if p.key not in DOCUMENTED else DOCUMENTED[p.key] for p in params])
    ev.many([x0], "start")
    lo, hi = np.array([p.lo for p in params]), np.array([p.hi for p in params])
    if args.max_evals > 1:
        ft.nelder_mead(ev.chi2, x0, 0.15 * (hi - lo), lo, hi, args.max_evals - 1)
    return min(ev.log, key=lambda r: r["J"]), ev.count


def held(args, files, values, spec, extra, out):
    """The staircase held at `values` (+ `extra` settings): (Sweep, sequence rows). A file left
    in --keep by an earlier run is this script's own output and is replaced."""
    if os.path.exists(out):
        os.remove(out)
    ft.run_sweep(args.astrojax_exe, files["held"], out, values, spec["tie"], 0, spec["set"] + extra)
    return ajx.Sweep(out), ajx.run_sequence(out, args.astrojax_exe)


def window(s, k):
    return dict(cls=s.class_name(0, k), w=s.omega_mean[0, k] / PI, wb=s.stats["omega_ball"][0, k] / PI,
                bead=s.stats["radius_bead_mean"][0, k], ball=s.stats["radius_bottom_mean"][0, k])


def level(s, omega_pi):
    """The window of the up leg held at ω_m = omega_pi·π: {class, ω_m, ω_ball [π], bead, ball [m]} or None."""
    for k in s.windows(0):
        if s.direction[0, k] == 1 and abs(s.omega_mean[0, k] / PI - omega_pi) < 0.01:
            return window(s, k)
    return None


def last_locked(s, top_pi=4.8):
    """The highest locked level of the up leg at or below top_pi·π (the paper's 4.8π orbit is
    locked; the model's ω1 may lie just below 4.8π), or None."""
    ks = [k for k in s.windows(0) if s.direction[0, k] == 1 and s.class_name(0, k) == "locked-circular"
          and s.omega_mean[0, k] / PI <= top_pi + 0.01]
    return window(s, ks[-1]) if ks else None


def lag_of(s, seq):
    """(mean ω_ball of the longest lagging run up [π], drop at ω1 [π]) or (nan, nan)."""
    runs = ft.up_runs(seq, "lagging-circular")
    if not runs:
        return np.nan, np.nan
    mean = float(max(runs, key=lambda r: int(r["windows"]))["omega_ball_mean_rad_s"]) / PI
    up = [k for k in s.windows(0) if s.direction[0, k] == 1]
    names = [s.class_name(0, k) for k in up]
    for i in range(1, len(up)):
        if names[i - 1] == "locked-circular" and names[i] == "lagging-circular":
            return mean, (s.stats["omega_ball"][0, up[i]] - s.stats["omega_ball"][0, up[i - 1]]) / PI
    return mean, np.nan


def flower_of(s):
    """Mean radii of bead and ball over the up leg's flower levels [m], or nan."""
    ks = [k for k in s.windows(0) if s.direction[0, k] == 1 and s.class_name(0, k) == "flower"]
    if not ks:
        return np.nan, np.nan
    return (float(np.mean(s.stats["radius_bead_mean"][0, ks])), float(np.mean(s.stats["radius_bottom_mean"][0, ks])))


def predict(variant, best, args, files, work):
    """Every prediction at the fitted point: {name: value}."""
    spec = VARIANTS[variant]
    out = {}
    for case, extra in (("base", []), *CHANGES.items()):
        path = os.path.join(args.keep or work, f"{variant}_{case}.h5")
        s, seq = held(args, files, best["values"], spec, extra, path)
        out[case] = dict(lag=lag_of(s, seq), at48=level(s, 4.8), locked=last_locked(s), at15=level(s, 15.0),
                         flower=flower_of(s))
    return out


def cm(x):
    return "—" if x is None or not np.isfinite(x) else f"{100 * x:.1f}"


def orbit_text(lv, at=False):
    if lv is None:
        return "none"
    wb = "" if not np.isfinite(lv["wb"]) else f", ω_ball {lv['wb']:.2f}π"
    return (f"{'at ' + format(lv['w'], '.1f') + 'π ' if at else ''}{lv['cls']}{wb}, "
            f"bead {cm(lv['bead'])} / ball {cm(lv['ball'])} cm")


def pct(value, paper):
    return "—" if not np.isfinite(value) else f"{100 * (value - paper) / paper:+.1f} %"


def threshold_cells(best):
    cells = []
    for k in ft.THRESHOLDS:
        v = best["meas"][k][0]
        cells.append("not reached" if not np.isfinite(v) else f"{v / PI:.2f}π ({pct(v / PI, ft.PAPER[k])})")
    return cells


def fit_table(fits):
    L = ["## The fits (four thresholds only)", "",
         "| variant | fitted parameters | evaluations | best point | ω_rise 12.63π | ω1 4.80π | ω2 15.00π | "
         "ω_fall 3.24π | J | thresholds reached : parameters |", "|---|---|---|---|---|---|---|---|---|---|"]
    for v, (best, n) in fits.items():
        keys = VARIANTS[v]["params"]
        point = ", ".join(f"{k} = {best['values'][k]:.4g}" for k in keys)
        reached = sum(np.isfinite(best["meas"][k][0]) for k in ft.THRESHOLDS)
        L.append(f"| {VARIANTS[v]['label']} | {len(keys)} | {n} | {point} | " + " | ".join(threshold_cells(best))
                 + f" | {best['J']:.3g} | {reached} : {len(keys)} |")
    return L + [""]


def change_text(base, changed):
    """A changed mass or length against the paper's 'same orbits': classes at 4.8π and 15π."""
    return (f"4.8π: {orbit_text(changed['at48'])}; last locked: {orbit_text(changed['locked'], True)}; "
            f"15π: {orbit_text(changed['at15'])}")


def prediction_table(preds):
    L = ["## The predictions (nothing refitted)", "",
         "| variant | lag ω_ball (paper ≈ 4.8π) | drop at ω1 (paper 0) | orbit at 4.8π | last locked orbit up to 4.8π "
         "(Table 1: bead 14.4 / ball 11.9 cm) | orbit at 15π (paper: as at 4.8π) | flower bead / ball [cm] (paper ≈ 4 / 24) |",
         "|---|---|---|---|---|---|---|"]
    for v, p in preds.items():
        b = p["base"]
        mean, drop = b["lag"]
        fb, fl = b["flower"]
        lag = "no lagging orbit" if not np.isfinite(mean) else f"{mean:.3f}π ({pct(mean, 4.8)})"
        dtext = "—" if not np.isfinite(drop) else f"{drop:+.3f}π"
        flower = "no flower" if not np.isfinite(fb) else f"{cm(fb)} / {cm(fl)} ({100 * (fb - FLOWER['bead']):+.1f} / " \
                                                          f"{100 * (fl - FLOWER['ball']):+.1f} cm)"
        L.append(f"| {VARIANTS[v]['label']} | {lag} | {dtext} | {orbit_text(b['at48'])} | {orbit_text(b['locked'], True)} | "
                 f"{orbit_text(b['at15'])} | {flower} |")
    L += ["", "| variant | m1 = m2 = 0.1 kg (paper: as with 18 g) | l = 0.662 m, started locked (paper: as at 0.826 m) |",
          "|---|---|---|"]
    for v, p in preds.items():
        L.append(f"| {VARIANTS[v]['label']} | {change_text(p['base'], p['mass'])} | {change_text(p['base'], p['length'])} |")
    return L + [""]


def report(args, fits, preds, elapsed):
    L = ["# Out of sample: fitted on the four thresholds, asked for the rest", "",
         f"Command: `/usr/bin/python3 analysis/out_of_sample.py {' '.join(args.argv)}`  ",
         f"{elapsed / 60:.1f} min. Each fit: Nelder–Mead from sweeps/paper.toml's set, at most {args.max_evals} "
         "evaluations (ω_rise from sweeps/paper_ramps.toml's first ramp, ω1, ω2, ω_fall from "
         "sweeps/table1_staircase.toml held level by level; ω_fall from Table 1's orbit held straight down, 3.9π … 2.5π, "
         "where the staircase's down leg has no circular orbit left), minimising J = Σ ((ω_k − paper_k)/paper_k)² over "
         f"the four thresholds; a threshold not reached counts as a relative miss of {args.penalty:g}. The brackets "
         "are 0.1π wide at ω1 and ω_fall, 0.5π at ω2 and one 10 s window (≈ 0.32π) at ω_rise.", ""]
    L += fit_table(fits) + prediction_table(preds)
    return "\n".join(L) + "\n"


def parse_args(argv):
    ap = ajx.parser(__doc__)
    ap.add_argument("-o", "--output", required=True, help="the Markdown report (.md)")
    ap.add_argument("--variants", default="rigid,clutch,couple", help="comma-separated, of: " + ", ".join(VARIANTS))
    ap.add_argument("--max-evals", type=int, default=12, help="evaluations per fit, the start included (default 12)")
    ap.add_argument("--penalty", type=float, default=1.0,
                    help="relative miss of a threshold not reached (default 1: 100 %%)")
    ap.add_argument("--keep", metavar="DIR", help="keep the prediction sweeps' files in DIR")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable (default: build/astrojax)")
    args = ap.parse_args(argv)
    args.argv = list(argv if argv is not None else sys.argv[1:])
    args.variant_list = [v.strip() for v in args.variants.split(",") if v.strip()]
    for v in args.variant_list:
        if v not in VARIANTS:
            ajx.fail(f"--variants: unknown '{v}'; allowed: {', '.join(VARIANTS)}")
    if not args.variant_list:
        ajx.fail("--variants: none given")
    if not 1 <= args.max_evals <= 1000:
        ajx.fail(f"--max-evals {args.max_evals}: allowed 1..1000")
    if not 0 < args.penalty <= 100:
        ajx.fail(f"--penalty {args.penalty:g}: allowed (0, 100]")
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    return args


def main(argv=None):
    args = parse_args(argv)
    args.astrojax_exe = ajx.require_astrojax(args.astrojax)
    t0 = time.time()
    fits, preds = {}, {}
    with tempfile.TemporaryDirectory() as work:
        files, _ = ft.rise_file(os.path.join(ft.SWEEPS, "paper_ramps.toml"), work)
        files.update(ft.staircase_file(os.path.join(ft.SWEEPS, "table1_staircase.toml"), work)[0])
        files["fall"] = fall_file(work)
        for v in args.variant_list:
            fits[v] = fit(v, args, files, work)
            preds[v] = predict(v, fits[v][0], args, {"held": files["held"]}, work)
    ajx.write_report(args.output, report(args, fits, preds, time.time() - t0))


if __name__ == "__main__":
    ajx.run(main)
