#!/usr/bin/python3
"""Model adequacy: which layers of physics each threshold and orbit type of the paper needs.

For every layer set (the [layers] keys of the configuration, docs/reference/configuration.md), runs
the built astrojax on the files of sweeps/adequacy/ at one representative (R, d):
  - `astrojax sweep ramp.toml`: the paper's up/down/up protocol; `astrojax thresholds --csv`
    brackets ω_rise, ω_fall, ω1 and ω2 (the only place thresholds are found);
  - `astrojax sweep hold.toml`: ω_m held from the seeds hanging, circular_high and
    locked_orbit; the class of each chain's measured window says which orbit types exist;
  - `astrojax run run_ramp.toml` and `run_hold.toml`: the same ramps, and the Table 1 orbit
    held at 4.8π, as single runs, whose /summary/violations list every assumption of an
    omitted layer that the motion violated;
  - `astrojax orbits ramp.toml --omega 4.8pi --thresholds`: the thresholds predicted from the
    co-rotating equilibria (ω_rise, ω_fall, ω1; lagging and flower orbits are not equilibria,
    so there is no ω2 there);
  - `astrojax sweep sweeps/table1_staircase.toml --set grid.tie_damping=[2e-6]`: the paper's
    second half held level by level from Table 1's orbit (100 s a level, up through ω1 to 18π,
    back down through ω_fall), one chain at the one parameter set's c_a (docs/reports/reproduction-evidence.md, "One
    parameter set for the whole protocol"; the tie keys do nothing without the clutch);
    `astrojax thresholds` brackets held ω1, ω2 and ω_fall, `--sequence-csv` gives the runs of
    one class per leg (with a lagging orbit's ω_ball plateau), and its "ω2 (Hopf)" row the Hopf
    point where there are flowers (its σ scaled by χ²/dof, as astrojax prints it).
A threshold is reproduced when a ramp bracket's midpoint, a staircase bracket's midpoint, the
Hopf point (ω2) or a prediction of the equilibria lies within 5 % of the paper's value; an
orbit type when some ramp window, held chain or staircase level is classified as it. The
layer sets are a ladder (frictionless, kinetic, stick-slip, + slack, + top stop = the full
model, + the tie clutch); the smallest set of the ladder that reproduces an item is named.
Then each layer omitted from the full model alone, measured against the full model: threshold
shifts, classes that change, and the violations the runs report; and, on the staircase, each
layer omitted from the full model and from the full model with the tie clutch (the set that
holds the second half), the clutch itself among them.

The bottom stop is in every set: the sweeps start from `hanging`, the bead resting on the
bottom ball, which the configuration allows only with layers.bottom_stop = true.

usage: /usr/bin/python3 analysis/model_adequacy.py -o out/adequacy.md [--work out/adequacy] [--set model.KEY=V]
       [--staircase sweeps/table1_staircase.toml]
"""
import os
import re
import sys

import numpy as np

import astrojax_analysis as ajx
from astrojax_analysis.orbits import read_predicted

PI = np.pi
HERE = os.path.dirname(os.path.abspath(__file__))
SWEEPS = os.path.join(HERE, "..", "sweeps", "adequacy")
STAIRCASE = os.path.join(HERE, "..", "sweeps", "table1_staircase.toml")
THRESHOLDS = ("omega_rise", "omega_fall", "omega_1", "omega_2")
ORBIT_TYPES = ("fallen", "locked-circular", "lagging-circular", "flower")
# astrojax orbits' predictions for each threshold of astrojax thresholds (none for ω2).
PREDICTED = {"omega_rise": ("omega_rise", "omega_rise_cone"), "omega_fall": ("omega_fall",), "omega_1": ("omega1",),
             "omega_2": ()}
TOLERANCE = 0.05  # "reproduced": within 5 % of the paper

# The tie is named in every set: the staircase file ties the string with the clutch.
FULL = {"friction": "stick_slip", "slack": "true", "top_stop": "true", "bottom_stop": "true", "tie": "rigid"}
# The layer beyond the paper's model (docs/reports/reproduction-evidence.md, "The tie clutch"), at the torques of the docs/reports/reproduction-evidence.md's
# one parameter set, which was found at this script's point (R = 15 mm, d = 3.5 cm).
CLUTCH = dict(FULL, tie="clutch", **{"model.tie_static_torque": "1.5e-3", "model.tie_kinetic_torque": "1.35e-3",
                                    "model.tie_damping": "2e-6"})
