#!/usr/bin/python3
"""An animation of one run file (`astrojax run`, or a sweep window re-run by `astrojax replay`):
the Astrojax moving, as the paper's videos show it, encoded by ffmpeg to .mp4 or .gif.

Two views side by side: the front view (x–z, the camera level with the pendulum) and the
bottom view (x–y seen from below, as the paper's mirror shows it: y points down on the
screen, so an orbit that turns counter-clockwise seen from above turns clockwise here). In
each: the motor's rod from the axis to the drive circle (radius R), the string as its two
straight segments from its top through the bead to the bottom ball, a trail of both balls
that fades over --trail seconds, and the bead coloured by its mode (sliding, stuck, on the
bottom ball, at the top, slack string). Beside them: t, ω_m, the balls' ω_ball over the last
second (their mean azimuth rate about the motor axis; undefined near the axis), the orbit
class of a replayed window, and the run file's energy ledger since the first frame as bars:
the motor's work at its rod = Δ kinetic + Δ potential + drag + friction + impact losses, and,
with the tie clutch (layers.tie = "clutch"), + the clutch's loss + the tie's Δ kinetic energy
½ I_a χ̇² (the motor's work that never reaches the string). The string's top is drawn where the
tie is, at its azimuth χ; the rod at the motor's phase φ (they differ while the clutch slips).

Real time by default (--speed 0.25 plays four times slower); --frame turning shows the frame
turning with the motor's rod, where a locked orbit stands still. Frames are drawn by
matplotlib and piped to ffmpeg (Debian's ffmpeg package); progress goes to stderr.

usage: build/astrojax replay out/paper.h5 --chain 3 --window 40 -o out/lagging.h5
       /usr/bin/python3 analysis/animate.py out/lagging.h5 -o out/lagging.mp4
       /usr/bin/python3 analysis/animate.py out/lagging.h5 -o out/lagging.gif --speed 0.5 --frame turning --to 4
"""
import os
import shutil
import subprocess
import sys
import time
import warnings

import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
CM = 100.0
# The ledger's bars, top to bottom: (key, label, colour), each from the first frame on. The
# last two only with the tie clutch: motor_work = Δ tie energy + clutch_loss + string_work.
BARS = (("motor", "motor's work at the rod", "#333333"), ("kinetic", "Δ kinetic", "#56B4E9"),
        ("potential", "Δ potential", "#56B4E9"), ("drag", "drag loss", "#D55E00"),
        ("friction", "friction loss", "#D55E00"), ("impact", "impact loss", "#D55E00"),
        ("clutch", "clutch loss (before the string)", "#999999"), ("tie", "Δ the tie's kinetic energy", "#999999"))
CLUTCH_BARS = ("clutch", "tie")
BEAD_TRAIL, BALL_TRAIL, BALL = "#8C6D31", "0.35", "0.1"
FIG_WIDTH = 10.24       # the layout's width [in]; --width sets the pixels, fonts scale with it
TRAIL_PIECES = 8        # a trail fades in this many steps of opacity
OMEGA_BALL_SPAN = 1.0   # ω_ball readout: the azimuth rate over the last second [s]
MIN_RADIUS = 0.01       # ... of balls at least 1 cm off the axis [m]


def check_args(args, run):
    ext = os.path.splitext(args.output)[1].lower()
    if ext not in (".mp4", ".gif"):
        ajx.fail(f"-o {args.output}: the extension must be .mp4 or .gif")
    if os.path.exists(args.output) and not args.force:
        ajx.fail(f"-o {args.output}: exists; add --force to replace it")
    if not shutil.which("ffmpeg"):
        ajx.fail("ffmpeg not found: install Debian's ffmpeg (./setup.sh install does)")
    for name in ("speed", "fps", "trail"):
        v = getattr(args, name)
        if not (np.isfinite(v) and v > 0):
            ajx.fail(f"--{name} {v}: must be a positive number")
    if not (160 <= args.width <= 3840 and args.width % 16 == 0):
        ajx.fail(f"--width {args.width}: a multiple of 16 in [160, 3840] pixels")
    if not 1 <= args.fps <= 120:
        ajx.fail(f"--fps {args.fps}: outside [1, 120]")
    t = run["t"]
    t0 = t[0] if args.start is None else args.start
    t1 = t[-1] if args.to is None else args.to
    if not t[0] <= t0 < t1 <= t[-1]:
        ajx.fail(f"--start {t0:g} --to {t1:g}: need {t[0]:g} <= start < to <= {t[-1]:g} s, the run file's samples")
    frames = int(np.floor((t1 - t0) / args.speed * args.fps)) + 1
    if frames > 100000:
        ajx.fail(f"--start/--to/--speed: {frames} frames, more than 100000; show less, or speed up")
    if frames < 2:
        ajx.fail(f"--start/--to/--speed: {frames} frame; show more")
    return t0, t1, frames


