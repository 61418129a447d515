"""A sweep file as the scripts use it: the validated table of reader.SweepFile plus the labels,
markers and panel groups of its chains. Every label taken from the file is escaped and cut
(labels.py) before it is printed or drawn."""
import numpy as np

from .errors import SweepFileError, fail
from .labels import for_figure, printable
from .reader import SweepFile

# Marker by /windows/direction: ▲ ω_m rising, ▼ falling, ● held.
DIRECTION_MARKERS = {1: "^", -1: "v", 0: "o"}
DIRECTION_WORDS = {1: "ω_m rising", -1: "ω_m falling", 0: "ω_m held"}
# Held windows (hold mode): marker by seed, in the order of /chains/seed@names.
SEED_MARKERS = ["o", "s", "D", "P", "X", "*"]
# Chain groups of a grouped sweep (/chains/group): marker by group, in the order of its names.
GROUP_MARKERS = ["o", "s", "D", "P", "X", "*"]


class Sweep(SweepFile):
    """The per-window table of a sweep file (reader.SweepFile) with its chains' labels."""

    def grid_label(self, c):
        """'drive_radius=0.01 ...' for the grid point of chain c ('' without grid axes)."""
        return " ".join(f"{printable(a, 40)}={v:g}" for a, v in zip(self.axes, self.grid[c]) if np.isfinite(v))

    def group_name(self, c):
        return self.group_names[int(self.group[c])] if self.is_grouped else ""

    def variant_name(self, c):
        return self.variant_names[int(self.variant[c])] if self.is_grouped else ""

    def start_seed_name(self, c):
        """Where a grouped sweep's chain starts: 'hanging', 'circular_high', ..."""
        return self.start_seed_names[int(self.start_seed[c])] if self.start_seed is not None else "hanging"

    def variant_label(self, c):
        return self.variant_labels[int(self.variant[c])] if self.is_grouped else ""

    def seed_name(self, i):
        return self.seed_names[i] if 0 <= i < len(self.seed_names) else str(i)

    def chain_label(self, c):
        """'chain 3 (group, variant): drive_radius=0.01, seed ...', escaped and cut."""
        label = f"chain {c}"
        if self.is_grouped:
            label += f" ({printable(self.group_name(c), 40)}, {printable(self.variant_name(c), 40)})"
        if self.grid_label(c):
            label += f": {self.grid_label(c)}"
        if self.is_hold:
            seed = printable(self.seed_name(int(self.seed[c])), 40)
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
        sweep has one chain per grid point; a hold sweep one per held ω_m, seed and kick).
        The labels are ready to draw (labels.for_figure)."""
        chains = range(self.n_chains) if chains is None else chains
        out = {}
        for c in chains:
            key = (int(self.variant[c]),) if self.is_grouped else tuple(np.nan_to_num(self.grid[c], nan=-1e300))
            out.setdefault(key, []).append(c)
        if self.is_grouped:
            return [(for_figure(self.variant_label(cs[0])), cs) for cs in out.values()]
        return [(for_figure(self.grid_label(cs[0]) or "all chains"), cs) for cs in out.values()]

    def parameter_title(self, c):
        """The chain's drive and contact, in symbols and units: 'R = 15 mm, d = 3.5 cm'."""
        return (f"R = {self.parameter(c, 'drive_radius') * 1e3:.3g} mm, "
                f"d = {self.parameter(c, 'contact_distance') * 1e2:.3g} cm")

    def windows(self, c):
        """The classified windows of chain c, in protocol order."""
        return [k for k in range(self.n_windows) if self.valid[c, k]]

    def legend_handles(self, chains):
        """Legend entries for the classes and markers used by these chains."""
        from matplotlib.lines import Line2D
        handles = []
        used = {self.class_name(c, k) for c in chains for k in self.windows(c)}
        for name, colour in self.class_colours.items():
            if name in used:
                handles.append(Line2D([], [], ls="", marker="s", color=colour, label=for_figure(name)))
        dirs = {int(self.direction[c, k]) for c in chains for k in self.windows(c)}
        for d in (1, -1):
            if d in dirs:
                handles.append(Line2D([], [], ls="", marker=DIRECTION_MARKERS[d], color="k", mfc="none",
                                      label=DIRECTION_WORDS[d]))
        if 0 in dirs:
            if self.is_hold:
                for i in sorted({int(self.seed[c]) for c in chains}):
                    handles.append(Line2D([], [], ls="", marker=SEED_MARKERS[i % len(SEED_MARKERS)], color="k",
                                          mfc="none", label=f"held, seed {for_figure(self.seed_name(i))}"))
            else:
                handles.append(Line2D([], [], ls="", marker="o", color="k", mfc="none", label=DIRECTION_WORDS[0]))
        return handles


def require_phase(sweep):
    """The motor phase at each window start (/windows/phi_begin, format 2 on), or a clear error."""
    if sweep.phi_begin is None:
        raise SweepFileError(sweep.path, "/windows/phi_begin",
                             f"missing (format version {sweep.version}): the motor phase at each window start; "
                             f"rerun the sweep with this version of astrojax")


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
