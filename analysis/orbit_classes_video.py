#!/usr/bin/python3
"""One short video of a sweep's orbit classes, one after the other: for each class named, the
middle window of that class on the chosen chain (by mean ω_m among its windows of that class)
is re-run by `astrojax replay`, animated by animate.py for --seconds from its start, and the
clips are joined by ffmpeg. The docs' video of the main job's locked, lagging and flower orbits
is made with the usage line below.

usage: /usr/bin/python3 analysis/orbit_classes_video.py out/paper.h5 --group up --variant clutch --direction up \\
           --classes locked-circular,lagging-circular,flower -o docs/media/orbit_classes.mp4
"""
import os
import subprocess
import tempfile

import astrojax_analysis as ajx
import animate

DIRECTIONS = {"up": "1", "down": "-1", "held": "0"}


def chosen_windows(args, exe, tmp):
    """[(chain, window, class)] of the classes asked for, from `astrojax windows`."""
    out = os.path.join(tmp, "windows.csv")
    ajx.run_checked([exe, "windows", args.input, "-o", out])
    rows = ajx.read_astrojax_csv(out, {"chain", "group", "variant", "window", "class", "direction"}, "astrojax windows")
    rows = [r for r in rows if (not args.group or r["group"] == args.group) and
            (not args.variant or r["variant"] == args.variant) and
            (args.direction == "any" or r["direction"] == DIRECTIONS[args.direction])]
    if not rows:
        ajx.fail(f"{args.input}: no window of group {args.group!r}, variant {args.variant!r}, direction {args.direction}")
    chain = int(rows[0]["chain"])
    picked = []
    for cls in [c.strip() for c in args.classes.split(",")]:
        found = [r for r in rows if int(r["chain"]) == chain and r["class"] == cls]
        if not found:
            ajx.fail(f"--classes: chain {chain} has no {cls} window; it has "
                     f"{', '.join(sorted({r['class'] for r in rows if int(r['chain']) == chain}))}")
        found.sort(key=lambda r: float(r["omega_m_begin_rad_s"]))
        picked.append((chain, int(found[len(found) // 2]["window"]), cls))
    return picked


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ap.add_argument("-o", "--output", required=True, help="video to write (.mp4)")
    ap.add_argument("--classes", default="locked-circular,lagging-circular,flower", help="classes, in order")
    ap.add_argument("--group", help="the chain group (a grouped sweep)")
    ap.add_argument("--variant", help="the model variant (a grouped sweep)")
    ap.add_argument("--direction", choices=("up", "down", "held", "any"), default="any")
    ap.add_argument("--seconds", type=float, default=4.0, help="run seconds of each clip (default 4)")
    ap.add_argument("--width", type=int, default=640, help="video width in pixels (default 640)")
    ap.add_argument("--frame", choices=("lab", "turning"), default="lab")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable (default build/astrojax)")
    ap.add_argument("--force", action="store_true", help="replace an existing output")
    args = ap.parse_args(argv)
    if not args.output.lower().endswith(".mp4"):
        ajx.fail(f"-o {args.output}: the extension must be .mp4")
    if os.path.exists(args.output) and not args.force:
        ajx.fail(f"-o {args.output}: exists; add --force to replace it")
    if not 0 < args.seconds <= 60:
        ajx.fail(f"--seconds {args.seconds}: outside (0, 60]")
    exe = ajx.require_astrojax(args.astrojax)
    with tempfile.TemporaryDirectory() as tmp:
        clips = []
        for chain, window, cls in chosen_windows(args, exe, tmp):
            run_h5 = os.path.join(tmp, f"{cls}.h5")
            ajx.run_checked([exe, "replay", args.input, "--chain", chain, "--window", window, "-o", run_h5])
            clip = os.path.join(tmp, f"{cls}.mp4")
            t0 = float(ajx.read_run(run_h5)["t"][0])
            animate.main([run_h5, "-o", clip, "--to", str(t0 + args.seconds), "--width", str(args.width),
                          "--frame", args.frame])
            clips.append(clip)
        listing = os.path.join(tmp, "clips.txt")
        with open(listing, "w") as f:
            f.writelines(f"file '{c}'\n" for c in clips)
        os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
        ajx.run_checked(["ffmpeg", "-y", "-loglevel", "error", "-f", "concat", "-safe", "0", "-i", listing,
                         "-c", "copy", "-movflags", "+faststart", args.output])
    print(f"wrote {args.output}")


if __name__ == "__main__":
    ajx.run(main)