def frame_times(t0, frames, speed, fps):
    """Run time of each frame: real time × --speed."""
    return t0 + np.arange(frames) * speed / fps


def live_omega_ball(t, r1, r2):
    """The balls' ω_ball at each sample over the last OMEGA_BALL_SPAN: the rate of their unwrapped
    azimuths, averaged over those at least MIN_RADIUS off the axis (NaN where neither is)."""
    rates = []
    back = np.searchsorted(t, t - OMEGA_BALL_SPAN)
    for r in (r1, r2):
        theta = np.unwrap(np.arctan2(r[:, 1], r[:, 0]))
        far = np.hypot(r[:, 0], r[:, 1]) >= MIN_RADIUS
        ok = far & far[back] & (t - t[back] > 0.5 * OMEGA_BALL_SPAN)
        rate = np.where(ok, (theta - theta[back]) / np.maximum(t - t[back], 1e-12), np.nan)
        rates.append(rate)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a sample where neither ball is off the axis
        return np.nanmean(np.stack(rates), axis=0) if np.isfinite(np.stack(rates)).any() else np.full(len(t), np.nan)


def ledger(run):
    """Each bar's value at each sample [J], from the first sample: kinetic and potential from
    E and the heights, U = g (m1 z1 + m2 z2), the motor's work and the losses from the run
    file's integrals (/trajectory/motor_work, drag_loss, ..., clutch_loss, tie_energy)."""
    g = float(run["resolved"].get("model.gravity", 9.81))
    m1, m2 = float(run["resolved"]["model.bead_mass"]), float(run["resolved"]["model.ball_mass"])
    pot = g * (m1 * run["r1"][:, 2] + m2 * run["r2"][:, 2])
    kin = run["energy"] - pot
    values = {"motor": run["motor_work"], "kinetic": kin, "potential": pot, "drag": run["drag_loss"],
              "friction": run["friction_loss"], "impact": run["impact_loss"], "clutch": run["clutch_loss"],
              "tie": run["tie_energy"]}
    return {k: v - v[0] for k, v in values.items()}


def has_clutch(run):
    return run["resolved"].get("layers.tie") == "clutch" or bool(np.any(run["clutch_loss"] != run["clutch_loss"][0]))


def sampled(run, times, frame):
    """The run at the frame times: positions interpolated linearly, the mode the last sample's,
    positions in the lab or in the frame turning with the motor's rod."""
    t = run["t"]
    idx = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(t) - 1)
    out = {"idx": idx}
    for name in ("r1", "r2"):
        out[name] = np.stack([np.interp(times, t, run[name][:, j]) for j in range(3)], axis=1)
    out["omega_m"] = np.interp(times, t, run["omega_m"])
    for name in ("phi", "chi"):  # the rod's phase φ and the top's azimuth χ, unwrapped to interpolate
        out[name] = np.interp(times, t, np.unwrap(run[name]))
    if frame == "turning":
        for name in ("r1", "r2"):
            out[name] = ajx.corotating(out[name], out["phi"])
        out["chi"] = out["chi"] - out["phi"]
        out["phi"] = np.zeros_like(times)
    return out


def trail_positions(run, frame, times):
    """Both balls at every sample (the trails), in the chosen frame: in the turning frame each
    sample is turned by the rod's phase at that sample."""
    r = {n: run[n] for n in ("r1", "r2")}
    if frame == "turning":
        r = {n: ajx.corotating(v, run["phi"]) for n, v in r.items()}
    return r


