#!/usr/bin/python3
"""Tests of the analysis scripts (analysis/*.py), run by ctest with Debian's interpreter.

`analysis_test.py ASTROJAX SOURCE_DIR DATA_DIR make` makes the small files once (the ctest
fixture analysis_data): a sweep over three drive radii (tests/data/tiny_phase.toml), the
tiny hold sweep, the tiny sweep over R and d, one trajectory, and the thresholds astrojax
prints for the first sweep.
`analysis_test.py ASTROJAX SOURCE_DIR DATA_DIR NAME` runs the unittest class NAME on them.

Images are checked without matplotlib or PIL: a PNG's IHDR gives its pixel size, which must
be the requested --size × --dpi exactly, and its decoded pixels must not be blank; a PDF's
MediaBox must be the requested size in points.
"""
import csv
import math
import os
import re
import struct
import subprocess
import sys
import shutil
import unittest
import zlib

import numpy as np

ASTROJAX, SOURCE, DATA = (os.path.abspath(p) for p in sys.argv[1:4])
# Every script a test starts finds the astrojax under test, whatever the build folder.
os.environ["ASTROJAX"] = ASTROJAX
ANALYSIS = os.path.join(SOURCE, "analysis")
PYTHON = sys.executable
sys.path.insert(0, ANALYSIS)  # the package, as the scripts beside it find it

import astrojax_analysis as ajx  # noqa: E402


def data(name):
    return os.path.join(DATA, name)


def run(args, check=True):
    """Runs a command; returns (exit code, stdout + stderr)."""
    p = subprocess.run(args, capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"{' '.join(args)} exited with {p.returncode}:\n{p.stdout}{p.stderr}")
    return p.returncode, p.stdout + p.stderr


def script(name, *args, check=True):
    return run([PYTHON, os.path.join(ANALYSIS, name), *args], check=check)


def make():
    shutil.rmtree(DATA, ignore_errors=True)  # made afresh: astrojax refuses to replace a file
    os.makedirs(DATA, exist_ok=True)
    run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests/data/tiny_phase.toml"), "-o", data("phase.h5"), "-q"])
    run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests/data/tiny_hold.toml"), "-o", data("hold.h5"), "-q"])
    run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests/data/tiny_sweep.toml"), "-o", data("grid2.h5"), "-q",
         "--set", "grid.contact_distance=[0.03,0.04]"])  # two grid axes: R and d
    run([ASTROJAX, "run", os.path.join(SOURCE, "sweeps/spin_up.toml"), "-o", data("run.h5"), "-q"])
    # For the calibration: two drive radii at two ramp rates across ω_rise.
    run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests/data/tiny_rise.toml"), "-o", data("calib.h5"), "-q",
         "--set", "grid.drive_radius=[0.01,0.02]", "--set", "grid.ramp_rate=[0.5,1.0]"])
    run([ASTROJAX, "thresholds", data("calib.h5"), "--no-hold", "--csv", data("calib_thresholds.csv")])
    # For the scripts of `astrojax orbits` and `astrojax bench`: a short continuation, and a
    # tiny work-precision and stability scan (about 1 s together).
    run([ASTROJAX, "orbits", os.path.join(SOURCE, "sweeps/orbits.toml"), "--continue", "omega", "--s", "0.5443",
         "--range", "10", "30", "-o", data("equilibria.h5")])
    # For plot_map.py: the cone_down and fold curves over R at the documented set (about 1 s).
    run([ASTROJAX, "orbits", os.path.join(SOURCE, "sweeps/orbits_map.toml"), "--map", "drive_radius",
         "--curves", "cone_down,fold", "--range", "0.01", "0.02", "-o", data("map.h5")])
    run([ASTROJAX, "bench", "work-precision", os.path.join(SOURCE, "sweeps/scenes/locked_circular.toml"),
         "--methods", "dop853,rk4", "--rtols", "1e-4,1e-6", "--steps", "0.01,0.005", "--horizon", "1",
         "--repeats", "1", "-o", data("work_precision.csv")])
    run([ASTROJAX, "bench", "stability", os.path.join(SOURCE, "sweeps/spin_up.toml"), "--methods", "rk4,euler",
         "--omegas-pi", "2,4", "--horizon", "1", "-o", data("stability.csv")])
    _, out = run([ASTROJAX, "thresholds", data("phase.h5"), "--no-hold", "--csv", data("thresholds.csv")])
    with open(data("thresholds.txt"), "w") as f:
        f.write(out)


# ---- PNG and PDF without an imaging library ----------------------------------------

def png_size(path):
    """(width, height) from a PNG's IHDR chunk, which follows the 8-byte signature."""
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise AssertionError(f"{path}: not a PNG")
    return struct.unpack(">II", head[16:24])


def png_pixels(path):
    """(width, height, rows of pixels as bytes tuples) of an 8-bit RGB or RGBA PNG."""
    with open(path, "rb") as f:
        blob = f.read()
    if blob[:8] != b"\x89PNG\r\n\x1a\n":
        raise AssertionError(f"{path}: not a PNG")
    pos, idat, ihdr = 8, b"", None
    while pos < len(blob):
        length, kind = struct.unpack(">I4s", blob[pos:pos + 8])
        body = blob[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = ihdr
    if depth != 8 or colour not in (2, 6) or interlace:
        raise AssertionError(f"{path}: unexpected PNG format (depth {depth}, colour {colour}, interlace {interlace})")
    bpp = 4 if colour == 6 else 3
    raw = zlib.decompress(idat)
    stride = width * bpp
    prev = bytearray(stride)
    rows = []
    for y in range(height):
        ftype, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):  # undo the filter of this row (PNG spec, section 9)
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ftype == 1:
                line[i] = (line[i] + a) & 255
            elif ftype == 2:
                line[i] = (line[i] + b) & 255
            elif ftype == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, bpp, rows


class ImageChecks(unittest.TestCase):
    def assert_png(self, path, width, height, min_ink=0.02, coloured=True):
        """The PNG is width × height pixels and shows a drawing: at least min_ink of its
        pixels differ from the background (the corner pixel), and (coloured) at least 0.03 %
        are coloured: the scripts draw classes, paths or thresholds in colour, while empty
        axes, ticks and text are black and grey (an empty axes at 50 dpi: 4.4 % ink, 0 %
        coloured)."""
        self.assertEqual(png_size(path), (width, height), f"{path}: pixel size")
        w, h, bpp, rows = png_pixels(path)
        background = rows[0][:bpp]
        pixels = [row[i:i + bpp] for row in rows[::2] for i in range(0, len(row), 2 * bpp)]
        ink = sum(p != background for p in pixels) / len(pixels)
        self.assertGreater(ink, min_ink, f"{path}: nearly blank ({100 * ink:.2f} % drawn)")
        if not coloured:
            return
        coloured = sum(max(p[:3]) - min(p[:3]) > 60 for p in pixels) / len(pixels)
        self.assertGreater(coloured, 0.0003, f"{path}: no coloured drawing ({100 * coloured:.3f} % coloured)")

    def assert_pdf(self, path, width_pt, height_pt):
        with open(path, "rb") as f:
            blob = f.read()
        self.assertTrue(blob.startswith(b"%PDF"), f"{path}: not a PDF")
        box = re.search(rb"/MediaBox\s*\[\s*0\s+0\s+([\d.]+)\s+([\d.]+)\s*\]", blob)
        self.assertIsNotNone(box, f"{path}: no MediaBox")
        self.assertAlmostEqual(float(box.group(1)), width_pt, places=3)
        self.assertAlmostEqual(float(box.group(2)), height_pt, places=3)
        self.assertGreater(len(blob), 5000, f"{path}: too small to hold a figure")

    def image(self, name, *args, size=(8, 5), dpi=50, inputs=("phase.h5",), ext="png", **png_checks):
        """Runs analysis/NAME on each input at --size and --dpi, checks each image."""
        for inp in inputs:
            out = data(f"{os.path.splitext(name)[0]}_{os.path.splitext(inp)[0]}.{ext}")
            if os.path.exists(out):
                os.remove(out)
            script(name, data(inp), "-o", out, "--size", f"{size[0]},{size[1]}", "--dpi", str(dpi), *args)
            if ext == "png":
                self.assert_png(out, round(size[0] * dpi), round(size[1] * dpi), **png_checks)
            else:
                self.assert_pdf(out, size[0] * 72, size[1] * 72)


THRESHOLD_ARGS = ("--astrojax", ASTROJAX)


class hysteresis(ImageChecks):
    def test_png_ramp_and_hold(self):
        self.image("plot_hysteresis.py", *THRESHOLD_ARGS, inputs=("phase.h5", "hold.h5"))

    def test_pdf(self):
        self.image("plot_hysteresis.py", *THRESHOLD_ARGS, "--chains", "0,2", size=(9, 4), ext="pdf")

    def test_thresholds_from_csv_and_the_demo_form(self):
        # the CSV instead of running astrojax; and setup.sh's form (astrojax found via $ASTROJAX)
        self.image("plot_hysteresis.py", "--thresholds", data("thresholds.csv"))
        out = data("hysteresis_demo_form.png")
        p = subprocess.run([PYTHON, os.path.join(ANALYSIS, "plot_hysteresis.py"), data("phase.h5"), "-o", out],
                           capture_output=True, text=True, env=dict(os.environ, ASTROJAX=ASTROJAX))
        self.assertEqual(p.returncode, 0, p.stderr)
        w, h = png_size(out)
        self.assertEqual(w, 2340)  # 3 panels of 6.5 in at 120 dpi
        self.assertGreater(h, 5.5 * 120)  # a row of 5.5 in and the legend


class branches(ImageChecks):
    def test_png(self):
        self.image("plot_branches.py", *THRESHOLD_ARGS, size=(10, 6), inputs=("phase.h5", "hold.h5"))


class phase(ImageChecks):
    def test_png_over_drive_radius_and_hold(self):
        self.image("plot_phase.py", "--axis", "drive_radius", "--omega-ball-tol", "0.1", size=(8, 6))
        self.image("plot_phase.py", size=(8, 3), inputs=("hold.h5",))

    def test_coexistence(self):
        # Two passes over 0..10 rad/s (entries: ω_m from, to, class, ω_ball): fallen
        # throughout; and fallen below 4 (ω_ball 1 rad/s below 2, 3 rad/s from 2 to 4), then
        # locked. Classes differ on [4, 7]; not-settled never counts, lagging does.
        import plot_phase
        strips = {"up": [(0, 5, "fallen", 1.0), (5, 10, "fallen", 1.0)],
                  "down": [(0, 2, "fallen", 1.0), (2, 4, "fallen", 3.0), (4, 7, "locked-circular", 5.5),
                           (7, 10, "not-settled", 8.5)]}
        self.assertEqual(plot_phase.coexistence(strips), [(4, 7, "class")])
        # ω_ball 1 and 3 rad/s at ω_m ≈ 3 differ by 2/3 ω_m: above a tolerance of 0.5, not of 0.7.
        self.assertEqual(plot_phase.coexistence(strips, 0.5), [(2, 4, "omega_ball"), (4, 7, "class")])
        self.assertEqual(plot_phase.coexistence(strips, 0.7), [(4, 7, "class")])
        strips["down"][3] = (7, 10, "lagging-circular", 8.5)
        self.assertEqual(plot_phase.coexistence(strips), [(4, 10, "class")])

    def test_two_grid_axes(self):
        rc, out = script("plot_phase.py", data("grid2.h5"), "-o", data("x.png"), "--axis", "drive_radius", check=False)
        self.assertEqual(rc, 2)
        self.assertIn("grid axis 'contact_distance' varies too; fix it with --where contact_distance=VALUE", out)
        # Every window of this sweep is fallen (grey): the class blocks must fill the axes.
        self.image("plot_phase.py", "--axis", "drive_radius", "--where", "contact_distance=0.04", size=(8, 4),
                   inputs=("grid2.h5",), min_ink=0.15, coloured=False)

    def test_bad_axis(self):
        rc, out = script("plot_phase.py", data("phase.h5"), "-o", data("x.png"), "--axis", "mass", check=False)
        self.assertEqual(rc, 2)
        self.assertIn("--axis mass: not a grid axis", out)


