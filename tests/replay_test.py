#!/usr/bin/python3
"""astrojax replay reproduces stored windows, and refuses bad input leaving nothing behind.

A sweep is run (tests/data/replay_three_orbits.toml: a locked, a lagging and a flower window of
the main job's tie clutch in one short chain; with --main, the main job sweeps/paper.toml itself
and its clutch `up` chain); for one window of each of the three classes, `astrojax replay`
must
- exit 0 and report the stored class and ω_ball back (/replay: same class; ω_ball equal to
  1e-6 relative, what the float32 samples the classifier reads resolve);
- write dense samples (--sample-rate 200, four per stored sample) over the window that pass
  through the stored samples: at every stored sample time the dense r1 and r2 equal the stored
  ones to 1e-6 m (the stored values are float32, 3e-8 m at 0.6 m; the dense output's own error
  at rtol 1e-9 is far smaller), so the run file holds the very orbit the sweep classified;
- close the energy ledger over the dense samples: the motor's work at its rod = ΔE + drag +
  friction + impact losses + the clutch's loss + the tie's Δ kinetic energy, to 1e-6 of the
  motor's work; the lagging window's clutch slips (its loss grows).
Older formats the reader accepts replay too: the short chain's file rewritten as format 3 (no
motor's ledger in /tasks/final_state, no string_power or clutch_power) and as format 2 (joined
strings, no /classes) reproduces the same three windows, and its run file reads in
astrojax_analysis.read_motion (the ledger finite: it counts from the task's start); the holds
of `astrojax thresholds` on the format 3 file give format 4's verdicts.
Bad input exits 2 with the file and the problem named and no output: a window or chain out of
range, a file without samples, an existing output without --force, a missing file.

usage: replay_test.py ASTROJAX SOURCE_DIR WORK_DIR [--main]
"""
import csv
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

failures = []


def check(what, ok):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def run(*cmd):
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True)


def windows_of(exe, h5, work):
    out = os.path.join(work, "windows.csv")
    p = run(exe, "windows", h5, "-o", out, "--force")
    check("astrojax windows exits 0", p.returncode == 0)
    with open(out, newline="") as f:
        return list(csv.DictReader(f))


