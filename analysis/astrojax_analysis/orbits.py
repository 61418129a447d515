"""Files of `astrojax orbits -o FILE`: the continuation's branches (/branches/points and
/branches/events, columns of equal length) and the predicted thresholds (/thresholds/<name>
with attributes predicted [rad/s] and mechanism), read and checked as reader.py reads sweeps."""
import h5py
import numpy as np

from .errors import SweepFileError
from .reader import dataset, format_version, open_h5, read, resolved, string_list, text_attr

POINT_COLUMNS = ("branch_id", "case", "lambda", "rho1", "s", "stable", "admissible")
EVENT_COLUMNS = ("branch_id", "lambda", "rho1", "s")


def _table(f, path, name, need):
    g = f.get(name)
    if not isinstance(g, h5py.Group):
        raise SweepFileError(path, "/" + name, "missing; run astrojax orbits with --continue and -o")
    first = dataset(f, path, f"{name}/{need[0]}", "f", (None,)) if need[0] in g else None
    n = first.shape[0] if first is not None else None
    out = {}
    for col, d in g.items():
        if isinstance(d, h5py.Dataset):
            n = d.shape[0] if n is None and d.ndim == 1 else n
            out[col] = read(dataset(f, path, f"{name}/{col}", "f" if d.dtype.kind == "f" else "i", (n,)), path)
    for col in need:
        if col not in out:
            raise SweepFileError(path, f"/{name}/{col}", "missing")
    return out


def _names(obj, path, name, sep, n):
    """A list of n names: a 1-D string attribute, or (files of astrojax orbits before
    2026-11-28, whatever their format_version) one string joined by `sep`."""
    joined = not isinstance(obj.attrs.get(name), np.ndarray)
    return string_list(obj, path, name, 2 if joined else 3, sep, n) if n else []


def read_branches(path):
    """(parameter, points {column: array}, events {column: array}, event kinds [str])."""
    with open_h5(path) as f:
        format_version(f, path)
        points = _table(f, path, "branches/points", POINT_COLUMNS)
        events = _table(f, path, "branches/events", EVENT_COLUMNS)
        parameter = text_attr(f["branches"], path, "parameter")
        n = len(events["lambda"])
        ev = f["branches/events"]
        kinds = _names(ev, path, "kinds", ",", n)
    cases = points["case"]
    if len(cases) and (np.any(cases < 0) or np.any(cases > 4) or np.any(cases != np.round(cases))):
        raise SweepFileError(path, "/branches/points/case", "a case outside 0..4 (stuck, bottom_stop, frictionless, "
                             "cone_up, cone_down)")
    for name, values in list(points.items()) + list(events.items()):
        if name in ("lambda", "rho1", "s") and not np.all(np.isfinite(values)):
            raise SweepFileError(path, f"/branches/*/{name}", "non-finite value")
    return parameter, points, events, kinds


def read_predicted(path):
    """{threshold: predicted [rad/s]} of /thresholds; NaN where the branches give none, or where
    they merely run to the end of the continuation range (nothing happened there)."""
    out = {}
    with open_h5(path) as f:
        format_version(f, path)
        g = f.get("thresholds")
        if not isinstance(g, h5py.Group):
            raise SweepFileError(path, "/thresholds", "missing; run astrojax orbits with --thresholds and -o")
        for name, t in g.items():
            if "end of the range" in text_attr(t, path, "mechanism"):
                out[name] = np.nan
                continue
            try:
                out[name] = float(t.attrs["predicted"])
            except (KeyError, TypeError, ValueError):
                raise SweepFileError(path, t.name, "attribute predicted missing or not a number") from None
    return out


class Curves:
    """The threshold curves of `astrojax orbits CONFIG --map PARAM -o FILE.h5` (/curves): each
    point of each curve, and the codimension-2 points where two curves meet. Columns by name
    (`p` the second parameter, `omega_m` the threshold in rad/s, `kind` a code of KINDS)."""

    KINDS = {0: "fold", 1: "cone_up", 2: "cone_down", 3: "hopf"}

    def __init__(self, path):
        self.path = path
        with open_h5(path) as f:
            format_version(f, path)
            g = f.get("curves")
            if not isinstance(g, h5py.Group):
                raise SweepFileError(path, "/curves",
                                     "missing; write one with `astrojax orbits CONFIG --map PARAM --s S -o FILE.h5`")
            self.parameter = text_attr(g, path, "parameter")
            self.parameter_symbol = text_attr(g, path, "parameter_symbol")
            self.parameter_unit = text_attr(g, path, "parameter_unit")
            self.points = _table(f, path, "curves/points", ("curve_id", "kind", "p", "omega_m"))
            self.codim2 = _table(f, path, "curves/codim2", ("curve_id", "kind", "p", "omega_m"))
            # the codimension-2 names: a string array, or joined by commas before
            self.codim2_names = _names(f["curves/codim2"], path, "names", ",", len(self.codim2["p"]))
            self.resolved = resolved(f["resolved"]) if "resolved" in f else {}
        kinds = self.points["kind"]
        if len(kinds) and not np.all(np.isin(kinds, list(self.KINDS))):
            raise SweepFileError(path, "/curves/points/kind", f"a kind outside {sorted(self.KINDS)}")

    def curve_ids(self, kinds):
        """The ids of the curves of the given kind names, in order."""
        codes = [k for k, v in self.KINDS.items() if v in kinds]
        return [int(i) for i in np.unique(self.points["curve_id"]) if
                int(self.points["kind"][self.points["curve_id"] == i][0]) in codes]

    def curve(self, curve_id):
        """The columns of one curve, in order along it."""
        m = self.points["curve_id"] == curve_id
        return {k: v[m] for k, v in self.points.items()}