class orbits(ImageChecks):
    def test_png_from_sweep_and_run(self):
        self.image("plot_orbits.py", "--chain", "2", "--omega", "3,13", size=(10, 6), dpi=40)
        # the circular_high seed at both held ω_m (two chains), and by default one per class
        self.image("plot_orbits.py", "--chain", "2", "--omega", "6,8", size=(10, 6), dpi=40, inputs=("hold.h5",))
        self.image("plot_orbits.py", "--chain", "2", size=(10, 6), dpi=40, inputs=("hold.h5",))
        self.image("plot_orbits.py", "--omega", "6,14", "--tail", "1.5", size=(10, 6), dpi=40, inputs=("run.h5",))

    def test_stored_phase_and_radius_put_the_top_on_the_string(self):
        # The files store R (/resolved, /chains/model) and the motor phase at each window start
        # (/windows/phi_begin); with them the top a(φ) = (R cos φ, R sin φ, 0) must lie at the
        # distance L1 from the bead wherever the string is taut. The samples are float32 (6e-8
        # relative): |r1 − a| and L1 (< 1 m) each carry up to ~6e-8 m, and ∫ω_m dt by the
        # trapezoid is exact on a ramp; so 1e-6 m bounds rounding, while a phase 1e-3 rad off
        # moves the top by R·1e-3 = 1e-5 m, ten times more.
        import numpy as np
        import astrojax_analysis as ajx
        sweep = ajx.Sweep(data("phase.h5"))
        worst = 0.0
        for c in range(sweep.n_chains):
            R = sweep.parameter(c, "drive_radius")
            for k in range(sweep.n_windows):
                s = sweep.samples(c, k)
                if len(s["t"]) < 2:
                    continue
                phi = ajx.window_phase(sweep, c, k, s)
                top = np.stack([R * np.cos(phi), R * np.sin(phi), np.zeros_like(phi)], axis=1)
                taut = s["mode"] != 4  # not slack (physics Mode::Slack)
                gap = np.abs(np.linalg.norm(s["r1"] - top, axis=1) - s["L1"])[taut]
                worst = max(worst, float(gap.max(initial=0.0)))
        print(f"\nlargest | |r1 − a(φ)| − L1 | over the sweep: {worst:.1e} m")
        self.assertLess(worst, 1e-6)
        # A run file: R from /resolved.
        self.assertEqual(ajx.run_parameter(data("run.h5"), "model.drive_radius"), 0.01)  # sweeps/spin_up.toml


def section(md_path, title):
    """The lines of a Markdown file's section "## title" (up to the next "## " heading)."""
    out, inside = [], False
    with open(md_path) as f:
        for line in f:
            if line.startswith("## "):
                inside = line.strip() == f"## {title}"
            elif inside:
                out.append(line)
    return out


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


