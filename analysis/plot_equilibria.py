#!/usr/bin/python3
"""Branch diagram of locked circular orbits written by `astrojax orbits ... --continue omega -o FILE`.

Two panels against ω_m (or the continued parameter): the bead's distance from the motor axis
(ρ1), and the bead's position along the string (s = L1). Each branch of the continuation is a
line: solid where the orbit is linearly stable, dashed where it is unstable; drawn bold where
the static friction cone holds the bead (admissible), thin and pale where it does not. Events
are marked: folds (●), cone exits (▲ the bead would slide up, ▼ down), Hopf-type crossings
(★), stability changes through a real eigenvalue (◆). The paper's thresholds are vertical lines.

With --sweep FILE (a sweep's HDF5, e.g. out/quick.h5) the sweep's windows are overlaid: the
mean bead radius and L1 of every window at its mean ω_m, coloured by orbit class, so that the
brute-force hysteresis loop and the branches can be read together.

Run with Debian's interpreter (it has numpy, h5py and matplotlib):
    build/astrojax orbits sweeps/orbits.toml --continue omega --s 0.5443 --range 3 63 -o out/orbits.h5
    /usr/bin/python3 analysis/plot_equilibria.py out/orbits.h5 -o out/branches.png --sweep out/quick.h5
"""
import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis.orbits import read_branches

PAPER = {"ω_rise": 12.63, "ω_fall": 3.24, "ω1": 4.80, "ω2": 15.00}  # [π rad/s], the paper's measured thresholds
CASES = ["stuck", "bottom_stop", "frictionless", "cone_up", "cone_down"]
CASE_COLOURS = ["tab:blue", "tab:grey", "tab:green", "tab:orange", "tab:red"]
EVENT_MARKERS = {
    "fold": ("o", "black"),
    "cone_exit_up": ("^", "tab:red"),
    "cone_exit_down": ("v", "tab:red"),
    "hopf": ("*", "magenta"),
    "stability_loss": ("D", "tab:purple"),
    "stability_gain": ("D", "tab:purple"),
    "branch_point": ("X", "tab:brown"),
    "slack": ("s", "tab:olive"),
}



def draw_branch(axes, x, ys, stable, admissible, colour, pi_units):
    key = stable.astype(int) * 2 + admissible.astype(int)
    for i, j, k in ajx.runs(key):
        sl = slice(i, min(j + 2, len(x)))  # overlap one point so that the line is continuous
        st, adm = k // 2, k % 2
        for ax, y in zip(axes, ys):
            ax.plot(x[sl] / (np.pi if pi_units else 1), y[sl], color=colour, lw=2.0 if adm else 0.8,
                    alpha=1.0 if adm else 0.4, ls="-" if st else "--")


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax orbits ... --continue PARAM -o FILE`")
    ap.add_argument("-o", "--output", required=True, help="image to write (.png or .pdf)")
    ap.add_argument("--sweep", help="a sweep's HDF5 file to overlay (windows as points)")
    ap.add_argument("--branches", default="all", help="comma-separated branch ids to draw (default: all)")
    args = ap.parse_args(argv)

    ajx.check_output(args.output)
    param, p, e, kinds = read_branches(args.input)
    sweep = ajx.Sweep(args.sweep) if args.sweep else None
    plt = ajx.pyplot()
    pi_units = param == "omega"
    fig, (ax_r, ax_s) = plt.subplots(2, 1, figsize=(9, 8), sharex=True)
    ids = np.unique(p["branch_id"]).astype(int)
    if args.branches != "all":
        try:
            ids = [int(i) for i in args.branches.split(",")]
        except ValueError:
            ajx.fail(f"--branches: '{args.branches}' is not 'all' or comma-separated branch ids")
    for b in ids:
        m = p["branch_id"] == b
        if not np.any(m):
            continue
        case = int(p["case"][m][0])
        draw_branch((ax_r, ax_s), p["lambda"][m], (p["rho1"][m], p["s"][m]), p["stable"][m] > 0,
                    p["admissible"][m] > 0, CASE_COLOURS[case], pi_units)
    seen = set()
    for i, kind in enumerate(kinds):
        if int(e["branch_id"][i]) not in ids:
            continue
        marker, colour = EVENT_MARKERS.get(kind, ("x", "black"))
        x = e["lambda"][i] / (np.pi if pi_units else 1)
        label = ajx.for_figure(kind) if kind not in seen else None
        seen.add(kind)
        ax_r.plot(x, e["rho1"][i], marker, color=colour, ms=8, mfc="none" if kind == "fold" else colour, label=label)
        ax_s.plot(x, e["s"][i], marker, color=colour, ms=8, mfc="none" if kind == "fold" else colour)

    if sweep is not None:
        cls = sweep.cls.ravel()
        wm = sweep.omega_mean.ravel()
        rb = sweep.stats["radius_bead_mean"].ravel() if "radius_bead_mean" in sweep.stats else np.full(cls.shape, np.nan)
        L1 = sweep.stats["L1_mean"].ravel() if "L1_mean" in sweep.stats else np.full(cls.shape, np.nan)
        for c, name in sweep.class_names.items():
            m = (cls == c) & np.isfinite(wm)
            if np.any(m):
                colour = sweep.class_colours.get(name, "black")
                ax_r.scatter(wm[m] / np.pi, rb[m], s=10, color=colour, alpha=0.5, label=f"sweep: {ajx.for_figure(name)}")
                ax_s.scatter(wm[m] / np.pi, L1[m], s=10, color=colour, alpha=0.5)

    if pi_units:
        for name, v in PAPER.items():
            for ax in (ax_r, ax_s):
                ax.axvline(v, color="k", lw=0.6, ls=":")
            ax_r.text(v, 1.0, f" {name}", transform=ax_r.get_xaxis_transform(), fontsize=8, va="bottom")
    ax_r.set_ylabel("bead radius ρ1 [m]")
    ax_s.set_ylabel("bead position s = L1 [m]")
    ax_s.set_xlabel("ω_m [π rad/s]" if pi_units else ajx.for_figure(param))
    for ax in (ax_r, ax_s):
        ax.grid(alpha=0.3)
    handles = [plt.Line2D([], [], color=c, lw=2, label=n) for n, c in zip(CASES, CASE_COLOURS)]
    handles += [plt.Line2D([], [], color="k", lw=2, ls="-", label="stable, held by friction"),
                plt.Line2D([], [], color="k", lw=2, ls="--", label="unstable"),
                plt.Line2D([], [], color="k", lw=0.8, alpha=0.4, label="outside the friction cone")]
    h2, _ = ax_r.get_legend_handles_labels()
    ax_r.legend(handles=handles + h2, fontsize=7, ncol=2, loc="upper right")
    fig.suptitle(f"Locked orbits continued in {ajx.for_figure(param)}")
    fig.tight_layout()
    fig.savefig(args.output, dpi=130)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    ajx.run(main)
