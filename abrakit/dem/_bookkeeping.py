"""The sums of a DEM step: per-contact arrays gathered from and summed onto the particles' rows, and the energy
account of :class:`~abrakit.dem.simulation.EnergyAccount`.

Per-contact vectors are component-major, shape (3, M); per-particle ones are rows, shape (N, 3). Loads are summed
with ``np.bincount`` (or, for pairs, one compiled loop giving the same sums bit for bit). The energy account books
at time t, the midpoint of the leap-frog step: stored energies (kinetic, elastic, potential), dissipation (slip,
local damping, dashpots) and the work of walls, applied forces and prescribed motions [J].
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from abrakit.dem.contact_laws import _cross, _dot, _rowdot


def _gather(a, index):
    """Rows ``a[index]`` of an (N, 3) array as a component-major (3, M) array (``np.take`` is the fast gather)."""
    return np.take(a.T, index, axis=1)


def _place(values, index, m):
    """A (…, m) array that holds ``values`` (…, K) at ``index`` and zeros elsewhere."""
    out = np.zeros(values.shape[:-1] + (m,), values.dtype)
    for row, part in zip(out.reshape(-1, m), values.reshape(out.size // m, -1), strict=True):   # by rows
        row[index] = part
    return out


class _Taken(Mapping):
    """The per-contact parameters ``prm`` of the contacts ``index``, each taken when first read (a law reads only
    the ones it needs)."""

    def __init__(self, prm: dict, index):
        self._prm, self._index, self._taken = prm, index, {}

    def __getitem__(self, key):
        if key not in self._taken:
            self._taken[key] = self._prm[key][self._index]
        return self._taken[key]

    def __iter__(self):
        return iter(self._prm)

    def __len__(self) -> int:
        return len(self._prm)


def _scatter(out, index, values, sign=1.0):
    """out[index] += sign · values for (N, 3) ``out`` and (3, M) ``values``, summed with np.bincount."""
    n = len(out)
    for k in range(3):
        out[:, k] += sign * np.bincount(index, values[k], n)


def _scatter_pair_loads(force, torque, i, j, force_on_j, torque_on_i, torque_on_j, *, compiled: bool) -> None:
    """Add the force of pairs i–j (on j, its reaction on i) and their torques on i and j to the particle sums
    (contacts and bonds; each component's two sums are added at once). ``compiled``: one compiled loop builds
    the same sums in the same order (:func:`abrakit.dem.kernels.scatter_pair_loads`; the simulation passes
    :data:`~abrakit.dem.simulation.COMPILED_SCATTER`)."""
    if compiled:
        from abrakit.dem.kernels import scatter_pair_loads

        return scatter_pair_loads(force, torque, i, j, np.ascontiguousarray(force_on_j),
                                  np.ascontiguousarray(torque_on_i), np.ascontiguousarray(torque_on_j))
    n = len(force)
    for k in range(3):
        force[:, k] += np.bincount(j, force_on_j[k], n) - np.bincount(i, force_on_j[k], n)
        torque[:, k] += np.bincount(i, torque_on_i[k], n) + np.bincount(j, torque_on_j[k], n)


def _pair_dashpot_loads(dashpot, f, n, i, j, arm_i, arm_j) -> None:
    """Add the dashpot forces ``f`` (3, M) of pairs i–j (on j, −f on i; normals ``n``, arms ``arm_i``, ``arm_j``
    from the centres to the contact point) and their moments to ``dashpot`` = (force sums, moment sums): their
    power is counted on the particles, like local damping."""
    lever = _cross(n, f)
    _scatter(dashpot[0], j, f)
    _scatter(dashpot[0], i, f, -1.0)
    _scatter(dashpot[1], i, arm_i * lever, -1.0)
    _scatter(dashpot[1], j, arm_j * lever, -1.0)


def _elastic_energy(law, prm, overlap, bonded, bond_gap, r) -> float:
    """Elastic energy of contacts [J]: the law's normal energy (½ K^n (U + gap)² for an intact contact bond) on the
    touching contacts, and the tangential springs' |F^t|² / 2K^t (results ``r``)."""
    normal = law.normal_energy(overlap, prm)
    if bonded.any():
        normal = np.where(bonded, 0.5 * prm["kn"] * (overlap + bond_gap) ** 2, normal)
    kt = np.broadcast_to(r.kt, r.fn.shape)
    shear = np.divide(0.5 * _dot(r.ft, r.ft), kt, out=np.zeros_like(r.fn), where=kt > 0)
    return float(np.sum(normal * r.touching) + np.sum(shear))


def _account(sim, stored, force, damping_force, damping_torque, v_old, w_old, wall_velocity_old,
             clump_damping) -> None:
    """Book the step just taken in ``sim.energy``: stored energies at time t (``stored``: the elastic part) and this
    step's dissipation and external work, from the leap-frog mid values of the velocities ``v_old``/``w_old``
    (before the update) and the new ones."""
    p, e, dt = sim.particles, sim.energy, sim.dt
    v_mid, w_mid = 0.5 * (v_old + p.v), 0.5 * (w_old + p.w)      # velocities at time t
    if sim.step_count == 0:
        v_mid, w_mid = v_old, w_old
    free = p.clump < 0
    e.kinetic = 0.5 * float(np.sum(p.mass[free] * _rowdot(v_mid[free], v_mid[free]))
                            + np.sum(p.inertia[free] * _rowdot(w_mid[free], w_mid[free])))
    if sim.clumps is not None:
        e.kinetic += sim.clumps.kinetic_mid
    e.elastic = stored
    e.potential = -float(np.sum(p.mass * ((p.x - p.v * dt) @ sim.gravity)))   # positions at time t
    if sim.step_count == 0:
        e.local_damping = e.dashpot = 0.0        # a half kick: the work of the first half step is not booked
    movable = (free & ~p.fixed)[:, None]
    if sim.local_damping:
        e.local_damping -= float(np.sum(damping_force * v_mid * movable)
                                 + np.sum(damping_torque * w_mid * movable)) * dt
        e.local_damping += clump_damping
    if sim.law.damping_normal or sim.law.damping_shear:
        f, m = sim._dashpot
        e.dashpot -= float(np.sum(f * v_mid) + np.sum(m * w_mid) - sim._dashpot_wall) * dt
    if sim.applied_force is not None:
        e.work_applied += float(np.sum(sim.applied_force * v_mid)) * dt
    if p.fixed.any():
        e.work_prescribed -= float(np.sum(force[p.fixed] * p.v[p.fixed])) * dt
    if len(sim.walls):
        wall_v = 0.5 * (wall_velocity_old + sim.walls.velocity)
        e.work_walls -= float(np.sum(sim.walls.force * wall_v)) * dt
    if e.initial is None:
        e.initial = e.stored
