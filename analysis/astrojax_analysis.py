"""Shared code of the analysis scripts: reading sweep and run files, the thresholds that
`astrojax thresholds` finds, the colours and markers of orbit classes, and figure output.

Every script in analysis/ imports this module (it sits next to them); nothing here draws a
whole figure. Files read:
- a sweep file (`astrojax sweep`): /windows/* (chains × windows), /samples/* (chains × windows
  × samples), /chains/* (grid values, model, hold seeds);
- a run file (`astrojax run`): /trajectory/*;
- the CSV of `astrojax thresholds FILE --csv OUT`, the one place where thresholds are found
  (src/sweep/thresholds.cpp); the scripts never find thresholds themselves.
"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

PI = np.pi

# Orbit classes (the 'names' attribute of /windows/class) and their colours, the same in every
# figure: the Okabe–Ito palette, told apart with any colour vision; grey for the fallen bead.
# Thresholds are drawn in black and grey only, so no threshold mark shares a class colour.
CLASS_COLOURS = {
    "fallen": "#999999",
    "locked-circular": "#0072B2",
    "lagging-circular": "#009E73",
    "flower": "#CC79A7",
    "not-settled": "#E69F00",
    "failed": "#000000",
}
# Classes of a steady orbit: where two of them meet at one ω_m, two orbits coexist.
STEADY_CLASSES = ("fallen", "locked-circular", "lagging-circular", "flower")
# Marker by /windows/direction: ▲ ω_m rising, ▼ falling, ● held.
DIRECTION_MARKERS = {1: "^", -1: "v", 0: "o"}
DIRECTION_WORDS = {1: "ω_m rising", -1: "ω_m falling", 0: "ω_m held"}
# Held windows (hold mode): marker by seed, in the order of /chains/seed@names.
SEED_MARKERS = ["o", "s", "D", "P", "X", "*"]
# Chain groups of a grouped sweep (/chains/group): marker by group, in the order of its names.
GROUP_MARKERS = ["o", "s", "D", "P", "X", "*"]
# astrojax thresholds' names (sweep::to_string) and how the figures write them.
THRESHOLD_SYMBOLS = {"omega_rise": "ω_rise", "omega_fall": "ω_fall", "omega_1": "ω1", "omega_2": "ω2"}
BRACKET_SHADE = "0.82"   # a measured bracket: a grey span
PAPER_LINE = {"color": "k", "ls": "--", "lw": 0.8}  # the paper's measured value
MODE_NAMES = {0: "sliding", 1: "on bottom ball", 2: "stuck", 3: "top stop", 4: "slack"}
MODE_COLOURS = {0: "tab:blue", 1: "tab:grey", 2: "tab:orange", 3: "tab:red", 4: "tab:green"}


def as_text(value):
    """An HDF5 string, whether h5py returns it as str or bytes."""
    return value.decode() if isinstance(value, bytes) else str(value)


def text_attr(obj, name, default=""):
    return as_text(obj.attrs.get(name, default))


def parse_names(text):
    """'0 fallen,1 locked-circular,...' -> {0: 'fallen', 1: 'locked-circular', ...}."""
    return {int(k): v for k, v in (item.split(" ", 1) for item in text.split(",") if item)}


def fail(message):
    """Stop a script with a message on stderr and exit code 2 (bad input), like astrojax."""
    print(f"error: {message}", file=sys.stderr)
    sys.exit(2)


# The newest layout of run and sweep files this library reads (root attribute format_version;
# 1 when absent): 2 added /resolved (the configuration in force as values) and, in sweeps,
# /windows/phi_begin (the motor phase at each window start); 4 made motor_work and
# motor_power the motor's at the rod with a clutch (string_work, string_power, clutch_loss,
# clutch_power, /trajectory/chi new). 3 is the string lists of the reader's rework.
FORMAT_VERSION = 4


def format_version(f, path):
    """The file's format version (1 without the attribute); a newer one than this library
    reads stops the script, naming both."""
    v = int(f.attrs.get("format_version", 1))
    if v > FORMAT_VERSION:
        fail(f"{path}: file format version {v} is newer than this analysis library reads ({FORMAT_VERSION})")
    return v


def need(f, path, name, what):
    """Stop when an older file lacks `name`, saying what it is for and how to get it."""
    if name not in f:
        fail(f"{path}: the file (format version {format_version(f, path)}) lacks /{name}, {what}; "
             f"rerun it with this version of astrojax")


def resolved(group):
    """The configuration in force stored as /resolved attributes: {'model.drive_radius': 0.01, ...}."""
    return {k: (v.decode() if isinstance(v, bytes) else v.item() if hasattr(v, "item") else v)
            for k, v in group.attrs.items()}


def file_kind(path):
    """'sweep' (written by astrojax sweep) or 'run' (astrojax run); exits on anything else."""
    try:
        with h5py.File(path, "r") as f:
            format_version(f, path)
            if "windows" in f and "samples" in f:
                return "sweep"
            if "trajectory" in f:
                return "run"
    except OSError as e:
        fail(f"{path}: cannot read as HDF5: {e}")
    fail(f"{path}: neither a sweep file (/windows, /samples) nor a run file (/trajectory)")


class Sweep:
    """The per-window table of a sweep file, chains × windows, with ω in rad/s.

    Unclassified windows (class -1: the task never ran) are kept with their class; use
    `valid` to skip them."""

    def __init__(self, path):
        self.path = path
        if file_kind(path) != "sweep":
            fail(f"{path}: not a sweep file (no /windows): make one with `astrojax sweep`")
        with h5py.File(path, "r") as f:
            w = f["windows"]
            self.class_names = parse_names(text_attr(w["class"], "names"))
            self.cls = w["class"][:]
            self.omega_begin = w["omega_m_begin"][:]
            self.omega_end = w["omega_m_end"][:]
            self.phi_begin = w["phi_begin"][:] if "phi_begin" in w else None
            self.t_begin = w["t_begin"][:]
            self.direction = w["direction"][:]
            self.segment = w["segment"][:]
            layout = ("class", "direction", "segment")
            self.stats = {name: w[name][:] for name in w if w[name].ndim == 2 and name not in layout}
            ch = f["chains"]
            self.model = ch["model"][:]
            self.model_columns = [c.split(" [")[0] for c in text_attr(ch["model"], "columns").split(",")]
            axes = text_attr(ch, "axes")
            self.axes = [a for a in axes.split(",") if a]
            self.grid = ch["grid_values"][:] if "grid_values" in ch else np.zeros((self.cls.shape[0], 0))
            self.hold_omega = ch["hold_omega"][:] if "hold_omega" in ch else None
            self.seed = ch["seed"][:] if "seed" in ch else None
            self.seed_names = text_attr(ch["seed"], "names").split(",") if "seed" in ch else []
            self.perturbation = ch["perturbation"][:] if "perturbation" in ch else None
            # A grouped sweep: each chain's group and model variant (indices into the names).
            self.group = ch["group"][:] if "group" in ch else None
            self.group_names = text_attr(ch["group"], "names").split("\n") if "group" in ch else []
            self.group_purposes = text_attr(ch["group"], "purposes").split("\n") if "group" in ch else []
            self.variant = ch["variant"][:] if "variant" in ch else None
            self.variant_names = text_attr(ch["variant"], "names").split("\n") if "variant" in ch else []
            self.variant_labels = text_attr(ch["variant"], "labels").split("\n") if "variant" in ch else []
            self.start_seed = ch["start_seed"][:] if "start_seed" in ch else None
            self.start_seed_names = text_attr(ch["start_seed"], "names").split("\n") if "start_seed" in ch else []
            self.sample_rate = float(f["samples"].attrs.get("sample_rate", np.nan))
            prov = f["provenance"] if "provenance" in f else None
            self.provenance = {k: text_attr(prov, k) for k in prov.attrs} if prov is not None else {}
        self.n_chains, self.n_windows = self.cls.shape
        self.omega_mean = 0.5 * (self.omega_begin + self.omega_end)
        self.valid = self.cls >= 0

    @property
    def is_hold(self):
        return self.hold_omega is not None

    def class_name(self, c, k):
        return self.class_names.get(int(self.cls[c, k]), "?")

    def parameter(self, c, name):
        """A model parameter of chain c by its /chains/model column name (SI units)."""
        return float(self.model[c, self.model_columns.index(name)])

    def grid_label(self, c):
        """'drive_radius=0.01 ...' for the grid point of chain c ('' without grid axes)."""
        return " ".join(f"{a}={v:g}" for a, v in zip(self.axes, self.grid[c]) if np.isfinite(v))

    @property
    def is_grouped(self):
        return self.variant is not None

    def group_name(self, c):
        return self.group_names[int(self.group[c])] if self.is_grouped else ""

    def variant_name(self, c):
        return self.variant_names[int(self.variant[c])] if self.is_grouped else ""

    def start_seed_name(self, c):
        """Where a grouped sweep's chain starts: 'hanging', 'circular_high', ..."""
        return self.start_seed_names[int(self.start_seed[c])] if self.start_seed is not None else "hanging"

    def variant_label(self, c):
        return self.variant_labels[int(self.variant[c])] if self.is_grouped else ""

    def chain_label(self, c):
        label = f"chain {c}"
        if self.is_grouped:
            label += f" ({self.group_name(c)}, {self.variant_name(c)})"
        if self.grid_label(c):
            label += f": {self.grid_label(c)}"
        if self.is_hold:
            seed = self.seed_names[int(self.seed[c])] if self.seed_names else str(self.seed[c])
            label += f", seed {seed}" + (f" + kick {int(self.perturbation[c])}" if self.perturbation[c] else "")
        return label

    def marker(self, c, k):
        """▲/▼ by direction on ramps; on held windows, one marker per seed."""
        d = int(self.direction[c, k])
        if d == 0 and self.is_hold:
            return SEED_MARKERS[int(self.seed[c]) % len(SEED_MARKERS)]
        return DIRECTION_MARKERS.get(d, "o")

    def groups(self, chains=None):
        """Chains grouped for one panel each, in order: [(label, [chain, ...]), ...]. A grouped
        sweep: by model variant (its chain groups together); otherwise by grid point (a ramp
        sweep has one chain per grid point; a hold sweep one per held ω_m, seed and kick)."""
        chains = range(self.n_chains) if chains is None else chains
        out = {}
        for c in chains:
            key = (self.variant_name(c),) if self.is_grouped else tuple(np.nan_to_num(self.grid[c], nan=-1e300))
            out.setdefault(key, []).append(c)
        if self.is_grouped:
            return [(self.variant_label(cs[0]), cs) for cs in out.values()]
        return [(self.grid_label(cs[0]) or "all chains", cs) for cs in out.values()]

    def parameter_title(self, c):
        """The chain's drive and contact, in symbols and units: 'R = 15 mm, d = 3.5 cm'."""
        return (f"R = {self.parameter(c, 'drive_radius') * 1e3:.3g} mm, "
                f"d = {self.parameter(c, 'contact_distance') * 1e2:.3g} cm")

    def windows(self, c):
        """The classified windows of chain c, in protocol order."""
        return [k for k in range(self.n_windows) if self.valid[c, k]]

    def samples(self, c, k):
        """The stored samples of window k of chain c: dict of t, omega_m, L1, T1, T2, mode
        (n) and r1, r2 (n × 3), trimmed to /samples/count."""
        with h5py.File(self.path, "r") as f:
            s = f["samples"]
            n = int(s["count"][c, k])
            out = {name: s[name][c, k, :n] for name in ("t", "omega_m", "L1", "T1", "T2", "mode")}
            out["r1"] = s["r1"][c, k, :n, :]
            out["r2"] = s["r2"][c, k, :n, :]
        out["mode"] = out["mode"].astype(int)
        return out

    def legend_handles(self, chains):
        """Legend entries for the classes and markers used by these chains."""
        from matplotlib.lines import Line2D
        handles = []
        used = {self.class_name(c, k) for c in chains for k in self.windows(c)}
        for name in CLASS_COLOURS:
            if name in used:
                handles.append(Line2D([], [], ls="", marker="s", color=CLASS_COLOURS[name], label=name))
        dirs = {int(self.direction[c, k]) for c in chains for k in self.windows(c)}
        for d in (1, -1):
            if d in dirs:
                handles.append(Line2D([], [], ls="", marker=DIRECTION_MARKERS[d], color="k", mfc="none",
                                      label=DIRECTION_WORDS[d]))
        if 0 in dirs:
            if self.is_hold:
                for i in sorted({int(self.seed[c]) for c in chains}):
                    name = self.seed_names[i] if i < len(self.seed_names) else str(i)
                    handles.append(Line2D([], [], ls="", marker=SEED_MARKERS[i % len(SEED_MARKERS)], color="k",
                                          mfc="none", label=f"held, seed {name}"))
            else:
                handles.append(Line2D([], [], ls="", marker="o", color="k", mfc="none", label=DIRECTION_WORDS[0]))
        return handles


