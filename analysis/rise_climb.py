#!/usr/bin/python3
"""The bead's climbs off the bottom ball in `astrojax run` files: where each starts, why, how
far it goes and why it ends (docs/reports/reproduction-evidence.md, "The rise from rest").

Before the climb the balls sit on the bottom-stop orbit the ramp picked up (the bottom ball
whirls around the bead at ω_m on the opposite side of the axis, the lower segment nearly
horizontal). For each climb (a stretch of samples off the bottom stop, mode ≠ 1) it prints:
- the onset: t, ω_m, and the capstan cone there, μ* = ln(T2/T1)/ψ on the last bottom-stop
  sample (the bead slides up where μ* reaches μ_s: T1/T2 = exp(−μ_s ψ));
- the climb: the highest point s_b − min L1, the time off the ball, the friction loss;
- the lock: the azimuth of the bead minus the motor's φ, and the spin rate of the pair (the
  rate of the azimuth of r2 − r1) against ω_m, over the second before the onset and over the
  climb: a pair that falls behind the motor is no longer fed by it;
- the angular momentum about the motor axis, L_z = Σ m (r × v)_z, at the onset and at the
  highest point, against ω_m Σ m ρ² there (the pair still locked to the motor): the torque
  that lock would need over the climb, against the motor's P_motor/ω_m and the bound
  R T1 |u1,horizontal| of what the upper string can pass.
Then the energy ledger of run_ledger.py in --window windows from --before seconds before the
first onset to --after seconds after it.

With the diagnostic layer pair_couple = "motor_clutch" (src/physics/pair_couple.hpp; docs/reports/reproduction-evidence.md, "A
couple on the pair") it also prints, per climb, the pair's phase against the motor (the azimuth
of r2 − r1 minus φ: its largest excursion from the onset over the climb, and its change to the
end of the climb) and the couple's work on the balls, recomputed from the samples as the layer
computes it. For any run, a last table gives one row per file: the first onset, the highest
point over all climbs, the time off the ball, and the final state over the last --tail seconds
with a coarse label (not the sweep's classifier, which needs a sweep): "fallen" (on the ball in
≥ 90 % of the samples), "circular" when L1, ρ1 and ρ2 vary by less than 5 % (locked: ω_ball
within 2 % of ω_m; else lagging), else "not steady".

usage: /usr/bin/python3 analysis/rise_climb.py out/rise_from_rest.h5 [-o out/rise.md]
The masses m1, m2 and the drive radius R come from the run's /config ([model] bead_mass,
ball_mass, drive_radius, else the model's defaults) and its recorded --set overrides.
"""
import tomllib

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis.config import model_values
from astrojax_analysis.ledger import HEADER, fmt_row, ledger, read_ledger, window_row

BOTTOM = 1  # /trajectory/mode: on the bottom ball
# physics::Model's defaults (src/physics/model.hpp), for keys a run's config leaves out
DEFAULTS = {"bead_mass": 0.018, "ball_mass": 0.018, "drive_radius": 0.01}  # [kg], [kg], [m]
COUPLE_DEFAULTS = {"couple_torque": 0.0, "couple_slip_rate": 1.0}  # τ_c [N m], Ω_ε [rad/s]
COUPLE_TILT_FLOOR = 1e-3  # ε of physics::kCoupleTiltFloor (src/physics/pair_couple.hpp)


def couple_values(path, run):
    """(τ_c [N m], Ω_ε [rad/s]) of the pair couple from the run's config and --set overrides,
    τ_c = 0 when layers.pair_couple is not "motor_clutch" (physics::Model's defaults otherwise)."""
    try:
        layer = tomllib.loads(run["config"]).get("layers", {}).get("pair_couple", "none")
    except tomllib.TOMLDecodeError as e:
        raise ajx.SweepFileError(path, "/config", f"not TOML: {e}") from None
    for item in run["overrides"]:
        key, _, value = item.strip().partition("=")
        if key.strip() == "layers.pair_couple":
            layer = value.strip().strip('"')
    v = model_values(path, run, COUPLE_DEFAULTS)
    return (v["couple_torque"] if layer == "motor_clutch" else 0.0), v["couple_slip_rate"]


