#!/usr/bin/python3
"""Windows that stop once their orbit is known change no class and no threshold.

Each sweep file given is run twice: with its settling stopped once the orbit is seen to converge
at a rate that holds to a fixed point or a periodic orbit of the frame turning with the top (the
default, sim/settle_watch.hpp) and with every settle at
its full length (`--set protocol.early_stop=false`, or `hold.early_stop=false`; or, with
--baseline, another build of the program, e.g. main's, which has no early stop). Asserted, per
file: the same class in every window of every chain (the class sequence), and the same
`astrojax thresholds --csv` brackets (chain, threshold, the levels before and after, its
verdict; against a baseline, whose file may be of an older format, without the verdict). Printed: the CPU seconds (user + sys) of both runs and their ratio, and the settling
seconds the early stop skipped (the sweep's summary line and /provenance). The ratio is
printed, never asserted: speed is a benchmark's (tests/bench/early_stop.sh), not a test's.

usage: early_stop_test.py ASTROJAX SOURCE_DIR WORK_DIR SWEEP.toml... [--baseline ASTROJAX_WITHOUT]
"""
import csv
import os
import resource
import subprocess
import sys
import time
import tomllib

import h5py
import numpy as np

# The columns of `astrojax thresholds --csv` that state a threshold: which chain and which
# threshold, where it was crossed (the levels on either side, in the order met) and the verdict.
# Fitted numbers (a Hopf point from the windows' amplitudes) move with the measured features
# within their own errors and are not part of a threshold's identity.
BRACKET = ("chain", "threshold", "before_rad_s", "after_rad_s", "verdict")

failures = []


def check(what, ok):
    print(f"{'ok  ' if ok else 'FAIL'} {what}", flush=True)
    if not ok:
        failures.append(what)


def cpu_of(cmd):
    """Runs cmd; returns (CPU seconds of the child, user + sys; its stdout)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def stop_key(path, on):
    with open(path, "rb") as f:
        root = tomllib.load(f)
    return f"{'hold' if 'hold' in root else 'protocol'}.early_stop={'true' if on else 'false'}"


def thresholds(exe, h5, work, tag, holds=True):
    csv_path = os.path.join(work, f"{tag}_thresholds.csv")
    subprocess.run([exe, "thresholds", h5, "--csv", csv_path] + ([] if holds else ["--no-hold"]),
                   check=True, capture_output=True)
    with open(csv_path, newline="") as f:
        return [tuple(r.get(k, "") for k in (BRACKET if holds else BRACKET[:-1])) for r in csv.DictReader(f)]


def compare(exe, src, work, sweep, baseline):
    name = os.path.splitext(os.path.basename(sweep))[0]
    path = os.path.join(src, sweep)
    runs = {}
    for tag, cmd in (("early", [exe, "--set", stop_key(path, True)]),
                     ("full", [baseline] if baseline else [exe, "--set", stop_key(path, False)])):
        h5 = os.path.join(work, f"{name}_{tag}.h5")
        cmd = [cmd[0], "sweep", path, "-o", h5, "--force", "-q"] + cmd[1:]
        t0 = time.monotonic()
        cpu, out = cpu_of(cmd)
        runs[tag] = dict(h5=h5, cpu=cpu, wall=time.monotonic() - t0, line=out.strip().splitlines()[-1])
    with h5py.File(runs["early"]["h5"], "r") as a, h5py.File(runs["full"]["h5"], "r") as b:
        ca, cb = a["windows/class"][...], b["windows/class"][...]
        skipped = float(a["provenance"].attrs.get("settle_seconds_skipped", 0.0))
        windows = int((ca >= 0).sum())
    differ = int((ca != cb).sum()) if ca.shape == cb.shape else -1
    check(f"{sweep}: the class of all {windows} windows the same with and without the early stop (differing: {differ})",
          differ == 0)
    # A baseline build's file may be of an older format (its final states without the motor's
    # ledger, which the holds restart from): against it, the brackets without the hold verdicts.
    holds = baseline is None
    ta = thresholds(exe, runs["early"]["h5"], work, name + "_early", holds)
    tb = thresholds(exe, runs["full"]["h5"], work, name + "_full", holds)
    check(f"{sweep}: the same {len(tb)} thresholds (chain, threshold, bracket{', verdict' if holds else ''})", ta == tb)
    if ta != tb:
        for x, y in zip(ta, tb):
            if x != y:
                print(f"     early {x}\n     full  {y}")
    ratio = runs["early"]["cpu"] / runs["full"]["cpu"] if runs["full"]["cpu"] > 0 else float("nan")
    print(f"     CPU {runs['early']['cpu']:.2f} s with, {runs['full']['cpu']:.2f} s without: ratio {ratio:.2f}; "
          f"{skipped:.0f} s of settling skipped\n     {runs['early']['line']}", flush=True)
    return ratio


def main():
    args = sys.argv[1:]
    baseline = None
    if "--baseline" in args:
        i = args.index("--baseline")
        baseline = args[i + 1]
        del args[i:i + 2]
    exe, src, work, *sweeps = args
    os.makedirs(work, exist_ok=True)
    for s in sweeps:
        compare(exe, src, work, s, baseline)
    if failures:
        print(f"{len(failures)} failed")
        sys.exit(1)


if __name__ == "__main__":
    main()
