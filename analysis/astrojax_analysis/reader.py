"""The one reader of sweep files (`astrojax sweep`) and run files (`astrojax run`), formats 1 to 5
(docs/reference/file-format.md). It checks on open what the C++ reader checks: the format
version (an integer, 1 when absent, not newer than FORMAT_VERSION), every dataset of the
layout present with its rank, shape and type class, checksum failures, and values the writer
never stores (non-finite window times, class codes outside [-1, 5], sample counts outside
[0, cap], indices past their names). Every refusal is a `SweepFileError` naming the file and
the dataset. Sample windows are read (and checked) when asked for: a sweep's samples are most
of its size and most scripts never read them.
"""
import os
import re
from contextlib import contextmanager

import h5py
import numpy as np

from . import classes as _classes
from .errors import SweepFileError

# The newest format this reader reads. 2 added /resolved and /windows/phi_begin; 3 stores
# names, labels, purposes, overrides and failures as string arrays and adds /classes; 4 made
# motor_work and motor_power the motor's at its rod with a clutch (the string's side moved to
# string_work and string_power; clutch_loss, clutch_power, tie_energy and /trajectory/chi new)
# and added the motor's ledger, two columns, to /tasks/final_state; 5 added /brackets, the
# bisections of a sweep with [bisect] chains, and /basins, a sweep's basin chains (laid out as
# format 4 otherwise).
FORMAT_VERSION = 5
THRESHOLD_NAMES = ("omega_rise", "omega_fall", "omega_1", "omega_2")  # /brackets/threshold codes
BISECT_STATUS = ("running", "converged", "start not on the known side", "no crossing in the range", "a probe failed")

SAMPLE_COLUMNS = ("t", "omega_m", "L1", "T1", "T2", "mode")
SAMPLE_VECTORS = ("r1", "r2")
WINDOW_LAYOUT = ("class", "direction", "segment")  # integer datasets of /windows
WINDOW_TIMES = ("t_begin", "t_end", "omega_m_begin", "omega_m_end")  # finite on every window of the layout
TASK_STATUSES = 4  # 0 never ran, 1 ok, 2 failed, 3 not run
RUN_REQUIRED = ("t", "omega_m", "phi", "L1", "mode", "r1", "r2")
RUN_VECTORS = ("r1", "r2", "v1", "v2")
# The per-window energy account of /windows [W] and the first format that always holds each
# (format 1 may lack the account; string_power and clutch_power came with format 4). An older
# file without one reads as NaN, as in the C++ reader (results/sweep_result.hpp, kPowers).
WINDOW_POWERS = {"motor_power": 2, "drag_power": 2, "friction_impact_power": 2, "energy_rate": 2,
                 "string_power": 4, "clutch_power": 4}
# /tasks/final_state columns: t, mode, sigma, s_star, impact_loss, the state y (15), the tie
# clutch's 5 (format 3) and the motor's ledger, 2 (format 4); an older file may hold fewer.
FINAL_STATE_COLUMNS = 27
FINAL_STATE_OLDER = {25: 4, 20: 3}  # columns: the first format that no longer writes so few
# /trajectory columns a run file holds from a format on; absent from an older one.
RUN_SINCE = {"chi": 4, "tie_energy": 4, "string_work": 4, "clutch_loss": 4}
_COLOUR = re.compile(r"#[0-9a-fA-F]{6}\Z")


# ---- opening and checked access ------------------------------------------------------

