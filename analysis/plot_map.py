#!/usr/bin/python3
"""The thresholds over a second parameter: the curves of `astrojax orbits CONFIG --map PARAM`.

One panel per threshold, ω_m against the parameter PARAM:
- ω1, the end of the locked orbit: the curves where the stuck bead starts to slide up
  (cone_up, solid) and the locked orbit's fold (dash-dotted);
- ω_fall: the curve where the stuck bead starts to slide down (cone_down);
- ω2 (tie clutch only): the lag's Hopf point, where the lagging orbit turns into a flower.
A curve is black where its orbit is the threshold's (the locked orbit stable and held by
friction; the lag held), grey where it is not (the curve exists, but no locked orbit ends
there). ◇ marks a codimension-2 point, where two curves meet (e.g. the fold meets the cone).
The paper's measured value is a dashed line; the model's own PARAM (the file's) a dotted
vertical line, and where the paper gives PARAM (l, m, c_D, μ) its apparatus is marked too
(for l and m also Section 3.3's second point, 0.662 m and 0.1 kg).

--brackets CSV overlays a sweep's brackets, so that the sweep and the continuation are read
together: either the CSV of `astrojax thresholds --csv` of a map ([bisect], docs/guide/maps.md:
columns threshold, one per grid axis, before_rad_s, after_rad_s, variant), whose column named
PARAM gives each bracket's place, or a plain CSV with columns symbol, p, before, after (symbol
one of omega_1, omega_fall, omega_2, omega_rise; before and after in rad/s). Each bracket is a
bar from before to after at its p: grey for the paper's physics (rigid tie), black for the tie
clutch; the brackets at one p (the other grid axis) side by side. A bisection that found no
crossing is a triangle at its last level (the threshold lies beyond, in the triangle's
direction); one whose start was already past the threshold an × at the start level. An ω_rise
panel appears when the brackets hold ω_rise (no curve predicts it). Where the CSV's column
start_seed shows one threshold bracketed from several starts (e.g. ω1 from the locked orbit and
from Table 1's orbit), each start has its own panel: the threshold depends on the history.

Run with Debian's interpreter:
    build/astrojax orbits sweeps/orbits_map.toml --map drive_radius --range 0.005 0.03 -o out/map_R.h5
    /usr/bin/python3 analysis/plot_map.py out/map_R.h5 -o out/map_R.png
"""
import csv

import numpy as np

from astrojax_analysis import (PAPER_LINE, Curves, add_figure_args, fail, legend, new_figure,
                               panel_grid, panels, parser, pyplot, run, runs, save)

PI = np.pi
# The paper's measured thresholds [π rad/s] and the curves that predict each.
PANELS = [
    ("omega_1", "ω1: the locked orbit is lost", 4.80, ("cone_up", "fold")),
    ("omega_fall", "ω_fall: the stuck bead slides down", 3.24, ("cone_down",)),
    ("omega_2", "ω2: the lag turns into a flower", 15.00, ("hopf",)),
    ("omega_rise", "ω_rise: the bead climbs off the ball", 12.63, ()),
]
# What each start seed is, for a panel's title.
START_TEXT = {"locked_orbit": "from the locked orbit", "circular_high": "from Table 1's orbit",
              "hanging": "from rest, on the ramp"}
# Which way a threshold's known side lies: +1 the threshold is above the known side (rising ω_m).
DIRECTION = {"omega_1": 1, "omega_2": 1, "omega_rise": 1, "omega_fall": -1}
VARIANT_STYLE = {"clutch": {"color": "k", "lw": 1.6}, "": {"color": "0.45", "lw": 3.2}}
KIND_STYLE = {"cone_up": "-", "cone_down": "-", "fold": "-.", "hopf": "-"}
# Where the paper gives the parameter: its apparatus, and Section 3.3's second point.
PAPER_APPARATUS = {
    "string_length": [(0.826, "paper's l"), (0.662, "§3.3: l = 0.662 m")],
    "mass": [(0.018, "paper's m"), (0.1, "§3.3: m = 0.1 kg")],
    "bead_mass": [(0.018, "paper's m1"), (0.1, "§3.3: m1 = 0.1 kg")],
    "ball_mass": [(0.018, "paper's m2"), (0.1, "§3.3: m2 = 0.1 kg")],
    "drag": [(1.7245e-3, "paper's c_D")],
    "mu_static": [(0.25676, "paper's μ_s")],
    "mu_kinetic": [(0.17176, "paper's μ_k")],
}


