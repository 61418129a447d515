#!/usr/bin/python3
"""Model adequacy: which layers of physics each threshold and orbit type of the paper needs.

For every layer set (the [layers] keys of the configuration, README "Configuration"), runs
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
    so there is no ω2 there).
A threshold is reproduced when a ramp bracket's midpoint, or a prediction of the equilibria,
lies within 5 % of the paper's value; an orbit type when some ramp window or held chain is
classified as it. The layer sets are a ladder (frictionless, kinetic, stick-slip, + slack,
+ top stop = the full model); the smallest set of the ladder that reproduces an item is named.
Then each layer omitted from the full model alone, measured against the full model: threshold
shifts, classes that change, and the violations the runs report.

The bottom stop is in every set: the sweeps start from `hanging`, the bead resting on the
bottom ball, which the configuration allows only with layers.bottom_stop = true.

usage: /usr/bin/python3 analysis/model_adequacy.py -o out/adequacy.md [--work out/adequacy] [--set model.KEY=V]
"""
import os
import sys

import h5py
import numpy as np

import astrojax_analysis as ajx

PI = np.pi
HERE = os.path.dirname(os.path.abspath(__file__))
SWEEPS = os.path.join(HERE, "..", "sweeps", "adequacy")
THRESHOLDS = ("omega_rise", "omega_fall", "omega_1", "omega_2")
ORBIT_TYPES = ("fallen", "locked-circular", "lagging-circular", "flower")
# astrojax orbits' predictions for each threshold of astrojax thresholds (none for ω2).
PREDICTED = {"omega_rise": ("omega_rise", "omega_rise_cone"), "omega_fall": ("omega_fall",), "omega_1": ("omega1",),
             "omega_2": ()}
TOLERANCE = 0.05  # "reproduced": within 5 % of the paper (issue 9)

FULL = {"friction": "stick_slip", "slack": "true", "top_stop": "true", "bottom_stop": "true"}
# The ladder, smallest first: each set adds one layer to the one before.
LADDER = [
    ("frictionless", dict(FULL, friction="none", slack="false", top_stop="false")),
    ("kinetic", dict(FULL, friction="kinetic", slack="false", top_stop="false")),
    ("stick_slip", dict(FULL, slack="false", top_stop="false")),
    ("stick_slip + slack", dict(FULL, top_stop="false")),
    ("stick_slip + slack + top_stop (full)", dict(FULL)),
    # The layer beyond the paper's model (README, "The tie clutch"), at the torques of the README's
    # one parameter set, which was found at this script's point (R = 15 mm, d = 3.5 cm).
    ("full + tie clutch", dict(FULL, tie="clutch", **{"model.tie_static_torque": "1.5e-3",
                                                     "model.tie_kinetic_torque": "1.35e-3",
                                                     "model.tie_damping": "2e-6"})),
]
# The full model with one layer omitted: (what is omitted, layers).
OMITTED = [
    ("static friction (friction = kinetic)", dict(FULL, friction="kinetic")),
    ("all friction (friction = none)", dict(FULL, friction="none")),
    ("slack string (slack = false)", dict(FULL, slack="false")),
    ("top stop (top_stop = false)", dict(FULL, top_stop="false")),
]


def layer_key(layers):
    return tuple(sorted(layers.items()))


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
    ramp_h5, hold_h5 = os.path.join(work, f"{name}_ramp.h5"), os.path.join(work, f"{name}_hold.h5")
    for path, src in ((ramp_h5, files["ramp"]), (hold_h5, files["hold"])):
        for stale in (path, path + ".part", path + ".journal"):
            if os.path.exists(stale):
                os.remove(stale)
        ajx.run_checked([exe, "sweep", src, "-o", path, "-q", *sets], allowed=(0, 3))  # 3: some task failed, reported
    rows, _ = ajx.run_thresholds(ramp_h5, exe)
    out["ramp"] = {r["threshold"]: ajx.number(r["mid_rad_s"]) for r in rows if int(r["chain"]) == 0}
    out["ramp_bracket"] = {r["threshold"]: (ajx.number(r["before_rad_s"]), ajx.number(r["after_rad_s"]))
                           for r in rows if int(r["chain"]) == 0}
    out["paper"] = ajx.paper_values(rows)
    sweep = ajx.Sweep(ramp_h5)
    out["ramp_windows"] = [(float(sweep.omega_mean[0, k]), sweep.class_name(0, k)) for k in range(sweep.n_windows)
                           if sweep.valid[0, k]]
    hold = ajx.Sweep(hold_h5)
    out["holds"] = []
    for c in range(hold.n_chains):
        ks = hold.windows(c)
        seed = hold.seed_names[int(hold.seed[c])]
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
    with h5py.File(orbits_h5, "r") as f:
        out["predicted"] = {k: predicted_value(g) for k, g in f["thresholds"].items()}
    return out


