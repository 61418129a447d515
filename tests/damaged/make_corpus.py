#!/usr/bin/python3
"""The damaged-file corpus: damaged copies of one finished sweep file, made at test time.

    make_corpus.py SOURCE.h5 OUTDIR     writes OUTDIR/<case>.h5 for every case and
                                        OUTDIR/manifest.tsv: case, dataset, what was done

Every reader of sweep files (the C++ commands, the Python scripts) is run over the copies by
tests/damaged/corpus_test.py; each must either give the undamaged file's result or refuse the
file with a clear error. Importable too: `cases()` lists the cases, `make(source, outdir)`
writes them and returns [(name, path, dataset, description)].

Kinds of damage: one flipped byte inside a stored chunk (caught by Fletcher32 or the deflate
stream's Adler-32), a truncated file, a dataset of the wrong shape or type, a string or newer
format_version, missing datasets and attributes, NaN or Inf where the writer never stores one,
codes and indices out of range, long and control-character labels, and values edited through
h5py with a valid checksum (the only damage a checksum cannot see; `astrojax verify` finds it
by remaking the layout from /config and classifying every window again from its samples).
Works on format 2 (joined strings) and format 3 (string arrays) files; cases that need a part
of the layout the source lacks (e.g. /classes before format 3) are left out.
"""
import os
import shutil
import sys

import h5py
import numpy as np

STR = h5py.string_dtype("utf-8")


# ---- the kinds of damage -------------------------------------------------------------------

