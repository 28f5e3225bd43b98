"""Force–displacement laws at a contact (Ch. 4.1.2–4.1.3): linear and Hertz–Mindlin, one shared interface.

Per-contact vectors are stored component-major, shape (3, M): then a line of code reads like its equation
(``fn * n`` rather than ``fn[:, None] * n``) and every component is a contiguous array, which is what makes
the kernels fast (``_dot``, ``_cross``).

A contact law is a small object with four pure methods, all vectorised over contacts:

- ``pair_parameters(particles, i, j)`` / ``wall_parameters(particles, walls, k, j)``: per-contact constants from
  the two bodies' properties (computed once per neighbour-list rebuild);
- ``normal_force(overlap, prm) -> (F^n, dF^n/dU)``: Eq. (4.6) or (4.13);
- ``shear_stiffness(F^n, prm) -> K^t``: Eq. (4.12) or (4.14);
- ``normal_energy(overlap, prm)``: the elastic energy stored by the normal spring;

and two flags: ``bondable`` (contact bonds allowed) and ``constant_stiffness`` (K^n and K^t do not depend on the
overlap, so the critical time step needs no contact geometry).

Everything else — incremental tangential force (4.7), Coulomb slip (4.8), dashpots (4.9, 4.10) and the contact bond
of Fig. 4.3 — is shared and lives in :func:`force_displacement`. Forces are those body A exerts on body B; the
normal ``n`` points from A to B; the overlap ``U`` is positive in contact (Eq. 4.3).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from abrakit.identification import series_stiffness
from abrakit.validation import (
    check_number_fields,
    check_poisson,
    check_positive,
    check_range,
    check_shape,
    number_arguments,
)


def _rowdot(a, b):
    """Row-wise dot product of two (M, 3) arrays."""
    return np.einsum("ij,ij->i", a, b)


def _dot(a, b):
    """Dot product of two component-major (3, M) arrays of vectors, shape (M,)."""
    return np.einsum("ij,ij->j", a, b)


def _cross(a, b):
    """Cross product of two component-major (3, M) arrays of vectors."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


PLANE_TOL = 1e-12
"""Relative in-plane remainder below which a turned tangential spring is taken as lying along the normal."""

RETURN_TOL = 1e-3
"""Relative in-plane remainder below which a turned spring is projected into the plane a second time."""


def _turn_into_plane(vec, n):
    """Remove the component of ``vec`` (3, M) along the unit normal ``n`` and restore its length.

    An incremental shear spring keeps its force in the contact plane when the plane turns with the pair. A spring
    that lies along the new normal (its in-plane remainder at round-off, below ``PLANE_TOL`` of its length) has no
    direction in the plane and is dropped: rescaling the round-off would point it anywhere, even along n. The
    normal component is removed twice: a spring nearly along n keeps a round-off normal part of order
    eps |vec| after one projection, which the rescaling by |vec| / |remainder| would amplify (found by a property
    test: 2e-9 |vec| out of the plane for a remainder of 6e-8 |vec|); after the second it is of order eps times the
    remainder. Only springs whose remainder is below ``RETURN_TOL`` of their length are projected the second time:
    for the others the rescaling amplifies the round-off by less than 1/RETURN_TOL (a tenth of the cost in a dense
    packing, where almost no spring needs it).
    """
    before = np.sqrt(_dot(vec, vec))
    vec = vec - _dot(vec, n) * n
    after = np.sqrt(_dot(vec, vec))
    again = np.flatnonzero(after < RETURN_TOL * before)
    if len(again):
        v, m = vec[:, again], n[:, again]
        vec[:, again] = v - _dot(v, m) * m
        after[again] = np.sqrt(_dot(vec[:, again], vec[:, again]))
    vec *= np.divide(before, after, out=np.zeros_like(after), where=after > PLANE_TOL * before)
    return vec


