"""The plastic return of the fatigue bond (Eqs. 15–22) compiled, one bond at a time.

:func:`~abrakit.fatigue.bond_law.plastic_return` solves the return's three equations (flow rule Eq. 19, 20 and
F = 0 with the damage of Eq. 21 at the end of the step) by Newton's method vectorised over the bonds. In a DEM run
only a handful of bonds yield in a step, and NumPy iterations on arrays of a few entries are mostly call overhead.
:func:`plastic_return_bonds` runs the same algorithm per bond in one numba loop: the same scaled unknowns
y = (Δu_nᵖ/ū_n, Δu_sᵖ/ū_s, 2Δλc/ū_s), the same first guess (one linearised return at the trial stress), the same
forward-difference Jacobian, the same backtracking line search, the same tolerance, the same intact fraction
1 − D = (1 − D₀) e^{−κ} taken to full precision as D → 1, and the same failure damage. It differs only where the
vectorised version cannot be per-bond: there every bond iterates until the slowest has converged, here each bond
stops when its own residual is below the tolerance, so the results agree to the tolerance, not bit for bit. A bond
whose Newton iteration fails splits its step in halves as the NumPy version does (``start``, ``max_halvings``);
one that fails at the deepest split short of the failure damage is flagged for the NumPy version, which raises.
"""

from __future__ import annotations

import math

import numpy as np

from abrakit.compiled import njit
from abrakit.fatigue.bond_law import FAILURE_DAMAGE


@njit(cache=True, inline="always")
def elastic_stresses(en, es, intact, kn, ks):  # pragma: no cover - compiled where numba is installed
    """(σ_n, σ_s) of one bond (Eq. 15, 16; ``bond_law._bond_stresses``): degraded stiffness in tension, full in
    compression."""
    return kn * (intact if en >= 0.0 else 1.0) * en, ks * intact * es


@njit(cache=True, inline="always")
def yield_function(sn, ss, intact, c, q0_unit, tan_phi, alpha2):  # pragma: no cover - compiled where numba is installed
    """F of Eq. (18) for one bond (``bond_law._criterion`` at level 1, continued beyond the far branch), with
    ``q0_unit`` = c − σ_t tan φ and ``alpha2`` = α²."""
    q = c * intact - sn * tan_phi
    q0 = q0_unit * intact
    return alpha2 * (ss * ss) - q * abs(q) + q0 * q0


@njit(cache=True, inline="always")
def surface_size(sn, intact, c, tan_phi):  # pragma: no cover - compiled where numba is installed
    """The yield surface's size c(1 − D) − σ_n tan φ for compressive σ_n (``bond_law._yield_scale``): F is measured
    against its square."""
    return c * intact + tan_phi * max(-sn, 0.0)


@njit(cache=True, inline="always")
def _residual(a, b, lam, tn, ts, d0, kn, ks, scale, un, us, c, tan_phi, tan_psi, alpha2, q0_unit):  # pragma: no cover
    """The residual of ``bond_law._return_residual`` for one bond, and the damage and stresses at y."""
    kappa = abs(a) + abs(b)
    d = d0 - (1.0 - d0) * math.expm1(-kappa)
    intact = (1.0 - d0) * math.exp(-kappa)                       # 1 − D to full precision as D → 1
    sn, ss = elastic_stresses(tn - a * un, ts - b * us, intact, kn, ks)
    g = lam * us / c
    r0 = a - g * (tan_psi * (c * intact - sn * tan_psi)) / un
    r1 = b - g * ss / us
    r2 = yield_function(sn, ss, intact, c, q0_unit, tan_phi, alpha2) / (scale * scale)
    return r0, r1, r2, d, sn, ss