@contextmanager
def open_h5(path):
    """The HDF5 file at `path`, read-only; a missing or non-HDF5 file is a SweepFileError."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise SweepFileError(path, None, "no such file")
    if os.path.isdir(path):
        raise SweepFileError(path, None, "is a directory, not a file")
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise SweepFileError(path, None, f"cannot read as HDF5 ({_reason(e)})") from None
    try:
        yield f
    except (OSError, KeyError, RuntimeError) as e:
        # What h5py raises on a damaged object header, B-tree or heap while a group is walked
        # or an attribute read: the file is damaged where the checks above do not look.
        raise SweepFileError(path, None, f"damaged HDF5 structure ({type(e).__name__}: {_reason(e)})") from None
    finally:
        try:
            f.close()
        except Exception:  # closing a damaged file must not hide the reason it was refused
            pass


def _reason(e):
    text = str(e).strip() or type(e).__name__
    return text.splitlines()[0][:200]


def format_version(f, path):
    """The root attribute format_version: an integer in [1, FORMAT_VERSION]; 1 when absent."""
    try:
        v = f.attrs.get("format_version", 1)
    except Exception as e:
        raise SweepFileError(path, "/", f"attribute format_version cannot be read ({_reason(e)})") from None
    if isinstance(v, np.ndarray) and v.shape in ((), (1,)):
        v = v.reshape(-1)[0]
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
        raise SweepFileError(path, "/", f"attribute format_version is {v!r}, not an integer")
    v = int(v)
    if v > FORMAT_VERSION:
        raise SweepFileError(path, "/", f"file format version {v} is newer than this reader reads ({FORMAT_VERSION})")
    if v < 1:
        raise SweepFileError(path, "/", f"file format version {v} outside [1, {FORMAT_VERSION}]")
    return v


def dataset(f, path, name, kind, shape, optional=False):
    """The dataset `name`, checked: kind 'f' (floating point) or 'i' (integer), `shape` a
    tuple whose None entries match any size. None when optional and absent."""
    if name not in f:
        if optional:
            return None
        raise SweepFileError(path, "/" + name, "missing")
    d = f[name]
    if not isinstance(d, h5py.Dataset):
        raise SweepFileError(path, "/" + name, "is a group, not a dataset")
    want = "floating point" if kind == "f" else "integer"
    ok = np.issubdtype(d.dtype, np.floating) if kind == "f" else np.issubdtype(d.dtype, np.integer)
    if not ok:
        raise SweepFileError(path, "/" + name, f"stored as {d.dtype}, expected {want}")
    if len(d.shape) != len(shape) or any(w is not None and s != w for s, w in zip(d.shape, shape)):
        expected = " × ".join("n" if w is None else str(w) for w in shape) or "a scalar"
        got = " × ".join(str(s) for s in d.shape) or "a scalar"
        raise SweepFileError(path, "/" + name, f"shape {got}, expected {expected}")
    return d


def read(d, path, sel=()):
    """d[sel], turning a checksum or decompression failure into a SweepFileError."""
    try:
        return d[sel] if sel != () else d[()]
    except Exception as e:  # h5py raises OSError for a failed filter, others for a broken layout
        raise SweepFileError(path, d.name, f"cannot be read: checksum or compression error ({_reason(e)})") from None


def attr(obj, path, name, default=None):
    try:
        return obj.attrs.get(name, default)
    except Exception as e:
        raise SweepFileError(path, obj.name, f"attribute {name} cannot be read ({_reason(e)})") from None


def as_text(value):
    """An HDF5 string, whether h5py returns it as str or bytes."""
    return value.decode("utf-8", "backslashreplace") if isinstance(value, bytes) else str(value)


def text_attr(obj, path, name, default=""):
    """A scalar string attribute."""
    v = attr(obj, path, name, default)
    if isinstance(v, np.ndarray):
        if v.shape in ((), (1,)) and v.dtype.kind in "OSU":
            v = v.reshape(-1)[0]
        else:
            raise SweepFileError(path, obj.name, f"attribute {name} is an array, expected one string")
    if not isinstance(v, (str, bytes)):
        raise SweepFileError(path, obj.name, f"attribute {name} is {type(v).__name__}, expected a string")
    return as_text(v)


def string_list(obj, path, name, version, sep, count=None):
    """A list of strings: a 1-D string-array attribute in format 3, a `sep`-joined string
    before (an empty string is an empty list). `count`: the length it must have."""
    where = f"attribute {name}"
    if version >= 3:
        v = attr(obj, path, name)
        if v is None:
            raise SweepFileError(path, obj.name, f"{where} missing")
        if not isinstance(v, np.ndarray) or v.ndim != 1 or (v.size and v.dtype.kind not in "OSU"):
            raise SweepFileError(path, obj.name, f"{where} is not a 1-D array of strings (format 3)")
        items = [as_text(x) for x in v]
        if any(not isinstance(x, (str, bytes)) for x in v):
            raise SweepFileError(path, obj.name, f"{where} holds a non-string")
    else:
        text = text_attr(obj, path, name)
        items = text.split(sep) if text else []
    if count is not None and len(items) != count:
        raise SweepFileError(path, obj.name, f"{where} has {len(items)} entries, expected {count}")
    return items


def check_range(values, path, name, lo, hi, what="values"):
    """Every value in [lo, hi]; names the first index outside."""
    bad = np.argwhere((values < lo) | (values > hi))
    if len(bad):
        i = tuple(int(x) for x in bad[0])
        raise SweepFileError(path, "/" + name, f"{what} {values[i]} at index {list(i)} outside [{lo}, {hi}]")


def check_finite(values, path, name, where=None, what="non-finite value"):
    """Every value finite (where `where` is true)."""
    bad = ~np.isfinite(values) if where is None else ~np.isfinite(values) & where
    if bad.any():
        i = tuple(int(x) for x in np.argwhere(bad)[0])
        raise SweepFileError(path, "/" + name, f"{what} {values[i]} at index {list(i)}")


def file_kind(path):
    """'sweep' (written by astrojax sweep) or 'run' (astrojax run); SweepFileError otherwise."""
    with open_h5(path) as f:
        format_version(f, path)
        if "windows" in f:  # one without /samples is refused by SweepFile, which says so
            return "sweep"
        if "trajectory" in f:
            return "run"
    raise SweepFileError(path, None, "neither a sweep file (/windows, /samples) nor a run file (/trajectory)")


def _kind_attr(f, path, want):
    kind = attr(f, path, "format")
    if kind is not None and text_attr(f, path, "format") != want:
        raise SweepFileError(path, "/", f"attribute format is '{as_text(kind)}', expected '{want}'")


def read_config(f, path, version):
    """(/config text, its --set overrides as a list)."""
    d = f.get("config")
    if not isinstance(d, h5py.Dataset) or d.shape != () or d.dtype.kind not in "OSU":
        raise SweepFileError(path, "/config", "missing or not one string")
    return as_text(read(d, path)), string_list(d, path, "overrides", version, "\n")


def resolved(group):
    """The configuration in force stored as /resolved attributes: {'model.drive_radius': 0.01, ...}."""
    return {k: (v.decode() if isinstance(v, bytes) else v.item() if hasattr(v, "item") else v)
            for k, v in group.attrs.items()}


# ---- the orbit classes ----------------------------------------------------------------

def read_classes(f, path, version):
    """The class table: /classes of a format-3 file, else the fallback (classes.FALLBACK)."""
    if version < 3:
        return _classes.FALLBACK
    g = f.get("classes")
    if not isinstance(g, h5py.Group):
        raise SweepFileError(path, "/classes", "missing (format 3 files declare their orbit classes there)")
    cols = {}
    for name in ("name", "description", "colour"):
        d = g.get(name)
        if not isinstance(d, h5py.Dataset) or d.ndim != 1 or d.dtype.kind not in "OSU":
            raise SweepFileError(path, f"/classes/{name}", "missing or not a 1-D array of strings")
        cols[name] = [as_text(x) for x in read(d, path)]
    circ = dataset(f, path, "classes/circular", "i", (None,))
    cols["circular"] = read(circ, path)
    n = len(cols["name"])
    for name, values in cols.items():
        if len(values) != n:
            raise SweepFileError(path, f"/classes/{name}", f"{len(values)} entries, /classes/name has {n}")
    if n == 0:
        raise SweepFileError(path, "/classes/name", "no classes")
    for i, c in enumerate(cols["colour"]):
        if not _COLOUR.match(c):
            raise SweepFileError(path, "/classes/colour", f"'{c}' at index {i} is not a colour #rrggbb")
    check_range(cols["circular"], path, "classes/circular", 0, 1)
    return tuple(_classes.OrbitClass(i, cols["name"][i], bool(cols["circular"][i]), cols["description"][i],
                                     cols["colour"][i]) for i in range(n))


# ---- sweep files ------------------------------------------------------------------------

class SweepFile:
    """The per-window table of a sweep file, chains × windows, with ω in rad/s, validated on
    open (SweepFileError). Unclassified windows (class -1: the task never ran) are kept with
    their class; use `valid` to skip them."""

    def __init__(self, path):
        self.path = os.fspath(path)
        with open_h5(self.path) as f:
            self.version = format_version(f, self.path)
            if "windows" not in f:
                what = "it is a run file, /trajectory" if "trajectory" in f else "nor a run file"
                raise SweepFileError(self.path, "/windows", f"missing: not a sweep file ({what}); make one with "
                                     f"`astrojax sweep`")
            if "samples" not in f:  # as the C++ reader says it
                raise SweepFileError(self.path, "/samples", "missing: the file stores no samples of its windows")
            _kind_attr(f, self.path, "sweep")
            self.classes = read_classes(f, self.path, self.version)
            self._read_windows(f)
            self._read_samples_layout(f)
            self._read_chains(f)
            self._read_brackets(f)
            self._read_tasks(f)
            self.basins = _read_basins(f, self.path, self.version, self.cls, len(self.classes))
            self.config, self.overrides = read_config(f, self.path, self.version)
            self.config_source = text_attr(f["config"], self.path, "source", "")
            prov = f.get("provenance")
            self.provenance = {k: as_text(v) for k, v in prov.attrs.items()} if isinstance(prov, h5py.Group) else {}
        self.class_names = {c.code: c.name for c in self.classes}
        self.class_colours = _classes.colours(self.classes)
        self.circular_classes = tuple(c.name for c in self.classes if c.circular)
        self.omega_mean = 0.5 * (self.omega_begin + self.omega_end)
        self.valid = self.cls >= 0

    def _read_windows(self, f):
        p = self.path
        cls = dataset(f, p, "windows/class", "i", (None, None))
        self.n_chains, self.n_windows = C, W = cls.shape
        self.cls = read(cls, p).astype(int)
        check_range(self.cls, p, "windows/class", -1, len(self.classes) - 1, "class code")
        self.direction = read(dataset(f, p, "windows/direction", "i", (C, W)), p).astype(int)
        check_range(self.direction, p, "windows/direction", -1, 1)
        self.segment = read(dataset(f, p, "windows/segment", "i", (C, W)), p).astype(int)
        exists = self.segment >= 0  # windows of the protocol; the rest pad shorter chains
        bad = np.argwhere(~exists & (self.cls >= 0))
        if len(bad):
            raise SweepFileError(p, "/windows/class", f"a class at index {bad[0].tolist()}, a window the protocol lacks")
        times = {}
        for name in WINDOW_TIMES:
            times[name] = read(dataset(f, p, "windows/" + name, "f", (C, W)), p)
            check_finite(times[name], p, "windows/" + name, exists)
        self.t_begin, self.t_end = times["t_begin"], times["t_end"]
        self.omega_begin, self.omega_end = times["omega_m_begin"], times["omega_m_end"]
        phi = dataset(f, p, "windows/phi_begin", "f", (C, W), optional=self.version < 2)
        self.phi_begin = read(phi, p) if phi is not None else None
        if self.phi_begin is not None:
            check_finite(self.phi_begin, p, "windows/phi_begin", exists)
        # Per-window statistics: every other 2-D dataset of /windows (each carries its units).
        self.stats, self.units = {}, {}
        for name, d in f["windows"].items():
            if name in WINDOW_LAYOUT or not isinstance(d, h5py.Dataset) or d.ndim != 2:
                continue
            self.stats[name] = read(dataset(f, p, "windows/" + name, "f", (C, W)), p)
            self.units[name] = text_attr(d, p, "units")
        for name, since in WINDOW_POWERS.items():
            if self.version >= since:
                dataset(f, p, "windows/" + name, "f", (C, W))
            elif name not in self.stats:
                self.stats[name], self.units[name] = np.full((C, W), np.nan), "W"
        for name in ("omega_ball", "confidence"):
            dataset(f, p, "windows/" + name, "f", (C, W))
        mf = dataset(f, p, "windows/mode_fraction", "f", (C, W, 5), optional=True)
        self.mode_fraction = read(mf, p) if mf is not None else None

    def _read_samples_layout(self, f):
        p, C, W = self.path, self.n_chains, self.n_windows
        count = dataset(f, p, "samples/count", "i", (C, W))
        t = dataset(f, p, "samples/t", "f", (C, W, None))
        self.cap = t.shape[2]
        for name in SAMPLE_COLUMNS:
            dataset(f, p, "samples/" + name, "f", (C, W, self.cap))
        for name in SAMPLE_VECTORS:
            dataset(f, p, "samples/" + name, "f", (C, W, self.cap, 3))
        self.count = read(count, p).astype(int)
        check_range(self.count, p, "samples/count", 0, self.cap, "sample count")
        bad = np.argwhere((self.count > 0) & (self.cls < 0))
        if len(bad):
            raise SweepFileError(p, "/samples/count", f"samples at index {bad[0].tolist()}, a window never computed "
                                 f"(class -1)")
        rate = attr(f["samples"], p, "sample_rate", np.nan)
        try:
            self.sample_rate = float(rate)
        except (TypeError, ValueError):
            raise SweepFileError(p, "/samples", f"attribute sample_rate is {rate!r}, not a number") from None

    def _indices(self, f, name, names_attr, sep, kind="i"):
        """An index per chain into the names of `names_attr` (None when absent): (values, names)."""
        p = self.path
        d = dataset(f, p, name, kind, (self.n_chains,), optional=True)
        if d is None:
            return None, []
        values = read(d, p)
        names = string_list(d, p, names_attr, self.version, sep) if names_attr else []
        if names_attr:
            check_range(values, p, name, 0, max(len(names) - 1, 0) if names else -1, f"index into {names_attr}")
        return values.astype(int), names

    def _read_chains(self, f):
        p, C = self.path, self.n_chains
        ch = f.get("chains")
        if not isinstance(ch, h5py.Group):
            raise SweepFileError(p, "/chains", "missing")
        model = dataset(f, p, "chains/model", "f", (C, None))
        self.model = read(model, p)
        check_finite(self.model, p, "chains/model")
        cols = string_list(model, p, "columns", self.version, ",", model.shape[1])
        self.model_columns = [c.split(" [")[0].strip() for c in cols]
        self.model_columns_with_units = [c.strip() for c in cols]
        self.axes = [a for a in string_list(ch, p, "axes", self.version, ",") if a]
        grid = dataset(f, p, "chains/grid_values", "f", (C, len(self.axes)), optional=not self.axes)
        self.grid = read(grid, p) if grid is not None else np.zeros((C, 0))
        hold = dataset(f, p, "chains/hold_omega", "f", (C,), optional=True)
        self.hold_omega = read(hold, p) if hold is not None else None
        if self.hold_omega is not None:
            check_finite(self.hold_omega, p, "chains/hold_omega")
        self.seed, self.seed_names = self._indices(f, "chains/seed", "names", ",")
        pert = dataset(f, p, "chains/perturbation", "i", (C,), optional=self.hold_omega is None)
        self.perturbation = read(pert, p).astype(int) if pert is not None else None
        if self.hold_omega is not None and self.seed is None:
            raise SweepFileError(p, "/chains/seed", "missing (a hold sweep names each chain's seed)")
        # A grouped sweep: each chain's group and model variant (indices into the names).
        self.group, self.group_names = self._indices(f, "chains/group", "names", "\n")
        self.variant, self.variant_names = self._indices(f, "chains/variant", "names", "\n")
        if (self.group is None) != (self.variant is None):
            missing = "chains/group" if self.group is None else "chains/variant"
            raise SweepFileError(p, "/" + missing, "missing (a grouped sweep has both /chains/group and /chains/variant)")
        self.group_purposes = (string_list(f["chains/group"], p, "purposes", self.version, "\n",
                                           len(self.group_names)) if self.group is not None else [])
        self.variant_labels = (string_list(f["chains/variant"], p, "labels", self.version, "\n",
                                           len(self.variant_names)) if self.variant is not None else [])
        self.start_seed, self.start_seed_names = self._indices(f, "chains/start_seed", "names", "\n")
        part = dataset(f, p, "chains/part", "i", (C,), optional=True)
        if part is not None:
            parts = f.get("resolved")
            n_parts = len(parts) if isinstance(parts, h5py.Group) else 0
            check_range(read(part, p), p, "chains/part", 0, n_parts - 1, "index into /resolved")
        start = dataset(f, p, "chains/start_omega", "f", (C,), optional=True)
        self.start_omega = read(start, p) if start is not None else None

    def _read_brackets(self, f):
        """/brackets (format 5): {name: array} per bisection chain, and "probes": {name: array}
        per probe; None without bisections. Checked as the C++ reader checks it."""
        p = self.path
        self.brackets = None
        if "brackets" not in f:
            return
        if self.version < 5:
            raise SweepFileError(p, "/brackets", f"present in a file of format {self.version}; /brackets is new in format 5")
        B = dataset(f, p, "brackets/chain", "i", (None,)).shape[0]
        P = dataset(f, p, "brackets/probes/chain", "i", (None,)).shape[0]
        b = {k: read(dataset(f, p, "brackets/" + k, "i", (B,)), p).astype(int)
             for k in ("chain", "threshold", "planned_probes", "known_class", "other_class", "status")}
        b.update({k: read(dataset(f, p, "brackets/" + k, "f", (B,)), p)
                  for k in ("from", "to", "width", "start_omega", "known_omega", "other_omega")})
        if "brackets/guide" in f:  # only in a file with a guided chain (bisect.guide = "held_orbit")
            b["guide"] = read(dataset(f, p, "brackets/guide", "f", (B,)), p)
        pr = {k: read(dataset(f, p, "brackets/probes/" + k, "i", (P,)), p).astype(int)
              for k in ("chain", "index", "class", "ran", "known_side", "status")}
        pr.update({k: read(dataset(f, p, "brackets/probes/" + k, "f", (P,)), p)
                   for k in ("omega_m", "known_omega", "other_omega")})
        pr["stats"] = read(dataset(f, p, "brackets/probes/stats", "f", (P, None)), p)
        pr["powers"] = read(dataset(f, p, "brackets/probes/powers", "f", (P, None)), p)
        n = len(self.classes) - 1
        check_range(b["chain"], p, "brackets/chain", 0, self.n_chains - 1, "chain index")
        check_range(b["threshold"], p, "brackets/threshold", 0, 3, "threshold code")
        check_range(b["planned_probes"], p, "brackets/planned_probes", 2, 64)
        for k in ("known_class", "other_class"):
            check_range(b[k], p, "brackets/" + k, -1, n, "class code")
        check_range(b["status"], p, "brackets/status", -1, len(BISECT_STATUS) - 1, "status")
        for k in ("from", "to", "width"):
            check_finite(b[k], p, "brackets/" + k)
        if int(b["planned_probes"].sum()) != P:
            raise SweepFileError(p, "/brackets/probes/chain", f"{P} probes, but /brackets/planned_probes plans "
                                 f"{int(b['planned_probes'].sum())}")
        want_chain = np.repeat(b["chain"], b["planned_probes"])
        want_index = np.concatenate([np.arange(k) for k in b["planned_probes"]]) if B else np.zeros(0, int)
        bad = np.flatnonzero((pr["chain"] != want_chain) | (pr["index"] != want_index))
        if len(bad):
            i = int(bad[0])
            raise SweepFileError(p, "/brackets/probes/index", f"at [{i}]: chain {pr['chain'][i]} probe {pr['index'][i]}, "
                                 f"expected chain {want_chain[i]} probe {want_index[i]}")
        check_range(pr["class"], p, "brackets/probes/class", -1, n, "class code")
        check_range(pr["ran"], p, "brackets/probes/ran", -1, 1)
        check_range(pr["known_side"], p, "brackets/probes/known_side", -1, 1)
        check_range(pr["status"], p, "brackets/probes/status", -1, len(BISECT_STATUS) - 1, "status")
        check_finite(pr["omega_m"], p, "brackets/probes/omega_m", pr["ran"] == 1)
        b["probes"] = pr
        self.brackets = b

    def _read_tasks(self, f):
        p = self.path
        chain = dataset(f, p, "tasks/chain", "i", (None,))
        T = chain.shape[0]
        self.task_chain = read(chain, p).astype(int)
        check_range(self.task_chain, p, "tasks/chain", 0, self.n_chains - 1, "chain index")
        self.task_index = read(dataset(f, p, "tasks/index", "i", (T,)), p).astype(int)
        self.task_t_begin = read(dataset(f, p, "tasks/t_begin", "f", (T,)), p)
        self.task_t_end = read(dataset(f, p, "tasks/t_end", "f", (T,)), p)
        planned = ~np.isin(self.task_chain, self.brackets["chain"]) if self.brackets else None  # a probe's times are not
        check_finite(self.task_t_begin, p, "tasks/t_begin", planned)
        check_finite(self.task_t_end, p, "tasks/t_end", planned)
        self.task_status = read(dataset(f, p, "tasks/status", "i", (T,)), p).astype(int)
        check_range(self.task_status, p, "tasks/status", 0, TASK_STATUSES - 1, "status")
        dataset(f, p, "tasks/steps", "i", (T,))
        cols = dataset(f, p, "tasks/final_state", "f", (T, None)).shape[1]
        if cols != FINAL_STATE_COLUMNS and self.version >= FINAL_STATE_OLDER.get(cols, 1):
            raise SweepFileError(p, "/tasks/final_state", f"has {cols} columns, expected {FINAL_STATE_COLUMNS}"
                                 f" (format {self.version})")
        self._final_state_cols = cols
        tasks = f["tasks"]
        self.failures = string_list(tasks, p, "failures", self.version, "\n") if "failures" in tasks.attrs or \
            self.version >= 3 else []

    # ---- what the scripts ask ----

    @property
    def n_tasks(self):
        return len(self.task_chain)

    def final_state(self, task):
        """/tasks/final_state of one task (t, mode, ..., see the dataset's `columns`)."""
        with open_h5(self.path) as f:
            return read(f["tasks/final_state"], self.path, (int(task),))

    def samples(self, c, k):
        """The stored samples of window k of chain c: dict of t, omega_m, L1, T1, T2, mode (n)
        and r1, r2 (n × 3), trimmed to /samples/count; SweepFileError where a checksum fails
        or a stored sample is not finite."""
        n = int(self.count[c, k])
        out = {}
        with open_h5(self.path) as f:
            s = f["samples"]
            for name in SAMPLE_COLUMNS + SAMPLE_VECTORS:
                out[name] = read(s[name], self.path, (c, k, slice(0, n)))
                check_finite(out[name], self.path, f"samples/{name}", what=f"chain {c}, window {k}: non-finite sample")
        out["mode"] = out["mode"].astype(int)
        return out

    def all_samples(self, names=SAMPLE_COLUMNS + SAMPLE_VECTORS):
        """The stored samples of every computed window at once, {(c, k): {name: array}} trimmed
        to /samples/count (one read per dataset instead of one per window), checked as
        `samples` checks them."""
        out = {}
        with open_h5(self.path) as f:
            data = {name: read(f["samples"][name], self.path) for name in names}
        for c, k in zip(*np.nonzero(self.valid & (self.count > 0))):
            n = int(self.count[c, k])
            win = {name: data[name][c, k, :n] for name in names}
            for name, v in win.items():
                check_finite(v, self.path, f"samples/{name}", what=f"chain {c}, window {k}: non-finite sample")
            out[(int(c), int(k))] = win
        return out

    def check_samples(self):
        """Reads every stored sample once (what `samples` checks, for the whole file): a
        checksum failure or a non-finite sample inside /samples/count is a SweepFileError."""
        with open_h5(self.path) as f:
            inside = np.arange(self.cap) < self.count[..., None]  # chains × windows × cap
            for name in SAMPLE_COLUMNS + SAMPLE_VECTORS:
                v = read(f["samples"][name], self.path)
                where = np.broadcast_to(inside[..., None] if v.ndim == 4 else inside, v.shape)
                check_finite(v, self.path, f"samples/{name}", where, what="non-finite sample")

    @property
    def is_hold(self):
        return self.hold_omega is not None

    @property
    def is_grouped(self):
        return self.variant is not None

    def class_name(self, c, k):
        return self.class_names.get(int(self.cls[c, k]), "?")

    def class_colour(self, c, k):
        return self.class_colours.get(self.class_name(c, k), _classes.UNKNOWN_COLOUR)

    def parameter(self, c, name):
        """A model parameter of chain c by its /chains/model column name (SI units)."""
        if name not in self.model_columns:
            raise SweepFileError(self.path, "/chains/model", f"no column '{name}' (columns: {', '.join(self.model_columns)})")
        return float(self.model[c, self.model_columns.index(name)])

    def resolved(self):
        """/resolved: {'model.drive_radius': 0.01, ...}, or {part: {...}} for a file of parts."""
        with open_h5(self.path) as f:
            g = f.get("resolved")
            if not isinstance(g, h5py.Group):
                return {}
            if len(g) and all(isinstance(v, h5py.Group) for v in g.values()):
                return {k: resolved(v) for k, v in g.items()}
            return resolved(g)


# ---- run files ----------------------------------------------------------------------------

# ---- /basins (format 5) --------------------------------------------------------------

BASIN_FEATURES = ("omega_ball", "radius_bead_mean", "radius_bottom_mean", "L1_mean")
BASIN_FAMILIES = ("hanging", "hand", "cloud")


def _read_basins(f, p, version, cls, n_classes):
    """/basins as a dict of arrays, checked as the C++ reader checks it (each sample's class is
    its chain's window 0; counts, fractions and Wilson intervals recomputed); None without."""
    if "basins" not in f:
        return None
    if version < 5:
        raise SweepFileError(p, "/basins", f"present in a file of format_version {version} (basins came with 5)")
    chain = dataset(f, p, "basins/chain", "i", (None,))
    S = chain.shape[0]
    b = {"chain": read(chain, p).astype(int)}
    for name in ("level", "sample", "class"):
        b[name] = read(dataset(f, p, "basins/" + name, "i", (S,)), p).astype(int)
    b["start"] = read(dataset(f, p, "basins/start", "f", (S, FINAL_STATE_COLUMNS)), p)
    b["features"] = read(dataset(f, p, "basins/features", "f", (S, len(BASIN_FEATURES))), p)
    L = dataset(f, p, "basins/levels/omega_m", "f", (None,)).shape[0]
    lv = {}
    lv["omega_m"] = read(dataset(f, p, "basins/levels/omega_m", "f", (L,)), p)
    for name in ("part", "first", "samples", "family", "done"):
        lv[name] = read(dataset(f, p, "basins/levels/" + name, "i", (L,)), p).astype(int)
    K = n_classes
    lv["count"] = read(dataset(f, p, "basins/levels/count", "i", (L, K)), p).astype(int)
    for name in ("fraction", "lower", "upper"):
        lv[name] = read(dataset(f, p, "basins/levels/" + name, "f", (L, K)), p)
    check_range(b["chain"], p, "basins/chain", 0, cls.shape[0] - 1, "chain index")
    check_range(b["level"], p, "basins/level", 0, L - 1, "level")
    check_range(lv["family"], p, "basins/levels/family", 0, len(BASIN_FAMILIES) - 1, "family")
    check_range(lv["samples"], p, "basins/levels/samples", 1, 2 ** 31 - 1, "N")
    check_finite(lv["omega_m"], p, "basins/levels/omega_m")
    if np.any(np.isinf(b["start"])) or np.any(np.isinf(b["features"])):
        raise SweepFileError(p, "/basins/start" if np.any(np.isinf(b["start"])) else "/basins/features", "an infinite value")
    bad = np.flatnonzero(b["class"] != cls[b["chain"], 0])
    if len(bad):
        i = int(bad[0])
        raise SweepFileError(p, "/basins/class", f"at [{i}]: class {b['class'][i]}, but its chain {b['chain'][i]} has "
                             f"class {cls[b['chain'][i], 0]} in /windows/class")
    done = b["class"] >= 0
    count = np.zeros((L, K), dtype=int)
    np.add.at(count, (b["level"][done], b["class"][done]), 1)
    if not np.array_equal(count, lv["count"]):
        raise SweepFileError(p, "/basins/levels/count", "differs from the samples' classes")
    if not np.array_equal(count.sum(axis=1), lv["done"]):
        raise SweepFileError(p, "/basins/levels/done", "differs from the samples with a class")
    _check_fractions(p, "/basins/levels/", lv, count, lv["done"])
    b["levels"] = lv
    b["attractors"] = _read_basin_attractors(f, p, b, L)
    return b


def _read_basin_attractors(f, p, b, L):
    """/basins/attractor and /basins/attractors (the attractors matched across ω_m, written by
    the sweep and by `astrojax classify`), checked as the C++ reader checks them; None in a file
    made before they were stored."""
    if "basins/attractor" not in f and "basins/attractors" not in f:
        return None
    S = len(b["class"])
    b["attractor"] = read(dataset(f, p, "basins/attractor", "i", (S,)), p).astype(int)
    names = f.get("basins/attractors/name")
    if not isinstance(names, h5py.Dataset) or names.ndim != 1 or names.dtype.kind not in "OSU":
        raise SweepFileError(p, "/basins/attractors/name", "missing or not a 1-D array of strings")
    A = names.shape[0]
    at = {"name": [as_text(x) for x in read(names, p)]}
    for name in ("class", "part"):
        at[name] = read(dataset(f, p, "basins/attractors/" + name, "i", (A,)), p).astype(int)
    at["count"] = read(dataset(f, p, "basins/attractors/count", "i", (L, A)), p).astype(int)
    for name in ("fraction", "lower", "upper"):
        at[name] = read(dataset(f, p, "basins/attractors/" + name, "f", (L, A)), p)
    lab = b["attractor"]
    check_range(lab, p, "basins/attractor", -1, A - 1, "attractor")
    on = lab >= 0
    if not np.array_equal(on, b["class"] >= 0) or np.any(at["class"][lab[on]] != b["class"][on]) or \
            np.any(at["part"][lab[on]] != b["levels"]["part"][b["level"][on]]):
        raise SweepFileError(p, "/basins/attractor", "a sample on an attractor of another class or part, or a sample "
                             "with a class on none")
    count = np.zeros((L, A), dtype=int)
    np.add.at(count, (b["level"][on], lab[on]), 1)
    if not np.array_equal(count, at["count"]):
        raise SweepFileError(p, "/basins/attractors/count", "differs from the samples' attractors")
    _check_fractions(p, "/basins/attractors/", at, count, b["levels"]["done"])
    return at


def _check_fractions(p, where, stored, count, done):
    """The stored fraction, lower and upper of each (level, column) against the counts: fraction =
    count / done, and its 95 % Wilson interval."""
    n = done[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(n > 0, count / np.maximum(n, 1), np.nan)
    lo, hi = wilson_interval(count, n)
    for name, want in (("fraction", frac), ("lower", lo), ("upper", hi)):
        if not np.allclose(stored[name], want, rtol=0, atol=1e-12, equal_nan=True):
            raise SweepFileError(p, where + name, "differs from the counts (fraction = count / done, the 95 % Wilson "
                                 "interval)")


def wilson_interval(k, n, z=1.959963984540054):
    """The Wilson score interval of k successes in n trials (arrays broadcast), NaN where n = 0:
    centre (k + z²/2)/(n + z²), half-width z √(k(n−k)/n + z²/4)/(n + z²)."""
    k = np.asarray(k, dtype=float)
    n = np.asarray(n, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        centre = (k + z * z / 2) / (n + z * z)
        half = z / (n + z * z) * np.sqrt(k * (n - k) / n + z * z / 4)
        lo = np.where(n > 0, np.maximum(0.0, centre - half), np.nan)
        hi = np.where(n > 0, np.minimum(1.0, centre + half), np.nan)
    return lo, hi


def read_run(path, columns=None):
    """A run file's trajectory, validated: dict of t, omega_m, phi, L1, mode (n), r1, r2 (n × 3),
    the further /trajectory `columns` asked for (one of RUN_SINCE is left out of the dict where
    a file older than its format lacks it), the /summary attributes as 'summary', the
    configuration as 'config' and its overrides as 'overrides'."""
    path = os.fspath(path)
    with open_h5(path) as f:
        version = format_version(f, path)
        tr = f.get("trajectory")
        if not isinstance(tr, h5py.Group):
            what = "it is a sweep file, /windows" if "windows" in f else "nor a sweep file"
            raise SweepFileError(path, "/trajectory", f"missing: not a run file ({what}); make one with `astrojax run`")
        _kind_attr(f, path, "run")
        t = dataset(f, path, "trajectory/t", "f", (None,))
        n = t.shape[0]
        out = {}
        for name in dict.fromkeys(RUN_REQUIRED + tuple(columns or ())):
            if version < RUN_SINCE.get(name, 1) and name not in tr:
                continue
            shape = (n, 3) if name in RUN_VECTORS else (n,)
            # mode is an integer column, stored as integers or as floats
            kind = "i" if name == "mode" and name in tr and np.issubdtype(tr[name].dtype, np.integer) else "f"
            out[name] = read(dataset(f, path, "trajectory/" + name, kind, shape), path)
            if name != "mode":
                check_finite(out[name], path, "trajectory/" + name)
        check_range(out["mode"], path, "trajectory/mode", 0, 4, "contact mode")
        if n and np.any(np.diff(out["t"]) < 0):
            raise SweepFileError(path, "/trajectory/t", "times decrease")
        summary = f.get("summary")
        if not isinstance(summary, h5py.Group):
            raise SweepFileError(path, "/summary", "missing")
        try:
            out["summary"] = {k: summary.attrs[k] for k in summary.attrs}
        except Exception as e:
            raise SweepFileError(path, "/summary", f"attributes cannot be read ({_reason(e)})") from None
        out["violations"] = _violations(summary, path)
        if "config" in f:
            out["config"], out["overrides"] = read_config(f, path, version)
        else:
            out["config"], out["overrides"] = "", []
        out["resolved"] = resolved(f["resolved"]) if isinstance(f.get("resolved"), h5py.Group) else None
        out["format_version"] = version
    out["mode"] = out["mode"].astype(int)
    return out


# What an animation needs of a run file beyond read_run's columns: the energy ledger [J] and,
# from format 4, the tie's azimuth χ, its energy and the clutch's loss.
MOTION_COLUMNS = ("energy", "motor_work", "drag_loss", "friction_loss", "impact_loss", "string_work", "clutch_loss",
                  "tie_energy", "chi")


def read_motion(path):
    """A run file (`astrojax run`, or `astrojax replay`, which adds /replay) as an animation
    reads it: read_run's trajectory with the ledger's columns (MOTION_COLUMNS); 'chi', the
    azimuth of the string's top, is φ where the file predates it (format < 4: a rigid tie's
    top, φ, is all such a file holds), and the clutch's loss and the tie's energy are zeros
    there; the configuration in force as 'resolved' (required: it gives R, the masses, g);
    the replay's attributes as 'replay', its stored and replayed window as 'replay_stored'
    and 'replay_replayed' ({} for a run file)."""
    path = os.fspath(path)
    out = read_run(path, MOTION_COLUMNS)
    n = len(out["t"])
    if out["resolved"] is None:
        raise SweepFileError(path, "/resolved", "missing: the configuration in force (format 2 on); rerun it with "
                             "this version of astrojax")
    for name in ("model.drive_radius", "model.bead_mass", "model.ball_mass", "model.contact_distance"):
        if name not in out["resolved"]:
            raise SweepFileError(path, "/resolved", f"no setting {name}")
    if "chi" not in out:
        out["chi"] = out["phi"].copy()
    for name in ("clutch_loss", "tie_energy"):
        out.setdefault(name, np.zeros(n))
    out["string_work"] = out.get("string_work", out["motor_work"])
    out["replay"], out["replay_stored"], out["replay_replayed"] = {}, {}, {}
    with open_h5(path) as f:
        rp = f.get("replay")
        if isinstance(rp, h5py.Group):
            out["replay"] = resolved(rp)
            for key, name in (("replay_stored", "stored"), ("replay_replayed", "replayed")):
                if isinstance(rp.get(name), h5py.Group):
                    out[key] = resolved(rp[name])
    if n < 2:
        raise SweepFileError(path, "/trajectory/t", f"{n} samples, too few to show motion")
    return out


def _violations(summary, path):
    """[(what, count, first time [s], worst, units)] of /summary/violations with count > 0."""
    v = summary.get("violations")
    out = []
    if not isinstance(v, h5py.Group):
        return out
    for name in sorted(v, key=lambda s: int(s) if s.isdigit() else 1 << 30):
        g = v[name]
        try:
            a = g.attrs
            item = (text_attr(g, path, "what"), int(a["count"]), float(a["first_time"]), float(a["worst"]),
                    text_attr(g, path, "worst_units"))
        except (KeyError, TypeError, ValueError) as e:
            raise SweepFileError(path, g.name, f"not a violation record ({_reason(e)})") from None
        if item[1] > 0:  # a watched assumption that held is not a violation
            out.append(item)
    return out
