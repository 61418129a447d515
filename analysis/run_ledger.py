#!/usr/bin/python3
"""The energy ledger of one or more `astrojax run` files, window by window.

For each window of --window seconds: the motor's ω_m and the balls' ω_ball (slope of the
unwrapped azimuth of each ball about the motor axis, in π rad/s), the orbit radii ρ1, ρ2,
the bead's s = L1, and the powers from the run's work integrals:
    P_motor, P_drag, P_fric (friction + impacts), dE/dt,
and what closes the ledger,
    injection = dE/dt − (P_motor − P_drag − P_fric),
the energy the integrator itself adds per second. An exact integration has injection ≈ 0;
an orbit the motor does not feed (P_motor ≈ 0) then decays, dE/dt ≈ −P_drag. A last line per
file gives the means over the final --tail seconds.

usage: /usr/bin/python3 analysis/run_ledger.py out/lag_dop853.h5 out/lag_euler.h5 [--window 10]
"""
import astrojax_analysis as ajx
from astrojax_analysis.ledger import HEADER, fmt_row, ledger, read_ledger


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("inputs", nargs="+", help="HDF5 files from `astrojax run`")
    ap.add_argument("--window", type=float, default=10.0, help="window length [s] (default 10)")
    ap.add_argument("--tail", type=float, default=40.0, help="final stretch for the summary line [s] (default 40)")
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
        print()


if __name__ == "__main__":
    ajx.run(main)
