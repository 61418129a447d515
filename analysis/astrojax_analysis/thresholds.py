"""The thresholds, from astrojax itself: `astrojax thresholds FILE --csv OUT` is the one place
where thresholds are found (src/sweep/thresholds.cpp); the scripts never find them themselves.
Also the astrojax executable and the CSVs it writes."""
import csv
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

from .errors import fail
from .paths import REPOSITORY


def find_astrojax(explicit=None):
    """The astrojax executable: --astrojax, else $ASTROJAX, else build/astrojax of this
    checkout, else astrojax on PATH; None if none exists. A path the user named (--astrojax or
    $ASTROJAX) that is not an executable file is an error, never passed over for another."""
    for name, named in (("--astrojax", explicit), ("$ASTROJAX", os.environ.get("ASTROJAX"))):
        if named:
            if os.path.isfile(named) and os.access(named, os.X_OK):
                return named
            fail(f"{name}: {named} is not an executable file")
    for candidate in (os.path.join(REPOSITORY, "build", "astrojax"), shutil.which("astrojax")):
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
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, errors="backslashreplace")
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
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        fail(f"{path}: cannot read: {e}")
    if rows and not need <= set(rows[0]):
        fail(f"{path}: not a CSV of `{what}` (columns {sorted(need - set(rows[0]))} missing)")
    return rows


def read_thresholds_csv(path):
    """The rows of `astrojax thresholds --csv`."""
    rows = read_astrojax_csv(path, {"chain", "threshold", "before_rad_s", "after_rad_s", "mid_rad_s", "paper_rad_s",
                                    "relative_difference"}, "astrojax thresholds")
    for i, row in enumerate(rows):
        try:
            int(row["chain"])
            [number(row[k]) for k in ("before_rad_s", "after_rad_s", "mid_rad_s", "paper_rad_s")]
        except (TypeError, ValueError):
            fail(f"{path}: row {i + 2}: not a row of `astrojax thresholds --csv` (a chain index and numbers)")
    return rows


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
