#!/usr/bin/python3
"""The sensitivity of the headline thresholds to every parameter, and ω2's spread over histories.

Reads the paired sweep of sweeps/sensitivity.toml (the main job's tie clutch, variant `base`, and
one variant per parameter and end of its plausible range, `NAME_lo` and `NAME_hi`) and, per
variant, takes from it:
  - ω_rise (group rise), ω2's classifier bracket and ω_fall after the lag (group up), ω1 (group
    lock),
    ω_fall from the fresh orbit (group fall): the brackets of `astrojax thresholds --no-hold`,
    each as its midpoint and its width;
  - the lag at 12π on the way up: its ω_ball and the bead's stuck position s (the window's
    mean L1), and s at 12π again from above;
and from the continuation of the lagging orbit (`astrojax orbits --lag`, an equilibrium of the
frame turning with the tie) the lag's Hopf point ω_H and its ω_ball at 12π, both at the base's s
(the parameter alone) and at the variant's own s (the parameter and the history it makes).

Each number's spread is its value at the two ends of each parameter's range minus the base's;
the derivative is (hi − lo)/(2Δ). A tornado figure per number (`--figures DIR`) sorts the
parameters by the larger of the two shifts.

With --histories FILE (sweeps/lag_histories.toml: held lags from several seeds, kicks and
settle times): the stuck position s of every lagging chain, the spread of s, and ω_H and ω_ball
at each s from the continuation: ω2's spread over histories.

With --paths FILE (sweeps/lag_paths.toml: the lag reached through ω1 in several ways): the
bead's s at 10π after each path, and ω_H at each s: ω2's spread over the histories that reach
the lag.

usage: /usr/bin/python3 analysis/sensitivity.py out/sensitivity.h5 -o out/sensitivity.md --figures out/
       /usr/bin/python3 analysis/sensitivity.py --paths out/lag_paths.h5 -o out/lag_paths.md
       /usr/bin/python3 analysis/sensitivity.py out/sensitivity.h5 --histories out/lag_histories.h5 \\
           --histories out/lag_histories_60.h5 -o out/sensitivity.md --figures out/
"""
import csv
import os
import tempfile

import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
ORBITS_CFG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sweeps", "orbits.toml")
PAPER = {"omega_rise": 12.63, "omega_fall_lag": 3.24, "omega_fall_fresh": 3.24, "omega_1": 4.80, "omega_2": 15.00,
         "omega_H": 15.00, "lag_omega_ball": 4.8}
# The headline numbers: key, symbol, where it comes from.
NUMBERS = [("omega_rise", "ω_rise", "ramp from rest, windows of 0.08π"),
           ("omega_fall_fresh", "ω_fall (fresh orbit)", "levels 0.02π apart"),
           ("omega_fall_lag", "ω_fall (after the lag)", "levels 0.02π apart"),
           ("omega_1", "ω1", "levels 0.02π apart"),
           ("omega_2", "ω2 (classifier)", "levels 0.1π apart"),
           ("omega_H", "ω2 (the lag's Hopf point, own s)", "continuation at the variant's s"),
           ("omega_H_fixed_s", "ω2 (Hopf point at the base's s)", "continuation"),
           ("lag_omega_ball", "lag ω_ball at 12π", "the sweep's window"),
           ("lag_s", "the lag's s at 12π", "the sweep's window")]
SYMBOLS = {"drive_radius": "R", "contact_distance": "d", "top_stop": "s_min", "mu_static": "μ_s",
           "mu_kinetic": "μ_k", "drag": "c_D", "string_length": "l", "bead_mass": "m1", "ball_mass": "m2",
           "tie_static_torque": "τ_s", "tie_kinetic_torque": "τ_k", "tie_damping": "c_a"}
UNITS = {"drive_radius": "m", "contact_distance": "m", "top_stop": "m", "mu_static": "", "mu_kinetic": "",
         "drag": "kg/s", "string_length": "m", "bead_mass": "kg", "ball_mass": "kg", "tie_static_torque": "N m",
         "tie_kinetic_torque": "N m", "tie_damping": "N m s"}