# The staircase's grid runs c_a: one chain, at the one parameter set's.
STAIRCASE_SETS = ("grid.tie_damping=[2e-6]",)
# The ladder, smallest first: each set adds one layer to the one before.
LADDER = [
    ("frictionless", dict(FULL, friction="none", slack="false", top_stop="false")),
    ("kinetic", dict(FULL, friction="kinetic", slack="false", top_stop="false")),
    ("stick_slip", dict(FULL, slack="false", top_stop="false")),
    ("stick_slip + slack", dict(FULL, top_stop="false")),
    ("stick_slip + slack + top_stop (full)", dict(FULL)),
    ("full + tie clutch", CLUTCH),
]
# The full model with one layer omitted: (what is omitted, layers).
OMITTED = [
    ("static friction (friction = kinetic)", dict(FULL, friction="kinetic")),
    ("all friction (friction = none)", dict(FULL, friction="none")),
    ("slack string (slack = false)", dict(FULL, slack="false")),
    ("top stop (top_stop = false)", dict(FULL, top_stop="false")),
]
# On the staircase, also each layer omitted from the set that holds the second half.
OMITTED_FROM_CLUTCH = [
    ("the tie clutch (tie = rigid)", FULL),
    ("static friction (friction = kinetic)", dict(CLUTCH, friction="kinetic")),
    ("slack string (slack = false)", dict(CLUTCH, slack="false")),
    ("top stop (top_stop = false)", dict(CLUTCH, top_stop="false")),
]


def layer_key(layers):
    return tuple(sorted(layers.items()))


def layer_tag(layers):
    """The runs' file-name stem of a layer set."""
    return "_".join(f"{k}-{v}" for k, v in layer_key(layers))


def layer_label(layers):
    return ", ".join(f"{k} = {v}" for k, v in sorted(layers.items()))


# ---- running astrojax ------------------------------------------------------------------

def overrides(layers, extra):
    out = []
    for k, v in sorted(layers.items()):
        # A dotted key is a model parameter the layer needs (the tie clutch's torques).
        out += ["--set", f"{k}={v}" if "." in k else f"layers.{k}={v}"]
    for kv in extra:
        out += ["--set", kv]
    return out


def simulate(exe, layers, files, work, name, extra, s_points):
    """Every run of one layer set; returns its measurements (see the module's docstring)."""
    os.makedirs(work, exist_ok=True)
    sets = overrides(layers, extra)
    out = {"layers": layers}
    ramp_h5, hold_h5, stair_h5 = (os.path.join(work, f"{name}_{k}.h5") for k in ("ramp", "hold", "staircase"))
    for path, src, more in ((ramp_h5, files["ramp"], ()), (hold_h5, files["hold"], ()),
                            (stair_h5, files["staircase"], STAIRCASE_SETS)):
        for stale in (path, path + ".part", path + ".journal"):
            if os.path.exists(stale):
                os.remove(stale)
        more = [a for kv in more for a in ("--set", kv)]
        ajx.run_checked([exe, "sweep", src, "-o", path, "-q", *sets, *more], allowed=(0, 3))  # 3: some task failed, reported
    rows, _ = ajx.run_thresholds(ramp_h5, exe)
    out["ramp"], out["ramp_bracket"] = brackets(rows)
    out["paper"] = ajx.paper_values(rows)
    out["ramp_windows"] = classed_windows(ajx.Sweep(ramp_h5))
    out["stair"] = staircase(exe, stair_h5)
    hold = ajx.Sweep(hold_h5)
    out["holds"] = []
    for c in range(hold.n_chains):
        ks = hold.windows(c)
        seed = ajx.printable(hold.seed_name(int(hold.seed[c])), 40)
        cls = hold.class_name(c, ks[-1]) if ks else "never ran"
        wb = float(hold.stats["omega_ball"][c, ks[-1]]) if ks else np.nan
        out["holds"].append((float(hold.hold_omega[c]), seed, cls, wb))
    out["violations"] = {}
    for key in ("run_ramp", "run_hold"):
        path = os.path.join(work, f"{name}_{key}.h5")
        ajx.run_checked([exe, "run", files[key], "-o", path, "-q", *sets], allowed=(0, 3))
        out["violations"][key] = read_violations(path)
    orbits_h5 = os.path.join(work, f"{name}_orbits.h5")
    ajx.run_checked([exe, "orbits", files["ramp"], "--omega", "4.8pi", "--thresholds", "--threshold-s-points",
                     str(s_points), "-o", orbits_h5, *sets])
    out["predicted"] = read_predicted(orbits_h5)
    return out


