#!/usr/bin/python3
"""The analysis package's reader (analysis/astrojax_analysis/reader.py) against files built here
with h5py exactly as docs/reference/file-format.md lays them out: format 4 (string_power and
clutch_power, 27 columns of /tasks/final_state), format 3 (string arrays, /classes, 25 columns)
and format 2 (joined strings, 20 columns), each then damaged one way at a time.

`analysis_reader_test.py SOURCE_DIR` runs without astrojax: every check here is on files this
test writes. (The damaged copies of files astrojax wrote are tests/analysis_damaged_test.py.)
"""
import contextlib
import io
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

SOURCE = os.path.abspath(sys.argv[1])
ANALYSIS = os.path.join(SOURCE, "analysis")
sys.path.insert(0, ANALYSIS)  # the package, as the scripts beside it find it

import astrojax_analysis as ajx  # noqa: E402
from astrojax_analysis import reader  # noqa: E402

C, W, CAP, T = 2, 3, 4, 2
CLASSES = [("fallen", 0, "#999999"), ("locked-circular", 1, "#0072B2"), ("lagging-circular", 1, "#009E73"),
           ("flower", 0, "#CC79A7"), ("not-settled", 0, "#E69F00"), ("failed", 0, "#000000")]
STR = h5py.string_dtype("utf-8")
NEWEST = 5
FINAL_STATE_COLUMNS = {1: 20, 2: 20, 3: 25, 4: 27, 5: 27}  # t, mode, σ, s*, impact_loss, y (15); tie (5); ledger (2)
POWERS = {"motor_power": 2, "drag_power": 2, "friction_impact_power": 2, "energy_rate": 2, "string_power": 4,
          "clutch_power": 4}  # each from the format that first always writes it


def strings(obj, name, items, version, sep):
    """A list of strings as format `version` stores it: an array (3) or joined (1, 2)."""
    if version >= 3:
        obj.attrs.create(name, np.array(items, dtype=object), dtype=STR)
    else:
        obj.attrs[name] = sep.join(items)


