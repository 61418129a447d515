"""Parallel efficiency of a sweep: measured (1 vs 2 workers) and projected to 64, 512, 4096 ranks.

Usage: project.py PAPER_1RANK.h5 QUICK_1WORKER.h5 QUICK_2WORKERS.h5 THROUGHPUT.txt
                  [BASIN_1RANK.h5 BASIN_2RANKS.h5 BASIN_THROUGHPUT.txt]

The model (docs/cluster/index.md, "Scale"). A sweep has C chains of K tasks; a task of g windows
integrates for tau = g * tau_w on a worker. The master spends s = g * m_w + 1/mu on each task:
m_w per window to classify, journal and write it (measured on 1 rank: time in on_result), 1/mu to
receive it and hand out the next (the farm's message throughput mu with a task's output size).
A worker waits for its next task while the master handles its result, so a chain advances one
task per tau + s, and W workers run at most C chains at once:
    T(W) = max(ceil(C / W) * K * (tau + s),  C * K * s)
the second term when the master is saturated. Efficiency E = C * K * tau / (R * T(W)) on R ranks.
Every rank integrates (rank 0 in a thread beside the master's loop, FarmOptions::threads), so
W = R - u: the master's own work, a share u = C K s / T of its core, is taken from rank 0's
worker (solved for u by iteration). BASIN_1RANK.h5, part of sweeps/basins.toml on one rank (one
short task per chain), gives tau and the master's m per task, BASIN_THROUGHPUT.txt the message
rate with a basin task's output (its size from BASIN_2RANKS.h5, the same sweep under mpirun -n
2), and the projection for 10^4 such chains. BASIN_2RANKS.h5 also gives the CPU time of the
master's loop per task there (receiving, on_result, handing out and polling, on a core shared
with rank 0's worker): an upper bound of s, projected beside the model's s.
"""
import math
import re
import sys

import h5py


def prov(path):
    with h5py.File(path, "r") as f:
        p = dict(f["provenance"].attrs)
        tasks = len(f["tasks/status"])
        windows = int((f["windows/class"][...] >= 0).sum())
        chains = f["windows/class"].shape[0]
    wall = float(p.get("wall_time", p.get("resume_wall_time")))
    return dict(wall=wall, work=float(p["work_seconds"]), master=float(p["master_result_seconds"]), tasks=tasks,
                windows=windows, chains=chains, master_cpu=float(p.get("master_cpu_seconds", 0.0)),
                bytes_in=int(p.get("bytes_from_workers", 0)))


def message_rate(path):
    """The farm's best message rate (tasks/s) over the rank counts of a farm_throughput log."""
    rates = {}
    for line in open(path):
        m = re.search(r"ranks (\d+) .* ([\d.]+) tasks/s", line)
        if m:
            rates[int(m.group(1))] = float(m.group(2))
    return max(rates.values()), rates


