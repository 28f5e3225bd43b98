"""Newton's second law and the leap-frog update (Fig. 4.1, second box; seed 002 Eq. 1–12).

Velocities live at half steps: with the unbalanced force F(t) (contact, body and applied forces),

    v(t + Δt/2) = v(t − Δt/2) + (F(t) + F_d(t)) / m Δt        (seed 002 Eq. 7)
    ω(t + Δt/2) = ω(t − Δt/2) + (M(t) + M_d(t)) / I Δt        (Eq. 8)
    x(t + Δt)   = x(t) + v(t + Δt/2) Δt                         (Eq. 9; spheres need no orientation, Eq. 10)

with the local ("global" in seed 002) non-viscous damping F_d = −α |F| sign(v), Eq. (5)/(6), applied per
component, α = 0.7 for quasi-static runs (Potyondy & Cundall 2004). The scheme is explicit and stable for
Δt ≤ C_s Δt_crit with Δt_crit = min √(m/k) over the particles (Eq. 11, 12).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from abrakit.validation import check_range, check_shape, number_arguments


@number_arguments
def local_damping(force: ArrayLike, velocity: ArrayLike, alpha: float):
    """Local non-viscous damping force F_d = −α |F| sign(v), per component [N] (seed 002 Eq. 5, 6), 0 ≤ α < 1."""
    check_shape("velocity", np.asarray(velocity), np.shape(force))
    return _local_damping(np.asarray(force, float), np.asarray(velocity, float),
                          check_range("alpha", alpha, 0.0, 1.0, high_open=True))


def _local_damping(force, velocity, alpha):
    """The kernel of :func:`local_damping`, unchecked (the time step calls it on its own arrays)."""
    return -alpha * np.abs(force) * np.sign(velocity)


def _leapfrog(x, v, w, force, torque, inv_mass, inv_inertia, dt, kick=None):
    """Advance ``v``, ``w`` by the velocity ``kick`` (default ``dt``) and ``x`` by ``dt``, in place (seed 002
    Eq. 7–9).

    ``force``/``torque`` include any damping. ``inv_mass``/``inv_inertia`` are zero for particles whose motion
    is prescribed (fixed particles, clump members), so those keep their velocities. The first step of a run uses
    ``kick = dt/2``: the given velocities are then those at t = 0 and v(Δt/2) = v(0) + a(0) Δt/2.
    """
    kick = dt if kick is None else kick
    v += force * (inv_mass * kick)[:, None]
    w += torque * (inv_inertia * kick)[:, None]
    x += v * dt


def particle_stiffness(n, springs):
    """Sum spring stiffnesses onto particles: ``springs`` is a list of ``(index, k)`` arrays [N/m per particle]."""
    total = np.zeros(n)
    for index, k in springs:
        if len(index):
            total += np.bincount(index, weights=k, minlength=n)
    return total


def critical_time_step(mass, inertia, k_translation, k_rotation, movable=None) -> float:
    """Critical time step Δt_crit = min_p min(√(m_p/k_p), √(I_p/k_p^rot)) [s] (seed 002 Eq. 12).

    ``k_translation`` is the sum of the contact stiffnesses acting on each particle [N/m], ``k_rotation`` the sum
    of K^t r² (and bond bending stiffnesses) [N m]. The estimate is conservative, as in PFC: a mass on one spring
    is stable up to 2√(m/k), a chain of equal masses and springs up to √(m/k) = √2 √(m/Σk). Particles with zero
    stiffness or that do not move (``movable`` false) are ignored; with no stiffness at all the result is ``inf``.
    """
    checks = (("mass", mass, True), ("inertia", inertia, True), ("k_translation", k_translation, False),
              ("k_rotation", k_rotation, False))
    for name, value, positive in checks:                 # never an inf or NaN step from bad input
        value = np.asarray(value, dtype=float)
        bad = ~np.isfinite(value) | ((value <= 0.0) if positive else (value < 0.0))
        if np.any(bad):
            raise ValueError(f"{name} must lie in {'(0, inf)' if positive else '[0, inf)'}, got {value[bad][:3]}")
    movable = np.ones(len(mass), bool) if movable is None else movable
    with np.errstate(divide="ignore"):
        dt_t = np.where(k_translation > 0, np.sqrt(mass / np.where(k_translation > 0, k_translation, 1.0)), np.inf)
        dt_r = np.where(k_rotation > 0, np.sqrt(inertia / np.where(k_rotation > 0, k_rotation, 1.0)), np.inf)
    dt = np.minimum(dt_t, dt_r)[movable]
    return float(dt.min()) if len(dt) else np.inf