class report(unittest.TestCase):
    def assert_rows_verbatim(self, ours_csv, theirs_csv):
        """Every row and field of astrojax's CSV stands in the report's CSV to the letter; returns
        astrojax's rows and those with a reached threshold (there must be some, or the
        comparison proves nothing)."""
        with open(theirs_csv, newline="") as f:
            theirs = list(csv.DictReader(f))
        with open(ours_csv, newline="") as f:
            ours = list(csv.DictReader(f))
        self.assertEqual(len(ours), len(theirs))
        for a, b in zip(ours, theirs):
            for k in b:
                self.assertEqual(a[k], b[k], f"chain {b['chain']} {b['threshold']} {k}")
        reached = [b for b in theirs if b["mid_rad_s"]]
        self.assertTrue(reached, "the test sweep must reach a threshold, or this comparison proves nothing")
        return theirs, reached

    def test_numbers_equal_astrojax_thresholds(self):
        md, out_csv = data("report.md"), data("report.csv")
        script("threshold_report.py", data("phase.h5"), "-o", md, "--csv", out_csv, *THRESHOLD_ARGS)
        # The CSV: astrojax's rows and fields, verbatim.
        theirs, reached = self.assert_rows_verbatim(out_csv, data("thresholds.csv"))
        # The Markdown: every row's numbers, the bracket, its midpoint and the paper's value in
        # π rad/s and the relative difference in %, at the precision astrojax gives them.
        printed = {}
        for b in theirs:
            nums = []
            if b["mid_rad_s"]:
                nums = [f"{float(b[k]) / math.pi:.3f}" for k in ("before_rad_s", "after_rad_s", "mid_rad_s")]
                nums += [f"{float(b['paper_rad_s']) / math.pi:.2f}", f"{100 * float(b['relative_difference']):+.1f}"]
            else:
                nums = [f"{float(b['paper_rad_s']) / math.pi:.2f}"]
            printed[(b["chain"], b["threshold"])] = nums
        symbols = {"omega_rise": "ω_rise", "omega_fall": "ω_fall", "omega_1": "ω1", "omega_2": "ω2"}
        table = [line for line in section(md, "Every chain") if re.match(r"\| \d+ \|", line)]
        self.assertEqual(len(table), len(theirs))
        for line, b in zip(table, theirs):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            self.assertEqual((cells[0], cells[2]), (b["chain"], symbols[b["threshold"]]))
            self.assertEqual(re.findall(r"[+-]?\d+\.\d+", " ".join(cells[3:])), printed[(b["chain"], b["threshold"])],
                             f"Markdown row {line.strip()}")


    def test_refined_columns(self):
        # --refine 1 re-runs each bracket at the sweep's own rate: the refined bracket is the
        # sweep's, to the digit, in the Markdown as in the CSV.
        md = data("report_refined.md")
        script("threshold_report.py", data("phase.h5"), "-o", md, "--refine", "1", *THRESHOLD_ARGS)
        with open(data("report_refined.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        reached = [r for r in rows if r["mid_rad_s"]]
        self.assertTrue(reached, "the test sweep must reach a threshold")
        for r in reached:
            self.assertEqual((r["refined_before_rad_s"], r["refined_after_rad_s"]), (r["before_rad_s"], r["after_rad_s"]))
        table = [line for line in section(md, "Every chain") if re.match(r"\| \d+ \|", line)]
        for line in table:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if cells[3] != "not reached":
                self.assertEqual(cells[7], cells[3], f"Markdown row {line.strip()}")


    def test_hold_verdicts(self):
        # --hold: the report's CSV carries astrojax's hold and verdict columns verbatim; the
        # Markdown shows both held sides of every bracket and one verdict per bracket, the same
        # as the CSV's.
        md, out_csv, theirs_csv = data("report_hold.md"), data("report_hold.csv"), data("hold_thresholds.csv")
        script("threshold_report.py", data("calib.h5"), "-o", md, "--csv", out_csv, "--hold", "10", *THRESHOLD_ARGS)
        run([ASTROJAX, "thresholds", data("calib.h5"), "--hold", "10", "--csv", theirs_csv])
        theirs, reached = self.assert_rows_verbatim(out_csv, theirs_csv)
        self.assertIn("verdict", theirs[0])
        for b in reached:
            self.assertIn(b["verdict"], ("bifurcation", "excursion", "time-limited transient", "undecided"))
            for side in ("pre", "post"):  # 10 s rounded up to whole windows, at least 4
                self.assertGreaterEqual(float(b[f"{side}_hold_s"]), 10.0)
        sides = [cells(l) for l in section(md, "Bifurcation or time limit") if re.match(r"\| \d+ \| \S+ \| (before|after)", l)]
        self.assertEqual(len(sides), 2 * len(reached))
        for (pre, post), b in zip(zip(sides[::2], sides[1::2]), reached):
            self.assertEqual((pre[0], pre[5], pre[6]), (b["chain"], b["pre_class"], b["pre_final_class"]))
            self.assertEqual((post[0], post[5], post[6]), (b["chain"], b["post_class"], b["post_final_class"]))
            self.assertAlmostEqual(float(pre[11]), float(b["pre_ratio"]), places=3)
        verdicts = [cells(l) for l in section(md, "Bifurcation or time limit") if re.match(r"\| \d+ \| \S+ \| [\d.]+ \.\.", l)]
        self.assertEqual([(v[0], v[3].strip("*")) for v in verdicts], [(b["chain"], b["verdict"]) for b in reached])

    def test_sequence(self):
        # The class sequence: astrojax's --sequence-csv rows verbatim next to the report, one
        # Markdown row per run and per paper step. Every chain starts from rest, so its first
        # run is fallen on the way up from ω_m = 0; where astrojax finds ω_rise without a blip
        # at the change, the paper's "rise" step sits at the bracket's midpoint (the window
        # boundary between the last fallen window and the first climbing one).
        md = data("report_seq.md")
        script("threshold_report.py", data("phase.h5"), "-o", md, "--csv", data("report_seq.csv"), *THRESHOLD_ARGS)
        run([ASTROJAX, "thresholds", data("phase.h5"), "--no-hold", "--sequence-csv", data("sequence.csv")])
        with open(data("sequence.csv"), newline="") as f:
            theirs = list(csv.DictReader(f))
        with open(data("report_seq_sequence.csv"), newline="") as f:
            ours = list(csv.DictReader(f))
        self.assertEqual(ours, theirs)
        with open(data("thresholds.csv"), newline="") as f:
            brackets = {(r["chain"], r["threshold"]): r for r in csv.DictReader(f)}
        lines = section(md, "Orbit class sequence")
        run_rows = [cells(l) for l in lines if re.match(r"\| \d+ \| (up|down|held) \|", l)]
        step_rows = [cells(l) for l in lines if re.match(r"\| (rise|circular|fall|locked|omega_1|omega_2) \|", l)]
        runs = [r for r in theirs if r["kind"] == "run"]
        steps = [r for r in theirs if r["kind"] == "step"]
        self.assertEqual([(r[2], r[4]) for r in run_rows], [(r["class"], r["windows"]) for r in runs])
        self.assertEqual([(r[0], r[2]) for r in step_rows], [(r["step"], r["status"]) for r in steps])
        chains = sorted({r["chain"] for r in runs}, key=int)
        self.assertEqual(len(chains), 3)
        checked = 0
        for c in chains:
            first = next(r for r in runs if r["chain"] == c)
            self.assertEqual((first["class"], first["direction"], float(first["omega_from_rad_s"])), ("fallen", "1", 0.0))
            rise = next(r for r in steps if r["chain"] == c and r["step"] == "rise")
            b = brackets[(c, "omega_rise")]
            climb = next((r for r in runs if r["chain"] == c and r["omega_from_rad_s"] == rise["omega_from_rad_s"]), None)
            if b["mid_rad_s"] and rise["status"] == "present" and climb and climb["blips"] == "0":
                self.assertAlmostEqual(float(rise["omega_from_rad_s"]), float(b["mid_rad_s"]), delta=1e-6)
                checked += 1
        self.assertGreater(checked, 0, "no chain to compare the rise step with astrojax's ω_rise")


class studies(ImageChecks):
    """The figures of `astrojax orbits` and `astrojax bench`: drawn at their own size, which
    the PNG must have (any size at all, but not blank and with colour)."""

    def figure(self, name, out, *args):
        if os.path.exists(out):
            os.remove(out)
        script(name, *args, "-o", out)
        self.assert_png(out, *png_size(out))

    def test_equilibria(self):
        self.figure("plot_equilibria.py", data("equilibria.png"), data("equilibria.h5"), "--sweep", data("phase.h5"))

    def map_figure(self, out, *args):
        # Thresholds are drawn in black and grey only (astrojax_analysis.py): no colour to find.
        if os.path.exists(out):
            os.remove(out)
        script("plot_map.py", *args, "-o", out)
        self.assert_png(out, *png_size(out), coloured=False)

    def test_map(self):
        self.map_figure(data("map.png"), data("map.h5"))

    def test_map_with_brackets_and_bad_input(self):
        # A sweep's brackets overlaid (the form a sweep map's `thresholds --csv` gives).
        with open(data("brackets.csv"), "w") as f:
            f.write("symbol,p,before,after\nomega_fall,0.012,10.0,10.6\nomega_fall,0.018,10.3,10.9\n")
        self.map_figure(data("map_brackets.png"), data("map.h5"), "--brackets", data("brackets.csv"))
        with open(data("brackets_bad.csv"), "w") as f:
            f.write("symbol,p,lo\nomega_fall,0.012,x\n")
        rc, out = script("plot_map.py", data("map.h5"), "--brackets", data("brackets_bad.csv"), "-o",
                         data("map_bad.png"), check=False)
        self.assertEqual(rc, 2, out)
        self.assertIn("symbol, p, before, after", out)
        rc, out = script("plot_map.py", data("phase.h5"), "-o", data("map_bad.png"), check=False)
        self.assertEqual(rc, 2, out)
        self.assertIn("/curves: missing", out)  # SweepFileError: file, dataset, problem
        # The reader: every curve point is on its curve's kind, and the codim-2 names match rows.
        from astrojax_analysis import Curves
        c = Curves(data("map.h5"))
        self.assertEqual(c.parameter, "drive_radius")
        self.assertEqual(c.parameter_unit, "m")
        self.assertEqual(len(c.codim2_names), len(c.codim2["p"]))
        self.assertTrue(c.curve_ids(("cone_down",)))

    def test_work_precision(self):
        self.figure("plot_work_precision.py", data("work_precision.png"), data("work_precision.csv"))

    def test_stability(self):
        self.figure("plot_stability.py", data("stability.png"), data("stability.csv"))


class calibration(unittest.TestCase):
    def test_extrapolation_recovers_a_line(self):
        import calibrate
        # Three rates on an exact line: the intercept, with the bracket widths' own error
        # (no scatter to scale it): σ² = 1/Σw for the intercept of a weighted line fit.
        w0, s0, b, sb, how = calibrate.extrapolate([0.1, 0.2, 0.4], [40.1, 40.2, 40.4], [0.05, 0.05, 0.05])
        self.assertAlmostEqual(w0, 40.0, places=10)
        self.assertAlmostEqual(b, 1.0, places=9)
        x = np.array([0.1, 0.2, 0.4])
        expected = 0.05 * np.sqrt(np.sum(x**2) / (3 * np.sum(x**2) - np.sum(x) ** 2))
        self.assertAlmostEqual(s0, expected, places=12)
        self.assertEqual(how, "3 rates")
        # One rate: the width-weighted mean and its error.
        w0, s0, _, _, how = calibrate.extrapolate([0.1, 0.1], [10.0, 12.0], [1.0, 1.0])
        self.assertEqual((w0, how), (11.0, "single rate"))
        self.assertAlmostEqual(s0, 1 / np.sqrt(2), places=12)

    def test_report_extrapolates_astrojax_brackets(self):
        # R = 2 cm crosses ω_rise at both rates: ω0 is the straight line through the two
        # bracket midpoints at rate 0, with σ² = (r2 h1)² + (r1 h2)² over (r2 − r1)².
        md = data("calibration.md")
        script("calibrate.py", data("calib.h5"), "-o", md, "--astrojax", ASTROJAX)
        with open(data("calib_thresholds.csv"), newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["threshold"] == "omega_rise" and "drive_radius=0.02" in r["parameters"]]
        pts = sorted((float(r["parameters"].split("ramp_rate=")[1]), float(r["before_rad_s"]), float(r["after_rad_s"]))
                     for r in rows if r["mid_rad_s"])
        self.assertEqual(len(pts), 2, "the test sweep must cross ω_rise at both rates for R = 2 cm")
        (r1, a1, b1), (r2, a2, b2) = pts
        m1, m2, h1, h2 = (a1 + b1) / 2, (a2 + b2) / 2, (b1 - a1) / 2, (b2 - a2) / 2
        w0 = (r2 * m1 - r1 * m2) / (r2 - r1)
        s0 = np.hypot(r2 * h1, r1 * h2) / (r2 - r1)
        with open(data("calibration.csv"), newline="") as f:
            mine = [r for r in csv.DictReader(f) if r["threshold"] == "omega_rise" and float(r["drive_radius_m"]) == 0.02]
        self.assertEqual(len(mine), 1)
        self.assertAlmostEqual(float(mine[0]["omega0_rad_s"]), w0, delta=1e-7 * w0)
        self.assertAlmostEqual(float(mine[0]["sigma_rad_s"]), s0, delta=1e-5 * s0)
        with open(md) as f:
            text = f.read()
        self.assertIn("## Best fit", text)


class adequacy(unittest.TestCase):
    """analysis/model_adequacy.py: the judging on constructed measurements, then a tiny run."""

    @staticmethod
    def measured(ramp=None, predicted=None, windows=(), holds=(), held=None, hopf=np.nan, stair_windows=()):
        paper = {"omega_rise": 12.63 * np.pi, "omega_fall": 3.24 * np.pi, "omega_1": 4.80 * np.pi,
                 "omega_2": 15.00 * np.pi}
        stair = {"mid": held or {}, "bracket": {}, "windows": list(stair_windows), "runs": [], "hopf": (hopf, 0.1),
                 "T_min": np.nan, "L1_min": np.nan}
        return {"paper": paper, "ramp": ramp or {}, "predicted": predicted or {}, "ramp_windows": list(windows),
                "holds": list(holds), "stair": stair, "layers": {}, "violations": {}}

    def test_judging(self):
        import model_adequacy as ma
        pi = np.pi
        # 5 % of the paper's value, either side: 12.63π · 1.05 = 13.26π is in, 13.27π out.
        self.assertTrue(ma.within(13.26 * pi, 12.63 * pi))
        self.assertFalse(ma.within(13.27 * pi, 12.63 * pi))
        self.assertFalse(ma.within(np.nan, 12.63 * pi))
        ladder = [("a", self.measured(ramp={"omega_rise": 11.0 * pi})),  # 12.9 % low: no
                  ("b", self.measured(ramp={"omega_rise": 12.5 * pi}, predicted={"omega_fall": 3.3 * pi},
                                      holds=[(4.8 * pi, "circular_high", "locked-circular", 4.8 * pi)])),
                  ("c", self.measured(ramp={"omega_rise": 12.7 * pi}, windows=[(2 * pi, "fallen", 1)]))]
        self.assertEqual(ma.smallest(ladder, "omega_rise"), ("b", "ramp"))
        self.assertEqual(ma.smallest(ladder, "omega_fall"), ("b", "equilibria"))
        self.assertEqual(ma.smallest(ladder, "omega_1"), (None, None))
        self.assertEqual(ma.smallest(ladder, "locked-circular"), ("b", "holds"))
        self.assertEqual(ma.smallest(ladder, "fallen"), ("c", "ramp"))
        # A prediction that only ran to the end of the continuation range is no threshold.
        text = ma.threshold_cell(ladder[0][1], "omega_rise")
        self.assertTrue(text.startswith("no: ramp 11.00π (-12.9 %)"), text)
        # The staircase: a held bracket's midpoint counts before the equilibria; for ω2 so does the
        # Hopf point (here the bracket's 16π is 6.7 % high, the Hopf point 14.81π 1.3 % low); a
        # staircase level names an orbit type after the ramps and holds.
        stair = [("d", self.measured(predicted={"omega1": 4.9 * pi}, held={"omega_1": 5.2 * pi, "omega_2": 16.0 * pi})),
                 ("e", self.measured(predicted={"omega1": 4.9 * pi}, held={"omega_1": 4.9 * pi, "omega_2": 16.0 * pi},
                                     hopf=14.81, stair_windows=[(5 * pi, "lagging-circular", 1)])),
                 ("f", self.measured(holds=[(6 * pi, "locked_orbit", "lagging-circular", 4.3 * pi)],
                                     stair_windows=[(5 * pi, "lagging-circular", -1)]))]
        self.assertEqual(ma.smallest(stair, "omega_1"), ("d", "equilibria"))  # 5.2π held is 8.3 % high
        self.assertEqual(ma.smallest(stair[1:], "omega_1"), ("e", "staircase"))
        self.assertEqual(ma.smallest(stair, "omega_2"), ("e", "Hopf point"))
        self.assertEqual(ma.smallest(stair, "lagging-circular"), ("e", "staircase"))
        self.assertEqual(ma.smallest(stair[2:], "lagging-circular"), ("f", "holds"))
        self.assertEqual(ma.shift_text(stair[1][1], stair[0][1], "omega_2", stair=True),
                         "ω2 Hopf: none (was 14.81π)")
        self.assertEqual(ma.threshold_cell(stair[1][1], "omega_2"),
                         "**yes**: ramp: not reached; held 16.00π (+6.7 %); Hopf 14.81π (-1.3 %)")
        self.assertEqual(ma.hopf_text(stair[1][1]), "Hopf 14.81 ± 0.10π (-1.3 %)")

    def test_hopf_point_is_the_one_astrojax_prints(self):
        import model_adequacy as ma
        # The row of `astrojax thresholds` on the staircase at c_a = 2e-6 (its σ scaled by
        # χ²/dof); another chain's row and a table without one give nothing.
        printed = ("  ω2         0 tie_damping=2e-06  16.000 → 16.500    0.500      lagging-circular → flower\n"
                   "  ω2 (Hopf)  1 tie_damping=3e-06  12.52 ± 0.13       0.260      lag's Hopf point, 30 levels\n"
                   "  ω2 (Hopf)  0 tie_damping=2e-06  15.34 ± 0.35       0.701      lag's Hopf point, 34 levels"
                   "        15.00      contains it        fit χ²/dof 2.1e+02\n")
        self.assertEqual(ma.hopf_point_printed(printed), (15.34, 0.35))
        self.assertTrue(all(math.isnan(v) for v in ma.hopf_point_printed(printed.splitlines()[1])))

    def test_tiny_run(self):
        md, work = data("adequacy.md"), data("adequacy_runs")
        script("model_adequacy.py", "-o", md, "--work", work, "--astrojax", ASTROJAX,
               "--ramp", os.path.join(SOURCE, "tests/data/tiny_rise.toml"),
               "--hold", os.path.join(SOURCE, "tests/data/tiny_adequacy_hold.toml"),
               "--run-ramp", os.path.join(SOURCE, "tests/data/tiny_adequacy_run_ramp.toml"),
               "--run-hold", os.path.join(SOURCE, "tests/data/tiny_adequacy_run_hold.toml"),
               "--staircase", os.path.join(SOURCE, "tests/data/tiny_adequacy_staircase.toml"),
               "--threshold-s-points", "2", "--sets-only", "stick_slip + slack,full + tie clutch")
        with open(md) as f:
            text = f.read()
        rows = {line.split("|")[1].strip(): [c.strip() for c in line.strip().strip("|").split("|")]
                for line in text.splitlines() if line.startswith("| ")}
        for item in ("ω_rise", "ω_fall", "ω1", "ω2", "fallen", "locked-circular", "lagging-circular", "flower"):
            self.assertIn(item, rows)
        # The ramp's ω_rise is astrojax thresholds' midpoint on the full model's own file.
        import model_adequacy as ma
        full = os.path.join(work, f"{ma.layer_tag(ma.FULL)}_ramp.h5")
        run([ASTROJAX, "thresholds", full, "--no-hold", "--csv", data("adequacy_full.csv")])
        with open(data("adequacy_full.csv"), newline="") as f:
            rise = [r for r in csv.DictReader(f) if r["threshold"] == "omega_rise"][0]
        self.assertTrue(rise["mid_rad_s"], "the tiny ramp must cross ω_rise, or this comparison proves nothing")
        mid = float(rise["mid_rad_s"])
        self.assertIn(f"ramp {mid / np.pi:.2f}π ({100 * float(rise['relative_difference']):+.1f} %)", rows["ω_rise"][-3])  # the full model's column
        # No ramp of 14π and no staircase to 5.4π reaches ω2: said, not hidden.
        self.assertEqual(rows["ω2"][-1], "**not reproduced**")
        self.assertIn("top stop (top_stop = false)", rows)
        # The staircase's held ω1 and ω_fall are astrojax thresholds' on the clutch set's own file,
        # and the lagging orbit, which no tiny hold gives, comes from the staircase alone.
        clutch = os.path.join(work, f"{ma.layer_tag(ma.CLUTCH)}_staircase.h5")
        run([ASTROJAX, "thresholds", clutch, "--no-hold", "--csv", data("adequacy_clutch.csv")])
        with open(data("adequacy_clutch.csv"), newline="") as f:
            held = {r["threshold"]: r for r in csv.DictReader(f)}
        for name, symbol in (("omega_1", "ω1"), ("omega_fall", "ω_fall")):
            self.assertTrue(held[name]["mid_rad_s"], f"the tiny staircase must cross {name}, or this proves nothing")
            mid, rel = float(held[name]["mid_rad_s"]), float(held[name]["relative_difference"])
            self.assertIn(f"held {mid / np.pi:.2f}π ({100 * rel:+.1f} %)", rows[symbol][-2])  # the clutch's column
        self.assertTrue(rows["lagging-circular"][-2].startswith("**yes**: staircase up"), rows["lagging-circular"])
        self.assertEqual(rows["lagging-circular"][-1], "full + tie clutch (staircase)")
        self.assertEqual(rows["ω2"][-2].split(": ", 1)[1], "ramp: not reached; held: not reached")
        # Omitting the clutch on the staircase: the lag's levels change class.
        self.assertIn("the tie clutch (tie = rigid)", rows)
        self.assertIn("lagging-circular→", rows["the tie clutch (tie = rigid)"][3])

    def test_bad_input(self):
        rc, out = script("model_adequacy.py", "-o", data("x.md"), "--ramp", data("missing.toml"), check=False)
        self.assertEqual(rc, 2)
        self.assertIn("missing.toml", out)
        rc, out = script("model_adequacy.py", "-o", data("x.md"), "--set", "layers.slack=false", check=False)
        self.assertEqual((rc, "outside [layers]" in out), (2, True), out)


class parameter_study_script(unittest.TestCase):
    def test_tiny_run(self):
        md, work = data("parameter_study.md"), data("parameter_study_runs")
        script("parameter_study.py", os.path.join(SOURCE, "tests/data/tiny_parameter_study.toml"), "-o", md,
               "--work", work, "--astrojax", ASTROJAX)
        with open(md) as f:
            lines = f.read().splitlines()
        eq = [[c.strip() for c in l.strip().strip("|").split("|")] for l in lines if l.startswith("| 4.8π | 0.")]
        eq = [row for row in eq if len(row) == 14]  # the equilibria's table (not the mass-change summary)
        # Each row's numbers are astrojax orbits' (its CSV in the work directory), rounded.
        self.assertTrue(eq)
        for row in eq:
            m, l, s = float(row[1]), float(row[2]), float(row[4])
            with open(os.path.join(work, f"orbits_m{m:g}_l{l:g}.csv"), newline="") as f:
                mine = [r for r in csv.DictReader(f) if r["case"] == "2" and abs(float(r["s"]) - s) < 6e-5]
            self.assertEqual(len(mine), 1, row)
            self.assertEqual(f"{float(mine[0]['T1']):.4f}", row[9])
            self.assertEqual(f"{100 * float(mine[0]['z1']):.2f}", row[6])
        # Held: one row per chain (2 masses × 2 lengths × 1 ω_m × 1 seed).
        held = [l for l in lines if l.startswith("| 4.8π | locked_orbit |")]
        self.assertEqual(len(held), 4)


class cli(unittest.TestCase):
    SCRIPTS = ("plot_hysteresis.py", "plot_branches.py", "plot_phase.py", "plot_orbits.py", "threshold_report.py",
               "plot_run.py", "calibrate.py")
    REPORTS = ("model_adequacy.py", "parameter_study.py", "flower_onset.py")

    def test_help(self):
        for name in self.SCRIPTS + self.REPORTS:
            rc, out = script(name, "--help")
            self.assertEqual(rc, 0)
            self.assertIn("usage:", out)
            self.assertIn("-o OUTPUT", out, name)

    def test_bad_input_named(self):
        for name in self.SCRIPTS:
            out_path = data("x.md" if name in ("threshold_report.py", "calibrate.py") else "x.png")
            rc, out = script(name, data("missing.h5"), "-o", out_path, check=False)
            self.assertEqual(rc, 2, name)
            self.assertIn("missing.h5", out, name)
        rc, out = script("plot_hysteresis.py", data("run.h5"), "-o", data("x.png"), check=False)
        self.assertEqual((rc, "not a sweep file" in out), (2, True), out)
        rc, out = script("plot_branches.py", data("phase.h5"), "-o", data("x.jpg"), *THRESHOLD_ARGS, check=False)
        self.assertEqual((rc, "must be .png or .pdf" in out), (2, True), out)

    def test_named_astrojax_not_replaced(self):
        # An executable the user named (--astrojax, or $ASTROJAX) that does not exist is an error
        # naming it, even though build/astrojax exists and would otherwise be found.
        missing = data("no_such_astrojax")
        rc, out = script("plot_hysteresis.py", data("hold.h5"), "-o", data("x.png"), "--astrojax", missing,
                         check=False)
        self.assertEqual((rc, "--astrojax" in out, missing in out), (2, True, True), out)
        p = subprocess.run([PYTHON, os.path.join(ANALYSIS, "plot_hysteresis.py"), data("hold.h5"), "-o",
                            data("x.png")], capture_output=True, text=True, env=dict(os.environ, ASTROJAX=missing))
        self.assertEqual((p.returncode, "$ASTROJAX" in p.stderr, missing in p.stderr), (2, True, True), p.stderr)

    def test_run_ledger(self):
        # An exact run (DOP853, rtol 1e-10) closes its ledger: the injection column, what the
        # integrator adds, is ~1e-9 of the powers (the run's energy residual), far below 1e-6.
        _, out = script("run_ledger.py", data("run.h5"), "--window", "10", "--tail", "5")
        rows = [line.split() for line in out.splitlines() if line.strip() and line.split()[0][0].isdigit()]
        self.assertGreaterEqual(len(rows), 5, out)
        self.assertIn("last 5 s", out)
        for r in rows:
            p_motor, p_drag, injection = float(r[8]), float(r[9]), float(r[12])
            self.assertLessEqual(abs(injection), 1e-6 * max(abs(p_motor), p_drag, 1e-9), r)
            self.assertEqual(float(r[13]), 0.0, r)  # P_clutch of a rigid tie
        _, out = script("run_ledger.py", data("run.h5"), "--window", "10", "--tail", "5", "--decay")
        m = re.search(r"amplitude \(ρ2\) ([-+0-9.]+) /s, kinetic energy ([-+0-9.]+) /s; c_D/2m = ([0-9.]+) /s", out)
        self.assertTrue(m, out)
        self.assertTrue(all(np.isfinite(float(g)) for g in m.groups()), out)
        rc, out = script("run_ledger.py", data("missing.h5"), check=False)
        self.assertEqual((rc, "missing.h5" in out), (2, True), out)
        rc, out = script("run_ledger.py", data("phase.h5"), check=False)
        self.assertEqual((rc, "not a run file" in out), (2, True), out)

    def test_tie_scan(self):
        # The scene of sweeps/scenes/lock_to_lag.toml with the rigid tie and one clutch: the
        # rigid orbit loses its lock and falls (the motor feeds a lagging orbit nothing); the
        # clutch keeps the bead up on a lagging orbit the motor sustains (dE/dt ≈ 0: the
        # decay at the drag rate would read −1; 0.01 leaves two decades).
        out = data("tie_scan.md")
        script("tie_scan.py", "-o", out, "--static", "8.8e-4", "--ratio", "1")
        rows = [[c.strip() for c in line.strip("|").split("|")] for line in open(out) if line.startswith("| ")]
        rows = [r for r in rows if r[0] in ("rigid", "clutch")]
        self.assertEqual([r[0] for r in rows], ["rigid", "clutch"])
        rigid, clutch = rows
        self.assertIn("(fallen)", rigid[7])
        self.assertNotIn("(fallen)", clutch[7])
        self.assertLess(abs(float(clutch[10])), 0.01)
        end_omega = float(clutch[7].rstrip("π"))
        self.assertLess(end_omega, 0.5 * 16.0)  # lagging far behind ω_m = 16π at the end
        rc, out = script("tie_scan.py", "-o", data("x.md"), "--ratio", "1.5", check=False)
        self.assertEqual((rc, "--ratio" in out), (2, True), out)

    def test_table1_scan(self):
        # One point, R = 1 cm and d = 3 cm: Table 1's orbit held at 4π locks; ramped down the
        # bead slides below 4π (it starts stuck inside its cone there); ramped up the lock is lost
        # near the fold of its branch of circular orbits (4.988π, tests/continuation_test), a
        # ramp at 0.1 rad/s² crossing it within a few tenths of π.
        out = data("table1_scan.md")
        script("table1_scan.py", "-o", out, "--radii", "0.01", "--distances", "0.03")
        row = [line for line in open(out) if line.startswith("| 10 | 3 |")]
        self.assertEqual(len(row), 1, open(out).read())
        cells = [c.strip() for c in row[0].strip().strip("|").split("|")]
        self.assertIn("locked", cells[2])
        slide = float(cells[3].split("π")[0])
        lost = float(cells[5].split("π")[0])
        self.assertTrue(3.0 < slide < 4.0, cells)
        self.assertTrue(4.5 < lost < 5.2, cells)
        rc, out = script("table1_scan.py", "-o", data("x.md"), "--set", "drive_radius=0.01", check=False)
        self.assertEqual((rc, "--set" in out), (2, True), out)

    def test_plot_run(self):
        out = data("run.png")
        script("plot_run.py", data("run.h5"), "-o", out, "--size", "8,6", "--dpi", "40")
        ImageChecks().assert_png(out, 320, 240)

    def test_compare_runs(self):
        # The fixture's work-precision CSV under two labels: each label prints the same
        # steps/evaluations at rtol 1e-4 and 1e-6 as the CSV holds, and the cheapest CPU time
        # within 1 m (every ok run reaches it) of each method.
        with open(data("work_precision.csv"), newline="") as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
        _, out = script("compare_runs.py", f"a={data('work_precision.csv')}", f"b={data('work_precision.csv')}",
                        "--rtols", "1e-4,1e-6", "--errors", "1")
        dop = [r for r in rows if r["method"] == "dop853" and r["param_kind"] == "rtol"]
        want = " / ".join(f"{r['steps']}/{r['rhs_evals']}" for r in sorted(dop, key=lambda r: -float(r["param"])))
        lines = [line for line in out.splitlines() if line.strip().startswith(("a ", "b "))]
        self.assertEqual(len(lines), 2 * len({(r["scene"], r["method"]) for r in rows}), out)
        section = out[out.index(", dop853"):]
        self.assertIn(want, section.splitlines()[1], out)
        cpu = min(float(r["cpu_median_s"]) for r in dop if r["status"] == "ok")
        self.assertIn(f"{cpu * 1e3:.2f}", section.splitlines()[1], out)
        for bad, word in (("a", "LABEL=CSV"), (f"a={data('thresholds.csv')}", "not a CSV"),
                          (f"a={data('missing.csv')}", "missing.csv")):
            rc, text = script("compare_runs.py", bad, check=False)
            self.assertEqual((rc, word in text, len(text.strip().splitlines())), (2, True, 1), text)

    def test_plot_matched(self):
        # A constructed astrojax_matched CSV: one scene, one horizon, one method in both
        # families. With the guarantee the cheapest run within 1e-6 m costs 3 ms, without it
        # 2 ms: the cost printed is +50 %. The figure: 5.2 × 3.9 in at 110 dpi.
        path = data("matched.csv")
        head = "scene,horizon_s,method,family,rtol,status,same_final_mode,err_position_m,cpu_min_s,reference_floor_m\n"
        with open(path, "w") as f:
            f.write(head)
            for family, cpu in (("guarantee", 3e-3), ("no guarantee", 2e-3)):
                f.write(f"locked,10,astrojax dop853,{family},1e-8,ok,1,1e-7,{cpu},1e-12\n")
                f.write(f"locked,10,astrojax dop853,{family},1e-4,ok,1,1e-3,{cpu / 3},1e-12\n")
        out = data("matched.png")
        _, text = script("plot_matched.py", path, "-o", out, "--costs", "1e-6")
        self.assertRegex(text, r"locked\s+10 s\s+astrojax dop853\s+1e-06 m:\s+\+50 %")
        ImageChecks().assert_png(out, round(5.2 * 110), round(3.9 * 110))
        rc, text = script("plot_matched.py", data("thresholds.csv"), "-o", out, check=False)
        self.assertEqual((rc, "not a CSV of `astrojax_matched`" in text), (2, True), text)

    def test_scene_state(self):
        # The final state of chain 0 of the tiny hold sweep, turned back by φ = ω_m t about z:
        # a scene's [initial] table (TOML) whose positions keep the stored radii and heights.
        import tomllib
        sweep = ajx.SweepFile(data("hold.h5"))
        _, out = script("scene_state.py", data("hold.h5"), "0")
        table = tomllib.loads(out)["initial"]
        self.assertEqual(table["preset"], "explicit")
        self.assertIn(table["mode"], ("sliding", "bottom_stop", "stuck", "slack"))
        rows = np.nonzero((sweep.task_chain == 0) & (sweep.task_status == 1))[0]
        state = sweep.final_state(rows[np.argmax(sweep.task_t_end[rows])])
        for k, name in enumerate(("r1", "r2", "v1", "v2")):
            stored, printed = state[5 + 3 * k: 8 + 3 * k], np.array(table[name])
            self.assertAlmostEqual(np.hypot(*printed[:2]), np.hypot(*stored[:2]), delta=1e-12)
            self.assertEqual(printed[2], stored[2])
        phi = math.fmod(float(sweep.hold_omega[0]) * state[0], 2 * math.pi)
        turned = math.atan2(table["r1"][1], table["r1"][0]) - math.atan2(state[6], state[5])
        self.assertAlmostEqual(math.remainder(turned + phi, 2 * math.pi), 0.0, delta=1e-9)
        for args, word in (([data("phase.h5"), "0"], "not a hold-mode sweep"), ([data("hold.h5"), "99"], "chain 99"),
                           ([data("run.h5"), "0"], "not a sweep file")):
            rc, text = script("scene_state.py", *args, check=False)
            self.assertEqual((rc, word in text, len(text.strip().splitlines())), (2, True, 1), text)


class flower_onset(unittest.TestCase):
    """analysis/flower_onset.py: the Hopf fit on constructed amplitudes, then the script's
    plumbing and errors on the fixture's files."""

    def test_fit_recovers_the_normal_form(self):
        import flower_onset
        omega = np.arange(12.0, 18.01, 0.5)
        mu = np.maximum(omega - 14.3, 0.0)
        a2 = mu * (4e-3 - 1e-4 * mu)
        # Noise-free: the model is exact, so the fit must return its parameters to the
        # resolution of the golden section (far below 1e-6 on this scale).
        wh, swh, k, q, red = flower_onset.hopf_fit(omega, a2, np.full_like(a2, 1e-6))
        self.assertAlmostEqual(wh, 14.3, delta=1e-6)
        self.assertAlmostEqual(k, 4e-3, delta=1e-8)
        self.assertAlmostEqual(q, -1e-4, delta=1e-8)
        # Gaussian noise of a known σ (seeded): ω_H within 4 σ(ω_H) of the truth, and the
        # reduced χ² of order one (it has 13 − 3 degrees of freedom: 0.1 to 3 holds with
        # probability above 99.5 %).
        rng = np.random.default_rng(7)
        sigma = np.full_like(a2, 2e-4)
        wh, swh, _, _, red = flower_onset.hopf_fit(omega, a2 + rng.normal(0.0, 2e-4, a2.size), sigma)
        self.assertGreater(swh, 0.0)
        self.assertLess(abs(wh - 14.3), 4 * swh)
        self.assertTrue(0.1 < red < 3.0, red)

    def test_short_staircase_through_the_onset(self):
        # The clutch with c_a = 2e-6 N m s (tests/data/flower_staircase.toml, about 5 s): the
        # lagging orbit gives way to a flower that the motor sustains, softly.
        import astrojax_analysis as ajx
        import flower_onset
        h5 = data("flower_staircase.h5")
        run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests/data/flower_staircase.toml"), "-o", h5, "-q"])
        sweep = ajx.Sweep(h5)
        lev = {o: v for o, v in flower_onset.levels(sweep, 0).items() if o >= 12.0}
        cls = {o: {leg: sweep.class_names[sweep.cls[0, w]] for leg, w in v.items()} for o, v in lev.items()}
        for o, legs in cls.items():
            # ω_H = 15.3π for this set (docs/reports/reproduction-evidence.md), and the classifier names the flower once its
            # radius oscillates by several per cent, 0.6-1.2π above ω_H: 16π is still a circle.
            want = "flower" if o >= 17.0 else "lagging-circular"
            for leg, got in legs.items():
                self.assertEqual(got, want, f"{leg} at {o}π")  # the same class up and down: no hysteresis
        # Sustained: a flower decaying at the drag rate would have dE/dt/P_drag ≈ −1; over a
        # 20 s window an orbit the motor feeds stays within m/(2 c_D T) = 0.26 (docs/reports/reproduction-evidence.md, hold
        # verdicts).
        bound = 0.018 / (2 * 1.7245e-3 * 20.0)
        for o, v in lev.items():
            for w in v.values():
                if sweep.class_names[sweep.cls[0, w]] == "flower":
                    r = sweep.stats["energy_rate"][0, w] / sweep.stats["drag_power"][0, w]
                    self.assertLess(abs(r), bound, f"{o}π")
        # The limit cycle grows with the distance from the onset (a² ∝ ω_m − ω_H).
        amp = [flower_onset.amplitude(sweep, 0, lev[o]["up"]) for o in (16.0, 17.0, 18.0, 19.0)]
        self.assertEqual(amp, sorted(amp))
        # The fitted onset lies below the first flower and above the highest level where the
        # up leg stayed on the circle (a below 1e-6 after 120 s: no growth there).
        quiet = max(o for o, v in lev.items() if flower_onset.amplitude(sweep, 0, v["up"]) < 1e-6)
        row = flower_onset.analyse(sweep, 0, 3.0)
        self.assertTrue(quiet < row["omega_H"] < 17.0, (quiet, row["omega_H"]))

    def test_script_on_a_sweep_without_flowers_and_bad_input(self):
        md = data("flower_onset.md")
        script("flower_onset.py", data("phase.h5"), "-o", md)
        with open(md) as f:
            text = f.read()
        self.assertIn("| ω_H ± σ [π] |", text)
        self.assertIn("— ± —", text)  # no flower window: no fit, said so
        rc, out = script("flower_onset.py", data("hold.h5"), "-o", md, check=False)
        self.assertEqual((rc, "a hold sweep has no staircase" in out), (2, True), out)
        rc, out = script("flower_onset.py", data("phase.h5"), "-o", md, "--span", "0", check=False)
        self.assertEqual((rc, "--span 0.0: allowed > 0" in out), (2, True), out)


class rise_climb(unittest.TestCase):
    """analysis/rise_climb.py: each climb's numbers on a constructed trajectory whose answers
    are known in closed form, then the script's plumbing and errors on the fixture's run."""

    def constructed(self):
        """A pair spinning rigidly at ω about the axis, bead and ball on opposite sides at ρ,
        the top at R on the bead's side; off the stop (mode 0) for 0.5 s from t = 1 s while
        L1 falls by 4 mm linearly and rises back, then on the stop again."""
        w, rho, R, m = 39.0, 0.016, 0.015, 0.018
        t = np.arange(0.0, 3.0, 1e-3)
        ang = w * t
        r1 = np.stack([rho * np.cos(ang), rho * np.sin(ang), np.full_like(t, -0.79)], axis=1)
        r2 = np.stack([-rho * np.cos(ang), -rho * np.sin(ang), np.full_like(t, -0.80)], axis=1)
        v1 = np.stack([-w * rho * np.sin(ang), w * rho * np.cos(ang), np.zeros_like(t)], axis=1)
        off = (t > 1.0) & (t < 1.5)
        L1 = 0.791 - np.where(off, 4e-3 * (1.0 - np.abs(t - 1.25) / 0.25), 0.0)
        run = dict(t=t, omega_m=np.full_like(t, w), phi=ang.copy(), L1=L1, mode=np.where(off, 0, 1),
                   r1=r1, r2=r2, v1=v1, v2=-v1, T1=np.full_like(t, 0.35), T2=np.full_like(t, 0.48),
                   psi=np.full_like(t, 1.2), m1=m, m2=m, R=R, motor_work=2e-3 * t, friction_loss=1e-4 * off.cumsum(),
                   energy=np.zeros_like(t), drag_loss=2e-3 * t, impact_loss=np.zeros_like(t))
        return run, dict(w=w, rho=rho, R=R, m=m)

    def test_numbers_of_a_constructed_climb(self):
        import rise_climb
        run, k = self.constructed()
        eps = rise_climb.episodes(run["mode"])
        self.assertEqual(len(eps), 1)
        r = rise_climb.climb_row(run, *eps[0])
        # Exact inputs: every figure below is a closed form, so the tolerances are round-off
        # (1e-12 relative), except the slope fits (polyfit of an exactly linear angle: 1e-9)
        # and the sampled times (one 1 ms sample).
        self.assertAlmostEqual(r["t"], 1.0, delta=1e-3)
        self.assertAlmostEqual(r["mu_star"], np.log(0.48 / 0.35) / 1.2, delta=1e-12)
        self.assertAlmostEqual(r["climb"], 4e-3, delta=4e-3 * 0.01 + 2e-5)  # within 1 % of the top, one sample
        self.assertAlmostEqual(r["t_top"], 0.25, delta=0.25 * 0.01 + 1e-3)
        lz = 2 * k["m"] * k["w"] * k["rho"] ** 2  # two balls on a circle of radius ρ: L_z = Σ m ω ρ²
        self.assertAlmostEqual(r["Lz_before"] / lz, 1.0, delta=1e-12)
        self.assertAlmostEqual(r["Lz_lock"] / lz, 1.0, delta=1e-12)  # rigid spin: locked by construction
        self.assertAlmostEqual(r["torque_needed"], 0.0, delta=1e-12 * lz)
        self.assertAlmostEqual(r["spin_before"] * np.pi / k["w"], 1.0, delta=1e-9)
        self.assertAlmostEqual(r["spin_during"] * np.pi / k["w"], 1.0, delta=1e-9)
        self.assertAlmostEqual(r["lag_before"], 0.0, delta=1e-9)  # the bead on the top's azimuth
        self.assertAlmostEqual(r["torque_motor"], 2e-3 / k["w"], delta=1e-12)
        # The top a = R(cos φ, sin φ, 0) and the bead at ρ on the same azimuth: the horizontal
        # part of the upper segment is ρ − R, its length √((ρ − R)² + 0.79²).
        h = k["rho"] - k["R"]
        self.assertAlmostEqual(r["torque_max"], k["R"] * 0.35 * h / np.hypot(h, 0.79), delta=1e-15)

    def test_pair_couple_of_a_constructed_pair(self):
        """rise_climb.pair_couple recomputes src/physics/pair_couple.cpp: zero for the rigidly
        spinning pair of constructed() (β̇ = ω_m), and for a lower segment at tilt θ spinning at
        β̇ its torque about z is τ_c tanh(w/Ω_ε) sin²θ with w = (ω_m − β̇) sin²θ/(sin²θ + ε²), its
        power that times β̇. Closed forms: round-off tolerances."""
        import rise_climb
        run, k = self.constructed()
        run["couple_torque"], run["couple_slip_rate"] = 1e-3, 1.0
        tau, tz, power = rise_climb.pair_couple(run)
        self.assertLess(np.max(np.abs(tau)), 1e-12)
        theta, spin, L2 = 1.1, 20.0, 0.035
        t = run["t"]
        d2 = L2 * np.stack([np.sin(theta) * np.cos(spin * t), np.sin(theta) * np.sin(spin * t),
                            -np.cos(theta) * np.ones_like(t)], axis=1)
        run["r2"] = run["r1"] + d2
        run["v2"] = run["v1"] + spin * np.stack([-d2[:, 1], d2[:, 0], np.zeros_like(t)], axis=1)
        tau, tz, power = rise_climb.pair_couple(run)
        s2 = np.sin(theta) ** 2
        w = (k["w"] - spin) * s2 / (s2 + rise_climb.COUPLE_TILT_FLOOR ** 2)
        expect = 1e-3 * np.tanh(w)
        np.testing.assert_allclose(tau, expect, rtol=1e-12)
        np.testing.assert_allclose(tz, expect * s2, rtol=1e-12)
        np.testing.assert_allclose(power, expect * s2 * spin, rtol=1e-12)

    def test_script_plumbing_and_bad_input(self):
        md = data("rise_climb.md")
        script("rise_climb.py", data("run.h5"), "-o", md, "--window", "2", "--levels", "2,4")
        with open(md) as f:
            text = f.read()
        self.assertIn("# Climbs off the bottom ball", text)
        self.assertIn("| ω_m [π] | ψ [rad] | T2/T1 | ρ1 [mm] | ρ2 [mm] | μ* |\n|---|---|---|---|---|---|\n| 2 |", text)
        self.assertTrue("| # | t [s] | ω_m [π] | μ* |" in text or "never leaves the bottom ball" in text, text)
        rc, out = script("rise_climb.py", data("run.h5"), "--window", "0", check=False)
        self.assertEqual((rc, "--window" in out), (2, True), out)
        rc, out = script("rise_climb.py", data("run.h5"), "--levels", "a,b", check=False)
        self.assertEqual((rc, "--levels a,b" in out), (2, True), out)
        rc, out = script("rise_climb.py", data("phase.h5"), check=False)
        self.assertEqual((rc, "not a run file" in out), (2, True), out)


class first_half(unittest.TestCase):
    """analysis/first_half.py: the climb's outcome from a chain's class runs, and the script on
    a small grouped sweep over R, d and the ramp rate (sweeps/first_half.toml made short)."""

    def runs(self, *classes):
        """Rising runs of these classes, each ending 1π further up."""
        return [{"direction": "1", "class": k, "omega_to_rad_s": str((i + 1) * np.pi), "windows": "2",
                 "omega_ball_mean_rad_s": str(4.5 * np.pi)} for i, k in enumerate(classes)]

    def test_outcomes(self):
        import first_half
        rise, what, n = first_half.outcome(self.runs("fallen", "not-settled", "locked-circular", "fallen"))
        self.assertAlmostEqual(rise, np.pi)
        self.assertEqual((what, n), ("circular (locked-circular, ω_ball 4.50π)", 2))
        self.assertEqual(first_half.outcome(self.runs("fallen", "not-settled", "fallen"))[1:], ("falls back", 0))
        self.assertEqual(first_half.outcome(self.runs("fallen"))[1], "no climb")
        self.assertEqual(first_half.outcome(self.runs("fallen", "flower"))[1], "ends flower")

    def test_script_on_a_small_grouped_sweep(self):
        h5, md = data("first_half.h5"), data("first_half.md")
        run([ASTROJAX, "sweep", os.path.join(SOURCE, "sweeps/first_half.toml"), "-o", h5, "-q",
             "--set", "grid.drive_radius=[0.02]", "--set", "grid.contact_distance=[0.035]",
             "--set", "grid.ramp_rate=[2.0]"])
        script("first_half.py", h5, "-o", md)
        with open(md) as f:
            text = f.read()
        for label in ("## paper's physics (rigid tie)", "## tie clutch", "| 20 | 3.5 | ", "## Outcomes counted"):
            self.assertIn(label, text)
        rc, out = script("first_half.py", data("hold.h5"), "-o", md, check=False)
        self.assertEqual((rc, "no grid axis" in out), (2, True), out)


class lag_limits(unittest.TestCase):
    """analysis/lag_limits.py: ω_fall(s) and the lag's ceiling from `astrojax orbits --lag`."""

    def test_both_rise_with_the_bead_position(self):
        # The claim of docs/reports/reproduction-evidence.md, "The lag's ceiling": along the string, ω_fall(s) (the stuck
        # family's entry into the cone) and the highest stable lag both grow with s, so the bead
        # position that lowers one lowers the other. Three positions, about 1 s.
        out = data("lag_limits.md")
        script("lag_limits.py", "-o", out, "--s", "0.44:0.56:0.06")
        rows = [cells(l) for l in section(out, "R = 15 mm, d = 3.5 cm") if l.startswith("| 0.")]
        self.assertEqual([r[0] for r in rows], ["0.440", "0.500", "0.560"])
        fall = [float(r[1]) for r in rows]
        ceiling = [float(r[3]) for r in rows]
        self.assertEqual(fall, sorted(fall))
        self.assertEqual(ceiling, sorted(ceiling))
        for f, c in zip(fall, ceiling):
            self.assertLess(f, c)  # the held, stable lag spans ω_fall(s) .. ceiling(s)

    def test_bad_input_names_the_option_and_range(self):
        for args, words in ((["--s", "0.5:0.4:0.1"], ["--s", "LO < HI"]), (["--radii", "0.5"], ["--radii", "0.05"])):
            code, text = script("lag_limits.py", "-o", data("lag_bad.md"), *args, check=False)
            self.assertNotEqual(code, 0)
            for w in words:
                self.assertIn(w, text)
            self.assertFalse(os.path.exists(data("lag_bad.md")))


class lag_paths(unittest.TestCase):
    """analysis/sensitivity.py --paths: the lag reached through ω1 in two ways (levels 0.1π and
    0.2π apart, tests/data/lag_paths_short.toml, about 1.5 s of CPU), the bead's s each leaves,
    and the lag's Hopf point at each s from the continuation."""

    @classmethod
    def setUpClass(cls):
        cls.h5 = data("lag_paths_short.h5")
        if os.path.exists(cls.h5):
            os.remove(cls.h5)
        run([ASTROJAX, "sweep", os.path.join(SOURCE, "tests/data/lag_paths_short.toml"), "-o", cls.h5, "-q"])

    def test_paths_leave_the_bead_at_different_s_and_the_hopf_point_falls_with_s(self):
        out = data("lag_paths.md")
        script("sensitivity.py", "--paths", self.h5, "--lag-omega", "6", "-o", out, "--astrojax", ASTROJAX)
        rows = {r[0]: r for r in (cells(l) for l in section(out, "ω2 over the paths through ω1")) if r[0] in
                ("fine", "coarse")}
        self.assertEqual(sorted(rows), ["coarse", "fine"])
        for r in rows.values():
            self.assertEqual(r[1], "lagging-circular")  # both paths reach the lag
        s = {k: float(r[2]) for k, r in rows.items()}
        ball = {k: float(r[3]) for k, r in rows.items()}
        hopf = {k: float(r[4]) for k, r in rows.items()}
        # The slide at ω1 decides s: the two paths must not leave the bead at the same place to
        # the file's 10 µm (they differ by about 3 mm), or the table measures no spread.
        self.assertGreater(abs(s["coarse"] - s["fine"]), 1e-5)
        # Along the string the stuck lag turns faster further out and loses its stability at a
        # lower ω_m (ω_H = ω_ball,H + (τ_H − τ_k)/c_a with τ_H falling with s): opposite orders.
        lo, hi = sorted(s, key=s.get)
        self.assertLess(ball[lo], ball[hi])
        self.assertGreater(hopf[lo], hopf[hi])

    def test_bad_lag_omega_names_the_option_and_range(self):
        code, text = script("sensitivity.py", "--paths", self.h5, "--lag-omega", "0", "-o", data("lag_bad.md"),
                            "--astrojax", ASTROJAX, check=False)
        self.assertEqual(code, 2)
        self.assertIn("--lag-omega", text)
        self.assertIn("0 < W < 100", text)
        self.assertFalse(os.path.exists(data("lag_bad.md")))


class paper_scheme(ImageChecks):
    """analysis/paper_scheme.py: the paper's scheme against DOP853 from Table 1's starts."""

    def test_lag_ledger_and_figure(self):
        # Two ω_m, 4 s each (well under 1 s of runs): the printed drag injects 2 P_drag
        # (tests/paper_scheme_test.cpp derives it), the corrected scheme closes the ledger.
        out, report = data("paper_lag.png"), data("paper_lag.md")
        script("paper_scheme.py", "lag", "--omegas", "4.8,15", "--duration", "4", "--early", "1",
               "--models", "paper,paper_corrected", "-o", out, "--report", report, "--size", "9,3", "--dpi", "50",
               "--astrojax", ASTROJAX)
        self.assert_png(out, 450, 150)
        rows = [[c.strip() for c in l.split("|")[1:-1]] for l in open(report) if re.match(r"\| (4\.8|15) \|", l)]
        self.assertEqual([(r[0], r[1]) for r in rows],
                         [("4.8", "paper"), ("4.8", "paper_corrected"), ("15", "paper"), ("15", "paper_corrected")])
        for r in rows:
            injection, p_drag = float(r[7]), float(r[8])
            if r[1] == "paper":
                self.assertAlmostEqual(injection / (2 * p_drag), 1.0, delta=0.01)
            else:
                self.assertLess(abs(injection), 1e-4 * p_drag)

    def test_bad_model_named(self):
        rc, out = script("paper_scheme.py", "lag", "--models", "euler", "-o", data("paper_bad.png"), check=False)
        self.assertEqual(rc, 2)
        self.assertIn("--models: 'euler' is not one of paper, paper_corrected, dop853", out)


class fit(unittest.TestCase):
    """analysis/fit_thresholds.py: the fitting core on synthetic thresholds with a known optimum
    and covariance (no astrojax runs), the reading of astrojax's rows, and bad input."""

    A = np.array([[2.0, 0.5], [-1.0, 1.5], [0.3, -2.0]])  # ∂r_k/∂p_j of a linear model
    SIGMA = np.array([0.01, 0.02, 0.05])                  # σ_k of the relative residuals

    def test_covariance_of_a_linear_model(self):
        from astrojax_analysis import fit as ft
        # Full rank, m > n, χ² below m − n: C = (AᵀWA)⁻¹ exactly (the scale S drops out).
        W = np.diag(1 / self.SIGMA**2)
        expected = np.linalg.inv(self.A.T @ W @ self.A)
        C, loose, s, factor = ft.covariance(self.A, self.SIGMA, [0.5, 2.0], chi2=0.3)
        np.testing.assert_allclose(C, expected, rtol=1e-12)
        self.assertEqual((loose, factor), ([], 1.0))
        # χ² = 4 over m − n = 1 degree of freedom scales it by 4.
        C, _, _, factor = ft.covariance(self.A, self.SIGMA, [1.0, 1.0], chi2=4.0)
        self.assertEqual(factor, 4.0)
        np.testing.assert_allclose(C, 4 * expected, rtol=1e-12)
        # m = n: no scaling, whatever χ².
        self.assertEqual(ft.covariance(self.A[:2], self.SIGMA[:2], [1.0, 1.0], chi2=50.0)[3], 1.0)

    def test_a_degenerate_direction_is_reported_not_inverted(self):
        from astrojax_analysis import fit as ft
        # Only p0 + p1 enters: the direction (1, −1)/√2 has singular value 0 and is returned;
        # the pseudo-inverse then gives var(p0) = var(p1) = 1/(2 Σ a_k²/σ_k²) / 2 along (1, 1)/√2.
        a = np.array([1.0, 2.0, 3.0])
        J = np.column_stack([a, a])
        C, loose, s, _ = ft.covariance(J, self.SIGMA, [1.0, 1.0])
        self.assertEqual(len(loose), 1)
        self.assertTrue(math.isinf(loose[0][0]), loose)  # s = 0 to rounding: no constraint at all
        self.assertEqual(ft.direction_text(loose[0][1], ["p0", "p1"]), "+0.71 p0 -0.71 p1")
        var_sum = 1 / np.sum(a**2 / self.SIGMA**2)  # var(p0 + p1) of the one constrained combination
        np.testing.assert_allclose(C, np.full((2, 2), var_sum / 4), rtol=1e-12)
        # A weak but non-zero direction counts as unconstrained once its σ exceeds 100 %.
        J2 = np.column_stack([a, a * (1 + 1e-4)])
        self.assertEqual(len(ft.covariance(J2, self.SIGMA, [1.0, 1.0])[1]), 1)

    def quantised(self, x, x_star, q):
        """Thresholds ω_k = paper_k (1 + r_k), r = A (x − x*) rounded to the resolution q (a
        bracket grid on which the paper's values lie): piecewise constant, zero at x*."""
        r = np.round(self.A @ (np.asarray(x) - x_star) / q) * q
        return 1.0 + r

    def test_nelder_mead_finds_the_cell_of_the_optimum(self):
        from astrojax_analysis import fit as ft
        x_star, q = np.array([0.3, 0.6]), 0.01
        sigma = np.full(3, q / 2)  # the bracket half-width
        f = lambda x: ft.chi2_of((self.quantised(x, x_star, q) - 1.0) / sigma)
        x, fx, n = ft.nelder_mead(f, [0.5, 0.2], [0.15, 0.15], [0, 0], [1, 1], max_evals=300)
        # χ² = 0 only where every |A (x − x*)|_k < q/2: inside the cell around x*.
        self.assertEqual(fx, 0.0)
        self.assertTrue(np.all(np.abs(self.A @ (x - x_star)) <= q / 2 + 1e-12), x)
        self.assertLessEqual(n, 300)
        # The box holds: with the optimum outside it, every point tried lies in the box.
        tried = []
        ft.nelder_mead(lambda x: tried.append(x) or f(x), [0.2, 0.2], [0.05, 0.05], [0, 0], [0.25, 1], max_evals=100)
        self.assertTrue(all(0 <= x[0] <= 0.25 and 0 <= x[1] <= 1 for x in tried))
        # The evaluation budget is a hard limit.
        calls = []
        ft.nelder_mead(lambda x: calls.append(1) or f(x), [0.5, 0.2], [0.15, 0.15], [0, 0], [1, 1], max_evals=7)
        self.assertEqual(len(calls), 7)
        self.assertEqual(ft.nelder_mead(f, [0.5, 0.2], [0.15, 0.15], [0, 0], [1, 1], max_evals=0)[2], 0)

    def test_jacobian_steps_past_the_resolution(self):
        from astrojax_analysis import fit as ft
        # The quantised model through the script's own jacobian(): with steps h = 0.1 |p| the
        # central difference of a rounded line errs by at most q / (2h) per entry (each end
        # off by ≤ q/2), so the covariance matches (AᵀWA)⁻¹ to that relative order.
        x_star, q = np.array([0.3, 0.6]), 1e-4
        names = ["a", "b", "c"]
        paper = {n: 1.0 for n in names}

        class Fake:
            def __init__(self):
                self.names = names

            def many(self, xs, phase):
                out = []
                for x in xs:
                    w = self.omega(x)
                    out.append({"x": np.asarray(x), "meas": {n: (w[k], q / 2, "") for k, n in enumerate(names)}})
                return out

            omega = staticmethod(lambda x: self.quantised(x, x_star, q))

        params = [ft.Param("drive_radius", 0.3, 0.0, 1.0), ft.Param("contact_distance", 0.6, 0.0, 1.0)]
        D, how, h, centre = ft.jacobian(Fake(), params, x_star, 0.1)
        np.testing.assert_allclose(h, 0.1 * x_star)
        self.assertTrue(all(hw == "central" for row in how for hw in row), how)
        err = q / (2 * h)  # the bound of each entry's error
        self.assertTrue(np.all(np.abs(D - self.A) <= err[None, :] + 1e-12), D - self.A)
        sigma = np.full(3, 0.01)
        C, _, _, _ = ft.covariance(D, sigma, np.abs(x_star))
        W = np.diag(1 / sigma**2)
        expected = np.linalg.inv(self.A.T @ W @ self.A)
        np.testing.assert_allclose(C, expected, rtol=50 * np.max(err) / np.min(np.abs(self.A)))
        # Where nothing moves (a flat threshold) the entry is flagged at the resolution and the
        # step is doubled once.
        Fake.omega = staticmethod(lambda x: np.array([1.0, 1.0, 1.0]) + 0 * x[0])
        D, how, h, _ = ft.jacobian(Fake(), params, x_star, 0.1)
        np.testing.assert_allclose(h, 0.2 * x_star)
        self.assertTrue(np.all(D == 0) and all("within a bracket" in hw for row in how for hw in row))
        d, how = ft.derivative(np.nan, 2.0, 1.0, 1.1, 0.9, 1.0)
        self.assertEqual(how, "backward")
        self.assertAlmostEqual(d, -10.0, places=12)
        self.assertTrue(math.isnan(ft.derivative(np.nan, np.nan, 1.0, 1.1, 0.9, 1.0)[0]))
        # A jump on one side (one-sided differences 2 and 0 against a resolution of 0.1): the
        # slope of the side without it; within twice the resolution: the central difference.
        self.assertEqual(ft.derivative(3.0, 1.0, 1.0, 1.1, 0.9, 1.0, 0.1), (0.0, "jump above: backward"))
        d, how = ft.derivative(1.15, 1.0, 1.0, 1.1, 0.9, 1.0, 0.1)
        self.assertEqual(how, "central")
        self.assertAlmostEqual(d, 0.75, places=12)

    def test_omega_2_only_where_a_lag_ends(self):
        from astrojax_analysis import fit as ft
        # An ω2 bracket whose lower window lies in the locked run (no lag before the flower) is
        # not the paper's lag → flower: not reached, with the reason; in a lagging run it counts.
        pi = math.pi
        row = lambda name, a, b: {"chain": "0", "threshold": name, "before_rad_s": repr(a), "after_rad_s": repr(b)}
        run = lambda cls, a, b: {"kind": "run", "direction": "1", "class": cls, "omega_from_rad_s": repr(a),
                                 "omega_to_rad_s": repr(b), "windows": "3", "omega_ball_mean_rad_s": repr(4.2 * pi)}
        up_rows = [row("omega_1", 4.72 * pi, 4.88 * pi), row("omega_2", 4.72 * pi, 4.88 * pi)]
        seq = [run("locked-circular", 4 * pi, 4.8 * pi), run("not-settled", 4.8 * pi, 4.96 * pi),
               run("lagging-circular", 4.96 * pi, 18 * pi)]
        res = {"rise": ([row("omega_rise", 12.25 * pi, 12.57 * pi)], []), "up": (up_rows, seq),
               "down": ([row("omega_fall", 3.5 * pi, 3.0 * pi)], [])}
        m = ft.measure(res, 0.02)
        self.assertTrue(math.isnan(m["omega_2"][0]))
        self.assertIn("the lag survives to the ramp's top, 18.00π", m["omega_2"][2])
        self.assertAlmostEqual(m["omega_1"][0], 4.80 * pi)
        self.assertAlmostEqual(m["omega_fall"][1], 0.25 * pi)  # half-width of a falling bracket
        self.assertAlmostEqual(m["plateau"][0], 4.2 * pi)
        w, rel, sig, flags = ft.residuals(m, ["omega_1", "omega_2"], "penalty", 100.0)
        self.assertEqual((w[1], flags[0]), (100.0, ""))
        self.assertIn("penalty 100 σ", flags[1])
        w, rel, sig, flags = ft.residuals(m, ["omega_1", "omega_2"], "exclude", 100.0)
        self.assertEqual((len(w), "excluded" in flags[1]), (1, True))
        seq[-1] = run("lagging-circular", 4.96 * pi, 15.0 * pi)
        seq.append(run("flower", 15.0 * pi, 18 * pi))
        up_rows[1] = row("omega_2", 14.92 * pi, 15.08 * pi)
        m = ft.measure(res, 0.02)
        self.assertAlmostEqual(m["omega_2"][0], 15.0 * pi)

    def test_a_bracket_over_unsettled_windows_weighs_as_one_step(self):
        from astrojax_analysis import fit as ft
        # ω_fall between a lagging window at 4.0π and the first fallen one at 3.0π, with four
        # not-settled windows at 3.8–3.2π in between (0.2π apart): σ is half the window
        # spacing, 0.1π, not the bracket's half-width 0.5π, so the same miss costs 25× more χ².
        pi = math.pi
        row = lambda name, a, b: {"chain": "0", "threshold": name, "before_rad_s": repr(a), "after_rad_s": repr(b)}
        run = lambda d, cls, a, b, n: {"kind": "run", "chain": "0", "direction": str(d), "class": cls,
                                       "omega_from_rad_s": repr(a), "omega_to_rad_s": repr(b), "windows": str(n),
                                       "omega_ball_mean_rad_s": repr(4.2 * pi)}
        down_seq = [run(-1, "lagging-circular", 4.4 * pi, 4.0 * pi, 3), run(-1, "not-settled", 3.8 * pi, 3.2 * pi, 4),
                    run(-1, "fallen", 3.0 * pi, 2.0 * pi, 6), run(1, "not-settled", 3.4 * pi, 3.6 * pi, 2)]
        self.assertEqual(ft.windows_inside(down_seq, 4.0 * pi, 3.0 * pi, -1), 4)  # the up leg's 2 do not count
        self.assertEqual(ft.windows_inside(down_seq, 4.0 * pi, 3.0 * pi, 1), 2)
        mid, sigma, before, hw = ft.bracket([row("omega_fall", 4.0 * pi, 3.0 * pi)], "omega_fall", down_seq, -1)
        self.assertAlmostEqual(mid, 3.5 * pi)
        self.assertAlmostEqual(hw, 0.5 * pi)
        self.assertAlmostEqual(sigma, 0.1 * pi)
        # A clean bracket between adjacent windows keeps σ = its half-width.
        clean = ft.bracket([row("omega_fall", 3.2 * pi, 3.0 * pi)], "omega_fall", down_seq, -1)
        self.assertAlmostEqual(clean[1], 0.1 * pi)
        res = {"rise": ([row("omega_rise", 12.5 * pi, 12.7 * pi)], []), "up": ([row("omega_1", 4.7 * pi, 4.9 * pi)], []),
               "down": ([row("omega_fall", 4.0 * pi, 3.0 * pi)], down_seq)}
        m = ft.measure(res, 0.02)
        self.assertAlmostEqual(m["omega_fall"][1], 0.1 * pi)
        self.assertAlmostEqual(m["omega_fall"][3], 0.5 * pi)
        w, rel, sig, _ = ft.residuals(m, ["omega_fall"], "penalty", 100.0)
        self.assertAlmostEqual(sig[0], 0.1 / 3.24)
        self.assertAlmostEqual(w[0], (3.5 - 3.24) / 0.1)  # (ω − paper)/σ: 2.6 σ, not 0.52

    def test_a_sweep_with_failed_tasks_is_kept_and_flagged(self):
        import tempfile
        from astrojax_analysis import fit as ft
        # A stand-in for astrojax: `sweep` exits 3 (some tasks failed) with its reason on
        # stderr, `thresholds` writes one ω1 row and an empty sequence. The sweep's rows are
        # kept and the note carries the reason; any other exit code stops with code 2.
        with tempfile.TemporaryDirectory() as tmp:
            fake = os.path.join(tmp, "astrojax")
            with open(fake, "w") as f:
                f.write("""#!/bin/sh
if [ "$1" = sweep ]; then echo "failed: task 6: event bound hit" >&2; exit ${FAKE_SWEEP_EXIT:-3}; fi
while [ $# -gt 0 ]; do
  case "$1" in
    --csv) printf 'chain,parameters,threshold,before_rad_s,after_rad_s,mid_rad_s,paper_rad_s,relative_difference\\n0,,omega_1,14.8,15.3,15.05,15.08,0\\n' > "$2";;
    --sequence-csv) printf 'chain,parameters,kind,leg,direction,class,omega_from_rad_s,omega_to_rad_s,windows,blips,omega_ball_mean_rad_s,omega_ball_slope,step,status,step_description\\n' > "$2";;
  esac; shift
done
""")
            os.chmod(fake, 0o755)
            rows, seq, note = ft.run_sweep(fake, os.path.join(tmp, "up.toml"), os.path.join(tmp, "o.h5"), {}, "clutch", 0)
            self.assertEqual((rows[0]["threshold"], seq), ("omega_1", []))
            self.assertIn("up sweep: some tasks failed (failed: task 6: event bound hit)", note)
            code = ("import os, sys; sys.path.insert(0, %r); from astrojax_analysis import fit as ft; "
                    "ft.run_sweep(%r, 'up.toml', 'o.h5', {}, 'clutch', 0)" % (ANALYSIS, fake))
            p = subprocess.run([PYTHON, "-c", code], capture_output=True, text=True,
                               env=dict(os.environ, FAKE_SWEEP_EXIT="1"))
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("exited with 1", p.stderr)

    def test_protocol_copies(self):
        import tempfile
        from astrojax_analysis import fit as ft
        with tempfile.TemporaryDirectory() as tmp:
            files, _ = ft.rise_file(os.path.join(SOURCE, "sweeps/paper_ramps.toml"), tmp)
            files.update(ft.ramp_files(os.path.join(SOURCE, "sweeps/table1.toml"), 18 * math.pi, tmp)[0])
            docs = {k: ft.load_toml(v, k) for k, v in files.items()}
        t1 = ft.load_toml(os.path.join(SOURCE, "sweeps/table1.toml"), "table1")
        self.assertEqual([s["kind"] for s in docs["rise"]["protocol"]["segment"]], ["ramp"])
        self.assertEqual(docs["up"]["protocol"]["segment"][1]["to"], 18 * math.pi)
        down = docs["down"]["protocol"]["segment"][1]
        self.assertEqual((down["from"], down["to"]), (4 * math.pi, t1["protocol"]["segment"][2]["to"]))
        self.assertEqual(docs["up"]["model"], t1["model"])
        self.assertEqual(docs["up"]["protocol"]["segment"][0], t1["protocol"]["segment"][0])

    def test_staircase_copy(self):
        # --protocol holds: the staircase without its grid (each evaluation sets its one chain),
        # its steps unchanged, and no ramp copies beside it.
        import tempfile
        from astrojax_analysis import fit as ft
        stair = os.path.join(SOURCE, "sweeps/table1_staircase.toml")
        with tempfile.TemporaryDirectory() as tmp:
            files, how = ft.staircase_file(stair, tmp)
            self.assertEqual(sorted(files), ["held"])
            self.assertEqual(sorted(os.listdir(tmp)), ["held.toml"])
            held = ft.load_toml(files["held"], "held")
        shipped = ft.load_toml(stair, "staircase")
        self.assertNotIn("grid", held)
        self.assertEqual(held["protocol"], shipped["protocol"])
        self.assertEqual(held["model"], shipped["model"])
        self.assertIn("levels up and down", how["held"])
        rc, out = script("fit_thresholds.py", "-o", os.path.join(DATA, "fit.md"), "--protocol", "holds",
                         "--staircase-sweep", os.path.join(SOURCE, "sweeps/table1.toml"), check=False)
        self.assertEqual(rc, 2, out)
        self.assertIn("expected ['steps', 'steps', 'steps'] first", out)

    def test_bad_input_named(self):
        cases = [
            (["--param", "bogus=1:0:2"], "unknown model key 'bogus'; allowed: string_length"),
            (["--param", "drive_radius=0.01:0.02:0.005"], "lo = 0.02 > hi = 0.005"),
            (["--param", "drive_radius=0.03:0.005:0.02"], "start 0.03 outside its bounds [0.005, 0.02]"),
            (["--param", "contact_distance=0.03:0:0.05"], "lo = 0 outside the allowed range of model.contact_distance: (0, inf)"),
            (["--param", "top_stop=0.05"], "give bounds for top_stop"),
            (["--params", "drive_radius,mass"], "--params: unknown 'mass'"),
            (["--fixed", "tie_damping=-1"], "--fixed 'tie_damping=-1': -1 outside the allowed range"),
            (["--params", "tie_damping", "--fixed", "tie_damping=1e-5"], "also fitted"),
            (["--params", "tie_kinetic_torque", "--fixed", "tie_static_torque=1e-3"],
             "tie_kinetic_torque 0.00135 > tie_static_torque 0.001"),
            (["--max-evals", "-1"], "--max-evals -1: allowed 0..10000"),
            (["--top", "3"], "--top 3: allowed (4, 40]"),
        ]
        for extra, message in cases:
            rc, out = script("fit_thresholds.py", "-o", os.path.join(DATA, "fit.md"), *extra, check=False)
            self.assertEqual(rc, 2, (extra, out))
            self.assertIn(message, out, extra)
        rc, out = script("fit_thresholds.py", "--help")
        self.assertEqual(rc, 0)
        self.assertIn("-o OUTPUT", out)


class out_of_sample(unittest.TestCase):
    """analysis/out_of_sample.py: its score, the fall protocol it builds, the settings it passes
    and its input errors; no runs."""

    def test_score(self):
        import out_of_sample as oos
        PI = math.pi
        # +10 % on ω_rise, −5 % on ω1, exact ω2 and ω_fall: J = 0.1² + 0.05².
        meas = {"omega_rise": (1.1 * 12.63 * PI, 0, ""), "omega_1": (0.95 * 4.80 * PI, 0, ""),
                "omega_2": (15.00 * PI, 0, ""), "omega_fall": (3.24 * PI, 0, "")}
        self.assertAlmostEqual(oos.score(meas, 1.0), 0.0125, places=12)
        # Not reached: penalty² each.
        meas["omega_2"] = (np.nan, np.nan, "not reached")
        self.assertAlmostEqual(oos.score(meas, 2.0), 0.0125 + 4.0, places=12)

    def test_fall_file_and_settings(self):
        import tempfile
        import tomllib
        from astrojax_analysis import fit as ft
        import out_of_sample as oos
        with tempfile.TemporaryDirectory() as tmp:
            with open(oos.fall_file(tmp), "rb") as f:
                doc = tomllib.load(f)
        hold, down = doc["protocol"]["segment"]
        self.assertNotIn("grid", doc)
        self.assertEqual((hold["from"], hold["to"], hold["num"]), (4 * math.pi, 4 * math.pi, 1))
        self.assertAlmostEqual(down["from"], 3.9 * math.pi, places=12)
        self.assertAlmostEqual(down["to"], 2.5 * math.pi, places=12)
        self.assertEqual(down["num"], 15)  # 3.9π … 2.5π in steps of 0.1π
        self.assertEqual(ft.overrides({"drive_radius": 0.01, "couple_torque": 1e-3}, "rigid",
                                      ["layers.pair_couple=motor_clutch"]),
                         ["--set", "layers.tie=rigid", "--set", "layers.pair_couple=motor_clutch",
                          "--set", "grid.drive_radius=[0.01]", "--set", "model.couple_torque=0.001"])

    def test_bad_input(self):
        for extra, message in ((["--variants", "rigid,bogus"], "--variants: unknown 'bogus'"),
                               (["--max-evals", "0"], "--max-evals 0: allowed 1..1000"),
                               (["--penalty", "0"], "--penalty 0: allowed (0, 100]")):
            rc, out = script("out_of_sample.py", "-o", os.path.join(DATA, "oos.md"), *extra, check=False)
            self.assertEqual(rc, 2, (extra, out))
            self.assertIn(message, out, extra)


if __name__ == "__main__":
    if sys.argv[4] == "make":
        make()
    else:
        unittest.main(argv=[sys.argv[0], "-v", *sys.argv[4:]])