def predicted_value(group):
    """A prediction of `astrojax orbits --thresholds` [rad/s]; NaN where the branches give none,
    or where they merely run to the end of the continuation range (nothing happened there)."""
    if "end of the range" in ajx.text_attr(group, "mechanism"):
        return np.nan
    return float(group.attrs["predicted"])


def read_violations(path):
    """[(what, count, first time [s], worst, units)] from a run file's /summary/violations,
    and its status."""
    out = []
    with h5py.File(path, "r") as f:
        v = f["summary"].get("violations")
        if v is not None:
            for name in sorted(v, key=int):
                a = v[name].attrs
                if int(a["count"]) > 0:  # a watched assumption that held is not a violation
                    out.append((ajx.as_text(a["what"]), int(a["count"]), float(a["first_time"]), float(a["worst"]),
                                ajx.as_text(a["worst_units"])))
        status = ajx.text_attr(f["summary"], "status")
    return {"status": status, "list": out}


# ---- judging ---------------------------------------------------------------------------

def relative(value, paper):
    return (value - paper) / paper if np.isfinite(value) and paper else np.nan


def within(value, paper):
    return bool(np.isfinite(value) and abs(relative(value, paper)) <= TOLERANCE)


def threshold_result(m, name):
    """(reproduced, source) of one threshold in one set's measurements: 'ramp' when the ramp
    bracket's midpoint is within 5 %, else 'equilibria' when a prediction is, else None."""
    paper = m["paper"][name]
    if within(m["ramp"].get(name, np.nan), paper):
        return True, "ramp"
    if any(within(m["predicted"].get(p, np.nan), paper) for p in PREDICTED[name]):
        return True, "equilibria"
    return False, None


def orbit_presence(m, cls):
    """Where one class was seen: (ramp window ω_m means, held (ω_m, seed) pairs)."""
    ramp = [w for w, c in m["ramp_windows"] if c == cls]
    held = [(w, seed) for w, seed, c, _ in m["holds"] if c == cls]
    return ramp, held


def item_reproduced(m, item):
    if item in THRESHOLDS:
        return threshold_result(m, item)[0]
    ramp, held = orbit_presence(m, item)
    return bool(ramp or held)


def smallest(ladder_results, item):
    """The first set of the ladder that reproduces the item, with how ('ramp', 'equilibria' or
    'holds' / 'ramp' for an orbit type), or (None, None)."""
    for name, m in ladder_results:
        if item in THRESHOLDS:
            ok, how = threshold_result(m, item)
        else:
            ramp, held = orbit_presence(m, item)
            ok, how = bool(ramp or held), "ramp" if ramp else "holds"
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


def orbit_cell(m, cls):
    ramp, held = orbit_presence(m, cls)
    if not ramp and not held:
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
    return "**yes**: " + "; ".join(parts)


def symbol(item):
    return ajx.THRESHOLD_SYMBOLS.get(item, item)


def shift_text(full, other, name):
    """The shift of one threshold against the full model, ramp and equilibria."""
    parts = []
    a, b = full["ramp"].get(name, np.nan), other["ramp"].get(name, np.nan)
    if np.isfinite(a) and np.isfinite(b):
        if b != a:
            parts.append(f"ramp {(b - a) / PI:+.3g}π")
    elif np.isfinite(a) != np.isfinite(b):
        parts.append("ramp: " + ("no longer reached" if np.isfinite(a) else f"now reached at {fmt_pi(b)}"))
    for p in PREDICTED[name]:
        a, b = full["predicted"].get(p, np.nan), other["predicted"].get(p, np.nan)
        if np.isfinite(a) and np.isfinite(b):
            if b != a:
                parts.append(f"eq. {p} {(b - a) / PI:+.3g}π")
        elif np.isfinite(a) != np.isfinite(b):
            parts.append(f"eq. {p}: " + ("none" if np.isfinite(a) else f"{fmt_pi(b)}"))
    return f"{symbol(name)} " + ", ".join(parts) if parts else ""


def class_changes(full, other):
    """Ramp windows (same protocol, same windows) and held chains whose class differs."""
    n = min(len(full["ramp_windows"]), len(other["ramp_windows"]))
    moved = [(w, a, b) for (w, a), (_, b) in zip(full["ramp_windows"][:n], other["ramp_windows"][:n]) if a != b]
    held = [(w, seed, a, b) for (w, seed, a, _), (_, _, b, _) in zip(full["holds"], other["holds"]) if a != b]
    return moved, held


def violation_text(v):
    if not v["list"]:
        return "none" + (f" (run {v['status']})" if v["status"] not in ("ok", "") else "")
    return "; ".join(f"{what}: {count}× from t = {t:.1f} s, worst {worst:.3g} {units}"
                     for what, count, t, worst, units in v["list"])


