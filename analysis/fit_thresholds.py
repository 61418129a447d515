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
import csv
import math
import os
import sys
import tempfile

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis.fit import (BASE, DEFAULT_PARAMS, PAPER, PI, SWEEPS, SYMBOL, Evaluator, Param, coarse_scan,
                                   covariance, direction_text, jacobian, nelder_mead, overrides, parse_fixed,
                                   parse_param, ramp_files, relation_issue, residuals, rise_file, staircase_file)


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
    ajx.run(main)
