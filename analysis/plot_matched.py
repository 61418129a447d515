#!/usr/bin/python3
"""The matched comparison (docs/reports/matched-comparison.md): CPU time against the ACHIEVED
position error, one panel per scene and horizon, from the CSV of `astrojax_matched`.

Colour: the method (the project's dop853 in black, the hand-written odeint peers, CVODE Adams,
ARKODE's ERK).
Line: solid with the event guarantee (steps capped at (k+1)/Omega, guards sampled inside the
step), dashed without it (guards checked at step ends, or CVODE's own root finding). Hollow
markers: the run failed or ended in another contact mode than the reference. The dotted
verticals are the target errors 1e-6 and 1e-9 m; errors left of the grey band are below the
reference's floor and not resolved.

With --costs: also print, for every method that runs in both families, the cost of the
guarantee at each target error: its cheapest CPU time with the guarantee over its cheapest
without, minus 1 (the cheapest point reaching the error, status ok and the reference's final
mode, as astrojax_matched counts it).

Usage: /usr/bin/python3 analysis/plot_matched.py out/matched.csv -o analysis/figures/matched_comparison.png
       [--costs 1e-6,1e-9]
"""
from collections import defaultdict

import astrojax_analysis as ajx

COLOURS = [("astrojax", "black"), ("rkf78", "tab:blue"), ("dopri5", "tab:orange"),
           ("bulirsch", "tab:green"), ("CVODE", "tab:red"), ("ARKODE", "tab:purple")]
LABELS = {"black": "astrojax dop853 (the project)", "tab:blue": "hand-written peer: odeint rkf78",
          "tab:orange": "hand-written peer: odeint dopri5", "tab:green": "hand-written peer: odeint Bulirsch-Stoer",
          "tab:red": "hand-written peer: CVODE Adams + CVodeRootInit",
          "tab:purple": "hand-written peer: ARKODE ERK Fehlberg 7(8) + ERKStepRootInit"}


NEED = {"scene", "horizon_s", "method", "family", "status", "same_final_mode", "err_position_m", "cpu_min_s", "rtol",
        "reference_floor_m"}


def colour(method):
    return next((c for key, c in COLOURS if key in method), "tab:gray")


def cheapest(rows, scene, horizon, method, family, target):
    cpu = [float(r["cpu_min_s"]) for r in rows if r["scene"] == scene and r["horizon_s"] == horizon
           and r["method"] == method and r["family"] == family and r["status"] == "ok"
           and r["same_final_mode"] == "1" and float(r["err_position_m"]) <= target]
    return min(cpu) if cpu else float("nan")


def print_costs(rows, targets):
    print("cost of the guarantee (with / without - 1) per method:")
    for scene, horizon in dict.fromkeys((r["scene"], r["horizon_s"]) for r in rows):
        for method in dict.fromkeys(r["method"] for r in rows if r["family"] == "guarantee"):
            if not any(r["method"] == method and r["family"] == "no guarantee" for r in rows):
                continue
            costs = [cheapest(rows, scene, horizon, method, "guarantee", e) /
                     cheapest(rows, scene, horizon, method, "no guarantee", e) - 1 for e in targets]
            print(f"  {scene:20s} {horizon:>4s} s  {method:34s} " +
                  "  ".join(f"{e:.0e} m: {100 * c:+4.0f} %" for e, c in zip(targets, costs)))


def read(path):
    """The rows of astrojax_matched's CSV, checked: its columns, and numbers where numbers go."""
    rows = ajx.read_astrojax_csv(path, NEED, "astrojax_matched")
    if not rows:
        ajx.fail(f"{path}: no rows: not a CSV of `astrojax_matched`")
    for i, r in enumerate(rows):
        try:
            [float(r[k]) for k in ("horizon_s", "err_position_m", "cpu_min_s", "rtol", "reference_floor_m")]
        except (TypeError, ValueError):
            ajx.fail(f"{path}: row {i + 2}: horizon_s, err_position_m, cpu_min_s, rtol and reference_floor_m must be "
                     f"numbers")
    return rows


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", default="out/matched.png")
    ap.add_argument("--costs", help="target errors, e.g. 1e-6,1e-9: print the guarantee's cost per method")
    a = ap.parse_args(argv)
    ajx.check_output(a.output)
    rows = read(a.csv)
    if a.costs:
        print_costs(rows, ajx.float_list(a.costs, "--costs"))
    plt = ajx.pyplot()
    from matplotlib.lines import Line2D
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    horizons = sorted({float(r["horizon_s"]) for r in rows})
    fig, axes = plt.subplots(len(scenes), len(horizons), figsize=(5.2 * len(horizons), 3.9 * len(scenes)),
                             squeeze=False)
    for i, scene in enumerate(scenes):
        for j, T in enumerate(horizons):
            ax = axes[i][j]
            lines = defaultdict(list)
            floor = 0.0
            for r in rows:
                if r["scene"] == scene and float(r["horizon_s"]) == T:
                    lines[(r["method"], r["family"])].append(r)
                    floor = float(r["reference_floor_m"])
            for (method, family), pts in lines.items():
                pts.sort(key=lambda r: float(r["rtol"]), reverse=True)
                ok = [r["status"] == "ok" and r["same_final_mode"] == "1" for r in pts]
                x = [max(float(r["err_position_m"]), 1e-14) for r in pts]
                y = [1e3 * float(r["cpu_min_s"]) for r in pts]
                c, ls = colour(method), "-" if family == "guarantee" else "--"
                ax.plot(x, y, ls, color=c, lw=2.2 if c == "black" else 1.3, alpha=0.9)
                for xi, yi, good in zip(x, y, ok):
                    ax.plot(xi, yi, "o", ms=3.5, color=c, mfc=c if good else "none")
            for target in (1e-6, 1e-9):
                ax.axvline(target, color="0.4", ls=":", lw=1)
            if floor > 0:
                ax.axvspan(1e-14, floor, color="0.9", zorder=0)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlim(1e-13, 1e-2)
            ax.invert_xaxis()
            ax.grid(True, which="major", alpha=0.3)
            ax.set_title(f"{scene}, horizon {T:g} s", fontsize=10)
            ax.set_xlabel("achieved position error at the horizon [m]")
            ax.set_ylabel("CPU time, min of rounds [ms]")
    handles = [Line2D([], [], color=c, lw=2) for c in LABELS] + [
        Line2D([], [], color="0.3", ls="-", lw=1.5), Line2D([], [], color="0.3", ls="--", lw=1.5)]
    labels = list(LABELS.values()) + ["with the event guarantee", "without (step-end check / own root finding)"]
    fig.legend(handles, labels, loc="upper center", ncol=3, fontsize=8.5, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    fig.savefig(a.output, dpi=110)
    print("->", a.output)


if __name__ == "__main__":
    ajx.run(main)