def read(path):
    run = read_ledger(path, ("v1", "v2", "T1", "T2", "psi"))
    v = model_values(path, run, DEFAULTS)
    run["m1"], run["m2"], run["R"] = v["bead_mass"], v["ball_mass"], v["drive_radius"]
    run["couple_torque"], run["couple_slip_rate"] = couple_values(path, run)
    a = run["summary"]
    try:
        run["ledger"] = float(a["energy_residual_relative"]) if "energy_residual_relative" in a else np.nan
        run["tie_slips"] = int(a["tie_slips"]) if "tie_slips" in a else 0
    except (TypeError, ValueError):
        raise ajx.SweepFileError(path, "/summary", "energy_residual_relative or tie_slips is not a number") from None
    return run


def pair_couple(run):
    """The pair couple at every sample, as src/physics/pair_couple.cpp computes it: the couple
    τ [N m], its torque about z τ ρ²/L2² [N m] and its power F2·(v2 − v1) [W]."""
    d2 = run["r2"] - run["r1"]
    dd = run["v2"] - run["v1"]
    rho2 = d2[:, 0] ** 2 + d2[:, 1] ** 2
    L2sq = np.sum(d2 ** 2, axis=1)
    w = run["omega_m"]
    rel_x = -w * d2[:, 1] - dd[:, 0]  # ω_m ẑ × d2 − ḋ2
    rel_y = w * d2[:, 0] - dd[:, 1]
    slip = (d2[:, 0] * rel_y - d2[:, 1] * rel_x) / (rho2 + COUPLE_TILT_FLOOR ** 2 * L2sq)
    tau = run.get("couple_torque", 0.0) * np.tanh(slip / run.get("couple_slip_rate", 1.0))
    power = tau / L2sq * (-d2[:, 1] * dd[:, 0] + d2[:, 0] * dd[:, 1])
    return tau, tau * rho2 / L2sq, power


def pair_phase(run, sl):
    """The azimuth of r2 − r1 minus the motor's φ over the slice sl, unwrapped [rad]."""
    d2 = run["r2"][sl] - run["r1"][sl]
    return np.unwrap(wrap(np.arctan2(d2[:, 1], d2[:, 0]) - run["phi"][sl]))


def couple_row(run, a, b):
    """The pair against the motor over a climb (samples a..b, onset at a − 1): the largest
    excursion of the pair's phase from the onset, its change to the end and over the first
    second, the couple's work and its mean torque about z."""
    p = a - 1
    ph = pair_phase(run, slice(p, b + 1))
    _, tz, power = pair_couple(run)
    t = run["t"][p:b + 1]
    work = float(np.sum(0.5 * (power[p + 1:b + 1] + power[p:b]) * np.diff(t))) if b > p else 0.0
    first = run["t"][p:b + 1] <= run["t"][p] + 1.0
    return dict(phase_max=float(np.max(np.abs(ph - ph[0]))), phase_end=float(ph[-1] - ph[0]),
                phase_1s=float(ph[first][-1] - ph[0]), couple_work=work, couple_tz=float(np.mean(tz[p:b + 1])))


def final_state(run, tail):
    """The last `tail` seconds: a coarse label and its numbers (module docstring)."""
    t = run["t"]
    sel = t >= t[-1] - tail
    r = window_row(run, sel)
    on_ball = np.mean(run["mode"][sel] == BOTTOM)
    rho = [np.hypot(run[k][sel, 0], run[k][sel, 1]) for k in ("r1", "r2")]
    spread = max(np.ptp(x) / max(np.mean(x), 1e-12) for x in rho + [run["L1"][sel]])
    w_ball = 0.5 * (r["omega_bead"] + r["omega_bottom"])
    if on_ball >= 0.9:
        label = "fallen"
    elif spread < 0.05:
        label = "locked circular" if abs(w_ball - r["omega_m"]) < 0.02 * r["omega_m"] else "lagging circular"
    else:
        label = "not steady"
    return dict(label=label, on_ball=on_ball, L1=r["L1"], rho1=r["rho1"], rho2=r["rho2"], omega_m=r["omega_m"],
                omega_ball=w_ball, P_motor=r["P_motor"], P_drag=r["P_drag"])