def hertz_normal_coefficient(shear_modulus, poisson, r_tilde):
    """Coefficient of Eq. (4.13): K^n = c_n √U with c_n = 2⟨G⟩√(2 r̃) / (3(1 − ⟨ν⟩)) [N/m^1.5].

    With r̃ = 2 r_A r_B/(r_A + r_B) the force F^n = c_n U^{3/2} is Hertz's (4/3) E* √R* U^{3/2} for two
    spheres of one material (E* = G/(1 − ν), R* = r_A r_B/(r_A + r_B)).
    """
    shear_modulus, poisson, r_tilde = _hertz_inputs(shear_modulus, poisson, r_tilde)
    return 2.0 * shear_modulus * np.sqrt(2.0 * r_tilde) / (3.0 * (1.0 - poisson))


def hertz_shear_coefficient(shear_modulus, poisson, r_tilde):
    """Coefficient of Eq. (4.14): ``K^t = c_t |F^n|^{1/3}``, c_t = 2(⟨G⟩² 3(1 − ⟨ν⟩) r̃)^{1/3} / (2 − ⟨ν⟩).

    This equals Mindlin's K^t = 8 G* a with G* = G/(2(2 − ν)) and contact radius a = √(R* U).
    """
    shear_modulus, poisson, r_tilde = _hertz_inputs(shear_modulus, poisson, r_tilde)
    return 2.0 * np.cbrt(shear_modulus**2 * 3.0 * (1.0 - poisson) * r_tilde) / (2.0 - poisson)


def _hertz_inputs(shear_modulus, poisson, r_tilde):
    """The checked inputs of the Hertz–Mindlin coefficients: G > 0, −1 < ν < 1/2, r̃ > 0."""
    return (check_positive("shear_modulus", shear_modulus), check_poisson("poisson", poisson),
            check_positive("r_tilde", r_tilde))


def _effective_mass(ma, mb):
    return ma * mb / (ma + mb)


@dataclass(frozen=True)
class Linear:
    """Linear contact model, Eq. (4.6), (4.7), (4.11), (4.12), with optional dashpots (4.9, 4.10).

    Contact stiffnesses are the particles' (and walls') ``kn``/``kt`` in series; μ is the smaller of the two
    friction coefficients. ``damping_normal``/``damping_shear`` are the ratios d_i of Eq. (4.10):
    β = d · 2√(m_c K), with m_c the effective mass m_A m_B/(m_A + m_B) (the particle's mass at a wall).
    """

    damping_normal: float = 0.0
    damping_shear: float = 0.0
    bondable = True
    constant_stiffness = True      # K^n, K^t do not depend on the overlap (the time step needs no geometry)

    def __post_init__(self):
        check_number_fields(self)
        check_range("damping_normal", self.damping_normal, 0.0, None)
        check_range("damping_shear", self.damping_shear, 0.0, None)

    def pair_parameters(self, p, i, j) -> dict:
        kn = series_stiffness(p.kn[i], p.kn[j])
        kt = series_stiffness(p.kt[i], p.kt[j])
        return self._finish(kn, kt, np.minimum(p.friction[i], p.friction[j]), _effective_mass(p.mass[i], p.mass[j]))

    def wall_parameters(self, p, walls, k, j) -> dict:
        kn = series_stiffness(walls.kn[k], p.kn[j])
        kt = series_stiffness(walls.kt[k], p.kt[j])
        return self._finish(kn, kt, np.minimum(walls.friction[k], p.friction[j]), p.mass[j].copy())

    def _finish(self, kn, kt, mu, mass):
        prm = {"kn": kn, "kt": kt, "mu": mu, "mass": mass}
        for key, ratio, k in (("beta_n", self.damping_normal, kn), ("beta_t", self.damping_shear, kt)):
            prm[key] = 2.0 * ratio * np.sqrt(mass * k) if ratio else np.zeros_like(k)  # Eq. (4.10), constant here
        return prm

    def normal_force(self, overlap, prm):
        """Eq. (4.6): F^n = K^n U for U > 0 (no tension without a bond); returns (F^n, dF^n/dU)."""
        return prm["kn"] * np.maximum(overlap, 0.0), prm["kn"]

    def shear_stiffness(self, fn, prm):
        """Eq. (4.12): constant K^t."""
        return prm["kt"]

    def normal_energy(self, overlap, prm):
        """½ K^n U² for U > 0 [J]."""
        return 0.5 * prm["kn"] * np.maximum(overlap, 0.0) ** 2

    def dashpots(self, prm, kn, kt):
        return prm["beta_n"], prm["beta_t"]


