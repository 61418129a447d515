#!/usr/bin/python3
"""The paper's own scheme (integrator.method = "paper" / "paper_corrected") against the project's
event-driven model (DOP853), from the paper's Table 1 starts (docs/reports/paper_scheme.md).

  lag     Fig. 7(i) redone: each ω_m of --omegas (in π rad/s) held for --duration s from Table 1's
          circular orbit 1 (turning at --start-omega π rad/s, or with the motor: --start-with-motor); per model: ω_ball over the first
          --early s and over the last 10 s the run reached, the orbit radii, L1, the mean energy
          injection dE/dt - (P_motor - P_drag - P_fric) and the drag power; a figure of ω_ball
          against ω_m with the paper's reading (ω_ball = ω_m up to 4.8π, then 4.8π up to 15π).
  table1  Table 1's six starts (circular orbits 1-2 at --circular-omega, flower orbits 1-4 at
          --flower-omega, both in π rad/s) for --duration s with each model; top views of both
          balls over the first and the last --tail s, and a table of radii and ω_ball.

Models: paper, paper_corrected (the scheme's physics: kinetic point-contact friction, taut
string, no stops; h = 1/2000 s) and dop853 (the project's full model: stick-slip, slack string,
stops, capstan law, rtol 1e-9). Scene: sweeps/scenes/paper_table1.toml (R = 15 mm).

usage: /usr/bin/python3 analysis/paper_scheme.py lag -o out/paper_lag.png --report out/paper_lag.md
       /usr/bin/python3 analysis/paper_scheme.py table1 -o out/paper_table1.png --report out/paper_table1.md
"""
import math
import os
import re
import tempfile

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis.ledger import read_ledger

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "sweeps", "scenes", "paper_table1.toml")
FULL_MODEL = ["layers.friction=stick_slip", "layers.friction_law=capstan", "layers.slack=true",
              "layers.bottom_stop=true", "layers.top_stop=true", "integrator.method=dop853",
              "integrator.rtol=1e-9", "integrator.atol=1e-11"]
MODELS = {"paper": ["integrator.method=paper"], "paper_corrected": ["integrator.method=paper_corrected"],
          "dop853": FULL_MODEL}
COLOURS = {"paper": "tab:red", "paper_corrected": "tab:blue", "dop853": "k"}
EXTRA_SETS = []  # --set of the command line, after each model's own
MIN_RHO = 0.03  # [m] an orbit closer to the axis (2R) has no meaningful azimuth rate about it


def scene_text(omega, duration):
    """The scene with its one hold set to ω_m [rad/s] for `duration` s."""
    text = open(SCENE).read()
    text = re.sub(r"(\[\[schedule\]\][^\[]*?omega = )[0-9.eE+-]+", rf"\g<1>{omega!r}", text)
    return re.sub(r"(\[\[schedule\]\][^\[]*?duration = )[0-9.eE+-]+", rf"\g<1>{duration!r}", text)


def run(astrojax, work, name, omega, duration, model, sets):
    """One `astrojax run`; returns the output path and the status line (runs that fail are kept)."""
    toml = os.path.join(work, f"{name}.toml")
    with open(toml, "w") as f:
        f.write(scene_text(omega, duration))
    out = os.path.join(work, f"{name}.h5")
    cmd = [astrojax, "run", toml, "-q", "-o", out]
    for s in MODELS[model] + sets + EXTRA_SETS:
        cmd += ["--set", s]
    proc = ajx.run_checked(cmd, allowed=(0, 3))
    return out, proc.stdout.strip().splitlines()[0] if proc.stdout.strip() else "ok"


def read(path):
    d = read_ledger(path)
    d["status"] = ajx.as_text(d["summary"].get("status", "?"))
    return d


def omega_ball(d, t0, t1):
    """Mean slope of the unwrapped azimuths of both balls over [t0, t1] [rad/s]."""
    sel = (d["t"] >= t0) & (d["t"] <= t1)
    if sel.sum() < 3:
        return float("nan")
    rates = [np.polyfit(d["t"][sel], np.unwrap(np.arctan2(d[r][:, 1], d[r][:, 0]))[sel], 1)[0] for r in ("r1", "r2")]
    return 0.5 * sum(rates)


