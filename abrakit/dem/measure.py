"""Measurements on a running simulation: stresses, strains, fabric and energies (Ch. 5.3 measurement schemes).

- wall-based stress: normal force on a wall over its area;
- specimen-based (Love–Weber) stress: σ = −(1/V) Σ_c sym(f_c ⊗ l_c) over contacts in the volume V, with l_c the
  branch vector from A to B (from the contact point to the particle centre at a wall) and f_c the force on B;
  **tension positive**, as in the continuum chapters (pass ``compression_positive=True`` for the soil-mechanics
  sign). In static equilibrium it equals the wall stress (boundary-traction average);
- strain from wall positions, ε = (L − L₀)/L₀ per box axis (extension positive);
- coordination number Z = 2C/N, the mechanical one Z_m = (2C − N₁)/(N − N₀ − N₁) without rattlers, and the
  contacts per particle (:func:`contact_counts`; their sum over 2 gives n_c of the contact density
  ρ_c = n_c/V, Eq. 5.29, :func:`abrakit.identification.measured_contact_density`);
- the energy balance of :class:`~abrakit.dem.simulation.EnergyAccount`.
"""

from __future__ import annotations

import numpy as np

from abrakit.dem.contact_laws import _rowdot
from abrakit.validation import check_instance, check_positive, check_range


def wall_stress(sim, wall, area: float | None = None) -> float:
    """Compressive normal stress on ``wall`` (index or name) [Pa]; ``area`` defaults to the box face area."""
    walls = sim.walls
    k = walls.index(wall) if isinstance(wall, str) else int(wall)
    if area is None:
        axis = next((a for a, pair in walls.box_axes.items() if k in pair), None)
        if axis is None:
            raise ValueError(f"wall {walls.names[k]!r} is not part of a box: give its area")
        area = walls.box_area(axis)
    return float(walls.normal_force(k)) / check_positive("area", area)


def love_weber_stress(sim, volume: float, *, include_walls: bool = True, region=None,
                     compression_positive: bool = False) -> np.ndarray:
    """Average stress in ``volume`` [m³] from the contact forces (Love–Weber), (3, 3) [Pa].

    ``region`` = ``(lower, upper)`` restricts the sum to contacts whose contact point lies in that box
    (a measurement region, e.g. the thesis's measurement spheres replaced by boxes).
    """
    check_positive("volume", volume)
    p = sim.particles
    parts = []
    c = sim.contacts
    if c.force is not None and len(c):
        t = c.touching
        i, j = c.i[t], c.j[t]
        branch = sim.branch(i, j).T                                # (3, K), from A to B (nearest images)
        point = p.x[i].T + (p.radius[i] - 0.5 * c.overlap[t]) * c.normal[:, t]
        parts.append((c.force[:, t], branch, point))
    w = sim.wall_contacts
    if include_walls and w.force is not None and len(w):
        t = w.touching
        branch = (p.radius[w.j[t]] - w.overlap[t]) * w.normal[:, t]   # wall plane to centre
        parts.append((w.force[:, t], branch, p.x[w.j[t]].T - branch))
    sigma = np.zeros((3, 3))
    for force, branch, point in parts:
        if region is not None:
            lo, hi = np.asarray(region, float)
            inside = np.all((point >= lo[:, None]) & (point <= hi[:, None]), axis=0)
            force, branch = force[:, inside], branch[:, inside]
        sigma -= force @ branch.T
    sigma = 0.5 * (sigma + sigma.T) / volume
    return -sigma if compression_positive else sigma


def box_strain(walls, initial_lengths) -> np.ndarray:
    """Strain of a wall box from its edge lengths, ε = (L − L₀)/L₀ per axis (x, y, z), extension positive."""
    initial_lengths = np.asarray(initial_lengths, float)
    return (walls.box_lengths() - initial_lengths) / initial_lengths


def contact_counts(sim) -> np.ndarray:
    """Number of force-carrying particle–particle contacts of each particle."""
    c, n = sim.contacts, len(sim.particles)
    if not len(c) or c.overlap is None:
        return np.zeros(n, int)
    t = c.touching
    return np.bincount(c.i[t], minlength=n) + np.bincount(c.j[t], minlength=n)


def coordination_number(sim, *, mechanical: bool = False) -> float:
    """Z = 2C/N, or the mechanical Z_m = (2C − N₁)/(N − N₀ − N₁) that leaves out rattlers (Thornton 2000)."""
    counts = contact_counts(sim)
    total = counts.sum()
    if not mechanical:
        return float(total / len(counts)) if len(counts) else 0.0
    n0, n1 = np.sum(counts == 0), np.sum(counts == 1)
    active = len(counts) - n0 - n1
    return float((total - n1) / active) if active > 0 else 0.0