def summary_row(path, run, tail):
    eps = episodes(run["mode"])
    f = final_state(run, tail)
    head = f"| {path} | {run.get('couple_torque', 0.0):.1e} | {run.get('couple_slip_rate', 1.0):g} |"
    tail_cols = (f" {f['label']} | {f['L1']:.3f} | {1e3 * f['rho1']:.1f}, {1e3 * f['rho2']:.1f} | "
                 f"{f['omega_ball']:.2f} / {f['omega_m']:.2f} | {f['P_motor']:+.2e} | "
                 f"{run.get('tie_slips', 0)} | {run.get('ledger', np.nan):+.1e} |")
    if not eps:
        return head + " none | — | — | — | — |" + tail_cols
    p = eps[0][0] - 1
    s_b = run["L1"][p]
    highest = max(s_b - np.min(run["L1"][a:b + 1]) for a, b in eps)
    off = sum(run["t"][b] - run["t"][a - 1] for a, b in eps)
    c = couple_row(run, *eps[0])
    return (head + f" {run['t'][p]:.1f} s, {run['omega_m'][p] / np.pi:.3f}π | {1e3 * highest:.1f} | {off:.1f} | "
            f"{c['phase_1s']:+.2f}, {c['phase_end']:+.1f} |" + tail_cols)


SUMMARY_HEADER = ["| run | τ_c [N m] | Ω_ε [rad/s] | first onset | highest [mm] | off the ball [s] | "
                  "pair phase, climb 0: change over its first second, to its end [rad] | final (last --tail s) | L1 [m] | "
                  "ρ1, ρ2 [mm] | ω_ball / ω_m [π] | P_motor [W] | tie slips | ledger residual (relative) |",
                  "|---" * 14 + "|"]


def episodes(mode):
    """(first, last) sample index of each stretch off the bottom stop that follows one on it."""
    off = mode != BOTTOM
    starts = np.nonzero(off[1:] & ~off[:-1])[0] + 1
    out = []
    for a in starts:
        rest = np.nonzero(~off[a:])[0]
        out.append((a, a + rest[0] - 1 if len(rest) else len(mode) - 1))
    return out


def wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def rate(t, angle):
    """Least-squares slope of an unwrapped angle [rad/s]."""
    return np.polyfit(t, np.unwrap(angle), 1)[0] if len(t) > 2 else np.nan


def lz(run, i):
    """Angular momentum about the motor axis [kg m²/s] at sample i."""
    total = 0.0
    for r, v, m in (("r1", "v1", run["m1"]), ("r2", "v2", run["m2"])):
        total += m * (run[r][i, 0] * run[v][i, 1] - run[r][i, 1] * run[v][i, 0])
    return total


def inertia(run, i):
    """Σ m ρ² about the motor axis [kg m²] at sample i: a locked pair has L_z = ω_m Σ m ρ²."""
    return sum(m * (run[r][i, 0] ** 2 + run[r][i, 1] ** 2) for r, m in (("r1", run["m1"]), ("r2", run["m2"])))


def torque_bound(run, i):
    """The most torque about z the upper string can pass to the top at sample i [N m]:
    R T1 |u1 horizontal|, u1 the unit vector from the top a = R(cos φ, sin φ, 0) to the bead."""
    a = run["R"] * np.array([np.cos(run["phi"][i]), np.sin(run["phi"][i]), 0.0])
    d = run["r1"][i] - a
    return run["R"] * run["T1"][i] * np.hypot(d[0], d[1]) / np.linalg.norm(d)


