#!/usr/bin/python3
"""Hysteresis diagram of a sweep: ω_ball against ω_m for every chain written by `astrojax sweep`.

Each window is a point at its mean ω_m, marked by direction (▲ ω_m rising, ▼ falling, ● held)
and coloured by orbit class; the diagonal ω_ball = ω_m is a locked orbit. The paper's measured
thresholds (ω_rise, ω_fall, ω1, ω2) are drawn as vertical lines for comparison. Windows whose
ω_ball is undefined (balls near the axis, sampling too coarse) sit on the lower axis as ×.
A second panel shows the bead's mean position L1 (where it climbs and falls).

Run with Debian's interpreter (it has numpy, h5py and matplotlib):
    /usr/bin/python3 analysis/plot_hysteresis.py out/quick.h5 -o out/quick_hysteresis.png
"""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

CLASS_COLOURS = {
    "fallen": "tab:grey",
    "locked-circular": "tab:blue",
    "lagging-circular": "tab:green",
    "flower": "tab:purple",
    "not-settled": "tab:orange",
    "failed": "tab:red",
}
MARKERS = {1: "^", -1: "v", 0: "o"}
# The paper's measured thresholds [π rad/s] (shared/model.md).
PAPER = {"ω_rise": 12.63, "ω_fall": 3.24, "ω1": 4.80, "ω2": 15.00}


def class_names(ds):
    names = ds.attrs["names"]
    names = names.decode() if isinstance(names, bytes) else names
    return {int(k): v for k, v in (item.split(" ", 1) for item in names.split(","))}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ap.add_argument("-o", "--output", required=True, help="image to write (.png or .pdf)")
    ap.add_argument("--chains", default="all", help="comma-separated chain indices to draw (default: all)")
    args = ap.parse_args(argv)

    with h5py.File(args.input, "r") as f:
        w = f["windows"]
        names = class_names(w["class"])
        cls = w["class"][:]
        wm = 0.5 * (w["omega_m_begin"][:] + w["omega_m_end"][:])
        wb = w["omega_ball"][:]
        direction = w["direction"][:]
        L1 = w["L1_mean"][:]
        model = f["chains/model"][:]
        axes = f["chains"].attrs.get("axes", "")
        axes = axes.decode() if isinstance(axes, bytes) else axes
        grid = f["chains/grid_values"][:] if "grid_values" in f["chains"] else None
    n_chains = cls.shape[0]
    chains = range(n_chains) if args.chains == "all" else [int(c) for c in args.chains.split(",")]
    if not any((cls[c] >= 0).any() for c in chains):
        sys.exit(f"{args.input}: no classified windows to draw")

    fig, (ax, ax_l) = plt.subplots(2, 1, figsize=(9, 8), sharex=True, height_ratios=[3, 1.3],
                                   constrained_layout=True)
    top = np.nanmax(wm[list(chains)]) / np.pi * 1.05
    ax.plot([0, top], [0, top], "k:", lw=0.8, label="ω_ball = ω_m (locked)")
    for name, value in PAPER.items():
        ax.axvline(value, color="k", lw=0.6, alpha=0.4)
        ax.text(value, 1.0, name, transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=8)
    seen = set()
    for c in chains:
        label_chain = ", ".join(f"{a}={v:g}" for a, v in zip(axes.split(","), grid[c])) if grid is not None and axes \
            else f"R={model[c, 7] * 1000:g} mm"
        for k in range(cls.shape[1]):
            if cls[c, k] < 0:
                continue
            name = names.get(int(cls[c, k]), "?")
            y = wb[c, k] / np.pi if np.isfinite(wb[c, k]) else 0.0
            marker = MARKERS.get(int(direction[c, k]), "o") if np.isfinite(wb[c, k]) else "x"
            label = name if name not in seen else None
            seen.add(name)
            ax.plot(wm[c, k] / np.pi, y, marker, color=CLASS_COLOURS.get(name, "k"), ms=5, label=label)
            ax_l.plot(wm[c, k] / np.pi, L1[c, k] * 100, marker, color=CLASS_COLOURS.get(name, "k"), ms=4)
        ax.plot([], [], " ", label=f"chain {c}: {label_chain}")
    ax.set_ylabel("ω_ball [π rad/s]")
    ax.set_xlim(0, top)
    ax.set_ylim(bottom=-0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(f"{args.input}: ▲ ω_m rising, ▼ falling; paper's thresholds as lines", fontsize=10)
    ax_l.set_ylabel("bead L1 [cm]")
    ax_l.invert_yaxis()
    ax_l.set_xlabel("ω_m [π rad/s]")
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
