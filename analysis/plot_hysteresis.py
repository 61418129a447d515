#!/usr/bin/python3
"""Hysteresis diagram of a sweep: ω_ball against ω_m, one panel per model variant (a grouped
sweep such as sweeps/paper.toml) or per grid point.

Each classified window is a point at its mean ω_m, filled with its orbit class's colour. A
chain's windows are joined in protocol order: a solid line where ω_m rises, a dashed one where
it falls, with arrowheads along the path. In a grouped sweep each chain group has its own
marker (from rest, from the circular orbit, ...). The dotted diagonal ω_ball = ω_m is a
locked orbit. Windows whose ω_ball is undefined (both balls too near the axis for an azimuth:
the pair hangs almost straight below the motor) sit in a shaded strip of their own below the
axis, at their ω_m, and the paths run through it. The thresholds that `astrojax thresholds`
finds are grey spans, each labelled with its symbol, its chain group and its bracket; the paper's
measured ω_rise, ω_fall, ω1, ω2 are dashed black lines named on the top axis.

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


UNDEFINED = -1.6   # the strip of windows without an ω_ball [π rad/s], below the axis
STRIP = (-2.3, -0.9)


def draw_path(ax, x, y, direction):
    """The chain's path in protocol order: solid where ω_m rises, dashed where it falls, with
    arrowheads pointing along it; through the strip where ω_ball is undefined."""
    y = np.where(np.isfinite(y), y, UNDEFINED)
    for i in range(len(x) - 1):
        style = "--" if direction[i + 1] < 0 else "-"
        ax.plot(x[i:i + 2], y[i:i + 2], style, color="0.45", lw=0.7, zorder=1)
        if i % ARROW_EVERY == ARROW_EVERY // 2 and (x[i + 1] != x[i] or y[i + 1] != y[i]):
            mid = np.array([0.5 * (x[i] + x[i + 1]), 0.5 * (y[i] + y[i + 1])])
            step = 0.15 * np.array([x[i + 1] - x[i], y[i + 1] - y[i]])
            ax.annotate("", xy=mid + step, xytext=mid,
                        arrowprops={"arrowstyle": "-|>", "color": "0.3", "lw": 0.7, "mutation_scale": 9}, zorder=2)


def draw_thresholds(ax, sweep, rows, chains, paper):
    """Each chain's brackets as grey spans, labelled (symbol, chain group, bracket) upright in a
    white box hanging from the top, so that no line crosses a label; the paper's values as
    dashed lines named on a top axis."""
    labels = []
    for row in rows:
        c = int(row["chain"])
        if c not in chains:
            continue
        lo, hi = sorted((ajx.number(row["before_rad_s"]) / PI, ajx.number(row["after_rad_s"]) / PI))
        if not np.isfinite(lo):
            continue
        ax.axvspan(lo, hi, color=ajx.BRACKET_SHADE, lw=0, zorder=0)
        symbol = ajx.THRESHOLD_SYMBOLS.get(row["threshold"], row["threshold"])
        group = f" ({ajx.for_figure(sweep.group_name(c), 40)})" if sweep.is_grouped else ""
        labels.append((hi, f" {mathtext(symbol)}{group} {lo:.2f}–{hi:.2f}π", "left", "bold"))
    ajx.place_upright_labels(ax, labels)
    for t in ax.texts[-len(labels):] if labels else []:
        t.set_bbox({"facecolor": "white", "edgecolor": "none", "pad": 0.6, "alpha": 0.9})
        t.set_zorder(5)
    if paper:
        values = ajx.paper_values(rows)
        for p in values.values():
            ax.axvline(p / PI, zorder=1, **ajx.PAPER_LINE)
        top = ax.secondary_xaxis("top")
        top.set_xticks([p / PI for p in values.values()],
                       [f"paper {mathtext(ajx.THRESHOLD_SYMBOLS.get(n, n))}" for n in values], fontsize=7, rotation=90)
        top.tick_params(length=3, pad=1)


def mathtext(symbol):
    """'ω_rise' -> '$\\omega_{rise}$', 'ω1' -> '$\\omega_1$'."""
    name = symbol.replace("ω", "")
    return f"$\\omega_{{{name.lstrip('_')}}}$" if name else "$\\omega$"


def draw_panel(ax, sweep, chains, rows, paper):
    top = max(np.nanmax(sweep.omega_mean[c][sweep.valid[c]]) for c in chains)
    if paper:  # every paper value in view
        top = max([top] + list(ajx.paper_values(rows).values()))
    top = top / PI * 1.04
    ax.set_xlim(0, top)
    ax.axhspan(*STRIP, color="0.94", lw=0, zorder=0)
    ax.plot([0, top], [0, top], "k:", lw=0.8, zorder=1)
    undefined = False
    for c in chains:
        ks = sweep.windows(c)
        x = sweep.omega_mean[c, ks] / PI
        y = sweep.stats["omega_ball"][c, ks] / PI
        if not sweep.is_hold:
            draw_path(ax, x, y, sweep.direction[c, ks])
        for k, xk, yk in zip(ks, x, y):
            colour = sweep.class_colour(c, k)
            undefined |= not np.isfinite(yk)
            ax.plot(xk, yk if np.isfinite(yk) else UNDEFINED, marker(sweep, c, k), color=colour, ms=5, mec="k",
                    mew=0.3, zorder=3)
    draw_thresholds(ax, sweep, rows, chains, paper)
    ax.set_xlim(0, top)
    ax.set_ylim(STRIP[0], top)
    ticks = [t for t in ax.get_yticks() if 0 <= t <= top]
    ax.set_yticks([UNDEFINED] + ticks, ["undefined"] + [f"{t:g}" for t in ticks])
    ax.set_xlabel(r"motor $\omega_m$ [π rad/s]")
    ax.set_ylabel(r"balls' $\omega_{ball}$ [π rad/s]")
    ax.grid(True, color="0.92", lw=0.5, zorder=0)


def group_words(sweep, chains, i):
    """What a chain group does, read off its chains: where it starts and where ω_m goes."""
    cs = [c for c in chains if int(sweep.group[c]) == i]
    start = {"hanging": "from rest", "circular_high": "from Table 1's orbit"}.get(sweep.start_seed_name(cs[0]),
                                                                                  sweep.start_seed_name(cs[0]))
    ks = sweep.windows(cs[0])
    w = sweep.omega_mean[cs[0], ks] / PI
    first, last = sweep.omega_begin[cs[0], ks[0]] / PI, sweep.omega_end[cs[0], ks[-1]] / PI
    peak = int(np.argmax(w))
    if 0 < peak < len(w) - 1:
        path = f"up to {w[peak]:.3g}π, back to {last:.3g}π"
    else:
        path = f"{'up' if last > first else 'down'} to {last:.3g}π"
    return f"'{ajx.for_figure(sweep.group_names[i])}': {ajx.for_figure(start)} at {first:.3g}π, {path}"


def legend_handles(sweep, chains, rows, paper):
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    handles = []
    used = {sweep.class_name(c, k) for c in chains for k in sweep.windows(c)}
    for name, colour in sweep.class_colours.items():
        if name in used:
            handles.append(Line2D([], [], ls="", marker="o", ms=6, mec="k", mew=0.3, color=colour,
                                  label=ajx.for_figure(name)))
    if sweep.is_grouped:
        for i in sorted({int(sweep.group[c]) for c in chains}):
            handles.append(Line2D([], [], ls="", marker=ajx.GROUP_MARKERS[i % len(ajx.GROUP_MARKERS)], color="white",
                                  mec="k", mew=0.6, label=group_words(sweep, chains, i)))
    if sweep.is_hold:
        for i in sorted({int(sweep.seed[c]) for c in chains}):
            name = ajx.for_figure(sweep.seed_name(i))
            handles.append(Line2D([], [], ls="", marker=ajx.SEED_MARKERS[i % len(ajx.SEED_MARKERS)], color="white",
                                  mec="k", mew=0.6, label=f"held, seed {name}"))
    else:
        handles += [Line2D([], [], color="0.45", lw=0.9, ls="-", label=r"path, $\omega_m$ rising"),
                    Line2D([], [], color="0.45", lw=0.9, ls="--", label=r"path, $\omega_m$ falling")]
    handles.append(Line2D([], [], color="k", ls=":", lw=0.8, label=r"$\omega_{ball} = \omega_m$ (locked)"))
    handles.append(Patch(color="0.94", label=r"$\omega_{ball}$ undefined: both balls near the axis"))
    handles.append(Patch(color=ajx.BRACKET_SHADE, label="threshold bracket (astrojax thresholds), its chain group"))
    if paper:
        values = ", ".join(f"{mathtext(ajx.THRESHOLD_SYMBOLS.get(n, n))} {p / PI:.2f}π"
                           for n, p in ajx.paper_values(rows).items())
        handles.append(Line2D([], [], label=f"paper: {values}", **ajx.PAPER_LINE))
    return handles


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
    fig = ajx.new_figure(args, (width, 5.5 * nr + ajx.legend_height(width, len(handles) * ajx.legend_columns(width)
                                                                      // max(1, int(width / 4.3))) + 0.5))
    fig_width = fig.get_size_inches()[0]
    ncol = max(1, int(fig_width / 4.3))  # the long legend entries need 4.3 in each
    axes, leg = ajx.panels(fig, nr, nc, -(-len(handles) // ncol) * ajx.legend_columns(fig_width), sharey=True)
    for ax, (label, cs) in zip(axes.flat, groups):
        draw_panel(ax, sweep, cs, rows, not args.no_paper)
        ax.set_title(title(sweep, label, cs), fontsize=9)
    for ax in axes.flat[len(groups):]:
        ax.set_visible(False)
    leg.legend(handles=handles, loc="center", ncol=ncol, fontsize=7.5, frameon=False)
    fig.suptitle(r"Hysteresis of the balls' angular velocity $\omega_{ball}$ as the motor's $\omega_m$ is ramped or stepped",
                 fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    ajx.run(main)