def climb_row(run, a, b):
    t, L1, om, mode = run["t"], run["L1"], run["omega_m"], run["mode"]
    p = a - 1  # last sample on the ball
    s_b = L1[p]
    low = np.min(L1[a:b + 1])
    top = a + int(np.nonzero(L1[a:b + 1] <= low + 0.01 * abs(s_b - low))[0][0])  # first within 1 % of the highest
    sliding = np.nonzero(mode[a:b + 1] != 0)[0]  # the first slide ends at the first stick, stop or slack
    e = a + (sliding[0] if len(sliding) else b - a)
    t_slide = max(t[e] - t[p], 1e-12)
    t_top = max(t[top] - t[p], 1e-12)
    pair = np.arctan2(run["r2"][:, 1] - run["r1"][:, 1], run["r2"][:, 0] - run["r1"][:, 0])
    bead_lag = wrap(np.arctan2(run["r1"][:, 1], run["r1"][:, 0]) - run["phi"])
    before = (t >= t[p] - 1.0) & (t <= t[p])
    during = np.arange(a, b + 1)
    return dict(
        t=t[p], omega=om[p] / np.pi, mu_star=np.log(run["T2"][p] / run["T1"][p]) / run["psi"][p],
        psi=run["psi"][p], T1=run["T1"][p], T2=run["T2"][p],
        climb=s_b - L1[top], t_top=t_top, slide=s_b - L1[e], t_slide=t_slide, off=t[b] - t[p],
        friction=run["friction_loss"][b] - run["friction_loss"][p],
        lag_before=bead_lag[p], lag_end=bead_lag[b],
        spin_before=rate(t[before], pair[before]) / np.pi, spin_during=rate(t[during], pair[during]) / np.pi,
        omega_during=om[during].mean() / np.pi,
        Lz_before=lz(run, p), Lz_top=lz(run, top), Lz_lock=om[top] * inertia(run, top),
        torque_needed=(om[top] * inertia(run, top) - lz(run, p)) / t_top,
        torque_motor=(run["motor_work"][top] - run["motor_work"][p]) / t_top / om[p],
        torque_max=torque_bound(run, p))


def branch_rows(run, levels, end):
    """The bottom-stop orbit the ramp carries, over the second before ω_m first reaches each
    level (π rad/s) and before sample `end`: mean ψ, T2/T1, ρ1, ρ2 and μ* = ln(T2/T1)/ψ."""
    t, om = run["t"], run["omega_m"]
    rows = []
    for w in levels:
        hit = np.nonzero(om[:end] >= w * np.pi)[0]
        if not len(hit):
            continue
        sel = (t > t[hit[0]] - 1.0) & (t <= t[hit[0]])
        rho = [np.hypot(run[r][sel, 0], run[r][sel, 1]).mean() for r in ("r1", "r2")]
        ratio = (run["T2"][sel] / run["T1"][sel]).mean()
        psi = run["psi"][sel].mean()
        rows.append(f"| {w:g} | {psi:.3f} | {ratio:.3f} | {1e3 * rho[0]:.1f} | {1e3 * rho[1]:.1f} | "
                    f"{np.log(ratio) / psi if psi > 0 else float('nan'):+.3f} |")
    return rows


