#!/usr/bin/python3
"""The paper's first half over the geometry: from rest, does the climb end on a circular orbit?

Reads a grouped or plain sweep whose chains start from rest and ramp ω_m up (such as
sweeps/first_half.toml: R, d and the ramp rate as grid axes, the rigid tie and the tie clutch
as variants), and asks `astrojax thresholds --sequence-csv` (the one place where classes are
read into steps) for each chain's runs of one class. Per chain it reports:
  - ω_rise, the first window that is no longer fallen on the way up;
  - the climb's outcome: 'circular' when a locked or lagging window follows the climb on the
    way up (the paper's Fig. 11), 'falls back' when the bead is fallen again before 14π, or
    the class it ends in;
  - how many windows the circular orbit lasts, and its ω_ball.
A table per variant, rows R × d, one column per ramp rate.

usage: /usr/bin/python3 analysis/first_half.py out/first_half.h5 -o out/first_half.md
"""
import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
CIRCULAR = ("locked-circular", "lagging-circular")


def outcome(runs):
    """(ω_rise [rad/s], outcome text, windows on a circular orbit) from a chain's runs on its
    first rising leg."""
    up = [r for r in runs if r["direction"] == "1"]
    if not up:
        return np.nan, "no ramp up", 0
    first = up[0]
    if first["class"] != "fallen" or len(up) == 1:
        return np.nan, "no climb" if first["class"] == "fallen" else f"starts {first['class']}", 0
    rise = ajx.number(first["omega_to_rad_s"])
    after = up[1:]
    circ = [r for r in after if r["class"] in CIRCULAR]
    if circ:
        n = sum(int(r["windows"]) for r in circ)
        wb = ajx.number(circ[0]["omega_ball_mean_rad_s"])
        return rise, f"circular ({circ[0]['class']}, ω_ball {wb / PI:.2f}π)", n
    if any(r["class"] == "fallen" for r in after):
        return rise, "falls back", 0
    return rise, f"ends {after[-1]['class']}", 0


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep` (chains from rest)")
    ap.add_argument("-o", "--output", required=True, help="Markdown report to write")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable (default: build/astrojax)")
    args = ap.parse_args(argv)
    sweep = ajx.Sweep(args.input)
    for axis in ("drive_radius", "contact_distance", "ramp_rate"):
        if axis not in sweep.axes:
            ajx.fail(f"{args.input}: no grid axis {axis}; run sweeps/first_half.toml")
    seq = ajx.run_sequence(args.input, ajx.require_astrojax(args.astrojax))
    runs = {}
    for r in seq:
        if r["kind"] == "run":
            runs.setdefault(int(r["chain"]), []).append(r)
    col = {a: sweep.axes.index(a) for a in ("drive_radius", "contact_distance", "ramp_rate")}
    rates = sorted({float(sweep.grid[c, col["ramp_rate"]]) for c in range(sweep.n_chains)}, reverse=True)
    variants = sorted({sweep.variant_name(c) for c in range(sweep.n_chains)},
                      key=lambda v: min(c for c in range(sweep.n_chains) if sweep.variant_name(c) == v))
    lines = ["# The paper's first half over the geometry", "",
             f"From rest, ω_m ramped up to 14π at each rate, held there 60 s, then down to 2π (`{args.input}`). "
             "Each cell: ω_rise [π rad/s] and what follows the climb on the way up.", ""]
    total = {}
    for v in variants:
        chains = [c for c in range(sweep.n_chains) if sweep.variant_name(c) == v]
        label = ajx.printable(sweep.variant_label(chains[0]), 120) if sweep.is_grouped else "every chain"
        lines += [f"## {label}", "", "| R [mm] | d [cm] | " + " | ".join(f"{r:g} rad/s²" for r in rates) + " |",
                  "|---|---|" + "---|" * len(rates)]
        cells = {}
        for c in chains:
            key = (sweep.grid[c, col["drive_radius"]], sweep.grid[c, col["contact_distance"]])
            rise, what, n = outcome(runs.get(c, []))
            text = (f"{rise / PI:.2f}: " if np.isfinite(rise) else "") + what + (f", {n} windows" if n else "")
            cells.setdefault(key, {})[float(sweep.grid[c, col["ramp_rate"]])] = text
            kind = what.split(" (")[0]  # circular, falls back, ends <class>, no climb
            total[(v, kind)] = total.get((v, kind), 0) + 1
        for (R, d), by_rate in sorted(cells.items()):
            lines.append(f"| {R * 1e3:g} | {d * 1e2:g} | " + " | ".join(by_rate.get(r, "") for r in rates) + " |")
        lines.append("")
    lines += ["## Outcomes counted", "", "| variant | outcome | chains |", "|---|---|---|"]
    lines += [f"| {v} | {w} | {n} |" for (v, w), n in sorted(total.items())]
    ajx.write_report(args.output, "\n".join(lines) + "\n")


if __name__ == "__main__":
    ajx.run(main)