@dataclass(frozen=True)
class HertzMindlin:
    """Hertz–Mindlin model, Eq. (4.13) and (4.14), with optional dashpots (4.9, 4.10) on the tangent stiffness.

    Per contact ⟨G⟩ and ⟨ν⟩ are the two particles' means and r̃ = 2 r_A r_B/(r_A + r_B); a wall acts as a
    flat of the particle's material (r̃ = 2 r). Not defined for tension, hence not bondable (Ch. 4.1.3).
    """

    damping_normal: float = 0.0
    damping_shear: float = 0.0
    bondable = False
    constant_stiffness = False

    def __post_init__(self):
        check_number_fields(self)
        check_range("damping_normal", self.damping_normal, 0.0, None)
        check_range("damping_shear", self.damping_shear, 0.0, None)

    def pair_parameters(self, p, i, j) -> dict:
        G = 0.5 * (p.shear_modulus[i] + p.shear_modulus[j])
        nu = 0.5 * (p.poisson[i] + p.poisson[j])
        r_tilde = 2.0 * p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j])
        return self._finish(G, nu, r_tilde, np.minimum(p.friction[i], p.friction[j]),
                            _effective_mass(p.mass[i], p.mass[j]))

    def wall_parameters(self, p, walls, k, j) -> dict:
        return self._finish(p.shear_modulus[j], p.poisson[j], 2.0 * p.radius[j],
                            np.minimum(walls.friction[k], p.friction[j]), p.mass[j].copy())

    def _finish(self, G, nu, r_tilde, mu, mass):
        return {"cn": hertz_normal_coefficient(G, nu, r_tilde), "ct": hertz_shear_coefficient(G, nu, r_tilde),
                "mu": mu, "mass": mass}

    def normal_force(self, overlap, prm):
        """Eq. (4.13): F^n = K^n U = c_n U^{3/2}; returns (F^n, dF^n/dU = 3/2 c_n √U)."""
        root = np.sqrt(np.maximum(overlap, 0.0))
        return prm["cn"] * root**3, 1.5 * prm["cn"] * root

    def shear_stiffness(self, fn, prm):
        """Eq. (4.14): ``K^t = c_t |F^n|^{1/3}``."""
        return prm["ct"] * np.cbrt(np.abs(fn))

    def normal_energy(self, overlap, prm):
        """∫ F^n dU = 2/5 c_n U^{5/2} [J]."""
        return 0.4 * prm["cn"] * np.maximum(overlap, 0.0) ** 2.5

    def dashpots(self, prm, kn, kt):
        two_root_m = 2.0 * np.sqrt(prm["mass"])
        return self.damping_normal * two_root_m * np.sqrt(kn), self.damping_shear * two_root_m * np.sqrt(kt)


class ContactForces(NamedTuple):
    """Result of :func:`force_displacement` for ``M`` contacts (forces on body B)."""

    force: np.ndarray       # (3, M) total contact force on B [N]
    fn: np.ndarray          # (M,) spring normal force, compression positive [N]
    ft: np.ndarray          # (3, M) tangential spring force = new history [N]
    touching: np.ndarray    # (M,) carries force
    sliding: np.ndarray     # (M,) at the Coulomb limit
    tension_failure: np.ndarray  # (M,) contact bond broke in tension this step
    shear_failure: np.ndarray    # (M,) contact bond broke in shear this step
    slip_dissipation: float      # energy dissipated by slip this step [J]
    dashpot_force: np.ndarray | None  # (3, M) dashpot part of ``force`` (None without dashpots) [N]
    kn: np.ndarray               # (M,) normal tangent stiffness (for time step and servo) [N/m]
    kt: np.ndarray               # (M,) shear stiffness [N/m]