def ledger(d):
    """Mean injection, drag power and motor power over the whole run [W]."""
    t = d["t"]
    dt = t[-1] - t[0]
    delta = lambda k: d[k][-1] - d[k][0]
    inj = delta("energy") - (delta("motor_work") - delta("drag_loss") - delta("friction_loss") - delta("impact_loss"))
    return inj / dt, delta("drag_loss") / dt, delta("motor_work") / dt


def summary(d, early):
    t_end = d["t"][-1]
    tail = d["t"] >= t_end - 10.0
    inj, p_drag, p_motor = ledger(d)
    return dict(t_end=t_end, w_early=omega_ball(d, d["t"][0], min(early, t_end)) / math.pi,
                w_last=omega_ball(d, t_end - 10.0, t_end) / math.pi,
                rho1=np.hypot(d["r1"][tail, 0], d["r1"][tail, 1]).mean(),
                rho2=np.hypot(d["r2"][tail, 0], d["r2"][tail, 1]).mean(), L1=d["L1"][tail].mean(),
                injection=inj, p_drag=p_drag, p_motor=p_motor, ok=d["status"] == "ok")


def publish(lines, args):
    """The report's table on stdout, and into --report when given."""
    text = "\n".join(lines) + "\n"
    if args.report:
        ajx.write_report(args.report, text)
    print(text)