def make_sweep(path, version=NEWEST, labels=("paper's physics (rigid tie)", "tie clutch"), purposes=("from rest",),
               colours=None):
    """A small grouped sweep (C chains × W windows, CAP samples, T tasks) as astrojax writes it."""
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "sweep"
        if version > 1:
            f.attrs["format_version"] = np.int64(version)
        cfg = f.create_dataset("config", data="[protocol]\n", dtype=STR)
        cfg.attrs["source"] = "tiny.toml"
        strings(cfg, "overrides", ["model.drag=0.5"], version, "\n")
        if version >= 3:
            g = f.create_group("classes")
            g.create_dataset("name", data=np.array([c[0] for c in CLASSES], dtype=object), dtype=STR)
            g.create_dataset("circular", data=np.array([c[1] for c in CLASSES], dtype=np.int8))
            g.create_dataset("description", data=np.array([f"the {c[0]} class" for c in CLASSES], dtype=object),
                             dtype=STR)
            g.create_dataset("colour", data=np.array(colours or [c[2] for c in CLASSES], dtype=object), dtype=STR)
        w = f.create_group("windows")
        cls = w.create_dataset("class", data=np.array([[1, 2, 3], [0, 1, -1]], np.int32))
        if version < 3:
            cls.attrs["names"] = ",".join(f"{i} {c[0]}" for i, c in enumerate(CLASSES))
        tb = np.array([[0.0, 5.0, 10.0]] * C)
        for name, v, unit in (("t_begin", tb, "s"), ("t_end", tb + 5, "s"), ("omega_m_begin", 4 * np.pi + tb, "rad/s"),
                              ("omega_m_end", 4 * np.pi + tb + 5, "rad/s"), ("phi_begin", tb * 3, "rad"),
                              ("omega_ball", 4 * np.pi + tb + 2.5, "rad/s"), ("confidence", np.ones((C, W)), "1"),
                              ("L1_mean", np.full((C, W), 0.5), "m"), ("radius_bead_mean", np.full((C, W), 0.1), "m")):
            d = w.create_dataset(name, data=v)
            d.attrs["units"] = unit
        for name, since in POWERS.items():
            if version >= since:
                w.create_dataset(name, data=np.full((C, W), 0.125)).attrs["units"] = "W"
        w.create_dataset("direction", data=np.ones((C, W), np.int32))
        w.create_dataset("segment", data=np.array([[0, 0, 0], [0, 0, -1]], np.int32))
        w.create_dataset("mode_fraction", data=np.zeros((C, W, 5)))
        s = f.create_group("samples")
        s.attrs["sample_rate"] = 10.0
        count = np.array([[CAP, CAP, 2], [CAP, 1, 0]], np.int32)
        s.create_dataset("count", data=count)
        for name in ("t", "omega_m", "L1", "T1", "T2", "mode"):
            v = np.full((C, W, CAP), np.nan)
            for c in range(C):
                for k in range(W):
                    v[c, k, :count[c, k]] = tb[c, k] + np.arange(count[c, k]) * 0.1 if name == "t" else 0.25
            s.create_dataset(name, data=v.astype(np.float64 if name == "t" else np.float32), chunks=(1, 1, CAP),
                             fletcher32=True, compression="gzip")
        for name in ("r1", "r2"):
            v = np.full((C, W, CAP, 3), np.nan, np.float32)
            for c in range(C):
                for k in range(W):
                    v[c, k, :count[c, k]] = 0.1
            s.create_dataset(name, data=v, chunks=(1, 1, CAP, 3), fletcher32=True, compression="gzip")
        ch = f.create_group("chains")
        model = ch.create_dataset("model", data=np.array([[0.826, 0.015, 0.035]] * C))
        strings(model, "columns", ["string_length [m]", "drive_radius [m]", "contact_distance [m]"], version, ",")
        strings(ch, "axes", [], version, ",")
        gr = ch.create_dataset("group", data=np.zeros(C, np.int32))
        strings(gr, "names", ["from_rest"], version, "\n")
        strings(gr, "purposes", list(purposes), version, "\n")
        va = ch.create_dataset("variant", data=np.arange(C, dtype=np.int32))
        strings(va, "names", ["rigid", "clutch"], version, "\n")
        strings(va, "labels", list(labels), version, "\n")
        ss = ch.create_dataset("start_seed", data=np.zeros(C, np.int32))
        strings(ss, "names", ["hanging"], version, "\n")
        ch.create_dataset("start_omega", data=np.zeros(C))
        t = f.create_group("tasks")
        t.create_dataset("chain", data=np.arange(T, dtype=np.int64))
        t.create_dataset("index", data=np.zeros(T, np.int64))
        t.create_dataset("t_begin", data=np.zeros(T))
        t.create_dataset("t_end", data=np.full(T, 15.0))
        t.create_dataset("status", data=np.ones(T, np.int32))
        t.create_dataset("steps", data=np.full(T, 100, np.int64))
        t.create_dataset("final_state", data=np.zeros((T, FINAL_STATE_COLUMNS[version])))
        strings(t, "failures", [], version, "\n")
        f.create_group("provenance").attrs["program"] = "astrojax test"


def refused(test, path, dataset, words=()):
    """The reader refuses the file with a SweepFileError naming `dataset` and each of `words`."""
    with test.assertRaises(ajx.SweepFileError) as cm:
        ajx.Sweep(path)
    e = cm.exception
    test.assertEqual(e.path, path)
    test.assertEqual(e.dataset, dataset, str(e))
    for w in words:
        test.assertIn(w, e.message)
    test.assertEqual(str(e), f"{path}: {dataset}: {e.message}" if dataset else f"{path}: {e.message}")
    return e


