#!/usr/bin/python3
"""Basins of the coexisting orbits against ω_m, from a sweep with basin groups
(sweeps/basins.toml): one column per basin group and model variant.

Top: the fraction of starts ending on each attractor at each level, stacked bottom to top in
the order the attractors first appear, each band in its orbit class's colour (a second
attractor of one class hatched); the bar at each band's upper edge is the 95 % Wilson interval
of that band's width. The attractors are the file's own (/basins/attractors: matched across ω_m
by the program when the sweep finished, src/sweep/basin_match.hpp). Above the bands, with
--paper, the main job's seeded chains of the same variant (out/paper.h5: rise from rest, up
and fall from Table 1's orbit), one row each, every window a mark at its ω_m in its class's
colour (▲ ω_m rising, ▼ falling). Bottom: the probability that the bead is up (any orbit but
fallen; not-settled and failed count as not up), with its Wilson interval shaded. Dashed: the
paper's measured ω_rise = 12.63π and ω_fall = 3.24π.

usage: /usr/bin/python3 analysis/plot_basins.py out/basins.h5 --paper out/paper.h5 -o out/basins.png
       /usr/bin/python3 analysis/plot_basins.py out/basins.h5 --table     (the numbers, as text)
"""
import warnings

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis import basins as bs
from astrojax_analysis.fit import PAPER

PI = ajx.PI
HATCHES = [None, "///", "\\\\\\", "xx", "..", "++"]
SEEDED_MARKS = {1: "^", -1: "v", 0: "o"}


def part_title(sweep, part):
    c = int(sweep.basins["chain"][sweep.basins["levels"]["first"][sweep.basins["levels"]["part"] == part][0]])
    return c, sweep.group_name(c), sweep.variant_name(c)


def draw_bands(ax, sweep, table):
    x = table["omega_m"] / PI
    colours = sweep.class_colours
    bottom = np.zeros(len(x))
    seen = {}
    handles = []
    for j, (label, cls) in enumerate(zip(table["labels"], table["classes"])):
        f = np.nan_to_num(table["fraction"][:, j])
        k = seen.get(cls, 0)
        seen[cls] = k + 1
        # A step per level (each level is its own set of starts, nothing lies between levels).
        poly = ax.fill_between(x, bottom, bottom + f, step="mid", color=colours.get(cls, "#777777"), alpha=0.85,
                               hatch=HATCHES[k % len(HATCHES)], edgecolor="white", lw=0.0, label=label)
        handles.append(poly)
        top = bottom + f
        lo = top - (f - np.nan_to_num(table["lower"][:, j]))
        hi = top + (np.nan_to_num(table["upper"][:, j]) - f)
        shown = f > 0
        ax.errorbar(x[shown], top[shown], yerr=[top[shown] - lo[shown], hi[shown] - top[shown]], fmt="none",
                    ecolor="k", elinewidth=0.6, capsize=1.5, zorder=3)
        bottom = top
    return handles


def draw_seeded(ax, sweep, paper, variant):
    """The main job's chains of this variant, one row per group, above the bands."""
    chains = [c for c in range(paper.n_chains) if paper.is_grouped and paper.variant_name(c) == variant]
    groups = []
    for c in chains:
        if paper.group_name(c) not in groups:
            groups.append(paper.group_name(c))
    for c in chains:
        row = groups.index(paper.group_name(c))
        y = 1.05 + 0.06 * row
        for k in paper.windows(c):
            ax.scatter(paper.omega_mean[c, k] / PI, y, s=9, marker=SEEDED_MARKS.get(int(paper.direction[c, k]), "o"),
                       color=paper.class_colour(c, k), edgecolors="none", zorder=4, clip_on=False)
    for row, g in enumerate(groups):
        ax.text(1.01, 1.05 + 0.06 * row, f"{ajx.for_figure(g, 12)}", transform=ax.get_yaxis_transform(), fontsize=6,
                va="center", ha="left")
    return len(groups)


def draw_up(ax, sweep, part):
    w, p, lo, hi = bs.up_probability(sweep, part)
    ax.fill_between(w / PI, lo, hi, color="0.8", lw=0, label="95 % Wilson interval")
    ax.plot(w / PI, p, "o-", color="k", ms=3, lw=1.0, label="P(bead up)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_ylabel("P(bead up)")
    ax.set_xlabel("ω_m [π rad/s]")


def paper_lines(ax, label=False):
    for name in ("omega_rise", "omega_fall"):
        ax.axvline(PAPER[name], zorder=5, **ajx.PAPER_LINE)
        if label:
            ax.text(PAPER[name], 0.97, f"paper {ajx.THRESHOLD_SYMBOLS[name]} = {PAPER[name]:.2f}π ", rotation=90,
                    transform=ax.get_xaxis_transform(), fontsize=6, va="top", ha="right", zorder=6,
                    bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.8})