class Scene:
    """The figure and its artists, updated in place each frame."""

    def __init__(self, args, run, title, span):
        plt = ajx.pyplot()
        from matplotlib.lines import Line2D
        self.run = run
        self.R = float(run["resolved"]["model.drive_radius"])
        self.fig = plt.figure(figsize=(FIG_WIDTH, FIG_WIDTH * 9 / 16), dpi=args.width / FIG_WIDTH)
        gs = self.fig.add_gridspec(2, 3, width_ratios=[1, 1, 0.95], height_ratios=[0.42, 0.58],
                                   left=0.06, right=0.98, bottom=0.08, top=0.86, wspace=0.22, hspace=0.3)
        self.front = self.fig.add_subplot(gs[:, 0])
        self.bottom = self.fig.add_subplot(gs[:, 1])
        self.text_ax = self.fig.add_subplot(gs[0, 2])
        self.bars_ax = self.fig.add_subplot(gs[1, 2])
        self.fig.suptitle(title, fontsize=9)
        lim = max(np.abs(run[n][:, :2]).max() for n in ("r1", "r2")) * CM * 1.1
        zlo = min(run["r1"][:, 2].min(), run["r2"][:, 2].min()) * CM * 1.05
        lim = max(lim, self.R * CM * 2)
        for ax, ylim, ylabel, name in ((self.front, (min(zlo, -5), 6), "z [cm]", "front view (x–z)"),
                                       (self.bottom, (lim, -lim), "y [cm]  (seen from below)", "bottom view (x–y)")):
            ax.set_xlim(-lim, lim)
            ax.set_ylim(*ylim)
            ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel("x [cm]" if args.frame == "lab" else "x' [cm] (along the rod)", fontsize=8)
            ax.set_ylabel(ylabel if args.frame == "lab" else ylabel.replace("y [", "y' ["), fontsize=8)
            ax.set_title(name + (", turning with the motor" if args.frame == "turning" else ""), fontsize=8.5)
            ax.tick_params(labelsize=7)
            ax.grid(True, color="0.93", lw=0.5)
        # The drive circle: a circle from below, a segment at z = 0 from the front; the axis.
        a = np.linspace(0, 2 * PI, 120)
        self.bottom.plot(self.R * CM * np.cos(a), self.R * CM * np.sin(a), "k--", lw=0.6)
        self.front.plot([-self.R * CM, self.R * CM], [0, 0], "k--", lw=0.6)
        self.front.plot([0, 0], [0, 6], "k-", lw=1.5)  # the motor's shaft above the rod
        self.bottom.plot(0, 0, "kx", ms=4)
        self.trail = {}
        self.parts = {}
        for ax, j in ((self.front, 2), (self.bottom, 1)):
            key = id(ax)
            for name, colour in (("r1", BEAD_TRAIL), ("r2", BALL_TRAIL)):  # oldest piece faintest
                self.trail[(key, name)] = [ax.plot([], [], "-", color=colour, lw=1.0, animated=True,
                                                   alpha=(i + 1) / TRAIL_PIECES)[0] for i in range(TRAIL_PIECES)]
            rod, = ax.plot([], [], "-", color="k", lw=2.2, solid_capstyle="round", animated=True)
            string, = ax.plot([], [], "-", color="0.25", lw=0.9, animated=True)
            ball, = ax.plot([], [], "o", color=BALL, ms=8, animated=True)
            bead, = ax.plot([], [], "o", ms=7, mec="k", mew=0.6, animated=True)
            self.parts[key] = (rod, string, ball, bead, j)
        self.text_ax.axis("off")
        self.readout = self.text_ax.text(0.0, 1.0, "", va="top", ha="left", fontsize=9, family="DejaVu Sans",
                                         transform=self.text_ax.transAxes, animated=True)
        handles = [Line2D([], [], ls="", marker="o", ms=6, mec="k", mew=0.5, color=ajx.MODE_COLOURS[m],
                          label=f"bead {ajx.MODE_NAMES[m]}") for m in sorted(ajx.MODE_NAMES)]
        handles += [Line2D([], [], ls="", marker="o", ms=6, color=BALL, label="bottom ball"),
                    Line2D([], [], color=BEAD_TRAIL, label="bead's trail"),
                    Line2D([], [], color=BALL_TRAIL, label="ball's trail"),
                    Line2D([], [], color="k", lw=2.2, label="motor's rod"),
                    Line2D([], [], color="k", ls="--", lw=0.6, label="drive circle")]
        self.text_ax.legend(handles=handles, loc="lower left", fontsize=6.5, ncol=2, frameon=False,
                            bbox_to_anchor=(0.0, -0.12))
        self.setup_bars(run, *span)

    def artists(self):
        """What changes from frame to frame (drawn over the static background)."""
        out = [piece for pieces in self.trail.values() for piece in pieces]
        for rod, string, ball, bead, _ in self.parts.values():
            out += [rod, string, ball, bead]
        return out + [self.readout] + list(self.bar_artists)

    def setup_bars(self, run, first, last):
        """The ledger's bars from the first frame's sample (index `first`) on, scaled to their
        range up to the last frame's (`last`)."""
        self.bars = {k: v - v[first] for k, v in ledger(run).items()}
        clutch = has_clutch(run)
        keys = [k for k, _, _ in BARS if clutch or k not in CLUTCH_BARS]
        self.bar_keys = keys
        ax = self.bars_ax
        span = slice(first, last + 1)
        lo = min(0.0, min(self.bars[k][span].min() for k in keys)) * 1e3
        hi = max(0.0, max(self.bars[k][span].max() for k in keys)) * 1e3
        pad = 0.08 * (hi - lo or 1.0)
        ax.set_xlim(lo - pad, hi + pad)
        y = np.arange(len(keys))[::-1]
        label = {k: text for k, text, _ in BARS}
        colour = {k: c for k, _, c in BARS}
        self.bar_artists = ax.barh(y, np.zeros(len(keys)), height=0.45, color=[colour[k] for k in keys])
        for bar in self.bar_artists:
            bar.set_animated(True)
        for yk, k in zip(y, keys):  # each bar's name above it, inside the axis
            ax.text(0.01, yk + 0.28, label[k], transform=ax.get_yaxis_transform(), fontsize=7, va="bottom")
        ax.set_ylim(-0.6, len(keys) - 0.1)
        ax.set_yticks([])
        ax.axvline(0, color="k", lw=0.6)
        ax.set_xlabel("energy since the first frame [mJ]", fontsize=7.5)
        ax.tick_params(axis="x", labelsize=7)
        ax.set_title("motor's work at the rod = Δ kinetic + Δ potential\n+ the losses" +
                     (" + the tie's Δ kinetic" if clutch else ""), fontsize=7)

    def update(self, f, s, times, trails, omega_ball, cls):
        run, R = self.run, self.R
        i = s["idx"][f]
        t = times[f]
        first = np.searchsorted(run["t"], t - self.trail_seconds)
        last = max(int(i) + 1, first + 1)
        for ax in (self.front, self.bottom):
            rod, string, ball, bead, j = self.parts[id(ax)]
            tip = np.array([R * np.cos(s["phi"][f]), R * np.sin(s["phi"][f]), 0.0]) * CM
            top = np.array([R * np.cos(s["chi"][f]), R * np.sin(s["chi"][f]), 0.0]) * CM
            r1, r2 = s["r1"][f] * CM, s["r2"][f] * CM
            rod.set_data([0, tip[0]], [0, tip[j]])
            string.set_data([top[0], r1[0], r2[0]], [top[j], r1[j], r2[j]])
            ball.set_data([r2[0]], [r2[j]])
            bead.set_data([r1[0]], [r1[j]])
            bead.set_color(ajx.MODE_COLOURS[int(run["mode"][i])])
            bead.set_markeredgecolor("k")
            for name in ("r1", "r2"):
                p = trails[name][first:last] * CM
                cuts = np.linspace(0, len(p) - 1, TRAIL_PIECES + 1).astype(int)
                for piece, a, b in zip(self.trail[(id(ax), name)], cuts[:-1], cuts[1:]):
                    piece.set_data(p[a:b + 1, 0], p[a:b + 1, j])
        w = omega_ball[i]
        lines = [f"t = {t:8.2f} s",
                 f"ω$_m$ = {s['omega_m'][f] / PI:6.3f}π rad/s",
                 "ω$_{ball}$ = " + (f"{w / PI:6.3f}π rad/s" if np.isfinite(w) else
                                    "(measuring)" if t - run["t"][0] <= 0.5 * OMEGA_BALL_SPAN else
                                    "undefined (near the axis)"),
                 f"bead: {ajx.MODE_NAMES[int(run['mode'][i])]}"]
        if cls:
            lines.append(f"orbit class: {cls}")
        self.readout.set_text("\n".join(lines))
        for bar, k in zip(self.bar_artists, self.bar_keys):
            bar.set_width(self.bars[k][i] * 1e3)