@njit(cache=True)
def _solve3(J, rhs):  # pragma: no cover - compiled where numba is installed
    """J⁻¹ rhs for a 3 × 3 J by Cramer's rule; the least-squares step (pseudo-inverse) where J is singular to
    round-off, as the NumPy return takes it."""
    c00 = J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]
    c01 = J[1, 2] * J[2, 0] - J[1, 0] * J[2, 2]
    c02 = J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0]
    det = J[0, 0] * c00 + J[0, 1] * c01 + J[0, 2] * c02
    norm = np.abs(J).max()
    if not abs(det) > 1e-14 * norm * norm * norm:
        return np.linalg.pinv(J) @ rhs
    x = np.empty(3)
    x[0] = (rhs[0] * c00 + J[0, 1] * (J[1, 2] * rhs[2] - rhs[1] * J[2, 2])
            + J[0, 2] * (rhs[1] * J[2, 1] - J[1, 1] * rhs[2])) / det
    x[1] = (J[0, 0] * (rhs[1] * J[2, 2] - J[1, 2] * rhs[2]) + rhs[0] * c01
            + J[0, 2] * (J[1, 0] * rhs[2] - rhs[1] * J[2, 0])) / det
    x[2] = (J[0, 0] * (J[1, 1] * rhs[2] - rhs[1] * J[2, 1]) + J[0, 1] * (rhs[1] * J[2, 0] - J[1, 0] * rhs[2])
            + rhs[0] * c02) / det
    return x


@njit(cache=True)
def _newton_one(tn, ts, d0, kn, ks, un, us, c, tan_phi, tan_psi, alpha2, q0_unit, tol,
                max_iter):  # pragma: no cover - compiled where numba is installed
    """One bond's return from the elastic trial (tn, ts) at damage d0 (``bond_law.plastic_return`` without the
    split): zero increments where the trial lies inside the surface (F ≤ tol · scale², the NumPy return's test),
    else Newton's method from the linearised first guess. Returns ``(converged, du_n, du_s, damage, σ_n, σ_s)``."""
    if d0 >= FAILURE_DAMAGE:                   # a broken bond carries nothing
        return True, 0.0, 0.0, d0, 0.0, 0.0
    intact = 1.0 - d0
    sn, ss = elastic_stresses(tn, ts, intact, kn, ks)
    scale = surface_size(sn, intact, c, tan_phi)
    f0 = yield_function(sn, ss, intact, c, q0_unit, tan_phi, alpha2)
    if not f0 > tol * scale * scale:
        return True, 0.0, 0.0, d0, sn, ss
    y, shifted, trial, step = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    r, rt = np.empty(3), np.empty(3)
    J = np.empty((3, 3))
    # First guess: one linearised return at the trial stress, damage frozen.
    fn = tan_psi * (c * intact - sn * tan_psi)
    dfn = 2.0 * tan_phi * abs(c * intact - sn * tan_phi)
    dfs = 2.0 * alpha2 * ss
    g0 = f0 / (dfn * (kn * intact) * fn + dfs * ks * intact * ss)
    y[0], y[1], y[2] = g0 * fn / un, g0 * ss / us, g0 * c / us
    r[0], r[1], r[2], d, sn, ss = _residual(y[0], y[1], y[2], tn, ts, d0, kn, ks, scale, un, us, c, tan_phi,
                                            tan_psi, alpha2, q0_unit)
    for _ in range(max_iter):
        size = max(abs(r[0]), abs(r[1]), abs(r[2]))
        if size < tol:
            break
        for col in range(3):
            h = 1e-7 * max(abs(y[col]), 1e-6)
            shifted[:] = y
            shifted[col] += h
            rs0, rs1, rs2, _, _, _ = _residual(shifted[0], shifted[1], shifted[2], tn, ts, d0, kn, ks, scale, un,
                                               us, c, tan_phi, tan_psi, alpha2, q0_unit)
            J[0, col], J[1, col], J[2, col] = (rs0 - r[0]) / h, (rs1 - r[1]) / h, (rs2 - r[2]) / h
        step[:] = _solve3(J, -r)
        t = 1.0                                   # halve the step until the residual decreases
        for _ in range(30):
            for m in range(3):
                trial[m] = y[m] + t * step[m]
            trial[0] = max(trial[0], 0.0)             # Δu_nᵖ ≥ 0 on the physical branch (ψ ≤ φ)
            trial[2] = max(trial[2], 0.0)
            rt[0], rt[1], rt[2], d, sn, ss = _residual(trial[0], trial[1], trial[2], tn, ts, d0, kn, ks, scale, un,
                                                       us, c, tan_phi, tan_psi, alpha2, q0_unit)
            if max(abs(rt[0]), abs(rt[1]), abs(rt[2])) < size:
                break
            t *= 0.5
        y[:] = trial
        r[:] = rt
    # on the surface to the precision of the larger of the start's and the end's size (``bond_law._converged``)
    larger = max(scale, surface_size(sn, 1.0 - d, c, tan_phi))
    converged = max(abs(r[0]), abs(r[1]), abs(r[2]) * (scale / larger) ** 2) < tol
    return converged, y[0] * un, y[1] * us, d, sn, ss