def pick(rows, cls, chain=None):
    """The middle window of class `cls` (on `chain`, when given)."""
    found = [r for r in rows if r["class"] == cls and (chain is None or int(r["chain"]) == chain)]
    return found[len(found) // 2] if found else None


def check_replay(exe, h5, row, work):
    c, k, cls = int(row["chain"]), int(row["window"]), row["class"]
    out = os.path.join(work, f"replay_{c}_{k}.h5")
    p = run(exe, "replay", h5, "--chain", c, "--window", k, "-o", out, "--sample-rate", 200, "--force")
    print(p.stdout.strip())
    check(f"{cls} window {k} of chain {c}: exit 0 ({p.returncode}: {p.stderr.strip()})", p.returncode == 0)
    if p.returncode != 0:
        return
    with h5py.File(out, "r") as f, h5py.File(h5, "r") as s:
        rp = f["replay"]
        stored, replayed = rp["stored"].attrs, rp["replayed"].attrs
        check(f"{cls}: /replay says reproduced", int(rp.attrs["reproduced"]) == 1)
        check(f"{cls}: the stored class is the file's", int(stored["class"]) == int(s["windows/class"][c, k]))
        check(f"{cls}: replayed class {replayed['class_name']} = stored {stored['class_name']}",
              int(replayed["class"]) == int(stored["class"]) and str(replayed["class_name"]) == cls)
        wb_s, wb_r = float(s["windows/omega_ball"][c, k]), float(replayed["omega_ball"])
        check(f"{cls}: ω_ball {wb_r!r} = stored {wb_s!r} to 1e-6",
              (np.isnan(wb_s) and np.isnan(wb_r)) or abs(wb_r - wb_s) <= 1e-6 * max(1.0, abs(wb_s)))
        tr = f["trajectory"]
        t = tr["t"][:]
        n = int(s["samples/count"][c, k])
        ts = s["samples/t"][c, k, :n]
        check(f"{cls}: dense samples span the window ({t[0]:.3f}..{t[-1]:.3f} s)",
              abs(t[0] - s["windows/t_begin"][c, k]) < 0.006 and abs(t[-1] - s["windows/t_end"][c, k]) < 0.006)
        check(f"{cls}: 200 Hz samples", abs(np.median(np.diff(t)) - 0.005) < 1e-9)
        at = np.searchsorted(t, ts - 1e-7)
        hit = (at < len(t)) & (np.abs(t[np.minimum(at, len(t) - 1)] - ts) < 1e-7)
        check(f"{cls}: every stored sample time is a dense sample time ({hit.sum()} of {n})", hit.all())
        for name in ("r1", "r2"):
            dense, kept = tr[name][:][at[hit]], s[f"samples/{name}"][c, k, :n][hit]
            err = float(np.abs(dense - kept).max())
            check(f"{cls}: dense {name} through the stored samples (max |Δ| {err:.2e} m <= 1e-6)", err <= 1e-6)
        e = tr["energy"][:]
        work_ = tr["motor_work"][:] - tr["motor_work"][0]
        losses = sum(tr[x][:] - tr[x][0] for x in ("drag_loss", "friction_loss", "impact_loss", "clutch_loss",
                                                     "tie_energy"))
        resid = float(np.abs(work_ - (e - e[0]) - losses).max())
        scale = max(float(np.abs(work_).max()), 1e-12)
        check(f"{cls}: energy ledger closed over the dense samples ({resid / scale:.1e} of the motor's work)",
              resid <= 1e-6 * scale)
        if cls == "lagging-circular":
            loss = tr["clutch_loss"][:]
            check(f"{cls}: the tie slips (the clutch's loss grows by {loss[-1] - loss[0]:.3g} J)", loss[-1] > loss[0])


def as_format_3(source, path):
    """`source` (format 4) as format 3 wrote it: /tasks/final_state without the motor's ledger
    (its last two columns), /windows without string_power and clutch_power."""
    shutil.copyfile(source, path)
    with h5py.File(path, "r+") as f:
        old = f["tasks/final_state"]
        data, attrs = old[:, :-2], dict(old.attrs)
        del f["tasks/final_state"]
        new = f["tasks"].create_dataset("final_state", data=data)
        for k, v in attrs.items():
            new.attrs[k] = v[:-2] if k == "columns" and len(v) == data.shape[1] + 2 else v
        for name in ("string_power", "clutch_power"):
            del f["windows/" + name]
        f.attrs["format_version"] = np.int64(3)
    return path


def check_older_formats(exe, src, h5, rows, work):
    sys.path.insert(0, os.path.join(src, "tests", "damaged"))
    sys.path.insert(0, os.path.join(src, "analysis"))
    import astrojax_analysis as ajx
    import make_corpus
    f3 = as_format_3(h5, os.path.join(work, "format3.h5"))
    f2 = make_corpus.as_format_2(f3, os.path.join(work, "format2.h5"))
    for version, path in ((3, f3), (2, f2)):
        for cls in ("locked-circular", "lagging-circular", "flower"):
            row = pick(rows, cls)
            c, k = int(row["chain"]), int(row["window"])
            out = os.path.join(work, f"replay_f{version}_{k}.h5")
            p = run(exe, "replay", path, "--chain", c, "--window", k, "-o", out, "--force")
            check(f"format {version}, {cls} window {k}: reproduced, exit 0 ({p.returncode}: {p.stderr.strip()})",
                  p.returncode == 0 and "reproduced: same class" in p.stdout)
            if p.returncode == 0:
                try:
                    motion = ajx.read_motion(out)
                    ok = all(np.isfinite(motion[n]).all() for n in ("motor_work", "clutch_loss", "string_work"))
                except ajx.SweepFileError as e:
                    ok = False
                    print(e)
                check(f"format {version}, {cls}: the run file reads, its ledger finite", ok)
    # The holds of `astrojax thresholds` restart from /tasks/final_state too: on the file without
    # the ledger they reach the verdicts they reach on the file with it (a tie's W_m, W_c start at 0).
    verdicts = {}
    for tag, path in (("4", h5), ("3", f3)):
        out = os.path.join(work, f"thresholds_f{tag}.csv")
        p = run(exe, "thresholds", path, "--csv", out, "--hold", "20")
        with open(out, newline="") as f:
            verdicts[tag] = [(r["chain"], r["threshold"], r["verdict"]) for r in csv.DictReader(f)] if p.returncode == 0 else None
    check(f"format 3: the holds' verdicts are format 4's ({verdicts['3']} against {verdicts['4']})",
          verdicts["4"] and verdicts["3"] == verdicts["4"] and all(v != "undecided" for _, _, v in verdicts["4"]))


def check_bad_input(exe, h5, work, rows):
    row = rows[0]
    c = int(row["chain"])
    out = os.path.join(work, "bad.h5")
    n_windows = sum(1 for r in rows if int(r["chain"]) == c)

    def refused(name, args, needles, target=out):
        p = run(exe, "replay", *args, "-o", target)
        msg = p.stderr.strip()
        check(f"{name}: exit 2 ({p.returncode})", p.returncode == 2)
        for needle in needles:
            check(f"{name}: message names {needle!r} ({msg})", needle in msg)
        check(f"{name}: no traceback or HDF5 stack", "HDF5-DIAG" not in msg and "Traceback" not in msg)
        check(f"{name}: nothing written", not os.path.exists(out) and not any(
            x.startswith("bad.h5") for x in os.listdir(work)))

    refused("window out of range", [h5, "--chain", c, "--window", 10000], [h5, "--window 10000", "outside"])
    refused("negative window", [h5, "--chain", c, "--window", -1], [h5, "--window -1"])
    refused("chain out of range", [h5, "--chain", 99, "--window", 0], [h5, "--chain 99", "outside"])
    refused("missing file", [os.path.join(work, "nope.h5"), "--chain", 0, "--window", 0], ["nope.h5", "no such file"])
    bare = os.path.join(work, "no_samples.h5")
    shutil.copy(h5, bare)
    with h5py.File(bare, "a") as f:
        del f["samples"]
    refused("file without samples", [bare, "--chain", c, "--window", 0], [bare, "/samples", "no samples"])
    exists = os.path.join(work, "exists.h5")
    open(exists, "w").write("keep me")
    p = run(exe, "replay", h5, "--chain", c, "--window", 0, "-o", exists)
    check(f"existing output: exit 2 naming it ({p.stderr.strip()})", p.returncode == 2 and "exists.h5" in p.stderr)
    check("existing output: left as it was", open(exists).read() == "keep me")
    p = run(exe, "replay", h5, "--chain", c, "--window", 0, "-o", exists, "--force")
    check("existing output with --force: replaced", p.returncode == 0 and h5py.is_hdf5(exists))


def main():
    exe, src, work = sys.argv[1:4]
    main_job = "--main" in sys.argv[4:]
    os.makedirs(work, exist_ok=True)
    h5 = os.path.join(work, "paper.h5" if main_job else "three_orbits.h5")
    toml = os.path.join(src, "sweeps", "paper.toml") if main_job else \
        os.path.join(src, "tests", "data", "replay_three_orbits.toml")
    p = run(exe, "sweep", toml, "-o", h5, "--force", "-q")
    check(f"sweep {os.path.basename(toml)} exits 0 ({p.stderr.strip()})", p.returncode == 0)
    rows = windows_of(exe, h5, work)
    chain = None
    if main_job:  # the clutch's `up` chain: locked, lagging and flower on one leg
        chain = next(int(r["chain"]) for r in rows if r["group"] == "up" and r["variant"] == "clutch")
    for cls in ("locked-circular", "lagging-circular", "flower"):
        row = pick(rows, cls, chain)
        check(f"the sweep has a {cls} window", row is not None)
        if row:
            check_replay(exe, h5, row, work)
    check("astrojax windows: every reclassified class is the stored one", all(r["reclassified_class"] == "same"
                                                                              for r in rows))
    check("astrojax windows: every window has a reason", all(r["reason"] for r in rows))
    if not main_job:
        check_older_formats(exe, src, h5, rows, work)
        check_bad_input(exe, h5, work, rows)
    print(f"{len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