# ω1 from the group `lock`, which approaches it in the main job's gentle steps (up's quick step
# to 4.6π loses the lock on the way)
THRESHOLD_OF_GROUP = {("rise", "omega_rise"): "omega_rise", ("lock", "omega_1"): "omega_1",
                      ("up", "omega_2"): "omega_2", ("up", "omega_fall"): "omega_fall_lag",
                      ("fall", "omega_fall"): "omega_fall_fresh"}


def model_sets(sweep, c):
    """--set model.NAME=VALUE for every model column of chain c."""
    out = []
    for k, name in enumerate(sweep.model_columns):
        out += ["--set", f"model.{name}={sweep.model[c, k]:.17g}"]
    return out


def lag_continuation(astrojax, sets, s, omega):
    """(ω_H [π], ω_ball at omega [π]) of the lagging orbit with the bead stuck at s, from
    `astrojax orbits --lag`: the first Hopf-type stability loss on the held branch, and the held,
    stable lag at omega. NaN where there is none."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "lag.csv")
        ajx.run_checked([astrojax, "orbits", ORBITS_CFG, "--set", "layers.tie=clutch", *sets, "--lag",
                         "--s", f"{s:.6f}", "--omega", f"{omega / PI:.6f}pi", "--csv", out])
        with open(out, newline="") as f:
            rows = list(csv.DictReader(f))
    hopf = [float(r["omega_m"]) / PI for r in rows if r["kind"].startswith("loss") and "hopf" in r["kind"]
            and np.isfinite(float(r["omega_m"]))]
    lag = [float(r["omega_ball"]) / PI for r in rows if r["kind"] == "lag" and r["admissible"] == "1"
           and r["stable"] == "1"]
    return (min(hopf) if hopf else np.nan), (lag[0] if lag else np.nan)


def level_window(sweep, c, omega_pi, direction, nth=0):
    """The nth window of chain c held at omega_pi (π rad/s) moving in `direction` (+1, −1), or None."""
    hits = [k for k in range(sweep.n_windows) if sweep.valid[c, k] and int(sweep.direction[c, k]) == direction
            and abs(sweep.omega_mean[c, k] / PI - omega_pi) < 1e-6]
    return hits[nth] if len(hits) > nth else None


def lag_at(sweep, c, omega_pi, direction):
    """(ω_ball [π], s [m]) of the lagging window of chain c at omega_pi, NaN if it is not lagging."""
    k = level_window(sweep, c, omega_pi, direction)
    if k is None or sweep.class_name(c, k) != "lagging-circular":
        return np.nan, np.nan
    return float(sweep.stats["omega_ball"][c, k]) / PI, float(sweep.stats["L1_mean"][c, k])


def measure_variants(path, astrojax):
    """{variant: {number: (value, width)}} and the variants' parameter values."""
    sweep = ajx.Sweep(path)
    if sweep.variant is None or "base" not in sweep.variant_names:
        ajx.fail(f"{path}: not a sweep of sweeps/sensitivity.toml (no variant 'base')")
    rows, _ = ajx.run_thresholds(path, astrojax)
    out = {name: {} for name in sweep.variant_names}
    chain_of = {}
    for c in range(sweep.n_chains):
        chain_of[(sweep.variant_name(c), sweep.group_name(c))] = c
    for r in rows:
        c = int(r["chain"])
        key = THRESHOLD_OF_GROUP.get((sweep.group_name(c), r["threshold"]))
        if key is None:
            continue
        b, a = ajx.number(r["before_rad_s"]) / PI, ajx.number(r["after_rad_s"]) / PI
        out[sweep.variant_name(c)][key] = (0.5 * (a + b), abs(a - b))
    base_up = chain_of[("base", "up")]
    _, s_base = lag_at(sweep, base_up, 12.0, +1)
    for name in sweep.variant_names:
        c = chain_of.get((name, "up"))
        if c is None:
            continue
        wb, s = lag_at(sweep, c, 12.0, +1)
        _, s_above = lag_at(sweep, c, 12.0, -1)
        out[name]["lag_omega_ball"] = (wb, np.nan)
        out[name]["lag_s"] = (s, np.nan)
        out[name]["lag_s_above"] = (s_above, np.nan)
        sets = model_sets(sweep, c)
        hf, _ = lag_continuation(astrojax, sets, s_base, 12 * PI) if np.isfinite(s_base) else (np.nan, np.nan)
        out[name]["omega_H_fixed_s"] = (hf, np.nan)
        h, wb_cont = lag_continuation(astrojax, sets, s, 12 * PI) if np.isfinite(s) else (np.nan, np.nan)
        out[name]["omega_H"] = (h, np.nan)
        out[name]["lag_omega_ball_cont"] = (wb_cont, np.nan)
    values = {}
    for name in sweep.variant_names:
        c = chain_of[(name, "up")]
        values[name] = {col: float(sweep.model[c, k]) for k, col in enumerate(sweep.model_columns)}
    return out, values, sweep