def threshold_mask(c, kind):
    """Points where the curve is the threshold: the locked orbit stable and held (hopf: held)."""
    held = c["admissible"] > 0
    return held if kind == "hopf" else held & (c["unstable"] == 0)



def draw_curves(ax, curves, kinds):
    """The curves of the given kinds: black where they are the threshold, grey where not."""
    drawn = False
    for cid in curves.curve_ids(kinds):
        c = curves.curve(cid)
        kind = Curves.KINDS[int(c["kind"][0])]
        for i, j, on in runs(threshold_mask(c, kind)):
            sl = slice(i, min(j + 2, len(c["p"])))  # one point of overlap: a continuous line
            ax.plot(c["p"][sl], c["omega_m"][sl] / PI, ls=KIND_STYLE[kind], color="k" if on else "0.6",
                    lw=1.6 if on else 1.0)
        drawn = True
    m = np.isin(curves.codim2["kind"], [k for k, v in Curves.KINDS.items() if v in kinds])
    ax.plot(curves.codim2["p"][m], curves.codim2["omega_m"][m] / PI, "D", mfc="white", mec="k", ms=5, zorder=5)
    return drawn


def draw_brackets(ax, sym, rows, span):
    """A sweep's brackets of one threshold: a bar from before to after [rad/s] at each p, the
    brackets sharing a p side by side (span: the x range, for the offsets); a triangle where the
    bisection found no crossing. Returns the values the y-range must hold [π rad/s] and the
    starts already past the threshold (x, start level, colour), drawn by set_range."""
    if not rows:
        return [], []
    span_y, starts_past = [], []  # what the y-range must hold [π rad/s]; the × markers, placed after it is set
    at_p = {}
    for r in rows:
        at_p.setdefault(r["p"], []).append(r)
    dx = 0.02 * span
    for p, here in at_p.items():
        for j, r in enumerate(sorted(here, key=lambda r: (r["variant"], r["other"]))):
            x = p + (j - (len(here) - 1) / 2) * dx
            style = VARIANT_STYLE.get(r["variant"], VARIANT_STYLE[""])
            b, a = r["before"], r["after"]
            if np.isfinite(b) and np.isfinite(a):
                ax.vlines(x, b / PI, a / PI, zorder=3, **style)
                span_y += [b / PI, a / PI]
            elif np.isfinite(b):
                ax.plot(x, b / PI, "^" if DIRECTION[sym] > 0 else "v", ms=4, mfc="none", mec=style["color"], zorder=3)
                span_y.append(b / PI)
            elif np.isfinite(a):
                starts_past.append((x, a / PI, style["color"]))
    return span_y, starts_past


def curve_values(curves, kinds):
    """ω_m [π rad/s] of the curves of the given kinds where they are the threshold."""
    out = []
    for cid in curves.curve_ids(kinds):
        c = curves.curve(cid)
        m = threshold_mask(c, Curves.KINDS[int(c["kind"][0])])
        out += list(c["omega_m"][m] / PI)
    return out


def set_range(ax, values, starts_past):
    """The y-range over the thresholds drawn (brackets, the curves where they are the threshold,
    the paper's value), with a margin; a start already past the threshold (an ×, at the start
    level, which can lie far from it) is drawn at the panel's edge on the known side instead."""
    v = np.asarray([x for x in values if np.isfinite(x)])
    if v.size:
        lo, hi = v.min(), v.max()
        pad = max(0.08 * (hi - lo), 0.1)
        ax.set_ylim(lo - pad, hi + pad)
    lo, hi = ax.get_ylim()
    for x, y, colour in starts_past:
        edge = min(max(y, lo), hi)
        ax.plot(x, edge, "x", ms=4, color=colour, zorder=3, clip_on=False)


def _number(text):
    return float(text) if text not in (None, "") else np.nan


