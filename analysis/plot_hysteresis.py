#!/usr/bin/python3
"""Hysteresis diagram of a sweep: ω_ball against ω_m, one panel per grid point.

Each classified window is a point at its mean ω_m, coloured by orbit class and marked by
direction (▲ ω_m rising, ▼ falling; held windows of the hold mode by seed). A thin line joins
a chain's windows in protocol order. The diagonal ω_ball = ω_m is a locked orbit. Windows
whose ω_ball is undefined (balls near the axis, sampling too coarse) sit on the lower axis
as ×. Each chain's thresholds from `astrojax thresholds` are shaded spans (the bracket), the
paper's measured ω_rise, ω_fall, ω1, ω2 dashed lines.

usage: /usr/bin/python3 analysis/plot_hysteresis.py out/quick.h5 -o out/quick_hysteresis.png
       /usr/bin/python3 analysis/plot_hysteresis.py out/paper.h5 -o paper.pdf --chains 0,2
"""
import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI


def draw_panel(ax, sweep, chains, rows, paper):
    top = max(np.nanmax(sweep.omega_mean[c][sweep.valid[c]]) for c in chains)
    if paper:  # every paper value in view
        top = max([top] + list(ajx.paper_values(rows).values()))
    top = top / PI * 1.05
    ajx.draw_thresholds(ax, rows, chains, paper=paper)
    ax.plot([0, top], [0, top], "k:", lw=0.8)
    for c in chains:
        ks = sweep.windows(c)
        x = sweep.omega_mean[c, ks] / PI
        y = sweep.stats["omega_ball"][c, ks] / PI
        if not sweep.is_hold:
            ax.plot(x, y, "-", color="0.75", lw=0.6, zorder=1)
        for k, xk, yk in zip(ks, x, y):
            colour = ajx.CLASS_COLOURS.get(sweep.class_name(c, k), "k")
            if np.isfinite(yk):
                ax.plot(xk, yk, sweep.marker(c, k), color=colour, ms=5, mec="k", mew=0.3, zorder=3)
            else:
                ax.plot(xk, 0.0, "x", color=colour, ms=5, zorder=3)
    ax.set_xlim(0, top)
    ax.set_ylim(bottom=-0.3)
    ax.set_xlabel("ω_m [π rad/s]")
    ax.set_ylabel("ω_ball [π rad/s]")


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ajx.add_figure_args(ap, "5.5 × 4.5 per panel")
    ap.add_argument("--chains", default="all", help="comma-separated chain indices to draw (default: all)")
    ap.add_argument("--no-paper", action="store_true", help="leave out the paper's measured values")
    ajx.add_threshold_args(ap)
    args = ap.parse_args(argv)

    sweep, chains, rows, groups = ajx.sweep_for_plot(args)
    nr, nc = ajx.panel_grid(len(groups))
    from matplotlib.lines import Line2D
    handles = sweep.legend_handles(chains) + [Line2D([], [], color="k", ls=":", lw=0.8, label="ω_ball = ω_m")]
    handles += ajx.threshold_legend_handles(rows, not args.no_paper)
    width = 5.5 * nc
    fig = ajx.new_figure(args, (width, 4.5 * nr + ajx.legend_height(width, len(handles)) + 0.4))
    axes, leg = ajx.panels(fig, nr, nc, len(handles), sharey=True)
    for ax, (label, cs) in zip(axes.flat, groups):
        draw_panel(ax, sweep, cs, rows, not args.no_paper)
        ax.set_title(label if len(cs) > 1 else sweep.chain_label(cs[0]), fontsize=9, pad=12)
    for ax in axes.flat[len(groups):]:
        ax.set_visible(False)
    ajx.legend(leg, handles)
    fig.suptitle(f"{args.input}: hysteresis of ω_ball", fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    main()
