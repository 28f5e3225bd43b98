"""The time step of a DEM run (:mod:`abrakit.dem.simulation`): the springs that bound it, Δt_crit = min √(m/Σk),
√(I/Σk_rot) over the particles (seed 002 Eq. 11, 12; Σk over each particle's candidate contacts, walls and bonds), the
travel limit against tunnelling, and the policy for a step given by the user."""

from __future__ import annotations

import warnings

import numpy as np

from abrakit.dem.contact_laws import _rowdot
from abrakit.dem.integrate import particle_stiffness


def _particle_springs(sim) -> tuple[np.ndarray, np.ndarray]:
    """Translational and rotational spring sums (k_t, k_r) of every particle of ``sim`` [N/m, N·m] over the candidate
    contacts, the walls and the bonds, each at least that of a contact with a particle like itself (1 % overlap
    for Hertz)."""
    p, law, n = sim.particles, sim.law, len(sim.particles)
    springs_t, springs_r = [], []
    for c, sides in ((sim.contacts, ("i", "j")), (sim.wall_contacts, ("j",))):
        if not len(c):
            continue
        reference = 0.01 * (p.radius[c.j] if len(sides) == 1 else np.minimum(p.radius[c.i], p.radius[c.j]))
        if getattr(law, "constant_stiffness", False):
            gap_overlap = reference
        elif len(sides) == 2:
            gap_overlap = p.radius[c.i] + p.radius[c.j] - np.linalg.norm(sim.branch(c.i, c.j), axis=1)
        else:
            gap_overlap = p.radius[c.j] - _rowdot(p.x[c.j] - sim.walls.point[c.i], sim.walls.normal[c.i])
        fn, kn = law.normal_force(np.maximum(gap_overlap, reference), c.prm)
        kt = np.broadcast_to(law.shear_stiffness(fn, c.prm), fn.shape)
        kn = np.broadcast_to(kn, fn.shape)
        for side in sides:
            idx = getattr(c, side)
            springs_t.append((idx, np.maximum(kn, kt)))
            springs_r.append((idx, kt * p.radius[idx] ** 2))
    b = sim.parallel_bonds
    if len(b):
        for idx in (b.i, b.j):
            springs_t.append((idx, np.maximum(b.kn, b.ks) * b.area))
            springs_r.append((idx, np.maximum(b.kn * b.inertia, b.ks * b.polar)
                              + b.ks * b.area * p.radius[idx] ** 2))
    f = sim.fatigue_bonds
    if len(f):
        k = np.maximum(f.kn, f.ks) * f.area
        for idx in (f.i, f.j):
            springs_t.append((idx, k))
            springs_r.append((idx, k * p.radius[idx] ** 2))
    all_ = np.arange(n)
    self_prm = law.pair_parameters(p, all_, all_)
    fn, kn = law.normal_force(0.01 * p.radius, self_prm)
    kt = np.broadcast_to(law.shear_stiffness(fn, self_prm), fn.shape)
    k_t = np.maximum(particle_stiffness(n, springs_t), np.maximum(kn, kt))
    k_r = np.maximum(particle_stiffness(n, springs_r), kt * p.radius**2)
    return k_t, k_r


def _travel_time_step(p, max_travel: float) -> float:
    """Δt at which the fastest of the particles ``p`` moves ``max_travel`` of the smallest radius (surface speed of its
    spin included) [s], ``inf`` at rest."""
    v, w, radius = (p.v, p.w, p.radius) if not p.fixed.any() else (p.v[~p.fixed], p.w[~p.fixed], p.radius[~p.fixed])
    if not len(v):
        return np.inf
    speed = np.sqrt(_rowdot(v, v)) + np.sqrt(_rowdot(w, w)) * radius
    fastest = float(speed.max())
    return np.inf if fastest == 0.0 else max_travel * float(p.radius.min()) / fastest


def _policed_time_step(dt, dt_crit, dt_travel, *, auto, safety, policy, warned, max_travel):
    """The time-step policy: ``(dt, refusal, warned)`` for the current step ``dt``, Δt_crit and the travel limit
    ``dt_travel`` [s]. ``auto`` takes ``safety`` · Δt_crit, at most the travel limit; a fixed ``dt`` above either is
    refused (``policy="raise"``), reduced with a warning (``"reduce"``) or, above Δt_crit only, kept with one
    warning (``"allow"``). ``refusal`` is the message of the refusal (None where there is none; the step returned
    is then the one given), ``warned`` whether the warning of ``"allow"`` has been given. The warnings point at the
    caller of the simulation's method that called :meth:`~abrakit.dem.simulation.Simulation.update_time_step`."""
    if auto:
        dt = min(safety * dt_crit, dt_travel)
    elif dt > dt_travel and dt_travel < dt_crit and policy != "allow":
        if policy == "raise":
            return dt, (f"dt = {dt:.4g} s lets the fastest particle move more than {max_travel:g} of the smallest "
                        f"radius per step (use dt <= {dt_travel:.4g} s, dt=None (automatic) or "
                        "dt_policy='reduce')"), warned
        warnings.warn(f"dt = {dt:.4g} s lets the fastest particle move more than {max_travel:g} of the "
                      f"smallest radius per step; reduced to {dt_travel:.4g} s", RuntimeWarning, stacklevel=4)
        dt = dt_travel
    elif dt > dt_crit:
        if policy == "raise":
            return dt, (f"dt = {dt:.4g} s exceeds the critical time step {dt_crit:.4g} s (seed 002 Eq. 11, 12); "
                        f"use dt <= {safety * dt_crit:.4g} s, dt=None (automatic) or dt_policy='reduce'"), warned
        if policy == "allow":
            if not warned:
                warnings.warn(f"dt = {dt:.4g} s exceeds the critical time step {dt_crit:.4g} s and is kept "
                              "(dt_policy='allow'): the run may become unstable", RuntimeWarning, stacklevel=4)
            return dt, None, True
        warnings.warn(f"dt = {dt:.4g} s exceeds the critical time step {dt_crit:.4g} s; reduced to "
                      f"{safety * dt_crit:.4g} s", RuntimeWarning, stacklevel=4)
        dt = safety * dt_crit
    if not np.isfinite(dt):
        return dt, "no stiffness in the system: give dt explicitly", warned
    return dt, None, warned