def report(path, run, before, after, window, levels=()):
    eps = episodes(run["mode"])
    lines = [f"# Climbs off the bottom ball: {path}", ""]
    if levels:
        lines += ["The bottom-stop orbit before the first climb, over the second before ω_m reaches each "
                  "level (μ* < 0: the ball's pull T2 is below T1 and the stop holds the bead):", "",
                  "| ω_m [π] | ψ [rad] | T2/T1 | ρ1 [mm] | ρ2 [mm] | μ* |", "|---" * 6 + "|"]
        lines += branch_rows(run, levels, eps[0][0] if eps else len(run["t"])) + [""]
    if not eps:
        lines += ["The bead never leaves the bottom ball.", ""]
        return "\n".join(lines)
    lines += ["Onset and climb: μ* = ln(T2/T1)/ψ on the last sample on the ball; the first slide ends at "
              "the first stick, stop or slack.", "",
              "| # | t [s] | ω_m [π] | μ* | ψ [rad] | T1, T2 [N] | first slide [mm] in [s] | highest [mm] at [s] | "
              "off the ball [s] | friction loss [J] | bead − φ: before → back on the ball [rad] | "
              "pair spin: before, off the ball [π rad/s] | ω_m off the ball [π rad/s] |",
              "|---" * 13 + "|"]
    rows = [climb_row(run, a, b) for a, b in eps]
    for k, r in enumerate(rows):
        lines.append(
            f"| {k} | {r['t']:.2f} | {r['omega']:.3f} | {r['mu_star']:.4f} | {r['psi']:.3f} | "
            f"{r['T1']:.3f}, {r['T2']:.3f} | {1e3 * r['slide']:.2f} in {r['t_slide']:.3f} | {1e3 * r['climb']:.2f} at {r['t_top']:.3f} | "
            f"{r['off']:.2f} | {r['friction']:.2e} | {r['lag_before']:+.2f} → {r['lag_end']:+.2f} | "
            f"{r['spin_before']:.2f}, {r['spin_during']:.2f} | {r['omega_during']:.2f} |")
    lines += ["", "Angular momentum about the motor axis from the onset to the highest point: L_z at both, "
              "and what a pair still locked to the motor would have at the highest point (ω_m Σ m ρ²); the "
              "torque that lock would need, (ω_m Σ m ρ² − L_z,onset)/Δt, against the motor's mean torque "
              "over the same time (P_motor/ω_m) and the most the upper string can pass at the onset "
              "(R T1 |u1,horizontal|).", "",
              "| # | L_z onset | L_z highest | L_z locked there [kg m²/s] | torque to stay locked | "
              "motor torque | string's bound [N m] |", "|---" * 7 + "|"]
    for k, r in enumerate(rows):
        lines.append(f"| {k} | {r['Lz_before']:.3e} | {r['Lz_top']:.3e} | {r['Lz_lock']:.3e} | "
                     f"{r['torque_needed']:.2e} | {r['torque_motor']:.2e} | {r['torque_max']:.2e} |")
    if run.get("couple_torque", 0.0) > 0:
        lines += ["", f"The pair against the motor and the pair couple (τ_c = {run['couple_torque']:g} N m, "
                  f"Ω_ε = {run['couple_slip_rate']:g} rad/s): the pair's phase (azimuth of r2 − r1 minus φ) from "
                  "the onset, the couple's work on the balls and its mean torque about z, over each climb.", "",
                  "| # | phase: max excursion [rad] | phase: change over the first second [rad] | "
                  "phase: change to the end [rad] | couple's work [J] | couple's torque about z [N m] |",
                  "|---" * 6 + "|"]
        for k, (a, b) in enumerate(eps):
            c = couple_row(run, a, b)
            lines.append(f"| {k} | {c['phase_max']:.3f} | {c['phase_1s']:+.3f} | {c['phase_end']:+.3f} | "
                         f"{c['couple_work']:.3e} | "
                         f"{c['couple_tz']:.2e} |")
    t0 = run["t"][eps[0][0] - 1]
    sel = (run["t"] >= t0 - before) & (run["t"] <= t0 + after)
    sub = {k: (v[sel] if isinstance(v, np.ndarray) and len(v) == len(run["t"]) else v) for k, v in run.items()}
    ledger_rows, _ = ledger(sub, window, window)
    lines += ["", f"Energy ledger from {before:g} s before the first onset to {after:g} s after it "
              "(run_ledger.py's columns):", "", "```", HEADER]
    lines += [fmt_row(r) for r in ledger_rows]
    lines += ["```", ""]
    return "\n".join(lines)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("inputs", nargs="+", help="HDF5 files from `astrojax run`")
    ap.add_argument("-o", "--output", help="Markdown report (default: stdout only)")
    ap.add_argument("--before", type=float, default=20.0, help="ledger start before the first onset [s]")
    ap.add_argument("--after", type=float, default=40.0, help="ledger end after the first onset [s]")
    ap.add_argument("--window", type=float, default=5.0, help="ledger window [s] (default 5)")
    ap.add_argument("--levels", default="", help="ω_m levels [π rad/s], comma-separated, at which to tabulate "
                    "the bottom-stop orbit before the first climb, e.g. 6,8,10,12")
    ap.add_argument("--tail", type=float, default=10.0, help="the final state over the last TAIL seconds (default 10)")
    args = ap.parse_args(argv)
    if not (args.before >= 0 and args.after > 0 and args.window > 0):
        ajx.fail("--before must be >= 0, --after and --window > 0 seconds")
    try:
        levels = [float(x) for x in args.levels.split(",") if x.strip()]
    except ValueError:
        ajx.fail(f"--levels {args.levels}: expected comma-separated numbers (π rad/s)")
    if not args.tail > 0:
        ajx.fail("--tail must be > 0 seconds")
    runs = [(p, read(p)) for p in args.inputs]
    text = "\n".join(report(p, run, args.before, args.after, args.window, levels) for p, run in runs)
    text += "\n".join(["", f"One row per run; the final state over the last {args.tail:g} s (module docstring).", ""]
                      + SUMMARY_HEADER + [summary_row(p, run, args.tail) for p, run in runs] + [""])
    if args.output:
        ajx.write_report(args.output, text)
    else:
        print(text)


if __name__ == "__main__":
    ajx.run(main)