def print_table(sweep):
    for part in bs.basin_parts(sweep):
        _, group, variant = part_title(sweep, part)
        t = bs.basin_table(sweep, part)
        print(f"# group {group}, variant {variant}: family {t['family']}")
        print("omega_m/pi  done  " + "  ".join(f"{lab} [95% CI]" for lab in t["labels"]))
        for i, w in enumerate(t["omega_m"]):
            cells = [f"{t['fraction'][i, j]:.3f} [{t['lower'][i, j]:.3f}, {t['upper'][i, j]:.3f}]"
                     for j in range(len(t["labels"]))]
            print(f"{w / PI:10.3f}  {t['done'][i]:4d}  " + "  ".join(cells))
        print("attractor: its levels [π rad/s], starts, mean ω_ball [π rad/s], ρ1, ρ2, s [m]")
        b = sweep.basins
        for j, lab in enumerate(t["labels"]):
            m = t["sample_label"] == j
            levels = np.unique(np.round(b["levels"]["omega_m"][b["level"][m]] / PI, 3))
            with warnings.catch_warnings():  # a feature no start of the attractor has: NaN, not a warning
                warnings.simplefilter("ignore", RuntimeWarning)
                f = np.nanmean(b["features"][m], axis=0) if m.any() else np.full(4, np.nan)
            def num(v, text):  # a feature none of its starts has (e.g. no ω_ball): said, not "nan"
                return text.format(v) if np.isfinite(v) else "none"
            print(f"  {lab}: {', '.join(f'{v:g}' for v in levels)}; {int(m.sum())} starts; "
                  f"ω_ball {num(f[0] / PI, '{:.2f}π')}, ρ1 {num(f[1], '{:.3f}')}, ρ2 {num(f[2], '{:.3f}')}, "
                  f"s {num(f[3], '{:.3f}')}")
        w, p, lo, hi = bs.up_probability(sweep, part)
        print("omega_m/pi  P(up) [95% CI]")
        for i in range(len(w)):
            print(f"{w[i] / PI:10.3f}  {p[i]:.3f} [{lo[i]:.3f}, {hi[i]:.3f}]")


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="sweep file with basin groups (astrojax sweep sweeps/basins.toml)")
    ap.add_argument("--paper", help="the main job's file (out/paper.h5): its seeded chains drawn over the bands")
    ap.add_argument("--table", action="store_true", help="print the matched fractions and P(up) instead of drawing")
    ap.add_argument("-o", "--output", help="image to write: .png or .pdf (by extension)")
    ap.add_argument("--dpi", type=float, default=120, help="pixels per inch of a PNG (default 120)")
    args = ap.parse_args(argv)
    if args.output:
        ajx.check_output(args.output)
    sweep = ajx.Sweep(args.input)
    parts = bs.basin_parts(sweep)
    if not parts:
        ajx.fail(f"{args.input}: /basins: missing: the sweep has no basin groups (a [basin] table; guide: basin sweeps)")
    if args.table:
        print_table(sweep)
        return 0
    if not args.output:
        ajx.fail("give -o FILE for the figure, or --table")
    paper = ajx.Sweep(args.paper) if args.paper else None
    plt = ajx.pyplot()
    fig, axes = plt.subplots(2, len(parts), figsize=(4.2 * len(parts) + 0.6, 6.2), squeeze=False,
                             gridspec_kw={"height_ratios": [2.2, 1.0]}, sharex="col")
    for col, part in enumerate(parts):
        _, group, variant = part_title(sweep, part)
        t = bs.basin_table(sweep, part)
        ax = axes[0, col]
        handles = draw_bands(ax, sweep, t)
        rows = draw_seeded(ax, sweep, paper, variant) if paper else 0
        ax.set_ylim(0, 1.0 + (0.06 * rows + 0.04 if rows else 0.0))
        ax.set_yticks([0, 0.25, 0.5, 0.75, 1.0])
        paper_lines(ax)
        n = int(t["samples"].max())
        ax.set_title(f"{ajx.for_figure(group, 20)} starts ({t['family']}), {ajx.for_figure(variant, 20)}: N = {n} per level",
                     fontsize=8)
        if col == 0:
            ax.set_ylabel("fraction of starts")
        ax.legend(handles=handles, fontsize=6, loc="lower right", framealpha=0.9)
        draw_up(axes[1, col], sweep, part)
        paper_lines(axes[1, col], label=True)
        if col == 0:
            axes[1, col].legend(fontsize=6, loc="center right")
    lo = min(bs.up_probability(sweep, p)[0].min() for p in parts) / PI
    hi = max(bs.up_probability(sweep, p)[0].max() for p in parts) / PI
    for ax in axes.flat:
        ax.set_xlim(min(lo, PAPER["omega_fall"]) - 0.5, hi + 0.5)
    fig.tight_layout()
    ajx.save(fig, args)
    return 0


if __name__ == "__main__":
    ajx.run(main)
