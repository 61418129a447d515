#!/usr/bin/python3
"""The energy ledger of one or more `astrojax run` files, window by window.

For each window of --window seconds: the motor's ω_m and the balls' ω_ball (slope of the
unwrapped azimuth of each ball about the motor axis, in π rad/s), the orbit radii ρ1, ρ2,
the bead's s = L1, and the powers from the run's work integrals:
    P_motor (the motor's, at its rod), P_drag, P_fric (friction + impacts), dE/dt, and last
    P_clutch (what the tie clutch dissipates; 0 for a rigid tie),
and what closes the ledger,
    injection = dE/dt + dE_tie/dt − (P_motor − P_clutch − P_drag − P_fric),
the energy the integrator itself adds per second (E_tie = ½ I_a χ̇², the tie's kinetic energy).
Files of format 2 and 3 hold the string's side in motor_work and lack the clutch's columns: their
P_clutch is read as 0. An exact integration has injection ≈ 0;
an orbit the motor does not feed (P_motor ≈ 0) then decays, dE/dt ≈ −P_drag. A last line per
file gives the means over the final --tail seconds.

With --decay: the e-folding rates over the final --tail seconds of an orbit the motor does not
feed, from least-squares slopes of ln ρ2 (the bottom ball's radius about the axis: the
orbit's amplitude) and of ln K (the balls' kinetic energy), next to c_D/2m and c_D/m.

usage: /usr/bin/python3 analysis/run_ledger.py out/lag_dop853.h5 out/lag_euler.h5 [--window 10] [--decay]
"""
import astrojax_analysis as ajx
from astrojax_analysis.ledger import HEADER, decay_line, fmt_row, ledger, read_ledger


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("inputs", nargs="+", help="HDF5 files from `astrojax run`")
    ap.add_argument("--window", type=float, default=10.0, help="window length [s] (default 10)")
    ap.add_argument("--tail", type=float, default=40.0, help="final stretch for the summary line [s] (default 40)")
    ap.add_argument("--decay", action="store_true",
                    help="also the e-folding rates of the orbit's amplitude and kinetic energy over the tail")
    args = ap.parse_args(argv)
    if not (args.window > 0 and args.tail > 0):
        ajx.fail("--window and --tail must be > 0 seconds")
    for path in args.inputs:
        run = read_ledger(path)
        rows, last = ledger(run, args.window, args.tail)
        print(f"# {path}")
        print(HEADER)
        for r in rows:
            print(fmt_row(r))
        print(fmt_row(last, f"last {args.tail:g} s"))
        if args.decay:
            print(decay_line(run, args.tail))
        print()


if __name__ == "__main__":
    ajx.run(main)