def brackets(rows):
    """Chain 0's thresholds of `astrojax thresholds --csv`: ({name: midpoint}, {name: (before,
    after)}) [rad/s], NaN where not reached."""
    mine = [r for r in rows if int(r["chain"]) == 0]
    return ({r["threshold"]: ajx.number(r["mid_rad_s"]) for r in mine},
            {r["threshold"]: (ajx.number(r["before_rad_s"]), ajx.number(r["after_rad_s"])) for r in mine})


def classed_windows(sweep):
    """Chain 0's classified windows in protocol order: [(mean ω_m [rad/s], class, direction)]."""
    return [(float(sweep.omega_mean[0, k]), sweep.class_name(0, k), int(sweep.direction[0, k]))
            for k in sweep.windows(0)]


def staircase(exe, path):
    """The second half held level by level (chain 0 of the staircase sweep): the held
    thresholds, each level's class, the runs of one class per leg with their mean ω_ball and
    dω_ball/dω_m, the Hopf point astrojax thresholds fits (ω_H, σ [π rad/s]; NaN without a flower that
    lasts to the top), and the smallest tension and L1 the measured windows saw (what the slack
    and top-stop layers are there for)."""
    rows, printed = ajx.run_thresholds(path, exe)
    out = dict(zip(("mid", "bracket"), brackets(rows)))
    sweep = ajx.Sweep(path)
    out["windows"] = classed_windows(sweep)
    out["runs"] = [(int(r["direction"]), r["class"], float(r["omega_from_rad_s"]), float(r["omega_to_rad_s"]),
                    ajx.number(r["omega_ball_mean_rad_s"]), ajx.number(r["omega_ball_slope"]))
                   for r in ajx.run_sequence(path, exe) if r["kind"] == "run" and int(r["chain"]) == 0]
    out["hopf"] = hopf_point_printed(printed)
    ks = sweep.windows(0)
    out["L1_min"] = float(np.min(sweep.stats["L1_min"][0, ks])) if ks else np.nan
    tensions = [sweep.samples(0, k) for k in range(sweep.n_windows) if sweep.count[0, k] > 0]
    out["T_min"] = min((float(np.min(s[k])) for s in tensions for k in ("T1", "T2")), default=np.nan)
    return out


def hopf_point_printed(text):
    """(ω_H, σ) [π rad/s] of chain 0's "ω2 (Hopf)" row in the table `astrojax thresholds` prints,
    its σ scaled by χ²/dof as astrojax gives it; (NaN, NaN) without one (no flower to the top)."""
    for line in text.splitlines():
        m = re.match(r"\s*ω2 \(Hopf\)\s+0\b.*?\s([0-9.]+) ± ([0-9.]+)\s", line)
        if m:
            return float(m.group(1)), float(m.group(2))
    return np.nan, np.nan


def read_violations(path):
    """[(what, count, first time [s], worst, units)] from a run file's /summary/violations,
    and its status."""
    run = ajx.read_run(path)
    return {"status": ajx.as_text(run["summary"].get("status", "")), "list": run["violations"]}


# ---- judging ---------------------------------------------------------------------------

def relative(value, paper):
    return (value - paper) / paper if np.isfinite(value) and paper else np.nan


def within(value, paper):
    return bool(np.isfinite(value) and abs(relative(value, paper)) <= TOLERANCE)


def hopf_point(m):
    """The staircase's Hopf point [rad/s] (NaN without one)."""
    return m["stair"]["hopf"][0] * PI


def threshold_result(m, name):
    """(reproduced, source) of one threshold in one set's measurements: 'ramp' when the ramp
    bracket's midpoint is within 5 %, else 'staircase' when the staircase's is, else (ω2)
    'Hopf point' when the staircase's Hopf point is, else 'equilibria' when a prediction is,
    else None."""
    paper = m["paper"][name]
    if within(m["ramp"].get(name, np.nan), paper):
        return True, "ramp"
    if within(m["stair"]["mid"].get(name, np.nan), paper):
        return True, "staircase"
    if name == "omega_2" and within(hopf_point(m), paper):
        return True, "Hopf point"
    if any(within(m["predicted"].get(p, np.nan), paper) for p in PREDICTED[name]):
        return True, "equilibria"
    return False, None


