#!/usr/bin/python3
"""Every reader of the analysis package, and the scripts that read sweep and run files, on
damaged copies of files astrojax wrote (the fixture analysis_data: phase.h5, hold.h5, run.h5).
Each copy must give a correct result or one line `error: <file>: ...` with exit 2: never a
traceback.

The copies: those of tests/damaged/make_corpus.py (the C++ readers' corpus, made here from
its tests/damaged/tiny_grouped.toml) when it is there, plus this test's own: every dataset of the layout
dropped, datasets with the wrong shape, rank or type class, values the writer never stores, a
string or newer format_version, and bytes flipped at fixed offsets spread over the file.

`analysis_damaged_test.py ASTROJAX SOURCE_DIR DATA_DIR [NAME]`
"""
import contextlib
import importlib
import io
import os
import shutil
import subprocess
import sys
import tempfile
import traceback
import unittest

import h5py
import numpy as np

ASTROJAX, SOURCE, DATA = (os.path.abspath(p) for p in sys.argv[1:4])
os.environ["ASTROJAX"] = ASTROJAX
ANALYSIS = os.path.join(SOURCE, "analysis")
sys.path.insert(0, ANALYSIS)  # the package and its scripts, as run in place

import astrojax_analysis as ajx  # noqa: E402

FLIPS = 12  # byte flips per file, at offsets spread evenly over it
# Datasets also stored one row short (a dataset every script reads, of each group).
SHORTENED = ("windows/class", "windows/omega_ball", "windows/t_begin", "windows/phi_begin", "samples/count",
             "samples/t", "samples/r1", "chains/model", "chains/variant", "tasks/final_state", "tasks/chain",
             "trajectory/t", "trajectory/r2", "trajectory/mode", "trajectory/energy")


def data(name):
    return os.path.join(DATA, name)


# ---- the corpus ----------------------------------------------------------------------------

def edits_of(path):
    """(name, function editing an open h5py.File) for every structural damage of `path`."""
    with h5py.File(path, "r") as f:
        datasets = []
        f.visititems(lambda n, o: datasets.append(n) if isinstance(o, h5py.Dataset) else None)
    out = []
    for name in datasets:
        out.append((f"drop {name}", lambda f, n=name: f.__delitem__(n)))

    def replace(name, fn):
        def edit(f):
            d = fn(f[name][()])
            attrs = dict(f[name].attrs)
            del f[name]
            new = f.create_dataset(name, data=d)
            for k, v in attrs.items():
                new.attrs[k] = v
        return edit

    def put(name, index, value):
        def edit(f):
            d = f[name][()]
            d[index] = value
            f[name][...] = d
        return edit

    for name in SHORTENED:
        if name in datasets:
            out.append((f"short {name}", replace(name, lambda d: d[:-1])))
    for name in ("windows/omega_ball", "windows/class", "samples/count", "trajectory/mode", "trajectory/t",
                 "tasks/chain", "chains/model"):
        if name in datasets:
            out.append((f"float->int/str {name}", replace(name, lambda d: d.astype(np.float64) if d.dtype.kind == "i"
                                                               else np.nan_to_num(d).astype(np.int32))))
            out.append((f"rank {name}", replace(name, lambda d: d.reshape(-1)[:, None] if d.ndim == 1 else d[..., 0])))
    for name, index, value in (("windows/class", (0, 0), 9), ("windows/class", (0, 1), -5),
                               ("samples/count", (0, 0), 10 ** 6), ("samples/count", (0, 1), -1),
                               ("windows/t_begin", (0, 0), np.nan), ("windows/omega_m_end", (0, 1), np.inf),
                               ("windows/direction", (0, 0), 3), ("tasks/chain", 0, 999), ("tasks/status", 0, 9),
                               ("chains/seed", 0, 99), ("trajectory/t", 3, np.nan), ("trajectory/r1", (2, 0), np.inf),
                               ("trajectory/mode", 1, 17)):
        if name in datasets:
            out.append((f"value {name}{index}={value}", put(name, index, value)))
    if "samples/r2" in datasets:
        out.append(("NaN inside count", put("samples/r2", (0, 0, 0, 0), np.nan)))
    for value in ("2", np.int64(99), 2.5, np.int64(-1)):
        out.append((f"format_version {value!r}", lambda f, v=value: f.attrs.__setitem__("format_version", v)))
    for name, attr in (("windows/class", "names"), ("chains/seed", "names"), ("chains/model", "columns"),
                       ("config", "overrides")):
        if name in datasets:
            out.append((f"attribute {name}@{attr}", lambda f, n=name, a=attr: f[n].attrs.__setitem__(a, "x" * 10000)))
    return out


def make_copies(src, folder, only=None, flips=FLIPS):
    """Damaged copies of src in folder: [(copy, what)]; `only`: the edits whose text holds one of
    these words."""
    out = []
    base = os.path.splitext(os.path.basename(src))[0]
    for i, (what, edit) in enumerate(edits_of(src)):
        if only and not any(w in what for w in only):
            continue
        dst = os.path.join(folder, f"{base}_edit{i:03d}.h5")
        shutil.copyfile(src, dst)
        try:
            with h5py.File(dst, "r+") as f:
                edit(f)
        except (KeyError, ValueError, TypeError, OSError, IndexError):
            os.remove(dst)  # an edit that does not apply to this file
            continue
        out.append((dst, what))
    size = os.path.getsize(src)
    for j in range(flips):
        offset = 256 + (size - 512) * j // flips
        dst = os.path.join(folder, f"{base}_flip{j:02d}.h5")
        shutil.copyfile(src, dst)
        with open(dst, "r+b") as f:
            f.seek(offset)
            b = f.read(1)
            f.seek(offset)
            f.write(bytes([b[0] ^ 0xFF]))
        out.append((dst, f"byte {offset} flipped"))
    return out


