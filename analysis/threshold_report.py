#!/usr/bin/python3
"""Threshold report of a sweep, in Markdown and CSV: for every chain, ω_rise, ω_fall, ω1 and
ω2 as this model's bracket (the mean ω_m of the last window before the class changed and of
the first window after), its midpoint, the paper's measured value and the relative
difference (midpoint − paper) / paper; then, per threshold, the chain closest to the paper.

The numbers are those of `astrojax thresholds FILE --csv CSV`, which this script runs (or
reads from --thresholds): the CSV keeps astrojax's columns verbatim and adds the values in
units of π rad/s; the Markdown prints brackets in π rad/s to 3 decimals, as astrojax does.

usage: /usr/bin/python3 analysis/threshold_report.py out/paper.h5 -o out/paper_thresholds.md
       /usr/bin/python3 analysis/threshold_report.py out/paper.h5 -o report.md --csv report.csv
"""
import csv
import os

import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI


def pi_units(text, digits):
    v = ajx.number(text)
    return f"{v / PI:.{digits}f}" if np.isfinite(v) else ""


def percent(text):
    v = ajx.number(text)
    return f"{100 * v:+.1f} %" if np.isfinite(v) else ""


def table_row(*cells):
    return "| " + " | ".join(str(c) for c in cells) + " |"


def bracket(r):
    return f"{pi_units(r['before_rad_s'], 3)} .. {pi_units(r['after_rad_s'], 3)}" if r["mid_rad_s"] else "not reached"


def refined(r):
    """The refined bracket and its relative difference, or astrojax's note when there is none."""
    if r.get("refined_mid_rad_s"):
        return (f"{pi_units(r['refined_before_rad_s'], 3)} .. {pi_units(r['refined_after_rad_s'], 3)}",
                percent(r["refined_relative_difference"]))
    return (r.get("refine_note", ""), "")


def markdown(path, rows, sweep):
    symbol = lambda name: ajx.THRESHOLD_SYMBOLS.get(name, name)  # noqa: E731
    prov = sweep.provenance
    lines = [f"# Thresholds of `{path}`", ""]
    factor = rows[0].get("refine_factor") if rows else None
    refine_head = (f"refined {factor}× slower [π rad/s]", "refined relative difference") if factor else ()
    facts = [("command", prov.get("command_line", "")), ("git commit", prov.get("git_commit", "")),
             ("version", prov.get("version", "")), ("finished", prov.get("end_time", ""))]
    lines += [f"- {k}: `{v}`" for k, v in facts if v]
    lines += [f"- chains: {sweep.n_chains}" + (f", grid axes: {', '.join(sweep.axes)}" if sweep.axes else ""),
              f"- made by `astrojax thresholds {path}{f' --refine {factor}' if factor else ''}`; definitions in README (\"Thresholds and reclassification\").",
              "", "## Every chain", "",
              table_row("chain", "parameters", "threshold", "bracket [π rad/s]", "midpoint [π rad/s]",
                        "paper [π rad/s]", "relative difference", *refine_head),
              "|---:|---|---|---|---:|---:|---:|" + "---|---:|" * bool(refine_head)]
    for r in rows:
        lines.append(table_row(r["chain"], r.get("parameters", "") or "—", symbol(r["threshold"]), bracket(r),
                               pi_units(r["mid_rad_s"], 3), pi_units(r["paper_rad_s"], 2),
                               percent(r["relative_difference"]), *(refined(r) if refine_head else ())))
    lines += ["", "## Closest chain per threshold", "",
              table_row("threshold", "paper [π rad/s]", "reached by", "closest chain", "its bracket [π rad/s]",
                        "relative difference"),
              "|---|---:|---:|---:|---|---:|"]
    n_chains = len({r["chain"] for r in rows})
    for name in dict.fromkeys(r["threshold"] for r in rows):
        mine = [r for r in rows if r["threshold"] == name]
        reached = [r for r in mine if r["relative_difference"]]
        paper = pi_units(mine[0]["paper_rad_s"], 2)
        if reached:
            best = min(reached, key=lambda r: abs(float(r["relative_difference"])))
            lines.append(table_row(symbol(name), paper, f"{len(reached)} of {n_chains}", best["chain"], bracket(best),
                                   percent(best["relative_difference"])))
        else:
            lines.append(table_row(symbol(name), paper, f"0 of {n_chains}", "—", "not reached", ""))
    return "\n".join(lines) + "\n"


def write_csv(path, rows):
    """astrojax's columns verbatim, then the symbol and the values in π rad/s."""
    base = list(rows[0].keys()) if rows else []
    extra = ["symbol", "before_pi", "after_pi", "mid_pi", "paper_pi"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(base + extra)
        for r in rows:
            w.writerow([r[k] for k in base] + [ajx.THRESHOLD_SYMBOLS.get(r["threshold"], r["threshold"])] +
                       [pi_units(r[k], 6) for k in ("before_rad_s", "after_rad_s", "mid_rad_s", "paper_rad_s")])


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ap.add_argument("-o", "--output", required=True, help="the Markdown report (.md)")
    ap.add_argument("--csv", help="the CSV report (default: the Markdown's path with .csv)")
    ajx.add_threshold_args(ap)
    args = ap.parse_args(argv)
    if not args.output.endswith(".md"):
        ajx.fail(f"-o {args.output}: the report is Markdown, give a path ending in .md")
    csv_path = args.csv or os.path.splitext(args.output)[0] + ".csv"

    sweep = ajx.Sweep(args.input)
    rows = ajx.thresholds_for(args, args.input)
    if not rows:
        ajx.fail(f"{args.input}: astrojax thresholds found no chains")
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    with open(args.output, "w") as f:
        f.write(markdown(args.input, rows, sweep))
    write_csv(csv_path, rows)
    print(f"wrote {args.output} and {csv_path}")


if __name__ == "__main__":
    main()
