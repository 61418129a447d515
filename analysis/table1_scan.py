#!/usr/bin/python3
"""ω_fall and ω1 from the paper's Table 1 orbit, over the drive radius R and contact distance d.

For each (R, d) of the grid:
  1. `astrojax sweep sweeps/hold.toml` holds the seed `circular_high` (Table 1's orbit) at
     ω_m = 4π for 70 s; its final state must be a locked circular orbit with the bead up,
     else the point is reported as "no locked orbit at 4π";
  2. that state starts the two scenes of sweeps/scenes/: lock_to_fall.toml (down to 2π at
     0.1 rad/s²) and lock_to_lag.toml (up to 16π), with R and d set, and --set overrides;
  3. ω_fall is ω_m where the bead first leaves the stuck orbit sliding down (mode 0 after 2,
     with L1 growing); ω1 is ω_m where the balls have fallen half a turn behind the motor.
The paper: ω_fall = 3.24π, ω1 = 4.80π.

usage: /usr/bin/python3 analysis/table1_scan.py -o out/table1_scan.md [--radii 0.005,0.01,0.015,0.02]
       [--distances 0.015,0.025,0.035,0.05] [--set model.key=value ...]
"""
import math
import os
import tempfile

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis import tie

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "..", "sweeps", "scenes")
PAPER = {"omega_fall": 3.24, "omega_1": 4.80}  # [π rad/s]
FOUR_PI = 4.0 * math.pi


def held_state(astrojax, work, sets):
    """The circular_high seed held at 4π: (state row, class of its window) or None."""
    out = os.path.join(work, "hold.h5")
    args = [astrojax, "sweep", os.path.join(HERE, "..", "sweeps", "hold.toml"), "-q", "-o", out,
            "--set", f"hold.omega=[{FOUR_PI!r}]", "--set", 'hold.seeds=["circular_high"]',
            "--set", "hold.perturbations=0"]
    for s in sets:
        args += ["--set", s]
    ajx.run_checked(args)
    sweep = ajx.SweepFile(out)
    return sweep.final_state(0), int(sweep.cls[0, -1])


def scene_with_state(template, state, path):
    """The scene `template` with its [initial] table replaced by the stored state, turned back
    by the top's azimuth so that it starts with the top at φ = 0 (a clutch's tie held there)."""
    t, mode = state[0], int(state[1])
    names = {0: "sliding", 1: "bottom_stop", 2: "stuck", 4: "slack"}
    if mode not in names:
        return False
    # The top's azimuth: the motor's phase, or with the tie clutch the tie's χ (its held offset
    # from the motor may be any angle after a slip during the hold).
    chi = state[5 + 15 + 3] if len(state) > 5 + 15 + 3 else float("nan")
    phi = math.fmod(chi if np.isfinite(chi) else FOUR_PI * t, 2 * math.pi)
    c, s = math.cos(-phi), math.sin(-phi)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    vecs = {n: rot @ state[5 + 3 * k: 8 + 3 * k] for k, n in enumerate(["r1", "r2", "v1", "v2"])}
    text = open(template).read()
    start = text.index("\n[initial]\n") + 1
    head, tail = text[:start], text[text.index("\n[[schedule]]", start) + 1:]
    initial = "[initial]\npreset = \"explicit\"\n" + "".join(
        f"{n} = [{v[0]!r}, {v[1]!r}, {v[2]!r}]\n" for n, v in vecs.items()) + f'mode = "{names[mode]}"\n\n'
    with open(path, "w") as f:
        f.write(head + initial + tail)
    return True


def fall_omega(path):
    """ω_m [π] where the stuck bead first slides down, and where it lands (mode 1)."""
    run = ajx.read_run(path)
    mode, w = run["mode"], run["omega_m"]
    slide = np.nonzero(mode != 2)[0]
    land = np.nonzero(mode == 1)[0]
    return (w[slide[0]] / np.pi if len(slide) else None, w[land[0]] / np.pi if len(land) else None)


def pct(v, paper):
    return "—" if v is None else f"{v:.2f}π ({100 * (v / paper - 1):+.0f} %)"


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("-o", "--output", required=True, help="Markdown table to write")
    ap.add_argument("--radii", default="0.005,0.01,0.015,0.02", help="R values [m]")
    ap.add_argument("--distances", default="0.015,0.025,0.035,0.05", help="d values [m]")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="an override for every run (model.* or layers.*), e.g. layers.tie=clutch")
    ap.add_argument("--astrojax", default=None, help="the astrojax binary (default: build/astrojax)")
    args = ap.parse_args(argv)
    radii, dists = tie.numbers(args.radii, "--radii"), tie.numbers(args.distances, "--distances")
    for kv in args.set:
        if "=" not in kv or not kv.startswith(("model.", "layers.")):
            ajx.fail(f"--set {kv}: expected model.key=value or layers.key=value")
    astrojax = ajx.require_astrojax(args.astrojax)

    lines = ["| R [mm] | d [cm] | at 4π | ω_fall: slides at | lands at | ω1: lock lost at | after ω1 at 16π |",
             "|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as work:
        for R in radii:
            for d in dists:
                sets = [f"model.drive_radius={R!r}", f"model.contact_distance={d!r}"] + args.set
                state, cls = held_state(astrojax, work, sets)
                label = f"| {1e3 * R:g} | {1e2 * d:g} |"
                if cls != 1 or int(state[1]) == 1:
                    lines.append(f"{label} no locked orbit with the bead up | — | — | — | — |")
                    print(lines[-1], flush=True)
                    continue
                res = {}
                for name in ("lock_to_fall", "lock_to_lag"):
                    scene = os.path.join(work, f"{name}.toml")
                    if not scene_with_state(os.path.join(SCENES, f"{name}.toml"), state, scene):
                        break
                    out = os.path.join(work, f"{name}.h5")
                    run_args = [astrojax, "run", scene, "-q", "-o", out]
                    for s in sets:
                        run_args += ["--set", s]
                    ajx.run_checked(run_args)
                    res[name] = out
                if len(res) < 2:
                    lines.append(f"{label} stored mode cannot start a run | — | — | — | — |")
                    continue
                slide, land = fall_omega(res["lock_to_fall"])
                lag = tie.summarise(res["lock_to_lag"], 5.0, 30.0)
                last = lag["last"]
                end = "fallen" if lag["fallen"] else f"ω_ball {last['omega_bottom']:.2f}π, L1 {last['L1']:.3f} m"
                lines.append(f"{label} locked, bead at z = {state[7]:.3f} m | "
                             f"{pct(slide, PAPER['omega_fall'])} | {'—' if land is None else f'{land:.2f}π'} | "
                             f"{pct(lag['lost'], PAPER['omega_1'])} | {end} |")
                print(lines[-1], flush=True)
    text = ("# ω_fall and ω1 from Table 1's orbit over (R, d)\n\n"
            f"Overrides: {' '.join(args.set) if args.set else 'none'}. The paper: ω_fall = 3.24π, ω1 = 4.80π.\n\n"
            + "\n".join(lines) + "\n")
    ajx.write_report(args.output, text)


if __name__ == "__main__":
    ajx.run(main)
