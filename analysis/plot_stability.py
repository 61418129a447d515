#!/usr/bin/python3
"""Where fixed-step methods fail, from `astrojax bench stability`: the largest acceptable step
against the held ω_m for each method (left), and explicit Euler at the paper's step, 1/2000 s, at
each ω_m: its energy-balance residual (energy injected against the drag) and its position
error against the reference (right).

Usage: /usr/bin/python3 analysis/plot_stability.py out/stability.csv -o out/stability.png
"""
import csv

import astrojax_analysis as ajx

NEED = ("method", "omega_over_pi", "largest_stable", "step", "energy_residual_rel", "err_position_m", "final_mode_ok")


def read(path):
    """The rows of `astrojax bench stability`'s CSV, checked: its columns, numbers where numbers go."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        ajx.fail(f"{path}: cannot read: {getattr(e, 'strerror', None) or e}")
    if not rows or any(c not in rows[0] for c in NEED):
        ajx.fail(f"{path}: not a CSV of `astrojax bench stability` (columns {', '.join(NEED)})")
    for i, r in enumerate(rows):
        try:
            [float(r[c]) for c in NEED[1:6]]
        except (TypeError, ValueError):
            ajx.fail(f"{path}: row {i + 2}: {', '.join(NEED[1:6])} must be numbers")
    return rows


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("csv", help="CSV of `astrojax bench stability`")
    ap.add_argument("-o", "--output", default="out/stability.png", help="image to write: .png or .pdf")
    a = ap.parse_args(argv)
    ajx.check_output(a.output)
    rows = read(a.csv)
    plt = ajx.pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for m in dict.fromkeys(r["method"] for r in rows):
        pts = {}
        for r in rows:
            if r["method"] == m:
                pts[float(r["omega_over_pi"])] = float(r["largest_stable"])
        ws = sorted(pts)
        ax1.semilogy(ws, [pts[w] if pts[w] > 0 else float("nan") for w in ws], "o-", label=m)
    ax1.axhline(5e-4, ls="--", color="k", lw=0.8, label="the paper's 1/2000 s")
    ax1.set_xlabel("ω_m / π [rad/s]")
    ax1.set_ylabel("largest acceptable step [s]")
    ax1.set_title("finished, right final mode, |energy residual| ≤ 1 %", fontsize=9)
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=8)
    paper = sorted((float(r["omega_over_pi"]), r) for r in rows
                   if r["method"] == "euler" and abs(float(r["step"]) - 5e-4) < 1e-12)
    if paper:
        ws = [w for w, _ in paper]
        ax2.semilogy(ws, [abs(float(r["energy_residual_rel"])) for _, r in paper], "o-", label="|energy residual|")
        ax2.semilogy(ws, [float(r["err_position_m"]) for _, r in paper], "s-", label="position error [m]")
        for w, r in paper:
            if r["final_mode_ok"] != "1":
                ax2.annotate("wrong mode", (w, float(r["err_position_m"])), fontsize=7)
        ax2.set_xlabel("ω_m / π [rad/s]")
        ax2.set_title("explicit Euler at the paper's step, 1/2000 s", fontsize=9)
        ax2.grid(True, which="both", alpha=0.3)
        ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"-> {a.output}")


if __name__ == "__main__":
    ajx.run(main)
