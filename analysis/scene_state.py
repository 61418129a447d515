#!/usr/bin/python3
"""Print the [initial] table of a work-precision scene from the final state of one chain of a
hold-mode sweep file (astrojax sweep with [hold]).

The state at t_end is rotated about the motor axis by -φ(t_end), φ = ω_m t (ω_m held from
t = 0), so that a run file whose schedule starts at φ = 0 continues the same orbit: the
equations are invariant under a rotation about z together with a shift of the motor phase.

Usage: /usr/bin/python3 analysis/scene_state.py out/hold.h5 CHAIN
"""
import argparse
import math

import h5py
import numpy as np

MODES = {0: "sliding", 1: "bottom_stop", 2: "stuck", 4: "slack"}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file")
    ap.add_argument("chain", type=int)
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        if "hold_omega" not in f["chains"]:
            raise SystemExit(f"{a.file}: not a hold-mode sweep (no /chains/hold_omega)")
        omega = float(f["chains/hold_omega"][a.chain])
        chains = f["tasks/chain"][:]
        rows = np.nonzero(chains == a.chain)[0]
        row = rows[np.argmax(f["tasks/t_end"][rows])]
        s = f["tasks/final_state"][row]
    t, mode = s[0], int(s[1])
    if mode not in MODES:
        raise SystemExit(f"chain {a.chain}: final mode {mode} cannot start a run file")
    phi = math.fmod(omega * t, 2 * math.pi)
    c, sn = math.cos(-phi), math.sin(-phi)
    rot = np.array([[c, -sn, 0], [sn, c, 0], [0, 0, 1]])
    vecs = {name: rot @ s[5 + 3 * k: 8 + 3 * k] for k, name in enumerate(["r1", "r2", "v1", "v2"])}
    print(f"# state of chain {a.chain} of {a.file} at t = {t:.6g} s (ω_m = {omega / math.pi:.6g}π rad/s),")
    print(f"# rotated by -φ = {-phi:.17g} rad about z")
    print("[initial]")
    print('preset = "explicit"')
    for name, v in vecs.items():
        print(f"{name} = [{v[0]:.17g}, {v[1]:.17g}, {v[2]:.17g}]")
    print(f'mode = "{MODES[mode]}"')


if __name__ == "__main__":
    main()