def orbit_presence(m, cls):
    """Where one class was seen: (ramp window ω_m means, held (ω_m, seed) pairs, staircase
    (level ω_m, direction) pairs)."""
    ramp = [w for w, c, _ in m["ramp_windows"] if c == cls]
    held = [(w, seed) for w, seed, c, _ in m["holds"] if c == cls]
    stair = [(w, d) for w, c, d in m["stair"]["windows"] if c == cls]
    return ramp, held, stair


def smallest(ladder_results, item):
    """The first set of the ladder that reproduces the item, with how ('ramp', 'staircase',
    'Hopf point' or 'equilibria' for a threshold; 'ramp', 'holds' or 'staircase' for an orbit
    type), or (None, None)."""
    for name, m in ladder_results:
        if item in THRESHOLDS:
            ok, how = threshold_result(m, item)
        else:
            seen = dict(zip(("ramp", "holds", "staircase"), orbit_presence(m, item)))
            how = next((k for k, v in seen.items() if v), None)
            ok = how is not None
        if ok:
            return name, how
    return None, None


# ---- formatting ------------------------------------------------------------------------

def fmt_pi(v, digits=2):
    return f"{v / PI:.{digits}f}π" if np.isfinite(v) else "—"


def value_text(v, paper):
    return f"{fmt_pi(v)} ({100 * relative(v, paper):+.1f} %)" if np.isfinite(v) else "none"


def threshold_cell(m, name):
    paper = m["paper"][name]
    ramp = m["ramp"].get(name, np.nan)
    parts = [f"ramp {value_text(ramp, paper)}" if np.isfinite(ramp) else "ramp: not reached"]
    held = m["stair"]["mid"].get(name, np.nan)
    if np.isfinite(held) or name != "omega_rise":  # the staircase starts on an orbit, not from rest
        parts.append(f"held {value_text(held, paper)}" if np.isfinite(held) else "held: not reached")
    if name == "omega_2" and np.isfinite(hopf_point(m)):
        parts.append(f"Hopf {value_text(hopf_point(m), paper)}")
    preds = [m["predicted"].get(p, np.nan) for p in PREDICTED[name]]
    if preds:
        shown = sorted({value_text(v, paper) for v in preds})
        parts.append("eq. " + " / ".join(shown))
    ok, _ = threshold_result(m, name)
    return ("**yes**: " if ok else "no: ") + "; ".join(parts)


def ranges(values):
    """ω_m values [rad/s] as 'a–bπ' (the span; n windows)."""
    if not values:
        return ""
    return f"{min(values) / PI:.1f}–{max(values) / PI:.1f}π" if len(values) > 1 else f"{values[0] / PI:.1f}π"


LEGS = ((0, "start"), (1, "up"), (-1, "down"))  # a staircase's legs by direction


def orbit_cell(m, cls):
    ramp, held, stair = orbit_presence(m, cls)
    if not ramp and not held and not stair:
        return "no: not seen"
    parts = []
    if ramp:
        parts.append(f"ramp {ranges(ramp)} ({len(ramp)} window{'s' if len(ramp) > 1 else ''})")
    if held:
        seeds = {}
        for _, seed, _, _ in m["holds"]:
            seeds.setdefault(seed, [0, 0])[1] += 1
        for _, seed in held:
            seeds[seed][0] += 1
        parts.append(f"held {ranges([w for w, _ in held])} (" +
                     ", ".join(f"{seed} {k}/{n}" for seed, (k, n) in seeds.items() if k) + ")")
    if stair:
        legs = [(word, [w for w, d in stair if d == direction]) for direction, word in LEGS]
        parts.append("staircase " + ", ".join(f"{word} {ranges(ws)}" for word, ws in legs if ws) +
                     f" ({len(stair)} level{'s' if len(stair) > 1 else ''})")
    return "**yes**: " + "; ".join(parts)


def symbol(item):
    return ajx.THRESHOLD_SYMBOLS.get(item, item)


