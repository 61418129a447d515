#!/usr/bin/python3
"""analysis/animate.py encodes what it says: a window of a short sweep re-run by `astrojax
replay`, animated to .mp4 and .gif, read back with ffprobe:
- the frame count is floor((to − start) / speed × fps) + 1 and the duration that count over
  the frame rate (to one frame), at real time and at --speed 0.5 (twice as many frames);
- the frame size is --width by 9/16 of it;
- bad input exits 2 with one line naming the problem and writes nothing: an unknown
  extension, --to beyond the run, an existing output without --force.

usage: animate_video_test.py ASTROJAX SOURCE_DIR WORK_DIR
"""
import json
import math
import os
import subprocess
import sys

failures = []


def check(what, ok):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def run(*cmd):
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True)


def probe(path):
    p = run("ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
            "stream=nb_read_frames,width,height,r_frame_rate:format=duration", "-of", "json", path)
    info = json.loads(p.stdout)
    s = info["streams"][0]
    num, den = (int(v) for v in s["r_frame_rate"].split("/"))
    return int(s["nb_read_frames"]), float(info["format"]["duration"]), int(s["width"]), int(s["height"]), num / den


def main():
    exe, src, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    h5, run_h5 = os.path.join(work, "three_orbits.h5"), os.path.join(work, "lagging.h5")
    run(exe, "sweep", os.path.join(src, "tests", "data", "replay_three_orbits.toml"), "-o", h5, "--force", "-q")
    p = run(exe, "replay", h5, "--chain", 0, "--window", 1, "-o", run_h5, "--force")
    check(f"replay of the lagging window exits 0 ({p.stderr.strip()})", p.returncode == 0)
    animate = [sys.executable, os.path.join(src, "analysis", "animate.py"), run_h5]
    t0 = 200.0  # the lagging window starts at 70 + 173.6 + 100 s; ask for 2 s from its start
    import h5py
    with h5py.File(run_h5, "r") as f:
        t0 = float(f["trajectory/t"][0])
    for ext, speed, fps in ((".mp4", 1.0, 12), (".gif", 0.5, 10), (".mp4", 1.0, 25)):
        out = os.path.join(work, f"anim_{speed:g}_{fps}{ext}")
        extra = ["--frame", "turning"] if ext == ".gif" else []
        p = run(*animate, "-o", out, "--start", t0, "--to", t0 + 2.0, "--speed", speed, "--fps", fps, "--force",
                "--width", 640, *extra)
        check(f"{ext} at {speed:g}x, {fps} fps: exit 0 ({p.stderr.strip()[-200:]})", p.returncode == 0)
        check(f"{ext}: progress shown on stderr", "frame " in p.stderr)
        frames, duration, w, h, rate = probe(out)
        want = math.floor(2.0 / speed * fps + 1e-9) + 1
        check(f"{ext} at {speed:g}x, {fps} fps: {frames} frames, want {want}", frames == want)
        tol = 1.0 / fps + (0.011 if ext == ".gif" else 0.0)  # a GIF stores delays in 1/100 s
        check(f"{ext}: duration {duration:.3f} s, want {want / fps:.3f} s within one frame",
              abs(duration - want / fps) <= tol)
        check(f"{ext}: frame rate {rate:g}, want {fps}", ext == ".gif" or abs(rate - fps) < 1e-6)
        check(f"{ext}: frame {w}x{h}, want 640x360", (w, h) == (640, 360))
    for name, args, needle in (
            ("unknown extension", ["-o", os.path.join(work, "x.avi")], ".mp4 or .gif"),
            ("--to beyond the run", ["-o", os.path.join(work, "x.mp4"), "--to", 1e6], "--to"),
            ("existing output", ["-o", os.path.join(work, "anim_1_12.mp4")], "exists")):
        p = run(*animate, *args)
        check(f"{name}: exit 2 naming it ({p.stderr.strip()})", p.returncode == 2 and needle in p.stderr
              and "Traceback" not in p.stderr)
    check("bad input wrote nothing", not any(n.startswith("x.") for n in os.listdir(work)))
    print(f"{len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
