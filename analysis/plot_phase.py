#!/usr/bin/python3
"""Phase diagram over two parameters: ω_m along x, a grid axis of the sweep (R, d, l, m, μ,
drag or ramp rate) along y, the orbit class as colour.

Each grid value is one row. A row is split into strips, one per pass over ω_m: on a ramp
sweep one strip per protocol segment (labelled ▲ rising or ▼ falling with the segment's
index, in protocol order from the top); on a hold sweep one per seed and kick. Each window
fills its ω_m range in its strip (held points the half-way span to their neighbours).
Where strips of a row end in different steady classes (fallen, locked, lagging, flower) at
the same ω_m, two orbits coexist: that hysteresis region is hatched (////) over the whole
row. With --omega-ball-tol, where they share a class but their ω_ball differ by more than
that fraction of ω_m (two orbits of one class), the row is dotted.
Grid axes other than the one drawn must be fixed with --where if they vary.

usage: /usr/bin/python3 analysis/plot_phase.py out/paper.h5 -o out/paper_phase.png --axis drive_radius
       /usr/bin/python3 analysis/plot_phase.py out/grid.h5 -o phase.pdf --axis contact_distance \
           --where drive_radius=0.01
"""
import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
HATCH = {"class": "////", "omega_ball": "...."}


def choose_chains(sweep, axis, where):
    """The chains on the drawn axis with every --where axis fixed; checks the axes."""
    keep = np.ones(sweep.n_chains, bool)
    fixed = {}
    for item in where:
        name, _, value = item.partition("=")
        if name not in sweep.axes:
            ajx.fail(f"--where {item}: '{name}' is not a grid axis of {sweep.path} (axes: {sweep.axes or 'none'})")
        try:
            v = float(value)
        except ValueError:
            ajx.fail(f"--where {item}: '{value}' is not a number")
        col = sweep.grid[:, sweep.axes.index(name)]
        near = col[np.argmin(np.abs(col - v))]
        keep &= col == near
        fixed[name] = near
    for j, name in enumerate(sweep.axes):
        if name != axis and name not in fixed and len(np.unique(sweep.grid[keep, j])) > 1:
            ajx.fail(f"{sweep.path}: grid axis '{name}' varies too; fix it with --where {name}=VALUE "
                     f"(values {sorted(set(sweep.grid[:, j]))})")
    return [c for c in range(sweep.n_chains) if keep[c] and sweep.valid[c].any()], fixed


def strips_of(sweep, chains):
    """{strip key: [(ω_lo, ω_hi, class name, ω_ball), ...]} for the chains of one row [rad/s]."""
    strips = {}
    if sweep.is_hold:
        held = np.unique(np.concatenate([sweep.omega_mean[c, sweep.windows(c)] for c in chains]))
        first, last = (held[1] - held[0], held[-1] - held[-2]) if len(held) > 1 else (1.0, 1.0)
        edges = np.concatenate([[held[0] - 0.5 * first], 0.5 * (held[1:] + held[:-1]), [held[-1] + 0.5 * last]])
        for c in chains:
            for k in sweep.windows(c):
                i = int(np.searchsorted(held, sweep.omega_mean[c, k]))
                key = (int(sweep.seed[c]), int(sweep.perturbation[c]))
                strips.setdefault(key, []).append((edges[i], edges[i + 1], sweep.class_name(c, k),
                                                   sweep.stats["omega_ball"][c, k]))
    else:
        for c in chains:
            for k in sweep.windows(c):
                lo, hi = sorted((sweep.omega_begin[c, k], sweep.omega_end[c, k]))
                key = (c, int(sweep.segment[c, k]), int(sweep.direction[c, k]))
                strips.setdefault(key, []).append((lo, hi, sweep.class_name(c, k), sweep.stats["omega_ball"][c, k]))
    return dict(sorted(strips.items()))


def strip_label(sweep, key):
    if sweep.is_hold:
        seed = ajx.for_figure(sweep.seed_name(key[0]), 40)
        return seed + (f"+{key[1]}" if key[1] else "")
    return {1: "▲", -1: "▼", 0: "●"}.get(key[2], "") + str(key[1])