def encode(scene, args, path, frames, update, started):
    """Each frame drawn over the static background (blitting: only the moving artists are drawn
    again) and piped as raw RGBA to ffmpeg, matplotlib's FFMpegWriter's encoder settings: H.264
    in yuv420p for .mp4, ffmpeg's GIF encoder for .gif."""
    from matplotlib.animation import FFMpegWriter
    fig = scene.fig
    canvas = fig.canvas
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    w, h = canvas.get_width_height()
    codec = ["-c:v", "libx264", "-pix_fmt", "yuv420p", "-preset", "veryfast"] if path.lower().endswith(".mp4") \
        else ["-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse", "-c:v", "gif"]  # a palette of the video's colours
    cmd = [FFMpegWriter.bin_path(), "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgba",
           "-s", f"{w}x{h}", "-r", f"{args.fps:g}", "-i", "pipe:", *codec, "-r", f"{args.fps:g}", path]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        for f in range(frames):
            update(f)
            canvas.restore_region(background)
            for a in scene.artists():
                fig.draw_artist(a)
            proc.stdin.write(canvas.buffer_rgba())
            progress(f + 1, frames, started)
        proc.stdin.close()
    finally:
        if proc.wait() != 0:
            ajx.fail(f"ffmpeg failed writing {path}: {proc.stderr.read().decode(errors='replace').strip()}")