def lag(args, astrojax, work):
    omegas = [float(w) for w in args.omegas.split(",")]
    rows = []
    for w in omegas:
        for model in args.models.split(","):
            start = w if args.start_with_motor else args.start_omega
            path, _ = run(astrojax, work, f"lag_{model}_{w:g}", w * math.pi, args.duration, model,
                          [f"initial.omega={start * math.pi!r}"])
            rows.append(dict(omega_m=w, model=model, **summary(read(path), args.early)))
    turning = "ω_m" if args.start_with_motor else f"{args.start_omega:g}π"
    lines = [f"# ω_ball against ω_m from Table 1's circular orbit 1 (turning at {turning}), "
             f"{args.duration:g} s holds", "",
             f"| ω_m/π | model | reached [s] | ω_ball/π first {args.early:g} s | ω_ball/π last 10 s | ρ1, ρ2 [m] last 10 s "
             "| L1 [m] | injection [W] | P_drag [W] | P_motor [W] |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['omega_m']:g} | {r['model']} | {r['t_end']:.2f}{'' if r['ok'] else ' (failed)'} | "
                     f"{r['w_early']:.3f} | {r['w_last']:.3f} | {r['rho1']:.3f}, {r['rho2']:.3f} | {r['L1']:.3f} | "
                     f"{r['injection']:+.3e} | {r['p_drag']:.3e} | {r['p_motor']:+.2e} |")
    publish(lines, args)
    fig = ajx.new_figure(args, (14, 4.5))
    axes = fig.subplots(1, 3)
    panels = ((axes[0], "w_early", f"ω_ball over the first {args.early:g} s"),
              (axes[1], "w_last", f"ω_ball over the last 10 s reached\n(only orbits with ρ2 >= {100 * MIN_RHO:g} cm)"),
              (axes[2], "rho2", "bottom ball's radius ρ2 over the last 10 s"))
    for ax, key, title in panels:
        if key != "rho2":
            ax.plot([0, 4.8, 15], [0, 4.8, 4.8], color="0.7", lw=4, label="paper's Fig. 7(i) as described")
        for model in args.models.split(","):
            sel = [r for r in rows if r["model"] == model]
            value = lambda r: 100 * r["rho2"] if key == "rho2" else (r[key] if key == "w_early" or r["rho2"] >= MIN_RHO
                                                                   else float("nan"))
            ax.plot([r["omega_m"] for r in sel], [value(r) for r in sel], "o-", color=COLOURS[model], label=model)
            bad = [r for r in sel if not r["ok"]]
            ax.plot([r["omega_m"] for r in bad], [value(r) for r in bad], "x", color=COLOURS[model], ms=10)
        ax.set_xlabel("ω_m [π rad/s]")
        ax.set_title(title + ("" if key == "rho2" else " (× : run failed)"), fontsize=9)
        ax.set_ylabel("ρ2 [cm]" if key == "rho2" else "ω_ball [π rad/s]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    ajx.save(fig, args)


def table1(args, astrojax, work):
    orbits = ["circular1", "circular2", "flower1", "flower2", "flower3", "flower4"]
    models = args.models.split(",")
    rows, runs = [], {}
    for orbit in orbits:
        w = args.circular_omega if orbit.startswith("circular") else args.flower_omega
        for model in models:
            path, _ = run(astrojax, work, f"t1_{model}_{orbit}", w * math.pi, args.duration, model,
                          [f"initial.orbit={orbit}"])
            d = read(path)
            runs[orbit, model] = d
            a = d["summary"]
            moved = a.get("start_projection", float("nan"))
            try:
                start = (a["start_pair_length_excess"], a["start_pair_speed_bead"], a["start_pair_speed_ball"])
            except KeyError as e:
                raise ajx.SweepFileError(path, "/summary", f"attribute {e} missing (the paper scheme's start pair)") \
                    from None
            t_end = d["t"][-1]
            tail = d["t"] >= t_end - args.tail
            head = d["t"] <= d["t"][0] + args.tail
            rows.append(dict(orbit=orbit, omega=w, model=model, t_end=t_end, ok=d["status"] == "ok",
                             head=[100 * np.hypot(d[r][head, 0], d[r][head, 1]).mean() for r in ("r1", "r2")],
                             w_head=omega_ball(d, d["t"][0], d["t"][0] + args.tail) / math.pi,
                             rho1=np.hypot(d["r1"][tail, 0], d["r1"][tail, 1]).mean(),
                             rho2=np.hypot(d["r2"][tail, 0], d["r2"][tail, 1]).mean(),
                             z1=d["r1"][tail, 2].mean(), z2=d["r2"][tail, 2].mean(),
                             w=omega_ball(d, t_end - args.tail, t_end) / math.pi, moved=moved, start=start))
    lines = ["# Table 1's pairs as read (mirrored y -> -y; R from the scene)", "",
             "| orbit | L1 + L2 - l at q^(0) [cm] | bead speed |q^(1) - q^(0)|/h [m/s] | bottom ball's [m/s] |",
             "|---|---|---|---|"]
    for r in rows[::len(models)]:
        lines.append(f"| {r['orbit']} | {100 * r['start'][0]:+.2f} | {r['start'][1]:.2f} | {r['start'][2]:.2f} |")
    lines += ["", f"# Table 1's starts, {args.duration:g} s: radii and ω_ball over the first {args.tail:g} s and over "
              f"the last {args.tail:g} s reached", "",
             "| orbit | ω_m/π | model | reached [s] | first: ρ1, ρ2 [cm] | first: ω_ball/π | last: ρ1 [cm] | ρ2 [cm] | "
             "z1 [cm] | z2 [cm] | ω_ball/π | start moved onto L1+L2=l [cm] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['orbit']} | {r['omega']:g} | {r['model']} | {r['t_end']:.2f}{'' if r['ok'] else ' (failed)'} | "
                     f"{r['head'][0]:.1f}, {r['head'][1]:.1f} | {r['w_head']:.2f} | {100 * r['rho1']:.1f} | {100 * r['rho2']:.1f} | {100 * r['z1']:.1f} | {100 * r['z2']:.1f} | "
                     f"{r['w']:.2f} | {100 * r['moved']:.2f} |")
    publish(lines, args)
    fig = ajx.new_figure(args, (2.6 * 2 * len(models), 2.6 * len(orbits)))
    axes = fig.subplots(len(orbits), 2 * len(models), squeeze=False)
    for i, orbit in enumerate(orbits):
        for j, model in enumerate(models):
            d = runs[orbit, model]
            t_end = d["t"][-1]
            windows = ((d["t"] <= d["t"][0] + args.tail, f"first {args.tail:g} s"),
                       (d["t"] >= t_end - args.tail, f"last {args.tail:g} s to {t_end:.1f} s"))
            for w, (sel, label) in enumerate(windows):
                ax = axes[i][2 * j + w]
                ax.plot(100 * d["r1"][sel, 0], 100 * d["r1"][sel, 1], lw=0.7, color="tab:orange", label="bead")
                ax.plot(100 * d["r2"][sel, 0], 100 * d["r2"][sel, 1], lw=0.7, color="tab:blue", label="bottom ball")
                ax.plot([0], [0], "k+", ms=6)
                lim = 1.1 * max(5.0, 100 * np.abs(np.concatenate([d["r1"][sel, :2], d["r2"][sel, :2]])).max())
                ax.set_xlim(-lim, lim)
                ax.set_ylim(-lim, lim)
                ax.set_aspect("equal")
                ax.grid(alpha=0.3)
                ax.tick_params(labelsize=6)
                failed = "" if d["status"] == "ok" else " (failed)"
                ax.set_title(f"{orbit}, {model}{failed}\n{label}", fontsize=7)
                if j == 0 and w == 0:
                    ax.set_ylabel("y [cm]", fontsize=7)
                if i == len(orbits) - 1:
                    ax.set_xlabel("x [cm]", fontsize=7)
    axes[0][0].legend(fontsize=6, loc="lower left")
    ajx.save(fig, args)


def main(argv=None):
    ap = ajx.parser(__doc__)
    sub = ap.add_subparsers(dest="what", required=True)
    a = sub.add_parser("lag", help="ω_ball against ω_m (Fig. 7(i))")
    a.add_argument("--omegas", default="3.5,4,4.5,4.8,5,6,8,10,12,14,15,16", help="ω_m list [π rad/s]")
    a.add_argument("--start-omega", type=float, default=4.8, help="Table 1 orbit's turning rate θ/h [π rad/s]")
    a.add_argument("--start-with-motor", action="store_true", help="the orbit starts turning at ω_m instead")
    a.add_argument("--duration", type=float, default=60.0, help="hold [s] (default 60)")
    a.add_argument("--early", type=float, default=2.0, help="the first window [s] (default 2)")
    b = sub.add_parser("table1", help="Table 1's six starts, top views")
    b.add_argument("--circular-omega", type=float, default=4.8, help="ω_m of circular orbits 1-2 [π rad/s]")
    b.add_argument("--flower-omega", type=float, default=16.0, help="ω_m of flower orbits 1-4 [π rad/s]")
    b.add_argument("--duration", type=float, default=20.0, help="run length [s] (default 20)")
    b.add_argument("--tail", type=float, default=2.0,
                   help="radii over the last [s]; top views of the first and the last [s] (default 2)")
    for p in (a, b):
        ajx.add_figure_args(p, "as the panels need")
        p.add_argument("--report", default=None, help="write the table (markdown) here too")
        p.add_argument("--models", default="paper,paper_corrected,dop853", help="models, comma separated")
        p.add_argument("--astrojax", default=None, help="the astrojax executable (default: build/astrojax)")
        p.add_argument("--keep", default=None, help="keep the run files in this folder")
        p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="override for every run (e.g. model.drive_radius=0.04), repeatable")
    args = ap.parse_args(argv)
    for m in args.models.split(","):
        if m not in MODELS:
            ajx.fail(f"--models: '{m}' is not one of {', '.join(MODELS)}")
    ajx.check_output(args.output)
    EXTRA_SETS.extend(args.set)
    astrojax = ajx.require_astrojax(args.astrojax)
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
        (lag if args.what == "lag" else table1)(args, astrojax, args.keep)
    else:
        with tempfile.TemporaryDirectory() as work:
            (lag if args.what == "lag" else table1)(args, astrojax, work)


if __name__ == "__main__":
    ajx.run(main)