def sweep_for_plot(args):
    """The sweep of a plotting script, its chains with classified windows (--chains), their
    thresholds and their grid-point groups."""
    sweep = Sweep(args.input)
    chains = [c for c in select_chains(sweep, args.chains) if sweep.valid[c].any()]
    if not chains:
        fail(f"{args.input}: no classified windows to draw")
    return sweep, chains, thresholds_for(args, args.input), sweep.groups(chains)


def select_chains(sweep, text):
    """--chains: 'all' or comma-separated indices, checked against the file."""
    if text == "all":
        return list(range(sweep.n_chains))
    try:
        chains = [int(c) for c in text.split(",")]
    except ValueError:
        fail(f"--chains: '{text}' is not 'all' or a comma-separated list of chain indices")
    bad = [c for c in chains if not 0 <= c < sweep.n_chains]
    if bad:
        fail(f"--chains: {bad} outside 0..{sweep.n_chains - 1} of {sweep.path}")
    return chains


# ---- thresholds, from astrojax itself --------------------------------------------------

def find_astrojax(explicit=None):
    """The astrojax executable: --astrojax, else $ASTROJAX, else build/astrojax of this
    checkout, else astrojax on PATH; None if none exists. A path the user named (--astrojax or
    $ASTROJAX) that is not an executable file is an error, never passed over for another."""
    here = os.path.dirname(os.path.abspath(__file__))
    for name, named in (("--astrojax", explicit), ("$ASTROJAX", os.environ.get("ASTROJAX"))):
        if named:
            if os.path.isfile(named) and os.access(named, os.X_OK):
                return named
            fail(f"{name}: {named} is not an executable file")
    for candidate in (os.path.join(here, "..", "build", "astrojax"), shutil.which("astrojax")):
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    return None