def porosity(sim, volume: float) -> float:
    """η = 1 − V_solid/V with the sphere volumes (overlaps ignored)."""
    solid = 4.0 / 3.0 * np.pi * np.sum(sim.particles.radius**3)
    return 1.0 - solid / check_positive("volume", volume)


def energy_balance(sim) -> dict:
    """Energy bookkeeping as a dict [J]: stored parts, dissipated parts, work done on the system, closure error.

    ``relative_error`` = error / max(initial stored energy, |work|, dissipated) (a scale of the energy turnover).
    """
    e = sim.energy
    if e.initial is None:
        raise ValueError("no step taken with track_energy=True yet")
    scale = max(abs(e.initial), abs(e.work), e.dissipated, 1e-300)
    return {
        "kinetic": e.kinetic, "elastic": e.elastic, "potential": e.potential, "stored": e.stored,
        "friction": e.friction, "local_damping": e.local_damping, "dashpot": e.dashpot,
        "dissipated": e.dissipated, "work_walls": e.work_walls, "work_applied": e.work_applied,
        "work_prescribed": e.work_prescribed, "work": e.work, "initial": e.initial, "error": e.error,
        "relative_error": e.error / scale,
    }


def kinetic_energy(sim) -> float:
    """Kinetic energy from the half-step velocities (cheap monitor of settling) [J]."""
    p = sim.particles
    free = p.clump < 0
    ke = 0.5 * np.sum(p.mass[free] * _rowdot(p.v[free], p.v[free]))
    ke += 0.5 * np.sum(p.inertia[free] * _rowdot(p.w[free], p.w[free]))
    if sim.clumps is not None:
        ke += sim.clumps.kinetic_energy()
    return float(ke)


def unbalanced_force_ratio(sim) -> float:
    """Mean unbalanced force over the mean contact force (PFC's "mechanical ratio"); → 0 in static equilibrium.

    Sums gravity and the contact forces of the last step (particle–particle and particle–wall) onto the bodies:
    free spheres, and clumps as a whole (their members are held by the rigid body, not by force balance).
    Without any force-carrying contact the ratio is 0 if nothing is unbalanced either and ∞ otherwise (a falling
    gas is not in equilibrium).
    """
    p, n = sim.particles, len(sim.particles)
    total = p.mass[:, None] * sim.gravity
    magnitudes = []
    for c, wall in ((sim.contacts, False), (sim.wall_contacts, True)):
        if not len(c) or c.force is None:
            continue
        for k in range(3):
            total[:, k] += np.bincount(c.j, c.force[k], n)
            if not wall:
                total[:, k] -= np.bincount(c.i, c.force[k], n)
        magnitudes.append(np.linalg.norm(c.force[:, c.touching], axis=0))
    bodies = total[p.clump < 0]
    if sim.clumps is not None:
        cl = sim.clumps
        per_clump = np.column_stack([np.bincount(cl.body, total[cl.members, k], len(cl)) for k in range(3)])
        bodies = np.concatenate([bodies, per_clump])
    unbalanced = float(np.mean(np.linalg.norm(bodies, axis=1))) if len(bodies) else 0.0
    magnitudes = np.concatenate(magnitudes) if magnitudes else np.zeros(0)
    mean_contact = float(magnitudes.mean()) if len(magnitudes) else 0.0
    if mean_contact == 0.0:
        return 0.0 if unbalanced == 0.0 else np.inf
    return unbalanced / mean_contact


def relax(sim, *, tolerance: float = 1e-2, stress_tolerance: float = 1e-2, min_steps: int = 200,
          max_steps: int = 20_000, check_every: int = 200) -> dict:
    """Cycle until static equilibrium: unbalanced force ratio below ``tolerance`` and every servo wall within
    ``stress_tolerance`` (relative) of its target. Returns ``{"steps", "ratio", "converged"}``."""
    check_positive("tolerance", tolerance)
    check_positive("stress_tolerance", stress_tolerance)
    for name, value, low in (("min_steps", min_steps, 0), ("max_steps", max_steps, 1), ("check_every", check_every, 1)):
        check_instance(name, value, (int, np.integer))
        check_range(name, value, low, None)
    steps, ratio = 0, np.inf
    while steps < max_steps:
        sim.run(check_every, progress=False)
        steps += check_every
        ratio = unbalanced_force_ratio(sim)
        stress_ok = all(abs(sim.walls.normal_force(s.wall) / s.current_area(sim.walls) - s.target_stress)
                        <= stress_tolerance * abs(s.target_stress) for s in sim.walls.servos)
        if steps >= min_steps and ratio < tolerance and stress_ok:
            return {"steps": steps, "ratio": ratio, "converged": True}
    return {"steps": steps, "ratio": ratio, "converged": False}
