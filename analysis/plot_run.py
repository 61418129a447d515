#!/usr/bin/python3
"""Plot one trajectory written by `astrojax run`.

Panels against time: the motor's ω_m and the balls' ω_ball (rate of the unwrapped azimuth
about the motor axis, averaged over --window seconds), both in units of π rad/s; the bead's
position s = L1 along the string with the contact mode; the orbit radius of both balls.
A last panel shows the top view of both balls over the final --tail seconds.

usage: /usr/bin/python3 analysis/plot_run.py out/spin_up.h5 -o out/spin_up.png
"""
import sys

import numpy as np

import astrojax_analysis as ajx


def azimuth_rate(t, xy, window):
    """d(unwrapped azimuth)/dt, as a centred difference over `window` seconds."""
    theta = np.unwrap(np.arctan2(xy[:, 1], xy[:, 0]))
    dt = np.median(np.diff(t))
    k = max(1, int(round(0.5 * window / dt)))
    rate = np.full_like(t, np.nan)
    rate[k:-k] = (theta[2 * k:] - theta[:-2 * k]) / (t[2 * k:] - t[:-2 * k])
    return rate


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax run`")
    ajx.add_figure_args(ap, "11,8")
    ap.add_argument("--window", type=float, default=1.0, help="averaging window for ω_ball [s] (default 1)")
    ap.add_argument("--tail", type=float, default=2.0, help="seconds of orbit in the top view (default 2)")
    args = ap.parse_args(argv)

    run = ajx.read_run(args.input)
    t, r1, r2, L1, mode, wm = (run[k] for k in ("t", "r1", "r2", "L1", "mode", "omega_m"))
    summary = run["summary"]
    if len(t) < 3:
        ajx.fail(f"{args.input}: fewer than 3 samples, nothing to plot")
    dt = np.median(np.diff(t))
    if np.max(np.abs(wm)) * dt > np.pi:
        print(f"warning: sample interval {dt:g} s is too coarse to unwrap the azimuth at ω_m = {np.max(wm):.1f} rad/s",
              file=sys.stderr)

    fig = ajx.new_figure(args, (11, 8))
    gs = fig.add_gridspec(3, 2, width_ratios=[2.2, 1])
    ax_w = fig.add_subplot(gs[0, 0])
    ax_s = fig.add_subplot(gs[1, 0], sharex=ax_w)
    ax_r = fig.add_subplot(gs[2, 0], sharex=ax_w)
    ax_top = fig.add_subplot(gs[:, 1])

    ax_w.plot(t, wm / np.pi, "k-", lw=1.2, label="ω_m (motor)")
    ax_w.plot(t, azimuth_rate(t, r1, args.window) / np.pi, lw=0.8, label="ω_ball, bead")
    ax_w.plot(t, azimuth_rate(t, r2, args.window) / np.pi, lw=0.8, label="ω_ball, bottom ball")
    ax_w.set_ylabel("angular velocity [π rad/s]")
    ax_w.legend(loc="upper left", fontsize=8)

    for m, name in ajx.MODE_NAMES.items():
        sel = mode == m
        if sel.any():
            ax_s.plot(t[sel], L1[sel] * 100, ".", ms=1.5, color=ajx.MODE_COLOURS[m], label=name)
    ax_s.set_ylabel("bead position s = L1 [cm]")
    ax_s.invert_yaxis()  # up the string is up
    ax_s.legend(loc="lower left", fontsize=8, markerscale=6)

    ax_r.plot(t, np.hypot(r1[:, 0], r1[:, 1]) * 100, lw=0.8, label="bead")
    ax_r.plot(t, np.hypot(r2[:, 0], r2[:, 1]) * 100, lw=0.8, label="bottom ball")
    ax_r.set_ylabel("orbit radius [cm]")
    ax_r.set_xlabel("t [s]")
    ax_r.legend(loc="upper left", fontsize=8)

    tail = t >= t[-1] - args.tail
    ax_top.plot(r1[tail, 0] * 100, r1[tail, 1] * 100, lw=0.8, label="bead")
    ax_top.plot(r2[tail, 0] * 100, r2[tail, 1] * 100, lw=0.8, label="bottom ball")
    ax_top.plot([0], [0], "k+")
    ax_top.set_aspect("equal", adjustable="datalim")
    ax_top.set_xlabel("x [cm]")
    ax_top.set_ylabel("y [cm]")
    ax_top.set_title(f"top view, last {args.tail:g} s", fontsize=9)
    ax_top.legend(fontsize=8)

    status, final_mode = (ajx.as_text(summary.get(k, "?")) for k in ("status", "final_mode"))
    fig.suptitle(f"{args.input}: {status}, final mode {final_mode}, "
                 f"ω_ball {summary.get('omega_ball', float('nan')) / np.pi:.3f}π rad/s at the end", fontsize=10)
    ajx.save(fig, args)


if __name__ == "__main__":
    ajx.run(main)
