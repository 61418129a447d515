"""The CSVs of `astrojax bench work-precision` (and of astrojax_peers, same columns): reading
them, the cheapest run of a method within a target error, and the table at equal error."""
import csv
import math

from .errors import fail


NEED = ("scene", "method", "status", "cpu_median_s", "param_kind", "param")


def read(paths, error_column="err_position_m"):
    """The rows of the CSVs (lines starting with '#' are comments), checked: the columns NEED
    and `error_column` present, CPU times and errors numbers."""
    rows = []
    for p in paths:
        try:
            with open(p, newline="") as f:
                lines = [line for line in f if not line.startswith("#")]
            got = list(csv.DictReader(lines))
        except (OSError, UnicodeDecodeError, csv.Error) as e:
            fail(f"{p}: cannot read: {getattr(e, 'strerror', None) or e}")
        if not got:
            fail(f"{p}: no rows: not a CSV of `astrojax bench work-precision`")
        missing = [c for c in NEED + (error_column,) if c not in got[0]]
        if missing:
            fail(f"{p}: not a CSV of `astrojax bench work-precision` (columns {missing} missing)")
        for i, r in enumerate(got):
            try:
                float(r["cpu_median_s"]), float(r[error_column])
            except (TypeError, ValueError):
                fail(f"{p}: row {i + 2}: cpu_median_s and {error_column} must be numbers")
        rows += got
    return rows


def cheapest(rows, method, target, column):
    ok = [float(r["cpu_median_s"]) for r in rows if r["method"] == method and r["status"] == "ok"
          and r.get("same_final_mode", "1") == "1" and float(r[column]) <= target]
    return min(ok) if ok else math.nan


def table(rows, targets, column):
    """CPU [s] of the cheapest run of each method reaching each target error, per scene."""
    for scene in dict.fromkeys(r["scene"] for r in rows):
        rs = [r for r in rows if r["scene"] == scene]
        methods = list(dict.fromkeys(r["method"] for r in rs))
        floor = float(rs[0].get("reference_floor_m", rs[0].get("omega_floor", "nan")))
        print(f"\n{scene} (reference floor {floor:.1e})")
        print(f"  {'method':24s}" + "".join(f"{'err <= %.0e' % t:>22s}" for t in targets))
        best = {t: min((cheapest(rs, m, t, column) for m in methods), key=lambda x: (math.isnan(x), x))
                for t in targets}
        for m in methods:
            cells = []
            for t in targets:
                c = cheapest(rs, m, t, column)
                cells.append("—" if math.isnan(c) else f"{c * 1e3:8.2f} ms ({c / best[t]:4.1f}x)")
            print(f"  {m:24s}" + "".join(f"{x:>22s}" for x in cells))
