"""The numerical minimiser behind :func:`abrakit.evolution.variational_update`: the global minimum of a scalar
function F(λ) near λ_m, where F may have a kink (the r1 |λ - λ_m| of the dissipation potential, Eq. 2.80).

A grid on [λ_m - w, λ_m + w] with λ_m as a grid point, widened while the lowest value sits on an end and probed at
λ_m ± 2^k w for a distant well; each grid basin refined by bounded Brent minimisation on each smooth side of the
kink, then polished by Newton steps on a 4th-order finite-difference derivative.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.optimize import minimize_scalar


class NonConvexWarning(UserWarning):
    """The incremental potential has more than one local minimum on the search interval."""



def _evaluate(F, lam):
    """F on an array of λ; point by point when the user's Ψ is not vectorised."""
    try:
        values = np.asarray(F(lam), dtype=float)
    except (TypeError, ValueError):
        values = None
    if values is None or values.shape != np.shape(lam):
        values = np.array([float(F(x)) for x in np.ravel(lam)]).reshape(np.shape(lam))
    if not np.all(np.isfinite(values)):
        raise ValueError("free_energy returned a non-finite value on the search interval; restrict bounds")
    return values


_PROBE = 2.0 ** np.arange(1, 9)  # probe distances, in search half-widths, of a search for a distant well


def _argmin_with_kink(F, center, width, lo, hi, n, on_nonconvex, max_expansions):
    """Global minimiser of the scalar F on [lo, hi] near ``center``, where F may have a kink."""
    for _ in range(max_expansions):
        a, b = max(center - width, lo), min(center + width, hi)
        half = n // 2 + 1  # the kink λ_m is a grid point, with n//2 cells on each side
        lam = np.concatenate((np.linspace(a, center, half)[:-1], np.linspace(center, b, half)))
        lam = lam[np.concatenate(([True], np.diff(lam) > 0))]  # drop repeats where λ_m sits on a bound
        values = _evaluate(F, lam)
        k = int(np.argmin(values))
        if (k == 0 and a > lo) or (k == lam.size - 1 and b < hi):
            width *= 2.0
            continue
        # probe far beyond the interval for a lower value, i.e. a distant well of a non-convex Ψ
        ladder = center + width * np.concatenate((-_PROBE, _PROBE))
        ladder = ladder[(ladder >= lo) & (ladder <= hi)]
        lower = ladder[_evaluate(F, ladder) < values[k]] if ladder.size else ladder
        if lower.size:
            width = float(np.max(np.abs(lower - center)))
            continue
        break
    else:
        raise RuntimeError(
            f"variational_update: the incremental potential keeps decreasing at λ = {lam[k]:.6g} after "
            f"{max_expansions} doublings of the search interval; is Ψ bounded below?"
        )
    # grid basins: indices not higher than their neighbours, runs of equal values counted once
    padded = np.concatenate(([np.inf], values, [np.inf]))
    is_min = (padded[1:-1] <= padded[:-2]) & (padded[1:-1] <= padded[2:])
    basins = np.flatnonzero(is_min & ~np.concatenate(([False], is_min[:-1])))
    candidates = [center]
    for i in basins:
        left, right = lam[max(i - 1, 0)], lam[min(i + 1, lam.size - 1)]
        for l_, r_ in ((left, min(right, center)), (max(left, center), right)):
            if r_ > l_:  # a bracket on one smooth side of the kink
                candidates.append(_refine(F, l_, r_, center, lo, hi))
    candidates = np.array(candidates)
    values_c = _evaluate(F, candidates)
    best = candidates[int(np.argmin(values_c))]
    if basins.size > 1 and on_nonconvex != "ignore":
        msg = (
            f"incremental potential is non-convex: {basins.size} local minima near λ = "
            f"{np.array2string(lam[basins], precision=4)}; returned the lowest, λ = {best:.6g} (global on the "
            f"searched interval [{a:.4g}, {b:.4g}] up to the grid spacing {np.max(np.diff(lam)):.3g})"
        )
        if on_nonconvex == "raise":
            raise RuntimeError(msg)
        warnings.warn(msg, NonConvexWarning, stacklevel=4)
    return float(best)


def _refine(F, left, right, kink, lo, hi):
    """Minimise F on [left, right], a bracket on which F is smooth (the kink is at most an end point).

    Newton polishing uses a 5-point stencil x ± 2h that stays on x's side of the kink and within [lo, hi].
    """
    x = minimize_scalar(lambda t: float(_evaluate(F, np.array([t]))[0]), bounds=(left, right), method="bounded",
                        options={"xatol": 1e-14 * max(right - left, 1e-300), "maxiter": 500}).x
    x_brent, f_brent = x, float(_evaluate(F, np.array([x]))[0])
    side = np.sign(x - kink)
    h = 1e-3 * (right - left)
    for _ in range(8):
        h = min(h, (x - lo) / 3.0, (hi - x) / 3.0, abs(x - kink) / 3.0 if side != 0 else np.inf)
        if h <= 1e-12 * max(abs(x), right - left):
            break
        f = _evaluate(F, x + h * np.array([-2.0, -1.0, 0.0, 1.0, 2.0]))
        grad = (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)
        curv = (f[1] - 2 * f[2] + f[3]) / h**2
        if not curv > 0:
            break
        x_new = float(np.clip(x - grad / curv, left, right))
        if side != 0 and np.sign(x_new - kink) != side:
            x_new = kink
        done = abs(x_new - x) <= 1e-15 * max(abs(x), right - left)
        x = x_new
        if done:
            break
    f_new = float(_evaluate(F, np.array([x]))[0])
    return x if f_new <= f_brent + 8 * np.finfo(float).eps * max(abs(f_brent), 1.0) else x_brent