def read_brackets(path, param):
    """({symbol: [{p, before, after, variant, other, start}]}, the other grid axes' names) from
    `astrojax thresholds --csv` of a map (the column `param` gives p) or from a CSV with columns
    symbol, p, before, after."""
    out = {}
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows, head = list(reader), reader.fieldnames or []
    except OSError as e:
        fail(f"--brackets {path}: {e}")
    sweep_csv = "threshold" in head and "before_rad_s" in head
    if sweep_csv and param not in head:
        axes = [h for h in head[head.index("variant") + 1:head.index("method")]] if "method" in head else []
        fail(f"--brackets {path}: no column '{param}', the curves' parameter; the map's grid axes are "
             f"{', '.join(axes) or 'none'}")
    other_axes = [h for h in head[head.index("variant") + 1:head.index("method")] if h != param] \
        if sweep_csv and "method" in head else []
    for n, r in enumerate(rows, start=2):
        try:
            if sweep_csv:
                row = {"p": float(r[param]), "before": _number(r["before_rad_s"]), "after": _number(r["after_rad_s"]),
                       "variant": r.get("variant", ""), "other": tuple(float(r[a]) for a in other_axes),
                       "start": r.get("start_seed") or ""}
                sym = r["threshold"]
            else:
                row = {"p": float(r["p"]), "before": float(r["before"]), "after": float(r["after"]), "variant": "",
                       "other": (), "start": ""}
                sym = r["symbol"]
        except (KeyError, TypeError, ValueError):
            fail(f"--brackets {path}: line {n}: expected columns symbol, p, before, after (numbers), or the columns "
                 f"of `astrojax thresholds --csv` with {param}")
        if sym not in DIRECTION:
            fail(f"--brackets {path}: line {n}: threshold '{sym}'; allowed: {', '.join(DIRECTION)}")
        out.setdefault(sym, []).append(row)
    # A threshold's rows that bracket nothing (a ladder chain that never crossed it: its other
    # thresholds' rows) say nothing about it; without a bracket anywhere the threshold has no panel.
    return ({sym: rows for sym, rows in out.items()
             if any(np.isfinite(r["before"]) or np.isfinite(r["after"]) for r in rows)}, other_axes)


def panel_list(curves, brackets):
    """[(symbol, title, paper value, curve kinds, brackets' rows)]: one panel a threshold, or one a
    start where its brackets come from several starts."""
    out = []
    for sym, title, paper, kinds in PANELS:
        rows = brackets.get(sym, [])
        starts = sorted({r["start"] for r in rows if np.isfinite(r["before"]) or np.isfinite(r["after"])})
        if len(starts) > 1:
            for st in starts:
                out.append((sym, f"{title}, {START_TEXT.get(st, 'from ' + st)}", paper, kinds,
                            [r for r in rows if r["start"] == st]))
        elif rows or (kinds and curves.curve_ids(kinds)):
            out.append((sym, title + (f", {START_TEXT.get(starts[0], 'from ' + starts[0])}" if starts and starts[0] else ""),
                        paper, kinds, rows))
    return out