class reader_formats(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def test_formats_2_3_and_4_read_alike(self):
        for v in (2, 3, 4):
            make_sweep(self.path(f"v{v}.h5"), v)
        a, b, d = (ajx.Sweep(self.path(f"v{v}.h5")) for v in (2, 3, 4))
        self.assertEqual((a.version, b.version, d.version), (2, 3, 4))
        for name in ("class_names", "class_colours", "variant_labels", "variant_names", "group_names", "group_purposes",
                     "start_seed_names", "model_columns", "axes", "overrides", "failures", "circular_classes"):
            self.assertEqual(getattr(a, name), getattr(b, name), name)
            self.assertEqual(getattr(d, name), getattr(b, name), name)
        self.assertEqual([len(s.final_state(0)) for s in (a, b, d)], [20, 25, 27])
        # string_power and clutch_power: format 4's; an older file's read as NaN (not computed)
        np.testing.assert_array_equal(d.stats["clutch_power"], np.full((C, W), 0.125))
        self.assertTrue(np.all(np.isnan(b.stats["string_power"])) and np.all(np.isnan(a.stats["clutch_power"])))
        np.testing.assert_array_equal(a.stats["motor_power"], d.stats["motor_power"])
        self.assertEqual(b.overrides, ["model.drag=0.5"])
        self.assertEqual(b.circular_classes, ("locked-circular", "lagging-circular"))
        self.assertEqual(b.class_colours, ajx.CLASS_COLOURS)  # FORMAT 3 colours: today's, figures unchanged
        np.testing.assert_array_equal(a.stats["omega_ball"], b.stats["omega_ball"])
        s = b.samples(0, 2)
        self.assertEqual(len(s["t"]), 2)
        self.assertEqual(s["r1"].shape, (2, 3))

    def test_colours_come_from_the_file(self):
        colours = [c[2] for c in CLASSES]
        colours[3] = "#123456"
        make_sweep(self.path("c.h5"), 3, colours=colours)
        s = ajx.Sweep(self.path("c.h5"))
        self.assertEqual(s.class_colours["flower"], "#123456")
        self.assertEqual(s.class_colour(0, 2), "#123456")  # chain 0, window 2 is a flower

    def test_labels_hold_any_text_and_print_escaped(self):
        odd = ["line one\nline two", "bel\x07and\x1b[31mred"]
        make_sweep(self.path("odd.h5"), 3, labels=odd)
        s = ajx.Sweep(self.path("odd.h5"))
        self.assertEqual(s.variant_labels, odd)  # stored as given: each variant keeps its own label
        self.assertEqual(s.variant_label(1), odd[1])
        self.assertEqual(ajx.printable(odd[1]), "bel\\x07and\\x1b[31mred")
        self.assertEqual(ajx.printable(odd[0]), "line one\\nline two")
        self.assertNotIn("\n", s.chain_label(0))
        self.assertEqual(ajx.for_figure("$x$ " + "y" * 500)[:6], r"\$x\$ ")
        self.assertLessEqual(len(ajx.for_figure("y" * 10000)), ajx.labels.FIGURE_LIMIT)

    def test_version_checks(self):
        for value, words in ((np.int64(6), ["6", "newer", "(5)"]), ("3", ["'3'", "not an integer"]),
                             (2.5, ["not an integer"]), (np.int64(0), ["outside [1, 5]"])):
            make_sweep(self.path("v.h5"))
            with h5py.File(self.path("v.h5"), "r+") as f:
                f.attrs["format_version"] = value
            refused(self, self.path("v.h5"), "/", words)

    def test_brackets(self):
        # Format 5: a bisection's bracket and its two probes (chain 1: ω_fall from 4π, past it at 2.5π).
        def add(path, threshold=1, index=(0, 1)):
            with h5py.File(path, "r+") as f:
                b = f.create_group("brackets")
                for k, v in (("chain", [1]), ("threshold", [threshold]), ("planned_probes", [2]), ("known_class", [1]),
                             ("other_class", [0]), ("status", [1])):
                    b.create_dataset(k, data=np.array(v, np.int32))
                for k, v in (("from", 4), ("to", 2.5), ("width", 1.5), ("start_omega", 4), ("known_omega", 4),
                             ("other_omega", 2.5)):
                    b.create_dataset(k, data=np.array([v * np.pi]))
                p = b.create_group("probes")
                for k, v in (("chain", [1, 1]), ("index", list(index)), ("class", [1, 0]), ("ran", [1, 1]),
                             ("known_side", [1, 0]), ("status", [0, 1])):
                    p.create_dataset(k, data=np.array(v, np.int32))
                for k, v in (("omega_m", [4, 2.5]), ("known_omega", [4, 4]), ("other_omega", [np.nan, 2.5])):
                    p.create_dataset(k, data=np.array(v) * np.pi)
                p.create_dataset("stats", data=np.zeros((2, 17)))
                p.create_dataset("powers", data=np.zeros((2, 6)))
        make_sweep(self.path("b.h5"), 5)
        add(self.path("b.h5"))
        s = ajx.SweepFile(self.path("b.h5"))
        self.assertAlmostEqual(s.brackets["known_omega"][0], 4 * np.pi)
        self.assertEqual(list(s.brackets["probes"]["class"]), [1, 0])
        self.assertNotIn("guide", s.brackets)
        with h5py.File(self.path("b.h5"), "r+") as f:  # a guided chain's prediction
            f["brackets"].create_dataset("guide", data=np.array([3.6 * np.pi]))
        self.assertAlmostEqual(ajx.SweepFile(self.path("b.h5")).brackets["guide"][0], 3.6 * np.pi)
        with h5py.File(self.path("b.h5"), "r+") as f:
            del f["brackets/guide"]
            f["brackets"].create_dataset("guide", data=np.array([1.0, 2.0]))
        refused(self, self.path("b.h5"), "/brackets/guide", [])
        make_sweep(self.path("b.h5"), 5)
        add(self.path("b.h5"), threshold=7)
        refused(self, self.path("b.h5"), "/brackets/threshold", ["7", "outside [0, 3]"])
        make_sweep(self.path("b.h5"), 5)
        add(self.path("b.h5"), index=(1, 0))
        refused(self, self.path("b.h5"), "/brackets/probes/index", ["expected chain 1 probe 0"])
        make_sweep(self.path("b.h5"), 4)
        add(self.path("b.h5"))
        refused(self, self.path("b.h5"), "/brackets", ["new in format 5"])

    def test_missing_and_not_hdf5(self):
        refused(self, self.path("none.h5"), None, ["no such file"])
        with open(self.path("text.h5"), "w") as f:
            f.write("not HDF5\n")
        refused(self, self.path("text.h5"), None, ["cannot read as HDF5"])

    def damaged(self, edit, version=NEWEST, **kw):
        make_sweep(self.path("d.h5"), version, **kw)
        with h5py.File(self.path("d.h5"), "r+") as f:
            edit(f)
        return self.path("d.h5")

    def test_basins(self):
        """/basins (format 5): read when consistent; refused naming the dataset when a sample's class
        is not its chain's window 0, a count or a fraction does not follow from the samples, or the
        file is older than basins; the stored attractors read when consistent with the samples'
        classes and refused naming /basins/attractor when a sample is on one of another class."""
        def add(f, cls=(1, 0), frac=None, attractor=None):
            g = f.create_group("basins")
            g.create_dataset("chain", data=np.arange(C, dtype=np.int64))
            g.create_dataset("level", data=np.zeros(C, np.int32))
            g.create_dataset("sample", data=np.arange(C, dtype=np.int32))
            g.create_dataset("class", data=np.array(cls, np.int32))
            g.create_dataset("start", data=np.zeros((C, 27)))
            g.create_dataset("features", data=np.full((C, 4), 0.1))
            lv = g.create_group("levels")
            for name, v in (("part", [0]), ("first", [0]), ("samples", [C]), ("family", [0]), ("done", [C])):
                lv.create_dataset(name, data=np.array(v, np.int32))
            lv.create_dataset("omega_m", data=np.array([4 * np.pi]))
            count = np.zeros((1, len(CLASSES)), np.int32)
            count[0, 0] = count[0, 1] = 1
            lv.create_dataset("count", data=count)
            lo, hi = reader.wilson_interval(count, np.array([[C]]))
            lv.create_dataset("fraction", data=frac if frac is not None else count / C)
            lv.create_dataset("lower", data=lo)
            lv.create_dataset("upper", data=hi)
            if attractor is not None:  # attractor 0 of class 1 (locked), 1 of class 0 (fallen)
                g.create_dataset("attractor", data=np.array(attractor, np.int32))
                at = g.create_group("attractors")
                at.create_dataset("name", data=np.array(["locked-circular", "fallen"], dtype=h5py.string_dtype()))
                at.create_dataset("class", data=np.array([1, 0], np.int32))
                at.create_dataset("part", data=np.array([0, 0], np.int32))
                c = np.array([[1, 1]], np.int32)
                at.create_dataset("count", data=c)
                a_lo, a_hi = reader.wilson_interval(c, np.array([[C]]))
                at.create_dataset("fraction", data=c / C)
                at.create_dataset("lower", data=a_lo)
                at.create_dataset("upper", data=a_hi)
        s = ajx.Sweep(self.damaged(lambda f: add(f, attractor=(0, 1))))
        self.assertEqual(s.basins["attractors"]["name"], ["locked-circular", "fallen"])
        self.assertEqual(s.basins["attractor"].tolist(), [0, 1])
        refused(self, self.damaged(lambda f: add(f, attractor=(1, 0))), "/basins/attractor", ["another class"])
        s = ajx.Sweep(self.damaged(add))
        self.assertIsNone(s.basins["attractors"])
        self.assertEqual(s.basins["levels"]["count"][0, :2].tolist(), [1, 1])
        self.assertAlmostEqual(s.basins["levels"]["lower"][0, 0], 0.0945, places=4)  # 1 of 2: [0.0945, 0.9055]
        refused(self, self.damaged(lambda f: add(f, cls=(0, 0))), "/basins/class", ["at [0]", "/windows/class"])
        bad = np.zeros((1, len(CLASSES)))
        bad[0, 0] = 1.0
        refused(self, self.damaged(lambda f: add(f, frac=bad)), "/basins/levels/fraction", ["count / done"])
        refused(self, self.damaged(add, version=4), "/basins", ["format_version 4"])

    def test_each_dataset_of_the_layout_is_required(self):
        for name in ("windows/class", "windows/t_begin", "windows/omega_m_end", "windows/phi_begin", "windows/direction",
                     "windows/segment", "windows/omega_ball", "samples/count", "samples/t", "samples/r2", "samples/mode",
                     "chains/model", "tasks/chain", "tasks/status", "tasks/final_state", "classes/colour",
                     "chains/variant", "windows/motor_power", "windows/string_power", "windows/clutch_power"):
            def drop(f):
                del f[name]
            refused(self, self.damaged(drop), "/" + name, ["missing"])
        # A power is required from the format that first always writes it on.
        drop_energy = lambda f: f["windows"].__delitem__("energy_rate")  # noqa: E731
        refused(self, self.damaged(drop_energy, version=2), "/windows/energy_rate", ["missing"])

    def test_final_state_columns_of_each_format(self):
        # 27 columns from format 4 on (the motor's ledger), 25 in format 3, 20 before: a format
        # reads its own count and the newest, and refuses a count it never wrote.
        def cols(n):
            def edit(f):
                del f["tasks/final_state"]
                f["tasks"].create_dataset("final_state", data=np.zeros((T, n)))
            return edit
        for version, n in ((4, 25), (4, 20), (3, 20), (4, 26), (2, 39)):
            refused(self, self.damaged(cols(n), version=version), "/tasks/final_state",
                    [f"has {n} columns, expected 27"])
        for version, n in ((3, 27), (2, 25), (2, 27)):
            self.assertEqual(len(ajx.Sweep(self.damaged(cols(n), version=version)).final_state(1)), n)

    def test_shape_and_type(self):
        def short(f):
            d = f["windows/omega_ball"][:, :2]
            del f["windows/omega_ball"]
            f.create_dataset("windows/omega_ball", data=d).attrs["units"] = "rad/s"
        refused(self, self.damaged(short), "/windows/omega_ball", ["shape 2 × 2, expected 2 × 3"])

        def floats(f):
            d = f["windows/class"][:].astype(float)
            del f["windows/class"]
            f.create_dataset("windows/class", data=d)
        refused(self, self.damaged(floats), "/windows/class", ["float64", "expected integer"])

        def cap(f):
            d = f["samples/L1"][:, :, :2]
            del f["samples/L1"]
            f.create_dataset("samples/L1", data=d)
        refused(self, self.damaged(cap), "/samples/L1", ["shape 2 × 3 × 2, expected 2 × 3 × 4"])

        def rank(f):
            d = f["samples/r1"][..., 0]
            del f["samples/r1"]
            f.create_dataset("samples/r1", data=d)
        refused(self, self.damaged(rank), "/samples/r1", ["expected 2 × 3 × 4 × 3"])

    def test_values_the_writer_never_stores(self):
        def put(name, index, value):
            def edit(f):
                d = f[name][()]
                d[index] = value
                f[name][...] = d
            return edit
        refused(self, self.damaged(put("windows/class", (0, 1), 6)), "/windows/class", ["6", "[0, 1]", "[-1, 5]"])
        refused(self, self.damaged(put("windows/class", (1, 0), -2)), "/windows/class", ["-2"])
        refused(self, self.damaged(put("samples/count", (0, 0), CAP + 1)), "/samples/count", ["5", "[0, 4]"])
        refused(self, self.damaged(put("samples/count", (1, 1), -1)), "/samples/count", ["-1"])
        refused(self, self.damaged(put("windows/t_begin", (0, 2), np.nan)), "/windows/t_begin", ["nan", "[0, 2]"])
        refused(self, self.damaged(put("chains/variant", 1, 2)), "/chains/variant", ["2", "index into names"])
        refused(self, self.damaged(put("tasks/chain", 0, 7)), "/tasks/chain", ["7"])
        refused(self, self.damaged(put("tasks/status", 0, 4)), "/tasks/status", ["4"])
        # A NaN inside /samples/count is refused when the window is read.
        s = ajx.Sweep(self.damaged(put("samples/r2", (0, 1, 2, 0), np.nan)))
        with self.assertRaises(ajx.SweepFileError) as cm:
            s.samples(0, 1)
        self.assertEqual(cm.exception.dataset, "/samples/r2")
        self.assertIn("chain 0, window 1", cm.exception.message)
        s.samples(0, 0)  # the other windows stay readable
        with self.assertRaises(ajx.SweepFileError) as cm:
            s.check_samples()  # the whole file's samples at once
        self.assertEqual(cm.exception.dataset, "/samples/r2")

    def test_strings_of_format_3_are_arrays(self):
        def joined(f):
            f["chains/variant"].attrs["labels"] = "a\nb"
        refused(self, self.damaged(joined), "/chains/variant", ["labels", "1-D array of strings"])

        def count(f):
            strings(f["chains/variant"], "labels", ["one"], 3, "")
        refused(self, self.damaged(count), "/chains/variant", ["labels has 1 entries, expected 2"])

        def colour(f):
            d = f["classes/colour"][()]
            d[2] = b"green"
            del f["classes/colour"]
            f["classes"].create_dataset("colour", data=d, dtype=STR)
        refused(self, self.damaged(colour), "/classes/colour", ["'green' at index 2"])

    def test_a_joined_label_of_format_2_cannot_mislabel(self):
        # Format 2 joins labels with newlines: a label holding one yields three labels for two
        # variants, which is refused instead of shifting the second variant's label.
        path = self.damaged(lambda f: None, version=2, labels=("one\ntwo", "three"))
        refused(self, path, "/chains/variant", ["labels has 3 entries, expected 2"])

    def test_checksum_failure_names_the_dataset(self):
        make_sweep(self.path("k.h5"), 3)
        with h5py.File(self.path("k.h5"), "r") as f:
            offset = f["samples/r2"].id.get_chunk_info(0).byte_offset
        with open(self.path("k.h5"), "r+b") as f:
            f.seek(offset + 4)
            b = f.read(1)
            f.seek(offset + 4)
            f.write(bytes([b[0] ^ 0x55]))
        s = ajx.Sweep(self.path("k.h5"))
        with self.assertRaises(ajx.SweepFileError) as cm:
            s.samples(0, 0)
        self.assertEqual(cm.exception.dataset, "/samples/r2")
        self.assertIn("checksum", cm.exception.message)

    def test_run_file(self):
        path = self.path("run.h5")
        n = 5
        with h5py.File(path, "w") as f:
            f.attrs["format"], f.attrs["format_version"] = "run", np.int64(3)
            tr = f.create_group("trajectory")
            for name in ("t", "omega_m", "phi", "L1"):
                tr.create_dataset(name, data=np.arange(n, dtype=float))
            tr.create_dataset("mode", data=np.zeros(n, np.int32))
            for name in ("r1", "r2"):
                tr.create_dataset(name, data=np.ones((n, 3)))
            f.create_group("summary").attrs["status"] = "ok"
        run = ajx.read_run(path)
        self.assertEqual(len(run["t"]), n)
        self.assertEqual(run["summary"]["status"], "ok")
        # The clutch's columns came with format 4: a format-3 file lacks them, a format-4 one
        # must hold them.
        self.assertNotIn("clutch_loss", ajx.read_run(path, ("clutch_loss", "tie_energy")))
        with h5py.File(path, "r+") as f:
            f.attrs["format_version"] = np.int64(4)
        with self.assertRaises(ajx.SweepFileError) as cm:
            ajx.read_run(path, ("clutch_loss",))
        self.assertEqual((cm.exception.dataset, cm.exception.message), ("/trajectory/clutch_loss", "missing"))
        with h5py.File(path, "r+") as f:
            f["trajectory"].create_dataset("clutch_loss", data=np.zeros(n))
        np.testing.assert_array_equal(ajx.read_run(path, ("clutch_loss",))["clutch_loss"], np.zeros(n))
        with h5py.File(path, "r+") as f:
            f["trajectory/r2"][2, 1] = np.inf
        with self.assertRaises(ajx.SweepFileError) as cm:
            ajx.read_run(path)
        self.assertEqual(cm.exception.dataset, "/trajectory/r2")
        with self.assertRaises(ajx.SweepFileError) as cm:
            ajx.Sweep(path)
        self.assertIn("run file", cm.exception.message)


class reader_scripts(unittest.TestCase):
    """Scripts on format-3 files made here: a correct result, or one line and exit 2."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.csv = os.path.join(self.tmp.name, "thresholds.csv")
        with open(self.csv, "w") as f:
            f.write("chain,threshold,before_rad_s,after_rad_s,mid_rad_s,paper_rad_s,relative_difference\n"
                    "0,omega_1,15.0,15.7,15.35,15.08,0.01\n")

    def script(self, name, *args):
        p = subprocess.run([sys.executable, os.path.join(ANALYSIS, name), *args], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    def test_a_10_kB_label_with_a_newline_and_a_dollar_draws(self):
        path = os.path.join(self.tmp.name, "odd.h5")
        make_sweep(path, 3, labels=("$\\alpha$ " + "x" * 10000, "two\nlines\x1b[2J"))
        out = os.path.join(self.tmp.name, "odd.png")
        code, stdout, stderr = self.script("plot_hysteresis.py", path, "-o", out, "--thresholds", self.csv,
                                           "--size", "9,6", "--dpi", "50")
        self.assertEqual(code, 0, stderr)
        self.assertTrue(os.path.getsize(out) > 1000)

    def test_a_damaged_file_is_one_line_and_exit_2(self):
        path = os.path.join(self.tmp.name, "bad.h5")
        make_sweep(path, 3)
        with h5py.File(path, "r+") as f:
            f.attrs["format_version"] = "three"
        for script, args in (("plot_hysteresis.py", ["-o", os.path.join(self.tmp.name, "x.png"), "--thresholds",
                                                      self.csv]),
                             ("plot_phase.py", ["-o", os.path.join(self.tmp.name, "x.png")]),
                             ("plot_branches.py", ["-o", os.path.join(self.tmp.name, "x.png"), "--thresholds",
                                                    self.csv]),
                             ("scene_state.py", ["0"])):
            code, stdout, stderr = self.script(script, path, *args)
            self.assertEqual(code, 2, (script, stderr))
            self.assertEqual(stderr, f"error: {path}: /: attribute format_version is 'three', not an integer\n", script)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], *sys.argv[2:]], verbosity=2)
