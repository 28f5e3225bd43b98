"""The contact stage of :meth:`~abrakit.dem.simulation.Simulation.step` through the numba kernels
(``Simulation(kernel="numba")``, the linear law only): the same equations as the NumPy path, Eq. (4.1)–(4.10) with
contact bonds, as one loop over the contacts of :mod:`abrakit.dem.kernels` that also sums the loads onto the
particles. Its outputs are returned as the :class:`~abrakit.dem.contact_laws.ContactForces` of the NumPy path.

Without dashpots and without an energy account the particle–particle kernel runs lean: it does not write the
normals, the normal and the total forces; :func:`_defer_compiled_results` rebuilds them from the step's positions
when they are read.
"""

from __future__ import annotations

import numpy as np

from abrakit.dem.contact_laws import ContactForces


def _ball_ball_compiled(sim, force, torque):
    """Particle–particle contacts of ``sim`` through :func:`~abrakit.dem.kernels.linear_contacts`, their loads added
    to ``force`` and ``torque``; the contact set's springs (and, unless lean, normals and forces) updated.
    Returns ``(r, overlap, n, failed)``: the :class:`ContactForces`, the overlaps, the normals (None after a lean
    step without broken bonds) and whether a contact bond broke."""
    from abrakit.dem.kernels import linear_contacts

    p, c, prm = sim.particles, sim.contacts, sim.contacts.prm
    damped = sim.law.damping_normal or sim.law.damping_shear
    full = sim.track_energy or damped
    m = len(c)
    k = m if full else 0
    overlap, fn, trial = np.empty(m), np.empty(k), np.empty(k)
    ft, n, total = np.empty((3, m)), np.empty((3, k)), np.empty((3, k))
    dashpot = np.empty((3, m if damped else 0))
    flags = np.zeros((4, m), np.bool_)
    failed = linear_contacts(p.x, p.v, p.w, p.radius, c.i, c.j, prm["kn"], prm["kt"], prm["mu"], prm["beta_n"],
                    prm["beta_t"], c.ft, c.bonded, c.bond_gap, c.bond_normal_strength, c.bond_shear_strength,
                    sim.dt, force, torque, ft, overlap, n, fn, total, dashpot, trial, flags,
                    *sim._cell_matrices(), full)
    r = _compiled_forces(sim, prm, total if full else None, fn if full else None, ft, flags, trial, dashpot)
    failed = failed > 0
    c.ft = r.ft
    if not full:                          # the lean kernel: results built from this step's positions if read
        _defer_compiled_results(sim, p.x.copy(), overlap, r)
        return r, overlap, c.normal if failed else None, failed
    c.fn, c.force, c.normal = r.fn, r.force, n
    return r, overlap, n, failed


def _defer_compiled_results(sim, x, overlap, r) -> None:
    """Normals, normal and total forces of a lean kernel step (results ``r``), built when read from the step's
    positions ``x``: n = d/|d| (Eq. 4.1), F^n = K^n U for U > 0 or K^n (U + gap) for a bond still intact
    (Eq. 4.6), F = F^n n + F^t (no dashpots), as the kernel computes them."""
    c, law = sim.contacts, sim.law
    bonded, gap = None, None
    if c.bonded.any():
        bonded, gap = c.bonded & ~(r.tension_failure | r.shear_failure), c.bond_gap.copy()

    def fn():                                          # as force_displacement: the law, a bond's K^n (U + gap)
        spring = law.normal_force(overlap, c.prm)[0]
        return spring if bonded is None else np.where(bonded, c.prm["kn"] * (overlap + gap), spring)

    c.defer(normal=lambda: np.divide(*sim._branches(x)), fn=fn, force=lambda: c.fn * c.normal + r.ft)


def _compiled_forces(sim, prm, total, fn, ft, flags, trial, dashpot) -> ContactForces:
    """The kernels' outputs as the :class:`ContactForces` of the NumPy path (slip work as μF^n · slip;
    ``total`` and ``fn`` are None after a lean kernel)."""
    m = len(ft[0])
    slip = 0.0
    if sim.track_energy and flags[1].any():
        limit = prm["mu"] * fn
        length = np.divide(trial - limit, prm["kt"], out=np.zeros(m), where=flags[1] & (prm["kt"] > 0))
        slip = float(np.sum(limit * length))
    damped = sim.law.damping_normal or sim.law.damping_shear
    tension, shear = (flags[2], flags[3]) if len(flags) == 4 else (np.zeros(m, bool),) * 2
    return ContactForces(total, fn, ft, flags[0], flags[1], tension, shear, slip, dashpot if damped else None,
                         prm["kn"], prm["kt"])


def _ball_wall_compiled(sim, force, torque):
    """Particle–wall contacts of ``sim`` through :func:`~abrakit.dem.kernels.linear_wall_contacts`, their loads added
    to ``force``, ``torque`` and the walls' forces and normal stiffnesses. Returns ``(r, overlap)``."""
    from abrakit.dem.kernels import linear_wall_contacts

    p, c, walls, prm = sim.particles, sim.wall_contacts, sim.walls, sim.wall_contacts.prm
    m = len(c)
    overlap, fn, trial = np.empty(m), np.empty(m), np.empty(m)
    ft, total = np.empty((3, m)), np.empty((3, m))
    dashpot = np.empty((3, m if sim.law.damping_normal or sim.law.damping_shear else 0))
    flags = np.empty((2, m), np.bool_)
    linear_wall_contacts(p.x, p.v, p.w, p.radius, c.i, c.j, walls.normal, walls.point, walls.velocity,
                         *sim._wall_prm, c.ft, sim.dt, force, torque, walls.force, sim._wall_stiffness, ft,
                         overlap, fn, total, dashpot, trial, flags)
    return _compiled_forces(sim, prm, total, fn, ft, flags, trial, dashpot), overlap


def _wall_parameters(prm, m) -> tuple[np.ndarray, ...]:
    """K^n, K^t, μ, β_n, β_t of the ``m`` wall contacts (``prm``), one contiguous array each, for the compiled
    wall loop."""
    return tuple(np.ascontiguousarray(np.broadcast_to(prm[q], (m,)), dtype=float)
                 for q in ("kn", "kt", "mu", "beta_n", "beta_t"))