def flip_chunk(dataset, coord=None):
    """XOR 0xFF into one byte in the middle of a stored chunk of `dataset` (the chunk at
    `coord`, default its first); the file's metadata stays intact."""
    def damage(path):
        with h5py.File(path, "r") as f:
            d = f[dataset]
            if d.chunks is None:
                off, size = d.id.get_offset(), d.id.get_storage_size()
            else:
                info = (d.id.get_chunk_info_by_coord(tuple(coord)) if coord is not None
                        else d.id.get_chunk_info(0))
                off, size = info.byte_offset, info.size
        if off is None or size == 0:
            raise RuntimeError(f"{dataset}: no stored chunk to damage")
        with open(path, "r+b") as fh:
            fh.seek(off + size // 2)
            b = fh.read(1)
            fh.seek(off + size // 2)
            fh.write(bytes([b[0] ^ 0xFF]))
    return damage


def truncate(fraction=None, size=None):
    def damage(path):
        n = size if size is not None else int(os.path.getsize(path) * fraction)
        with open(path, "r+b") as fh:
            fh.truncate(n)
    return damage


def _recreate(f, name, data, **kw):
    """Replace dataset `name` by `data` (as a checksummed chunked dataset), keeping its
    attributes."""
    attrs = {k: v for k, v in f[name].attrs.items()}
    del f[name]
    d = f.create_dataset(name, data=data, **kw)
    for k, v in attrs.items():
        d.attrs[k] = v


def reshape(dataset, new_shape_of):
    """The dataset cut or padded to new_shape_of(old_shape)."""
    def damage(path):
        with h5py.File(path, "r+") as f:
            old = f[dataset][()]
            shape = new_shape_of(old.shape)
            new = np.resize(old, shape) if np.prod(shape) > 0 else np.zeros(shape, old.dtype)
            if new.dtype == object:  # strings: HDF5 cannot checksum their heap
                _recreate(f, dataset, new, dtype=STR)
            else:
                _recreate(f, dataset, new, fletcher32=True, chunks=True if new.ndim else None)
    return damage


def retype(dataset, dtype):
    """The dataset's values stored as another type (e.g. the integer /windows/class as float)."""
    def damage(path):
        with h5py.File(path, "r+") as f:
            old = f[dataset][()]
            with np.errstate(invalid="ignore"):  # NaN (not computed) as an integer: any value
                new = np.array(old).astype(dtype) if dtype is not STR else np.array([str(v) for v in np.ravel(old)], dtype=object).reshape(old.shape)
            _recreate(f, dataset, new, fletcher32=dtype is not STR, chunks=True)
    return damage


def remove(dataset):
    def damage(path):
        with h5py.File(path, "r+") as f:
            del f[dataset]
    return damage


def remove_attr(obj, name):
    def damage(path):
        with h5py.File(path, "r+") as f:
            del f[obj].attrs[name]
    return damage


def set_attr(obj, name, value):
    def damage(path):
        with h5py.File(path, "r+") as f:
            f[obj].attrs[name] = value
    return damage


def computed_window(f):
    """(chain, window) of a window with samples: the first of chain 0."""
    count = f["samples/count"][()]
    c, k = np.argwhere(count > 0)[0]
    return int(c), int(k)


def set_value(dataset, index_of, value_of):
    """One element rewritten through h5py (its checksum is made afresh): index_of(f) gives the
    index, value_of(old) the new value."""
    def damage(path):
        with h5py.File(path, "r+") as f:
            d = f[dataset]
            i = index_of(f)
            d[i] = value_of(d[i])
    return damage


def at_window(offset=(0,)):
    """Index of the first computed window, followed by `offset`."""
    def index(f):
        c, k = computed_window(f)
        return (c, k) + tuple(offset)
    return index


def edit_names(dataset, attr, edit):
    """A string-list attribute (format 3: an array; 1-2: joined by newlines) edited as a list."""
    def damage(path):
        with h5py.File(path, "r+") as f:
            obj = f[dataset]
            v = obj.attrs[attr]
            if isinstance(v, np.ndarray):
                items = [x.decode() if isinstance(x, bytes) else str(x) for x in v]
                obj.attrs.create(attr, np.array(edit(items), dtype=object), dtype=STR)
            else:
                text = v.decode() if isinstance(v, bytes) else str(v)
                obj.attrs[attr] = "\n".join(edit(text.split("\n")))
    return damage


def edit_config(old, new):
    def damage(path):
        with h5py.File(path, "r+") as f:
            text = f["config"][()]
            text = text.decode() if isinstance(text, bytes) else str(text)
            if old not in text:
                raise RuntimeError(f"/config lacks {old!r}")
            attrs = dict(f["config"].attrs.items())
            del f["config"]
            d = f.create_dataset("config", data=text.replace(old, new, 1), dtype=STR)
            for k, v in attrs.items():
                d.attrs[k] = v
    return damage


def replace_first(items, new):
    return [new] + items[1:]


# ---- the cases -----------------------------------------------------------------------------

def cases():
    """[(name, dataset, description, damage(path), needs)]: `needs` is a path the source
    must hold for the case to apply."""
    out = []

    def add(name, dataset, what, damage, needs=None):
        out.append((name, dataset, what, damage, needs or dataset.split("@")[0]))

    # One flipped byte in a stored chunk: a checksum fails.
    for ds in ["windows/class", "windows/omega_ball", "windows/confidence", "windows/rotation_number",
               "windows/radius_bottom_mean", "windows/radius_bottom_std", "windows/L1_mean", "windows/T1_mean",
               "windows/mode_fraction", "windows/motor_power", "windows/energy_rate", "windows/t_begin",
               "windows/omega_m_begin", "windows/omega_m_end", "windows/direction", "windows/segment",
               "windows/phi_begin", "samples/count", "tasks/status", "tasks/steps", "tasks/final_state",
               "tasks/chain", "tasks/t_begin", "chains/model", "chains/group", "chains/variant",
               "chains/start_omega", "chains/part"]:
        add("flip_" + ds.replace("/", "_"), ds, "one byte flipped in its first chunk", flip_chunk(ds))
    for col in ["t", "omega_m", "L1", "T1", "T2", "mode", "r1", "r2"]:
        ds = "samples/" + col
        add("flip_" + ds.replace("/", "_"), ds, "one byte flipped in chain 0 window 0's deflated chunk",
            flip_chunk(ds, (0, 0, 0) if col not in ("r1", "r2") else (0, 0, 0, 0)))
    add("flip_samples_r2_window3", "samples/r2", "one byte flipped in chain 1 window 3's chunk",
        flip_chunk("samples/r2", (1, 3, 0, 0)))

    # Truncated files.
    for frac in (0.5, 0.9, 0.99):
        add(f"truncated_{int(frac * 100)}", "", f"the file cut to {int(frac * 100)} % of its size", truncate(frac), "")
    add("truncated_header", "", "the file cut to its first 1000 bytes", truncate(size=1000), "")

    # Wrong shapes.
    add("shape_windows_omega_ball", "windows/omega_ball", "one window fewer per chain",
        reshape("windows/omega_ball", lambda s: (s[0], s[1] - 1)))
    add("shape_windows_class_1d", "windows/class", "flattened to 1-D", reshape("windows/class", lambda s: (s[0] * s[1],)))
    add("shape_samples_count", "samples/count", "one window more per chain",
        reshape("samples/count", lambda s: (s[0], s[1] + 1)))
    add("shape_samples_r2", "samples/r2", "two components per sample instead of 3",
        reshape("samples/r2", lambda s: s[:3] + (2,)))
    add("shape_samples_t_cap", "samples/t", "fewer samples per window than the others",
        reshape("samples/t", lambda s: (s[0], s[1], s[2] - 1)))
    add("shape_tasks_final_state", "tasks/final_state", "one column fewer",
        reshape("tasks/final_state", lambda s: (s[0], s[1] - 1)))
    add("shape_chains_model", "chains/model", "one chain fewer", reshape("chains/model", lambda s: (s[0] - 1, s[1])))
    add("shape_tasks_status", "tasks/status", "one task fewer", reshape("tasks/status", lambda s: (s[0] - 1,)))

    # Wrong types.
    add("type_windows_class_float", "windows/class", "stored as float64", retype("windows/class", np.float64))
    add("type_samples_count_float", "samples/count", "stored as float64", retype("samples/count", np.float64))
    add("type_tasks_status_float", "tasks/status", "stored as float32", retype("tasks/status", np.float32))
    add("type_windows_direction_float", "windows/direction", "stored as float64",
        retype("windows/direction", np.float64))
    add("type_windows_omega_ball_int", "windows/omega_ball", "stored as int32", retype("windows/omega_ball", np.int32))
    add("type_chains_variant_float", "chains/variant", "stored as float64", retype("chains/variant", np.float64))
    add("type_samples_t_string", "samples/t", "stored as strings", retype("samples/t", STR))

    # The format version.
    add("version_string", "@format_version", "format_version the string '3'", set_attr("/", "format_version", "3"), "")
    add("version_newer", "@format_version", "format_version 99", set_attr("/", "format_version", np.int64(99)), "")
    add("version_float", "@format_version", "format_version 2.5", set_attr("/", "format_version", 2.5), "")
    add("version_missing", "@format_version", "no format_version (read as 1)", remove_attr("/", "format_version"), "")

    # Missing datasets and attributes.
    for ds in ["windows/class", "windows/omega_ball", "windows/radius_bottom_std", "windows/omega_m_begin",
               "samples/r2", "samples/count", "chains/model", "config", "tasks/status", "classes"]:
        add("missing_" + ds.replace("/", "_"), ds, "removed", remove(ds))
    add("missing_variant_labels", "chains/variant@labels", "attribute removed", remove_attr("chains/variant", "labels"))
    add("missing_chains_axes", "chains@axes", "attribute removed", remove_attr("chains", "axes"))
    add("missing_model_columns", "chains/model@columns", "attribute removed", remove_attr("chains/model", "columns"))

    # NaN and Inf where the writer never stores one.
    nan = lambda old: np.nan
    add("nan_windows_t_begin", "windows/t_begin", "NaN at the first computed window", set_value("windows/t_begin", at_window(()), nan))
    add("nan_windows_omega_m_begin", "windows/omega_m_begin", "NaN at a computed window",
        set_value("windows/omega_m_begin", at_window(()), nan))
    add("inf_windows_omega_m_end", "windows/omega_m_end", "Inf at a computed window",
        set_value("windows/omega_m_end", at_window(()), lambda old: np.inf))
    add("nan_samples_r2", "samples/r2", "NaN inside count (a chunk read as fill values)",
        set_value("samples/r2", at_window((5,)), lambda old: np.full_like(old, np.nan)))
    add("nan_samples_t", "samples/t", "NaN inside count", set_value("samples/t", at_window((3,)), nan))
    add("nan_samples_L1", "samples/L1", "NaN inside count", set_value("samples/L1", at_window((0,)), nan))
    add("nan_chains_model", "chains/model", "NaN in chain 0's first parameter",
        set_value("chains/model", lambda f: (0, 0), nan))

    # Codes and indices out of range.
    add("range_class_6", "windows/class", "class code 6", set_value("windows/class", at_window(()), lambda o: 6))
    add("range_class_minus2", "windows/class", "class code -2", set_value("windows/class", at_window(()), lambda o: -2))
    add("range_count_over_cap", "samples/count", "count above the samples per window",
        set_value("samples/count", at_window(()), lambda o: 10 ** 6))
    add("range_count_negative", "samples/count", "count -1", set_value("samples/count", at_window(()), lambda o: -1))
    add("range_variant_index", "chains/variant", "variant index 7 of 2", set_value("chains/variant", lambda f: 0, lambda o: 7))
    add("range_group_index", "chains/group", "group index -1", set_value("chains/group", lambda f: 0, lambda o: -1))
    add("range_part_index", "chains/part", "part 99", set_value("chains/part", lambda f: 0, lambda o: 99))
    add("range_start_seed_index", "chains/start_seed", "seed index 9",
        set_value("chains/start_seed", lambda f: 0, lambda o: 9))
    add("range_task_status", "tasks/status", "status 7", set_value("tasks/status", lambda f: 0, lambda o: 7))

    # Labels and names: long, with control characters, the wrong number of them.
    add("label_10kB", "chains/variant@labels", "a 10 kB variant label",
        edit_names("chains/variant", "labels", lambda l: replace_first(l, "x" * 10240)))
    add("label_newline", "chains/variant@labels", "a newline inside a variant label",
        edit_names("chains/variant", "labels", lambda l: replace_first(l, "first line\nsecond line")))
    add("label_ansi", "chains/variant@labels", "an ANSI escape inside a variant label",
        edit_names("chains/variant", "labels", lambda l: replace_first(l, "\x1b[2J\x1b[31mred\x1b[0m")))
    add("label_nul_like", "chains/variant@labels", "a bell and a backspace inside a variant label",
        edit_names("chains/variant", "labels", lambda l: replace_first(l, "bell\x07back\x08")))
    add("name_group_newline", "chains/group@names", "a newline inside a group name",
        edit_names("chains/group", "names", lambda l: replace_first(l, "ri\nse")))
    add("purpose_control", "chains/group@purposes", "an escape inside a group purpose",
        edit_names("chains/group", "purposes", lambda l: replace_first(l, "\x1b]0;title\x07")))
    add("names_variant_extra", "chains/variant@names", "one variant name more than variants",
        edit_names("chains/variant", "names", lambda l: l + ["ghost"]))
    add("names_variant_short", "chains/variant@names", "one variant name fewer",
        edit_names("chains/variant", "names", lambda l: l[:-1]))

    # Values edited with a valid checksum.
    add("edit_class", "windows/class", "a computed window's class changed",
        set_value("windows/class", at_window(()), lambda o: 3 if o != 3 else 1))
    add("edit_omega_ball", "windows/omega_ball", "a computed window's ω_ball changed",
        set_value("windows/omega_ball", at_window(()), lambda o: o + 1.0))
    add("edit_omega_m_begin", "windows/omega_m_begin", "a window's ω_m changed",
        set_value("windows/omega_m_begin", at_window(()), lambda o: o + 0.5))
    add("edit_samples_r2", "samples/r2", "a sample's position moved by 1 m",
        set_value("samples/r2", at_window((2,)), lambda o: o + 1.0))
    add("edit_samples_count", "samples/count", "a window's count halved",
        set_value("samples/count", at_window(()), lambda o: o // 2))
    add("edit_chains_variant", "chains/variant", "chain 0 moved to the other variant",
        set_value("chains/variant", lambda f: 0, lambda o: 1 - o))
    add("edit_config_radius", "config", "the stored configuration's drive radius changed",
        edit_config("drive_radius = 0.015", "drive_radius = 0.016"))
    add("edit_config_garbage", "config", "the stored configuration is not TOML",
        edit_config("[model]", "[model"))
    add("edit_classifier_settings", "windows@classifier_settings", "another classifier setting recorded",
        set_attr("windows", "classifier_settings", "circular_max_rel_amplitude=0.01"))
    add("edit_classifier_settings_bad", "windows@classifier_settings", "an unknown classifier setting",
        set_attr("windows", "classifier_settings", "no_such_setting=1"))
    add("edit_task_status", "tasks/status", "a finished task marked never ran",
        set_value("tasks/status", lambda f: 0, lambda o: 0))
    add("edit_chains_axes", "chains@axes", "an axis name changed",
        edit_names("chains", "axes", lambda l: l + ["ghost_axis"]))

    # The class table (format 3).
    add("classes_name", "classes/name", "a class renamed",
        set_value("classes/name", lambda f: 3, lambda o: "daisy"), "classes")
    add("classes_circular", "classes/circular", "fallen marked circular",
        set_value("classes/circular", lambda f: 0, lambda o: 1), "classes")
    add("classes_short", "classes/colour", "one colour fewer",
        reshape("classes/colour", lambda s: (s[0] - 1,)), "classes")
    return out


def as_format_2(source, path):
    """`source` (format 3) rewritten as format 2 wrote it: the lists joined by newlines (commas
    for axes, columns and hold seeds), /windows/class@names instead of /classes. Every reader
    must read it as it reads the source."""
    shutil.copyfile(source, path)
    commas = {("chains", "axes"), ("chains/model", "columns"), ("chains/seed", "names")}
    with h5py.File(path, "r+") as f:
        def join(name, obj):
            for k, v in list(obj.attrs.items()):
                if isinstance(v, np.ndarray) and v.dtype == object:
                    sep = "," if (name, k) in commas else "\n"
                    obj.attrs[k] = sep.join(x.decode() if isinstance(x, bytes) else str(x) for x in v)
        join("", f)
        f.visititems(join)
        names = [x.decode() if isinstance(x, bytes) else str(x) for x in f["classes/name"][()]]
        f["windows/class"].attrs["names"] = ",".join(f"{i} {n}" for i, n in enumerate(names))
        del f["classes"]
        f.attrs["format_version"] = np.int64(2)
    return path


def make(source, outdir):
    """Every applicable case written into outdir; returns [(name, path, dataset, description)]
    and writes outdir/manifest.tsv."""
    os.makedirs(outdir, exist_ok=True)
    with h5py.File(source, "r") as f:
        present = lambda p: p == "" or p in f
        applicable = [c for c in cases() if present(c[4])]
    made = []
    for name, dataset, what, damage, _ in applicable:
        path = os.path.join(outdir, name + ".h5")
        shutil.copyfile(source, path)
        damage(path)
        made.append((name, path, dataset, what))
    with open(os.path.join(outdir, "manifest.tsv"), "w") as fh:
        for name, path, dataset, what in made:
            fh.write(f"{name}\t{dataset}\t{what}\n")
    return made


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: make_corpus.py SOURCE.h5 OUTDIR")
    made = make(sys.argv[1], sys.argv[2])
    print(f"{len(made)} damaged copies of {sys.argv[1]} in {sys.argv[2]}")