def corpus_copies(folder):
    """The C++ reader's corpus (tests/damaged/make_corpus.py) when it is there: [(copy, what)]."""
    maker = os.path.join(SOURCE, "tests", "damaged", "make_corpus.py")
    if not os.path.exists(maker):
        return []
    out_dir, source = os.path.join(folder, "corpus"), os.path.join(folder, "grouped.h5")
    # The corpus's own source: the small grouped sweep its cases are written for.
    subprocess.run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests", "damaged", "tiny_grouped.toml"), "-o", source,
                    "-q"], check=True, capture_output=True,
                   env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"))
    p = subprocess.run([sys.executable, maker, source, out_dir], capture_output=True, text=True)
    if p.returncode != 0:
        raise AssertionError(f"{maker} exited with {p.returncode}: {p.stderr}")
    return [(os.path.join(out_dir, n), f"corpus {n}") for n in sorted(os.listdir(out_dir)) if n.endswith(".h5")]


# ---- running readers and scripts in this process -----------------------------------------------

def call(main, argv):
    """(exit code, stderr) of a script's main through ajx.run, in this process; any other
    exception propagates (the traceback a user would see)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            ajx.run(main, argv)
            code = 0
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else 1
    return code, err.getvalue()


def read_everything(path):
    """The readers themselves: the sweep and every window's samples, or the run."""
    kind = ajx.file_kind(path)
    if kind == "sweep":
        s = ajx.Sweep(path)
        s.check_samples()
        s.samples(0, int(np.argmax(s.count[0])))
        for c in range(s.n_chains):
            s.chain_label(c)
        s.groups()
    else:
        ajx.read_run(path, ("energy", "motor_work", "drag_loss", "friction_loss", "impact_loss"))


class Corpus(unittest.TestCase):
    SOURCES = ()
    SCRIPTS = ()
    MAX_DRAWN = 8  # accepted copies drawn by a script (each drawing costs about a second)

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()
        cls.copies = []
        for name, only, flips in cls.SOURCES:
            cls.copies += make_copies(data(name), cls.tmp, only, flips)
        if cls.SOURCES and cls.SOURCES[0][0] == "phase.h5":
            cls.copies += corpus_copies(cls.tmp)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def check(self, label, path, run):
        """run() is a clean result (0), or one line naming the file with exit 2."""
        try:
            code, err = run()
        except Exception:
            return f"{label} on {path}: traceback\n{traceback.format_exc(limit=4)}"
        if code == 0:
            return None
        lines = err.splitlines()
        if code != 2 or len(lines) != 1 or not lines[0].startswith(f"error: {path}"):
            return f"{label} on {path}: exit {code}, stderr {err!r}"
        return None

    def test_readers_and_scripts(self):
        self.assertGreater(len(self.copies), 30)
        problems, refused, accepted = [], 0, 0
        out = os.path.join(self.tmp, "figure.png")
        for path, what in self.copies:
            outcome = []

            def reader():
                try:
                    read_everything(path)
                    outcome.append(0)
                except ajx.SweepFileError as e:
                    outcome.append(2)
                    return 2, f"error: {e}\n"
                return 0, ""
            problems.append(self.check(f"reader ({what})", path, reader))
            refused += outcome == [2]
            accepted += outcome == [0]
            # A copy the reader refuses costs a script little: every script runs on it. One it
            # accepts is drawn, the costly part: by one script each, in turn.
            scripts = self.SCRIPTS if outcome != [0] else [self.SCRIPTS[accepted % len(self.SCRIPTS)]]
            if outcome == [0] and self.MAX_DRAWN is not None and accepted > self.MAX_DRAWN:
                scripts = []  # the default suite draws a few; the *_all tests (label long) draw them all
            for script, args in scripts:
                main = importlib.import_module(script).main
                problems.append(self.check(f"{script} ({what})", path,
                                           lambda: call(main, [path, *[out if a == "OUT" else a for a in args]])))
        problems = [p for p in problems if p]
        self.assertEqual(problems, [], "\n".join(problems[:10]))
        # Most damage is found: every structural edit and most flips outside the raw data.
        self.assertGreater(refused, len(self.copies) // 2, f"{refused} of {len(self.copies)} copies refused")


class damaged_sweep(Corpus):
    # The grouped-free ramp sweep fully; of the hold sweep what only it has.
    SOURCES = (("phase.h5", None, FLIPS), ("hold.h5", ("hold_omega", "seed", "perturbation"), 6))
    SCRIPTS = (("plot_hysteresis", ["-o", "OUT", "--thresholds", data("thresholds.csv"), "--size", "4,3", "--dpi",
                                    "20", "--no-paper"]),
               ("plot_orbits", ["-o", "OUT", "--size", "4,3", "--dpi", "20"]))


class damaged_run(Corpus):
    SOURCES = (("run.h5", None, FLIPS),)
    SCRIPTS = (("plot_run", ["-o", "OUT", "--size", "4,3", "--dpi", "20"]),
               ("run_ledger", ["--window", "1", "--tail", "1"]))


class damaged_sweep_all(damaged_sweep):
    MAX_DRAWN = None


class damaged_run_all(damaged_run):
    MAX_DRAWN = None


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], *sys.argv[4:]], verbosity=2)
