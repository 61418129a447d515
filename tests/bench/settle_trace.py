#!/usr/bin/python3
"""Summarises the settle trace of tests/bench/settle_trace.sh: per chain, the runs of consecutive
held levels whose settle ended alike (how, and for a full one the last fixed-point verdict), with
the settle seconds integrated of those available and the steps they took, then the chain's steps
in all (/tasks/steps: settles, ramps and windows).

usage: settle_trace.py TRACE.txt SWEEP.h5
"""
import itertools
import re
import sys

import h5py
import numpy as np


def main(trace_path, h5_path):
    with h5py.File(h5_path, "r") as f:
        t_begin = f["/windows/t_begin"][:]
        t_end = f["/windows/t_end"][:]
        vnames = list(f["/chains/variant"].attrs["names"])
        gnames = list(f["/chains/group"].attrs["names"])
        variant = [vnames[int(v)] for v in f["/chains/variant"][:]]
        group = [gnames[int(g)] for g in f["/chains/group"][:]]
        cols = list(f["/chains/model"].attrs["columns"])
        model = f["/chains/model"][:]
        task_chain = f["/tasks/chain"][:]
        task_steps = f["/tasks/steps"][:]
    which = [cols.index(c) for c in ("drive_radius [m]", "contact_distance [m]", "tie_static_torque [N m]", "tie_damping [N m s]")]
    lines = [dict(re.findall(r"(\w+)=(\S+)", l)) for l in open(trace_path) if l.startswith("TRACE")]
    rows = {c: [] for c in range(len(variant))}
    taken = set()
    for d in lines:
        t0, t1 = float(d["t0"]), float(d["t1"])
        m = np.array([float(x) for x in d["model"].split(",")])
        # the chain of this model with a window that begins where this settle ends and none
        # measured during it; among equals (the same seed and level in two chains: identical
        # runs), the first not yet taken
        cands = [c for c in range(len(variant))
                 if np.allclose(model[c, which], m, rtol=1e-8, atol=0) and np.any(np.abs(t_begin[c] - t1) < 0.05)
                 and not np.any((t_begin[c] < t1 - 0.05) & (t_end[c] > t0 + 0.05))]
        if not cands:
            sys.exit(f"settle ending at t = {t1} s matches no chain of {h5_path}")
        c = next((c for c in cands if (c, t1) not in taken), cands[0])
        taken.add((c, t1))
        rows[c].append(d)
    total_settle = 0
    for c, R in rows.items():
        if not R:
            continue
        R.sort(key=lambda d: float(d["t0"]))
        steps_chain = int(task_steps[task_chain == c].sum())
        settle_steps = sum(int(d["steps"]) for d in R)
        total_settle += settle_steps
        used = sum(float(d["used"]) for d in R)
        avail = sum(float(d["t1"]) - float(d["t0"]) for d in R)
        print(f"chain {c} ({group[c]}, variant {variant[c]}): {len(R)} settles, {used:.0f} of {avail:.0f} s "
              f"integrated, {settle_steps} of the chain's {steps_chain} steps")
        key = lambda d: (d["how"], d["why"] if d["how"] == "full" else "")
        for k, g in itertools.groupby(R, key=key):
            g = list(g)
            w0, w1 = float(g[0]["w"]), float(g[-1]["w"])
            u = sum(float(d["used"]) for d in g)
            a = sum(float(d["t1"]) - float(d["t0"]) for d in g)
            st = sum(int(d["steps"]) for d in g)
            sw = sum(int(d.get("tie_switches", 0)) for d in g)
            rs = sum(int(d["restarts"]) - 1 for d in g)
            why = f" ({k[1]})" if k[1] else ""
            extra = (f", {sw} tie switches" if sw else "") + (f", {rs} bead mode switches" if rs > 0 else "")
            print(f"  {w0:5.1f}π..{w1:5.1f}π  {len(g):2d} levels  {u:5.0f}/{a:5.0f} s  {st:7d} steps  {k[0]}{why}{extra}")
    print(f"all settles: {total_settle} of {int(task_steps.sum())} steps")


if __name__ == "__main__":
    main(*sys.argv[1:3])
