"""Figure output shared by the plotting scripts: size and file checks, panels with a legend
strip, the thresholds of `astrojax thresholds` drawn as grey spans and the paper's values as
dashed lines. matplotlib is imported only when a figure is made (--help and bad input stay fast)."""
import os

import numpy as np

from .errors import fail
from .labels import for_figure

from .sweep import Sweep, select_chains
from .thresholds import number, thresholds_for

PI = np.pi
# astrojax thresholds' names (sweep::to_string) and how the figures write them.
THRESHOLD_SYMBOLS = {"omega_rise": "ω_rise", "omega_fall": "ω_fall", "omega_1": "ω1", "omega_2": "ω2"}
BRACKET_SHADE = "0.82"   # a measured bracket: a grey span
PAPER_LINE = {"color": "k", "ls": "--", "lw": 0.8}  # the paper's measured value
MODE_NAMES = {0: "sliding", 1: "on bottom ball", 2: "stuck", 3: "top stop", 4: "slack"}
MODE_COLOURS = {0: "tab:blue", 1: "tab:grey", 2: "tab:orange", 3: "tab:red", 4: "tab:green"}


def sweep_for_plot(args):
    """The sweep of a plotting script, its chains with classified windows (--chains), their
    thresholds and their grid-point groups."""
    sweep = Sweep(args.input)
    chains = [c for c in select_chains(sweep, args.chains) if sweep.valid[c].any()]
    if not chains:
        fail(f"{args.input}: no classified windows to draw")
    return sweep, chains, thresholds_for(args, args.input), sweep.groups(chains)


def draw_thresholds(ax, rows, chains, paper=True, values=False):
    """On an axis with ω_m [π rad/s] along x: each chain's threshold brackets as grey spans
    labelled with their symbol (values=True: and the bracket's ends, written upright beside it),
    and (paper=True) the paper's measured values as dashed black lines (values=True: labelled)."""
    labels = []  # (x, text, ha) of the upright labels, placed below
    for row in rows:
        if int(row["chain"]) not in chains:
            continue
        lo, hi = sorted((number(row["before_rad_s"]) / PI, number(row["after_rad_s"]) / PI))
        if not np.isfinite(lo):
            continue
        ax.axvspan(lo, hi, color=BRACKET_SHADE, lw=0, zorder=0)
        symbol = THRESHOLD_SYMBOLS.get(row["threshold"]) or for_figure(row["threshold"], 20)
        if values:
            labels.append((hi, f" {symbol} {lo:.2f}–{hi:.2f}π", "left", "bold"))
        else:
            ax.text(0.5 * (lo + hi), 1.0, symbol, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                    fontsize=7, color="k", fontweight="bold")
    if paper:
        for name, p in paper_values(rows).items():
            ax.axvline(p / PI, zorder=1, **PAPER_LINE)
            if values:
                labels.append((p / PI, f"paper {THRESHOLD_SYMBOLS.get(name) or for_figure(name, 20)} ", "right", "normal"))
    place_upright_labels(ax, labels)


def place_upright_labels(ax, labels, fontsize=7):
    """Upright labels hanging from the top of the axis beside their x; one that would overlap
    an earlier one on the same side drops to the next tier."""
    x0, x1 = ax.get_xlim() if ax.get_xlim()[1] > 1 else (0.0, max([x for x, *_ in labels] + [1.0]) * 1.05)
    width = 0.03 * (x1 - x0)  # an upright 7-pt label's width, as a share of the axis
    placed = []
    for x, text, ha, weight in sorted(labels):
        edge = (x - width, x) if ha == "right" else (x, x + width)
        tier = 0
        while any(t == tier and e[0] < edge[1] and edge[0] < e[1] for t, e in placed):
            tier += 1
        placed.append((tier, edge))
        ax.text(x, 0.99 - 0.36 * (tier % 3), text, transform=ax.get_xaxis_transform(), ha=ha, va="top",
                fontsize=fontsize, rotation=90, color="k", fontweight=weight)


def paper_values(rows):
    """{threshold: the paper's measured value [rad/s]} as astrojax thresholds prints it."""
    out = {}
    for row in rows:
        p = number(row["paper_rad_s"])
        if np.isfinite(p):
            out.setdefault(row["threshold"], p)
    return out


