#!/usr/bin/python3
"""Where the bead climbs and falls: the bead position L1 and the orbit radius of both balls
against ω_m, on the same branches as the hysteresis diagram, one column per grid point.

Top row: the bead's mean position s = L1 along the string (bars from its smallest to its
largest value in the window; the axis points up the string, so a climbing bead goes up).
Bottom row: the mean horizontal radius of the bead (filled markers) and of the bottom ball
(open markers). Colour: orbit class; marker: direction (▲ rising, ▼ falling, held by seed).
Threshold brackets from `astrojax thresholds` are shaded.

usage: /usr/bin/python3 analysis/plot_branches.py out/quick.h5 -o out/quick_branches.png
"""

import astrojax_analysis as ajx

PI = ajx.PI


def draw_column(ax_l, ax_r, sweep, chains, rows):
    ajx.draw_thresholds(ax_l, rows, chains, paper=False)
    ajx.draw_thresholds(ax_r, rows, chains, paper=False)
    st = sweep.stats
    for c in chains:
        ks = sweep.windows(c)
        x = sweep.omega_mean[c, ks] / PI
        if not sweep.is_hold:
            ax_l.plot(x, st["L1_mean"][c, ks] * 100, "-", color="0.75", lw=0.6, zorder=1)
        for k, xk in zip(ks, x):
            colour = sweep.class_colour(c, k)
            m = sweep.marker(c, k)
            lo, mean, hi = (st[n][c, k] * 100 for n in ("L1_min", "L1_mean", "L1_max"))
            ax_l.errorbar(xk, mean, yerr=[[mean - lo], [hi - mean]], fmt=m, color=colour, ms=4, mec="k", mew=0.3,
                          elinewidth=0.6, zorder=3)
            ax_r.plot(xk, st["radius_bead_mean"][c, k] * 100, m, color=colour, ms=4, mec="k", mew=0.3, zorder=3)
            ax_r.plot(xk, st["radius_bottom_mean"][c, k] * 100, m, color=colour, mfc="none", ms=4, mew=0.8, zorder=3)
    ax_l.set_ylabel("bead position L1 [cm]")
    ax_l.invert_yaxis()  # up the string is up
    ax_r.set_ylabel("orbit radius [cm]")
    ax_r.set_xlabel("ω_m [π rad/s]")
    ax_r.set_xlim(left=0)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ajx.add_figure_args(ap, "5.5 wide per grid point × 6.5")
    ap.add_argument("--chains", default="all", help="comma-separated chain indices to draw (default: all)")
    ajx.add_threshold_args(ap)
    args = ap.parse_args(argv)

    sweep, chains, rows, groups = ajx.sweep_for_plot(args)
    from matplotlib.lines import Line2D
    handles = sweep.legend_handles(chains)
    handles += [Line2D([], [], ls="", marker="o", color="k", label="bead"),
                Line2D([], [], ls="", marker="o", color="k", mfc="none", label="bottom ball")]
    handles += ajx.threshold_legend_handles(rows, paper=False)
    width = 5.5 * len(groups)
    fig = ajx.new_figure(args, (width, 6.5 + ajx.legend_height(width, len(handles))))
    axes, leg = ajx.panels(fig, 2, len(groups), len(handles), sharex=True)
    for j, (label, cs) in enumerate(groups):
        draw_column(axes[0, j], axes[1, j], sweep, cs, rows)
        axes[0, j].set_title(label if len(cs) > 1 else ajx.for_figure(sweep.chain_label(cs[0]), 200), fontsize=9, pad=12)
    ajx.legend(leg, handles)
    fig.suptitle(f"{args.input}: bead position and orbit radius along the branches", fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    ajx.run(main)