@number_arguments
def force_displacement(law, prm, overlap: ArrayLike, n: ArrayLike, v_rel: ArrayLike, ft: ArrayLike, dt: float,
                       bonded=None, bond_gap: ArrayLike | None = None, bond_normal_strength: ArrayLike | None = None,
                       bond_shear_strength: ArrayLike | None = None, energy: bool = False) -> ContactForces:
    """One force–displacement update of ``M`` contacts, Eq. (4.5)–(4.10), with contact bonds (Fig. 4.3).

    ``overlap`` U (M,) [m], unit normal ``n`` (3, M) from A to B, velocity of B's contact point relative to
    A's ``v_rel`` (3, M) [m/s], old tangential force ``ft`` (3, M) [N], time step ``dt`` [s].

    - normal spring: F^n from the law, Eq. (4.6)/(4.13); an intact contact bond carries tension,
      F^n = K^n (U + g₀) with g₀ the gap at installation;
    - tangential spring, incremental: the old force is turned into the current contact plane (its magnitude
      kept) and ΔF^t = −K^t V^t Δt is added, Eq. (4.7);
    - slip: |F^t| ≤ μ F^n, Eq. (4.8), except while a contact bond holds;
    - contact bond failure: tension −F^n ≥ f^{n,c}, or shear |F^t| ≥ f^{t,c}; a broken bond's forces are
      zeroed this step (Ch. 4.1.2) and the contact continues as an unbonded frictional contact;
    - dashpots in parallel, Eq. (4.9)/(4.10): D = −β V (normal and, while not sliding, tangential).
    """
    overlap = check_shape("overlap", np.asarray(overlap, float), (None,))
    shape = (3, len(overlap))
    n, v_rel, ft = (check_shape(name, np.asarray(a, float), shape)
                    for name, a in (("n", n), ("v_rel", v_rel), ("ft", ft)))
    return _force_displacement(law, prm, overlap, n, v_rel, ft, check_positive("dt", dt), bonded, bond_gap,
                               bond_normal_strength, bond_shear_strength, energy)


def _force_displacement(law, prm, overlap, n, v_rel, ft, dt, bonded=None, bond_gap=None,
                        bond_normal_strength=None, bond_shear_strength=None, energy=False) -> ContactForces:
    """The kernel of :func:`force_displacement`, unchecked (the time step calls it with its own arrays)."""
    touching = overlap > 0.0
    fn, kn = law.normal_force(overlap, prm)
    has_bonds = bonded is not None and bonded.any()
    if has_bonds:
        fn = np.where(bonded, prm["kn"] * (overlap + bond_gap), fn)
        touching = touching | bonded
    kt = law.shear_stiffness(fn, prm)

    vn = _dot(v_rel, n)
    vt = v_rel - vn * n
    ft = _turn_into_plane(ft, n) - kt * dt * vt                     # Eq. (4.7)
    ft *= touching                                                 # an open contact forgets its history

    limit = prm["mu"] * fn                                         # Eq. (4.8)
    magnitude = np.sqrt(_dot(ft, ft))
    sliding = magnitude > limit
    tension = shear = np.zeros(len(fn), bool)
    if has_bonds:
        sliding &= ~bonded
        tension = bonded & (-fn >= bond_normal_strength)
        shear = bonded & ~tension & (magnitude >= bond_shear_strength)
    slip = 0.0
    if energy and sliding.any():
        slip_length = np.divide(magnitude - limit, kt, out=np.zeros_like(magnitude), where=sliding & (kt > 0))
        slip = float(np.sum(limit * slip_length))
    ft *= np.divide(limit, magnitude, out=np.ones_like(magnitude), where=sliding)
    if has_bonds and (tension.any() or shear.any()):
        broken = tension | shear
        ft[:, broken] = 0.0
        fn = np.where(broken, law.normal_force(overlap, prm)[0], fn)

    force = fn * n + ft
    dashpot = None
    if law.damping_normal or law.damping_shear:
        beta_n, beta_t = law.dashpots(prm, kn, kt)
        dashpot = -beta_n * vn * touching * n - beta_t * (touching & ~sliding) * vt   # Eq. (4.9), (4.10)
        force += dashpot
    return ContactForces(force, fn, ft, touching, sliding, tension, shear, slip, dashpot, kn, kt)