def coexistence(strips, omega_ball_tol=None):
    """ω_m intervals [rad/s] where two orbits coexist: (lo, hi, kind). kind 'class': strips
    hold different steady classes there. kind 'omega_ball' (only with omega_ball_tol): the
    same steady class, but ω_ball differing by more than omega_ball_tol × ω_m."""
    edges = np.unique([e for windows in strips.values() for w in windows for e in w[:2]])
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        mid = 0.5 * (lo + hi)
        here = [(name, wb) for windows in strips.values() for a, b, name, wb in windows
                if a <= mid <= b and name in ajx.STEADY_CLASSES]
        kind = None
        if len({name for name, _ in here}) > 1:
            kind = "class"
        elif omega_ball_tol is not None:
            wbs = [wb for _, wb in here if np.isfinite(wb)]
            if wbs and max(wbs) - min(wbs) > omega_ball_tol * mid:
                kind = "omega_ball"
        if kind is None:
            continue
        if out and out[-1][2] == kind and np.isclose(out[-1][1], lo):
            out[-1] = (out[-1][0], hi, kind)
        else:
            out.append((lo, hi, kind))
    return out


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ajx.add_figure_args(ap, "10 × (1.6 + 0.7 per strip row)")
    ap.add_argument("--axis", help="grid axis along y (default: the first grid axis with several values)")
    ap.add_argument("--omega-ball-tol", type=float, metavar="FRACTION",
                    help="also mark where passes share a steady class but their ω_ball differ by more than "
                         "FRACTION × ω_m (two orbits of one class; off by default)")
    ap.add_argument("--where", action="append", default=[], metavar="AXIS=VALUE",
                    help="fix another grid axis at its value nearest VALUE (repeatable)")
    args = ap.parse_args(argv)

    sweep = ajx.Sweep(args.input)
    axis = args.axis
    if axis is None:
        varying = [a for j, a in enumerate(sweep.axes) if len(np.unique(sweep.grid[:, j])) > 1]
        axis = varying[0] if varying else None
    elif axis not in sweep.axes:
        ajx.fail(f"--axis {axis}: not a grid axis of {args.input} (axes: {sweep.axes or 'none'})")
    chains, fixed = choose_chains(sweep, axis, args.where)
    if not chains:
        ajx.fail(f"{args.input}: no classified windows to draw")
    if axis is None:
        rows = {"all chains": chains}
    else:
        col = sweep.grid[:, sweep.axes.index(axis)]
        rows = {f"{axis} = {v:g}": [c for c in chains if col[c] == v] for v in np.unique(col[chains])}
    row_strips = {label: strips_of(sweep, cs) for label, cs in rows.items()}
    n_strips = sum(len(s) for s in row_strips.values())

    from matplotlib.patches import Patch, Rectangle
    used = {name for s in row_strips.values() for windows in s.values() for _, _, name, _ in windows}
    handles = [Patch(color=col, label=ajx.for_figure(n)) for n, col in sweep.class_colours.items() if n in used]
    handles.append(Patch(facecolor="none", edgecolor="k", hatch=HATCH["class"], label="coexisting classes (hysteresis)"))
    if args.omega_ball_tol is not None:
        handles.append(Patch(facecolor="none", edgecolor="k", hatch=HATCH["omega_ball"],
                             label=f"one class, ω_ball apart by > {args.omega_ball_tol:g} ω_m"))
    fig = ajx.new_figure(args, (10, 1.6 + 0.35 * n_strips + 0.4 * len(rows) + ajx.legend_height(10, len(handles))))
    axes, leg = ajx.panels(fig, 1, 1, len(handles))
    ax = axes[0, 0]
    top = 0.0
    for i, (label, strips) in enumerate(row_strips.items()):
        y0, h = i - 0.42, 0.84 / max(len(strips), 1)
        for j, (key, windows) in enumerate(strips.items()):
            y = y0 + (len(strips) - 1 - j) * h  # the first pass on top
            for lo, hi, name, _ in windows:
                ax.add_patch(Rectangle((lo / PI, y), (hi - lo) / PI, h, facecolor=sweep.class_colours.get(name, "k"),
                                       edgecolor="none"))
                top = max(top, hi / PI)
            ax.text(-0.005, y + 0.5 * h, strip_label(sweep, key), transform=ax.get_yaxis_transform(), ha="right",
                    va="center", fontsize=6.5)
        for lo, hi, kind in coexistence(strips, args.omega_ball_tol):
            ax.add_patch(Rectangle((lo / PI, y0), (hi - lo) / PI, 0.84, facecolor="none", edgecolor="k",
                                   hatch=HATCH[kind], lw=0.8))
    ax.set_xlim(0, top * 1.02)
    ax.set_ylim(-0.5, len(rows) - 0.5)
    ax.set_yticks(range(len(rows)), list(rows), fontsize=8)
    ax.tick_params(axis="y", pad=28)
    ax.set_xlabel("ω_m [π rad/s]")
    ajx.legend(leg, handles)
    where = ", ".join(f"{k} = {v:g}" for k, v in fixed.items())
    fig.suptitle(f"{args.input}: orbit class over ω_m" + (f" and {axis}" if axis else "") +
                 (f" ({where})" if where else ""), fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    ajx.run(main)