def shift_part(label, a, b):
    """The change of one reading [rad/s] from the reference's a to b ('' when equal or both absent)."""
    if np.isfinite(a) and np.isfinite(b):
        return f"{label} {(b - a) / PI:+.3g}π" if b != a else ""
    if np.isfinite(a):
        return f"{label}: none (was {fmt_pi(a)})"
    return f"{label}: {fmt_pi(b)} (was none)" if np.isfinite(b) else ""


def readings(m, name, stair):
    """[(label, value [rad/s])] of one threshold: on the staircase the held bracket's midpoint
    (and for ω2 the Hopf point), else the ramp's and the equilibria's."""
    if stair:
        return [("held", m["stair"]["mid"].get(name, np.nan))] + ([("Hopf", hopf_point(m))] if name == "omega_2" else [])
    return [("ramp", m["ramp"].get(name, np.nan))] + [(f"eq. {p}", m["predicted"].get(p, np.nan)) for p in PREDICTED[name]]


def shift_text(ref, other, name, stair=False):
    """The shift of one threshold against the reference set."""
    parts = [shift_part(label, a, b) for (label, a), (_, b) in zip(readings(ref, name, stair),
                                                                   readings(other, name, stair))]
    parts = [p for p in parts if p]
    return f"{symbol(name)} " + ", ".join(parts) if parts else ""


def changes_text(ref, other):
    """Windows of one protocol (compared one by one) whose class differs from the reference's."""
    arrow = {1: "↑", -1: "↓", 0: ""}
    moved = [(w, d, a, b) for (w, a, d), (_, b, _) in zip(ref, other) if a != b]
    if not moved:
        return "none"
    return (f"{len(moved)} of {len(ref)}: " + ", ".join(f"{w / PI:.1f}π{arrow[d]} {a}→{b}" for w, d, a, b in moved[:6]) +
            (", …" if len(moved) > 6 else ""))


def held_changes(full, other):
    """Held chains whose class differs from the reference's."""
    return [(w, seed, a, b) for (w, seed, a, _), (_, _, b, _) in zip(full["holds"], other["holds"]) if a != b]


def bracket_text(m, name):
    """A staircase bracket: 'before–afterπ, mid Xπ (±%)', or 'not reached'."""
    lo, hi = m["stair"]["bracket"].get(name, (np.nan, np.nan))
    if not np.isfinite(lo):
        return "not reached"
    return f"{lo / PI:.2f}–{hi / PI:.2f}π, mid {value_text(m['stair']['mid'][name], m['paper'][name])}"


def hopf_text(m):
    wh, sigma = m["stair"]["hopf"]
    if not np.isfinite(wh):
        return "no flower to the top"
    return f"Hopf {wh:.2f} ± {sigma:.2f}π ({100 * relative(wh * PI, m['paper']['omega_2']):+.1f} %)"


def runs_text(m, directions):
    """The staircase's runs of one class on the given legs, with a lagging orbit's ω_ball plateau."""
    parts = []
    for d, cls, lo, hi, wb, slope in m["stair"]["runs"]:
        if d not in directions:
            continue
        text = f"{cls} {lo / PI:.1f}π" if lo == hi else f"{cls} {lo / PI:.1f}–{hi / PI:.1f}π"
        if cls == "lagging-circular" and np.isfinite(wb):
            text += f" (ω_ball {wb / PI:.2f}π, dω_ball/dω_m {slope:+.3f})"
        parts.append(("start: " if d == 0 else "") + text)
    return ", ".join(parts) or "—"


def extremes_text(m):
    return f"{m['stair']['T_min']:.3g} N, {m['stair']['L1_min']:.4f} m"


def violation_text(v):
    if not v["list"]:
        return "none" + (f" (run {v['status']})" if v["status"] not in ("ok", "") else "")
    return "; ".join(f"{what}: {count}× from t = {t:.1f} s, worst {worst:.3g} {units}"
                     for what, count, t, worst, units in v["list"])


