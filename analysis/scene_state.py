#!/usr/bin/python3
"""Print the [initial] table of a work-precision scene from the final state of one chain of a
hold-mode sweep file (astrojax sweep with [hold]).

The state at t_end is rotated about the motor axis by -φ(t_end), φ = ω_m t (ω_m held from
t = 0), so that a run file whose schedule starts at φ = 0 continues the same orbit: the
equations are invariant under a rotation about z together with a shift of the motor phase.

Usage: /usr/bin/python3 analysis/scene_state.py out/hold.h5 CHAIN
"""
import math

import numpy as np

import astrojax_analysis as ajx

MODES = {0: "sliding", 1: "bottom_stop", 2: "stuck", 4: "slack"}


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("file", help="HDF5 file from `astrojax sweep` with [hold]")
    ap.add_argument("chain", type=int, help="the chain whose final state to print")
    a = ap.parse_args(argv)
    sweep = ajx.SweepFile(a.file)
    if not sweep.is_hold:
        ajx.fail(f"{a.file}: not a hold-mode sweep (no /chains/hold_omega)")
    if not 0 <= a.chain < sweep.n_chains:
        ajx.fail(f"chain {a.chain} outside 0..{sweep.n_chains - 1} of {a.file}")
    omega = float(sweep.hold_omega[a.chain])
    rows = np.nonzero((sweep.task_chain == a.chain) & (sweep.task_status == 1))[0]
    if not len(rows):
        ajx.fail(f"{a.file}: chain {a.chain} has no finished task (its /tasks/status is never 1)")
    row = rows[np.argmax(sweep.task_t_end[rows])]
    s = sweep.final_state(row)
    if len(s) < 17 or not np.all(np.isfinite(s[:17])):
        raise ajx.SweepFileError(a.file, "/tasks/final_state", f"task {row}: not a finite state (t, mode, ..., r1..v2)")
    t, mode = s[0], int(s[1])
    if mode not in MODES:
        ajx.fail(f"chain {a.chain}: final mode {mode} cannot start a run file")
    phi = math.fmod(omega * t, 2 * math.pi)
    c, sn = math.cos(-phi), math.sin(-phi)
    rot = np.array([[c, -sn, 0], [sn, c, 0], [0, 0, 1]])
    vecs = {name: rot @ s[5 + 3 * k: 8 + 3 * k] for k, name in enumerate(["r1", "r2", "v1", "v2"])}
    print(f"# state of chain {a.chain} of {ajx.printable(a.file)} at t = {t:.6g} s (ω_m = {omega / math.pi:.6g}π rad/s),")
    print(f"# rotated by -φ = {-phi:.17g} rad about z")
    print("[initial]")
    print('preset = "explicit"')
    for name, v in vecs.items():
        print(f"{name} = [{v[0]:.17g}, {v[1]:.17g}, {v[2]:.17g}]")
    print(f'mode = "{MODES[mode]}"')


if __name__ == "__main__":
    ajx.run(main)
