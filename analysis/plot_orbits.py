#!/usr/bin/python3
"""Orbit pictures like the paper's figures 7, 8 and 10: both balls' paths at chosen ω_m, seen
from the top and from the side, in the lab frame and in the frame turning with the motor.

One row per chosen orbit, four views: top (x, y) and side (x, z) in the lab frame; top and
side in the co-rotating frame, whose x' axis points along the motor's rod to the top of the
string. In the co-rotating frame a locked circular orbit is a point, a lagging one a circle
turning backwards, a flower orbit a rosette. The string at the last sample (top, bead,
bottom ball) is drawn in the co-rotating views; the drive circle of radius R in the lab's
top view.

From a sweep file: one stored window per --omega value (the nearest mean ω_m on --chain,
optionally only --direction up/down/held; on a hold sweep, among the chains of --chain's
grid point, seed and kick); by default one window per orbit class (the middle ω_m among
its most confident windows). The sweep does not store the
motor phase: it is recovered from the string (the top is at distance L1 from the bead)
and ∫ω_m dt.
--top draws only the top view in the lab frame, the orbits side by side, as the paper's Fig. 7
and 8 show them; --classes picks one window per named class (the default picks every class).
From a run file (`astrojax run`): the --tail seconds ending at the last time each --omega
value is reached, or ending at each --time; by default the end of the run.

usage: /usr/bin/python3 analysis/plot_orbits.py out/hold.h5 -o out/hold_orbits.png --chain 2 --omega 3,6,7.5
       /usr/bin/python3 analysis/plot_orbits.py out/paper.h5 -o out/paper_orbits.png --group up --variant clutch --direction up \
           --classes locked-circular,lagging-circular,flower --top
       /usr/bin/python3 analysis/plot_orbits.py out/quick.h5 -o orbits.pdf --chain 1 --omega 4,8,12 --direction down
       /usr/bin/python3 analysis/plot_orbits.py out/spin_up.h5 -o out/spin_up_orbits.png --omega 6,14 --tail 3
"""
import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
# The balls' colours: Tol's wine and indigo, apart from every orbit class's colour.
BEAD, BALL = "#882255", "#332288"
VIEWS = ("top, lab frame", "side, lab frame", "top, turning with the motor", "side, turning with the motor")


def number_list(text, what):
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        ajx.fail(f"{what}: '{text}' is not a comma-separated list of numbers")