def main(argv=None):
    ap = parser(__doc__)
    ap.add_argument("input", help="HDF5 file of `astrojax orbits CONFIG --map PARAM -o FILE`")
    ap.add_argument("--brackets", help="a sweep's brackets to overlay: CSV with symbol, p, before, after")
    add_figure_args(ap, "4 in per panel × 4.2 in")
    args = ap.parse_args(argv)
    curves = Curves(args.input)
    param = curves.parameter
    brackets, other_axes = read_brackets(args.brackets, param) if args.brackets else ({}, [])
    panels_drawn = panel_list(curves, brackets)
    if not panels_drawn:
        fail(f"{args.input}: no curves in /curves/points")
    rows, cols = panel_grid(len(panels_drawn))
    fig = new_figure(args, (4.0 * cols, 3.6 * rows + 0.6))
    axes, leg = panels(fig, rows, cols, n_legend=6 + (4 if brackets else 0))
    symbol = curves.parameter_symbol or param
    unit = curves.parameter_unit
    model_value = curves.resolved.get(f"model.{param}", curves.resolved.get("model.bead_mass") if param == "mass" else None)
    for ax, (sym, title, paper, kinds, rows_here) in zip(axes.ravel(), panels_drawn):
        if kinds:
            draw_curves(ax, curves, kinds)
        xs = [r["p"] for rows in brackets.values() for r in rows] + list(curves.points["p"])
        span_y, starts_past = draw_brackets(ax, sym, rows_here, (max(xs) - min(xs)) if xs else 1.0)
        on_curves = curve_values(curves, kinds) if kinds else []
        if span_y:  # the sweep's brackets set the scale: a curve far off them (a Hopf point at 250π) is cut at the edge
            lo, hi = min(span_y + [paper]), max(span_y + [paper])
            on_curves = [v for v in on_curves if lo - (hi - lo) - 1 <= v <= hi + (hi - lo) + 1]
        set_range(ax, span_y + on_curves + [paper], starts_past)
        ax.axhline(paper, **PAPER_LINE)
        ax.text(1.0, paper, f" paper {paper:.2f}π", transform=ax.get_yaxis_transform(), fontsize=7, va="center",
                ha="left", clip_on=False)
        if model_value is not None and param != "s":
            ax.axvline(model_value, color="k", ls=":", lw=0.8)
        for v, label in PAPER_APPARATUS.get(param, []):
            ax.axvline(v, color="0.4", ls=(0, (1, 3)), lw=0.8)
            ax.text(v, 0.99, f" {label}", transform=ax.get_xaxis_transform(), fontsize=6.5, rotation=90, va="top")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(f"{symbol} [{unit}]" if unit else symbol)
        ax.set_ylabel("ω_m [π rad/s]")
        ax.grid(alpha=0.3)
    for ax in axes.ravel()[len(panels_drawn):]:
        ax.set_visible(False)
    plt = pyplot()
    s_values = sorted(set(np.round(curves.points["s"], 4)))
    handles = [plt.Line2D([], [], color="k", lw=1.6, label="cone exit (cone_up, cone_down), lag's Hopf point"),
               plt.Line2D([], [], color="k", lw=1.6, ls="-.", label="fold of the locked orbit"),
               plt.Line2D([], [], color="0.6", lw=1.0, label="orbit there unstable or not held: no threshold"),
               plt.Line2D([], [], marker="D", mfc="white", mec="k", ls="", label="codim-2: two curves meet"),
               plt.Line2D([], [], **PAPER_LINE, label="the paper's measured value"),
               plt.Line2D([], [], color="k", ls=":", lw=0.8, label=f"this model's {symbol}")]
    if brackets:
        variants = {r["variant"] for rows in brackets.values() for r in rows}
        if "clutch" in variants:
            handles.append(plt.Line2D([], [], **VARIANT_STYLE["clutch"], label="sweep bracket, tie clutch"))
        if variants - {"clutch"}:
            handles.append(plt.Line2D([], [], **VARIANT_STYLE[""], label="sweep bracket" +
                                      (", rigid tie" if "clutch" in variants else "")))
        if any(np.isfinite(r["before"]) and not np.isfinite(r["after"]) for rows in brackets.values() for r in rows):
            handles.append(plt.Line2D([], [], marker="^", mfc="none", mec="k", ls="", label="no crossing up to here (▼: down to)"))
        if any(np.isfinite(r["after"]) and not np.isfinite(r["before"]) for rows in brackets.values() for r in rows):
            handles.append(plt.Line2D([], [], marker="x", color="k", ls="", label="start past it (at the edge)"))
    legend(leg, handles)
    order = ""
    if other_axes:  # how the bars at one p are ordered (draw_brackets sorts by variant, then the other axes)
        values = sorted({r["other"] for rows in brackets.values() for r in rows})
        spans = ", ".join(f"{a} {min(v[i] for v in values):g} to {max(v[i] for v in values):g}"
                          for i, a in enumerate(other_axes))
        tie = "tie clutch, then rigid tie, each " if len({r["variant"] for rows in brackets.values() for r in rows}) > 1 else ""
        order = f"\nsweep brackets at one {symbol}, left to right: {tie}{spans}"
    fig.suptitle(f"Thresholds over {symbol}, bead stuck at s = {', '.join(f'{s:g}' for s in s_values)} m "
                 f"(continuation, astrojax orbits --map {param}){order}", fontsize=9)
    save(fig, args)


if __name__ == "__main__":
    run(main)