def require_astrojax(explicit=None):
    """find_astrojax, or a clear error naming how to get one."""
    exe = find_astrojax(explicit)
    if exe is None:
        fail("cannot find the astrojax executable: build it (cmake --build build) or pass --astrojax PATH")
    return exe


def run_checked(cmd, allowed=(0,)):
    """Runs a command (astrojax, mostly); an exit code outside `allowed` is an error that quotes
    the command and what it printed. Returns the completed process."""
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if proc.returncode not in allowed:
        fail(f"`{' '.join(str(c) for c in cmd)}` exited with {proc.returncode}: {(proc.stderr or proc.stdout).strip()}")
    return proc


def write_report(path, text, stream=sys.stdout):
    """Writes a text report, making its folder, and says so on `stream`."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    print(f"wrote {path}", file=stream)


def run_thresholds(h5_path, astrojax, extra=()):
    """Runs `astrojax thresholds FILE --csv TMP [extra]`; returns (rows of its CSV, its stdout).
    Without --hold in `extra` the brackets alone (--no-hold): holds integrate, brackets do not."""
    extra = list(extra) if "--hold" in extra else ["--no-hold", *extra]
    with tempfile.TemporaryDirectory() as tmp:
        out_csv = os.path.join(tmp, "thresholds.csv")
        proc = run_checked([astrojax, "thresholds", h5_path, "--csv", out_csv, *extra])
        return read_thresholds_csv(out_csv), proc.stdout


def read_astrojax_csv(path, need, what):
    """The rows of a CSV that astrojax wrote, as dicts of strings (the text as written); it must
    have the columns `need`, else it is not `what`."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: cannot read: {e}")
    if rows and not need <= set(rows[0]):
        fail(f"{path}: not a CSV of `{what}` (columns {sorted(need - set(rows[0]))} missing)")
    return rows


