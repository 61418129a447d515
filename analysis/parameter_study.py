#!/usr/bin/python3
"""The paper's parameter study (its Fig. 9): m1 = m2 = m in {0.018, 0.1} kg and l in {0.826,
0.662} m at ω_m = 4.8π and 15π rad/s. The paper finds the circular orbits barely change and
the tension scales with the mass.

Two sources, both from the built astrojax and the sweep file (default
sweeps/parameter_study.toml, whose [grid] gives the masses and lengths and whose [hold] the ω_m):
  - equilibria: `astrojax orbits FILE --omega ... --csv` at each (m, l), with --set for the
    grid values. Of the locked orbits it finds, the table lists the frictionless ones (T1 = T2:
    the member of the stuck family that needs no friction, one per root, found exactly rather
    than on the s grid) that are stable; where none at an ω_m is stable, the one with the bead
    highest (largest s), flagged unstable;
  - holds: `astrojax sweep FILE`: each (m, l, ω_m) held from the seeds of [hold], with the
    measured window's class, ω_ball, mean radii and heights of both balls and mean tensions.
T/(m g) is the tension per weight: equal at both masses when the tension scales with m.

usage: /usr/bin/python3 analysis/parameter_study.py -o out/parameter_study.md [FILE] [--work DIR]
"""
import csv
import os
import sys

import numpy as np

import astrojax_analysis as ajx

PI = np.pi
HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT = os.path.join(HERE, "..", "sweeps", "parameter_study.toml")
FRICTIONLESS = 2  # the 'case' column of astrojax orbits --csv


def equilibria(exe, config, masses, lengths, omegas, work, extra):
    """[(m, l, row of astrojax orbits' CSV as floats)] of the orbits this study tabulates."""
    out = []
    for m in masses:
        for l in lengths:
            path = os.path.join(work, f"orbits_m{m:g}_l{l:g}.csv")
            ajx.run_checked([exe, "orbits", config, *(a for w in omegas for a in ("--omega", repr(w))), "--csv", path,
                             "--set", f"model.bead_mass={m!r}", "--set", f"model.ball_mass={m!r}",
                             "--set", f"model.string_length={l!r}", *extra])
            with open(path, newline="") as f:
                rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
            for w in omegas:
                free = sorted((r for r in rows if r["case"] == FRICTIONLESS and abs(r["omega_m"] - w) <= 1e-9 * w
                               and r["admissible"] == 1), key=lambda r: r["s"])
                stable = [r for r in free if r["stable"] == 1]
                for r in stable or free[-1:]:
                    out.append((m, l, r))
    return out


def side(r):
    return ("+" if r["bead_side"] > 0 else "−") + "/" + ("+" if r["ball_side"] > 0 else "−")


def holds(path):
    sweep = ajx.Sweep(path)
    if not sweep.is_hold or sweep.axes != ["mass", "string_length"]:
        ajx.fail(f"{path}: expected a hold sweep over the grid axes mass and string_length, got {sweep.axes}")
    out = []
    for c in range(sweep.n_chains):
        ks = sweep.windows(c)
        if not ks:
            continue
        k = ks[-1]
        st = {name: float(v[c, k]) for name, v in sweep.stats.items() if v.ndim == 2}
        # Every ball stays within l + R of the motor axis's top (triangle inequality): a sample
        # beyond it is off the string, and the window's means are not an orbit's.
        smp = sweep.samples(c, k)
        reach = max(np.max(np.linalg.norm(smp["r1"], axis=1)), np.max(np.linalg.norm(smp["r2"], axis=1)))
        st["off_string"] = reach if reach > (1 + 1e-6) * (sweep.parameter(c, "string_length") +
                                                           sweep.parameter(c, "drive_radius")) else np.nan
        out.append((float(sweep.grid[c][0]), float(sweep.grid[c][1]), float(sweep.hold_omega[c]),
                    ajx.printable(sweep.seed_name(int(sweep.seed[c])), 40), sweep.class_name(c, k), st))
    return out


def cm(v):
    return f"{100 * v:.2f}"


def mass_changes(eq, gravity):
    """For each orbit at m_min, the same orbit (ω, l, side, rank in s) at m_max: the largest
    change of a radius or height [m], the change of the bead's azimuth relative to the top
    [deg] (the lag the drag sets), and the largest change of T/(m g)."""
    masses = sorted({m for m, _, _ in eq})
    if len(masses) < 2:
        return []
    key = {}
    for m, l, r in eq:
        k = (r["omega_m"], l, side(r))
        key.setdefault(k, {}).setdefault(m, []).append(r)
    out = []
    for (w, l, sd), by_m in sorted(key.items()):
        a, b = by_m.get(masses[0], []), by_m.get(masses[-1], [])
        for ra, rb in zip(a, b):
            dpos = max(abs(ra[q] - rb[q]) for q in ("rho1", "z1", "rho2", "z2"))
            dT = max(abs(ra[t] / (masses[0] * gravity) - rb[t] / (masses[-1] * gravity)) for t in ("T1", "T2"))
            dphi = np.degrees(abs(np.angle(np.exp(1j * (rb["phase1"] - ra["phase1"])))))
            out.append((w, l, sd, ra["s"], dpos, dphi, dT, rb["T1"] / ra["T1"], masses[-1] / masses[0]))
    return out


