#!/usr/bin/python3
"""Work-precision diagrams: CPU time (median of repeats) against the ACHIEVED error at the
horizon, one panel per scene, one line per method, from the CSV files of
`astrojax bench work-precision` (and of `astrojax_peers`, same columns).

Errors left of the dashed line (the reference floor: |DOP853 at rtol 1e-13 - DOPRI5 at rtol
1e-12|) are not resolved by the reference. Hollow markers: the run ended in another contact
mode than the reference, or failed. The star is explicit Euler at the paper's step, 1/2000 s.

With --table E1,E2,...: for each scene and target error, the CPU time of each method's
cheapest run that reached it (same final contact mode, status ok), and the ratio to the best.

Usage: /usr/bin/python3 analysis/plot_work_precision.py out/work_precision.csv [more.csv] -o out/wp.png
       [--table 1e-6,1e-9]
"""
import math
from collections import defaultdict

import astrojax_analysis as ajx
from astrojax_analysis.workprecision import read, table


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("csv", nargs="+")
    ap.add_argument("-o", "--output", default="out/work_precision.png")
    ap.add_argument("--error", default="err_position_m", help="error column (err_position_m, omega_ball_error, ...)")
    ap.add_argument("--table", default="", help="comma-separated target errors for a table at equal error")
    a = ap.parse_args(argv)
    ajx.check_output(a.output)
    rows = read(a.csv, a.error)
    if a.table:
        table(rows, ajx.float_list(a.table, "--table"), a.error)
    plt = ajx.pyplot()
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    n = len(scenes)
    cols = min(n, 3)
    fig, axes = plt.subplots((n + cols - 1) // cols, cols, figsize=(5.2 * cols, 4.4 * ((n + cols - 1) // cols)),
                             squeeze=False)
    methods = list(dict.fromkeys(r["method"] for r in rows))
    # One colour per solver; a formulation suffix (/lab, /rotating) keeps the colour, dashed.
    bases = list(dict.fromkeys(m.split("/")[0] for m in methods))
    colors = {m: plt.cm.tab20(bases.index(m.split("/")[0]) % 20) for m in methods}
    for k, scene in enumerate(scenes):
        ax = axes[k // cols][k % cols]
        rs = [r for r in rows if r["scene"] == scene]
        by = defaultdict(list)
        for r in rs:
            by[r["method"]].append(r)
        for m, pts in by.items():
            good = [(float(p[a.error]), float(p["cpu_median_s"]), p) for p in pts
                    if p["status"] == "ok" and math.isfinite(float(p[a.error])) and float(p[a.error]) > 0]
            if not good:
                continue
            xs, ys = [g[0] for g in good], [g[1] for g in good]
            ax.plot(xs, ys, "--" if "/" in m else "-", color=colors[m], lw=2.5 if m == "dop853" else 1, label=m)
            for x, y, p in good:
                filled = p.get("same_final_mode", "1") == "1"
                ax.plot(x, y, "o", ms=4, color=colors[m], mfc=colors[m] if filled else "none")
                if m == "euler" and p["param_kind"] == "step" and abs(float(p["param"]) - 5e-4) < 1e-12:
                    ax.plot(x, y, "*", ms=14, color="k", mfc="gold", zorder=5)
        floor = float(rs[0].get("reference_floor_m", rs[0].get("omega_floor", "nan")))
        if a.error in ("err_position_m", "omega_fall_error", "omega_1_error") and floor > 0:
            ax.axvline(floor, ls="--", color="0.5", lw=0.8)
        chaotic = rs[0].get("chaotic", "0") == "1"
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{scene}" + (" (chaotic: use statistics)" if chaotic else ""))
        ax.set_xlabel({"err_position_m": "achieved position error at the horizon [m]",
                       "omega_ball_error": "|Δω_ball| [rad/s]",
                       "omega_fall_error": "|Δω_fall| [rad/s] (the bead's first landing)",
                       "omega_1_error": "|Δω1| [rad/s] (the balls half a turn behind)"}.get(a.error, a.error))
        ax.set_ylabel("CPU time per run [s]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for k in range(n, axes.size):
        axes[k // cols][k % cols].axis("off")
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"-> {a.output}")


if __name__ == "__main__":
    ajx.run(main)
