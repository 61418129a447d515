"""Minimisers the scripts share, on SciPy's (python3-scipy): Nelder–Mead in a box for the
threshold fit, and a scan refined by bounded Brent for one-dimensional fits."""
import math

import numpy as np


def nelder_mead(f, x0, steps, lo, hi, max_evals, xtol=1e-3, ftol=1e-6):
    """Minimises f over the box [lo, hi] with scipy.optimize.minimize(method="Nelder-Mead"),
    whose trial points are clipped onto the box, from x0 with an initial simplex of
    x0 + steps_j e_j (a step is reversed where it would leave the box). Works in coordinates
    scaled by the steps, so it stops when the simplex is smaller than xtol steps and its values
    agree to ftol, or after max_evals evaluations of f (a hard limit). Returns (best x, best f,
    number of evaluations)."""
    from scipy.optimize import Bounds, minimize  # imported when used: scipy is slow to import
    x0, steps, lo, hi = (np.asarray(v, float) for v in (x0, steps, lo, hi))
    n = len(x0)
    if max_evals <= 0:  # no search
        return np.clip(x0, lo, hi), math.nan, 0
    scale = np.where(steps > 0, steps, 1.0)
    simplex = [np.clip(x0, lo, hi)]
    for j in range(n):
        x = x0.copy()
        x[j] = x0[j] + steps[j] if x0[j] + steps[j] <= hi[j] else x0[j] - steps[j]
        simplex.append(np.clip(x, lo, hi))
    tried = []  # every (f, x) evaluated: the best is returned whatever stopped the search

    def scaled(u):
        x = np.asarray(u, float) * scale  # a new array: f may keep it
        value = f(x)
        tried.append((value, x))
        return value

    minimize(scaled, simplex[0] / scale, method="Nelder-Mead", bounds=Bounds(lo / scale, hi / scale),
             options={"initial_simplex": np.array(simplex) / scale, "maxfev": int(max_evals), "maxiter": 10**9,
                      "xatol": xtol, "fatol": ftol})
    best = min(range(len(tried)), key=lambda i: tried[i][0])
    return tried[best][1], tried[best][0], len(tried)


def scan_and_refine(cost, lo, hi, n):
    """The minimum of cost over [lo, hi]: the best of n grid points, refined by bounded Brent
    (scipy.optimize.minimize_scalar) between its neighbours."""
    from scipy.optimize import minimize_scalar
    grid = np.linspace(lo, hi, n)
    i = int(np.argmin([cost(x) for x in grid]))
    if not grid[1] > grid[0]:
        return grid[i]
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, n - 1)]
    res = minimize_scalar(cost, bounds=(a, b), method="bounded", options={"xatol": 1e-12 * max(abs(a), abs(b), 1.0)})
    return res.x if cost(res.x) <= cost(grid[i]) else grid[i]