def report(eq, held, config, gravity=9.81):
    lines = ["# The paper's parameter study: m and l at 4.8π and 15π", "", f"- sweep file: `{os.path.relpath(config)}`",
             "- lengths in cm (frame turning with the motor for the equilibria); tensions in N; T/(m g) per weight", "",
             "## Equilibria (`astrojax orbits`): frictionless locked orbits", "",
             "| ω_m | m [kg] | l [m] | side | s [m] | ρ1 | z1 | ρ2 | z2 | T1 | T2 | T1/(m g) | T2/(m g) | stable |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for m, l, r in sorted(eq, key=lambda e: (e[2]["omega_m"], e[1], side(e[2]), e[2]["s"], e[0])):
        lines.append(f"| {r['omega_m'] / PI:.1f}π | {m:g} | {l:g} | {side(r)} | {r['s']:.4f} | {cm(r['rho1'])} | "
                     f"{cm(r['z1'])} | {cm(r['rho2'])} | {cm(r['z2'])} | {r['T1']:.4f} | {r['T2']:.4f} | "
                     f"{r['T1'] / (m * gravity):.4f} | {r['T2'] / (m * gravity):.4f} | "
                     f"{'yes' if r['stable'] == 1 else 'no'} |")
    changes = mass_changes(eq, gravity)
    if changes:
        lines += ["", "Mass change, same orbit: the largest change of a radius or height, the change of the bead's "
                  "azimuth relative to the top, of T/(m g), and the tension ratio against the mass ratio:", "",
                  "| ω_m | l [m] | side | s [m] at the lighter mass | largest Δ radius or height [mm] | "
                  "Δ azimuth of the bead [°] | largest Δ T/(m g) | T1 ratio | m ratio |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for w, l, sd, s, dpos, dphi, dT, ratio, mratio in changes:
            lines.append(f"| {w / PI:.1f}π | {l:g} | {sd} | {s:.4f} | {1e3 * dpos:.3f} | {dphi:.2f} | {dT:.2e} | "
                         f"{ratio:.4f} | {mratio:.4f} |")
    lines += ["", "## Held (`astrojax sweep`): the orbit each seed settles on", "",
              "| ω_m | seed | m [kg] | l [m] | class | ω_ball | ρ1 | z1 | ρ2 | z2 | T1 | T2 | T1/(m g) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for m, l, w, seed, cls, st in sorted(held, key=lambda h: (h[2], h[3], -h[1], h[0])):
        wb = st["omega_ball"]
        if np.isfinite(st["off_string"]):
            lines.append(f"| {w / PI:.1f}π | {seed} | {m:g} | {l:g} | {cls}, **but a sample lies "
                         f"{st['off_string']:.3g} m from the axis's top, off a string of {l:g} m** |" + " |" * 8)
            continue
        lines.append(f"| {w / PI:.1f}π | {seed} | {m:g} | {l:g} | {cls} | "
                     f"{f'{wb / PI:.3f}π' if np.isfinite(wb) else '—'} | {cm(st['radius_bead_mean'])} | "
                     f"{cm(st['height_bead_mean'])} | {cm(st['radius_bottom_mean'])} | {cm(st['height_bottom_mean'])} | "
                     f"{st['T1_mean']:.4f} | {st['T2_mean']:.4f} | {st['T1_mean'] / (m * gravity):.4f} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", nargs="?", default=DEFAULT, help="the hold sweep file (default sweeps/parameter_study.toml)")
    ap.add_argument("-o", "--output", required=True, help="the Markdown report to write")
    ap.add_argument("--work", default=None, help="directory for the runs' files (default: next to the report)")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="an override for every run (model.*, layers.*)")
    args = ap.parse_args(argv)
    if not args.output.endswith(".md"):
        ajx.fail(f"-o {args.output}: the report is Markdown and must end in .md")
    if not os.path.isfile(args.input):
        ajx.fail(f"{args.input}: no such file")
    exe = ajx.require_astrojax(args.astrojax)
    work = args.work or os.path.splitext(args.output)[0] + "_runs"
    os.makedirs(work, exist_ok=True)
    extra = [a for kv in args.sets for a in ("--set", kv)]
    hold_h5 = os.path.join(work, "holds.h5")
    for stale in (hold_h5, hold_h5 + ".part", hold_h5 + ".journal"):
        if os.path.exists(stale):
            os.remove(stale)
    ajx.run_checked([exe, "sweep", args.input, "-o", hold_h5, "-q", *extra])
    held = holds(hold_h5)
    sweep = ajx.Sweep(hold_h5)
    masses = sorted({float(v) for v in sweep.grid[:, 0]})
    lengths = sorted({float(v) for v in sweep.grid[:, 1]}, reverse=True)
    omegas = sorted({float(v) for v in sweep.hold_omega})
    gravity = sweep.parameter(0, "gravity")
    eq = equilibria(exe, args.input, masses, lengths, omegas, work, extra)
    text = report(eq, held, args.input, gravity)
    ajx.write_report(args.output, text, sys.stderr)
    print(text)


if __name__ == "__main__":
    ajx.run(main)