def parameters_of(out):
    """The parameters with both ends present: {name: ("NAME_lo", "NAME_hi")}."""
    return {p: (f"{p}_lo", f"{p}_hi") for p in SYMBOLS if f"{p}_lo" in out and f"{p}_hi" in out}


def sensitivity_rows(out, values):
    """Per number and parameter: (shift at lo, shift at hi, derivative per unit, Δ)."""
    table = {}
    base = out["base"]
    for key, _, _ in NUMBERS:
        v0 = base.get(key, (np.nan, np.nan))[0]
        rows = {}
        for p, (lo, hi) in parameters_of(out).items():
            a, b = out[lo].get(key, (np.nan,))[0], out[hi].get(key, (np.nan,))[0]
            d = values[hi][p] - values[lo][p]
            rows[p] = (a - v0, b - v0, (b - a) / d if d else np.nan, 0.5 * d)
        table[key] = (v0, rows)
    return table


def tornado(path, symbol, v0, rows, unit="π rad/s", paper=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    order = sorted(rows, key=lambda p: -np.nanmax(np.abs(rows[p][:2])) if np.any(np.isfinite(rows[p][:2])) else 0)
    fig, ax = plt.subplots(figsize=(6.4, 0.32 * len(order) + 1.4))
    for i, p in enumerate(reversed(order)):
        lo, hi = rows[p][0], rows[p][1]
        for shift, colour, label in ((lo, "tab:blue", "low end"), (hi, "tab:red", "high end")):
            if np.isfinite(shift):
                ax.barh(i, shift, left=v0, color=colour, alpha=0.75, label=label if i == 0 else None)
            else:
                ax.plot([v0], [i], marker="x", color=colour)
    ax.set_yticks(range(len(order)))
    ax.set_yticklabels([SYMBOLS[p] for p in reversed(order)])
    ax.axvline(v0, color="black", lw=0.8)
    if paper is not None:
        ax.axvline(paper, color="black", ls="--", lw=0.8, label=f"paper {paper:g}")
    ax.set_xlabel(f"{symbol} [{unit}]")
    ax.set_title(f"{symbol}: base {v0:.3f}; each parameter at the ends of its range", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def hold_settle(sweep):
    """The hold sweep's settle time [s]: its --set hold.settle override, else its /config's."""
    import tomllib
    for item in (part for o in sweep.overrides for part in o.split(";")):
        if item.strip().startswith("hold.settle="):
            return float(item.split("=", 1)[1])
    return float(tomllib.loads(sweep.config).get("hold", {}).get("settle", np.nan))


def histories(paths, astrojax):
    """Every lagging chain of the hold sweeps `paths`: (file, ω_m [π], seed, kick, settle, s, ω_ball [π]),
    and ω_H [π] at each distinct s (to 0.1 mm) from the continuation."""
    found = []
    for path in paths:
        sweep = ajx.Sweep(path)
        if not sweep.is_hold:
            ajx.fail(f"{path}: --histories needs a hold sweep (sweeps/lag_histories.toml)")
        settle = hold_settle(sweep)
        for c in range(sweep.n_chains):
            k = sweep.n_windows - 1
            if not sweep.valid[c, k] or sweep.class_name(c, k) != "lagging-circular":
                continue
            found.append(dict(file=path, omega=float(sweep.hold_omega[c]) / PI, seed=sweep.seed_names[int(sweep.seed[c])],
                              kick=int(sweep.perturbation[c]), settle=settle, s=float(sweep.stats["L1_mean"][c, k]),
                              omega_ball=float(sweep.stats["omega_ball"][c, k]) / PI))
    sets = []
    if found:
        sw = ajx.Sweep(paths[0])
        sets = model_sets(sw, 0)
    hopf = {}
    for row in found:
        key = round(row["s"], 4)
        if key not in hopf:
            hopf[key] = lag_continuation(astrojax, sets, key, 12 * PI)[0]
        row["omega_H"] = hopf[key]
    return found


def paths(path, astrojax, omega_pi=10.0):
    """Every chain of a sweep of paths to the lag (sweeps/lag_paths.toml): its group (the way it
    crossed ω1), the bead's s and ω_ball of its window at omega_pi on the way up if that window
    is lagging, and ω_H at that s from the continuation."""
    sweep = ajx.Sweep(path)
    sets = model_sets(sweep, 0)
    hopf, rows = {}, []
    for c in range(sweep.n_chains):
        omega_ball, s = lag_at(sweep, c, omega_pi, +1)
        k = level_window(sweep, c, omega_pi, +1)
        g = int(sweep.group[c])
        row = dict(path=sweep.group_names[g], purpose=sweep.group_purposes[g], s=s, omega_ball=omega_ball,
                   cls=sweep.class_name(c, k) if k is not None else "not reached", omega_H=np.nan)
        if np.isfinite(s):
            key = round(s, 6)  # the continuation takes s to 1 µm
            if key not in hopf:
                hopf[key] = lag_continuation(astrojax, sets, key, 12 * PI)[0]
            row["omega_H"] = hopf[key]
        rows.append(row)
    return rows


def paths_report(path, rows, omega_pi=10.0):
    """The markdown section of --paths."""
    lines = ["## ω2 over the paths through ω1", "", f"- sweep: `{path}`; the lag read at {omega_pi:g}π on the way up",
             "", f"| path | class at {omega_pi:g}π | s [m] | ω_ball [π] | ω_H at s [π] |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {ajx.printable(r['path'])} | {r['cls']} | {fmt(r['s'], 5)} | {fmt(r['omega_ball'], 4)} | "
                     f"{fmt(r['omega_H'], 3)} |")
    lag = [r for r in rows if np.isfinite(r["s"])]
    if lag:
        s = np.array([r["s"] for r in lag])
        h = np.array([r["omega_H"] for r in lag])
        lines += ["", f"- {len(lag)} of {len(rows)} paths end on the lag; s: {s.min():.5f} … {s.max():.5f} m "
                  f"(spread {1e3 * (s.max() - s.min()):.2f} mm); ω_H: {fmt(np.nanmin(h))} … {fmt(np.nanmax(h))}π "
                  f"(spread {fmt(np.nanmax(h) - np.nanmin(h))}π)"]
    else:
        lines += ["", "- no path ends on the lag"]
    lines.append("")
    return "\n".join(lines)


def fmt(v, d=3):
    return f"{v:.{d}f}" if np.isfinite(v) else "—"


def report(path, out, values, table, hist, hist_paths):
    base = out["base"]
    lines = ["# Sensitivity of the headline numbers", "", f"- paired sweep: `{path}` (sweeps/sensitivity.toml)",
             "- each number at the base (the main job's clutch set) and with one parameter at either end of its "
             "range; shifts in π rad/s (s in m); derivative = (hi − lo)/(2Δ) per unit of the parameter", "",
             "## The base", "", "| number | value | bracket width | paper |", "|---|---|---|---|"]
    for key, sym, how in NUMBERS:
        v, w = base.get(key, (np.nan, np.nan))
        lines.append(f"| {sym} ({how}) | {fmt(v, 4)} | {fmt(w, 3)} | {PAPER.get(key, '—')} |")
    lines += ["", "## Shifts at the ends of each range", ""]
    params = list(parameters_of(out))
    head = "| number | " + " | ".join(f"{SYMBOLS[p]} ±{values[f'{p}_hi'][p] - values['base'][p]:.3g}" for p in params) + \
           " | total (quadrature) |"
    lines += [head, "|---|" + "---|" * (len(params) + 1)]
    for key, sym, _ in NUMBERS:
        v0, rows = table[key]
        cells, sq = [], 0.0
        for p in params:
            lo, hi, _, _ = rows[p]
            cells.append(f"{fmt(lo, 3)} / {fmt(hi, 3)}")
            m = np.nanmax(np.abs([lo, hi])) if np.any(np.isfinite([lo, hi])) else np.nan
            if np.isfinite(m):
                sq += m * m
        lines.append(f"| {sym} | " + " | ".join(cells) + f" | ±{np.sqrt(sq):.3f} |")
    lines += ["", "## Derivatives", "", "| number | " + " | ".join(f"∂/∂{SYMBOLS[p]} [per {UNITS[p] or '1'}]"
                                                                        for p in params) + " |",
              "|---|" + "---|" * len(params)]
    for key, sym, _ in NUMBERS:
        _, rows = table[key]
        lines.append(f"| {sym} | " + " | ".join(f"{rows[p][2]:.3g}" for p in params) + " |")
    if hist is not None:
        lines += ["", "## ω2 over histories", "", f"- hold sweeps: {', '.join(f'`{h}`' for h in hist_paths)}", "",
                  "| file | settle [s] | ω_m [π] | seed | kick | s [m] | ω_ball [π] | ω_H at s [π] |",
                  "|---|---|---|---|---|---|---|---|"]
        for r in hist:
            lines.append(f"| {os.path.basename(r['file'])} | {r['settle']:g} | {r['omega']:.2f} | {r['seed']} | {r['kick']} | {r['s']:.4f} | "
                         f"{r['omega_ball']:.4f} | {fmt(r['omega_H'], 3)} |")
        if not hist:
            lines += ["", "- none of these chains ends on the lag: no history of them gives an s"]
        if hist:
            s = np.array([r["s"] for r in hist])
            h = np.array([r["omega_H"] for r in hist])
            wb = np.array([r["omega_ball"] for r in hist])
            lines += ["", f"- s: {s.min():.4f} … {s.max():.4f} m over {len(hist)} lagging chains; "
                      f"ω_H: {np.nanmin(h):.3f} … {np.nanmax(h):.3f}π (mean {np.nanmean(h):.3f}, sd {np.nanstd(h, ddof=1) if len(h) > 1 else 0:.3f}); "
                      f"ω_ball: {wb.min():.4f} … {wb.max():.4f}π"]
    lines.append("")
    return "\n".join(lines)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", nargs="?", help="the paired sweep (sweeps/sensitivity.toml)")
    ap.add_argument("-o", "--output", required=True, help="markdown report to write")
    ap.add_argument("--figures", metavar="DIR", help="write a tornado figure per number into DIR")
    ap.add_argument("--histories", action="append", default=[], metavar="H5",
                    help="hold sweeps of the lag (sweeps/lag_histories.toml), repeatable")
    ap.add_argument("--paths", metavar="H5", help="a sweep of paths through ω1 to the lag (sweeps/lag_paths.toml)")
    ap.add_argument("--lag-omega", type=float, default=10.0, metavar="W",
                    help="with --paths: the level (in π rad/s, on the way up) where the lag is read (default 10)")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable")
    args = ap.parse_args(argv)
    if not args.input and not args.paths:
        ap.error("give the paired sweep, or --paths H5, or both")
    exe = ajx.require_astrojax(args.astrojax)
    if not 0 < args.lag_omega < 100:
        ap.error(f"--lag-omega {args.lag_omega:g}: allowed 0 < W < 100 (in π rad/s)")
    section = paths_report(args.paths, paths(args.paths, exe, args.lag_omega), args.lag_omega) if args.paths else ""
    if not args.input:
        ajx.write_report(args.output, "# ω2's spread over histories\n\n" + section)
        return
    out, values, _ = measure_variants(args.input, exe)
    table = sensitivity_rows(out, values)
    hist = histories(args.histories, exe) if args.histories else None
    ajx.write_report(args.output, report(args.input, out, values, table, hist, args.histories) + section)
    if args.figures:
        os.makedirs(args.figures, exist_ok=True)
        for key, sym, _ in NUMBERS:
            v0, rows = table[key]
            if not np.isfinite(v0):
                continue
            f = os.path.join(args.figures, f"tornado_{key}.png")
            tornado(f, sym, v0, rows, "m" if key == "lag_s" else "π rad/s", PAPER.get(key))
            print(f"wrote {f}")


if __name__ == "__main__":
    ajx.run(main)
