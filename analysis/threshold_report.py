#!/usr/bin/python3
"""Threshold report of a sweep, in Markdown and CSV: for every chain, ω_rise, ω_fall, ω1 and
ω2 as this model's bracket (the mean ω_m of the last window before the class changed and of
the first window after), its midpoint, the paper's measured value and the relative
difference (midpoint − paper) / paper; then, per threshold, the chain closest to the paper.

The numbers are those of `astrojax thresholds FILE --csv CSV`, which this script runs (or
reads from --thresholds): the CSV keeps astrojax's columns verbatim and adds the values in
units of π rad/s; the Markdown prints brackets in π rad/s to 3 decimals, as astrojax does.

With --hold T (`astrojax thresholds --hold T`) each bracket's two sides are held for T and
the report adds, per side, the class before and after the hold and the energy account over its
last half (motor and drag power, dE/dt and r = dE/dt / P_drag against the tolerance), and per
threshold the verdict: bifurcation or time-limited transient, with the reason. The orbit class
sequence of every chain (`astrojax thresholds --sequence-csv`) follows: runs of one class per
leg of the protocol, and the paper's steps present, missing or out of order; it is also
written as CSV next to the report (<csv>_sequence.csv).

usage: /usr/bin/python3 analysis/threshold_report.py out/paper.h5 -o out/paper_thresholds.md
       /usr/bin/python3 analysis/threshold_report.py out/paper.h5 -o report.md --csv report.csv
       /usr/bin/python3 analysis/threshold_report.py out/quick.h5 -o out/quick_thresholds.md --hold 5tau
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


def markdown(path, rows, sweep, seq=()):
    symbol = lambda name: ajx.THRESHOLD_SYMBOLS.get(name, name)  # noqa: E731
    prov = sweep.provenance
    lines = [f"# Thresholds of `{path}`", ""]
    factor = rows[0].get("refine_factor") if rows else None
    refine_head = (f"refined {factor}× slower [π rad/s]", "refined relative difference") if factor else ()
    facts = [("command", prov.get("command_line", "")), ("git commit", prov.get("git_commit", "")),
             ("version", prov.get("version", "")), ("finished", prov.get("end_time", ""))]
    lines += [f"- {k}: `{ajx.printable(v, 2000)}`" for k, v in facts if v]
    lines += [f"- chains: {sweep.n_chains}" + (f", grid axes: {ajx.printable(', '.join(sweep.axes), 400)}"
                                               if sweep.axes else ""),
              f"- made by `astrojax thresholds {path}{f' --refine {factor}' if factor else ''}"
              f"{' --hold T' if any(r.get('verdict') for r in rows) else ''}`; definitions in docs/guide/thresholds.md "
              "(\"Bifurcation or time limit\") and docs/physics/orbit-classes.md.",
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
    lines += hold_sections(rows)
    lines += sequence_sections(seq)
    return "\n".join(lines).rstrip("\n") + "\n"


def power(text):
    v = ajx.number(text)
    return f"{v:.3e}" if np.isfinite(v) else ""


def signed(text, digits=3):
    v = ajx.number(text)
    return f"{v:+.{digits}f}" if np.isfinite(v) else ""


def hold_sections(rows):
    """The held sides and the verdicts (rows with astrojax's --hold columns)."""
    symbol = lambda name: ajx.THRESHOLD_SYMBOLS.get(name, name)  # noqa: E731
    held = [r for r in rows if r.get("verdict")]
    if not held:
        return []
    lines = ["", "## Bifurcation or time limit", "",
             "Each bracket restarted from the stored state before it and ω_m held for T at its two sides; powers, "
             "dE/dt and r = dE/dt / P_drag over the last half of the hold; an orbit is sustained when |r| ≤ the "
             "tolerance (m/(2 c_D T), or twice the standard error of r between windows), undetermined when that "
             "error cannot tell r = 0 from r = −1.", "",
             table_row("chain", "threshold", "side", "T [s]", "ω_m held [π rad/s]", "sweep's class",
                       "class after the hold",
                       "P_motor [W]", "P_drag [W]", "P_friction+impacts [W]", "dE/dt [W]", "r", "tolerance",
                       "sustained"),
             "|---:|---|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---|"]
    for r in held:
        for side, name in (("pre", "before the change"), ("post", "after the change")):
            sustained = ("undetermined" if r[f"{side}_determined"] != "1" else
                         "yes" if r[f"{side}_sustained"] == "1" else "no")
            lines.append(table_row(r["chain"], symbol(r["threshold"]), name, f"{ajx.number(r[f'{side}_hold_s']):.1f}",
                                   pi_units(r[f"{side}_omega_rad_s"], 3),
                                   r[f"{side}_class"], r[f"{side}_final_class"], power(r[f"{side}_motor_power_W"]),
                                   power(r[f"{side}_drag_power_W"]), power(r[f"{side}_friction_impact_power_W"]),
                                   power(r[f"{side}_energy_rate_W"]), signed(r[f"{side}_ratio"]),
                                   signed(r[f"{side}_tolerance"]).lstrip("+"), sustained))
    rate = "rate_dependent" in held[0]
    lines += ["", table_row("chain", "threshold", "bracket [π rad/s]", "verdict", "reason",
                            *(("rate-dependent (--refine)",) if rate else ())),
              "|---:|---|---|---|---|" + "---|" * rate]
    for r in held:
        lines.append(table_row(r["chain"], symbol(r["threshold"]), bracket(r), f"**{r['verdict']}**",
                               r["verdict_reason"], *((r["rate_dependent"] or "—",) if rate else ())))
    return lines


def sequence_sections(seq):
    """Each chain's runs of one class and the paper's steps (astrojax's --sequence-csv rows)."""
    if not seq:
        return []
    direction = {"1": "up", "-1": "down", "0": "held"}
    lines = ["", "## Orbit class sequence", "",
             "Per chain, the runs of one orbit class on each leg of the protocol (repeats collapsed; blips: single "
             "not-settled windows absorbed, with `astrojax thresholds --absorb-blips` only), then the paper's "
             "sequence: each step looked for after the last one found.", ""]
    for chain in dict.fromkeys(r["chain"] for r in seq):
        mine = [r for r in seq if r["chain"] == chain]
        params = mine[0].get("parameters", "")
        lines += [f"### Chain {chain}" + (f" ({params})" if params else ""), "",
                  table_row("leg", "direction", "class", "ω_m [π rad/s]", "windows", "blips", "mean ω_ball [π rad/s]",
                            "dω_ball/dω_m"),
                  "|---:|---|---|---|---:|---:|---:|---:|"]
        for r in (r for r in mine if r["kind"] == "run"):
            lines.append(table_row(r["leg"], direction.get(r["direction"], r["direction"]), r["class"],
                                   f"{pi_units(r['omega_from_rad_s'], 3)} .. {pi_units(r['omega_to_rad_s'], 3)}",
                                   r["windows"], r["blips"], pi_units(r["omega_ball_mean_rad_s"], 3),
                                   signed(r["omega_ball_slope"])))
        lines += ["", table_row("paper step", "", "status", "at ω_m [π rad/s]"), "|---|---|---|---:|"]
        for r in (r for r in mine if r["kind"] == "step"):
            lines.append(table_row(r["step"], r["step_description"], r["status"], pi_units(r["omega_from_rad_s"], 3)))
        lines.append("")
    return lines


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
    ap.add_argument("--sequence", metavar="CSV",
                    help="the class sequence from `astrojax thresholds FILE --sequence-csv CSV` (default: run astrojax)")
    args = ap.parse_args(argv)
    if not args.output.endswith(".md"):
        ajx.fail(f"-o {args.output}: the report is Markdown, give a path ending in .md")
    csv_path = args.csv or os.path.splitext(args.output)[0] + ".csv"

    sweep = ajx.Sweep(args.input)
    rows = ajx.thresholds_for(args, args.input)
    if not rows:
        ajx.fail(f"{args.input}: astrojax thresholds found no chains")
    if args.sequence:
        seq = ajx.read_sequence_csv(args.sequence)
    else:
        exe = ajx.find_astrojax(args.astrojax)
        seq = ajx.run_sequence(args.input, exe) if exe else []
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    with open(args.output, "w") as f:
        f.write(markdown(args.input, rows, sweep, seq))
    write_csv(csv_path, rows)
    written = [args.output, csv_path]
    if seq:
        seq_path = os.path.splitext(csv_path)[0] + "_sequence.csv"
        with open(seq_path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(seq[0].keys()), lineterminator="\n")
            w.writeheader()
            w.writerows(seq)
        written.append(seq_path)
    print("wrote " + ", ".join(written))


if __name__ == "__main__":
    ajx.run(main)