def read_thresholds_csv(path):
    """The rows of `astrojax thresholds --csv`."""
    return read_astrojax_csv(path, {"chain", "threshold", "before_rad_s", "after_rad_s", "mid_rad_s", "paper_rad_s",
                                    "relative_difference"}, "astrojax thresholds")


def number(text):
    """A CSV field as a float; '' (not reached) is NaN."""
    return float(text) if text not in ("", None) else np.nan


def add_threshold_args(ap):
    ap.add_argument("--thresholds", metavar="CSV",
                    help="thresholds from `astrojax thresholds FILE --csv CSV` (default: run astrojax on the input)")
    ap.add_argument("--astrojax", metavar="PATH",
                    help="the astrojax executable (default: $ASTROJAX, build/astrojax, or astrojax on PATH)")
    ap.add_argument("--refine", metavar="F", type=int,
                    help="also refine every bracket F times slower (`astrojax thresholds --refine F`)")
    ap.add_argument("--hold", metavar="T",
                    help="also hold both sides of every bracket for T (seconds, or e.g. 5tau) and judge it a "
                         "bifurcation or a time-limited transient (`astrojax thresholds --hold T`)")


def thresholds_for(args, h5_path):
    """The threshold rows for a script's input: from --thresholds, else from astrojax."""
    if args.thresholds:
        return read_thresholds_csv(args.thresholds)
    exe = find_astrojax(args.astrojax)
    if exe is None:
        fail("cannot find the astrojax executable to compute the thresholds: build it (cmake --build build), "
             "or pass --astrojax PATH or --thresholds CSV")
    extra = ("--refine", str(args.refine)) if getattr(args, "refine", None) else ()
    extra += ("--hold", args.hold) if getattr(args, "hold", None) else ()
    extra += ("-j", str(os.cpu_count() or 1)) if extra else ()
    return run_thresholds(h5_path, exe, extra)[0]


