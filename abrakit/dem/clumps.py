"""Clumps: rigid multi-sphere grains (Ch. 4.1.2), e.g. the dyads and three-sphere peanuts of Table 5.4 / Fig. 5.9.

Member spheres take part in contact detection like free spheres, but contacts inside one clump are skipped
(:func:`~abrakit.dem.neighbours.candidate_pairs`), so members may overlap to any extent. The forces and moments
on the members are summed onto the clump body, which moves as a rigid body:

    V(t + Δt/2) = V(t − Δt/2) + Δt F/M,        L(t + Δt/2) = L(t − Δt/2) + Δt M_O,
    ω(t + Δt/2) = R I_b⁻¹ Rᵀ L(t + Δt/2)  (R at mid-step),   R(t + Δt) = exp([ω Δt]×) R(t),

with the angular momentum L carried in the world frame (exact for a torque-free body, so a tumbling clump keeps
L and its kinetic energy). Member positions and velocities are then set from the body:
x_m = X + R d_m, v_m = V + ω × (x_m − X), ω_m = ω.

Mass properties are summed over the member spheres (overlapping volumes counted twice, as when a clump's mass
is taken from its balls); :func:`make_clumps` diagonalises the inertia tensor so the body frame is principal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from abrakit.dem.integrate import _local_damping
from abrakit.dem.state import Particles
from abrakit.validation import check_finite, check_positive, number_arguments


def dyad(radius: float, spacing: float | None = None):
    """Two equal spheres with centres ``spacing`` apart (default: one radius, a strongly overlapping pair).

    Returns ``(offsets (2, 3), radii (2,))`` about the geometric centre.
    """
    radius = check_positive("radius", radius)
    s = radius if spacing is None else check_positive("spacing", spacing)
    return np.array([[-s / 2, 0.0, 0.0], [s / 2, 0.0, 0.0]]), np.full(2, radius)


def peanut(radius: float, spacing: float | None = None):
    """Three equal spheres in a row, centres ``spacing`` apart (default one radius): the 3-particle clump."""
    radius = check_positive("radius", radius)
    s = radius if spacing is None else check_positive("spacing", spacing)
    return np.array([[-s, 0.0, 0.0], [0.0, 0.0, 0.0], [s, 0.0, 0.0]]), np.full(3, radius)


@number_arguments
def rotation_from_vector(phi: ArrayLike):
    """Rotation matrices exp([φ]×) for rotation vectors φ (C, 3) (Rodrigues' formula)."""
    phi = np.atleast_2d(phi)
    angle = np.linalg.norm(phi, axis=1)
    axis = np.divide(phi, angle[:, None], out=np.zeros_like(phi), where=angle[:, None] > 0)
    K = np.zeros((len(phi), 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = axis[:, 2], -axis[:, 1], axis[:, 0]
    s, c = np.sin(angle)[:, None, None], (1.0 - np.cos(angle))[:, None, None]
    return np.eye(3) + s * K + c * (K @ K)


def clump_particles(centres, template, density=2650.0, *, rng=None, **particle_kwargs) -> Particles:
    """Copies of a clump ``template`` (offsets, radii) at ``centres`` (C, 3), randomly turned if ``rng`` given.

    Returns :class:`Particles` whose ``clump`` array numbers the clumps 0..C−1; pass them to a ``Simulation``.
    """
    offsets, radii = template
    centres = np.atleast_2d(np.asarray(check_finite("centres", centres), float))
    c, k = len(centres), len(radii)
    R = np.broadcast_to(np.eye(3), (c, 3, 3))
    if rng is not None:
        q, r = np.linalg.qr(rng.standard_normal((c, 3, 3)))
        R = q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None, :]
        R = R * np.sign(np.linalg.det(R))[:, None, None]
    x = (centres[:, None, :] + np.einsum("cij,kj->cki", R, offsets)).reshape(-1, 3)
    p = Particles.spheres(x, np.tile(radii, c), density, **particle_kwargs)
    p.clump = np.repeat(np.arange(c), k)
    return p


@dataclass
class Clumps:
    """``C`` rigid bodies built from member spheres (body arrays plus the member → body map)."""

    members: np.ndarray   # (K,) particle index of each member
    body: np.ndarray      # (K,) clump index of each member
    offset: np.ndarray    # (K, 3) member centre in the principal body frame [m]
    x: np.ndarray         # (C, 3) centre of mass [m]
    v: np.ndarray         # (C, 3) velocity (half step) [m/s]
    L: np.ndarray         # (C, 3) angular momentum about the centre of mass, world frame (half step) [kg m²/s]
    R: np.ndarray         # (C, 3, 3) rotation body → world
    mass: np.ndarray      # (C,) [kg]
    inertia: np.ndarray   # (C, 3) principal moments [kg m²]

    def __len__(self) -> int:
        return len(self.mass)

    def angular_velocity(self, R=None, L=None):
        """ω = R I_b⁻¹ Rᵀ L [rad/s]."""
        R = self.R if R is None else R
        L = self.L if L is None else L
        return np.einsum("cij,cj->ci", R, np.einsum("cji,cj->ci", R, L) / self.inertia)

    def kinetic_energy(self) -> float:
        w = self.angular_velocity()
        return float(0.5 * np.sum(self.mass * np.einsum("ci,ci->c", self.v, self.v))
                     + 0.5 * np.sum(np.einsum("ci,ci->c", w, self.L)))

    def step(self, particles: Particles, force, torque, dt: float, alpha: float = 0.0, kick=None) -> float:
        """Advance all clumps by one step from member forces/torques (velocity ``kick``, default ``dt``); set member
        kinematics. Returns the energy dissipated by local damping [J]; stores the kinetic energy at the force
        evaluation time in ``kinetic_mid``."""
        kick = dt if kick is None else kick
        n = len(self)
        arm = particles.x[self.members] - self.x[self.body]
        f_m = force[self.members]
        m_m = torque[self.members] + np.cross(arm, f_m)
        F = np.column_stack([np.bincount(self.body, f_m[:, k], n) for k in range(3)])
        M = np.column_stack([np.bincount(self.body, m_m[:, k], n) for k in range(3)])
        w_old = self.angular_velocity()
        dissipated = 0.0
        if alpha:
            F_d, M_d = _local_damping(F, self.v, alpha), _local_damping(M, w_old, alpha)
            F, M = F + F_d, M + M_d
        v_old, L_old = self.v.copy(), self.L.copy()
        self.v = self.v + F * (kick / self.mass)[:, None]
        self.L = self.L + M * kick
        R_half = np.einsum("cij,cjk->cik", rotation_from_vector(0.5 * dt * w_old), self.R)
        w = self.angular_velocity(R_half)
        first = kick != dt
        v_mid = v_old if first else 0.5 * (v_old + self.v)
        L_mid = L_old if first else 0.5 * (L_old + self.L)
        w_mid = w_old if first else 0.5 * (w_old + w)
        self.kinetic_mid = 0.5 * float(np.sum(self.mass * np.einsum("ci,ci->c", v_mid, v_mid))
                                       + np.sum(np.einsum("ci,ci->c", w_mid, L_mid)))
        if alpha:
            dissipated = -float(np.sum(F_d * v_mid) + np.sum(M_d * w_mid)) * dt
        self.x = self.x + self.v * dt
        self.R = np.einsum("cij,cjk->cik", rotation_from_vector(dt * w), self.R)
        self.place_members(particles, w)
        return dissipated

    def place_members(self, particles: Particles, w=None) -> None:
        w = self.angular_velocity() if w is None else w
        arm = np.einsum("kij,kj->ki", self.R[self.body], self.offset)
        particles.x[self.members] = self.x[self.body] + arm
        particles.v[self.members] = self.v[self.body] + np.cross(w[self.body], arm)
        particles.w[self.members] = w[self.body]


def make_clumps(particles: Particles) -> Clumps | None:
    """Build the rigid bodies of all particles with ``clump >= 0`` (ids need not be contiguous)."""
    members = np.flatnonzero(particles.clump >= 0)
    if not len(members):
        return None
    ids, body = np.unique(particles.clump[members], return_inverse=True)
    c = len(ids)
    m = particles.mass[members]
    mass = np.bincount(body, m, c)
    x = np.column_stack([np.bincount(body, m * particles.x[members, k], c) for k in range(3)]) / mass[:, None]
    v = np.column_stack([np.bincount(body, m * particles.v[members, k], c) for k in range(3)]) / mass[:, None]
    d = particles.x[members] - x[body]
    own = particles.inertia[members]
    tensor = ((own + m * np.einsum("ki,ki->k", d, d))[:, None, None] * np.eye(3)
              - m[:, None, None] * np.einsum("ki,kj->kij", d, d))
    I_world = np.zeros((c, 3, 3))
    np.add.at(I_world, body, tensor)
    inertia, R = np.linalg.eigh(I_world)
    R = R * np.sign(np.linalg.det(R))[:, None, None]            # proper rotations
    offset = np.einsum("kji,kj->ki", R[body], d)
    first = np.unique(body, return_index=True)[1]
    w = particles.w[members[first]]
    L = np.einsum("cij,cj->ci", I_world, w)
    clumps = Clumps(members, body, offset, x, v, L, R, mass, inertia)
    clumps.place_members(particles)
    return clumps