def main():
    paper, w1, w2, tput = sys.argv[1:5]
    p = prov(paper)
    tau_w = p["work"] / p["windows"]
    m_w = p["master"] / p["windows"]
    windows_per_chain = p["windows"] / p["chains"]
    print(f"paper protocol on 1 rank: {p['chains']} chains, {p['windows']} windows, {p['tasks']} tasks, "
          f"wall {p['wall']:.2f} s, integration {p['work']:.2f} s")
    print(f"  worker per window (integrate, classify, compress) tau_w = {tau_w * 1e3:.2f} ms; master per window "
          f"(journal, HDF5 writes) m_w = {m_w * 1e3:.2f} ms; {windows_per_chain:.0f} windows per chain")

    a, b = prov(w1), prov(w2)
    e = a["wall"] / (2 * b["wall"])
    print(f"quick sweep, {a['chains']} chains, {a['tasks']} tasks: 1 worker {a['wall']:.2f} s, 2 workers "
          f"{b['wall']:.2f} s: speed-up {a['wall'] / b['wall']:.2f}, efficiency {e:.2f}")
    print(f"  bytes per task to the master: {b['bytes_in'] / b['tasks']:.0f}")

    mu, rates = message_rate(tput)  # the master's best message rate with sweep-sized outputs
    print(f"master message throughput with sweep-sized outputs: {', '.join(f'{r} ranks {v:.0f}/s' for r, v in sorted(rates.items()))}")

    def farm(C, R, K, tau, s):
        """E on R ranks, every rank integrating, the master's share u taken from rank 0's worker."""
        u = 0.0
        for _ in range(50):
            W = R - u
            T = max(math.ceil(C / W) * K * (tau + s), C * K * s)
            u = min(1.0, C * K * s / T)
        return C * K * tau / (R * T)

    def efficiency(C, R, g, m=None):
        m = m_w if m is None else m
        return farm(C, R, math.ceil(windows_per_chain / g), g * tau_w, g * m + 1.0 / mu)

    gs = [1, 2, 5, 10, 20, 50, int(windows_per_chain)]
    for C in (1024, 4096):
        print(f"\nprojection: the paper's protocol on a {int(math.sqrt(C))} x {int(math.sqrt(C))} grid of R x d "
              f"= {C} chains; efficiency by windows per task g")
        print("  ranks  " + "  ".join(f"g={g:<4d}" for g in gs) + "   smallest g with E >= 0.9")
        for R in (64, 512, 4096):
            es = [efficiency(C, R, g) for g in gs]
            ok = [g for g in range(1, int(windows_per_chain) + 1) if efficiency(C, R, g) >= 0.9]
            print(f"  {R:5d}  " + "  ".join(f"{x:6.2f}" for x in es) + f"   {ok[0] if ok else 'none'}")
        print(f"  (at most {C} workers can be busy: {C} chains)")
        for R in (64, 512, 4096):
            # The master's cost per window that would give E >= 0.9 with whole chains as tasks.
            g = int(windows_per_chain)
            lo, hi = 0.0, m_w
            if efficiency(C, R, g, 0.0) < 0.9:
                print(f"  {R} ranks: below 0.9 even with a master that costs nothing per window "
                      f"(messages alone: {1e3 / mu:.2f} ms per task; a chain integrates in {g * tau_w:.2f} s)")
                continue
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if efficiency(C, R, g, mid) >= 0.9 else (lo, mid)
            print(f"  {R} ranks: E >= 0.9 needs the master's cost per window below {lo * 1e6:.1f} us "
                  f"(now {m_w * 1e3:.2f} ms), with one task per chain")

    if len(sys.argv) > 7:
        basins(*sys.argv[5:8], farm)


def basins(one_rank, two_ranks, tput, farm):
    """10^4 short chains of one task each, as a basin sweep has: the projection by ranks."""
    h, h2 = prov(one_rank), prov(two_ranks)
    mu, rates = message_rate(tput)
    tau = h["work"] / h["tasks"]
    m = h["master"] / h["tasks"]
    s = m + 1.0 / mu
    s_cpu = h2["master_cpu"] / h2["tasks"]  # 0: a file from before master_cpu_seconds
    print(f"\nbasin tasks on 1 rank ({one_rank}): {h['tasks']} chains of one task, integration {tau * 1e3:.1f} ms "
          f"and master {m * 1e3:.3f} ms per task; messages {1e3 / mu:.3f} ms per task "
          f"({h2['bytes_in'] / h2['tasks']:.0f} B back, best of {', '.join(f'{r} ranks {v:.0f}/s' for r, v in sorted(rates.items()))})")
    if s_cpu > 0:
        print(f"  under mpirun -n 2 ({two_ranks}): the master's loop took {s_cpu * 1e3:.3f} ms of CPU per task "
              f"(polling included), against s = {s * 1e3:.3f} ms of the model")
    else:
        print(f"  ({two_ranks} does not record the master's CPU: the model's s alone)")
    print("projection: 10^4 such chains; efficiency by ranks, with the model's s and with the master's CPU per task")
    for R in (2, 8, 16, 64, 128, 512):
        print(f"  {R:5d} ranks: E = {farm(10_000, R, 1, tau, s):.2f}  ({farm(10_000, R, 1, tau, max(s, s_cpu)):.2f})")
    print(f"  (the master saturates at {(tau + s) / s:.0f} busy workers with s"
          + (f", {(tau + s_cpu) / s_cpu:.0f} with its CPU)" if s_cpu > 0 else ")"))


if __name__ == "__main__":
    main()