def run_sequence(h5_path, astrojax):
    """Runs `astrojax thresholds FILE --sequence-csv TMP`; returns the rows of that CSV: kind
    'run' (a run of one orbit class on one leg) and kind 'step' (a step of the paper's
    sequence: present, out of order or missing)."""
    with tempfile.TemporaryDirectory() as tmp:
        out_csv = os.path.join(tmp, "sequence.csv")
        run_checked([astrojax, "thresholds", h5_path, "--no-hold", "--sequence-csv", out_csv])
        return read_sequence_csv(out_csv)


def read_sequence_csv(path):
    """The rows of `astrojax thresholds --sequence-csv`."""
    return read_astrojax_csv(path, {"chain", "kind", "class", "omega_from_rad_s", "omega_to_rad_s", "step", "status"},
                             "astrojax thresholds --sequence-csv")


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
        symbol = THRESHOLD_SYMBOLS.get(row["threshold"], row["threshold"])
        if values:
            labels.append((hi, f" {symbol} {lo:.2f}–{hi:.2f}π", "left", "bold"))
        else:
            ax.text(0.5 * (lo + hi), 1.0, symbol, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                    fontsize=7, color="k", fontweight="bold")
    if paper:
        for name, p in paper_values(rows).items():
            ax.axvline(p / PI, zorder=1, **PAPER_LINE)
            if values:
                labels.append((p / PI, f"paper {THRESHOLD_SYMBOLS.get(name, name)} ", "right", "normal"))
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
        values = ", ".join(f"{THRESHOLD_SYMBOLS.get(n, n)} {p / PI:.2f}π" for n, p in paper_values(rows).items())
        handles.append(Line2D([], [], label=f"paper: {values}", **PAPER_LINE))
    return handles