def sweep_orbits(args):
    """[(title, samples with phi, R)] for the chosen windows of a sweep file."""
    sweep = ajx.Sweep(args.input)
    if args.group or args.variant:  # a grouped sweep's chain by its group and variant
        if not sweep.is_grouped:
            ajx.fail(f"--group/--variant: {args.input} has no chain groups or model variants")
        found = [c for c in range(sweep.n_chains) if (not args.group or sweep.group_name(c) == args.group) and
                 (not args.variant or sweep.variant_name(c) == args.variant)]
        if not found:
            ajx.fail(f"--group {args.group} --variant {args.variant}: no such chain in {args.input}; groups "
                     f"{', '.join(sweep.group_names)}, variants {', '.join(sweep.variant_names)}")
        args.chain = found[0]
    if not 0 <= args.chain < sweep.n_chains:
        ajx.fail(f"--chain {args.chain}: outside 0..{sweep.n_chains - 1} of {args.input}")
    c0 = args.chain
    # A hold sweep has one window per chain: choose among the chains of --chain's grid point,
    # seed and kick, one per held ω_m.
    same = [c for c in range(sweep.n_chains) if (sweep.grid[c] == sweep.grid[c0]).all() and
            sweep.seed[c] == sweep.seed[c0] and sweep.perturbation[c] == sweep.perturbation[c0]] \
        if sweep.is_hold else [c0]
    want = {"up": 1, "down": -1, "held": 0}.get(args.direction)
    cks = [(c, k) for c in same for k in sweep.windows(c) if want is None or sweep.direction[c, k] == want]
    if not cks:
        which = f" with direction {args.direction}" if want is not None else ""
        ajx.fail(f"{args.input}: chain {c0} has no classified window{which}")
    omega = lambda ck: sweep.omega_mean[ck]  # noqa: E731
    if args.omega:
        chosen = [min(cks, key=lambda ck: abs(omega(ck) - w * PI)) for w in number_list(args.omega, "--omega")]
    else:
        by_class = {}
        for ck in cks:
            by_class.setdefault(sweep.class_name(*ck), []).append(ck)
        best = {}
        for name, members in by_class.items():  # the middle ω_m among the class's most confident windows
            conf = np.array([sweep.stats["confidence"][ck] for ck in members])
            sure = [ck for ck, q in zip(members, conf) if q >= 0.9 * np.nanmax(conf)] if np.isfinite(conf).any() \
                else members
            sure.sort(key=omega)
            best[name] = sure[len(sure) // 2]
        if args.classes:
            wanted = [c.strip() for c in args.classes.split(",")]
            missing = [c for c in wanted if c not in best]
            if missing:
                ajx.fail(f"--classes: chain {c0} has no {', '.join(missing)} window"
                         f"{' with direction ' + args.direction if want is not None else ''}; it has "
                         f"{', '.join(sorted(best))}")
            best = {c: best[c] for c in wanted}
        chosen = sorted(best.values(), key=omega)[:6]
    out = []
    for c, k in chosen:
        R = sweep.parameter(c, "drive_radius")
        s = sweep.samples(c, k)
        if len(s["t"]) < 3:
            ajx.fail(f"{args.input}: window {k} of chain {c} stores {len(s['t'])} samples, too few to draw")
        if args.tail:
            keep = s["t"] >= s["t"][-1] - args.tail
            s = {n: v[keep] for n, v in s.items()}
        s["phi"] = ajx.window_phase(sweep, c, k, s)
        wb = sweep.stats["omega_ball"][c, k]
        arrow = {1: "▲", -1: "▼", 0: "●"}[int(sweep.direction[c, k])]
        if args.top:
            title = (f"{ajx.for_figure(sweep.class_name(c, k))}\n$\\omega_m$ = {sweep.omega_mean[c, k] / PI:.2f}π {arrow}, "
                     r"$\omega_{ball}$ = " + (f"{wb / PI:.2f}π rad/s" if np.isfinite(wb) else "undefined"))
        else:
            title = (f"{ajx.for_figure(sweep.chain_label(c), 200)}, window {k}: "
                     f"ω_m {sweep.omega_mean[c, k] / PI:.2f}π {arrow}, "
                     f"{ajx.for_figure(sweep.class_name(c, k))}, ω_ball " + (f"{wb / PI:.2f}π rad/s" if np.isfinite(wb) else "undefined"))
        out.append((title, s, R))
    args.subject = orbit_subject(sweep, [c for c, _ in chosen])
    args.arrows = sorted({int(sweep.direction[c, k]) for c, k in chosen})
    return out


def orbit_subject(sweep, chains):
    """What the orbits are of: the model variant and group with its parameters, 'R = .., d = ..'."""
    c = chains[0]
    who = (f"{ajx.for_figure(sweep.variant_label(c))}, chain group '{ajx.for_figure(sweep.group_name(c), 40)}'; "
           if sweep.is_grouped else (f"{ajx.for_figure(sweep.grid_label(c))}; " if sweep.grid_label(c) else ""))
    return who + sweep.parameter_title(c)


def run_orbits(args):
    """[(title, samples, R)] for the chosen stretches of a run file."""
    run = ajx.read_run(args.input)
    t = run["t"]
    tail = args.tail or 2.0
    if args.time:
        ends = number_list(args.time, "--time")
        bad = [e for e in ends if not t[0] < e <= t[-1]]
        if bad:
            ajx.fail(f"--time {bad}: outside the run's ({t[0]:g}, {t[-1]:g}] s")
    elif args.omega:
        ends = []
        for w in number_list(args.omega, "--omega"):
            gap = np.abs(run["omega_m"] - w * PI)
            ends.append(t[np.flatnonzero(gap <= gap.min() + 1e-9)[-1]])  # the last time ω_m is nearest
    else:
        ends = [t[-1]]
    out = []
    for end in ends:
        keep = (t >= end - tail) & (t <= end)
        if keep.sum() < 3:
            ajx.fail(f"{args.input}: fewer than 3 samples in the {tail:g} s before t = {end:g} s")
        s = {n: run[n][keep] for n in ("t", "omega_m", "phi", "L1", "mode", "r1", "r2")}
        R = float(ajx.run_parameter(args.input, "model.drive_radius"))
        w0, w1 = s["omega_m"][0] / PI, s["omega_m"][-1] / PI
        title = f"t = {s['t'][0]:.1f}–{s['t'][-1]:.1f} s, ω_m {w0:.2f}–{w1:.2f}π rad/s, R = {R * 1000:.3g} mm"
        out.append((title, s, R))
    return out


def draw_orbit(axes, s, R):
    cm = 100.0
    lab = {"bead": s["r1"], "bottom ball": s["r2"]}
    turn = {n: ajx.corotating(r, s["phi"]) for n, r in lab.items()}
    colours = {"bead": "tab:blue", "bottom ball": "tab:red"}
    for frame, paths, (ax_top, ax_side) in (("lab", lab, axes[:2]), ("turning", turn, axes[2:])):
        for name, r in paths.items():
            ax_top.plot(r[:, 0] * cm, r[:, 1] * cm, lw=0.7, color=colours[name])
            ax_side.plot(r[:, 0] * cm, r[:, 2] * cm, lw=0.7, color=colours[name])
            for ax, j in ((ax_top, 1), (ax_side, 2)):
                ax.plot(r[-1, 0] * cm, r[-1, j] * cm, "o", ms=4, color=colours[name])
        if frame == "lab":
            a = np.linspace(0, 2 * PI, 100)
            ax_top.plot(R * cm * np.cos(a), R * cm * np.sin(a), "k--", lw=0.6)
        else:  # the string at the last sample: top a = (R, 0, 0), bead, bottom ball
            string = np.array([[R, 0.0, 0.0], paths["bead"][-1], paths["bottom ball"][-1]]) * cm
            ax_top.plot(string[:, 0], string[:, 1], "-", color="0.4", lw=0.6, zorder=0)
            ax_side.plot(string[:, 0], string[:, 2], "-", color="0.4", lw=0.6, zorder=0)
            ax_top.plot(R * cm, 0, "k+", ms=6)
        ax_top.plot(0, 0, "kx", ms=4)
        ax_top.set_aspect("equal", adjustable="datalim")
        ax_top.set_xlabel("x [cm]" if frame == "lab" else "x' [cm]", fontsize=8)
        ax_top.set_ylabel("y [cm]" if frame == "lab" else "y' [cm]", fontsize=8)
        ax_side.set_xlabel("x [cm]" if frame == "lab" else "x' [cm]", fontsize=8)
        ax_side.set_ylabel("z [cm]", fontsize=8)
    for ax in axes:
        ax.tick_params(labelsize=7)


def top_views(args, orbits):
    """The orbits side by side, each from the top in the lab frame (the paper's Fig. 7, 8)."""
    from matplotlib.lines import Line2D
    cm = 100.0
    n = len(orbits)
    handles = [Line2D([], [], color=BEAD, marker="o", ms=4, label="bead (● last position)"),
               Line2D([], [], color=BALL, marker="o", ms=4, label="bottom ball (● last position)"),
               Line2D([], [], color="k", ls="--", lw=0.6, label="drive circle (radius R)"),
               Line2D([], [], color="k", marker="x", ls="", ms=4, label="motor axis")]
    words = {1: r"▲ $\omega_m$ rising", -1: r"▼ $\omega_m$ falling", 0: r"● $\omega_m$ held"}
    handles += [Line2D([], [], ls="", label=words[d]) for d in getattr(args, "arrows", [])]
    fig = ajx.new_figure(args, (3.6 * n, 4.6))
    axes, leg = ajx.panels(fig, 1, n, len(handles))
    axes = axes[0]
    lim = max(max(np.abs(s[k][:, :2]).max() for k in ("r1", "r2")) for _, s, _ in orbits) * cm * 1.08
    for ax, (title, s, R) in zip(axes, orbits):
        for name, colour in (("r1", BEAD), ("r2", BALL)):
            ax.plot(s[name][:, 0] * cm, s[name][:, 1] * cm, lw=0.7, color=colour)
            ax.plot(s[name][-1, 0] * cm, s[name][-1, 1] * cm, "o", ms=4, color=colour)
        a = np.linspace(0, 2 * PI, 100)
        ax.plot(R * cm * np.cos(a), R * cm * np.sin(a), "k--", lw=0.6)
        ax.plot(0, 0, "kx", ms=4)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        ax.set_xlabel("x [cm]", fontsize=8)
        ax.set_ylabel("y [cm]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.set_title(title, fontsize=8.5)
    ajx.legend(leg, handles)
    subject = getattr(args, "subject", "")
    fig.suptitle("Top view in the lab frame over one measured window" + (f"\n{subject}" if subject else ""),
                 fontsize=10)
    ajx.save(fig, args)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep` or `astrojax run`")
    ajx.add_figure_args(ap, "13 × (0.6 + 3.1 per orbit)")
    ap.add_argument("--omega", help="ω_m values to show, comma-separated [π rad/s]")
    ap.add_argument("--chain", type=int, default=0, help="sweep file: the chain (default 0)")
    ap.add_argument("--direction", choices=("up", "down", "held", "any"), default="any",
                    help="sweep file: only windows with ω_m rising, falling or held (default any)")
    ap.add_argument("--time", help="run file: end times of the stretches shown, comma-separated [s]")
    ap.add_argument("--tail", type=float, default=0.0,
                    help="seconds of path shown (default: the whole window of a sweep; 2 s of a run)")
    ap.add_argument("--group", help="grouped sweep file: the chain of this group (with --variant)")
    ap.add_argument("--variant", help="grouped sweep file: the chain of this model variant (with --group)")
    ap.add_argument("--classes", help="sweep file: one window of each of these classes, comma-separated "
                                      "(e.g. locked-circular,lagging-circular,flower)")
    ap.add_argument("--top", action="store_true", help="only the top view in the lab frame, the orbits side by side")
    args = ap.parse_args(argv)
    if args.tail < 0:
        ajx.fail(f"--tail {args.tail}: must be >= 0")

    ap_top = args.top
    orbits = sweep_orbits(args) if ajx.file_kind(args.input) == "sweep" else run_orbits(args)
    if ap_top:
        return top_views(args, orbits)
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color="tab:blue", marker="o", ms=4, label="bead (● last position)"),
               Line2D([], [], color="tab:red", marker="o", ms=4, label="bottom ball"),
               Line2D([], [], color="0.4", lw=0.6, label="string at the last sample"),
               Line2D([], [], color="k", ls="--", lw=0.6, label="drive circle (radius R)"),
               Line2D([], [], color="k", marker="+", ls="", label="top of the string"),
               Line2D([], [], color="k", marker="x", ls="", ms=4, label="motor axis")]
    legend_h = ajx.legend_height(13, len(handles))
    fig = ajx.new_figure(args, (13, 0.6 + 3.1 * len(orbits) + legend_h))
    height = fig.get_size_inches()[1]
    ratios = [(height - legend_h) / len(orbits)] * len(orbits) + [legend_h]
    subs = fig.subfigures(len(orbits) + 1, 1, height_ratios=ratios)
    for sub, (title, s, R) in zip(subs, orbits):
        row = sub.subplots(1, 4)
        draw_orbit(row, s, R)
        for ax, view in zip(row, VIEWS):
            ax.set_title(view, fontsize=8, style="italic")
        sub.suptitle(title, fontsize=9, x=0.01, ha="left")
    leg = subs[-1].add_subplot()
    leg.axis("off")
    ajx.legend(leg, handles)
    fig.suptitle("Orbits of the bead and the bottom ball: lab frame and the frame turning with the motor", fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    ajx.run(main)
