#!/usr/bin/python3
"""Hysteresis diagram of a sweep: ω_ball against ω_m, one panel per model variant (a grouped
sweep such as sweeps/paper.toml) or per grid point.

Each classified window is a point at its mean ω_m, filled with its orbit class's colour. A
chain's windows are joined in protocol order: a solid line where ω_m rises, a dashed one where
it falls, with arrowheads along the path. In a grouped sweep each chain group has its own
marker (from rest, from the circular orbit, ...). The dotted diagonal ω_ball = ω_m is a
locked orbit. Windows whose ω_ball is undefined (balls near the axis) sit on the lower axis as
×. The thresholds that `astrojax thresholds` finds are grey spans labelled with their bracket,
the paper's measured ω_rise, ω_fall, ω1, ω2 dashed black lines.

usage: /usr/bin/python3 analysis/plot_hysteresis.py out/paper.h5 -o out/paper_hysteresis.png
       /usr/bin/python3 analysis/plot_hysteresis.py out/quick.h5 -o quick.pdf --chains 0
"""
import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
ARROW_EVERY = 4  # an arrowhead on every 4th segment of a chain's path


def marker(sweep, c, k):
    """By chain group in a grouped sweep, by seed on a hold sweep's held windows, else a dot."""
    if sweep.is_grouped:
        return ajx.GROUP_MARKERS[int(sweep.group[c]) % len(ajx.GROUP_MARKERS)]
    if sweep.is_hold and int(sweep.direction[c, k]) == 0:
        return ajx.SEED_MARKERS[int(sweep.seed[c]) % len(ajx.SEED_MARKERS)]
    return "o"


def draw_path(ax, x, y, direction):
    """The chain's path in protocol order: solid where ω_m rises, dashed where it falls, with
    arrowheads pointing along it; broken where ω_ball is undefined."""
    for i in range(len(x) - 1):
        if not (np.isfinite(y[i]) and np.isfinite(y[i + 1])):
            continue
        style = "--" if direction[i + 1] < 0 else "-"
        ax.plot(x[i:i + 2], y[i:i + 2], style, color="0.45", lw=0.7, zorder=1)
        if i % ARROW_EVERY == ARROW_EVERY // 2 and (x[i + 1] != x[i] or y[i + 1] != y[i]):
            mid = np.array([0.5 * (x[i] + x[i + 1]), 0.5 * (y[i] + y[i + 1])])
            step = 0.15 * np.array([x[i + 1] - x[i], y[i + 1] - y[i]])
            ax.annotate("", xy=mid + step, xytext=mid,
                        arrowprops={"arrowstyle": "-|>", "color": "0.3", "lw": 0.7, "mutation_scale": 9}, zorder=2)


def draw_panel(ax, sweep, chains, rows, paper):
    top = max(np.nanmax(sweep.omega_mean[c][sweep.valid[c]]) for c in chains)
    if paper:  # every paper value in view
        top = max([top] + list(ajx.paper_values(rows).values()))
    top = top / PI * 1.04
    ax.set_xlim(0, top)
    ajx.draw_thresholds(ax, rows, chains, paper=paper, values=True)
    ax.plot([0, top], [0, top], "k:", lw=0.8, zorder=1)
    for c in chains:
        ks = sweep.windows(c)
        x = sweep.omega_mean[c, ks] / PI
        y = sweep.stats["omega_ball"][c, ks] / PI
        if not sweep.is_hold:
            draw_path(ax, x, y, sweep.direction[c, ks])
        for k, xk, yk in zip(ks, x, y):
            colour = sweep.class_colour(c, k)
            if np.isfinite(yk):
                ax.plot(xk, yk, marker(sweep, c, k), color=colour, ms=5, mec="k", mew=0.3, zorder=3)
            else:
                ax.plot(xk, 0.0, "x", color=colour, ms=5, zorder=3)
    ax.set_xlim(0, top)
    ax.set_ylim(bottom=-0.3)
    ax.set_xlabel("motor ω_m [π rad/s]")
    ax.set_ylabel("balls' ω_ball [π rad/s]")
    ax.grid(True, color="0.92", lw=0.5, zorder=0)


def legend_handles(sweep, chains, rows, paper):
    from matplotlib.lines import Line2D
    handles = []
    used = {sweep.class_name(c, k) for c in chains for k in sweep.windows(c)}
    for name, colour in sweep.class_colours.items():
        if name in used:
            handles.append(Line2D([], [], ls="", marker="o", ms=6, mec="k", mew=0.3, color=colour,
                                  label=ajx.for_figure(name)))
    if sweep.is_grouped:
        for i in sorted({int(sweep.group[c]) for c in chains}):
            starts = {sweep.start_seed_name(c) for c in chains if int(sweep.group[c]) == i}
            start = {"hanging": "from rest", "circular_high": "from Table 1's orbit"}.get(min(starts), min(starts))
            handles.append(Line2D([], [], ls="", marker=ajx.GROUP_MARKERS[i % len(ajx.GROUP_MARKERS)], color="0.6",
                                  mec="k", mew=0.3, label=f"'{ajx.for_figure(sweep.group_names[i])}': {ajx.for_figure(start)}"))
    if sweep.is_hold:
        for i in sorted({int(sweep.seed[c]) for c in chains}):
            name = ajx.for_figure(sweep.seed_name(i))
            handles.append(Line2D([], [], ls="", marker=ajx.SEED_MARKERS[i % len(ajx.SEED_MARKERS)], color="0.6",
                                  mec="k", mew=0.3, label=f"held, seed {name}"))
    else:
        handles += [Line2D([], [], color="0.45", lw=0.9, ls="-", label="path, ω_m rising"),
                    Line2D([], [], color="0.45", lw=0.9, ls="--", label="path, ω_m falling")]
    handles.append(Line2D([], [], color="k", ls=":", lw=0.8, label="ω_ball = ω_m (locked)"))
    return handles + ajx.threshold_legend_handles(rows, paper)


def title(sweep, label, cs):
    """A panel's title in symbols and units, never a file path."""
    if sweep.is_grouped:
        return f"{label}\n{sweep.parameter_title(cs[0])}"
    return label if len(cs) > 1 else ajx.for_figure(sweep.chain_label(cs[0]), 200)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ajx.add_figure_args(ap, "6.5 × 5.5 per panel")
    ap.add_argument("--chains", default="all", help="comma-separated chain indices to draw (default: all)")
    ap.add_argument("--no-paper", action="store_true", help="leave out the paper's measured values")
    ajx.add_threshold_args(ap)
    args = ap.parse_args(argv)

    sweep, chains, rows, groups = ajx.sweep_for_plot(args)
    nr, nc = ajx.panel_grid(len(groups))
    handles = legend_handles(sweep, chains, rows, not args.no_paper)
    width = 6.5 * nc
    fig = ajx.new_figure(args, (width, 5.5 * nr + ajx.legend_height(width, len(handles)) + 0.5))
    axes, leg = ajx.panels(fig, nr, nc, len(handles), sharey=True)
    for ax, (label, cs) in zip(axes.flat, groups):
        draw_panel(ax, sweep, cs, rows, not args.no_paper)
        ax.set_title(title(sweep, label, cs), fontsize=9)
    for ax in axes.flat[len(groups):]:
        ax.set_visible(False)
    ajx.legend(leg, handles)
    fig.suptitle("Hysteresis of the balls' angular velocity ω_ball as the motor's ω_m is ramped or stepped",
                 fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    ajx.run(main)