@njit(cache=True)
def plastic_return_bonds(trial_n, trial_s, damage, kn, ks, un, us, c, tensile_strength, tan_phi, tan_psi, alpha,
                         tol, max_iter, start_n, start_s, max_halvings):  # pragma: no cover - compiled
    """Return every given bond onto its yield surface (the bonds are those the elastic trial found outside it).

    Arguments as :func:`~abrakit.fatigue.bond_law.plastic_return` (elastic trial displacements, damage at the step's
    start, per-bond stiffnesses, the elastic displacements at the step's start ``start_n``, ``start_s`` and
    ``max_halvings``) with the parameters unpacked. A bond whose Newton iteration fails splits its step in halves,
    as the NumPy return does: the path from the start to the trial is cut into intervals, depth first, each
    returned from the state the intervals before it left (the plastic displacements taken off its end point), and
    an interval that fails is halved, at most ``max_halvings`` times. Returns ``(du_n, du_s, damage, sigma_n,
    sigma_s, converged)``; a bond with ``converged`` False failed at the deepest split short of the failure damage
    (the NumPy return raises there). Failure as in the NumPy return: a bond at :data:`~abrakit.fatigue.bond_law.
    FAILURE_DAMAGE` carries nothing, one that reaches it in a part of its path ends there, and one whose iteration
    fails at the deepest split with its damage past it is broken with zero stresses."""
    B = trial_n.shape[0]
    du_n, du_s, d_out = np.zeros(B), np.zeros(B), damage.copy()
    sigma_n, sigma_s = np.zeros(B), np.zeros(B)
    converged = np.zeros(B, dtype=np.bool_)
    alpha2 = alpha * alpha
    q0_unit = c - tensile_strength * tan_phi
    pending_a, pending_b = np.empty(max_halvings + 1), np.empty(max_halvings + 1)
    pending_depth = np.empty(max_halvings + 1, np.int64)
    for k in range(B):
        a, b, depth, top = 0.0, 1.0, 0, 0              # the interval [a, b] of the step's path, and the stack
        plastic_n, plastic_s, d = 0.0, 0.0, damage[k]
        while True:
            end_n = trial_n[k] if b == 1.0 else start_n[k] + b * (trial_n[k] - start_n[k])
            end_s = trial_s[k] if b == 1.0 else start_s[k] + b * (trial_s[k] - start_s[k])
            ok, dn, ds, d_new, sn, ss = _newton_one(end_n - plastic_n, end_s - plastic_s, d, kn[k], ks[k], un, us,
                                                    c, tan_phi, tan_psi, alpha2, q0_unit, tol, max_iter)
            if ok or depth == max_halvings:
                plastic_n, plastic_s, d = plastic_n + dn, plastic_s + ds, d_new
                broken = d_new >= FAILURE_DAMAGE      # the bond breaks here: the rest of its path is moot
                sigma_n[k], sigma_s[k] = (0.0, 0.0) if broken and not ok else (sn, ss)
                if broken or not ok or top == 0:
                    converged[k] = ok or broken
                    break
                top -= 1
                a, b, depth = pending_a[top], pending_b[top], pending_depth[top]
            else:                                      # halve the interval: its second half waits
                middle = 0.5 * (a + b)
                pending_a[top], pending_b[top], pending_depth[top] = middle, b, depth + 1
                top += 1
                b, depth = middle, depth + 1
        du_n[k], du_s[k], d_out[k] = plastic_n, plastic_s, d
    return du_n, du_s, d_out, sigma_n, sigma_s, converged