def report(ladder, omitted, full, meta, stair_sets, stair_omitted):
    """The Markdown report. stair_sets: [(name, measurements)] of every set run, for the
    staircase's table; stair_omitted: [(reference name, its measurements, [(omitted, measurements)])]."""
    lines = ["# Model adequacy: the layers each threshold and orbit type needs", "",
             f"- model: {meta['model']}", f"- runs: {meta['runs']}",
             "- reproduced: a threshold within 5 % of the paper (ramp bracket midpoint, `held`: the staircase's "
             "bracket midpoint, `Hopf`: the staircase's Hopf point for ω2, or the co-rotating "
             "equilibria's prediction, `eq.`: for ω_rise the stability / cone readings); an orbit type seen in a "
             "ramp window, a held chain's measured window or a staircase level",
             "- the bottom stop is in every set: the sweeps start from the bead resting on the bottom ball, the "
             "staircase from its file's seed (sweeps/table1_staircase.toml: Table 1's orbit at 4π)", ""]
    names = [n for n, _ in ladder]
    lines += ["## Reproduced, per layer set", "",
              "| item | paper | " + " | ".join(names) + " | smallest set |",
              "|---|---|" + "---|" * len(names) + "---|"]
    for item in THRESHOLDS + ORBIT_TYPES:
        paper = fmt_pi(full["paper"][item]) if item in THRESHOLDS else "present"
        cells = [threshold_cell(m, item) if item in THRESHOLDS else orbit_cell(m, item) for _, m in ladder]
        best, how = smallest(ladder, item)
        lines.append(f"| {symbol(item)} | {paper} | " + " | ".join(cells) +
                     (f" | {best} ({how}) |" if best else " | **not reproduced** |"))
    lines += ["", "## What each omitted layer changes (against the full model)", "",
              "| omitted | threshold shifts | ramp windows whose class changes | held chains whose class changes | "
              "violations reported (ramp run; Table 1 orbit held at 4.8π) |", "|---|---|---|---|---|"]
    for name, m in omitted:
        shifts = [t for t in (shift_text(full, m, k) for k in THRESHOLDS) if t]
        held_text = ", ".join(f"{w / PI:g}π {seed}: {a}→{b}" for w, seed, a, b in held_changes(full, m)) or "none"
        viol = (f"ramp: {violation_text(m['violations']['run_ramp'])}; "
                f"held: {violation_text(m['violations']['run_hold'])}")
        lines.append(f"| {name} | {'; '.join(shifts) or 'none'} | {changes_text(full['ramp_windows'], m['ramp_windows'])} "
                     f"| {held_text} | {viol} |")
    paper = {k: fmt_pi(v) for k, v in full["paper"].items()}
    lines += ["", "## The second half held level by level (the staircase from Table 1's orbit)", "",
              f"| layer set | ω1 (paper {paper['omega_1']}) | ω2 (paper {paper['omega_2']}): bracket; Hopf point | "
              f"ω_fall (paper {paper['omega_fall']}) | classes from the start up | classes down | "
              "smallest T, L1 sampled |", "|---|---|---|---|---|---|---|"]
    for name, m in stair_sets:
        lines.append(f"| {name} | {bracket_text(m, 'omega_1')} | {bracket_text(m, 'omega_2')}; {hopf_text(m)} | "
                     f"{bracket_text(m, 'omega_fall')} | {runs_text(m, (0, 1))} | {runs_text(m, (-1,))} | "
                     f"{extremes_text(m)} |")
    lines += ["", "## What each omitted layer changes on the staircase", "",
              "| omitted | from | held threshold shifts | levels whose class changes (↑ up, ↓ down) | "
              "smallest T, L1 sampled (the set it is omitted from) |", "|---|---|---|---|---|"]
    for ref_name, ref, rows in stair_omitted:
        for name, m in rows:
            shifts = [t for t in (shift_text(ref, m, k, stair=True) for k in THRESHOLDS) if t]
            lines.append(f"| {name} | {ref_name} | {'; '.join(shifts) or 'none'} | "
                         f"{changes_text(ref['stair']['windows'], m['stair']['windows'])} | "
                         f"{extremes_text(m)} ({extremes_text(ref)}) |")
    lines += ["", "## Violations reported by each set of the ladder", "",
              "| layer set | ramp run | Table 1 orbit held at 4.8π |", "|---|---|---|"]
    for name, m in ladder:
        lines.append(f"| {name} | {violation_text(m['violations']['run_ramp'])} | "
                     f"{violation_text(m['violations']['run_hold'])} |")
    lines += ["", "Layers of each set: " + "; ".join(f"{n}: {layer_label(m['layers'])}" for n, m in stair_sets), ""]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("-o", "--output", required=True, help="the Markdown report to write")
    ap.add_argument("--work", default=None, help="directory for the runs' files (default: next to the report)")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="an override for every run, e.g. model.drive_radius=0.01 (not layers.*)")
    for key, default in (("ramp", "ramp.toml"), ("hold", "hold.toml"), ("run-ramp", "run_ramp.toml"),
                         ("run-hold", "run_hold.toml")):
        ap.add_argument(f"--{key}", default=os.path.join(SWEEPS, default), help=f"default sweeps/adequacy/{default}")
    ap.add_argument("--staircase", default=STAIRCASE,
                    help="the second half held level by level, run with " + " ".join(f"--set {kv}" for kv in STAIRCASE_SETS)
                         + " (default sweeps/table1_staircase.toml)")
    ap.add_argument("--threshold-s-points", type=int, default=21,
                    help="bead positions of `astrojax orbits --thresholds` (default 21)")
    ap.add_argument("--sets-only", default=None, metavar="NAMES",
                    help="comma-separated ladder set names to run (default: all; the full model always runs)")
    args = ap.parse_args(argv)
    if not args.output.endswith(".md"):
        ajx.fail(f"-o {args.output}: the report is Markdown and must end in .md")
    for kv in args.sets:
        if "=" not in kv or kv.startswith("layers."):
            ajx.fail(f"--set {kv}: expected KEY=VALUE outside [layers] (the layers are what this script varies)")
    files = {"ramp": args.ramp, "hold": args.hold, "run_ramp": args.run_ramp, "run_hold": args.run_hold,
             "staircase": args.staircase}
    for k, path in files.items():
        if not os.path.isfile(path):
            ajx.fail(f"--{k.replace('_', '-')} {path}: no such file")
    exe = ajx.require_astrojax(args.astrojax)
    work = args.work or os.path.splitext(args.output)[0] + "_runs"
    ladder_sets = LADDER
    if args.sets_only:
        wanted = args.sets_only.split(",")
        unknown = [w for w in wanted if w not in [n for n, _ in LADDER]]
        if unknown:
            ajx.fail(f"--sets-only: {unknown} not among {[n for n, _ in LADDER]}")
        ladder_sets = [(n, l) for n, l in LADDER if n in wanted or l == FULL]
    cache = {}

    def measure(layers):
        key = layer_key(layers)
        if key not in cache:
            print(f"running layer set {layer_label(layers)}", file=sys.stderr)
            cache[key] = simulate(exe, layers, files, work, layer_tag(layers), args.sets, args.threshold_s_points)
        return cache[key]

    ladder = [(n, measure(l)) for n, l in ladder_sets]
    # With --sets-only, only the omissions whose set ran anyway (the top stop's is a ladder set).
    wanted = lambda sets: [(n, measure(l)) for n, l in sets if not args.sets_only or layer_key(l) in cache]
    omitted = wanted(OMITTED)
    full = measure(FULL)
    stair_omitted = [("full", full, omitted)]
    if not args.sets_only or layer_key(CLUTCH) in cache:
        stair_omitted.append(("full + tie clutch", measure(CLUTCH), wanted(OMITTED_FROM_CLUTCH)))
    # Every set run, once, for the staircase's table: the ladder's, then the omissions'.
    stair_sets, seen = [], set()
    for name, m in ladder + [(f"{ref} − {n}", m) for ref, _, rows in stair_omitted for n, m in rows]:
        if layer_key(m["layers"]) not in seen:
            seen.add(layer_key(m["layers"]))
            stair_sets.append((name, m))
    ramp = ajx.SweepFile(os.path.join(work, f"{layer_tag(FULL)}_ramp.h5"))
    model = ", ".join(f"{c} {v:g}" for c, v in zip(ramp.model_columns_with_units, ramp.model[0]))
    meta = {"model": model,
            "runs": f"`{os.path.relpath(args.ramp)}`, `{os.path.relpath(args.hold)}`, `{os.path.relpath(args.run_ramp)}`, "
                    f"`{os.path.relpath(args.run_hold)}`, `{os.path.relpath(args.staircase)}` with "
                    + " ".join(f"`--set {kv}`" for kv in STAIRCASE_SETS)
                    + (f"; overrides {' '.join(args.sets)}" if args.sets else "")}
    text = report(ladder, omitted, full, meta, stair_sets, stair_omitted)
    ajx.write_report(args.output, text, sys.stderr)
    print(text)


if __name__ == "__main__":
    ajx.run(main)