def report(ladder, omitted, full, meta):
    lines = ["# Model adequacy: the layers each threshold and orbit type needs", "",
             f"- model: {meta['model']}", f"- runs: {meta['runs']}",
             "- reproduced: a threshold within 5 % of the paper (ramp bracket midpoint, or the co-rotating "
             "equilibria's prediction, `eq.`: for ω_rise the stability / cone readings); an orbit type seen in a "
             "ramp window or a held chain's measured window",
             "- the bottom stop is in every set: the sweeps start from the bead resting on the bottom ball", ""]
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
        moved, held = class_changes(full, m)
        moved_text = (f"{len(moved)} of {len(full['ramp_windows'])}: " +
                      ", ".join(f"{w / PI:.1f}π {a}→{b}" for w, a, b in moved[:6]) +
                      (", …" if len(moved) > 6 else "")) if moved else "none"
        held_text = ", ".join(f"{w / PI:g}π {seed}: {a}→{b}" for w, seed, a, b in held) or "none"
        viol = (f"ramp: {violation_text(m['violations']['run_ramp'])}; "
                f"held: {violation_text(m['violations']['run_hold'])}")
        lines.append(f"| {name} | {'; '.join(shifts) or 'none'} | {moved_text} | {held_text} | {viol} |")
    lines += ["", "## Violations reported by each set of the ladder", "",
              "| layer set | ramp run | Table 1 orbit held at 4.8π |", "|---|---|---|"]
    for name, m in ladder:
        lines.append(f"| {name} | {violation_text(m['violations']['run_ramp'])} | "
                     f"{violation_text(m['violations']['run_hold'])} |")
    lines += ["", "Layers of each set: " + "; ".join(f"{n}: {layer_label(m['layers'])}" for n, m in ladder + omitted),
              ""]
    return "\n".join(lines) + "\n"


def main():
    ap = ajx.parser(__doc__)
    ap.add_argument("-o", "--output", required=True, help="the Markdown report to write")
    ap.add_argument("--work", default=None, help="directory for the runs' files (default: next to the report)")
    ap.add_argument("--astrojax", metavar="PATH", help="the astrojax executable")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="an override for every run, e.g. model.drive_radius=0.01 (not layers.*)")
    for key, default in (("ramp", "ramp.toml"), ("hold", "hold.toml"), ("run-ramp", "run_ramp.toml"),
                         ("run-hold", "run_hold.toml")):
        ap.add_argument(f"--{key}", default=os.path.join(SWEEPS, default), help=f"default sweeps/adequacy/{default}")
    ap.add_argument("--threshold-s-points", type=int, default=21,
                    help="bead positions of `astrojax orbits --thresholds` (default 21)")
    ap.add_argument("--sets-only", default=None, metavar="NAMES",
                    help="comma-separated ladder set names to run (default: all; the full model always runs)")
    args = ap.parse_args()
    if not args.output.endswith(".md"):
        ajx.fail(f"-o {args.output}: the report is Markdown and must end in .md")
    for kv in args.sets:
        if "=" not in kv or kv.startswith("layers."):
            ajx.fail(f"--set {kv}: expected KEY=VALUE outside [layers] (the layers are what this script varies)")
    files = {"ramp": args.ramp, "hold": args.hold, "run_ramp": args.run_ramp, "run_hold": args.run_hold}
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
            tag = "_".join(f"{k}-{v}" for k, v in key)
            print(f"running layer set {layer_label(layers)}", file=sys.stderr)
            cache[key] = simulate(exe, layers, files, work, tag, args.sets, args.threshold_s_points)
        return cache[key]

    ladder = [(n, measure(l)) for n, l in ladder_sets]
    # With --sets-only, only the omissions whose set ran anyway (the top stop's is a ladder set).
    omitted = [(n, measure(l)) for n, l in OMITTED if not args.sets_only or layer_key(l) in cache]
    full = measure(FULL)
    with h5py.File(os.path.join(work, f"{'_'.join(f'{k}-{v}' for k, v in layer_key(FULL))}_ramp.h5"), "r") as f:
        cols = ajx.text_attr(f["chains"]["model"], "columns").split(",")
        vals = f["chains"]["model"][0]
    model = ", ".join(f"{c.strip()} {v:g}" for c, v in zip(cols, vals))
    meta = {"model": model,
            "runs": f"`{os.path.relpath(args.ramp)}`, `{os.path.relpath(args.hold)}`, `{os.path.relpath(args.run_ramp)}`, "
                    f"`{os.path.relpath(args.run_hold)}`" + (f"; overrides {' '.join(args.sets)}" if args.sets else "")}
    text = report(ladder, omitted, full, meta)
    ajx.write_report(args.output, text, sys.stderr)
    print(text)


if __name__ == "__main__":
    main()