# ---- run files and the motor's frame ---------------------------------------------------

def read_run(path):
    """A run file's trajectory: dict of t, omega_m, phi, L1, mode (n), r1, r2 (n × 3), and
    the /summary attributes as 'summary'."""
    if file_kind(path) != "run":
        fail(f"{path}: not a run file (no /trajectory): make one with `astrojax run`")
    with h5py.File(path, "r") as f:
        tr = f["trajectory"]
        out = {name: tr[name][:] for name in ("t", "omega_m", "phi", "L1", "mode", "r1", "r2")}
        out["summary"] = {k: f["summary"].attrs[k] for k in f["summary"].attrs}
    out["mode"] = out["mode"].astype(int)
    return out


def _golden(cost, lo, hi, iterations=80):
    g = (np.sqrt(5) - 1) / 2
    for _ in range(iterations):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        if cost(a) < cost(b):
            hi = b
        else:
            lo = a
    return 0.5 * (lo + hi)


def _scan_and_refine(cost, lo, hi, n):
    grid = np.linspace(lo, hi, n)
    i = int(np.argmin([cost(x) for x in grid]))
    step = grid[1] - grid[0]
    return _golden(cost, grid[max(i - 1, 0)], grid[min(i + 1, n - 1)]) if step > 0 else grid[i]


def window_phase(sweep, c, k, s):
    """The motor phase φ at the samples s of window k of chain c: the file's phase at the
    window start plus ∫ω_m dt (trapezoid; exact on a linear ramp, as ω_m is)."""
    if sweep.phi_begin is None:
        with h5py.File(sweep.path, "r") as f:
            need(f, sweep.path, "windows/phi_begin", "the motor phase at each window start")
    t, omega_m = s["t"], s["omega_m"]
    t0 = float(sweep.t_begin[c, k])
    # From the window start to each sample: the first sample is at or just after t0.
    rel = np.concatenate([[0.0], np.cumsum(0.5 * (omega_m[1:] + omega_m[:-1]) * np.diff(t))])
    w0 = float(sweep.omega_begin[c, k])
    lead = 0.5 * (w0 + omega_m[0]) * (t[0] - t0)
    return float(sweep.phi_begin[c, k]) + lead + rel


def run_parameter(path, key):
    """A setting of a run file's configuration in force, e.g. 'model.drive_radius'."""
    with h5py.File(path, "r") as f:
        need(f, path, "resolved", "the configuration in force")
        values = resolved(f["resolved"])
    if key not in values:
        fail(f"{path}: /resolved has no {key}")
    return values[key]


def corotating(r, phi):
    """Positions in the frame turning with the motor: x' along the motor's rod, z unchanged."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * r[:, 0] + s * r[:, 1], -s * r[:, 0] + c * r[:, 1], r[:, 2]], axis=1)


# ---- command line and figure output ----------------------------------------------------

def parser(doc):
    """An argparse parser whose description is the script's docstring (--help shows usage)."""
    import argparse
    return argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)


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
