#!/usr/bin/python3
"""Compare work-precision runs of the same methods under different settings.

Each argument is LABEL=CSV (a CSV of `astrojax bench work-precision`). For every scene and
method, prints per label the machine-independent work (steps / rhs_evals at the given rtols)
and the CPU time of the cheapest run within each target error (ms, as the --table of
plot_work_precision.py).

  /usr/bin/python3 analysis/compare_runs.py k0=out/wp_k0.csv k3=out/wp_k3.csv \
      [--rtols 1e-3,1e-6,1e-9] [--errors 1e-3,1e-6,1e-9]
"""
import math

import astrojax_analysis as ajx
# The CSV reader and the "cheapest run within an error" rule of the work-precision table.
from astrojax_analysis.workprecision import cheapest, read


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("runs", nargs="+", help="LABEL=CSV")
    ap.add_argument("--rtols", default="1e-3,1e-6,1e-9")
    ap.add_argument("--errors", default="1e-3,1e-6,1e-9")
    a = ap.parse_args(argv)
    rtols, errors = ajx.float_list(a.rtols, "--rtols"), ajx.float_list(a.errors, "--errors")
    runs = []
    for spec in a.runs:
        label, _, path = spec.partition("=")
        if not path:
            ap.error(f"'{spec}': expected LABEL=CSV")
        runs.append((label, read([path])))
        if any(c not in runs[-1][1][0] for c in ("steps", "rhs_evals")):
            ajx.fail(f"{path}: not a CSV of `astrojax bench work-precision` (columns steps, rhs_evals missing)")
    keys = list(dict.fromkeys((r["scene"], r["method"]) for _, rows in runs for r in rows))
    for scene, method in keys:
        print(f"\n{scene}, {method}")
        for label, rows in runs:
            rs = [r for r in rows if r["scene"] == scene and r["method"] == method]
            if not rs:
                continue
            work = []
            for t in rtols:
                m = [r for r in rs if r["param_kind"] == "rtol" and math.isclose(ajx.number(r["param"]), t)]
                work.append(f"{m[0]['steps']}/{m[0]['rhs_evals']}" if m else "—")
            cpu = [cheapest(rs, method, e, "err_position_m") for e in errors]
            print(f"  {label:10s} steps/evals at rtol {'/'.join(f'{t:.0e}' for t in rtols)}: {' / '.join(work)};"
                  f"  CPU [ms] within {'/'.join(f'{e:.0e}' for e in errors)} m: "
                  + " / ".join("—" if math.isnan(c) else f"{c * 1e3:.2f}" for c in cpu))


if __name__ == "__main__":
    ajx.run(main)