def threshold_legend_handles(rows, paper=True):
    """Legend entries: the bracket shading and the paper's values."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    handles = [Patch(color=BRACKET_SHADE, label="threshold bracket (astrojax thresholds)")]
    if paper:
        values = ", ".join(f"{THRESHOLD_SYMBOLS.get(n) or for_figure(n, 20)} {p / PI:.2f}π" for n, p in paper_values(rows).items())
        handles.append(Line2D([], [], label=f"paper: {values}", **PAPER_LINE))
    return handles


def add_figure_args(ap, default_size):
    ap.add_argument("-o", "--output", required=True, help="image to write: .png or .pdf (by extension)")
    ap.add_argument("--size", default=None, metavar="W,H",
                    help=f"figure size in inches (default: {default_size}, or as the panels need)")
    ap.add_argument("--dpi", type=float, default=120, help="pixels per inch of a PNG (default 120)")


def figure_size(args, default):
    """--size 'W,H' in inches, else the default (a pair)."""
    if not args.size:
        return default
    try:
        w, h = (float(v) for v in args.size.split(","))
    except ValueError:
        fail(f"--size: '{args.size}' is not W,H in inches (for example 9,6)")
    if not (0 < w <= 100 and 0 < h <= 100):
        fail(f"--size: {w},{h} inches outside (0, 100]")
    return w, h


def check_output(path):
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".png", ".pdf"):
        fail(f"-o {path}: the extension must be .png or .pdf")


def pyplot():
    """matplotlib.pyplot without a display, imported only when a figure is made (--help and
    bad input stay fast)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save(fig, args):
    """Writes the figure at exactly its size (W·dpi × H·dpi pixels for a PNG)."""
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    fig.savefig(args.output, dpi=args.dpi)
    pyplot().close(fig)
    print(f"wrote {args.output}")


def new_figure(args, default_size, **kw):
    check_output(args.output)
    return pyplot().figure(figsize=figure_size(args, default_size), layout="constrained", **kw)


def panel_grid(n, max_cols=3):
    """Rows and columns for n panels."""
    cols = min(n, max_cols)
    return (n + cols - 1) // cols, cols


def legend_columns(width):
    """Legend columns that fit a figure width [in]."""
    return max(1, int(width / 2.1))


def legend_height(width, n_entries):
    """Height [in] of a legend strip with n entries across a figure width [in]."""
    return 0.2 + 0.2 * -(-n_entries // legend_columns(width))


def panels(fig, rows, cols, n_legend=0, **kw):
    """rows × cols axes above a strip for a legend of n_legend entries (an axis without
    frame); unused axes hidden by the caller. Returns (axes array rows × cols, legend axis)."""
    w, h = fig.get_size_inches()
    legend_height_in = min(legend_height(w, n_legend), 0.4 * h)
    h = max(h, legend_height_in + rows * 0.5)
    gs = fig.add_gridspec(rows + 1, cols, height_ratios=[(h - legend_height_in) / rows] * rows + [legend_height_in])
    axes = np.empty((rows, cols), dtype=object)
    for i in range(rows):
        for j in range(cols):
            share = {k: axes[0, 0] for k, v in kw.items() if v and i + j > 0}
            axes[i, j] = fig.add_subplot(gs[i, j], **share)
    leg = fig.add_subplot(gs[rows, :])
    leg.axis("off")
    return axes, leg


def legend(leg_ax, handles):
    """The legend in its strip, as many columns as the figure's width holds."""
    ncol = legend_columns(leg_ax.figure.figure.get_size_inches()[0])  # .figure.figure: the root figure
    leg_ax.legend(handles=handles, loc="center", ncol=min(len(handles), ncol), fontsize=7.5, frameon=False)


def runs(mask):
    """(i, j, value) for each run of consecutive equal values of mask, [i, j] inclusive: the
    pieces of a curve to draw in one style."""
    out, i = [], 0
    while i < len(mask):
        j = i
        while j + 1 < len(mask) and mask[j + 1] == mask[i]:
            j += 1
        out.append((i, j, mask[i]))
        i = j + 1
    return out