def title_of(run, args):
    rs, rp = run["resolved"], run["replay"]
    R, d = float(rs["model.drive_radius"]), float(rs["model.contact_distance"])
    params = f"R = {R * 1e3:.3g} mm, d = {d * 1e2:.3g} cm"
    if rs.get("layers.tie") == "clutch":
        params += (f", tie clutch $\\tau_s$ = {float(rs['model.tie_static_torque']) * 1e3:.3g}, "
                   f"$\\tau_k$ = {float(rs['model.tie_kinetic_torque']) * 1e3:.3g} mN m, "
                   f"$c_a$ = {float(rs['model.tie_damping']) * 1e6:.3g} µN m s")
    else:
        params += ", rigid tie"
    if rp:
        who = f" ({ajx.for_figure(rp['group'], 40)}, {ajx.for_figure(rp['variant'], 40)})" if rp.get("group") else ""
        where = f"{ajx.for_figure(os.path.basename(str(rp['source'])))} chain {rp['chain']}{who}, window {rp['window']}"
        head = f"{where}: {params}"
    else:
        head = f"{ajx.for_figure(os.path.basename(args.input))}; {params}"
    speed = "real time" if args.speed == 1 else f"{args.speed:g}× real time"
    return f"{head}\n{speed}"


def progress(done, total, started):
    """Every 5 % of the frames: on a terminal one line rewritten, else a line each."""
    if done % max(1, total // 20) and done != total:
        return
    rate = done / max(time.monotonic() - started, 1e-9)
    tty = sys.stderr.isatty()
    print(f"{chr(13) if tty else ''}frame {done}/{total} ({rate:.0f} frames/s)",
          end="\n" if done == total or not tty else "", file=sys.stderr, flush=True)


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax run` or `astrojax replay`")
    ap.add_argument("-o", "--output", required=True, help="video to write: .mp4 (H.264) or .gif")
    ap.add_argument("--speed", type=float, default=1.0, help="run seconds per second of video (default 1: real time)")
    ap.add_argument("--fps", type=float, default=25.0, help="frames per second of video (default 25)")
    ap.add_argument("--frame", choices=("lab", "turning"), default="lab",
                    help="lab frame, or the frame turning with the motor's rod (default lab)")
    ap.add_argument("--start", type=float, help="run time of the first frame [s] (default: the first sample)")
    ap.add_argument("--to", type=float, help="run time of the last frame [s] (default: the last sample)")
    ap.add_argument("--trail", type=float, default=1.0, help="seconds of path that fade behind each ball (default 1)")
    ap.add_argument("--width", type=int, default=1024,
                    help="video width in pixels, a multiple of 16 (default 1024: 1024 × 576); the height is 9/16 of it")
    ap.add_argument("--force", action="store_true", help="replace an existing output")
    args = ap.parse_args(argv)
    run = ajx.read_motion(args.input)
    t0, t1, frames = check_args(args, run)
    times = frame_times(t0, frames, args.speed, args.fps)
    s = sampled(run, times, args.frame)
    trails = trail_positions(run, args.frame, times)
    omega_ball = live_omega_ball(run["t"], run["r1"], run["r2"])
    cls = str(run["replay_stored"].get("class_name", "")) if run["replay"] else ""
    scene = Scene(args, run, title_of(run, args), (int(s["idx"][0]), int(s["idx"][-1])))
    scene.trail_seconds = args.trail
    partial = args.output + ".part" + os.path.splitext(args.output)[1]
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    started = time.monotonic()
    try:
        encode(scene, args, partial, frames, lambda f: scene.update(f, s, times, trails, omega_ball, cls), started)
    except BaseException:
        if os.path.exists(partial):
            os.remove(partial)
        raise
    os.replace(partial, args.output)
    print(f"wrote {args.output}: {frames} frames at {args.fps:g} fps, t {t0:g}–{times[-1]:g} s of the run "
          f"({args.frame} frame), {time.monotonic() - started:.1f} s")


if __name__ == "__main__":
    ajx.run(main)
